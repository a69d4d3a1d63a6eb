"""The animator's walk: bipeds with arms, foot roll, key poses, styles, timing and arcs
(issue 9). Real values throughout: measured duty factors and phases, event times, slip,
mirror symmetry, heights, and the CLI's files and exit codes."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from cli_runner import gaitlab
from PIL import Image

from app import build_rig, load_creature
from app.analysis import analyze_tracks, tracks_from_motion
from app.analysis.metrics import cyclic_distance
from app.kinematics.arcs import arc_points, key_pose_frames, parse_arc_joints, trail
from app.kinematics.clip import clip_motion
from app.kinematics.motion import simulate
from app.kinematics.path import CirclePath
from app.kinematics.poses import key_pose_phases, pose_height
from app.kinematics.roll import HEEL_PART, contact_points
from app.kinematics.world import World
from app.rigging import apply_style
from app.spec import SpecError

ROOT = Path(__file__).parents[1]
MIRROR = np.array([-1.0, 1.0, 1.0])


@pytest.fixture(scope="module")
def human():
    return load_creature("human")


@pytest.fixture(scope="module")
def walk_report(human):
    rig = build_rig(human)
    motion, _ = clip_motion(rig, 200.0, cycles=4.0)
    return rig, motion, analyze_tracks(tracks_from_motion(motion), requested_gait="walk")


# -- the human walk, measured ------------------------------------------------------------


def test_human_walk_duty_factor_and_phases(walk_report) -> None:
    _, _, report = walk_report
    for foot in report.feet:
        assert 0.58 <= foot.duty_factor <= 0.65, (foot.name, foot.duty_factor)
    assert cyclic_distance(report.foot("R").phase - report.foot("L").phase, 0.5) < 0.01


def test_strike_before_landing_and_lift_before_liftoff_at_the_roll_timing(walk_report) -> None:
    """The analysis of Gaitlab's own rolling feet finds the heel strike at touchdown, the
    toes down when the roll sets them, the toes leaving at lift-off: each within one frame
    at the animator's 24 fps; and the heel rising in terminal stance, as a walker's does
    (it turns about the ball as the knee asks, from ~30 % of the cycle: Perry & Burnfield),
    at least a tenth of a cycle before the toes leave."""
    rig, motion, report = walk_report
    cycle = 1.0 / rig.gait.frequency
    duty = rig.gait.duty_factor
    r = float(rig.roll_amount[0])
    frame = 1.0 / 24.0
    for foot in report.feet:
        events = dict()
        for kind, t in foot.events:
            events.setdefault(kind, []).append(t)
        strikes = np.array(events["strike"])
        for strike in strikes[(strikes > 0.1) & (strikes < motion.times[-1] - cycle)]:
            landing = min(t for t in events["landing"] if t >= strike)
            lift = min(t for t in events["lift"] if t > landing)
            liftoff = min(t for t in events["liftoff"] if t > lift)
            assert strike < landing < lift < liftoff
            assert landing - strike == pytest.approx(r * HEEL_PART * duty * cycle, abs=frame)
            assert 0.1 * cycle <= liftoff - lift <= 0.35 * cycle
            assert liftoff - strike == pytest.approx(duty * cycle, abs=frame)


def _slip(motion, rig) -> float:
    """The most any planted point moves between frames of one roll part, in the ground's frame."""
    heel = motion.heel.copy()
    joints = motion.joints.copy()
    heel[..., 2] += motion.ground_offset[:, None]
    joints[..., 2] += motion.ground_offset[:, None, None]
    duty = np.broadcast_to(rig.gait.duty_factor, motion.phase.shape)
    points = contact_points(rig, rig.poses.foot_angle, motion.phase, duty, motion.contact, heel, joints)
    u = motion.phase / duty
    r = rig.roll_amount
    part = np.digitize(u, [0.0, r[0] * HEEL_PART, 1.0 - r[0] * 0.2]) + 10 * (u < 1e-12)
    same = motion.contact[1:] & motion.contact[:-1] & (part[1:] == part[:-1]) & (np.diff(motion.phase, axis=0) > 0)
    moved = np.linalg.norm(np.diff(points, axis=0), axis=-1)
    return float(np.max(np.where(same, moved, 0.0)))


