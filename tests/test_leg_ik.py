"""Four-bone leg IK: reach, exact bone lengths, knee direction, metatarsus and toe."""

from __future__ import annotations

import numpy as np
import pytest

from app import build_rig, load_creature
from app.kinematics.leg import solve_legs

UP = np.array([0.0, 1.0, 0.0])
FWD = np.array([0.0, 0.0, 1.0])


def solve(rig, hips, targets, curl=0.0):
    curl = np.broadcast_to(curl, hips.shape[:-1])
    return solve_legs(hips, targets, FWD, UP, curl, femur=rig.femur, tibia=rig.tibia, metatarsus=rig.metatarsus,
                      toe=rig.toe, ankle_lift=rig.ankle_lift, l_max=rig.l_max, l_rest=rig.l_rest, l_min=rig.l_min,
                      knee_sign=rig.knee_sign)


def bone_lengths(joints):
    return np.linalg.norm(np.diff(joints, axis=-2), axis=-1)


@pytest.fixture(params=["dog", "horse", "bear", "cat", "deer"])
def rig(request):
    return build_rig(load_creature(request.param))


def rest_pose(rig):
    hips = np.stack([rig.hip_side * 0.1, rig.l_rest, np.zeros(4)], axis=-1)
    targets = hips * np.array([1.0, 0.0, 1.0])
    return hips, targets


def test_rest_pose_reaches_target_with_rest_ankle_lift(rig) -> None:
    hips, targets = rest_pose(rig)
    joints = solve(rig, hips, targets)
    assert np.allclose(joints[:, 3], targets, atol=1e-12)  # ball on its target
    meta = joints[:, 2] - joints[:, 3]  # ball -> ankle
    angle = np.arctan2(meta[:, 1], -meta[:, 2])  # angle to the ground, ankle behind the ball
    assert np.allclose(angle, rig.ankle_lift, atol=1e-9)
    assert np.allclose(joints[:, 4, 1], 0.0)  # toe flat on the ground


def test_bone_lengths_are_exact_for_any_target(rig) -> None:
    rng = np.random.default_rng(7)
    hips = np.broadcast_to(rest_pose(rig)[0], (500, 4, 3))
    targets = hips + rng.normal(scale=rig.l_max.max(), size=(500, 4, 3))
    targets[..., 1] = np.abs(targets[..., 1]) * 0.2
    joints = solve(rig, hips, targets, curl=rng.random((500, 4)))
    expected = np.stack([rig.femur, rig.tibia, rig.metatarsus, rig.toe], axis=-1)
    assert np.allclose(bone_lengths(joints), expected, rtol=1e-9, atol=0)
    assert np.isfinite(joints).all()


def test_out_of_reach_targets_are_pulled_along_the_hip_line(rig) -> None:
    hips, _ = rest_pose(rig)
    far = hips + np.array([0.0, -3.0, 0.5]) * rig.l_max[:, None]
    joints = solve(rig, hips, far)
    reach = np.linalg.norm(joints[:, 3] - hips, axis=-1)
    assert np.allclose(reach, rig.l_max)
    direction = (far - hips) / np.linalg.norm(far - hips, axis=-1, keepdims=True)
    assert np.allclose((joints[:, 3] - hips) / reach[:, None], direction)


def test_knees_point_forward_and_elbows_back(rig) -> None:
    hips, targets = rest_pose(rig)
    joints = solve(rig, hips, targets)
    hip, knee, ankle = joints[:, 0], joints[:, 1], joints[:, 2]
    mid = hip + (ankle - hip) * (np.sum((knee - hip) * (ankle - hip), -1) / np.sum((ankle - hip) ** 2, -1))[:, None]
    side = np.sign((knee - mid)[:, 2])  # + = knee ahead of the hip-ankle line
    assert np.all(side == rig.knee_sign)
    assert np.all(rig.knee_sign == np.array([-1, -1, 1, 1]))  # fore: elbow back; hind: knee forward


