"""The gaitlab command end to end, through a subprocess: outputs and every bad input."""

from __future__ import annotations

import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from cli_runner import gaitlab, gaitlab_process
from PIL import Image

from app.output import gif_durations

DOG = Path(__file__).parents[1] / "creatures" / "dog.toml"


def test_console_script_is_installed() -> None:
    script = Path(sys.executable).with_name("gaitlab")
    assert script.exists() or shutil.which("gaitlab") is not None
    out = subprocess.run([str(script) if script.exists() else "gaitlab", "--version"], capture_output=True, text=True)
    assert out.returncode == 0 and out.stdout.startswith("gaitlab ")


def test_help_teaches() -> None:
    out = gaitlab("render", "--help")
    assert out.returncode == 0
    for word in ("--gait", "--seconds", "--cycles", "--fps", "--size", "--camera", "--time", "--set", "examples:"):
        assert word in out.stdout


def test_creatures_lists_presets_and_gaits() -> None:
    out = gaitlab("creatures", "--keys")
    assert out.returncode == 0
    for word in ("bear", "cat", "deer", "dog", "horse", "walk", "trot", "pace", "bound", "pronk", "gallop",
                 "plantigrade", "digitigrade", "unguligrade", "legs.hind.femur", "gait.duty_factor"):
        assert word in out.stdout


@pytest.mark.gl
def test_gif_frames_duration_and_loop(tmp_path: Path) -> None:
    out = gaitlab("render", "dog", "-o", "walk.gif", "--seconds", "1.2", "--fps", "15", "--size", "96x72",
                  "--msaa", "0", cwd=tmp_path)
    assert out.returncode == 0, out.stderr
    with Image.open(tmp_path / "walk.gif") as gif:
        assert gif.n_frames == 18  # seconds x fps
        assert gif.info["loop"] == 0
        durations = []
        for i in range(gif.n_frames):
            gif.seek(i)
            durations.append(gif.info["duration"])
    assert all(abs(d - 1000 / 15) <= 10 for d in durations)
    assert abs(sum(durations) - 1200) <= 10
    assert list(tmp_path.iterdir()) == [tmp_path / "walk.gif"]


def test_gif_durations_are_exact_to_gif_resolution() -> None:
    assert gif_durations(4, 25) == [40, 40, 40, 40]
    d = gif_durations(30, 30)
    assert set(d) <= {30, 40} and sum(d) == 1000


@pytest.mark.gl
def test_default_render_is_a_looping_gif_of_the_dog(tmp_path: Path) -> None:
    out = gaitlab("render", "--size", "96x72", cwd=tmp_path)
    assert out.returncode == 0, out.stderr
    with Image.open(tmp_path / "dog.gif") as gif:
        assert gif.info["loop"] == 0 and gif.n_frames > 10
    assert "2.00 cycles of dog walk" in out.stdout


@pytest.mark.gl
def test_png_at_time_and_same_pixels_twice(tmp_path: Path) -> None:
    for name in ("a.png", "b.png"):
        out = gaitlab("render", "horse", "--gait", "trot", "-o", name, "--time", "0.37", "--size", "120x90",
                      "--camera", "side", cwd=tmp_path)
        assert out.returncode == 0, out.stderr
    a, b = (np.asarray(Image.open(tmp_path / n)) for n in ("a.png", "b.png"))
    assert a.shape == (90, 120, 3)
    assert np.array_equal(a, b)


@pytest.mark.gl
def test_mp4_is_h264_with_the_right_frame_count(tmp_path: Path) -> None:
    import imageio_ffmpeg

    out = gaitlab("render", "cat", "-o", "cat.mp4", "--seconds", "1", "--fps", "20", "--size", "96x72",
                  cwd=tmp_path)
    assert out.returncode == 0, out.stderr
    frames, seconds = imageio_ffmpeg.count_frames_and_secs(str(tmp_path / "cat.mp4"))
    assert frames == 20 and seconds == pytest.approx(1.0, abs=0.06)
    reader = imageio_ffmpeg.read_frames(str(tmp_path / "cat.mp4"))
    meta = next(reader)
    assert meta["codec"] == "h264" and tuple(meta["size"]) == (96, 72)
    reader.close()


@pytest.mark.gl
def test_set_and_creature_file_path(tmp_path: Path) -> None:
    out = gaitlab("render", str(DOG), "-o", "x.png", "--size", "64x48", "--set", "gait.duty_factor=0.8",
                  "--set", "legs.hind.femur=0.25", cwd=tmp_path)
    assert out.returncode == 0, out.stderr
    assert (tmp_path / "x.png").exists()


def write_dog(tmp_path: Path, old: str, new: str) -> str:
    text = DOG.read_text()
    assert old in text
    path = tmp_path / "custom.toml"
    path.write_text(text.replace(old, new))
    return str(path)


