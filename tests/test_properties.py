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
from app.styles import WALK_STYLES

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
                   "bob_phase": draw(st.floats(-1, 1)), "spine_flex": draw(st.floats(0.0, 3.0))},
        "overlap": {part: draw(st.floats(0.0, 0.5)) for part in ("head", "neck", "tail", "ears")},
    }
    for pair in ("fore", "hind"):  # foot roll on some legs
        if draw(st.booleans()):
            data["legs"][pair]["roll"] = draw(st.floats(0.0, 1.0))
    try:
        return creature_from_dict(data)
    except SpecError:
        assume(False)


def assert_bones_exact(motion, rig) -> None:
    """Every leg bone keeps its length to 1e-9 (relative; zero-length toes stay zero)."""
    bones = np.linalg.norm(np.diff(motion.joints, axis=2), axis=-1)
    expected = np.stack([rig.femur, rig.tibia, rig.metatarsus, rig.toe], axis=-1)
    with np.errstate(invalid="ignore", divide="ignore"):
        rel = np.where(expected > 0, np.abs(bones / expected - 1.0), bones)
    assert rel.max() < 1e-9, (np.unravel_index(rel.argmax(), rel.shape), bones.reshape(-1, 4)[:2], expected)


SETTINGS = settings(max_examples=int(__import__("os").environ.get("GAITLAB_EXAMPLES", "60")), deadline=None,
                    suppress_health_check=[HealthCheck.filter_too_much, HealthCheck.too_slow])


@SETTINGS
@given(spec=creatures(), fps=st.sampled_from([24.0, 30.0, 60.0]))
def test_motion_is_finite_exact_and_above_ground(spec, fps) -> None:
    rig = build_rig(spec)
    motion, _ = clip_motion(rig, fps, cycles=1.0)
    arrays = [motion.joints, motion.spine, motion.spine_tangent, motion.neck, motion.head, motion.tail, motion.root]
    assert all(np.isfinite(a).all() for a in arrays)
    assert_bones_exact(motion, rig)
    assert motion.joints[..., 3:5, 1].min() >= -1e-12  # ball and toe tip never below the ground
    assert motion.joints[..., 0, 1].min() >= -1e-12  # nor a hip


@SETTINGS
@given(spec=creatures(), fps=st.sampled_from([24.0, 30.0, 60.0]))
def test_measured_duty_factor_matches_request_within_one_frame(spec, fps) -> None:
    rig = build_rig(spec)
    motion, _ = clip_motion(rig, fps, cycles=1.0)  # exactly one cycle in a whole number of frames
    frames = motion.frame_count
    # The planned stance: planted, or lifted early / landed late where a leg cannot reach
    # its foothold (odd bodies: hind legs half as long as the fore legs, a long stride)...
    stance = (motion.contact | motion.lifted).sum(axis=0)
    assert np.all(np.abs(stance - rig.gait.duty_factor * frames) <= 1.0), (stance, rig.gait.duty_factor * frames)
    # ... and those only where the leg cannot reach.
    assert np.all(motion.reach_error[motion.lifted] > 1e-6)


@st.composite
def many_legged(draw):
    """Random body plans: 1 to 6 leg pairs, upright or sprawled, with the gaits that fit."""
    pairs = draw(st.integers(1, 6))
    positions = sorted(draw(st.lists(st.floats(0.0, 1.0), min_size=pairs, max_size=pairs, unique=True)))
    assume(all(b - a > 0.02 for a, b in zip(positions, positions[1:])))
    sprawled = draw(st.booleans())
    legs = {}
    for i, position in enumerate(positions):
        table = draw(leg_tables())
        table["position"] = position
        table["natural_bend"] = max(table["natural_bend"], 0.05)  # room to walk: not locked straight at rest
        if sprawled:
            table.update(knee="out", abduction=draw(st.floats(20.0, 70.0)), splay=draw(st.floats(-60.0, 60.0)))
        else:
            table["knee"] = draw(st.sampled_from(["forward", "back"]))
        legs[f"pair{i}"] = table
    gait = {"preset": draw(st.sampled_from(gaits_for(pairs))), "duty_factor": draw(st.floats(0.3, 0.85)),
            "step_height": draw(st.floats(0.05, 0.4)), "stride": draw(st.floats(0.1, 1.0))}
    data = {"name": "random", "body": {"length": draw(st.floats(0.2, 2.0)), "width": draw(st.floats(0.1, 0.6)),
                                       "radius": [0.05, 0.08, 0.06]},
            "legs": legs, "gait": gait}
    try:
        return creature_from_dict(data)
    except SpecError:
        assume(False)


