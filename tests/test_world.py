"""Creatures that travel: along paths, over terrain, with any number of leg pairs.

The acceptance of the world issue: planted feet never slip and stand on the ground,
swinging feet stay above it, bones keep their lengths, the body follows its path, turns
shorten the inner strides, stairs are climbed without standing on an edge, and the gaits
measure true.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from app import build_rig, load_creature, simulate
from app.analysis import analyze_tracks, tracks_from_motion
from app.analysis.metrics import cyclic_distance, path_error, wave_lag
from app.kinematics.clip import clip_motion
from app.kinematics.live import LiveMotion
from app.kinematics.motion import simulate as simulate_rig
from app.kinematics.roll import bearing_points
from app.kinematics.terrain import StairsTerrain
from app.resources import preset_creature_names
from app.worlds import make_world

PRESETS = preset_creature_names()


def terrains(rig) -> dict[str, str]:
    """The issue's terrains, sized to the creature (hills and steps it can walk; a biped's
    short trunk says little of its size: its legs do)."""
    h, length = rig.hip_height, rig.body_length
    if rig.leg_count == 2:
        length = max(length, 2.0 * h)
    return {"flat": "flat", "slope": "slope:angle=15,dir=30",
            "hills": f"hills:amp={0.12 * h:.4f},wavelength={3 * length:.3f}",
            "stairs": f"stairs:rise={0.2 * h:.4f},run={max(0.6 * rig.leg_scale, 0.12):.3f},steps=6,"
                      f"start={0.8 * length:.3f}"}


def paths(rig) -> dict[str, str]:
    """Straight, a circle of radius two body lengths, a figure-eight, four waypoints."""
    L = rig.body_length
    return {"straight": "straight", "circle": f"circle:r={2 * L:.3f}", "figure-eight": f"figure-eight:r={2 * L:.3f}",
            "waypoints": f"waypoints:0,0,{2.25 * L:.3f},{4.5 * L:.3f},0,{9 * L:.3f},{2.25 * L:.3f},{13.5 * L:.3f}"}


def planted_steps(motion) -> np.ndarray:
    """(T-1, L) True where a foot is planted in both frames of the same stance."""
    c = motion.contact
    return c[1:] & c[:-1] & (motion.phase[1:] > motion.phase[:-1])


@pytest.mark.parametrize("terrain", ["flat", "slope", "hills", "stairs"])
@pytest.mark.parametrize("creature", PRESETS)
def test_feet_plant_without_slip_on_every_path(creature: str, terrain: str) -> None:
    rig = build_rig(load_creature(creature))
    for path_name, path in paths(rig).items():
        motion = simulate_rig(rig, 4.0, 60.0, world=make_world(path, terrains(rig)[terrain]))
        where = f"{creature} on {terrain} along {path_name}"
        joints = motion.joints
        assert np.all(np.isfinite(joints)), where
        # What bears a planted foot (its ball; a rolling foot's heel, ball or toe tip in turn)
        # is a constant in the world, on the ground.
        bearing, same = bearing_points(motion)
        slip = np.linalg.norm(bearing[1:] - bearing[:-1], axis=-1)[same]
        assert slip.max() < 1e-6, where
        ground = motion.terrain.height(bearing[..., [0, 2]])
        ball_down = motion.contact & np.all(bearing == joints[:, :, 3], axis=-1)
        assert np.abs(bearing[..., 1] - ground)[ball_down].max() <= 1e-3, where
        # A rolling foot's heel or toe tip turns about the ground's plane under its ball: on
        # curved hills a rigid sole's end stands off the surface by a few millimetres (the
        # human's heel, 21 cm behind the ball, by up to 5.2 mm on these hills).
        assert np.abs(bearing[..., 1] - ground)[motion.contact].max() <= 6e-3, where
        swinging = ~motion.contact
        for k in (2, 3, 4):  # ankle, ball, toe tip of a swinging foot stay above the ground
            under = motion.terrain.height(joints[:, :, k][..., [0, 2]]) - joints[:, :, k, 1]
            assert under[swinging].max() <= 1e-3, (where, k)
        bones = np.linalg.norm(np.diff(joints, axis=2), axis=-1)
        expected = np.stack([rig.femur, rig.tibia, rig.metatarsus, rig.toe], axis=-1)
        assert np.abs(bones - expected).max() < 1e-9, where
        error = path_error(motion)
        assert error is not None and error.max_body_lengths <= 0.02, where
        assert error.heading_max_deg <= 5.0, where


def test_distance_is_speed_times_time_on_a_straight_path() -> None:
    for name in ("dog", "horse", "ant", "centipede"):
        rig = build_rig(load_creature(name))
        motion = simulate(rig, seconds=6.0, fps=60.0)
        travelled = np.linalg.norm(motion.root[-1, [0, 2], 3] - motion.root[0, [0, 2], 3])
        expected = rig.ground_speed * (motion.times[-1] - motion.times[0])
        assert travelled == pytest.approx(expected, rel=0.01), name
        # The planted feet really carry it: a stance covers speed x stance time relative to the hip.
        assert not motion.in_place and np.all(motion.ground_offset == 0.0)


def test_inner_feet_take_shorter_strides_on_a_turn() -> None:
    rig = build_rig(load_creature("dog"))
    radius = 2.0 * rig.body_length
    motion = simulate_rig(rig, 8.0, 60.0, world=make_world(f"circle:r={radius},dir=left"))
    lateral = rig.neutral_feet[:, 0]  # + left of the path: the inside of a left turn
    for inner, outer in ((0, 1), (2, 3)):  # LF/RF, LH/RH
        strides = []
        for leg in (inner, outer):
            touch = np.nonzero(motion.contact[1:, leg] & ~motion.contact[:-1, leg])[0] + 1
            spots = motion.joints[touch, leg, 3][:, [0, 2]]
            strides.append(np.median(np.linalg.norm(np.diff(spots, axis=0), axis=1)))
        expected = (radius - lateral[inner]) / (radius - lateral[outer])
        assert strides[0] / strides[1] == pytest.approx(expected, rel=0.10)
        assert strides[0] < strides[1]


@pytest.mark.parametrize("creature", PRESETS)
def test_stairs_are_climbed_without_standing_on_an_edge(creature: str) -> None:
    rig = build_rig(load_creature(creature))
    rise, run, steps, start = 0.2 * rig.hip_height, max(0.6 * rig.leg_scale, 0.12), 6, 0.8 * rig.body_length
    stairs = StairsTerrain(rise, run, steps=steps, start=start)
    seconds = (start + steps * run + 1.5 * rig.body_length) / rig.ground_speed
    motion = simulate_rig(rig, seconds, 60.0, world=make_world("straight", stairs))
    ball = motion.joints[:, :, 3]
    planted = ball[motion.contact]
    along = planted[:, 2] - start
    on_flight = (along > -run) & (along < steps * run + run)
    assert np.all(stairs.edge_distance(planted[on_flight][:, [0, 2]]) >= 0.01)  # not on a riser, not on an edge
    # The body climbs the flight: at the end it stands on the landing, a whole flight up.
    ground_end = float(stairs.height(motion.root[-1:, [0, 2], 3])[0])
    assert ground_end == pytest.approx(steps * rise)
    assert motion.root[-1, 1, 3] - motion.root[0, 1, 3] == pytest.approx(steps * rise, rel=0.1)


def _measured(creature: str, **overrides):
    spec = load_creature(creature).with_overrides(overrides) if overrides else load_creature(creature)
    rig = build_rig(spec)
    fps = max(120.0, math.ceil(200 * rig.gait.frequency))
    motion, _ = clip_motion(rig, fps, cycles=4.0)
    return rig, analyze_tracks(tracks_from_motion(motion))


@pytest.mark.parametrize("creature, gait", [("ant", "tripod"), ("ant", "tetrapod"), ("spider", "metachronal"),
                                            ("centipede", "metachronal")])
def test_many_legged_gaits_measure_true(creature: str, gait: str) -> None:
    rig, report = _measured(creature, **{"gait.preset": gait})
    requested = dict(zip(rig.leg_names, rig.gait.offsets))
    reference = requested[f"L{len(rig.leg_names) // 2}"]  # the rearmost left foot touches down at 0
    for foot in report.feet:
        assert foot.duty_factor == pytest.approx(rig.gait.duty_factor, abs=0.02), foot.name
        assert cyclic_distance(foot.phase, (requested[foot.name] - reference) % 1.0) <= 0.02, foot.name
    assert report.gait_match == gait


def test_the_ant_tripods_touch_down_together() -> None:
    _, report = _measured("ant")
    phases = {f.name: f.phase for f in report.feet}
    for group in (("L1", "R2", "L3"), ("R1", "L2", "R3")):
        for a in group:
            for b in group:
                assert cyclic_distance(phases[a], phases[b]) <= 0.02, (a, b)
    assert cyclic_distance(phases["L1"], phases["R1"]) == pytest.approx(0.5, abs=0.02)


@pytest.mark.parametrize("creature, lag", [("spider", 0.25), ("centipede", 0.12)])
def test_metachronal_waves_have_the_requested_lag(creature: str, lag: float) -> None:
    _rig, report = _measured(creature)
    assert float(load_creature(creature).gait.front_back) == lag
    measured = wave_lag({f.name: f.phase for f in report.feet})
    assert measured is not None and cyclic_distance(measured, lag) <= 0.02


def test_live_motion_travels_with_planted_feet() -> None:
    """The viewer's real-time path: along a circle over hills, planted feet stay put."""
    rig = build_rig(load_creature("dog"))
    live = LiveMotion(rig, make_world("circle:r=1.5", "hills:amp=0.05,wavelength=2"))
    balls, contact, phase = [], [], []
    for _ in range(240):
        live.step(1.0 / 60.0)
        pose = live.pose()
        balls.append(pose.joints[:, 3].copy())
        contact.append(pose.contact.copy())
        phase.append(pose.phase.copy())
    balls, contact, phase = np.array(balls), np.array(contact), np.array(phase)
    planted = contact[1:] & contact[:-1] & (phase[1:] > phase[:-1])
    assert np.linalg.norm(np.diff(balls, axis=0), axis=-1)[planted].max() < 1e-9
    assert live.travel == pytest.approx(rig.ground_speed * 4.0, rel=1e-6)


