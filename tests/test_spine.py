"""Bezier spine: end points and equal arc-length spacing."""

from __future__ import annotations

import numpy as np
import pytest

from app import load_creature, simulate
from app.kinematics.spine import arc_length_parameters, bezier


def test_bezier_end_points_and_batching() -> None:
    ctrl = np.array([[[0, 0, 0], [1, 2, 0], [3, 2, 0], [4, 0, 0]]], dtype=float).repeat(3, axis=0)
    pts = bezier(ctrl, np.broadcast_to(np.array([0.0, 1.0]), (3, 2)))
    assert np.allclose(pts[:, 0], [0, 0, 0]) and np.allclose(pts[:, 1], [4, 0, 0])


def test_points_are_at_equal_arc_length_not_equal_t() -> None:
    ctrl = np.array([[0, 0, 0], [0.1, 1.5, 0], [0.2, 1.5, 0], [3, 0, 0]], dtype=float)
    fractions = np.linspace(0, 1, 11)
    t = arc_length_parameters(ctrl, fractions, samples=256)
    fine = bezier(ctrl, np.linspace(0, 1, 20001))
    seg = np.linalg.norm(np.diff(fine, axis=0), axis=1)
    cum = np.concatenate([[0], np.cumsum(seg)])
    s = np.interp(t, np.linspace(0, 1, 20001), cum)
    assert np.allclose(np.diff(s), cum[-1] / 10, rtol=2e-3)
    assert not np.allclose(t, fractions, atol=0.02)  # the curve is far from uniform in t


def test_body_segments_evenly_spaced_in_simulation() -> None:
    motion = simulate(load_creature("dog"), seconds=0.5, fps=30)
    gaps = np.linalg.norm(np.diff(motion.spine, axis=1), axis=-1)  # chords ~ arc for gentle curves
    assert np.allclose(gaps, gaps.mean(axis=1, keepdims=True), rtol=5e-3)


def test_a_tail_curls_by_its_tail_curl_from_the_first_segment_to_the_last() -> None:
    """``body.tail_curl`` turns the tail up (+) or down (-) along its length: the last
    segment's droop below the first's changes by the curl (tails were straight cones)."""
    from app import build_rig, load_creature
    from app.kinematics.clip import clip_motion

    def bend(curl: float) -> float:
        spec = load_creature("dog").with_overrides({"body.tail_curl": curl, "motion.tail_sway": 0.0})
        motion, _ = clip_motion(build_rig(spec), 30.0, cycles=0.25)
        tail = motion.tail[0]
        first, last = tail[1] - tail[0], tail[-1] - tail[-2]
        slope = lambda v: np.degrees(np.arctan2(v[1], np.linalg.norm(v[[0, 2]])))
        return slope(last) - slope(first)

    straight, up, down = bend(0.0), bend(50.0), bend(-30.0)
    assert up - straight == pytest.approx(50.0, abs=1.0)
    assert down - straight == pytest.approx(-30.0, abs=1.0)
