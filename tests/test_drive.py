"""Drive mode's kinematics: the path laid down by steering, and the driver's limits."""

from __future__ import annotations

import math

import numpy as np
import pytest

from app import build_rig, load_creature
from app.kinematics.drive import DriveLimits, DrivenPath, Driver
from app.kinematics.live import LiveMotion, stack_inputs
from app.kinematics.motion import solve_motion
from app.kinematics.path import CirclePath, StraightPath

DT = 1.0 / 60.0


def heading_of(tangents: np.ndarray) -> np.ndarray:
    return np.unwrap(np.arctan2(tangents[..., 0], tangents[..., 1]))


def test_driven_path_follows_its_base_then_its_arcs_continuously() -> None:
    base = CirclePath(3.0, "right")
    path = DrivenPath(base, s0=2.0, min_radius=0.5)
    path.steer(2.5, 0.8)
    path.steer(4.0, -0.3)
    path.steer(5.0, 0.0)
    s = np.linspace(0.0, 8.0, 8001)
    points, tangents = path.sample(s)
    # Before s0 it is the base path.
    old = s < 2.0
    bp, bt = base.sample(s[old])
    assert np.allclose(points[old], bp) and np.allclose(tangents[old], bt)
    # Continuous everywhere (position and heading), with unit tangents.
    assert np.abs(np.linalg.norm(np.diff(points, axis=0), axis=-1) - 1e-3).max() < 1e-6
    assert np.abs(np.diff(heading_of(tangents))).max() < 1e-3
    assert np.allclose(np.linalg.norm(tangents, axis=-1), 1.0)
    # Each arc turns at its curvature: dheading/ds (left positive).
    turn = np.diff(heading_of(tangents)) / 1e-3
    mid = 0.5 * (s[1:] + s[:-1])
    for lo, hi, k in ((2.0, 2.5, 0.0), (2.5, 4.0, 0.8), (4.0, 5.0, -0.3), (5.0, 8.0, 0.0)):
        inside = (mid > lo + 0.01) & (mid < hi - 0.01)
        assert np.allclose(turn[inside], k, atol=1e-6), (lo, hi, k)


def test_a_constant_curvature_is_a_circle() -> None:
    path = DrivenPath(StraightPath(), s0=0.0, min_radius=1.0)
    path.steer(0.0, 0.5)  # radius 2 m to the left
    circle = CirclePath(2.0, "left")
    s = np.linspace(0.0, 20.0, 101)
    for a, b in zip(path.sample(s), circle.sample(s)):
        assert np.allclose(a, b, atol=1e-9)


def test_steering_never_moves_the_path_already_travelled() -> None:
    path = DrivenPath(StraightPath(), s0=0.0, min_radius=1.0)
    s = np.linspace(-1.0, 3.0, 50)
    path.steer(1.0, 0.4)
    before = path.sample(s)
    path.steer(3.0, -0.9)
    after = path.sample(s)
    assert np.array_equal(before[0], after[0]) and np.array_equal(before[1], after[1])


def drive(creature: str, seconds: float, throttle, steer):
    """Drive ``creature`` for ``seconds`` at 60 Hz; throttle/steer are functions of time.
    Returns the driver, per-frame inputs, ground speeds and gaits."""
    rig = build_rig(load_creature(creature))
    live = LiveMotion(rig)
    driver = Driver(live, rig)
    frames, speeds, gaits, curvatures = [], [], [], []
    for i in range(int(round(seconds / DT))):
        t = i * DT
        driver.step(DT, throttle(t), steer(t))
        frames.append(live.frame_inputs())
        speeds.append(driver.ground_speed)
        gaits.append(driver.gait)
        curvatures.append(driver.curvature)
    return driver, frames, np.array(speeds), gaits, np.array(curvatures)


def test_holding_w_moves_the_creature_by_its_speed_times_time() -> None:
    driver, frames, speeds, gaits, _ = drive("dog", 2.0, lambda t: 1.0, lambda t: 0.0)
    motion = solve_motion(driver.live.rig, driver.live.world, stack_inputs(frames))
    root = motion.root[:, [0, 2], 3]
    moved = float(np.linalg.norm(root[-1] - root[0]))
    expected = float(speeds[1:].sum() * DT)
    assert abs(moved - expected) <= 0.03 * expected
    assert speeds[-1] > 2.5 * speeds[0]  # it sped up
    assert root[-1, 1] - root[0, 1] > 0.99 * moved  # straight ahead (+Z)
    assert gaits[0] == "walk" and gaits[-1] != "walk"


def test_a_turns_left_and_d_right_within_the_limits() -> None:
    for steer, sign in ((1.0, 1.0), (-1.0, -1.0)):
        driver, _frames, speeds, _, curvatures = drive("dog", 3.0, lambda t: 0.0, lambda t, s=steer: s)
        # The heading turned through along the way (unwrapped: three seconds of a full
        # turn takes the dog round by about half a circle, where atan2 wraps).
        _, tangent = driver.path.sample(np.linspace(0.0, driver.live.travel, 400))
        heading = np.unwrap(np.arctan2(tangent[:, 0], tangent[:, 1]))[-1]
        assert sign * heading > math.radians(60)  # left is +X, heading grows
        limits = driver.limits
        radius = limits.min_radius * driver.base_rig.body_length
        assert np.abs(curvatures).max() <= 1.0 / radius + 1e-12
        lateral = speeds ** 2 * np.abs(curvatures)
        assert lateral.max() <= limits.lateral_g * 9.81 * 1.05  # speed blends lag the limit a little
        # The curvature ramps in over turn_time, not at once.
        assert np.abs(np.diff(curvatures)).max() <= DT / limits.turn_time / radius + 1e-12


@pytest.mark.parametrize("creature", ["dog", "horse"])
def test_driven_feet_stay_planted_through_speed_and_turns(creature: str) -> None:
    def throttle(t):
        return 1.0 if t < 3.0 else (-1.0 if t > 5.0 else 0.0)

    def steer(t):
        return 1.0 if 1.0 < t < 2.5 else (-1.0 if 4.0 < t < 6.0 else 0.0)

    driver, frames, _speeds, gaits, _ = drive(creature, 7.0, throttle, steer)
    assert {"walk", "trot"} <= set(gaits)
    motion = solve_motion(driver.live.rig, driver.live.world, stack_inputs(frames))
    ball = motion.joints[:, :, 3]
    c = motion.contact
    planted = c[1:] & c[:-1] & (motion.phase[1:] > motion.phase[:-1])
    slip = np.linalg.norm(ball[1:] - ball[:-1], axis=-1)[planted]
    assert planted.sum() > 100
    assert slip.max() < 1e-6
    assert np.all(np.isfinite(motion.joints))


def test_speed_stays_within_the_froude_limits() -> None:
    limits = DriveLimits()
    driver, _, _, gaits, _ = drive("dog", 8.0, lambda t: 1.0, lambda t: 0.0)
    h = driver.base_rig.hip_height
    assert driver.speed == pytest.approx(math.sqrt(limits.max_froude * 9.81 * h), rel=1e-3)
    assert gaits[-1] == "gallop"
    driver.step(20.0, -1.0, 0.0)  # a long brake in one step: clamped at the slowest stroll
    assert driver.target_speed == pytest.approx(math.sqrt(limits.min_froude * 9.81 * h))