def test_speed_ramp_travels_the_path() -> None:
    from app.kinematics.speed import simulate_speed

    rig = build_rig(load_creature("dog"))
    fps = 60.0
    speeds = np.linspace(0.5, 3.0, int(6 * fps))
    motion, gaits = simulate_speed(rig, speeds, fps, world=make_world("circle:r=3"))
    assert gaits[0] == "walk" and gaits[-1] == "trot"
    slip = np.linalg.norm(np.diff(motion.joints[:, :, 3], axis=0), axis=-1)[planted_steps(motion)]
    assert slip.max() < 1e-9
    # The body follows the speed with the feet (strides change at lift-off): a little behind.
    assert motion.travel[-1] == pytest.approx(np.sum(speeds[1:]) / fps, rel=0.05)


def test_in_place_keeps_the_body_at_the_origin() -> None:
    motion = simulate("dog", seconds=2.0, fps=30.0, in_place=True)
    assert np.abs(motion.root[:, 2, 3]).max() < 0.05  # bob and sway only
    assert motion.ground_offset[-1] == pytest.approx(motion.travel[-1]) and motion.travel[-1] > 0.5


@pytest.mark.parametrize("creature", PRESETS)
def test_tight_turns_keep_feet_planted(creature: str) -> None:
    """A circle of half a body length: the inner feet almost mark time, none slips."""
    rig = build_rig(load_creature(creature))
    motion = simulate_rig(rig, 3.0, 60.0, world=make_world(f"circle:r={0.5 * rig.body_length:.4f}"))
    assert np.all(np.isfinite(motion.joints))
    bearing, same = bearing_points(motion)
    slip = np.linalg.norm(np.diff(bearing, axis=0), axis=-1)[same]
    assert slip.max() < 1e-6


