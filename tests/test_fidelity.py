"""Gaitlab's motion against published biomechanics (../shared/reference/fidelity.md), measured
from the joints that ``simulate`` solves, never from the spec's own parameters.

One test per row of the human-walk table. Rows Gaitlab does not meet yet are strict
expected failures: each names what is wrong, and starts failing the day it is fixed (so
the mark comes off)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from cli_runner import gaitlab

from app import build_rig, load_creature
from app.analysis.compare import compare_curves, leg_curves, read_normative
from app.analysis.fidelity import HUMAN_RUN, HUMAN_WALK, quadruped_measures, run_measures, walk_measures
from app.analysis.limbs import bvh_legs, motion_legs
from app.kinematics.clip import clip_motion
from app.resources import reference_dir

DATA = Path(__file__).parent / "data"
CMU_WALK = DATA / "human_walk_cmu_12_01.bvh"

NOT_YET: dict[str, str] = {}  # row: why Gaitlab's walk is still outside the typical range (none today)


@pytest.fixture(scope="module")
def walk():
    rig = build_rig(load_creature("human"))
    motion, _ = clip_motion(rig, 240.0, cycles=8.0)
    return rig, motion, walk_measures(motion)


@pytest.fixture(scope="module")
def run():
    rig = build_rig(load_creature("human").with_overrides({"gait.preset": "run"}))
    motion, _ = clip_motion(rig, 240.0, cycles=8.0)
    return run_measures(motion)


ROWS = [pytest.param(name, marks=[pytest.mark.xfail(strict=True, reason=NOT_YET[name])] if name in NOT_YET else [],
                     id=name.replace(" ", "_")) for name in HUMAN_WALK]


@pytest.mark.parametrize("row", ROWS)
def test_human_walk_row_is_in_its_typical_range(walk, row: str) -> None:
    low, high = HUMAN_WALK[row]
    value = walk[2][row]
    assert low - 1e-9 <= value <= high + 1e-9, f"{row}: {value:.2f} (typical {low:g} to {high:g})"


def _walk_curves(walk):
    rig, motion, _ = walk
    return leg_curves(motion_legs(motion), "L", contact_fraction=rig.gait.duty_factor)


@pytest.mark.parametrize("joint", ["hip", "knee", "ankle"])
def test_human_walk_curves_are_near_the_normative_mean(walk, joint: str) -> None:
    """Within 8 degrees RMS of Schwartz, Rozumalski & Trost (2008), free speed (bundled)."""
    normative = read_normative(reference_dir() / "human_walk_schwartz2008.csv")
    assert compare_curves(_walk_curves(walk), normative).rms[joint] < 8.0


@pytest.mark.xfail(strict=True, reason="the CMU 12_01 walker keeps 25-34 degrees of knee flexion through "
                                       "stance and peaks late, 17 degrees RMS from the normative mean; a knee "
                                       "within 8 of the norm (4.7 here) is 14.6 from this walker")
def test_human_walk_knee_is_near_the_cmu_walk(walk) -> None:
    clip = compare_curves(_walk_curves(walk), leg_curves(bvh_legs(str(CMU_WALK)), "L"))
    assert clip.rms["knee"] < 10.0


def _knee_peak(overrides: dict) -> float:
    rig = build_rig(load_creature("human").with_overrides(overrides))
    motion, _ = clip_motion(rig, 240.0, cycles=4.0)
    return float(leg_curves(motion_legs(motion), "L", contact_fraction=rig.gait.duty_factor).mean["knee"].max())


def test_a_walker_s_swing_knee_sets_how_far_its_knee_folds() -> None:
    """poses.swing_knee: people's 59 degrees by default; 75 folds the knee to about 75."""
    assert 55.0 < _knee_peak({}) < 63.0
    assert 70.0 < _knee_peak({"poses.swing_knee": 75.0}) < 80.0


