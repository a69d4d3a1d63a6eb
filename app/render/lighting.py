"""The light and what it reaches, as numbers (no OpenGL): the key light's direction, the
shadow map's fit around the casters, the polygon that holds the shadow on the floor, the floor's
light and the sky's band on screen. The passes in :mod:`.renderer` and
:mod:`.ground` draw with these."""

from __future__ import annotations

from typing import cast

import numpy as np
from numpy.typing import NDArray
from pyglm import glm

from ..kinematics.terrain import Terrain
from .camera import Camera
from .options import RenderOptions
from .scene import SceneInstances, srgb_to_linear

SHADOW_MAP_SIZE = 256
SUN_COLOR = np.array([0.95, 0.90, 0.84])  # as in shaders/lighting.glsl
LIGHT_DIR = np.array([-0.45, -1.0, -0.35]) / np.linalg.norm([-0.45, -1.0, -0.35])


def creature_bounds(scene: SceneInstances, terrain: Terrain) -> tuple[np.ndarray, float]:
    """The creatures' box down to the ground: its centre (3,) and half diagonal (m), from
    the centres of every shape drawn (capsules, ellipsoids and the joints of skinned
    bodies: a skinned body drawn without joint markers otherwise leaves only its eyes)."""
    pts = scene.spheres()[0]  # every shape's centre, skinned bodies' joints included
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    lo[1] = 0.0 if terrain.flat else min(float(lo[1]), float(terrain.height(0.5 * (lo + hi)[[0, 2]])))
    centre = 0.5 * (lo + hi)
    return centre, float(np.linalg.norm(hi - lo) * 0.5 + 0.05)


def light_view_proj(scene: SceneInstances, ground: float | None = None) -> tuple[glm.mat4, float]:
    """Orthographic key-light matrix fitted tightly around the shadow casters, and the
    world size (m) of one shadow-map texel.

    Seen from a directional light, a shadow lies exactly within its casters' xy
    footprint, so any receiver outside this box is lit and costs no shadow lookups.
    The depth range reaches past the casters down to the ground under them (``ground``:
    the terrain's height under the creature; None for the flat floor).
    """
    points, pads = scene.spheres()
    centre = 0.5 * (points.min(axis=0) + points.max(axis=0))
    height = float(points[:, 1].max() + pads.max())
    view = glm.lookAt(glm.vec3(*(centre - LIGHT_DIR * (height + 1.0) * 4.0)), glm.vec3(*centre),
                      glm.vec3(0.0, 0.0, 1.0))
    m = np.array(view, dtype=np.float64)  # numpy sees glm matrices row-major (as written in maths)
    local = points @ m[:3, :3].T + m[:3, 3]
    lo = local.min(axis=0) - pads.max()
    hi = local.max(axis=0) + pads.max()
    # From the highest caster down to the flat floor (y = 0), or on terrain as far again
    # below it, for slopes falling away.
    drop = height if ground is None else 2.0 * (height - ground) + 0.5 * float(np.ptp(points[:, 0]))
    reach = drop / max(-LIGHT_DIR[1], 1e-3) + 0.01
    near, far = -hi[2] - 0.01, -lo[2] + reach
    proj = glm.ortho(float(lo[0]), float(hi[0]), float(lo[1]), float(hi[1]), float(near), float(far))
    return cast(glm.mat4, proj * view), float(max(hi[0] - lo[0], hi[1] - lo[1]) / SHADOW_MAP_SIZE)


SHADOW_OUTLINE_SIDES = 32  # directions of the polygon that holds the shadow on the floor