def test_leg_types_have_distinct_metatarsus_angles() -> None:
    angles = {name: np.degrees(build_rig(load_creature(name)).ankle_lift[2]) for name in ("bear", "dog", "horse")}
    assert angles["bear"] < 20 < angles["dog"] < 75 < angles["horse"]


def test_heel_lifts_at_push_off_for_plantigrade() -> None:
    rig = build_rig(load_creature("bear"))
    hips, targets = rest_pose(rig)
    behind = targets - np.array([0.0, 0.0, 0.25]) * rig.l_rest[:, None]
    ahead = targets + np.array([0.0, 0.0, 0.25]) * rig.l_rest[:, None]
    heel_behind = solve(rig, hips, behind)[:, 2, 1]
    heel_ahead = solve(rig, hips, ahead)[:, 2, 1]
    assert np.all(heel_behind > heel_ahead)
    assert np.all(heel_ahead >= 0)


def test_toe_drops_in_the_air_but_never_below_ground(rig) -> None:
    hips, targets = rest_pose(rig)
    lifted = targets + np.array([0.0, 0.05, 0.0]) * rig.l_rest[:, None]
    flat = solve(rig, hips, lifted, curl=0.0)
    curled = solve(rig, hips, lifted, curl=1.0)
    assert np.allclose(flat[:, 4, 1], flat[:, 3, 1])  # flat toe level with the ball
    assert np.all(curled[:, 4, 1] <= curled[:, 3, 1] + 1e-12)
    assert np.all(curled[:, 4, 1] >= 0.5 * curled[:, 3, 1] - 1e-12)  # never touches down before the ball


def test_vectorised_solver_matches_the_scalar_reference(rig) -> None:
    from app.kinematics.leg_scalar import solve_leg

    rng = np.random.default_rng(3)
    hips = np.broadcast_to(rest_pose(rig)[0], (50, 4, 3)).copy()
    hips[..., 1] += rng.normal(scale=0.2, size=(50, 4)) * rig.l_rest
    targets = hips * np.array([1.0, 0.0, 1.0]) + rng.normal(scale=0.5, size=(50, 4, 3)) * rig.l_rest[:, None]
    targets[..., 1] = np.abs(targets[..., 1]) * 0.3
    curl = rng.random((50, 4))
    fast = solve(rig, hips, targets, curl)
    for i in range(50):
        for leg in range(4):
            slow = solve_leg(tuple(hips[i, leg]), tuple(targets[i, leg]), tuple(FWD), tuple(UP), curl[i, leg],
                             rig.femur[leg], rig.tibia[leg], rig.metatarsus[leg], rig.toe[leg], rig.ankle_lift[leg],
                             rig.l_max[leg], rig.l_rest[leg], rig.l_min[leg], rig.knee_sign[leg])
            assert np.allclose(np.array(slow), fast[i, leg], atol=1e-9)


def test_long_batches_are_solved_in_blocks_with_identical_results() -> None:
    from app.kinematics import leg as leg_module

    rig = build_rig(load_creature("dog"))
    rng = np.random.default_rng(5)
    frames = 3 * leg_module._CHUNK_LEGS // 4 + 17  # several blocks and a ragged end
    hips = np.broadcast_to(rest_pose(rig)[0], (frames, 4, 3)) + rng.normal(scale=0.02, size=(frames, 4, 3))
    targets = hips * np.array([1.0, 0.0, 1.0]) + rng.normal(scale=0.1, size=(frames, 4, 3))
    curl = rng.random((frames, 4))
    blocked = solve(rig, hips, targets, curl)
    whole = leg_module._solve(hips, targets, FWD, UP, curl, 0.0, femur=rig.femur, tibia=rig.tibia,
                              metatarsus=rig.metatarsus, toe=rig.toe, ankle_lift=rig.ankle_lift, l_max=rig.l_max,
                              l_rest=rig.l_rest, l_min=rig.l_min, knee_sign=rig.knee_sign)
    assert np.array_equal(blocked, whole)