@pytest.mark.parametrize("duty", [0.60, 0.72])
def test_a_walker_moves_without_jumps_at_toe_off(duty: float) -> None:
    """A slow walker (duty 0.72, the CMU subject's) at 240 frames a second: its knee turned
    23 degrees in one frame at toe-off (the swing's knee started part way through) and
    its hips rose 22 mm in one frame as the other foot left (its reach let go at once)."""
    rig = build_rig(load_creature("human").with_overrides({"gait.duty_factor": duty}))
    motion, _ = clip_motion(rig, 240.0, cycles=2.0)
    knee = np.asarray(motion_legs(motion).angles["L"].knee)  # degrees
    hip_height = motion.joints[:, :, 0, 1]
    assert np.abs(np.diff(knee)).max() < 10.0
    assert np.abs(np.diff(hip_height, axis=0)).max() < 0.008


@pytest.mark.parametrize("duty, most", [(0.60, 3.5), (0.72, 6.5)])
def test_a_walker_s_knee_straightens_through_the_terminal_swing_not_at_the_strike(duty: float, most: float) -> None:
    """People's knee straightens through the last sixth of the swing, nearly straight a
    few hundredths of a cycle before the strike (Schwartz et al. 2008). Gaitlab's walker's
    straightened in its last frames: 4.8 degrees in the last 240 fps frame at free speed,
    7.6 at duty 0.72; now its largest turn in a frame over the last 0.15 cycle is under
    ``most``, and it lands within 10 degrees of straight."""
    rig = build_rig(load_creature("human").with_overrides({"gait.duty_factor": duty}))
    motion, _ = clip_motion(rig, 240.0, cycles=3.0)
    legs = motion_legs(motion)
    knee, strikes = np.asarray(legs.angles["L"].knee), legs.strikes["L"]
    late = int(0.15 * np.median(np.diff(strikes)))
    checked = [strike for strike in strikes if strike >= late]
    assert len(checked) >= 2
    for strike in checked:
        assert np.abs(np.diff(knee[strike - late:strike + 1])).max() < most
        assert knee[strike] < 10.0


def test_the_cmu_strikes_are_the_heel_strikes() -> None:
    """A clip's cycles start where each foot is farthest ahead of the body (Zeni et al.
    2008), not where its toes brush the ground late in the swing: the knee is near its
    straightest for the cycle there, and peaks in the swing at 70-80 %."""
    legs = bvh_legs(str(CMU_WALK))
    curves = leg_curves(legs, "L")
    knee = curves.mean["knee"]
    assert knee[0] < knee.max() - 40.0
    peak = 100.0 * np.argmax(knee) / (len(knee) - 1)
    assert 70.0 <= peak <= 80.0


@pytest.mark.parametrize("row", list(HUMAN_RUN))
def test_human_run_row_is_in_its_typical_range(run, row: str) -> None:
    low, high = HUMAN_RUN[row]
    assert low - 1e-9 <= run[row] <= high + 1e-9, f"{row}: {run[row]:.2f} (typical {low:g} to {high:g})"


def test_the_run_flies_at_g_and_lands_without_a_jolt(run) -> None:
    assert run["flight acceleration g"] == pytest.approx(-1.0, abs=0.1)
    assert abs(run["largest vertical jolt g"]) <= 3.0


@pytest.mark.parametrize("speed", [2.5, 4.0, 5.5])
def test_a_run_at_any_speed_flies_without_a_jolt(speed: float) -> None:
    """The run's heights are worked out from where its feet land and leave: at 4 m/s and
    over, a toe-off height set by the thigh's angle alone asked the trailing leg to reach
    further back than it can, and the hips were pulled down at every toe-off (27-40 g)."""
    from app.kinematics.speed import simulate_speed

    motion, gaits = simulate_speed(build_rig(load_creature("human")), np.full(240 * 3, speed), 240.0)
    assert set(gaits) == {"run"}
    pelvis = motion.joints[:, -2:, 0, 1].mean(axis=1)
    accel = np.gradient(np.gradient(pelvis, 1 / 240), 1 / 240) / 9.81
    assert np.abs(accel[10:]).max() < 3.0


