"""Bezier spine: end points and equal arc-length spacing."""

from __future__ import annotations

import numpy as np

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
