"""Analysing Gaitlab's own motion: the measured gait is the requested one."""

from __future__ import annotations

import math

import pytest

from app import build_rig, load_creature
from app.analysis import analyze_tracks, tracks_from_motion
from app.analysis.metrics import cyclic_distance
from app.gaits import gaits_for
from app.kinematics.clip import clip_motion


def analyse(creature: str, gait: str, wave: str = "planted"):
    rig = build_rig(load_creature(creature).with_overrides({"gait.preset": gait, "gait.wave": wave}))
    fps = max(120.0, math.ceil(200 * rig.gait.frequency))
    motion, _ = clip_motion(rig, fps, cycles=4.0)
    return rig, analyze_tracks(tracks_from_motion(motion), gait)


CASES = [("dog", g, "planted") for g in gaits_for(2)] + [("horse", g, "skewed-sine") for g in gaits_for(2)]


@pytest.mark.parametrize("creature, gait, wave", CASES)
def test_measured_duty_and_phase_match_the_request(creature: str, gait: str, wave: str) -> None:
    rig, report = analyse(creature, gait, wave)
    requested = dict(zip(rig.leg_names, rig.gait.offsets))
    for foot in report.feet:
        assert foot.duty_factor == pytest.approx(rig.gait.duty_factor, abs=0.02), foot.name
        assert cyclic_distance(foot.phase, requested[foot.name]) <= 0.02, foot.name
    assert report.gait_match == gait
    assert report.cycle_seconds == pytest.approx(1.0 / rig.gait.frequency, rel=0.01)


def test_walk_limb_phase_and_trot_diagonals() -> None:
    _, walk = analyse("dog", "walk")
    assert 0.2 <= walk.limb_phase <= 0.3
    _, trot = analyse("dog", "trot")
    assert cyclic_distance(trot.foot("LH").phase, trot.foot("RF").phase) <= 0.02
    assert cyclic_distance(trot.foot("RH").phase, trot.foot("LF").phase) <= 0.02


def test_planted_feet_do_not_slip_or_skate() -> None:
    _, report = analyse("cat", "gallop")
    for foot in report.feet:
        assert foot.max_stance_slip == pytest.approx(0.0, abs=1e-6)
        assert foot.skating_ratio == 0.0


def test_report_json_has_the_documented_shape() -> None:
    _, report = analyse("dog", "canter")
    doc = report.to_json()
    assert set(doc) >= {"source", "gait", "cycle_seconds", "speed", "limb_phase", "gait_match", "feet"}
    foot = doc["feet"][0]
    assert set(foot) == {"name", "duty_factor", "phase", "stride_length", "max_stance_slip", "skating_ratio", "events"}
    kinds = {e["kind"] for e in foot["events"]}
    assert kinds == {"lift", "liftoff", "strike", "landing", "stance"}
    times = [e["time"] for e in foot["events"]]
    assert times == sorted(times)


def test_a_stance_found_twice_is_one_contact_and_a_swing_dip_is_no_stance(tmp_path) -> None:
    """A person with a short thigh and a high step (the CMU walker's first fit): the heel
    strike and the flat foot were two "strikes" of one stance (duty 3.5, half the cycle),
    and a toe dipping in mid-swing a stance of no length. One step per contact, from its
    first strike to its last liftoff; no contact shorter than 8 % of a stride."""
    import numpy as np

    spec = load_creature("human").with_overrides({
        "legs.legs.femur": 0.3408, "legs.legs.tibia": 0.4454, "legs.legs.metatarsus": 0.1124,
        "gait.frequency": 0.7843, "gait.duty_factor": 0.5833, "gait.step_height": 0.1036, "gait.stride": 0.8099,
        "poses.contact_height": -0.0572, "poses.down_height": -0.0694, "poses.pass_height": -0.0163,
        "poses.up_height": -0.0041})
    rig = build_rig(spec)
    motion, _ = clip_motion(rig, 157.0, cycles=5.0)
    report = analyze_tracks(tracks_from_motion(motion))
    assert report.cycle_seconds == pytest.approx(1.0 / rig.gait.frequency, rel=0.01)
    for foot in report.feet:
        assert foot.duty_factor == pytest.approx(rig.gait.duty_factor, abs=0.01)
    for events in report.foot_events:
        strikes = [s.strike for s in events.steps]
        assert len(strikes) == len(set(strikes)) and all(np.diff(strikes) > 0.5 * 157 / rig.gait.frequency)