@pytest.mark.parametrize("world", [World(in_place=True), World(path=CirclePath(2.5, "left"))],
                         ids=["in-place", "circle"])
def test_no_planted_point_slips(human, world) -> None:
    rig = build_rig(human)
    motion = simulate(rig, 3.0, 60.0, world=world)
    assert motion.reach_error[motion.contact].max() < 1e-9
    assert _slip(motion, rig) < 1e-6
    # ... and the contact point does move heel -> ball -> toe over a stance.
    first = np.nonzero(motion.contact[:, 0] & (np.diff(motion.phase[:, 0], prepend=1.0) < 0))[0][0]
    assert motion.heel[first, 0, 2] < motion.joints[first, 0, 3, 2] - 0.1  # the heel is behind the ball


def test_arms_swing_opposite_to_the_legs(walk_report) -> None:
    _rig, motion, report = walk_report
    # Left hand farthest forward with the right foot's touchdown (half a cycle after the left's).
    assert cyclic_distance(report.arm_phase["L"], 0.5) < 0.06
    assert cyclic_distance(report.arm_phase["R"], 0.0) < 0.06
    # At the right foot's touchdown the left hand is ahead of the right one.
    right_down = np.nonzero(np.diff(motion.contact[:, 1].astype(int)) == 1)[0] + 1
    ahead = motion.arms[right_down, 0, 3, 2] - motion.arms[right_down, 1, 3, 2]
    assert np.all(ahead > 0.2)


def test_human_run_has_a_flight_phase(human) -> None:
    rig = build_rig(human.with_overrides({"gait.preset": "run"}))
    motion, _ = clip_motion(rig, 200.0, cycles=4.0)
    report = analyze_tracks(tracks_from_motion(motion))
    assert all(f.duty_factor < 0.5 for f in report.feet)
    airborne = ~motion.contact.any(axis=1)
    assert airborne.mean() > 0.1  # both feet off the ground a tenth of the time or more


def test_speed_switches_a_biped_from_walk_to_run(human) -> None:
    from app.kinematics.speed import gait_at_speed

    rig = build_rig(human)
    assert gait_at_speed(rig, 1.2).gait.preset == "walk"
    assert gait_at_speed(rig, 3.5).gait.preset == "run"


def test_bird_and_theropod_walk_on_two_legs() -> None:
    for name in ("bird", "theropod"):
        rig = build_rig(load_creature(name))
        assert rig.leg_names == ("L", "R")
        motion = simulate(rig, 2.0, 60.0)
        assert np.isfinite(motion.joints).all()
        assert motion.reach_error[motion.contact].max() < 1e-6
        report = analyze_tracks(tracks_from_motion(clip_motion(rig, 200.0, cycles=4.0)[0]))
        assert cyclic_distance(report.foot("R").phase, 0.5) < 0.02


# -- key poses -------------------------------------------------------------------------


def _cycle(spec, fps: float = 96.0):
    rig = build_rig(spec)
    motion = simulate(rig, 1.0 / rig.gait.frequency, fps, world=World(in_place=True))
    return rig, motion


KEYS = ("contact", "down", "pass", "up")


