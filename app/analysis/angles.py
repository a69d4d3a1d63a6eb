"""Sagittal joint angles as clinical gait analysis gives them, from joint positions, and
their mean curves over a normalised cycle.

Conventions (degrees, in the plane of the body's forward direction and up):

- **hip**: the thigh against the vertical, + flexion (the knee ahead of the hip). Clinical
  hip flexion is against the pelvis; a pelvis tilted forward by p adds p to it
  (``normative`` curves are converted with their own pelvic tilt).
- **knee**: flexion, the angle between thigh and shank, 0 straight, + bent.
- **ankle**: dorsiflexion, the foot against the shank, 0 at the standing pose (the
  foot at a right angle to the shank as it stands), + toes towards the shin, -
  plantarflexion.

A cycle runs from a foot's strike to its next strike (0-100 %), resampled at 101 points;
the mean curve is the average of every whole cycle.

Pure numpy, no GL.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

JOINTS: tuple[str, ...] = ("hip", "knee", "ankle")
SAMPLES = 101  # points of a normalised cycle, 0..100 %


@dataclass(frozen=True)
class LegAngles:
    """One leg's sagittal angles over a clip, degrees, (T,) each."""

    hip: NDArray[np.float64]
    knee: NDArray[np.float64]
    ankle: NDArray[np.float64]

    def joint(self, name: str) -> NDArray[np.float64]:
        return getattr(self, name)


def _unit(v: NDArray[np.float64]) -> NDArray[np.float64]:
    return v / np.maximum(np.linalg.norm(v, axis=-1, keepdims=True), 1e-12)


def sagittal_frame(forward: NDArray[np.float64], up: NDArray[np.float64] | None = None
                   ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Unit forward (horizontal) and up vectors (T, 3) of the body's sagittal plane from a
    forward direction (T, 3) (only its horizontal part counts)."""
    up_v = np.broadcast_to(np.array([0.0, 1.0, 0.0]) if up is None else up, forward.shape)
    horizontal = forward - np.sum(forward * up_v, axis=-1, keepdims=True) * up_v
    return _unit(horizontal), up_v


def leg_angles(hip: NDArray[np.float64], knee: NDArray[np.float64], ankle: NDArray[np.float64],
               foot: NDArray[np.float64], forward: NDArray[np.float64], ankle_zero: float = 0.0) -> LegAngles:
    """The sagittal angles of one leg from its points (T, 3) each: hip, knee, ankle and a
    point ahead along the foot (the ball, or the toe); ``forward`` (T, 3) the body's
    forward direction. ``ankle_zero`` (deg) is the dorsiflexion the same formula gives in
    the standing pose, subtracted so standing reads 0."""
    fwd, up = sagittal_frame(forward)

    def from_vertical(v: NDArray[np.float64]) -> NDArray[np.float64]:
        """Angle (deg) of a downward segment from the vertical, + when its lower end is ahead."""
        return np.degrees(np.arctan2(np.sum(v * fwd, axis=-1), -np.sum(v * up, axis=-1)))

    thigh = from_vertical(knee - hip)
    shank = from_vertical(ankle - knee)
    flexion = thigh - shank
    # The foot against the shank, in the sagittal plane: 90 degrees (a right angle) reads 0.
    f = foot - ankle
    s = knee - ankle  # up the shank
    foot_angle = np.arctan2(np.sum(f * up, axis=-1), np.sum(f * fwd, axis=-1))
    shank_angle = np.arctan2(np.sum(s * up, axis=-1), np.sum(s * fwd, axis=-1))
    between = np.degrees(shank_angle - foot_angle)
    dorsiflexion = 90.0 - (np.mod(between + 180.0, 360.0) - 180.0) - ankle_zero
    return LegAngles(hip=thigh, knee=flexion, ankle=dorsiflexion)


def strikes_from_contact(contact: NDArray[np.bool_]) -> NDArray[np.intp]:
    """Frames (K,) at which a foot touches down: contact goes from False to True."""
    c = np.asarray(contact, dtype=bool)
    return np.nonzero(c[1:] & ~c[:-1])[0] + 1


def cycle_curves(values: NDArray[np.float64], strikes: NDArray[np.intp]) -> NDArray[np.float64]:
    """Every whole cycle of ``values`` (T,) between consecutive ``strikes``, resampled at
    :data:`SAMPLES` points: (cycles, SAMPLES); empty (0, SAMPLES) with fewer than two
    strikes."""
    s = np.asarray(strikes, dtype=np.intp)
    if len(s) < 2:
        return np.zeros((0, SAMPLES))
    out = np.empty((len(s) - 1, SAMPLES))
    grid = np.linspace(0.0, 1.0, SAMPLES)
    for k, (a, b) in enumerate(zip(s[:-1], s[1:])):  # a handful of cycles
        frames = np.arange(a, b + 1)
        out[k] = np.interp(grid, (frames - a) / max(b - a, 1), values[frames])
    return out


def mean_curve(values: NDArray[np.float64], strikes: NDArray[np.intp]) -> NDArray[np.float64] | None:
    """The mean over whole cycles (SAMPLES,), or None without one."""
    curves = cycle_curves(values, strikes)
    return curves.mean(axis=0) if len(curves) else None


def rms(a: NDArray[np.float64], b: NDArray[np.float64]) -> float:
    """Root-mean-square difference of two curves (degrees)."""
    return float(np.sqrt(np.mean((np.asarray(a) - np.asarray(b)) ** 2)))
