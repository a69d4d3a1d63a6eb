"""The few signal filters the analysis uses, in numpy: Savitzky-Golay smoothing and
derivatives, a running percentile, a running mean and peak finding.

They give SciPy's results (``scipy.signal.savgol_filter`` with ``mode="interp"``,
``scipy.ndimage.percentile_filter`` and ``uniform_filter1d`` with ``mode="nearest"``,
``scipy.signal.find_peaks`` with ``height``, ``distance`` and ``prominence``; the tests
hold them to it) without importing ``scipy.signal`` and ``scipy.ndimage``, which take
about 1 s together: most of a short ``gaitlab analyze`` and the whole of its start-up.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.lib.stride_tricks import sliding_window_view
from numpy.typing import ArrayLike, NDArray


def savgol(x: ArrayLike, window: int, order: int, deriv: int = 0, axis: int = 0) -> NDArray[np.float64]:
    """Savitzky-Golay filter along ``axis``: each sample replaced by (the ``deriv``-th
    derivative, per sample, of) the least-squares polynomial of degree ``order`` through
    the ``window`` samples centred on it; within half a window of either end, the
    polynomial through the first (last) ``window`` samples. Same shape as ``x``."""
    data = np.moveaxis(np.asarray(x, dtype=np.float64), axis, 0)
    n = data.shape[0]
    if window % 2 == 0 or order >= window or window > n:
        raise ValueError(f"savgol: window {window} must be odd, longer than the order {order} and at most {n}")
    half = window // 2
    offsets = np.arange(-half, half + 1, dtype=np.float64)
    target = np.zeros(order + 1)
    target[deriv] = math.factorial(deriv)
    weights = np.linalg.lstsq(offsets ** np.arange(order + 1)[:, None], target, rcond=None)[0]  # (window,)
    flat = data.reshape(n, -1)
    out = np.empty_like(flat)
    out[half:n - half] = np.einsum("tkw,w->tk", sliding_window_view(flat, window, axis=0), weights)
    positions = np.arange(window, dtype=np.float64)
    for start, lo, hi in ((0, 0, half), (n - window, n - half, n)):  # the ends: one polynomial each
        fit = np.polyfit(positions, flat[start:start + window], order)  # (order + 1, K), highest power first
        for _ in range(deriv):
            fit = fit[:-1] * np.arange(len(fit) - 1, 0, -1)[:, None]
        out[lo:hi] = np.polyval(fit, np.arange(lo - start, hi - start, dtype=np.float64)[:, None])
    return np.moveaxis(out.reshape(data.shape), 0, axis)


def running_percentile(x: ArrayLike, percentile: float, size: int) -> NDArray[np.float64]:
    """Each sample's ``percentile`` over the ``size`` samples around it along axis 0
    (the ends extended with their own values; the rank-th smallest, no interpolation)."""
    data = np.asarray(x, dtype=np.float64)
    rank = min(int(size * percentile / 100.0), size - 1)
    pad = [(size // 2, size - 1 - size // 2)] + [(0, 0)] * (data.ndim - 1)
    windows = sliding_window_view(np.pad(data, pad, mode="edge"), size, axis=0)
    return np.partition(windows, rank, axis=-1)[..., rank]


def running_mean(x: ArrayLike, size: int) -> NDArray[np.float64]:
    """Each sample's mean over the ``size`` samples around it along axis 0 (the ends
    extended with their own values)."""
    data = np.asarray(x, dtype=np.float64)
    pad = [(size // 2, size - 1 - size // 2)] + [(0, 0)] * (data.ndim - 1)
    total = np.cumsum(np.pad(data, pad, mode="edge"), axis=0)
    total = np.concatenate([np.zeros((1,) + data.shape[1:]), total])
    return (total[size:] - total[:-size]) / size


def find_peaks(x: ArrayLike, height: float | None = None, distance: float | None = None,
               prominence: float | None = None) -> tuple[NDArray[np.intp], dict[str, NDArray[np.float64]]]:
    """Local maxima of ``x`` (1-D; a flat top counts once, at its middle; never the first
    or last sample) at least ``height`` high, at least ``distance`` samples apart (the
    higher kept), standing at least ``prominence`` above the higher of the lowest points
    on either side before a higher sample. Their indices and, for the criteria given,
    ``peak_heights`` and ``prominences``."""
    a = np.asarray(x, dtype=np.float64)
    n = len(a)
    peaks = np.zeros(0, dtype=np.intp)
    if n >= 3:  # runs of equal samples: a run is a peak when both neighbouring runs are lower
        starts = np.flatnonzero(np.r_[True, a[1:] != a[:-1]])
        ends = np.r_[starts[1:], n] - 1
        values = a[starts]
        inner = np.zeros(len(starts), dtype=bool)
        inner[1:-1] = (values[1:-1] > values[:-2]) & (values[1:-1] > values[2:])
        peaks = ((starts[inner] + ends[inner]) // 2).astype(np.intp)
    props: dict[str, NDArray[np.float64]] = {}
    if height is not None:
        peaks = peaks[a[peaks] >= height]
        props["peak_heights"] = a[peaks]
    if distance is not None and len(peaks) > 1:
        keep = np.ones(len(peaks), dtype=bool)
        reach = math.ceil(distance)
        for j in np.argsort(a[peaks])[::-1]:  # highest first: it clears its neighbours
            if keep[j]:
                near = np.abs(peaks - peaks[j]) < reach
                near[j] = False
                keep &= ~near
        peaks = peaks[keep]
        props = {key: value[keep] for key, value in props.items()}
    if prominence is not None:
        prominences = np.array([a[p] - max(_side_min(a[p::-1], a[p]), _side_min(a[p:], a[p])) for p in peaks],
                               dtype=np.float64)
        keep = prominences >= prominence
        peaks = peaks[keep]
        props = {key: value[keep] for key, value in props.items()}
        props["prominences"] = prominences[keep]
    return peaks, props


def _side_min(side: NDArray[np.float64], top: float) -> float:
    """The lowest of ``side`` (from the peak outwards) before it first rises above ``top``."""
    higher = np.flatnonzero(side > top)
    return float(side[:higher[0] if len(higher) else len(side)].min())
