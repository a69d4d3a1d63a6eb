"""Easing curves on [0, 1] (the one home of smoothstep and smootherstep)."""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray


def smoothstep(x: ArrayLike) -> NDArray[np.float64]:
    """``3x^2 - 2x^3`` of x clamped to [0, 1]: zero slope at both ends."""
    x = np.clip(np.asarray(x, dtype=np.float64), 0.0, 1.0)
    return x * x * (3.0 - 2.0 * x)


def smootherstep(x: ArrayLike) -> NDArray[np.float64]:
    """``6x^5 - 15x^4 + 10x^3`` of x clamped to [0, 1]: zero slope and curvature at both ends."""
    x = np.clip(np.asarray(x, dtype=np.float64), 0.0, 1.0)
    return x * x * x * (x * (6.0 * x - 15.0) + 10.0)
