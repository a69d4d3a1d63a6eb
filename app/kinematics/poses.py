"""Key poses: the body's height through a step as an animator keys it.

A step runs from one foot's contact to the other's (half a cycle). Its key poses fall at
fixed fractions of it (:data:`app.styles.KEY_POSE_TIMES`): contact 0, down 1/4, pass 1/2,
up 3/4; the next contact starts the mirrored step. The in-betweens follow a periodic
monotone cubic (PCHIP) through the four heights: smooth (C1), no overshoot, so the lowest
and highest points of the curve are key poses themselves — moving the down pose moves the
body's lowest point by exactly as much, and no other key pose moves.

Pure numpy and scipy, no GL.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np
from numpy.typing import NDArray
from scipy.interpolate import PchipInterpolator

from ..styles import KEY_POSE_TIMES
from .rig import Rig


def reference_foot(rig: Rig) -> int:
    """The foot whose touchdown starts a cycle: the rearmost left foot (Hildebrand)."""
    return rig.leg_count - 2


def step_phase(rig: Rig, phase: NDArray[np.float64]) -> NDArray[np.float64]:
    """Where each frame is within its step, [0, 1): 0 at the reference foot's contact and
    again at the other side's, half a cycle later. phase (T, L) feet's phases since touchdown."""
    return np.mod(2.0 * phase[..., reference_foot(rig)], 1.0)


@lru_cache(maxsize=64)
def _curve(heights: tuple[float, ...]) -> PchipInterpolator:
    times = np.asarray(KEY_POSE_TIMES)
    values = np.asarray(heights)
    # Two keys either side wrap the step around, so the slopes at contact match (periodic).
    t = np.concatenate([times[-2:] - 1.0, times, times[:2] + 1.0, [times[2] + 1.0]])
    v = np.concatenate([values[-2:], values, values[:2], [values[2]]])
    return PchipInterpolator(t, v)


def pose_height(heights: NDArray[np.float64], u: NDArray[np.float64]) -> NDArray[np.float64]:
    """The body's height offset (m) at step phases ``u`` (...), through the key poses'
    heights (4,) (contact, down, pass, up)."""
    curve = _curve(tuple(round(float(h), 9) for h in heights))  # nanometres: no overflowing slopes
    return curve(np.mod(u, 1.0))


def key_pose_phases(first_step: bool = True) -> NDArray[np.float64]:
    """Cycle phases of contact, down, pass, up and the next contact (5,), for the first
    step (or the second, mirrored one)."""
    start = 0.0 if first_step else 0.5
    return start + 0.5 * np.append(np.asarray(KEY_POSE_TIMES), 1.0)