@SETTINGS
@given(spec=many_legged(), terrain=st.sampled_from(["flat", "slope:angle=10,dir=40", "hills:amp=0.03,wavelength=3"]),
       path=st.sampled_from(["straight", "circle:r=3", "figure-eight:r=4"]))
def test_any_body_plan_travels_with_planted_feet(spec, terrain, path) -> None:
    from app.kinematics.motion import simulate
    from app.kinematics.world import WorldError
    from app.worlds import make_world

    rig = build_rig(spec)
    # Feet can stay planted only where the stride is within the legs' reach (otherwise the
    # body crouches as far as it may and the IK pulls the foot in: no NaN, exact bones).
    feasible = bool(np.all(rig.stance_extent(0.5 * rig.stride_length) < 0.6 * rig.l_max)
                    and np.all(rig.l_min < 0.5 * rig.l_max))  # and legs that can bend (not stilts)
    try:
        motion = simulate(rig, 1.0 / rig.gait.frequency, 30.0, world=make_world(path, terrain))
    except WorldError:
        assume(False)
    arrays = [motion.joints, motion.spine, motion.neck, motion.head, motion.tail, motion.root]
    assert all(np.isfinite(a).all() for a in arrays)
    assert_bones_exact(motion, rig)
    ball = motion.joints[:, :, 3]
    same = motion.contact[1:] & motion.contact[:-1] & (motion.phase[1:] > motion.phase[:-1])
    if same.any() and feasible:
        assert np.linalg.norm(np.diff(ball, axis=0), axis=-1)[same].max() < 1e-9  # planted feet never slip


@st.composite
def bipeds(draw):
    """Random two-legged creatures: upright or horizontal, with or without arms, rolling
    feet, key poses (a style or random heights), overlap."""
    leg = draw(leg_tables())
    leg.update(position=0.5, knee="forward", natural_bend=max(leg["natural_bend"], 0.01),
               roll=draw(st.floats(0.0, 1.0)))
    hip = 0.5 * (leg["femur"] + leg["tibia"])
    data = {"name": "biped", "legs": {"legs": leg},
            "body": {"length": draw(st.floats(0.1, 1.2)), "width": draw(st.floats(0.05, 0.5)), "radius": [0.05, 0.08],
                     "posture": draw(st.sampled_from(["upright", "horizontal"])), "tail_length": draw(st.floats(0, 0.8))},
            "gait": {"preset": draw(st.sampled_from(gaits_for(1))), "duty_factor": draw(st.floats(0.3, 0.8)),
                     "stride": draw(st.floats(0.1, 1.0)), "step_height": draw(st.floats(0.05, 0.3))},
            "motion": {"pelvis_tilt": draw(st.floats(0.0, 20.0)), "yaw": draw(st.floats(0.0, 20.0))},
            "overlap": {part: draw(st.floats(0.0, 0.5)) for part in ("head", "neck", "arms", "tail", "ears")}}
    if draw(st.booleans()):
        data["arms"] = {"upper": draw(length), "fore": draw(length), "hand": draw(st.floats(0.01, 0.3)),
                        "elbow": draw(st.floats(0.0, 150.0))}
    if draw(st.booleans()):
        data["poses"] = {"style": draw(st.sampled_from(list(WALK_STYLES)))}
    else:
        data["poses"] = {k: draw(st.floats(-0.3, 0.05)) * hip for k in
                         ("contact_height", "down_height", "pass_height", "up_height")}
    data["poses"].update(foot_angle=draw(st.floats(-30.0, 60.0)), arm_swing=draw(st.floats(0.0, 80.0)),
                         torso_lean=draw(st.floats(-30.0, 45.0)))
    try:
        return creature_from_dict(data)
    except SpecError:
        assume(False)