def _slowing_to_a_walk(rig):
    """The live motion of ``rig`` slowing from 4 to 1 m/s over 8 s at 240 fps (each frame
    with the gait its speed calls for), and the frames at which the reference foot took a
    walk's duty factor."""
    from app.kinematics.live import LiveMotion, stack_inputs
    from app.kinematics.motion import solve_motion
    from app.kinematics.speed import gait_at_speed

    speeds = np.linspace(4.0, 1.0, 240 * 8)
    current = gait_at_speed(rig, float(speeds[0]))
    live, gait, frames = LiveMotion(current), current.gait.preset, []
    for i, v in enumerate(speeds):
        if i:
            target = gait_at_speed(rig, float(v), gait)
            gait = target.gait.preset
            live.set_rig(target)
            live.step(1 / 240)
        frames.append(live.frame_inputs())
    inputs = stack_inputs(frames)
    motion = solve_motion(live.rig, live.world, inputs, fps=240.0)
    duty = inputs.plan.duty[:, -2]
    return motion, np.nonzero((duty[1:] >= 0.5) & (duty[:-1] < 0.5))[0] + 1


def test_a_runner_slowing_to_a_walk_keeps_its_height_and_speed_through_the_switch() -> None:
    """A foot takes the walk's duty factor at its touchdown, and the body's height follows
    the duty at once: from the run's last flight to the walk's contact pose it dropped 2.4 cm
    in one 240 fps frame (41 g); the run's forward lean went at once too, the chest and head
    moving 4 cm over the hips in one frame (80 g). Both jumps are now eased away
    (inertialization): within 0.1 s of every change of duty the hips' height, and the chest
    and head about the hips, accelerate under 3 g."""
    motion, switches = _slowing_to_a_walk(build_rig(load_creature("human")))
    assert len(switches) == 1
    pelvis = motion.joints[:, -2:, 0, 1].mean(axis=1)
    accel = np.gradient(np.gradient(pelvis, 1 / 240), 1 / 240) / 9.81
    near = slice(int(switches[0]) - 24, int(switches[0]) + 24)
    assert np.abs(accel[near]).max() < 3.0
    hips = motion.joints[:, -2:, 0].mean(axis=1)
    for point in (motion.spine[:, -1], motion.head[:, 0]):  # the chest, the head
        above = point - hips
        accel = np.linalg.norm(np.gradient(np.gradient(above, 1 / 240, axis=0), 1 / 240, axis=0), axis=-1) / 9.81
        assert accel[near].max() < 3.0


def test_a_theropod_slowing_to_a_walk_keeps_its_elbows_through_the_switch() -> None:
    """A body without key-pose heights (the theropod's [poses] sets only its arm swing) took
    no easing at all: its elbows opened from a run's bend in one frame (the wrist 49 mm over
    the hips, 72 g). The run's weight is eased for every body."""
    rig = build_rig(load_creature("theropod"))
    assert rig.poses.heights is None
    motion, switches = _slowing_to_a_walk(rig)
    assert len(switches) >= 1
    wrist = motion.arms[:, :, 2] - motion.joints[:, -2:, 0].mean(axis=1)[:, None]
    accel = np.linalg.norm(np.gradient(np.gradient(wrist, 1 / 240, axis=0), 1 / 240, axis=0), axis=-1).max(axis=1)
    for switch in switches:
        assert accel[int(switch) - 24:int(switch) + 24].max() / 9.81 < 5.0


def test_a_horse_walking_before_it_gallops_nods_as_a_walker() -> None:
    """A clip whose gait changes is solved in one pass with its last gait's rig: the nod was
    timed by that gait's offsets, so a horse that walked and then galloped swung its neck
    once a stride all through (a gallop's swing, 9 degrees, on a walk). The nod follows the
    fore feet's own phases now: twice a walking stride."""
    from numpy.fft import rfft

    from app.kinematics.speed import gait_at_speed, simulate_speed

    rig = build_rig(load_creature("horse"))
    fps = 60.0
    motion, gaits = simulate_speed(rig, np.concatenate([np.full(240, 1.6), np.linspace(1.6, 9.0, 240)]), fps)
    assert gaits[100] == "walk" and gaits[-1] == "gallop"
    d = motion.head[:, 1] - motion.head[:, 0]
    pitch = np.arctan2(d[:, 1], np.linalg.norm(d[:, [0, 2]], axis=-1))[60:240]  # the steady walk
    spectrum = np.abs(rfft(pitch - pitch.mean()))
    period = len(pitch) / (np.argmax(spectrum[1:]) + 1)  # frames
    stride = fps / gait_at_speed(rig, 1.6).gait.frequency
    assert period == pytest.approx(stride / 2, rel=0.15)


