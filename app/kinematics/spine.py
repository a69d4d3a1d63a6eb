"""Cubic Bezier spine with points placed at equal arc length, vectorised over frames."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray


def bezier(ctrl: NDArray[np.float64], t: NDArray[np.float64]) -> NDArray[np.float64]:
    """Points of cubic Beziers.

    ctrl: (..., 4, 3) control points; t: (..., N) parameters (values outside [0, 1]
    extrapolate the cubic). Returns (..., N, 3).
    """
    t = t[..., None]
    s = 1.0 - t
    p0, p1, p2, p3 = (ctrl[..., i:i + 1, :] for i in range(4))
    return s * s * s * p0 + 3.0 * s * s * t * p1 + 3.0 * s * t * t * p2 + t * t * t * p3


def bezier_tangent(ctrl: NDArray[np.float64], t: NDArray[np.float64]) -> NDArray[np.float64]:
    """Unit tangents dB/dt of cubic Beziers at ``t``: (..., 4, 3), (..., N) -> (..., N, 3)."""
    t = t[..., None]
    s = 1.0 - t
    p0, p1, p2, p3 = (ctrl[..., i:i + 1, :] for i in range(4))
    d = 3.0 * s * s * (p1 - p0) + 6.0 * s * t * (p2 - p1) + 3.0 * t * t * (p3 - p2)
    return d / np.maximum(np.linalg.norm(d, axis=-1, keepdims=True), 1e-12)


def arc_length_parameters(ctrl: NDArray[np.float64], fractions: NDArray[np.float64],
                          t_start: float = 0.0, t_end: float = 1.0, samples: int = 64) -> NDArray[np.float64]:
    """Bezier parameters at given fractions of the arc length between ``t_start`` and ``t_end``.

    ctrl: (..., 4, 3); fractions: (S,) in [0, 1]. Returns t of shape (..., S). The curve
    is sampled at ``samples`` points and the arc length interpolated linearly between
    them (error well below 1e-4 of the length for body-like curves).
    """
    grid = np.linspace(t_start, t_end, samples)
    pts = bezier(ctrl, np.broadcast_to(grid, ctrl.shape[:-2] + (samples,)))
    seg = np.linalg.norm(np.diff(pts, axis=-2), axis=-1)
    cum = np.concatenate([np.zeros(seg.shape[:-1] + (1,)), np.cumsum(seg, axis=-1)], axis=-1)
    wanted = fractions * cum[..., -1:]  # (..., S)
    idx = np.clip((cum[..., :, None] <= wanted[..., None, :]).sum(axis=-2) - 1, 0, samples - 2)
    c0 = np.take_along_axis(cum, idx, axis=-1)
    c1 = np.take_along_axis(cum, idx + 1, axis=-1)
    w = np.clip((wanted - c0) / np.maximum(c1 - c0, 1e-15), 0.0, 1.0)
    step = grid[1] - grid[0]
    return grid[idx] + w * step
