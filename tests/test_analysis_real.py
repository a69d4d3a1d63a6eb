"""The analysis on real motion capture nobody here wrote (see tests/data/README.md)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from app.analysis import analyze_tracks
from app.analysis.metrics import cyclic_distance
from app.analysis.sources import load_tracks

DATA = Path(__file__).parent / "data"
CMU_WALK_PATH = DATA / "human_walk_cmu_12_01.bvh"


def test_cmu_human_walk() -> None:
    tracks, notes = load_tracks(str(DATA / "human_walk_cmu_12_01.bvh"))
    assert tracks.names == ("L", "R") and "cmu" in notes and "rest pose" in notes
    assert tracks.hip_height == pytest.approx(0.85, abs=0.1)  # metres, after detecting CMU units
    report = analyze_tracks(tracks)
    for foot in report.feet:
        # Stance ~60-70% of the stride; this slow walk (0.88 m/s) stands long: Zeni et al.'s
        # kinematic events (heel most forward, toe most behind the pelvis) give 0.69-0.72.
        assert 0.60 <= foot.duty_factor <= 0.75, foot
    assert cyclic_distance(report.foot("R").phase, 0.5) <= 0.05
    assert report.gait_match == "walk"
    assert 1.0 <= report.cycle_seconds <= 1.4 and 0.6 <= report.speed <= 1.3


def test_dog_walk_reads_as_a_lateral_sequence_walk_into_an_amble() -> None:
    """The Labrador speeding up from a walk: lateral sequence (LF lands a little after LH,
    RH half a cycle off), a walk, then lateral footfalls with the duty factor falling
    towards 0.5: an amble, then a walk again. Its paws slide: a contact ends where the paw
    moves over the ground (the left fore paw read 0.82 when it ended only where it rose).
    The corpus test holds the same clip to an independent detector within 0.05."""
    tracks, notes = load_tracks(str(DATA / "dog_walk_tencent_walkrun005_f120-419.bvh"))
    assert set(tracks.names) == {"LF", "RF", "LH", "RH"} and "centimetres" in notes
    report = analyze_tracks(tracks)
    assert 0.05 <= report.foot("LF").phase <= 0.45  # LF touches down a fraction of a cycle after LH
    assert cyclic_distance(report.foot("RH").phase, 0.5) <= 0.12  # RH about half a cycle after LH
    assert report.spans[0].gait == "walk" and report.gait_match == "walk"
    assert {span.gait for span in report.spans} <= {"walk", "amble", "pace", "transition"}
    assert all(0.45 <= foot.duty_factor <= 0.62 for foot in report.feet), report.feet


def test_dog_trot() -> None:
    """Diagonal pairs land close together (the fore paw about 0.12 of a cycle before its
    diagonal hind paw in this curving take, by the corpus's independent detector too)."""
    report = analyze_tracks(load_tracks(str(DATA / "dog_trot_tencent_walkrun001_f960-1156.bvh"))[0])
    assert report.gait_match == "trot"
    assert cyclic_distance(report.foot("RF").phase, 0.0) <= 0.08
    assert cyclic_distance(report.foot("LF").phase, report.foot("RH").phase) <= 0.16


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
    """The real human's hands swing against the legs: they alternate, and each is farthest
    forward in the half cycle before the other foot lands (this subject's at about 0.2 of
    a cycle before it: at 0.88 m/s the hands also swing at twice the stride rate, a known
    trait of slow walking, which moves the fundamental's peak)."""
    from app.analysis.metrics import cyclic_distance

    tracks, _ = load_tracks(str(DATA / "human_walk_cmu_12_01.bvh"))
    assert tracks.hands is not None and tracks.hands.shape[1:] == (2, 3)
    report = analyze_tracks(tracks)
    left, right = report.arm_phase["L"], report.arm_phase["R"]
    assert cyclic_distance(left - right, 0.5) < 0.12
    assert (report.foot("R").phase - left) % 1.0 <= 0.3  # the left hand leads the right foot's landing
    assert (1.0 - right) % 1.0 <= 0.3  # the right hand leads the left foot's
    dog, _ = load_tracks(str(DATA / "dog_walk_tencent_walkrun005_f120-419.bvh"))
    assert dog.hands is None and analyze_tracks(dog).arm_phase is None


NAMING = {  # convention: (left ankle, left toe, right ankle, right toe)
    "Mixamo, any prefix": ("mixamorig7:LeftFoot", "mixamorig7:LeftToeBase", "mixamorig7:RightFoot",
                           "mixamorig7:RightToeBase"),
    "L_Foot/L_ToeBase": ("L_Foot", "L_ToeBase", "R_Foot", "R_ToeBase"),
    "ASF lfoot/ltoes": ("lfoot", "ltoes", "rfoot", "rtoes"),
    "3ds Max Biped": ("Bip01_L_Foot", "Bip01_L_Toe0", "Bip01_R_Foot", "Bip01_R_Toe0"),
    "Blender foot.L": ("foot.L", "toe.L", "foot.R", "toe.R"),
    "lFoot/rFoot": ("lFoot", "lToes", "rFoot", "rToes"),
    "SMPL L_Ankle/L_Foot": ("L_Ankle", "L_Foot", "R_Ankle", "R_Foot"),
}


@pytest.mark.parametrize("convention", list(NAMING))
def test_feet_are_found_under_every_usual_naming(tmp_path: Path, convention: str) -> None:
    """The CMU walk with its foot joints renamed as other tools name them: the same feet
    are found and the same gait measured, without --feet."""
    from app.analysis import analyze_tracks
    from app.analysis.sources import load_tracks

    text = CMU_WALK_PATH.read_text()
    for old, new in zip(("LeftFoot", "LeftToeBase", "RightFoot", "RightToeBase"), NAMING[convention]):
        text = text.replace(f"JOINT {old}\n", f"JOINT {new}\n")
    renamed = tmp_path / "walk.bvh"
    renamed.write_text(text)
    ours = analyze_tracks(load_tracks(str(renamed))[0])
    theirs = analyze_tracks(load_tracks(str(CMU_WALK_PATH))[0])
    assert [f.name for f in ours.feet] == ["L", "R"]
    for a, b in zip(ours.feet, theirs.feet):
        assert a.duty_factor == pytest.approx(b.duty_factor, abs=1e-9)
        assert a.phase == pytest.approx(b.phase, abs=1e-9)


def test_feet_may_name_namespaced_joints_and_end_sites(tmp_path: Path) -> None:
    """``--feet`` takes a namespaced joint (colons and all) and an End Site (JOINT/End) as
    the toe."""
    from app.analysis.sources import load_tracks

    text = CMU_WALK_PATH.read_text()
    for old in ("LeftFoot", "LeftToeBase", "RightFoot", "RightToeBase"):
        text = text.replace(f"JOINT {old}\n", f"JOINT ns:{old}\n")
    renamed = tmp_path / "walk.bvh"
    renamed.write_text(text)
    tracks, note = load_tracks(str(renamed), feet="L=ns:LeftFoot:ns:LeftToeBase,R=ns:RightFoot:ns:RightToeBase")
    assert "L=ns:LeftFoot:ns:LeftToeBase" in note
    tracks, note = load_tracks(str(CMU_WALK_PATH), feet="L=LeftFoot:LeftToeBase/End,R=RightFoot:RightToeBase/End")
    assert "LeftToeBase/End" in note and tracks.toe.shape[1] == 2
    ends = tracks.toe[:, 0] - tracks.heel[:, 0]
    assert np.median(np.linalg.norm(ends, axis=-1)) > 0.1  # the toe's tip, well ahead of the ankle


def _rescaled_bvh(source: Path, factor: float, out: Path) -> Path:
    """``source`` with every length multiplied by ``factor``: OFFSETs and position channels."""
    lines = source.read_text().splitlines()
    motion = next(i for i, line in enumerate(lines) if line.strip().upper() == "MOTION")
    channels: list[bool] = []  # per channel: a position?
    for line in lines[:motion]:
        words = line.split()
        if words and words[0] == "CHANNELS":
            channels += [w.lower().endswith("position") for w in words[2:]]
    text = []
    for i, line in enumerate(lines):
        words = line.split()
        if i < motion and words and words[0] == "OFFSET":
            line = "OFFSET " + " ".join(f"{float(w) * factor:.6f}" for w in words[1:])
        elif i > motion + 2 and len(words) == len(channels):
            line = " ".join(f"{float(w) * factor:.6f}" if pos else w for w, pos in zip(words, channels))
        text.append(line)
    out.write_text("\n".join(text) + "\n")
    return out


def test_inches_are_told_from_centimetres_by_the_stride(tmp_path: Path) -> None:
    """A person in inches has the hip height (~36 units) of a small animal in centimetres;
    the stride's period tells them apart. The dog in centimetres stays in centimetres."""
    for clip in (CMU_WALK_PATH, DATA / "human_run_cmu_09_01.bvh"):  # a walk and a run (strides 1.3 and 0.75 s)
        inches = _rescaled_bvh(clip, 0.056444 / 0.0254, tmp_path / f"{clip.stem}_in.bvh")
        tracks, note = load_tracks(str(inches))
        original, _ = load_tracks(str(clip))
        assert "units in" in note, clip.name
        assert tracks.hip_height == pytest.approx(original.hip_height, rel=1e-3)
    _, dog_note = load_tracks(str(DATA / "dog_walk_tencent_walkrun005_f120-419.bvh"))
    assert "units cm" in dog_note


@pytest.mark.parametrize("clip", ["human_walk_cmu_12_01.bvh", "human_run_cmu_09_01.bvh"])
def test_a_leading_rest_pose_changes_nothing(tmp_path: Path, clip: str) -> None:
    """The CMU clips open on a T-pose frame: with it dropped by hand the analysis is the same."""
    lines = (DATA / clip).read_text().splitlines()
    motion = next(i for i, line in enumerate(lines) if line.strip().upper() == "MOTION")
    frames = int(lines[motion + 1].split()[-1])
    trimmed = tmp_path / clip
    trimmed.write_text("\n".join(lines[:motion + 1] + [f"Frames: {frames - 1}", lines[motion + 2]]
                                 + lines[motion + 4:]) + "\n")
    full, cut = (analyze_tracks(load_tracks(str(p))[0]) for p in (DATA / clip, trimmed))
    assert full.gait_match == cut.gait_match
    assert cut.cycle_seconds == pytest.approx(full.cycle_seconds, rel=0.01)
    for a, b in zip(full.feet, cut.feet):
        assert b.duty_factor == pytest.approx(a.duty_factor, abs=0.01)
        assert cyclic_distance(b.phase, a.phase) < 0.01


def test_a_take_that_begins_standing_names_no_gait_while_it_stands() -> None:
    """A whole take often begins with the animal standing: a paw shuffled then is no
    stride, and the gaits over time start where it walks (this take's first second read
    "canter")."""
    report = analyze_tracks(load_tracks(str(DATA / "corpus" / "dog_stand_walk_tencent_walkrun005_f0-420.bvh"))[0])
    assert report.spans and report.spans[0].start >= 0.9 and report.spans[0].gait == "walk", report.spans
    assert report.gait_match == "walk"


def test_a_whole_take_that_starts_walks_and_stops_is_read() -> None:
    """CMU 131_01 whole (another converter's BVH: 3ds Max names LeftAnkle/LeftToe): ten
    seconds of standing, a stylised start, walking and a stop. Its stride is found from
    the feet's touchdowns ("no repeating step found in 10.38 s" when it came from the
    heights' autocorrelation, whose strongest repeat there was 4.7 s): a walk of a
    person's cycle, the feet half a cycle apart, and no gait named while it stands at
    the start."""
    tracks, notes = load_tracks(str(DATA / "corpus" / "human_start_walk_stop_cmu_131_01_max.bvh"))
    assert tracks.names == ("L", "R") and "cmu" in notes
    report = analyze_tracks(tracks)
    assert report.gait_match == "walk" and 1.0 <= report.cycle_seconds <= 1.4
    assert all(0.5 < foot.duty_factor < 0.85 for foot in report.feet), report.feet
    assert cyclic_distance(report.foot("R").phase, 0.5) <= 0.15  # (a stylised walk, the right foot a little late)
    assert report.spans and report.spans[0].start > 0.2 and all(span.gait == "walk" for span in report.spans)


def test_a_one_cycle_loop_is_analysed_as_played_round(tmp_path: Path) -> None:
    """A game's walk loop (one cycle of CMU 12_01, heel strike to heel strike: it ends on
    the pose it starts with) is read as played round three times, and says so: the same
    walk as the whole clip's (it gave "no repeating step found"). A single cycle that does
    not close is one line that says what would make it readable."""
    from cli_runner import gaitlab

    loop = analyze_tracks(load_tracks(str(DATA / "corpus" / "human_walk_loop_cmu_12_01_f101-251.bvh"))[0])
    whole = analyze_tracks(load_tracks(str(CMU_WALK_PATH))[0])
    assert any("one loop" in note for note in loop.notes)
    assert loop.gait_match == "walk" and loop.cycle_seconds == pytest.approx(whole.cycle_seconds, rel=0.03)
    for a, b in zip(loop.feet, whole.feet):
        assert abs(a.duty_factor - b.duty_factor) <= 0.03 and cyclic_distance(a.phase, b.phase) <= 0.03
    lines = CMU_WALK_PATH.read_text().splitlines()
    motion = lines.index("MOTION")
    cut = lines[:motion + 1] + ["Frames: 120", lines[motion + 2]] + lines[motion + 3 + 101:motion + 3 + 221]
    (tmp_path / "cut.bvh").write_text("\n".join(cut) + "\n")
    result = gaitlab("analyze", "cut.bvh", cwd=tmp_path)
    assert result.returncode == 2 and "end on the pose it starts with" in result.stderr
    assert len(result.stderr.strip().splitlines()) == 1


def _trotting_csv(fps: float) -> str:
    """Four feet trotting at 1 Hz, duty factor 0.6 exactly, planted while down, at ``fps``
    (touchdowns and lifts fall on frames at every rate tried)."""
    rows = ["time,LH_x,LH_y,LH_z,RH_x,RH_y,RH_z,LF_x,LF_y,LF_z,RF_x,RF_y,RF_z,body_x,body_y,body_z"]
    for t in np.arange(0.0, 5.0, 1.0 / fps):
        values = [f"{t:.5f}"]
        for x, z, phase in ((-0.3, 0.1, 0.0), (-0.3, -0.1, 0.5), (0.3, 0.1, 0.5), (0.3, -0.1, 0.0)):
            cycle, p = divmod(round(t * fps) / fps + phase, 1.0)
            lift = np.sin(np.pi * (p - 0.6) / 0.4) * 0.06 if p > 0.6 else 0.0
            values += [f"{x + 0.5 * (cycle + max(0.0, p - 0.6) / 0.4):.5f}", f"{lift:.5f}", f"{z:.5f}"]
        values += [f"{t:.5f}", "0.45", "0"]
        rows.append(",".join(values))
    return "\n".join(rows) + "\n"


@pytest.mark.parametrize("fps", [120.0, 30.0, 20.0])
def test_contacts_keep_their_length_at_low_frame_rates(tmp_path: Path, fps: float) -> None:
    """A planted frame next to a swinging one is slow on its own side: contacts lose no
    frame at either end (with central differences a trot of duty 0.60 read 0.53 at
    30 fps, 0.50 at 20)."""
    path = tmp_path / "trot.csv"
    path.write_text(_trotting_csv(fps))
    report = analyze_tracks(load_tracks(str(path))[0])
    assert all(abs(foot.duty_factor - 0.6) <= 0.01 for foot in report.feet), report.feet


def test_a_dog_trotting_in_place_reads_as_the_same_trot() -> None:
    """The corpus trot with its root held in place (a treadmill): its paws are "low"
    through most of the swing too, so the belt is read from their lowest frames; the same
    trot, duty factors within 0.04 (the reference foot was lost before)."""
    text = (DATA / "corpus" / "dog_trot_tencent_walkrun006_f480-660.bvh").read_text().splitlines()
    motion = text.index("MOTION")
    held = text[:motion + 3] + [" ".join(["0", r.split()[1], "0"] + r.split()[3:]) for r in text[motion + 3:]]
    moving = analyze_tracks(load_tracks(str(DATA / "corpus" / "dog_trot_tencent_walkrun006_f480-660.bvh"))[0])
    import tempfile

    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "in_place.bvh"
        path.write_text("\n".join(held) + "\n")
        still = analyze_tracks(load_tracks(str(path))[0])
    assert still.gait_match == moving.gait_match == "trot" and still.speed < 0.05
    for a, b in zip(still.feet, moving.feet):
        assert abs(a.duty_factor - b.duty_factor) <= 0.04 and cyclic_distance(a.phase, b.phase) <= 0.04


def test_a_clip_that_stands_still_says_so_about_itself(tmp_path: Path) -> None:
    """A clip that never moves "closes" like a loop; its error still names its own length,
    not the three plays tried."""
    from cli_runner import gaitlab

    text = CMU_WALK_PATH.read_text().splitlines()
    motion = text.index("MOTION")
    still = text[:motion + 1] + ["Frames: 240", text[motion + 2]] + [text[motion + 3 + 60]] * 240
    (tmp_path / "still.bvh").write_text("\n".join(still) + "\n")
    result = gaitlab("analyze", "still.bvh", cwd=tmp_path)
    assert result.returncode == 2 and len(result.stderr.strip().splitlines()) == 1
    assert "1.99 s" in result.stderr or "2.00 s" in result.stderr, result.stderr


def test_an_in_place_export_of_one_cycle_is_a_loop(tmp_path: Path) -> None:
    """``export horse --in-place --cycles 1`` (no closing frame: the loop stops a frame
    short of its start) is read as a loop."""
    from cli_runner import gaitlab

    assert gaitlab("export", "horse", "--in-place", "--cycles", "1", "-o", "h.bvh", "-q", cwd=tmp_path).returncode == 0
    result = gaitlab("analyze", "h.bvh", cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    assert "one loop" in result.stdout and "walk" in result.stdout


@pytest.mark.parametrize(("clip", "running"), [("human_walk_cmu_12_01", False), ("human_run_cmu_09_01", True),
                                               ("corpus/human_jog_hdm05_dg_06-03_03", True),
                                               ("corpus/human_jog_circle_hdm05_mm_011", True)])
def test_people_who_run_are_told_from_people_who_walk(clip: str, running: bool) -> None:
    """A runner's body is lowest mid-stance, a walker's highest: a slow jog (HDM05, about
    2 m/s) read as a walk, duty 0.52, when a runner's feet were judged as a walker's."""
    from app.analysis.events import _signals, runs_like_a_runner, stride_period

    tracks = load_tracks(str(DATA / f"{clip}.bvh"))[0]
    frames = int(round(stride_period(tracks) * tracks.fps))
    assert runs_like_a_runner(tracks, _signals(tracks, frames), frames) is running
    report = analyze_tracks(tracks)
    assert report.gait_match == ("run" if running else "walk")
    assert all((f.duty_factor < 0.45) is running for f in report.feet), [f.duty_factor for f in report.feet]