def test_a_height_jump_settles_from_its_height_and_speed_to_rest() -> None:
    from app.kinematics.poses import HEIGHT_SETTLE, settle

    t = np.array([0.0, 1e-5, HEIGHT_SETTLE - 1e-5, HEIGHT_SETTLE, 1.0])
    left = settle(0.02, -0.5, t)
    assert left[0] == pytest.approx(0.02)
    assert (left[1] - left[0]) / 1e-5 == pytest.approx(-0.5, rel=1e-3)
    assert left[2] == pytest.approx(0.0, abs=1e-9) and left[3] == 0.0 and left[4] == 0.0


def test_the_horse_walks_at_a_horse_s_duty_stride_and_nod() -> None:
    rig = build_rig(load_creature("horse"))
    motion, _ = clip_motion(rig, 240.0, cycles=6.0)
    q = quadruped_measures(motion)
    assert 0.60 <= q["duty factor"] <= 0.67
    assert 1.5 <= q["stride m"] <= 2.0
    assert 1.5 <= q["speed m/s"] <= 1.8
    assert 3.0 <= q["head vertical cm"] <= 12.0
    assert q["head frequency / stride frequency"] == pytest.approx(2.0, abs=0.2)


def test_the_horse_trots_a_trotter_s_stride_and_nods() -> None:
    """Alexander's relative stride at the trot's Froude number, and the head bowing twice a
    stride as each fore foot takes the weight."""
    rig = build_rig(load_creature("horse").with_overrides({"gait.preset": "trot"}))
    motion, _ = clip_motion(rig, 240.0, cycles=6.0)
    q = quadruped_measures(motion)
    assert 2.3 <= q["stride m"] <= 3.0 and 0.65 <= q["cycle s"] <= 0.8
    assert 3.0 <= q["head vertical cm"] <= 12.0
    assert q["head frequency / stride frequency"] == pytest.approx(2.0, abs=0.2)


def _fore_touchdowns(motion) -> list[np.ndarray]:
    c = motion.contact[:, :2]  # the fore pair (LF, RF)
    return [np.nonzero(c[1:, k] & ~c[:-1, k])[0] + 1 for k in range(2)]


@pytest.mark.parametrize("gait", ["walk", "trot"])
def test_the_horse_s_head_is_lowest_as_a_fore_foot_takes_the_weight(gait: str) -> None:
    """Twice a stride, the head's low point (against the withers' own motion: the neck's
    bow) comes within a fifth of a cycle after a fore foot lands, never before it."""
    rig = build_rig(load_creature("horse").with_overrides({"gait.preset": gait}))
    motion, _ = clip_motion(rig, 240.0, cycles=4.0)
    bow = motion.neck[:, 0, 1] - motion.head[:, 1, 1]  # the nose below the neck's root
    period = 240.0 / rig.gait.frequency
    lows = [i for i in range(1, len(bow) - 1) if bow[i] >= bow[i - 1] and bow[i] > bow[i + 1]]
    assert len(lows) >= 6
    touchdowns = np.concatenate(_fore_touchdowns(motion))
    for low in lows[1:-1]:
        since = (low - touchdowns[touchdowns <= low]).min() / period
        assert 0.0 < since <= 0.2, (gait, low, since)


