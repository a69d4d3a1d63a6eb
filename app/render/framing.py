"""Filming a clip: a camera per frame that keeps the creatures in view, and a grid
spacing that makes whole-cycle clips loop without a seam (numbers only, no OpenGL)."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
from numpy.typing import NDArray

from ..kinematics.motion import Motion
from .camera import Camera, clear_elevations, frame_points, look_ahead, point3, preset_for
from .options import ViewSettings, nice_grid_spacing
from .scene import box_corners, creature_points, motion_bounds

FOLLOW_SMOOTHING = 1.0  # seconds over which the follow camera averages the ground's height


def clip_camera(motion: Motion, view: ViewSettings) -> Camera:
    """The preset camera framing the creature over the whole clip (no jitter); for a
    travelling creature, its first frame of :func:`clip_cameras`."""
    return clip_cameras(motion, view)[0]


def clip_cameras(motion: Motion, view: ViewSettings, extra: NDArray[np.float64] | None = None) -> list[Camera]:
    """A camera per frame. In place: one fixed preset camera framing the whole clip. A
    travelling creature is followed: the preset's angle is kept relative to the path's
    heading, the target moves with the body along its path (at the ground's height,
    smoothed), and the distance frames the creature's whole motion about that point, so
    it never leaves the frame and the camera does not jitter with the steps. ``extra``
    (T, K, 3): more points to keep in view (a herd around a travelling creature)."""
    w, h = view.size
    aspect = w / h
    preset = preset_for(view.camera)
    length = motion.rig.body_length
    if motion.in_place:
        points = look_ahead(motion_bounds(motion), preset, length)
        return [frame_points(points, preset, aspect=aspect)] * motion.frame_count
    points, tangents = motion.path.sample(motion.travel)
    heading = np.unwrap(np.arctan2(tangents[:, 0], tangents[:, 1]))
    ground = np.zeros(motion.frame_count)
    if not motion.terrain.flat:
        from scipy.ndimage import uniform_filter1d

        window = max(1, int(round(FOLLOW_SMOOTHING * motion.fps)))
        ground = uniform_filter1d(motion.terrain.height(points), size=window, mode="nearest")
    anchor = np.column_stack([points[:, 0], ground, points[:, 1]])
    c, s = np.cos(heading), np.sin(heading)
    points_all = creature_points(motion)
    if extra is not None:
        points_all = np.concatenate([points_all, extra], axis=1)
    rel = points_all - anchor[:, None, :]
    # Into each frame's heading frame (the creature facing +Z): rotate by -heading about Y.
    local = np.stack([c[:, None] * rel[..., 0] - s[:, None] * rel[..., 2], rel[..., 1],
                      s[:, None] * rel[..., 0] + c[:, None] * rel[..., 2]], axis=-1).reshape(-1, 3)
    lo, hi = local.min(axis=0), local.max(axis=0)
    lo[1] = min(lo[1], 0.0)
    base = frame_points(look_ahead(box_corners(lo, hi), preset, length), preset, aspect=aspect)
    tx, ty, tz = base.target
    targets = anchor + np.stack([c * tx + s * tz, np.full_like(c, ty), -s * tx + c * tz], axis=-1)
    azimuths = base.azimuth + np.degrees(heading)
    elevations = np.full(motion.frame_count, base.elevation)
    if not motion.terrain.flat and not base.top_down:
        # Rise over hills that would hide the creature; smoothly (the highest need within
        # a second either side, then averaged), and never lower than the preset.
        from scipy.ndimage import maximum_filter1d, uniform_filter1d

        need = clear_elevations(targets, azimuths, base.elevation, base.distance, motion.terrain.height,
                                margin=0.1 * motion.rig.hip_height)
        window = max(1, int(round(FOLLOW_SMOOTHING * motion.fps)))
        elevations = np.maximum(uniform_filter1d(maximum_filter1d(need, 2 * window + 1, mode="nearest"), window,
                                                 mode="nearest"), base.elevation)
    return [replace(base, target=point3(targets[i]), azimuth=float(azimuths[i]),
                    elevation=float(elevations[i])) for i in range(motion.frame_count)]


def loop_grid_spacing(motion: Motion, cycles: float | None) -> float:
    """A round grid spacing for the creature's size; for a clip of whole cycles it is
    nudged so the ground has moved a whole number of major squares (5 lines) by the end,
    which makes the loop seamless."""
    spacing = nice_grid_spacing(motion.rig.hip_height * 1.6)
    travel = float(motion.travel[-1] - motion.travel[0]) + (
        float(motion.travel[1] - motion.travel[0]) if motion.frame_count > 1 else 0.0)
    if cycles and travel > 0:
        majors = max(1, round(travel / (5.0 * spacing)))
        spacing = travel / (5.0 * majors)
    return spacing
