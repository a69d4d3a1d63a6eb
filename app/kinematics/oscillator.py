"""Foot oscillators: where each foot is in its step, as pure functions of its phase.

A foot's *phase* ``phi`` is a fraction of its cycle in [0, 1) measured from touchdown:
the foot is planted for ``0 <= phi < duty`` and swings for ``duty <= phi < 1``.

Two wave shapes:

``"skewed-sine"``
    The seed's waves. With ``k_duty = e^b`` and ``k_slope = (2/pi) atan b``:
    vertical ``peak(x) = 2 (k^(sin x) - 1/k) / (k - 1/k) - 1`` (planted where
    ``peak(x + pi/2) <= 0``) and fore-aft ``slope(x) = (1/k) atan2(k sin x, 1 - k cos x)``
    (normalised here to amplitude 1). The closed-form duty factor is
    ``duty(b) = 1/2 + asin(ln(cosh b) / b) / pi``. Both tend to ``sin x`` as ``b -> 0``.
    The wave angle is aligned so that touchdown is exactly at ``phi = 0``, which keeps
    each foot's phase offset as ``b`` passes through 0.

``"planted"``
    The foot moves linearly backwards during stance (constant ground speed, so it stays
    put on a moving ground) and forward on an eased arc during swing, with exactly the
    requested duty factor.

All functions broadcast over any array shape and do no Python-level looping.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..choices import WaveShape
from .easing import smootherstep

_TINY_BIAS = 1e-12
_TINY_SLOPE = 1e-12


def _log_cosh(b: NDArray[np.float64]) -> NDArray[np.float64]:
    """``ln(cosh b)`` accurate for all b: ``log1p(2 sinh^2(b/2))`` for small |b| (no
    cancellation), ``|b| + log1p(e^(-2|b|)) - ln 2`` for large |b| (no overflow)."""
    a = np.abs(b)
    small = np.log1p(2.0 * np.sinh(0.5 * np.minimum(a, 2.0)) ** 2)
    large = a + np.log1p(np.exp(-2.0 * a)) - np.log(2.0)
    return np.where(a < 2.0, small, large)


def duty_threshold(bias: ArrayLike) -> NDArray[np.float64]:
    """``c(b) = ln(cosh b) / b``: the foot is planted where ``cos x <= c`` (0 at b = 0)."""
    b = np.asarray(bias, dtype=np.float64)
    safe = np.where(np.abs(b) < _TINY_BIAS, 1.0, b)
    return np.where(np.abs(b) < _TINY_BIAS, b / 2.0, _log_cosh(safe) / safe)


def duty_from_bias(bias: ArrayLike) -> NDArray[np.float64]:
    """Closed-form duty factor of the skewed wave: ``1/2 + asin(ln(cosh b)/b)/pi``.

    ``bias``: any shape, dimensionless. Returns the same shape, in (0, 1).
    """
    return 0.5 + np.arcsin(np.clip(duty_threshold(bias), -1.0, 1.0)) / np.pi


def bias_from_duty(duty: ArrayLike, iterations: int = 64) -> NDArray[np.float64]:
    """Inverse of :func:`duty_from_bias` by vectorised bisection (monotone, exact to ~1e-15).

    ``duty``: any shape, each in (0, 1). Returns the bias ``b`` with ``duty_from_bias(b) == duty``.
    Gaits use a handful of distinct duty factors, so each distinct value is solved once
    (and remembered) however large the array.
    """
    d = np.asarray(duty, dtype=np.float64)
    if d.ndim == 0:  # one duty factor (a gait's): no sorting
        return np.array(_bias_for_duty(float(d), iterations))
    values, inverse = np.unique(d, return_inverse=True)
    if values.size <= 16:
        solved = np.array([_bias_for_duty(float(v), iterations) for v in values])
        return solved[inverse].reshape(d.shape)
    return _bisect_bias(d, iterations)


@lru_cache(maxsize=4096)
def _bias_for_duty(duty: float, iterations: int) -> float:
    return float(_bisect_bias(np.array(duty), iterations))


def _bisect_bias(d: NDArray[np.float64], iterations: int) -> NDArray[np.float64]:
    target = np.sin(np.pi * (d - 0.5))  # the threshold c the bias must produce
    lo = np.full(d.shape, -200.0)
    hi = np.full(d.shape, 200.0)
    for _ in range(iterations):  # fixed count: 400 / 2^64 is far below float resolution
        mid = 0.5 * (lo + hi)
        below = duty_threshold(mid) < target
        lo = np.where(below, mid, lo)
        hi = np.where(below, hi, mid)
    return 0.5 * (lo + hi)


def peak_wave(x: ArrayLike, bias: ArrayLike) -> NDArray[np.float64]:
    """The seed's vertical wave ``2 (k^(sin x) - 1/k)/(k - 1/k) - 1`` with ``k = e^b``.

    Written as ``2 e^(b(s-1)/2) sinh(b(s+1)/2) / sinh(b) - 1`` (s = sin x), which is
    exact for |b| up to ~700 and continuous through b = 0, where it equals ``sin x``.
    """
    s = np.sin(np.asarray(x, dtype=np.float64))
    b = np.asarray(bias, dtype=np.float64)
    small = np.abs(b) < _TINY_BIAS
    safe = np.where(small, 1.0, b)
    u = 0.5 * (s + 1.0)
    ratio = np.exp(safe * (u - 1.0)) * np.sinh(safe * u) / np.sinh(safe)
    return np.where(small, s, 2.0 * ratio - 1.0)


def slope_wave(x: ArrayLike, bias: ArrayLike) -> NDArray[np.float64]:
    """The seed's fore-aft wave ``atan2(k sin x, 1 - k cos x)``, ``k = (2/pi) atan b``,
    normalised by its amplitude ``asin k`` so it spans exactly [-1, 1]; ``sin x`` at b = 0."""
    x = np.asarray(x, dtype=np.float64)
    k = (2.0 / np.pi) * np.arctan(np.asarray(bias, dtype=np.float64))
    small = np.abs(k) < _TINY_SLOPE
    safe = np.where(small, 0.5, k)
    wave = np.arctan2(safe * np.sin(x), 1.0 - safe * np.cos(x)) / np.arcsin(safe)
    return np.where(small, np.sin(x), wave)


def touchdown_angle(bias: ArrayLike) -> NDArray[np.float64]:
    """Wave angle x at which the skewed foot touches down: ``acos(c(b))`` (pi/2 at b = 0)."""
    return np.arccos(np.clip(duty_threshold(bias), -1.0, 1.0))


@dataclass(frozen=True)
class FootWave:
    """The state of feet at given phases; every array has the broadcast input shape.

    forward: fore-aft offset from the neutral point, in [-1/2, 1/2] strides (+ = ahead)
    lift:    height above the ground, in [0, 1] step heights
    contact: True while the foot is planted (``phase < duty``)
    swing:   progress through the swing in [0, 1] (0 during stance)
    """

    forward: NDArray[np.float64]
    lift: NDArray[np.float64]
    contact: NDArray[np.bool_]
    swing: NDArray[np.float64]


def foot_wave(phase: ArrayLike, duty: ArrayLike, shape: WaveShape = "planted") -> FootWave:
    """Evaluate the oscillator of feet at ``phase`` (cycle fraction since touchdown).

    ``phase`` and ``duty`` broadcast together (e.g. (T, L) and (L,)); ``duty`` in (0, 1).
    """
    phi = np.mod(np.asarray(phase, dtype=np.float64), 1.0)
    d = np.asarray(duty, dtype=np.float64)
    contact = phi < d
    swing = np.where(contact, 0.0, (phi - d) / (1.0 - d))
    if shape == "planted":
        forward = np.where(contact, 0.5 - phi / d, smootherstep(swing) - 0.5)
        lift = np.where(contact, 0.0, np.sin(np.pi * swing))
    elif shape == "skewed-sine":
        bias = bias_from_duty(d)
        x = 2.0 * np.pi * phi + touchdown_angle(bias)
        forward = 0.5 * slope_wave(x, bias)
        lift = np.where(contact, 0.0, np.maximum(peak_wave(x + 0.5 * np.pi, bias), 0.0))
    else:
        raise ValueError(f"unknown wave shape {shape!r}; expected planted or skewed-sine")
    return FootWave(forward=forward, lift=lift, contact=contact, swing=swing)