def test_the_galloping_horse_s_neck_swings_once_a_stride() -> None:
    """In the gallop the head rises and falls once a stride (the neck swinging with it),
    lowest while the fore feet bear the weight and highest through the hind stance."""
    rig = build_rig(load_creature("horse").with_overrides({"gait.preset": "gallop"}))
    motion, _ = clip_motion(rig, 240.0, cycles=6.0)
    q = quadruped_measures(motion)
    assert q["head frequency / stride frequency"] == pytest.approx(1.0, abs=0.2)
    assert q["head vertical cm"] >= 10.0
    head = motion.head[:, 1, 1]
    fore = motion.contact[:, :2].any(axis=1) & ~motion.contact[:, 2:].any(axis=1)
    hind = motion.contact[:, 2:].any(axis=1) & ~motion.contact[:, :2].any(axis=1)
    assert head[fore].mean() < head[hind].mean() - 0.05


@pytest.mark.parametrize("gait", ["rotary-gallop", "bound"])
def test_a_galloping_dog_flexes_its_back(gait: str) -> None:
    rig = build_rig(load_creature("dog").with_overrides({"gait.preset": gait}))
    motion, _ = clip_motion(rig, 240.0, cycles=6.0)
    assert quadruped_measures(motion)["back flexion deg"] >= 8.0


# -- gaitlab compare ----------------------------------------------------------------------


def test_compare_against_the_cmu_walk_prints_rms_and_draws_the_plot(tmp_path) -> None:
    plot = tmp_path / "cmp.png"
    result = gaitlab("compare", "human", "--reference", CMU_WALK, "--plot", plot)
    assert result.returncode == 0, result.stderr
    assert "RMS" in result.stdout and "knee" in result.stdout
    from PIL import Image

    with Image.open(plot) as image:
        assert image.width > 600 and image.height > 200
        pixels = np.asarray(image.convert("RGB"), dtype=np.int16)
    assert np.ptp(pixels) > 100  # curves drawn, not a blank page


def test_compare_json_against_the_bundled_norms(tmp_path) -> None:
    import json

    result = gaitlab("compare", "human", "--json")
    assert result.returncode == 0, result.stderr
    data = json.loads(result.stdout)
    assert set(data["rms_deg"]) == {"hip", "knee", "ankle"}
    assert all(np.isfinite(v) for v in data["rms_deg"].values())


def test_compare_averages_the_cycles_asked() -> None:
    """--cycles 6 averaged 5, and --cycles 1 found no whole stride."""
    for cycles, shown in (("1", "(1 cycle)"), ("6", "(6 cycles)")):
        result = gaitlab("compare", "human", "--cycles", cycles)
        assert result.returncode == 0, result.stderr
        assert result.stdout.splitlines()[0].endswith(shown), result.stdout


def test_compare_asks_for_a_reference_for_animals_that_are_not_bipeds() -> None:
    """The bundled curves are a person's walk: a spider against them read knee -142 degrees."""
    result = gaitlab("compare", "spider")
    assert result.returncode == 2 and len(result.stderr.strip().splitlines()) == 1, result.stderr
    assert "the bundled reference is a person's walk, and the spider has 8 legs; give --reference" in result.stderr
    assert result.stdout == ""


@pytest.mark.parametrize("case, text, expect", [
    ("missing.bvh", None, "no such file"),
    ("columns.csv", "a,b\n1,2\n", "expected a header"),
    ("nolegs.bvh", "HIERARCHY\nROOT Hips\n{\n OFFSET 0 0 0\n CHANNELS 3 Xposition Yposition Zposition\n"
                   " End Site\n {\n  OFFSET 0 1 0\n }\n}\nMOTION\nFrames: 2\nFrame Time: 0.1\n0 0 0\n0 0 1\n",
     "no feet recognised"),
    ("negative_sd.csv", "phase,knee_mean,knee_sd\n0,5,2\n50,10,-3\n100,5,2\n",
     "knee_sd is -3 at phase 50; a standard deviation is 0 or more"),
    ("per_mille.csv", "phase,knee_mean,knee_sd\n0,5,2\n500,10,3\n1000,5,2\n",
     "phase must rise from about 0 to about 100"),
    ("huge.csv", "phase,knee_mean,knee_sd\n0,5,2\n50,1e308,3\n100,5,2\n",
     "knee_mean is 1e+308 at phase 50; joint angles are degrees, within -360 to 360"),
    ("twice.csv", "phase,knee_mean,knee_sd,knee_mean\n0,5,2,6\n50,10,3,7\n100,5,2,6\n",
     "column 'knee_mean' appears 2 times"),
])
def test_compare_refuses_bad_references_in_one_line(tmp_path, case: str, text: str | None, expect: str) -> None:
    path = tmp_path / case
    if text is not None:
        path.write_text(text)
    result = gaitlab("compare", "human", "--reference", path)
    assert result.returncode == 2
    assert expect in result.stderr and len(result.stderr.strip().splitlines()) == 1
    assert "Traceback" not in result.stderr


