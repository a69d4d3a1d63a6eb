"""Resolving a gait spec (preset + adjustments) into the numbers the oscillators use."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from ..gaits import TETRAPOD_FEET
from ..spec import GaitSpec, WaveShape
from .oscillator import duty_from_bias

G = 9.81


@dataclass(frozen=True)
class GaitParams:
    """A fully resolved gait.

    frequency:    strides per second (Hz)
    duty_factor:  fraction of the cycle each foot is planted
    offsets:      (L,) touchdown phase of each foot (cycle fractions), left hind = 0
    stride:       planted-foot travel relative to the hip, in mean leg rest lengths
    step_height:  swing height in each leg's rest length
    bob:          body bob amplitude in leg rest lengths
    wave:         oscillator shape
    """

    preset: str
    frequency: float
    duty_factor: float
    offsets: NDArray[np.float64]
    stride: float
    step_height: float
    bob: float
    wave: WaveShape

    @property
    def bias(self) -> float:
        """The seed's swing/stance bias b that gives this duty factor."""
        from .oscillator import bias_from_duty

        return float(bias_from_duty(self.duty_factor))


def phases_from_offsets(front_back: float, left_right: float,
                        feet: tuple[str, ...] = TETRAPOD_FEET) -> NDArray[np.float64]:
    """Touchdown phases ``LH=0, RH=lr, LF=fb, RF=fb+lr`` in the order of ``feet``, in [0, 1)."""
    table = {"LH": 0.0, "RH": left_right, "LF": front_back, "RF": front_back + left_right}
    return np.mod(np.array([table[f] for f in feet], dtype=np.float64), 1.0)


def resolve_phases(gait: GaitSpec, feet: tuple[str, ...] = TETRAPOD_FEET) -> NDArray[np.float64]:
    """Each foot's touchdown phase for a gait spec, shape (L,), in [0, 1)."""
    preset = gait.preset_spec
    if gait.phases is not None:
        given = dict(gait.phases)
        return np.mod(np.array([given[f] for f in feet], dtype=np.float64), 1.0)
    if preset.symmetric:
        fb = preset.front_back if gait.front_back is None else gait.front_back
        lr = preset.left_right if gait.left_right is None else gait.left_right
        return phases_from_offsets(fb, lr, feet)
    return np.mod(np.array([preset.phases[f] for f in feet], dtype=np.float64), 1.0)


def resolve_duty(gait: GaitSpec) -> float:
    """The duty factor: given directly, from the bias, or the preset's."""
    if gait.duty_factor is not None:
        return float(gait.duty_factor)
    if gait.bias is not None:
        return float(duty_from_bias(gait.bias))
    return gait.preset_spec.duty_factor


def natural_frequency(cadence: float, hip_height: float) -> float:
    """Stride frequency (Hz) of a Froude-scaled cadence ``f sqrt(h/g)`` at hip height h (m)."""
    return cadence * math.sqrt(G / hip_height)


def resolve_gait(gait: GaitSpec, feet: tuple[str, ...], hip_height: float, bob: float | None = None) -> GaitParams:
    """Combine a gait spec with its preset. ``hip_height`` (m) sets the default frequency."""
    preset = gait.preset_spec
    return GaitParams(
        preset=gait.preset,
        frequency=gait.frequency if gait.frequency is not None else natural_frequency(preset.cadence, hip_height),
        duty_factor=resolve_duty(gait),
        offsets=resolve_phases(gait, feet),
        stride=preset.stride if gait.stride is None else gait.stride,
        step_height=preset.step_height if gait.step_height is None else gait.step_height,
        bob=preset.bob if bob is None else bob,
        wave=gait.wave,
    )