BAD_INPUTS = {
    "unknown creature": (["render", "dgo", "-o", "x.gif"],
                         "presets are: ant, bear, bird, cat, centipede, deer, dog, horse, human, spider, theropod"),
    "unknown gait": (["render", "dog", "--gait", "trto", "-o", "x.gif"], "did you mean 'trot'"),
    "set unknown key": (["render", "dog", "--set", "legs.hind.femr=0.3", "-o", "x.gif"],
                        "did you mean 'legs.hind.femur'"),
    "set not a number": (["render", "dog", "--set", "gait.duty_factor=abc", "-o", "x.gif"], "expected a number"),
    "set duty too high": (["render", "dog", "--set", "gait.duty_factor=0.97", "-o", "x.gif"], "(0.05, 0.95)"),
    "set negative length": (["render", "dog", "--set", "body.length=-1", "-o", "x.gif"], "body.length"),
    "set nan length": (["render", "dog", "--set", "legs.fore.tibia=nan", "-o", "x.gif"], "not a finite number"),
    "set inf length": (["render", "dog", "--set", "legs.fore.tibia=inf", "-o", "x.gif"], "not a finite number"),
    "set zero length": (["render", "dog", "--set", "legs.fore.femur=0", "-o", "x.gif"], "legs.fore.femur"),
    "bad suffix": (["render", "dog", "-o", "x.webm"], "use .png (one frame), .gif or .mp4"),
    "missing folder": (["render", "dog", "-o", "nope/x.gif"], "does not exist"),
    "unwritable folder": (["render", "dog", "-o", "/sys/x.gif"], "not writable"),
    "size zero": (["render", "dog", "--size", "0x0", "-o", "x.gif"], "between 1 and 8192"),
    "size too big": (["render", "dog", "--size", "9000x9000", "-o", "x.gif"], "between 1 and 8192"),
    "size garbage": (["render", "dog", "--size", "big", "-o", "x.gif"], "WIDTHxHEIGHT"),
    "fps zero": (["render", "dog", "--fps", "0", "-o", "x.gif"], "at least 1"),
    "seconds and cycles": (["render", "dog", "--seconds", "1", "--cycles", "2", "-o", "x.gif"], "not allowed with"),
    "odd mp4 size": (["render", "dog", "--size", "95x72", "-o", "x.mp4"], "even width and height"),
    "unknown antialias": (["render", "dog", "--antialias", "ssaa", "-o", "x.gif"], "choose from 'fxaa', 'msaa', 'off'"),
    "msaa with fxaa": (["render", "dog", "--antialias", "fxaa", "--msaa", "4", "-o", "x.gif"],
                       "--msaa 4 asks for multisampling but --antialias is fxaa"),
}


@pytest.mark.parametrize("case", list(BAD_INPUTS))
def test_bad_input_is_one_line_exit_2_and_leaves_nothing(tmp_path: Path, case: str) -> None:
    args, expected = BAD_INPUTS[case]
    out = gaitlab(*args, cwd=tmp_path)
    assert out.returncode == 2
    lines = out.stderr.strip().splitlines()
    assert len(lines) == 1, out.stderr
    assert expected in lines[0]
    assert "Traceback" not in out.stderr + out.stdout
    assert list(tmp_path.iterdir()) == []


FILE_ERRORS = {
    "syntax error": ("femur = 0.21", "femur = = 0.21", "TOML syntax error"),
    "unknown key": ("femur = 0.21", "femr = 0.21", "did you mean 'legs.hind.femur'"),
    "negative length": ("tibia = 0.23", "tibia = -0.23", "legs.hind.tibia = -0.23"),
    "nan length": ("tibia = 0.23", "tibia = nan", "legs.hind.tibia = nan"),
    "zero length": ("tibia = 0.23", "tibia = 0.0", "legs.hind.tibia = 0"),
    "duty out of range": ('preset = "walk"', 'preset = "walk"\nduty_factor = 0.02', "gait.duty_factor"),
    "unknown gait": ('preset = "walk"', 'preset = "slither"', "gait.preset = 'slither'"),
}


@pytest.mark.parametrize("case", list(FILE_ERRORS))
def test_bad_creature_file(tmp_path: Path, case: str) -> None:
    old, new, expected = FILE_ERRORS[case]
    path = write_dog(tmp_path, old, new)
    out_dir = tmp_path / "out"
    out_dir.mkdir()
    out = gaitlab("render", path, "-o", "x.gif", cwd=out_dir)
    assert out.returncode == 2 and "Traceback" not in out.stderr
    line, = out.stderr.strip().splitlines()
    assert path in line and expected in line
    assert list(out_dir.iterdir()) == []


def test_missing_egl_names_the_package_to_install(tmp_path: Path) -> None:
    out = gaitlab_process("render", "dog", "-o", "x.png", cwd=tmp_path,
                          env={"__EGL_VENDOR_LIBRARY_FILENAMES": str(tmp_path / "none.json")})
    assert out.returncode == 2 and "Traceback" not in out.stderr
    line, = out.stderr.strip().splitlines()
    assert "EGL" in line and "apt-get install libegl1 libgl1-mesa-dri" in line
    assert list(tmp_path.iterdir()) == []


def test_existing_output_survives_a_failed_render(tmp_path: Path) -> None:
    keep = tmp_path / "x.gif"
    keep.write_bytes(b"previous")
    out = gaitlab("render", "dog", "--set", "gait.duty_factor=2", "-o", "x.gif", cwd=tmp_path)
    assert out.returncode == 2
    assert keep.read_bytes() == b"previous"


def test_view_panels_names_every_sidebar_panel() -> None:
    """``gaitlab view --panels`` takes each sidebar panel by name and nothing else."""
    import argparse

    from app.choices import PANEL_TITLES
    from app.cli.options import panels
    from app.ui.panels import PANELS

    assert tuple(title for title, _, _ in PANELS) == PANEL_TITLES
    assert panels("plots,key-poses,Path") == ("Plots", "Key poses", "Path")
    with pytest.raises(argparse.ArgumentTypeError, match="expected a comma-separated list of creature"):
        panels("plot")
