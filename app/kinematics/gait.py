"""A resolved gait: the numbers the oscillators use (built from a creature file by
:mod:`app.rigging`; no file types here)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from ..choices import WaveShape

G = 9.81  # m/s^2
WALK_DUTY = (0.45, 0.55)  # duty factors over which a walk turns into a run (a walker's swing, stance, heights)


@dataclass(frozen=True)
class GaitParams:
    """A fully resolved gait.

    preset:       the gait preset's name
    frequency:    strides per second (Hz)
    duty_factor:  fraction of the cycle each foot is planted
    offsets:      (L,) touchdown phase of each foot (cycle fractions), rearmost left = 0
    stride:       planted-foot travel relative to the hip, in mean leg rest lengths
    step_height:  swing height in each leg's rest length
    bob:          body bob amplitude in leg rest lengths
    wave:         oscillator shape
    flex:         how far (rad, either way) the spine flexes and extends with the hind legs
    pitch:        how far (rad, over a cycle) the trunk pitches through stances and flights
    """

    preset: str
    frequency: float
    duty_factor: float
    offsets: NDArray[np.float64]
    stride: float
    step_height: float
    bob: float
    wave: WaveShape
    flex: float = 0.0
    pitch: float = 0.0

    @property
    def bias(self) -> float:
        """The seed's swing/stance bias b that gives this duty factor."""
        from .oscillator import bias_from_duty

        return float(bias_from_duty(self.duty_factor))


def natural_frequency(cadence: float, hip_height: float) -> float:
    """Stride frequency (Hz) of a Froude-scaled cadence ``f sqrt(h/g)`` at hip height h (m)."""
    return cadence * math.sqrt(G / hip_height)


def ground_speed(stride_m: float | NDArray, duty: float | NDArray, frequency: float | NDArray = 1.0):
    """Speed (m/s, or m per cycle with the default frequency) at which planted feet move
    relative to the body: a foot covers ``stride_m`` in ``duty`` of a cycle."""
    return stride_m / duty * frequency


def walking_weight(duty: float | NDArray[np.float64]) -> NDArray[np.float64]:
    """1 for a walk (duty factor 0.55 and over), 0 for a run (0.45 and under), smooth
    (smoothstep) between; the shape of ``duty``."""
    low, high = WALK_DUTY
    x = np.clip((np.asarray(duty, dtype=np.float64) - low) / (high - low), 0.0, 1.0)
    return x * x * (3.0 - 2.0 * x)