def test_speed_ramp_up_a_slope_has_no_foot_jumps() -> None:
    """Speed and gait changes mid-swing: a swing aims at where it will really land, so on
    a slope no foot moves further in a frame than on flat ground (within 25%)."""
    rig = build_rig(load_creature("dog"))

    def largest_step(terrain: str) -> float:
        motion, _ = clip_motion(rig, 300.0, seconds=5.0, speed=(0.5, 6.0), world=make_world("straight", terrain))
        assert np.abs(motion.joints[:, :, 3, 1] - motion.terrain.height(motion.joints[:, :, 3][..., [0, 2]])
                      )[motion.contact].max() <= 1e-3  # planted feet on the ground
        return float(np.linalg.norm(np.diff(motion.joints[:, :, 3], axis=0), axis=-1).max())

    assert largest_step("slope:angle=10,dir=20") <= 1.25 * largest_step("flat")


def test_a_speed_ramp_clip_can_start_later() -> None:
    """--time with --speed: the creature has walked at the first speed until then."""
    rig = build_rig(load_creature("dog"))
    motion, _ = clip_motion(rig, 25.0, seconds=2.0, speed=(1.0, 2.0), start=3.0)
    assert motion.frame_count == 50 and motion.times[0] == pytest.approx(3.0)
    assert motion.travel[0] == pytest.approx(3.0, rel=0.02) and len(motion.gaits) == 50


