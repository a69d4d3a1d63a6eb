"""Property tests over random valid creatures and gaits (hypothesis)."""

from __future__ import annotations

import numpy as np
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

from app import build_rig
from app.errors import SpecError
from app.gaits import GAIT_PRESETS, gaits_for
from app.kinematics.clip import clip_motion
from app.spec import creature_from_dict

length = st.floats(0.03, 1.2)


@st.composite
def leg_tables(draw) -> dict:
    return {
        "femur": draw(length), "tibia": draw(length), "metatarsus": draw(st.floats(0.01, 0.6)),
        "toe": draw(st.one_of(st.just(0.0), st.floats(0.001, 0.2))), "ankle_lift": draw(st.floats(0.0, 90.0)),
        "natural_bend": draw(st.floats(0.0, 0.6)), "radius": draw(st.floats(0.005, 0.05)),
    }


@st.composite
def creatures(draw):
    gait = {"preset": draw(st.sampled_from(gaits_for(2))),
            "duty_factor": draw(st.floats(0.06, 0.94)),
            "wave": draw(st.sampled_from(["planted", "skewed-sine"])),
            "step_height": draw(st.floats(0.0, 0.6)),
            "stride": draw(st.floats(0.0, 1.4))}
    if draw(st.booleans()) and GAIT_PRESETS[gait["preset"]].symmetric:
        gait["front_back"] = draw(st.floats(-1, 1))
        gait["left_right"] = draw(st.floats(-1, 1))
    data = {
        "name": "random",
        "body": {"length": draw(st.floats(0.1, 2.0)), "width": draw(st.floats(0.1, 0.8)),
                 "radius": draw(st.lists(st.floats(0.02, 0.4), min_size=1, max_size=5)),
                 "segments": draw(st.integers(2, 16)), "neck_length": draw(st.floats(0.0, 0.8)),
                 "tail_length": draw(st.floats(0.0, 0.8)), "tail_segments": draw(st.integers(1, 8))},
        "legs": {"fore": draw(leg_tables()), "hind": draw(leg_tables())},
        "gait": gait,
        "motion": {"bob": draw(st.floats(0.0, 0.2)), "yaw": draw(st.floats(0.0, 30.0)),
                   "bob_phase": draw(st.floats(-1, 1))},
    }
    try:
        return creature_from_dict(data)
    except SpecError:
        assume(False)


SETTINGS = settings(max_examples=int(__import__("os").environ.get("GAITLAB_EXAMPLES", "60")), deadline=None, suppress_health_check=[HealthCheck.filter_too_much,
                                                                            HealthCheck.too_slow])


@SETTINGS
@given(spec=creatures(), fps=st.sampled_from([24.0, 30.0, 60.0]))
def test_motion_is_finite_exact_and_above_ground(spec, fps) -> None:
    rig = build_rig(spec)
    motion, _ = clip_motion(rig, fps, cycles=1.0)
    arrays = [motion.joints, motion.spine, motion.spine_tangent, motion.neck, motion.head, motion.tail, motion.root]
    assert all(np.isfinite(a).all() for a in arrays)
    bones = np.linalg.norm(np.diff(motion.joints, axis=2), axis=-1)
    expected = np.stack([rig.femur, rig.tibia, rig.metatarsus, rig.toe], axis=-1)
    with np.errstate(invalid="ignore", divide="ignore"):
        rel = np.where(expected > 0, np.abs(bones / expected - 1.0), bones)
    assert rel.max() < 1e-9
    assert motion.joints[..., 3:5, 1].min() >= -1e-12  # ball and toe tip never below the ground


@SETTINGS
@given(spec=creatures(), fps=st.sampled_from([24.0, 30.0, 60.0]))
def test_measured_duty_factor_matches_request_within_one_frame(spec, fps) -> None:
    rig = build_rig(spec)
    motion, _ = clip_motion(rig, fps, cycles=1.0)  # exactly one cycle in a whole number of frames
    frames = motion.frame_count
    stance = motion.contact.sum(axis=0)
    assert np.all(np.abs(stance - rig.gait.duty_factor * frames) <= 1.0), (stance, rig.gait.duty_factor * frames)
