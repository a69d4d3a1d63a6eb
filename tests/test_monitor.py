"""The viewer's live gait monitor (no window): history, resampling, measurement."""

from __future__ import annotations

import pytest

from app import load_creature
from app.ui.monitor import GaitMonitor
from app.ui.state import ViewerState


def feed(state: ViewerState, monitor: GaitMonitor, seconds: float, dt: float = 1 / 55) -> None:
    for _ in range(int(seconds / dt)):
        state.advance(dt)
        monitor.record(state.pose(), state.live.time, state.live.rig.hip_height, state.live.frequency)


def test_monitor_measures_the_live_gait() -> None:
    state = ViewerState(load_creature("dog").with_overrides({"gait.preset": "trot"}))
    monitor = GaitMonitor()
    feed(state, monitor, 3.0)
    assert monitor.times[-1] - monitor.times[0] <= monitor.seconds + 1e-9  # a rolling window
    report = monitor.measure(state.live.time, force=True)
    assert report is not None and report.gait_match == "trot"
    for foot in report.feet:
        assert foot.duty_factor == pytest.approx(0.4, abs=0.05)
    assert monitor.measure(state.live.time) is report  # throttled: no re-measure within `every`


def test_monitor_follows_a_gait_change_and_reports_short_history() -> None:
    state = ViewerState(load_creature("cat"))
    monitor = GaitMonitor()
    feed(state, monitor, 0.1)
    assert monitor.measure(state.live.time, force=True) is None and monitor.error
    feed(state, monitor, 3.0)
    assert monitor.measure(state.live.time, force=True).gait_match == "walk"
    state.set_gait("pronk")
    feed(state, monitor, 8.0)
    assert monitor.measure(state.live.time, force=True).gait_match == "pronk"
