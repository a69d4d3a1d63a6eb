"""Cameras: presets (side, front, top, three-quarter, chase), framing, view/projection matrices."""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from functools import cached_property
from typing import cast

import numpy as np
from numpy.typing import NDArray
from pyglm import glm

from ..choices import CAMERA_PRESETS, DEFAULT_CAMERA, CameraPreset

CHASE_LOOK_AHEAD = 1.2  # body lengths of ground ahead that the chase camera keeps in view


def preset_for(choice: str) -> CameraPreset:
    """The preset a camera choice films with ("follow" is the default preset)."""
    return DEFAULT_CAMERA if choice == "follow" else choice  # type: ignore[return-value]


def look_ahead(points: NDArray[np.float64], preset: str, length: float) -> NDArray[np.float64]:
    """Points to frame for ``preset``: for "chase", ``points`` (N, 3, in a frame where the
    creature faces +Z) and the same points ``CHASE_LOOK_AHEAD`` x ``length`` (m) ahead,
    so the view looks where the creature is going; otherwise ``points`` as they are."""
    if preset != "chase":
        return points
    return np.concatenate([points, points + np.array([0.0, 0.0, CHASE_LOOK_AHEAD * length])])

# (azimuth, elevation) in degrees. Azimuth 0 looks at the creature's right side (camera
# on -X), so it faces screen-right; 90 looks at its face (camera on +Z).
_PRESET_ANGLES: dict[str, tuple[float, float]] = {
    "side": (0.0, 6.0),
    "front": (90.0, 8.0),
    "top": (0.0, 89.0),
    "three-quarter": (38.0, 20.0),
    "chase": (-90.0, 20.0),  # behind (camera on -Z), a little above, looking ahead
}


def point3(values: object) -> tuple[float, float, float]:
    """Three numbers (an array or a sequence) as a point tuple of floats."""
    x, y, z = (float(v) for v in values)  # type: ignore[attr-defined]
    return x, y, z


@dataclass(frozen=True)
class Camera:
    """An orbit camera: it looks at ``target`` from ``distance`` along (azimuth, elevation).

    Angles in degrees, lengths in metres. ``ortho`` switches to an orthographic
    projection whose view height matches the perspective one at the target.
    """

    target: tuple[float, float, float] = (0.0, 0.4, 0.0)
    azimuth: float = 38.0
    elevation: float = 20.0
    distance: float = 3.0
    fov: float = 30.0
    ortho: bool = False
    top_down: bool = False

    # A camera never changes (a new one is made for every move), so what it works out is
    # kept: a frame asks for its eye and its matrices a dozen times. Read-only arrays.

    @cached_property
    def direction(self) -> NDArray[np.float64]:
        """Unit vector from the target to the eye."""
        az, el = math.radians(self.azimuth), math.radians(self.elevation)
        direction = np.array([-math.cos(el) * math.cos(az), math.sin(el), math.cos(el) * math.sin(az)])
        direction.flags.writeable = False
        return direction

    @cached_property
    def eye(self) -> NDArray[np.float64]:
        eye = np.asarray(self.target) + self.distance * self.direction
        eye.flags.writeable = False
        return eye

    @property
    def up(self) -> NDArray[np.float64]:
        return np.array([0.0, 0.0, 1.0]) if self.top_down else np.array([0.0, 1.0, 0.0])

    def view(self) -> glm.mat4:
        return glm.lookAt(glm.vec3(*self.eye), glm.vec3(*self.target), glm.vec3(*self.up))

    def projection(self, aspect: float) -> glm.mat4:
        near = max(self.distance * 0.02, 0.01)
        far = self.distance * 20.0 + 10.0
        if self.ortho:
            half_h = self.distance * math.tan(math.radians(self.fov) / 2.0)
            return glm.ortho(-half_h * aspect, half_h * aspect, -half_h, half_h, near, far)
        return glm.perspective(math.radians(self.fov), aspect, near, far)

    def view_proj(self, aspect: float) -> glm.mat4:
        cached = self.__dict__.get("_view_proj")
        if cached is None or cached[0] != aspect:
            matrix = cast(glm.mat4, self.projection(aspect) * self.view())  # pyglm's stubs type mat4 * mat4 loosely
            cached = (aspect, matrix)
            self.__dict__["_view_proj"] = cached  # (frozen: kept beside the fields, as cached_property does)
        return glm.mat4(cached[1])  # a copy: glm matrices are mutable

    def orbit(self, d_azimuth: float, d_elevation: float) -> Camera:
        return replace(self, azimuth=self.azimuth + d_azimuth,
                       elevation=float(np.clip(self.elevation + d_elevation, -5.0, 89.0)), top_down=False)

    def zoom(self, factor: float) -> Camera:
        return replace(self, distance=float(np.clip(self.distance * factor, 0.05, 500.0)))

    def pan(self, dx: float, dy: float) -> Camera:
        """Move the target by (dx, dy) fractions of the view height, in screen directions."""
        forward = -self.direction
        right = np.cross(forward, self.up)
        right = right / max(float(np.linalg.norm(right)), 1e-9)
        up = np.cross(right, forward)
        scale = 2.0 * self.distance * math.tan(math.radians(self.fov) / 2.0)
        target = np.asarray(self.target) + scale * (-dx * right + dy * up)
        return replace(self, target=point3(target))


