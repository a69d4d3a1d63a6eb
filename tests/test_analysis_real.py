"""The analysis on real motion capture nobody here wrote (see tests/data/README.md)."""

from __future__ import annotations

from pathlib import Path

import pytest

from app.analysis import analyze_tracks
from app.analysis.metrics import cyclic_distance
from app.analysis.sources import load_tracks

DATA = Path(__file__).parent / "data"


def test_cmu_human_walk() -> None:
    tracks, notes = load_tracks(str(DATA / "human_walk_cmu_12_01.bvh"))
    assert tracks.names == ("L", "R") and "cmu" in notes and "rest pose" in notes
    assert tracks.hip_height == pytest.approx(0.85, abs=0.1)  # metres, after detecting CMU units
    report = analyze_tracks(tracks)
    for foot in report.feet:
        assert 0.55 <= foot.duty_factor <= 0.70, foot  # human walking: stance ~60% of the stride
    assert cyclic_distance(report.foot("R").phase, 0.5) <= 0.05
    assert report.gait_match == "walk"
    assert 1.0 <= report.cycle_seconds <= 1.4 and 0.6 <= report.speed <= 1.3


def test_dog_walk_reads_as_a_lateral_sequence_walk() -> None:
    tracks, notes = load_tracks(str(DATA / "dog_walk_tencent_walkrun005_f120-419.bvh"))
    assert set(tracks.names) == {"LF", "RF", "LH", "RH"} and "centimetres" in notes
    report = analyze_tracks(tracks)
    assert 0.05 <= report.foot("LF").phase <= 0.45  # LF touches down a fraction of a cycle after LH
    assert cyclic_distance(report.foot("RH").phase, 0.5) <= 0.12  # RH about half a cycle after LH
    assert report.gait_match == "walk"
    assert all(f.duty_factor > 0.5 for f in report.feet)  # a walk: always more than half on the ground


def test_dog_trot() -> None:
    report = analyze_tracks(load_tracks(str(DATA / "dog_trot_tencent_walkrun001_f960-1156.bvh"))[0])
    assert report.gait_match == "trot"
    assert cyclic_distance(report.foot("RF").phase, 0.0) <= 0.08  # diagonal pairs together
    assert cyclic_distance(report.foot("LF").phase, report.foot("RH").phase) <= 0.08


def test_feet_mapping_by_hand_gives_the_same_result() -> None:
    from app.analysis.sources import parse_feet, tracks_from_bvh

    feet = parse_feet("LH=b_LeftAnkle:b_LeftToe,RH=b_RightAnkle:b_RightToe,LF=b_LeftHand:b__LeftFinger,"
                      "RF=b_RightHand:b_RightFinger")
    tracks, notes = tracks_from_bvh(str(DATA / "dog_trot_tencent_walkrun001_f960-1156.bvh"), feet, units="cm")
    assert "--feet" in notes and analyze_tracks(tracks).gait_match == "trot"


def test_cmu_human_run_a_single_stride_is_estimated_and_says_so() -> None:
    """Issue 9: a take holding one stride (each foot lands once or twice) is analysed:
    the cycle from the foot seen landing twice, duty factors from each foot's contact,
    and a note that these are estimates. A run has a flight phase: duty under 0.5."""
    tracks, _ = load_tracks(str(DATA / "human_run_cmu_09_01.bvh"))
    report = analyze_tracks(tracks)
    assert report.notes and "single stride" in report.notes[0] and "estimates" in report.notes[0]
    assert report.cycle_seconds == pytest.approx(0.75, abs=0.02)  # R lands at frames 39 and 129 (120 fps)
    assert report.gait_match == "run"
    for foot in report.feet:
        assert 0.2 < foot.duty_factor < 0.5
    assert cyclic_distance(report.foot("R").phase, 0.5) < 0.15  # roughly opposite feet


def test_the_long_clips_carry_no_note() -> None:
    for name in ("human_walk_cmu_12_01.bvh", "dog_walk_tencent_walkrun005_f120-419.bvh"):
        tracks, _ = load_tracks(str(DATA / name))
        assert analyze_tracks(tracks).notes == ()


def test_cmu_walk_arms_swing_against_the_legs() -> None:
    """The real human's hands: each farthest forward near the other foot's touchdown."""
    from app.analysis.metrics import cyclic_distance

    tracks, _ = load_tracks(str(DATA / "human_walk_cmu_12_01.bvh"))
    assert tracks.hands is not None and tracks.hands.shape[1:] == (2, 3)
    report = analyze_tracks(tracks)
    assert cyclic_distance(report.arm_phase["L"], 0.5) < 0.15
    assert cyclic_distance(report.arm_phase["R"], 0.0) < 0.15
    dog, _ = load_tracks(str(DATA / "dog_walk_tencent_walkrun005_f120-419.bvh"))
    assert dog.hands is None and analyze_tracks(dog).arm_phase is None