@SETTINGS
@given(spec=bipeds(), world=st.sampled_from(["in-place", "straight", "circle"]))
def test_any_biped_is_finite_exact_and_mirrored(spec, world) -> None:
    from app.kinematics.motion import simulate
    from app.kinematics.roll import bearing_points
    from app.kinematics.world import World, WorldError
    from app.worlds import make_world

    rig = build_rig(spec)
    place = World(in_place=True) if world == "in-place" else make_world(
        "straight" if world == "straight" else f"circle:r={max(4.0 * rig.body_length, 3.0):.3f}", "flat")
    try:
        motion = simulate(rig, 1.0 / rig.gait.frequency, 48.0 * rig.gait.frequency, world=place)
    except WorldError:
        assume(False)
    arrays = [motion.joints, motion.heel, motion.arms, motion.spine, motion.neck, motion.head, motion.tail,
              motion.root, motion.ear_lag]
    assert all(np.isfinite(a).all() for a in arrays)
    assert_bones_exact(motion, rig)
    if rig.arms is not None:
        arm = np.linalg.norm(np.diff(motion.arms, axis=2), axis=-1)
        assert np.allclose(arm, [rig.arms.upper, rig.arms.fore, rig.arms.hand], rtol=1e-9)
    # Where the legs can put the foot as the roll asks (the ball on its target and the
    # bearing point on the ground: an absurd leg, a femur eight times its tibia, cannot),
    # what bears a planted foot never slips.
    bearing, same = bearing_points(motion)
    placed = (motion.reach_error < 1e-9) & (np.abs(bearing[..., 1]) < 1e-6)
    reached = placed[:-1] & placed[1:]  # in both frames
    moved = np.linalg.norm(np.diff(bearing, axis=0), axis=-1)
    with np.errstate(invalid="ignore"):
        assert np.nan_to_num(np.where(same & reached, moved, 0.0)).max() < 1e-6
    alternating = abs(abs(rig.gait.offsets[1] - rig.gait.offsets[0]) - 0.5) < 1e-12  # walk, run; not a hop
    if world == "in-place" and alternating:  # the second step is the first mirrored
        half = motion.frame_count // 2
        mirror = np.array([-1.0, 1.0, 1.0])
        assert np.abs(motion.joints[half:2 * half, 0] - motion.joints[:half, 1] * mirror).max() < 1e-9
        assert np.abs(motion.spine[half:2 * half] - motion.spine[:half] * mirror).max() < 1e-9


def test_a_leg_s_longest_reach_is_never_shorter_than_its_shortest() -> None:
    """Found by a 2000-example run: a sprawled leg with a metatarsus four times its femur
    and tibia together (0.0625, 0.0625, 0.5 m), its rest turned far out, had an L_max below
    its L_min; the ball was held out of the ankle's reach and femur and tibia stretched 2.7 %."""
    from app.kinematics.rig import leg_lengths

    grid = np.stack(np.meshgrid([0.0625, 0.25, 1.0], [0.0625, 1.0], [0.05, 0.5, 2.0], np.radians([0.0, 40.0, 76.0]),
                                np.radians([0.0, 30.0, 60.0, 90.0]), indexing="ij"), axis=-1).reshape(-1, 5)
    femur, tibia, metatarsus, lift, swing_rest = grid.T
    l_max, _, l_min = leg_lengths(femur, tibia, metatarsus, lift, np.full(len(grid), 0.05), swing_rest)
    assert np.all(l_max >= l_min) and np.all(l_max <= femur + tibia + metatarsus)


def test_hips_of_a_tiny_hind_leg_under_a_tall_body_stay_above_the_ground() -> None:
    """Found by a 2000-example run: hind legs a tenth of the fore legs' reach under a
    short, thick, wide body. The girdle's lowest height was the planted foot's nearest
    for the hip but was kept by the girdle's centre, and the pelvis's tilt took one hip
    1.8 mm under the ground; the ball, pulled in towards that hip, 27 um under it."""
    leg = {"toe": 0.0, "ankle_lift": 0.0, "natural_bend": 0.0, "radius": 0.005}
    spec = creature_from_dict({
        "name": "short hind legs",
        "body": {"length": 0.1, "width": 0.5, "radius": [0.25], "segments": 2, "neck_length": 0.0,
                 "tail_length": 0.0, "tail_segments": 1},
        "legs": {"fore": {**leg, "femur": 1.0, "tibia": 0.5, "metatarsus": 0.5, "knee": "back", "roll": 1.0},
                 "hind": {**leg, "femur": 0.34375, "tibia": 0.1875, "metatarsus": 0.515625, "knee": "forward"}},
        "gait": {"preset": "walk", "duty_factor": 0.5, "wave": "planted", "step_height": 0.0, "stride": 1.0},
        "motion": {"bob": 0.0, "yaw": 0.0, "bob_phase": 0.0, "spine_flex": 0.0},
        "overlap": {part: 0.0 for part in ("head", "neck", "tail", "ears")}})
    rig = build_rig(spec)
    for fps in (24.0, 60.0):
        motion, _ = clip_motion(rig, fps, cycles=1.0)
        assert motion.joints[..., 0, 1].min() >= -1e-12  # hips
        assert motion.joints[..., 3:5, 1].min() >= -1e-12  # balls and toe tips
        assert_bones_exact(motion, rig)