# -- ground that the README offers is walked, not refused (issue 14) -----------------------


@pytest.mark.parametrize("creature, terrain", [
    ("human", "hills"), ("bird", "hills"), ("theropod", "hills"), ("bear", "hills"), ("bird", "stairs"),
])
def test_people_birds_and_bears_walk_the_default_hills_and_stairs(creature: str, terrain: str) -> None:
    from app.worlds import make_world

    rig = build_rig(load_creature(creature))
    motion = simulate_rig(rig, 20.0, 30.0, world=make_world("straight", terrain))
    bearing, same = bearing_points(motion)
    assert np.linalg.norm(bearing[1:] - bearing[:-1], axis=-1)[same].max() < 1e-6
    assert motion.reach_error[motion.contact].max() < 1e-6
    ground = motion.terrain.height(bearing[..., [0, 2]])
    ball_down = motion.contact & np.all(bearing == motion.joints[:, :, 3], axis=-1)
    assert np.abs(bearing[..., 1] - ground)[ball_down].max() <= 1e-3  # standing on the ground


README_TERRAINS = ("flat", "slope:angle=15", "hills", "stairs")
README_PATHS = ("straight", "circle:r=3", "figure-eight:r=3")
# Where the ground the README offers compromises footholds (60 s at 30 fps): the bird's
# short toes on the default stairs' edges, the cat where the default hills pass 40 degrees.
COMPROMISED = {("bird", "stairs", "straight"), ("bird", "stairs", "circle:r=3"),
               ("bird", "stairs", "figure-eight:r=3"), ("cat", "hills", "straight")}


def test_render_horse_on_steep_hills_walks(tmp_path) -> None:
    """``gaitlab render horse --terrain hills:amp=0.4`` walks, and so do twenty seconds
    of it (once refused at t = 14 s: a fore foot at the end of its stance could not reach
    its foothold down in a valley). Planted feet stay put, on the ground, within reach;
    where a leg cannot reach at a stance's end the foot lifts early, rarely."""
    from cli_runner import gaitlab

    result = gaitlab("render", "horse", "--terrain", "hills:amp=0.4", "-q", "-o", tmp_path / "horse.png")
    assert result.returncode == 0, result.stderr
    rig = build_rig(load_creature("horse"))
    motion = simulate_rig(rig, 20.0, 25.0, world=make_world("straight", "hills:amp=0.4"))
    bearing, same = bearing_points(motion)
    assert np.linalg.norm(bearing[1:] - bearing[:-1], axis=-1)[same].max() < 1e-6
    assert motion.reach_error[motion.contact].max() < 1e-3  # (0.9 mm where a hind foot's stretch outlasts its end)
    ground = motion.terrain.height(bearing[..., [0, 2]])
    ball_down = motion.contact & np.all(bearing == motion.joints[:, :, 3], axis=-1)
    assert np.abs(bearing[..., 1] - ground)[ball_down].max() <= 1e-3
    lifted = motion.lifted
    assert lifted is not None and 0 < lifted.sum() < 0.02 * (motion.contact | lifted).sum()
    ball = motion.joints[:, :, 3]
    assert np.all(ball[..., 1][lifted] > motion.terrain.height(ball[..., [0, 2]])[lifted])  # off the ground, not in it
    from app.analysis import analyze_tracks, tracks_from_motion

    notes = analyze_tracks(tracks_from_motion(motion)).notes
    assert any("cut short where the leg could not reach" in note for note in notes), notes


