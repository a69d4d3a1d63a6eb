"""The analysis's numpy filters give SciPy's results (app.analysis.filters imports no
scipy.signal, whose import cost most of a short ``gaitlab analyze``)."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.ndimage import percentile_filter, uniform_filter1d
from scipy.signal import find_peaks as scipy_find_peaks
from scipy.signal import savgol_filter

from app.analysis.filters import find_peaks, running_mean, running_percentile, savgol


@pytest.mark.parametrize("window,order,deriv", [(5, 2, 0), (7, 3, 0), (7, 3, 1), (7, 3, 2), (31, 2, 0), (9, 3, 2)])
def test_savgol_is_scipys(window: int, order: int, deriv: int) -> None:
    rng = np.random.default_rng(window * 10 + deriv)
    for shape in ((60,), (80, 3), (window, 2)):
        x = np.cumsum(rng.normal(size=shape), axis=0)
        want = savgol_filter(x, window, order, deriv=deriv, axis=0, mode="interp")
        assert np.allclose(savgol(x, window, order, deriv=deriv), want, rtol=1e-9, atol=1e-9)


def test_savgol_refuses_a_window_it_cannot_fit() -> None:
    for window, order, n in ((4, 2, 10), (3, 3, 10), (11, 2, 10)):
        with pytest.raises(ValueError):
            savgol(np.zeros(n), window, order)


@settings(max_examples=60, deadline=None)
@given(st.integers(3, 400), st.integers(1, 61), st.sampled_from([0, 10, 50, 90, 100]), st.integers(0, 10 ** 6))
def test_running_percentile_and_mean_are_scipys(n: int, size: int, percentile: float, seed: int) -> None:
    x = np.round(np.random.default_rng(seed).normal(size=(n, 2)), 1)  # ties too
    want = percentile_filter(x, percentile, size=(size, 1), mode="nearest")
    assert np.array_equal(running_percentile(x, percentile, size), want)
    assert np.allclose(running_mean(x, size), uniform_filter1d(x, size=size, axis=0, mode="nearest"), atol=1e-12)


@settings(max_examples=150, deadline=None)
@given(st.integers(0, 300), st.integers(0, 10 ** 6), st.booleans(),
       st.one_of(st.none(), st.floats(-1.0, 1.0)), st.one_of(st.none(), st.integers(1, 40)),
       st.one_of(st.none(), st.floats(0.0, 2.0)))
def test_find_peaks_is_scipys(n: int, seed: int, plateaus: bool, height, distance, prominence) -> None:
    x = np.random.default_rng(seed).normal(size=n)
    if plateaus:
        x = np.round(x, 0)  # flat tops and ties
    mine, props = find_peaks(x, height=height, distance=distance, prominence=prominence)
    want, scipy_props = scipy_find_peaks(x, height=height, distance=distance, prominence=prominence)
    assert np.array_equal(mine, want)
    for key in ("peak_heights", "prominences"):
        if key in scipy_props:
            assert np.allclose(props[key], scipy_props[key])
