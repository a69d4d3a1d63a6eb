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


def feed_samples(state: ViewerState, monitor: GaitMonitor, seconds: float, fps: float) -> None:
    """As the viewer does: one frame at a time, the monitor fed the frame's sub-steps."""
    for _ in range(int(round(seconds * fps))):
        state.advance(1.0 / fps)
        monitor.record_samples(state.live.rig, state.world, state.take_samples(), state.live.frequency)


@pytest.mark.parametrize("creature, gait", [("dog", g) for g in ("walk", "diagonal-walk", "amble", "trot", "pace",
                                                                  "canter", "gallop", "rotary-gallop", "half-bound",
                                                                  "bound", "pronk")]
                         + [("ant", "tripod"), ("ant", "tetrapod"), ("spider", "metachronal")])
def test_live_measurement_is_true_at_20_fps(creature: str, gait: str) -> None:
    """Issue 12, item 2: the history is sampled at a fixed rate, not once per frame, so a
    viewer running at 20 fps still measures every gait preset it shows within 0.02."""
    from app.analysis.metrics import cyclic_distance, reference_foot

    state = ViewerState(load_creature(creature).with_overrides({"gait.preset": gait}))
    monitor = GaitMonitor()
    feed_samples(state, monitor, 3.5 / state.live.frequency + 0.5, fps=20.0)
    report = monitor.measure(state.live.time, force=True)
    assert report is not None, monitor.error
    asked = dict(zip(state.live.rig.leg_names, state.live.rig.gait.offsets))
    for foot in report.feet:
        assert foot.duty_factor == pytest.approx(state.live.rig.gait.duty_factor, abs=0.02), foot.name
        reference = asked[reference_foot(tuple(asked))]
        assert cyclic_distance(foot.phase, (asked[foot.name] - reference) % 1.0) <= 0.02, foot.name


def test_background_measurement_matches_the_synchronous_one() -> None:
    """The viewer measures in a worker process; it reports what measure() reports."""
    import time

    state = ViewerState(load_creature("dog").with_overrides({"gait.preset": "trot"}))
    monitor = GaitMonitor()
    feed_samples(state, monitor, 3.0, fps=30.0)
    expected = monitor.measure(state.live.time, force=True)
    monitor.report = None
    monitor._last_measure = -1e9
    try:
        assert monitor.update(state.live.time) is None  # started, not finished: the frame goes on
        deadline = time.monotonic() + 60
        while monitor.report is None and time.monotonic() < deadline:
            time.sleep(0.05)
            monitor.update(state.live.time)
        report = monitor.report
        assert report is not None, monitor.error
        assert report.gait_match == expected.gait_match == "trot"
        for a, b in zip(report.feet, expected.feet):
            assert (a.name, a.duty_factor, a.phase) == (b.name, b.duty_factor, b.phase)
    finally:
        monitor.close()