def test_a_stance_ends_where_the_leg_cannot_reach() -> None:
    """Misses at a stance's ends lift the foot early (in the stance's second half) or land
    it late (in its first); a miss between frames that reach, beyond the half, or through
    a whole stance stays a planted foot that misses (for check_reach to judge)."""
    from app.kinematics.motion import stance_ends_out_of_reach

    contact = np.array([0, 1, 1, 1, 1, 1, 1, 0, 1, 1], dtype=bool)[:, None]
    error = np.array([0, 0.05, 0, 0, 0.002, 0, 0.03, 0.1, 0, 0.04])[:, None]
    progress = np.array([0.9, 0.0, 0.2, 0.4, 0.6, 0.8, 0.95, 0.5, 0.1, 0.9])[:, None]
    lifted = stance_ends_out_of_reach(contact, error, progress)[:, 0]
    assert lifted.tolist() == [False, True, False, False, False, False, True, False, False, True]
    # An early lift stops at the stance's half: before it the foot stays planted (and missing).
    early = stance_ends_out_of_reach(np.ones((6, 1), bool), np.array([0, 0, 0.01, 0.02, 0.03, 0.04])[:, None],
                                     np.array([0.0, 0.2, 0.4, 0.6, 0.8, 0.99])[:, None])[:, 0]
    assert early.tolist() == [False, False, False, True, True, True]
    # A stance that never reaches, touchdown to lift-off, is no early lift or late landing:
    # it stays planted (and is refused).
    whole = stance_ends_out_of_reach(np.array([0, 1, 1, 1, 0], bool)[:, None], np.full((5, 1), 0.05),
                                     np.array([[0.9], [0.1], [0.5], [0.9], [0.1]]))
    assert not whole.any()
    # The same frames cut by the clip's start or end are judged on what the clip holds: a
    # landing (first half) or a lift (second half), as in any longer clip.
    contact, progress = np.array([0, 1, 1, 1, 0], bool)[:, None], np.array([[0.9], [0.1], [0.5], [0.9], [0.1]])
    expected = {(1, 4): [True, False, True], (0, 3): [False, True, False], (2, 5): [False, True, False]}
    for (a, b), lifted_frames in expected.items():
        part = stance_ends_out_of_reach(contact[a:b], np.full((3, 1), 0.05), progress[a:b])
        assert part[:, 0].tolist() == lifted_frames, (a, b)
    # Nor is a miss beyond the farthest a foot may lift early (steps far too high).
    assert not stance_ends_out_of_reach(np.array([[True], [True]]), np.array([[0.0], [0.3]]),
                                        np.array([[0.6], [0.7]]), np.array([0.2])).any()


@pytest.mark.parametrize("creature", PRESETS)
def test_every_preset_walks_a_minute_of_the_ground_the_readme_offers(creature: str) -> None:
    """Every preset x {flat, slope 15, the default hills, the default stairs} x {straight,
    circle r=3, figure-eight r=3}, 60 s each: never refused; planted feet do not slip and
    stand on the ground, within reach; compromised footholds only where :data:`COMPROMISED`
    lists them; a stance's ends lifted out of reach rarely (under 1 % of stance frames:
    the centipede's downhill feet across the hills' 34 degree side slopes)."""
    rig = build_rig(load_creature(creature))
    for terrain in README_TERRAINS:
        for path in README_PATHS:
            where = (creature, terrain, path)
            motion = simulate_rig(rig, 60.0, 30.0, world=make_world(path, terrain))
            bearing, same = bearing_points(motion)
            assert np.linalg.norm(bearing[1:] - bearing[:-1], axis=-1)[same].max() < 1e-6, where
            ground = motion.terrain.height(bearing[..., [0, 2]])
            ball_down = motion.contact & np.all(bearing == motion.joints[:, :, 3], axis=-1)
            assert np.abs(bearing[..., 1] - ground)[ball_down].max() <= 1e-3, where
            assert bool(motion.compromised.any()) == (where in COMPROMISED), where
            assert motion.reach_error[motion.contact].max() < 1e-6, where
            assert motion.lifted.sum() <= 0.01 * (motion.contact | motion.lifted).sum(), where


