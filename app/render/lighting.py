"""The light and what it reaches, as numbers (no OpenGL): the key light's direction, the
shadow map's fit around the casters, the shadow's footprint on the floor, the floor's
light and the sky's band on screen. The passes in :mod:`.renderer` and
:mod:`.ground` draw with these."""

from __future__ import annotations

from typing import cast

import numpy as np
from pyglm import glm

from ..kinematics.terrain import Terrain
from .camera import Camera
from .options import RenderOptions
from .scene import SceneInstances, srgb_to_linear

SHADOW_MAP_SIZE = 256
SUN_COLOR = np.array([0.95, 0.90, 0.84])  # as in shaders/lighting.glsl
LIGHT_DIR = np.array([-0.45, -1.0, -0.35]) / np.linalg.norm([-0.45, -1.0, -0.35])


def creature_bounds(scene: SceneInstances, terrain: Terrain) -> tuple[np.ndarray, float]:
    """The creatures' box down to the ground: its centre (3,) and half diagonal (m)."""
    caps, ells = scene.capsules, scene.ellipsoids
    from .scene import Cap, Ell

    pts = np.concatenate([caps[:, Cap.A], caps[:, Cap.B], ells[:, Ell.CENTRE]])
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


def shadow_footprint(scene: SceneInstances, texel: float) -> tuple[np.ndarray, np.ndarray]:
    """World xz bounds (lo, hi) of the shadow on the plane y = 0: every caster point
    projected along the light, padded by the largest radius."""
    points, radii = scene.spheres(casters_only=True)
    pad = float(radii.max())
    on_ground = points - LIGHT_DIR * (points[:, 1:2] / LIGHT_DIR[1])
    pad = pad / abs(LIGHT_DIR[1]) + 4.0 * texel
    return on_ground[:, [0, 2]].min(axis=0) - pad, on_ground[:, [0, 2]].max(axis=0) + pad


def floor_light(options: RenderOptions) -> tuple[np.ndarray, np.ndarray]:
    """Ambient and sun light reaching the flat floor: lighting.glsl's model for an upward
    normal (``ambient_light(up)`` and the wrapped key light)."""
    sky = srgb_to_linear(options.sky_color)
    ambient = sky * 0.55  # mix(bounce, sky, 0.5 + 0.5 * n.y) with n = up
    wrapped = max((-LIGHT_DIR[1] + 0.35) / 1.35, 0.0)
    return ambient, SUN_COLOR * wrapped


def sky_band(camera: Camera, aspect: float, centre: np.ndarray, reach: float,
             ground_level: float = 0.0) -> np.ndarray | None:
    """The sky's screen band: from the floor's far edge straight ahead up to the top of
    the view, as 4 vertices (ndc x, ndc y, height); None when no sky is in view."""
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
        h1 = max(float(ray[1] / np.linalg.norm(ray)), 0.0)
    return np.array([[-1, y0, 0.0], [1, y0, 0.0], [-1, 1, h1], [1, 1, h1]], dtype="f4")