def test_a_key_pose_edit_moves_its_frames_by_the_edit_and_nothing_else(human) -> None:
    """Editing a key pose's height moves the body at that key's frames by exactly the
    edit, both steps, and no other key; the lowest point of the walk is a key pose, so
    editing the lowest key moves the lowest point by exactly as much."""
    rig, motion = _cycle(human)
    frames = np.rint(key_pose_phases(True)[:4] * motion.frame_count).astype(int)
    both = np.stack([frames, frames + motion.frame_count // 2])  # (2 steps, 4 keys)
    lowest_key = int(np.argmin(rig.poses.heights))
    for key in {1, lowest_key}:  # the down pose, and the lowest (the contact, in the natural walk)
        name = KEYS[key]
        edited = human.with_overrides({f"poses.{name}_height": float(rig.poses.heights[key]) - 0.03})
        _rig2, motion2 = _cycle(edited)
        moved = motion2.spine[both, 0, 1] - motion.spine[both, 0, 1]
        assert np.allclose(moved[:, key], -0.03, atol=1e-3), name
        assert np.allclose(np.delete(moved, key, axis=1), 0.0, atol=1e-9), name
        if key == lowest_key:
            assert motion2.spine[:, 0, 1].min() == pytest.approx(motion.spine[:, 0, 1].min() - 0.03, abs=1e-3)


def test_pose_curve_passes_through_the_keys_smoothly() -> None:
    heights = np.array([-0.06, -0.08, -0.01, 0.0])
    u = np.array([0.0, 0.25, 0.5, 0.75, 1.0])
    assert np.allclose(pose_height(heights, u), [-0.06, -0.08, -0.01, 0.0, -0.06])
    fine = np.linspace(0.0, 1.0, 4001)
    curve = pose_height(heights, fine)
    assert curve.min() == pytest.approx(-0.08) and curve.max() == pytest.approx(0.0)  # no overshoot
    slope = np.diff(curve) / np.diff(fine)
    assert np.abs(np.diff(slope)).max() < 0.01  # C1: no kinks, also across the step's ends


def test_second_step_is_the_first_mirrored(human) -> None:
    _rig, motion = _cycle(human, fps=48.0)
    half = motion.frame_count // 2
    a, b = slice(half, motion.frame_count), slice(0, half)
    assert np.abs(motion.joints[a, 0] - motion.joints[b, 1] * MIRROR).max() < 1e-9
    assert np.abs(motion.joints[a, 1] - motion.joints[b, 0] * MIRROR).max() < 1e-9
    assert np.abs(motion.arms[a, 0] - motion.arms[b, 1] * MIRROR).max() < 1e-9
    for part in ("spine", "neck", "head", "heel"):
        values = getattr(motion, part)
        if part == "heel":
            values = values[:, ::-1]
        assert np.abs(getattr(motion, part)[a] - values[b] * MIRROR).max() < 1e-9, part


def test_key_poses_round_trip_through_the_creature_file(human, tmp_path) -> None:
    edited = human.with_overrides({"poses.down_height": -0.091, "poses.arm_swing": 31.0, "poses.torso_lean": 7.5,
                                   "gait.frames_per_cycle": 30})
    path = edited.save(tmp_path / "edited.toml")
    again = load_creature(str(path))
    assert again.poses == edited.poses
    assert again.gait.frames_per_cycle == 30
    assert build_rig(again).gait.frequency == pytest.approx(24.0 / 30.0)
    assert np.allclose(build_rig(again).poses.heights, build_rig(edited).poses.heights)


# -- styles ------------------------------------------------------------------------------


def _minima(y: np.ndarray) -> int:
    """Local minima of a periodic curve."""
    return int(np.sum((y < np.roll(y, 1)) & (y <= np.roll(y, -1))))


def test_double_bounce_has_two_downs_a_step(human) -> None:
    _, normal = _cycle(apply_style(human, "normal"))
    _, bounce = _cycle(apply_style(human, "double-bounce"))
    assert _minima(normal.spine[:, 0, 1]) == 2  # one a step
    assert _minima(bounce.spine[:, 0, 1]) == 4  # two a step


def test_sneak_is_at_least_ten_percent_lower(human) -> None:
    _, normal = _cycle(apply_style(human, "normal"))
    _, sneak = _cycle(apply_style(human, "sneak"))
    assert sneak.spine[:, :, 1].mean() <= 0.9 * normal.spine[:, :, 1].mean()
    for style in ("proud", "tired"):
        _, motion = _cycle(apply_style(human, style))
        assert np.isfinite(motion.joints).all()


def test_a_style_writes_its_values_for_editing(human) -> None:
    spec = apply_style(human, "tired")
    assert spec.poses.style == "tired" and spec.gait.stride == 0.5
    assert spec.poses.down_height == pytest.approx(-0.13 * build_rig(human).hip_height, abs=1e-4)
    with pytest.raises(SpecError, match="unknown"):
        apply_style(human, "moonwalk")


# -- arcs --------------------------------------------------------------------------------


def test_arc_is_the_joints_world_path_each_frame(human) -> None:
    rig = build_rig(human)
    motion = simulate(rig, 2.0, 24.0, world=World(path=CirclePath(3.0)))
    toe = arc_points(motion, "toe")
    assert np.array_equal(toe, motion.joints[:, :, 4])
    per_cycle = int(round(24.0 / rig.gait.frequency))
    path = trail(toe, 40, per_cycle)
    assert path.shape == (per_cycle + 1, 2, 3)
    assert np.array_equal(path, motion.joints[40 - per_cycle:41, :, 4])
    assert np.array_equal(arc_points(motion, "hand"), motion.arms[:, :, 3])
    keys = key_pose_frames(motion, 40, per_cycle)
    assert len(keys) == 8  # four key poses a step, two steps
    assert parse_arc_joints("toe, hand,toe") == ("toe", "hand")
    with pytest.raises(ValueError, match="elbow"):
        parse_arc_joints("toe,elbow")
    with pytest.raises(ValueError, match="no arms"):
        arc_points(simulate(build_rig(load_creature("dog")), 0.2, 24.0), "hand")


# -- the command line ----------------------------------------------------------------------


def test_poses_sheet_shows_five_labelled_poses(tmp_path) -> None:
    out = tmp_path / "poses.png"
    result = gaitlab("poses", "human", "-o", str(out), "--size", "160x200")
    assert result.returncode == 0, result.stderr
    image = np.asarray(Image.open(out).convert("RGB")).astype(int)
    assert image.shape == (200 + 44, 5 * 160, 3)
    background = np.array([250, 248, 244])
    for i in range(5):
        pose = image[:200, i * 160:(i + 1) * 160]
        label = image[200:, i * 160 + 2:(i + 1) * 160 - 2]
        assert (np.abs(pose - pose.mean(axis=(0, 1))).sum(axis=-1) > 60).mean() > 0.02  # a creature is drawn
        assert (np.abs(label - background).sum(axis=-1) > 150).sum() > 40  # its label is written
    assert "contact, down, pass, up, contact" in result.stdout


def test_a_pose_sheet_one_pixel_wide_is_made_not_a_traceback(tmp_path) -> None:
    result = gaitlab("poses", "human", "-o", str(tmp_path / "thin.png"), "--size", "1x100", "-q")
    assert result.returncode == 0, result.stderr
    assert np.asarray(Image.open(tmp_path / "thin.png")).shape[:2] == (100 + 44, 5)


@pytest.mark.parametrize("args, needle", [
    (["--set", "poses.down_height=3"], "poses.down_height"),
    (["--set", "poses.arm_swing=-5"], "poses.arm_swing"),
    (["--style", "moonwalk"], "moonwalk"),
    (["--frames-per-cycle", "0"], "frames per cycle"),
    (["--frames-per-cycle", "-12"], "frames per cycle"),
    (["--set", "gait.frames_per_cycle=0"], "gait.frames_per_cycle"),
])
def test_bad_animator_input_is_one_line_and_writes_nothing(tmp_path, args, needle) -> None:
    for command in (["poses", "human", "-o", str(tmp_path / "p.png")],
                    ["render", "human", "-o", str(tmp_path / "r.png"), "--size", "64x48"]):
        result = gaitlab(*command, *args)
        assert result.returncode == 2, (command, args, result.stderr)
        assert needle in result.stderr and result.stderr.count("\n") == 1, result.stderr
        assert "Traceback" not in result.stderr
    assert not list(tmp_path.iterdir())


def test_bad_arc_joint_is_one_line(tmp_path) -> None:
    for arcs, needle in (("toe,elbow", "elbow"), ("hand", "no arms")):
        result = gaitlab("render", "dog", "-o", str(tmp_path / "a.png"), "--size", "64x48", "--arcs", arcs)
        assert result.returncode == 2 and needle in result.stderr and result.stderr.count("\n") == 1, result.stderr
    assert not list(tmp_path.iterdir())


def test_render_with_arcs_draws_them(tmp_path) -> None:
    plain, arcs = tmp_path / "plain.png", tmp_path / "arcs.png"
    for out, extra in ((plain, []), (arcs, ["--arcs", "toe,hand"])):
        result = gaitlab("render", "human", "--in-place", "--camera", "side", "--size", "240x180", "-o", str(out),
                         *extra)
        assert result.returncode == 0, result.stderr
    a = np.asarray(Image.open(plain).convert("RGB")).astype(int)
    b = np.asarray(Image.open(arcs).convert("RGB")).astype(int)
    yellow = (b[..., 0] > 200) & (b[..., 1] > 150) & (b[..., 2] < 90)  # the toe's arc
    assert yellow.sum() > 15 and ((a[..., 0] > 200) & (a[..., 1] > 150) & (a[..., 2] < 90)).sum() < 5


def test_frames_per_cycle_sets_the_frequency(human) -> None:
    spec = human.with_overrides({"gait.frames_per_cycle": 32})
    assert build_rig(spec).gait.frequency == pytest.approx(0.75)
    spec = spec.with_overrides({"gait.frequency": 1.5})  # the other way round: frequency wins, cleanly
    assert spec.gait.frames_per_cycle is None and build_rig(spec).gait.frequency == 1.5
    assert math.isclose(build_rig(human).gait.frequency, 1.0)  # the human's 24 frames at 24 fps


# -- a quadruped's trunk in bounds and gallops --------------------------------------------


def _trunk_angles(motion) -> tuple[np.ndarray, np.ndarray]:
    """Spine flexion (rear segment's pitch minus the front one's) and trunk pitch (the
    chord from the rear segment to the front one), rad, per frame, from Motion.spine."""
    tangent_pitch = np.arcsin(np.clip(motion.spine_tangent[..., 1], -1.0, 1.0))
    chord = motion.spine[:, -1] - motion.spine[:, 0]
    return tangent_pitch[:, 0] - tangent_pitch[:, -1], np.arctan2(chord[:, 1], np.hypot(chord[:, 0], chord[:, 2]))


@pytest.mark.parametrize("creature, gait", [("dog", "bound"), ("dog", "gallop"), ("cat", "rotary-gallop"),
                                            ("cat", "half-bound"), ("horse", "gallop")])
def test_bounds_and_gallops_flex_the_spine_and_pitch_the_trunk(creature: str, gait: str) -> None:
    rig = build_rig(load_creature(creature).with_overrides({"gait.preset": gait}))
    assert rig.gait.flex > 0 and rig.gait.pitch > 0
    motion = simulate(rig, 2.0 / rig.gait.frequency, 120.0, world=World(in_place=True))
    flex, pitch = _trunk_angles(motion)
    # flex is asked either way (its range twice it), pitch over the cycle.
    assert np.ptp(flex) >= 2.0 * rig.gait.flex and np.ptp(pitch) >= rig.gait.pitch, (np.ptp(flex), np.ptp(pitch))
    # Flexed (arched) as the hind feet reach forward to land, extended as they push off.
    hind = rig.leg_count - 2
    touchdown = np.nonzero(np.diff(motion.contact[:, hind].astype(int)) == 1)[0] + 1
    liftoff = np.nonzero(np.diff(motion.contact[:, hind].astype(int)) == -1)[0] + 1
    assert flex[touchdown].mean() > flex[liftoff].mean()
    assert motion.reach_error[motion.contact].max() < 1e-9


def test_small_digitigrades_bend_most_and_walks_stay_straight() -> None:
    flex = {name: build_rig(load_creature(name).with_overrides({"gait.preset": "gallop"})).gait.flex
            for name in ("cat", "dog", "horse", "bear")}
    assert flex["cat"] > flex["dog"] > flex["bear"] > flex["horse"]
    for gait in ("walk", "trot", "pace"):
        motion = simulate(build_rig(load_creature("dog").with_overrides({"gait.preset": gait})), 1.0, 60.0,
                          world=World(in_place=True))
        assert np.ptp(_trunk_angles(motion)[0]) < 1e-3  # only the bob bends it, by hundredths of a degree
    stiff = build_rig(load_creature("dog").with_overrides({"gait.preset": "bound", "motion.spine_flex": 0}))
    assert stiff.gait.flex == 0.0


def test_a_gait_switch_eases_the_back_into_the_gallop() -> None:
    """Speeding up from a trot into a gallop: the back starts to flex without a jump, no
    faster from frame to frame than it does in the steady gallop at the end."""
    from app.kinematics.speed import simulate_speed

    rig = build_rig(load_creature("dog"))
    speeds = np.concatenate([np.linspace(2.0, 7.0, 600), np.full(240, 7.0)])
    motion, gaits = simulate_speed(rig, speeds, 120.0)
    assert gaits[0] == "trot" and gaits[-1] == "gallop"
    flex, _ = _trunk_angles(motion)
    steady = np.abs(np.diff(flex[-240:])).max()
    assert np.abs(np.diff(flex)).max() <= 1.25 * steady
    assert np.ptp(flex[-240:]) >= rig.speed.gaits["gallop"].flex


# -- overlap ------------------------------------------------------------------------------


def _fundamental_phase(signal: np.ndarray, clock: np.ndarray, harmonic: int) -> float:
    angle = 2.0 * np.pi * harmonic * clock
    centred = signal - signal.mean()
    return float(np.arctan2(np.sum(centred * np.sin(angle)), np.sum(centred * np.cos(angle))) / (2.0 * np.pi))


def test_overlap_delays_the_parts_it_names() -> None:
    """The tail's sway and the head's nod follow the body by the overlap's delay."""
    base = load_creature("dog")
    phases = {}
    for delay in (0.0, 0.1):
        rig = build_rig(base.with_overrides({"overlap.tail": delay, "overlap.head": delay, "motion.yaw": 0}))
        motion = simulate(rig, 2.0 / rig.gait.frequency, 120.0, world=World(in_place=True))
        sway = motion.tail[:, -1, 0]
        phases[delay] = _fundamental_phase(sway, motion.clock, 1)
        if delay:
            nod = motion.head[:, 1, 1] - motion.head[:, 0, 1]
            still = simulate(build_rig(base), 2.0 / rig.gait.frequency, 120.0, world=World(in_place=True))
            assert np.ptp(nod - (still.head[:, 1, 1] - still.head[:, 0, 1])) > 1e-3  # the head follows through
    assert cyclic_distance(phases[0.1] - phases[0.0], 0.1) < 0.01  # the sway comes 0.1 cycle later


def test_ears_follow_through_only_with_their_overlap() -> None:
    base = load_creature("dog")
    still = simulate(build_rig(base), 1.0, 60.0, world=World(in_place=True))
    assert np.all(still.ear_lag == 0.0)
    floppy = simulate(build_rig(base.with_overrides({"overlap.ears": 0.15})), 1.0, 60.0, world=World(in_place=True))
    assert np.ptp(floppy.ear_lag) > np.radians(3.0)
    from app.render.scene import motion_instances

    a, b = motion_instances(still, False), motion_instances(floppy, False)
    assert a.capsules.shape == b.capsules.shape and not np.allclose(a.capsules, b.capsules)  # the ears move


def test_ghosts_are_the_current_steps_key_poses_along_the_path(human) -> None:
    from app.kinematics.ghosts import key_pose_ghosts

    rig = build_rig(human)
    for world in (World(in_place=True), World(path=CirclePath(3.0))):
        ghosts = key_pose_ghosts(rig, world, clock=3.3, travel=3.3 * 1.05, phase=0.3)
        assert ghosts.frame_count == 5
        assert np.allclose(np.mod(ghosts.phase[:, 0], 1.0), np.mod(key_pose_phases(True), 1.0))
        roots = ghosts.spine[:, 0, [0, 2]]
        steps = np.linalg.norm(np.diff(roots, axis=0), axis=1)
        assert np.all(steps > 0.05)  # spread along the path, not piled on the creature
    second = key_pose_ghosts(rig, World(in_place=True), clock=3.7, travel=0.0, phase=0.7)
    assert np.allclose(np.mod(second.phase[:, 0], 1.0), np.mod(key_pose_phases(False), 1.0))


def test_arcs_stay_while_paused_and_ghosts_follow_the_ground(human) -> None:
    from app.kinematics.arcs import ArcTrail
    from app.kinematics.live import LiveMotion
    from app.ui.state import ViewerState

    rig = build_rig(human)
    live, arcs = LiveMotion(rig), ArcTrail()
    for _ in range(60):
        live.step(1.0 / 60.0)
        arcs.record(live.pose(), ("toe", "hand"), live.time, 1.0, 0)
    for _ in range(3):  # paused: the same frame drawn again
        arcs.record(live.pose(), ("toe", "hand"), live.time, 1.0, 0)
    trails, beads = arcs.trails()
    assert trails["toe"].shape[0] == 60 and sum(len(b) for b in beads.values()) >= 8
    arcs.record(live.pose(), ("toe", "hand", "head"), live.time, 1.0, 0)  # a joint ticked while paused
    assert "head" in arcs.trails()[0] and len(arcs.trails()[0]["toe"]) == 60

    state = ViewerState(human, world=World(in_place=True))
    state.show_ghosts = True
    first = [p.spine[0].copy() for p in state.ghost_poses()]
    for _ in range(6):
        state.advance(1.0 / 60.0)
    later = state.ghost_poses()
    moved = state.live.travel - 0.0
    assert len(later) == 5
    fresh = key_pose_ghosts_now(state)
    assert np.allclose([p.spine[0] for p in later], [p.spine[0] for p in fresh], atol=1e-9)
    assert not np.allclose([p.spine[0] for p in later], first) and moved > 0


def key_pose_ghosts_now(state):
    from app.kinematics.ghosts import key_pose_ghosts

    live = state.live
    phase = float(live.foot_phase()[live.rig.leg_count - 2])
    motion = key_pose_ghosts(live.rig, live.world, live.clock, live.travel, phase)
    return [motion.pose(i) for i in range(motion.frame_count)]


def test_a_png_s_arcs_are_the_cycle_up_to_its_frame(human, tmp_path) -> None:
    from app.recording import Recording, RecordRequest
    from app.render.options import ViewSettings

    request = RecordRequest.of(human, output=tmp_path / "a.png", fps=24.0, start=2.0, arcs=("hip",),
                            view=ViewSettings(size=(64, 48), antialias="off"))
    recording = Recording(request)
    try:
        _source, points, per_cycle, whole = recording._arcs
        assert whole and per_cycle == 24
        hip_now = recording.motion.joints[0, :, 0]
        assert np.allclose(points["hip"][-1], hip_now, atol=1e-9)  # the trail ends where the creature is
        assert points["hip"][0, 0, 2] < hip_now[0, 2] - 0.5  # and runs a cycle back
    finally:
        recording.cancel()


@pytest.mark.parametrize("args, needle", [
    (["--frames-per-cycle", "24", "--speed", "1.2"], "--frames-per-cycle"),
    (["--frames-per-cycle", "0.01"], "gait.frames_per_cycle"),
])
def test_timing_that_cannot_be_is_refused(tmp_path, args, needle) -> None:
    result = gaitlab("render", "human", "-o", str(tmp_path / "r.gif"), *args)
    assert result.returncode == 2 and needle in result.stderr and result.stderr.count("\n") == 1, result.stderr
    assert not list(tmp_path.iterdir())


def test_an_empty_arms_table_is_an_error(tmp_path) -> None:
    text = (ROOT / "creatures" / "human.toml").read_text()
    start = text.index("[arms]")
    end = text.index("[gait]")
    bad = tmp_path / "armless.toml"
    bad.write_text(text[:start] + "[arms]\n\n" + text[end:])
    with pytest.raises(SpecError, match="missing key arms.upper"):
        load_creature(str(bad))


def test_the_walker_curves_are_built_once() -> None:
    """The walker's five curves are kept (a cache of four thrashed: every solve rebuilt
    them, 40 % of a person's one-frame solve in the viewer)."""
    from app.kinematics.motion import simulate
    from app.kinematics.walker import _curve

    rig = build_rig(load_creature("human"))
    simulate(rig, 0.5, fps=30.0)  # a stance and a swing: every curve, in the order a clip asks for them
    before = _curve.cache_info().misses
    for _ in range(3):
        simulate(rig, 0.5, fps=30.0)
    assert _curve.cache_info().misses == before and _curve.cache_info().currsize == 5