def test_uneven_ground_compromises_footholds_instead_of_refusing_them() -> None:
    """Ground whose every spot is too bumpy for a flat footprint (but not too steep) is
    walked on the least-bad spots, counted: ``analyze`` notes them, nothing slips."""
    from app.analysis import analyze_tracks, tracks_from_motion
    from app.worlds import make_world

    rig = build_rig(load_creature("dog"))
    motion = simulate_rig(rig, 6.0, 60.0, world=make_world("straight", "hills:amp=0.02,wavelength=0.3"))
    assert motion.compromised is not None and motion.compromised.any()
    bearing, same = bearing_points(motion)
    assert np.linalg.norm(bearing[1:] - bearing[:-1], axis=-1)[same].max() < 1e-6
    report = analyze_tracks(tracks_from_motion(motion))
    assert any("compromised footholds" in note for note in report.notes)
    # On the default hills the dog finds acceptable spots: nothing compromised.
    calm = simulate_rig(rig, 6.0, 60.0, world=make_world("straight", "hills"))
    assert calm.compromised is not None and not calm.compromised.any()


def test_a_rigid_sole_is_judged_along_its_heading() -> None:
    """A foot that keeps its heading through the stance (a person's) is probed along its
    sole: toe ahead, heel behind, its half-width across; a foot the body may turn is
    probed on a disc of its longest reach. (A 27 cm sole fits a 35 cm tread; a 42 cm disc
    does not.)"""
    from app.kinematics.footholds import footprint_probes

    front, back, side = np.array([0.1, 0.1]), np.array([0.2, 0.2]), np.array([0.03, 0.03])
    probes = footprint_probes(front, back, side, np.array([[0.0, 1.0], [np.nan, np.nan]]))
    sole, disc = probes[0], probes[1]
    assert sole[:, 1].max() == pytest.approx(0.1) and sole[:, 1].min() == pytest.approx(-0.2)
    assert np.abs(sole[:, 0]).max() == pytest.approx(0.03)
    assert np.linalg.norm(disc, axis=-1).max() == pytest.approx(0.2)
    assert disc[:, 1].max() == pytest.approx(0.2) and np.abs(disc[:, 0]).max() == pytest.approx(0.2)


def test_a_girdle_rolls_on_where_no_height_reaches_both_sides() -> None:
    """Across the default hills' steepest side slopes the centipede's girdles roll further
    towards the downhill side where no height would let both sides' feet reach: its
    feet miss their footholds by under 6 mm (8.4 mm with the roll that only followed the
    slope), and only at a stance's end, where the foot lifts early."""
    rig = build_rig(load_creature("centipede"))
    motion = simulate_rig(rig, 40.0, 30.0, world=make_world("straight", "hills"))
    assert motion.reach_error[motion.contact | motion.lifted].max() < 0.006
    assert motion.reach_error[motion.contact].max() < 1e-6


def test_footholds_and_straight_paths_on_their_short_cuts_are_the_general_answers() -> None:
    """The live motion's fast paths give the same numbers as the general code: feet placed
    on the flat floor without probing it, and a straight path sampled without its clamp
    and turn (both run several times a step; a centipede's Plots cost 13 % less)."""
    from app.kinematics.footholds import place_feet
    from app.kinematics.path import Path, StraightPath
    from app.kinematics.terrain import FlatTerrain

    class ProbedFlat(FlatTerrain):
        @property
        def flat(self) -> bool:
            return False  # the general search, on the same plane

    rng = np.random.default_rng(3)
    ideal = rng.uniform(-3.0, 3.0, (12, 2))
    reach = rng.uniform(0.01, 0.2, (3, 12))
    search, slope = np.full(12, 0.3), np.full(12, np.radians(30.0))
    fast, probed = (place_feet(t, ideal, *reach, search, slope) for t in (FlatTerrain(), ProbedFlat()))
    for a, b in ((fast.points, probed.points), (fast.normals, probed.normals), (fast.ok, probed.ok),
                 (fast.compromised, probed.compromised)):
        assert np.array_equal(a, b)
    s = rng.uniform(-4.0, 40.0, (5, 3))
    for start, heading in (((0.0, 0.0), 0.0), ((1.5, -2.25), 0.7), ((-3.0, 4.0), -2.1)):
        path = StraightPath(start, heading)
        for a, b in zip(path.sample(s), Path.sample(path, s)):
            assert a.shape == (5, 3, 2) and np.array_equal(a, b)