def test_a_runner_leans_in_and_drives_the_elbows_back() -> None:
    """Runners lean 5-10 degrees forward and swing their arms more back than forward, the
    hands coming forward to about the chest (the run's forearm once pointed up ahead at
    shoulder height, on an upright trunk), the elbow closing as the arm comes forward."""
    from app.kinematics.body import RUN_LEAN

    walk_rig = build_rig(load_creature("human"))
    run_rig = build_rig(load_creature("human").with_overrides({"gait.preset": "run"}))
    lean = {}
    for name, rig in (("walk", walk_rig), ("run", run_rig)):
        motion, _ = clip_motion(rig, 120.0, cycles=2.0)
        axis = motion.spine[:, -1] - motion.spine[:, 0]
        forward = motion.root[:, :3, 2]
        lean[name] = float(np.degrees(np.mean(np.arctan2(np.sum(axis * forward, axis=-1), axis[:, 1]))))
        if name == "run":
            shoulder, elbow, hand = motion.arms[:, 0, 0], motion.arms[:, 0, 1], motion.arms[:, 0, 3]
            upper = elbow - shoulder
            swing = np.degrees(np.arctan2(np.sum(upper * forward, axis=-1), -upper[:, 1]))
            assert swing.max() < 12.0 and swing.min() < -30.0  # more back than forward
            assert np.max(hand[:, 1] - shoulder[:, 1]) < -0.2  # the hand never above the lower chest
            # ... its forearm rising as it comes forward (held out level like a tray, it
            # was 0.6 cm higher at the wrist than at the elbow), turned in to the body's middle.
            front = int(np.argmax(swing))
            wrist = motion.arms[:, 0, 2]
            assert wrist[front, 1] - elbow[front, 1] > 0.04
            left = np.cross(np.array([0.0, 1.0, 0.0]), forward)
            assert np.sum((wrist[front] - elbow[front]) * left[front]) < -0.02
    assert 5.0 <= lean["run"] <= 10.0
    assert lean["run"] - lean["walk"] == pytest.approx(np.degrees(RUN_LEAN), abs=0.5)


def test_the_pelvis_drops_early_in_the_other_foot_s_stance() -> None:
    """A walker's swing side of the pelvis is lowest early in single support (~15-20 % of
    the cycle after the stance foot's strike: Perry & Burnfield), not at mid-swing (it
    dropped with the swinging foot's lift, lowest at ~30 %); timed so, the hips crest higher
    over the stance leg (pelvis vertical 3.3 -> 3.5 cm)."""
    from app.kinematics.body import OBLIQUITY_PEAK

    rig = build_rig(load_creature("human"))
    motion, _ = clip_motion(rig, 240.0, cycles=4.0)
    hips = motion.joints[:, :2, 0]
    across = hips[:, 0] - hips[:, 1]  # left hip minus right
    obliquity = np.degrees(np.arctan2(across[:, 1], np.linalg.norm(across[:, [0, 2]], axis=-1)))
    strikes = np.flatnonzero(np.diff(motion.contact[:, 0].astype(int)) == 1) + 1
    cycle = int(np.median(np.diff(strikes)))
    start = strikes[1]
    right_lowest = int(np.argmax(obliquity[start:start + cycle]))  # the left hip highest: the right side down
    assert abs(right_lowest / cycle - OBLIQUITY_PEAK) < 0.04
    assert 0.14 <= right_lowest / cycle <= 0.22