def frame_points(points: NDArray[np.float64], preset: CameraPreset | str = DEFAULT_CAMERA,
                 aspect: float = 4.0 / 3.0, margin: float = 1.12, fov: float = 30.0,
                 ortho: bool = False) -> Camera:
    """A preset camera that keeps every point of ``points`` (N, 3) in view.

    The target is the centre of the points' bounding box; the distance is the smallest
    that fits all points inside the frustum (exact for a perspective camera), times
    ``margin``.
    """
    preset = preset_for(preset)
    if preset not in _PRESET_ANGLES:
        raise ValueError(f"unknown camera {preset!r}; expected one of {', '.join(CAMERA_PRESETS)}")
    azimuth, elevation = _PRESET_ANGLES[preset]
    lo, hi = points.min(axis=0), points.max(axis=0)
    centre = 0.5 * (lo + hi)
    cam = Camera(target=point3(centre), azimuth=azimuth, elevation=elevation, fov=fov,
                 ortho=ortho, top_down=(preset == "top"), distance=1.0)
    back = cam.direction
    right = np.cross(-back, cam.up)
    right /= np.linalg.norm(right)
    up = np.cross(right, -back)
    rel = points - centre
    x, y, z = rel @ right, rel @ up, rel @ back  # z > 0: towards the camera
    tan_v = math.tan(math.radians(fov) / 2.0)
    tan_h = tan_v * aspect
    if ortho:
        need = max(np.abs(y).max() / tan_v, np.abs(x).max() / tan_h)
    else:
        need = max((np.abs(x) / tan_h + z).max(), (np.abs(y) / tan_v + z).max())
    return replace(cam, distance=float(max(need, 1e-3) * margin))


def clear_elevations(targets: NDArray[np.float64], azimuths: NDArray[np.float64], elevation: float,
                     distance: float, height_at, margin: float, step: float = 4.0,
                     highest: float = 70.0) -> NDArray[np.float64]:
    """For cameras looking at ``targets`` (T, 3) from ``azimuths`` (T,) degrees at
    ``distance`` m: the lowest elevation (degrees, from ``elevation`` up in ``step``s, at
    most ``highest``) at which the sight line from the eye to the target stays ``margin``
    m above the ground (``height_at``: (N, 2) -> (N,)), so hills never hide the creature."""
    frames = targets.shape[0]
    candidates = np.arange(elevation, max(highest, elevation) + 1e-9, step)  # (C,)
    az = np.radians(azimuths)[:, None]
    el = np.radians(candidates)[None, :]
    direction = np.stack(np.broadcast_arrays(-np.cos(el) * np.cos(az), np.sin(el), np.cos(el) * np.sin(az)),
                         axis=-1)  # (T, C, 3)
    along = np.linspace(0.02, 1.0, 40)  # from next to the target (a riser at its feet) out to the eye
    points = targets[:, None, None, :] + distance * along[None, None, :, None] * direction[:, :, None, :]
    ground = height_at(points[..., [0, 2]].reshape(-1, 2)).reshape(points.shape[:-1])
    clear = np.all(points[..., 1] >= ground + margin, axis=-1)  # (T, C)
    first = np.where(clear.any(axis=1), clear.argmax(axis=1), len(candidates) - 1)
    return candidates[first] if frames else np.zeros(0)


def eye_ray(camera: Camera, aspect: float, ndc: tuple[float, float]
            ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The ray through view point ``ndc`` (x, y in -1..1): origin on the near plane (3,)
    and unit direction (3,)."""
    inverse = np.linalg.inv(np.array(camera.view_proj(aspect), dtype=np.float64))
    near = inverse @ np.array([ndc[0], ndc[1], -1.0, 1.0])
    far = inverse @ np.array([ndc[0], ndc[1], 1.0, 1.0])
    origin = near[:3] / near[3]
    direction = far[:3] / far[3] - origin
    return origin, direction / np.linalg.norm(direction)


def ground_point(camera: Camera, aspect: float, ndc: tuple[float, float], height,
                 reach: float = 500.0, samples: int = 512) -> NDArray[np.float64] | None:
    """Where the ray through ``ndc`` (x, y in -1..1 of the view) first meets the ground
    ``height`` (a function of (N, 2) x, z giving (N,) heights): (x, y, z), or None when
    it meets no ground within ``reach`` m (the sky). Marched in ``samples`` steps, then
    refined by bisection within the step that crosses the ground."""
    origin, direction = eye_ray(camera, aspect, ndc)
    t = np.linspace(0.0, reach, samples) ** 2 / reach  # finer near the eye
    points = origin + t[:, None] * direction
    above = points[:, 1] - height(points[:, [0, 2]])
    below = np.nonzero(above <= 0.0)[0]
    if not len(below):
        return None
    i = int(below[0])
    if i == 0:
        return points[0]
    lo, hi = float(t[i - 1]), float(t[i])
    for _ in range(30):  # bisection within the bracketing step: well under a millimetre
        mid = 0.5 * (lo + hi)
        p = origin + mid * direction
        if p[1] - float(height(p[None, [0, 2]])[0]) > 0.0:
            lo = mid
        else:
            hi = mid
    return origin + hi * direction
