"""gaitlab analyze end to end: outputs, and every kind of bad input (one line, exit 2)."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from cli_runner import gaitlab
from PIL import Image

DATA = Path(__file__).parent / "data"
DOG_WALK = DATA / "dog_walk_tencent_walkrun005_f120-419.bvh"


def test_table_for_a_creature(tmp_path: Path) -> None:
    out = gaitlab("analyze", "dog", "--gait", "trot", cwd=tmp_path)
    assert out.returncode == 0, out.stderr
    assert "trot (matches)" in out.stdout and "asked duty" in out.stdout and "LH" in out.stdout


def test_json_csv_and_plot(tmp_path: Path) -> None:
    out = gaitlab("analyze", str(DOG_WALK), "--json", "--csv", "events.csv", "--plot", "plot.png", cwd=tmp_path)
    assert out.returncode == 0, out.stderr
    doc = json.loads(out.stdout)
    assert doc["gait_match"] == "walk" and doc["gait"] is None and len(doc["feet"]) == 4  # (see test_analysis_real)
    rows = (tmp_path / "events.csv").read_text().splitlines()
    assert rows[0] == "foot,kind,time" and len(rows) > 40
    image = np.asarray(Image.open(tmp_path / "plot.png").convert("RGB"))
    assert image.shape[0] > 400 and image.shape[1] > 800
    assert sorted(p.name for p in tmp_path.iterdir()) == ["events.csv", "plot.png"]


def test_csv_and_plot_are_written_both_or_neither(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """When the plot cannot be written (a full disk, say), the CSV given with it is not
    written either, and an earlier file of that name is left as it was."""
    import errno

    from app.analysis import plot

    def full_disk(report, path) -> None:
        Path(path).write_bytes(b"half a png")
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(plot, "save_plot", full_disk)
    (tmp_path / "events.csv").write_text("yesterday's events\n")
    out = gaitlab("analyze", str(DOG_WALK), "--csv", "events.csv", "--plot", "plot.png", cwd=tmp_path)
    assert out.returncode == 2 and len(out.stderr.strip().splitlines()) == 1, out.stderr
    assert "plot.png" in out.stderr and "No space left" in out.stderr
    assert (tmp_path / "events.csv").read_text() == "yesterday's events\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["events.csv"]


def test_speed_ramp_reports_gait_per_time_span(tmp_path: Path) -> None:
    """Issue 8: from a walk to a gallop, the named walk, trot and gallop spans cover at
    least 80% of the ramp (the switches are short; the clip's ends are measured too)."""
    out = gaitlab("analyze", "dog", "--speed", "0.5:9", "--seconds", "12", "--json", cwd=tmp_path)
    assert out.returncode == 0, out.stderr
    spans = json.loads(out.stdout)["spans"]
    gaits = [s["gait"] for s in spans]
    assert gaits[0] == "walk" and gaits[-1] == "gallop" and "trot" in gaits
    named = sum(s["end"] - s["start"] for s in spans if s["gait"] in ("walk", "trot", "gallop"))
    assert named >= 0.8 * 12.0, spans
    assert all(s["end"] - s["start"] < 0.5 for s in spans if s["gait"] == "transition"), spans


def test_csv_input(tmp_path: Path) -> None:
    from app import build_rig, load_creature
    from app.analysis import tracks_from_motion
    from app.kinematics.clip import clip_motion

    motion, _ = clip_motion(build_rig(load_creature("cat").with_overrides({"gait.preset": "pace"})), 400.0,
                            cycles=4.0)
    tracks = tracks_from_motion(motion)
    header = ["time"] + [f"{n}_{a}" for n in tracks.names for a in "xyz"] + \
        [f"{n}_toe_{a}" for n in tracks.names for a in "xyz"]
    rows = np.column_stack([tracks.times, tracks.heel.reshape(len(tracks.times), -1),
                            tracks.toe.reshape(len(tracks.times), -1)])
    path = tmp_path / "cat.csv"
    path.write_text(",".join(header) + "\n" + "\n".join(",".join(f"{v:.6f}" for v in row) for row in rows))
    out = gaitlab("analyze", str(path), "--json", cwd=tmp_path)
    assert out.returncode == 0, out.stderr
    assert json.loads(out.stdout)["gait_match"] == "pace"
    # Saved by a spreadsheet, with a byte-order mark before "time": the same clip.
    marked = tmp_path / "marked.csv"
    marked.write_bytes(b"\xef\xbb\xbf" + path.read_bytes())
    out = gaitlab("analyze", str(marked), "--json", cwd=tmp_path)
    assert out.returncode == 0, out.stderr
    assert json.loads(out.stdout)["gait_match"] == "pace"


def write(tmp_path: Path, name: str, text: str) -> Path:
    path = tmp_path / name
    path.write_text(text)
    return path


def bvh_lines() -> list[str]:
    return DOG_WALK.read_text().splitlines()


NO_FEET_BVH = """HIERARCHY
ROOT Hips
{
  OFFSET 0 0 0
  CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation
  JOINT Spine
  {
    OFFSET 0 10 0
    CHANNELS 3 Zrotation Xrotation Yrotation
    End Site
    {
      OFFSET 0 10 0
    }
  }
}
MOTION
Frames: 2
Frame Time: 0.01
0 90 0 0 0 0 0 0 0
0 90 1 0 0 0 0 0 0
"""


def bad_cases(tmp_path: Path) -> dict[str, tuple[list[str], str]]:
    lines = bvh_lines()
    motion = lines.index("MOTION")
    truncated = write(tmp_path, "truncated.bvh", "\n".join(lines[:motion + 50]))
    corrupt = lines.copy()
    corrupt[motion + 10] = corrupt[motion + 10].replace(corrupt[motion + 10].split()[3], "abc", 1)
    malformed = write(tmp_path, "malformed.bvh", "\n".join(corrupt))
    typo = lines.copy()
    typo[3] = typo[3].replace("OFFSET", "OFSET")
    hierarchy = write(tmp_path, "hierarchy.bvh", "\n".join(typo))
    short = write(tmp_path, "short.bvh", "\n".join(lines[:motion + 1] + ["Frames: 20", lines[motion + 2]]
                                                   + lines[motion + 3:motion + 23]))
    no_feet = write(tmp_path, "nofeet.bvh", NO_FEET_BVH)
    csv_missing = write(tmp_path, "missing.csv", "time,LH_x,LH_y\n0,0,0\n0.1,0,0\n")
    csv_bad = write(tmp_path, "bad.csv", "time,LH_x,LH_y,LH_z\n0,0,0,0\n0.1,0,x,0\n")
    csv_twice = write(tmp_path, "twice.csv", "time,LH_x,LH_y,LH_z,LH_y\n0,0,0,0,1\n0.1,0,0,0,1\n")
    return {
        "no feet": (["analyze", str(no_feet)], "no feet recognised among the joints (Hips, Spine)"),
        "truncated bvh": (["analyze", str(truncated)], f"{truncated}:{motion + 50}: truncated BVH"),
        "malformed bvh value": (["analyze", str(malformed)], f"{malformed}:{motion + 11}: malformed BVH: value 4"),
        "malformed hierarchy": (["analyze", str(hierarchy)], f"{hierarchy}:4: malformed BVH: expected 'OFFSET'"),
        "clip shorter than a step": (["analyze", str(short)], "at least one full stride"),
        "csv missing columns": (["analyze", str(csv_missing)], "missing columns LH_z"),
        "csv not a number": (["analyze", str(csv_bad)], f"{csv_bad}:3: malformed CSV: column 'LH_y' value 'x'"),
        "csv column twice": (["analyze", str(csv_twice)], f"{csv_twice}:1: column 'LH_y' appears 2 times"),
        "unknown feet joint": (["analyze", str(DOG_WALK), "--feet", "LH=b_LeftAnkel"], "did you mean 'b_LeftAnkle'"),
        "bad feet syntax": (["analyze", str(DOG_WALK), "--feet", "LH"], "expected NAME=ANKLE[:TOE]"),
        "gait for a file": (["analyze", str(DOG_WALK), "--gait", "trot"], "for creatures"),
        "units for a creature": (["analyze", "dog", "--units", "cm"], "for BVH or CSV files"),
        "plot suffix": (["analyze", "dog", "--plot", "out.gif"], "use a .png file name"),
        "missing file": (["analyze", "nothere.bvh"], "no such file"),
        "unknown file type": (["analyze", str(write(tmp_path, "x.fbx", ""))], "unknown file type '.fbx'"),
        "bad speed": (["analyze", "dog", "--speed", "fast"], "expected a speed in m/s"),
    }


CASE_NAMES = ["no feet", "truncated bvh", "malformed bvh value", "malformed hierarchy", "clip shorter than a step",
              "csv missing columns", "csv not a number", "csv column twice", "unknown feet joint", "bad feet syntax",
              "gait for a file",
              "units for a creature", "plot suffix", "missing file", "unknown file type", "bad speed"]


@pytest.mark.parametrize("case", CASE_NAMES)
def test_bad_input(tmp_path: Path, case: str) -> None:
    inputs = tmp_path / "inputs"
    inputs.mkdir()
    args, expected = bad_cases(inputs)[case]
    work = tmp_path / "work"
    work.mkdir()
    out = gaitlab(*args, cwd=work)
    assert out.returncode == 2, (out.stdout, out.stderr)
    assert "Traceback" not in out.stderr
    line, = out.stderr.strip().splitlines()
    assert expected in line, line
    assert list(work.iterdir()) == []


def test_analyze_a_single_stride_clip_prints_the_note(tmp_path) -> None:
    data = Path(__file__).parent / "data" / "human_run_cmu_09_01.bvh"
    out = gaitlab("analyze", str(data), cwd=tmp_path)
    assert out.returncode == 0, out.stderr
    assert "note         the clip holds a single stride" in out.stdout
    assert "gait         run" in out.stdout


# -- a folder of clips ---------------------------------------------------------------------


def _clip_folder(tmp_path: Path, corrupt: bool) -> Path:
    folder = tmp_path / "clips"
    (folder / "dogs").mkdir(parents=True)
    for clip in DATA.glob("human_*.bvh"):
        (folder / clip.name).write_bytes(clip.read_bytes())
    for clip in DATA.glob("dog_*.bvh"):
        (folder / "dogs" / clip.name).write_bytes(clip.read_bytes())
    (folder / "notes.txt").write_text("not a clip")  # other files are left alone
    if corrupt:
        (folder / "dogs" / "broken.bvh").write_text("HIERARCHY\nROOT Hips\n{\n")
    return folder


def test_a_folder_of_clips_is_a_row_each_in_parallel(tmp_path: Path) -> None:
    """``analyze DIR --csv --jobs 2``: one row per clip in the folder's sorted order, the
    same numbers as each clip analysed alone; a corrupt clip is a row with its error, the
    rest are analysed, and the exit status says not every clip was read."""
    import csv

    folder = _clip_folder(tmp_path, corrupt=True)
    table = tmp_path / "table.csv"
    result = gaitlab("analyze", folder, "--csv", table, "--jobs", "2")
    assert result.returncode == 2
    assert result.stderr.strip().splitlines()[-1].startswith("gaitlab analyze: 1 of 5 clips could not be analysed")
    rows = list(csv.DictReader(table.open()))
    assert [Path(r["source"]).name for r in rows] == ["broken.bvh", "dog_trot_tencent_walkrun001_f960-1156.bvh",
                                                      "dog_walk_tencent_walkrun005_f120-419.bvh",
                                                      "human_run_cmu_09_01.bvh", "human_walk_cmu_12_01.bvh"]
    broken, *good = rows
    assert "truncated BVH" in broken["error"] and broken["gait"] == "" and broken["cycle_s"] == ""
    for row in good:
        assert row["error"] == ""
        alone = json.loads(gaitlab("analyze", row["source"], "--json").stdout)
        assert row["gait"] == alone["gait_match"]
        assert float(row["cycle_s"]) == pytest.approx(alone["cycle_seconds"], abs=1e-4)
        for foot in alone["feet"]:
            assert 0.0 < float(row[f"duty_{foot['name']}"]) < 1.0
            assert float(row[f"duty_{foot['name']}"]) == pytest.approx(foot["duty_factor"], abs=1e-4)
            assert float(row[f"phase_{foot['name']}"]) == pytest.approx(foot["phase"], abs=1e-4)
    assert "walk" in result.stdout and "error: " in result.stdout  # the terminal's table


def test_a_folder_of_good_clips_exits_0(tmp_path: Path) -> None:
    """... and again with its own table and an events CSV written into the folder: analyze's
    own CSVs are no clips."""
    folder = _clip_folder(tmp_path, corrupt=False)
    table = folder / "table.csv"
    for _ in range(2):
        result = gaitlab("analyze", folder, "--csv", table, "--jobs", "1")
        assert result.returncode == 0, result.stderr
        assert "wrote" in result.stderr and len(table.read_text().splitlines()) == 5
    gaitlab("analyze", DATA / "human_walk_cmu_12_01.bvh", "--csv", folder / "events.csv")
    assert gaitlab("analyze", folder, "--csv", table, "--jobs", "1").returncode == 0


@pytest.mark.parametrize("case", ["empty", "jobs0", "plot", "jobs-file", "creature-option"])
def test_a_folder_s_bad_input_is_one_line(tmp_path: Path, case: str) -> None:
    empty = tmp_path / "empty"
    empty.mkdir()
    folder = _clip_folder(tmp_path, corrupt=False)
    argv = {"empty": [empty],
            "jobs0": [folder, "--jobs", "0"],
            "plot": [folder, "--plot", tmp_path / "p.png"],
            "jobs-file": [DATA / "human_walk_cmu_12_01.bvh", "--jobs", "2"],
            "creature-option": [folder, "--gait", "trot"]}[case]
    result = gaitlab("analyze", *argv, "--csv", tmp_path / "t.csv")
    assert result.returncode == 2
    assert len(result.stderr.strip().splitlines()) == 1 and "Traceback" not in result.stderr
    assert not (tmp_path / "t.csv").exists()  # nothing written