def shadow_outline(scene: SceneInstances, texel: float,
                   sides: int = SHADOW_OUTLINE_SIDES) -> NDArray[np.float64]:
    """A convex polygon on the plane y = 0 holding the creatures' shadow: (sides, 2)
    world xz corners in order around it.

    Every caster sphere is projected along the light (its shadow lies within
    radius / |light y| of its centre's) and padded by four shadow-map texels (the soft
    filter's reach and the normal offset). The polygon's edges touch the padded shadow in
    ``sides`` evenly spaced directions: much tighter than the shadow's bounding box for
    an oblique light, so the soft lookups run over the shadow and little else."""
    points, radii = scene.spheres(casters_only=True)
    on_ground = (points - LIGHT_DIR * (points[:, 1:2] / LIGHT_DIR[1]))[:, [0, 2]]
    pads = radii / abs(LIGHT_DIR[1]) + 4.0 * texel
    angles = np.arange(sides) * (2.0 * np.pi / sides)
    normals = np.column_stack([np.cos(angles), np.sin(angles)])  # (sides, 2) outward edge normals
    reach = (on_ground @ normals.T + pads[:, None]).max(axis=0)  # (sides,) support distances
    # Corner k: where edge k meets edge k + 1 (two lines n . x = h, solved in closed form).
    n0, n1 = normals, np.roll(normals, -1, axis=0)
    h0, h1 = reach, np.roll(reach, -1)
    det = n0[:, 0] * n1[:, 1] - n0[:, 1] * n1[:, 0]
    return np.column_stack([(h0 * n1[:, 1] - h1 * n0[:, 1]) / det, (h1 * n0[:, 0] - h0 * n1[:, 0]) / det])


def floor_light(options: RenderOptions) -> tuple[np.ndarray, np.ndarray]:
    """Ambient and sun light reaching the flat floor: lighting.glsl's model for an upward
    normal (``ambient_light(up)`` and the wrapped key light)."""
    sky = srgb_to_linear(options.sky_color)
    ambient = sky * 0.55  # mix(bounce, sky, 0.5 + 0.5 * n.y) with n = up
    wrapped = max((-LIGHT_DIR[1] + 0.35) / 1.35, 0.0)
    return ambient, SUN_COLOR * wrapped


SKY_FADE = 0.45  # the sky turns from the horizon colour to its own by this height (sine of elevation)
SKY_ROWS = 12  # rows of the band's gradient (a smoothstep, linear between rows)


def sky_band(camera: Camera, aspect: float, centre: np.ndarray, reach: float,
             ground_level: float = 0.0) -> np.ndarray | None:
    """The sky's screen band, from the floor's far edge straight ahead up to the top of
    the view, as rows (K, 2): ndc y and height (the sine of the elevation the row looks
    at), bottom to top, spaced to follow the gradient (:data:`SKY_ROWS` through the
    fade, one more at the top); None when no sky is in view: when the view's top looks
    no higher than the horizon, what lies beyond the floor is all horizon colour (the
    clear colour), and a band would cost its pixels for nothing."""
    forward = np.asarray(camera.target, dtype=np.float64) - camera.eye
    flat = np.array([forward[0], 0.0, forward[2]])
    if camera.top_down or np.linalg.norm(flat) < 1e-6:
        return None
    flat /= np.linalg.norm(flat)
    edge = np.array([centre[0], ground_level, centre[2]]) + flat * reach
    vp = np.array(camera.view_proj(aspect), dtype=np.float64)
    clip = vp @ np.append(edge, 1.0)
    y0 = float(np.clip(clip[1] / clip[3], -1.0, 1.0)) if clip[3] > 0 else -1.0
    if y0 >= 1.0:
        return None
    if camera.ortho:
        h1 = 0.6
    else:
        far = np.linalg.inv(vp) @ np.array([0.0, 1.0, 1.0, 1.0])
        ray = far[:3] / far[3] - camera.eye
        h1 = float(ray[1] / np.linalg.norm(ray))
    if h1 <= 0.0:
        return None
    # Height runs linearly up the screen from the edge (0) to the top (h1).
    heights = np.linspace(0.0, min(h1, SKY_FADE), SKY_ROWS + 1)
    if h1 > SKY_FADE:
        heights = np.append(heights, h1)
    rows = y0 + (1.0 - y0) * heights / h1
    return np.column_stack([rows, heights])
