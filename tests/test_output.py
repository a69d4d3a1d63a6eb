"""The writers: streamed GIFs (palette, differencing, gifsicle), streamed MP4s, atomic
files, and runs interrupted by SIGINT / SIGTERM / SIGKILL leaving nothing behind."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from app.errors import OutputError
from app.output import AtomicPath, GifWriter, Mp4Writer, gif_durations, remove_stale_partials, stale_partials
from app.output import files as files_module
from app.output import gif as gif_module


def moving_frames(count: int, size: tuple[int, int] = (64, 48)) -> list[np.ndarray]:
    """A gradient background with a square that moves: like a clip, a few colours change."""
    w, h = size
    base = np.zeros((h, w, 3), np.uint8)
    base[..., 0] = np.linspace(40, 220, w, dtype=np.uint8)[None, :]
    base[..., 2] = np.linspace(200, 60, h, dtype=np.uint8)[:, None]
    frames = []
    for i in range(count):
        f = base.copy()
        x = (3 * i) % (w - 10)
        f[10:20, x:x + 10] = (250, 240, 30)
        frames.append(f)
    return frames


def decoded(path: Path) -> tuple[list[np.ndarray], list[int]]:
    frames, durations = [], []
    with Image.open(path) as gif:
        for i in range(gif.n_frames):
            gif.seek(i)
            frames.append(np.asarray(gif.convert("RGB")))
            durations.append(gif.info["duration"])
    return frames, durations


def palette_mapped(frames: list[np.ndarray], samples: list[np.ndarray], colors: int) -> list[np.ndarray]:
    palette = gif_module.choose_palette(samples, colors)
    return [np.asarray(Image.fromarray(f).quantize(palette=palette, dither=Image.Dither.NONE).convert("RGB"))
            for f in frames]


@pytest.mark.parametrize("gifsicle", [True, False])
def test_best_gif_decodes_to_the_palette_mapped_frames(tmp_path: Path, monkeypatch, gifsicle: bool) -> None:
    if gifsicle and gif_module.gifsicle_path() is None:
        pytest.skip("gifsicle is not installed")
    if not gifsicle:
        monkeypatch.setattr(gif_module, "gifsicle_path", lambda: None)
    frames = moving_frames(12)
    samples = [frames[0], frames[4], frames[8]]
    writer = GifWriter(tmp_path / "a.gif", (64, 48), 25.0, samples, "best", frame_count=12)
    for f in frames:
        writer.add(f)
    writer.close(ok=True)
    got, durations = decoded(tmp_path / "a.gif")
    expected = palette_mapped(frames, samples, 255)
    assert len(got) == 12
    for g, e in zip(got, expected):  # lossless: differencing and transparency change no pixel
        assert np.array_equal(g, e)
    assert durations == gif_durations(12, 25.0)
    assert bool(writer.notes) != gifsicle  # a note says gifsicle is missing, only when it is
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.gif"]


def test_smaller_qualities_stay_close_and_shrink(tmp_path: Path) -> None:
    if gif_module.gifsicle_path() is None:
        pytest.skip("gifsicle is not installed")
    frames = moving_frames(20, (160, 120))
    sizes = {}
    for quality in ("best", "good", "small"):
        writer = GifWriter(tmp_path / f"{quality}.gif", (160, 120), 25.0, frames[::7], quality, frame_count=20)
        for f in frames:
            writer.add(f)
        writer.close(ok=True)
        sizes[quality] = (tmp_path / f"{quality}.gif").stat().st_size
        got, _ = decoded(tmp_path / f"{quality}.gif")
        error = np.mean([np.abs(g.astype(int) - f).mean() for g, f in zip(got, frames)])
        assert error < {"best": 3, "good": 6, "small": 10}[quality]
    assert sizes["small"] < sizes["good"] < sizes["best"]


def test_unchanged_frames_still_take_their_time(tmp_path: Path) -> None:
    frames = [moving_frames(1)[0]] * 5
    writer = GifWriter(tmp_path / "still.gif", (64, 48), 10.0, frames[:1], "best", frame_count=5)
    for f in frames:
        writer.add(f)
    writer.close(ok=True)
    got, durations = decoded(tmp_path / "still.gif")
    assert sum(durations) == 500  # gifsicle may merge the repeats into one frame of 500 ms
    assert all(np.array_equal(g, got[0]) for g in got)


@pytest.mark.parametrize("count", [1, 199, 200, 201, 450])
def test_a_gif_optimised_in_parts_is_whole_and_exact(tmp_path: Path, monkeypatch, count: int) -> None:
    """Long GIFs are optimised by gifsicle part by part while rendering goes on, then
    joined: every frame and delay survives the parts' seams."""
    if gif_module.gifsicle_path() is None:
        pytest.skip("gifsicle is not installed")
    frames = moving_frames(count, (32, 24))
    samples = frames[:1]
    writer = GifWriter(tmp_path / "long.gif", (32, 24), 30.0, samples, "best", frame_count=count)
    for f in frames:
        writer.add(f)
    writer.close(ok=True)
    got, durations = decoded(tmp_path / "long.gif")
    expected = palette_mapped(frames, samples, 255)
    assert sum(durations) == sum(gif_durations(count, 30.0))
    if len(got) == count:  # gifsicle may merge repeated frames (this clip has none)
        assert all(np.array_equal(g, e) for g, e in zip(got, expected))
    else:
        pytest.fail(f"{len(got)} frames decoded, {count} written")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["long.gif"]


def test_cancelling_while_gifsicle_works_is_quick_and_clean(tmp_path: Path, monkeypatch) -> None:
    """A slow gifsicle (here one that never finishes) neither delays a cancel nor leaves
    processes or files behind; the writer thread never waits for it either."""
    import time as clock

    fake = tmp_path / "bin" / "gifsicle"
    fake.parent.mkdir()
    fake.write_text("#!/bin/sh\nexec sleep 60\n")
    fake.chmod(0o755)
    monkeypatch.setattr(gif_module, "gifsicle_path", lambda: str(fake))
    out = tmp_path / "out"
    out.mkdir()
    frames = moving_frames(1000, (32, 24))
    writer = GifWriter(out / "a.gif", (32, 24), 30.0, frames[:1], "good", frame_count=1000)
    t0 = clock.monotonic()
    for f in frames:  # five parts: gifsicle "runs" on two, three wait; adding frames never blocks on it
        writer.add(f)
    assert clock.monotonic() - t0 < 20
    processes = [c.process for c in writer._chunks if c.process is not None]
    assert len(processes) == 2
    t0 = clock.monotonic()
    writer.close(ok=False)
    assert clock.monotonic() - t0 < 2.0
    assert all(p.poll() is not None for p in processes)
    assert list(out.iterdir()) == []


def test_cancelled_writers_leave_nothing(tmp_path: Path) -> None:
    frames = moving_frames(4)
    gif = GifWriter(tmp_path / "a.gif", (64, 48), 25.0, frames[:1])
    mp4 = Mp4Writer(tmp_path / "a.mp4", (64, 48), 25.0)
    for f in frames:
        gif.add(f)
        mp4.add(f)
    gif.close(ok=False)
    mp4.close(ok=False)
    assert list(tmp_path.iterdir()) == []


def test_a_gif_of_no_frames_is_refused_and_not_written(tmp_path: Path) -> None:
    writer = GifWriter(tmp_path / "a.gif", (64, 48), 25.0, moving_frames(1))
    with pytest.raises(OutputError, match="no frames"):
        writer.close(ok=True)
    assert list(tmp_path.iterdir()) == []


def test_mp4_streams_every_frame(tmp_path: Path) -> None:
    import imageio_ffmpeg

    writer = Mp4Writer(tmp_path / "a.mp4", (64, 48), 20.0, crf=10)
    frames = moving_frames(30)
    for f in frames:
        writer.add(f)
    writer.close(ok=True)
    got = list(imageio_ffmpeg.read_frames(str(tmp_path / "a.mp4")))[1:]
    assert len(got) == 30
    first = np.frombuffer(got[5], np.uint8).reshape(48, 64, 3)
    assert np.abs(first.astype(int) - frames[5]).mean() < 4
    with pytest.raises(OutputError, match="crf 60"):
        Mp4Writer(tmp_path / "b.mp4", (64, 48), 20.0, crf=60)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.mp4"]


def test_a_frame_of_the_wrong_size_is_refused(tmp_path: Path) -> None:
    writer = Mp4Writer(tmp_path / "a.mp4", (64, 48), 20.0)
    with pytest.raises(OutputError, match="frame is 32x48"):
        writer.add(np.zeros((48, 32, 3), np.uint8))
    writer.close(ok=False)
    assert list(tmp_path.iterdir()) == []


def test_partials_of_dead_processes_are_cleaned_and_live_ones_kept(tmp_path: Path) -> None:
    dead = subprocess.Popen([sys.executable, "-c", "pass"])
    dead.wait()
    host = files_module._host()
    stale = tmp_path / f".walk.{host}_{dead.pid}-abc123.partial.gif"
    live = tmp_path / f".walk.{host}_{os.getppid()}-def456.partial.gif"  # our parent is running
    other = tmp_path / f".other.{host}_{dead.pid}-abc123.partial.gif"  # another output's: not ours to touch
    remote = tmp_path / f".walk.elsewhere_{dead.pid}-abc123.partial.gif"  # another machine's writer
    for p in (stale, live, other, remote):
        p.write_bytes(b"GIF89a")
    assert stale_partials(tmp_path / "walk.gif") == [stale]
    with AtomicPath(tmp_path / "walk.gif") as out:
        out.tmp.write_bytes(b"x")
    assert not stale.exists() and live.exists() and other.exists() and remote.exists()
    assert remove_stale_partials(tmp_path / "other.gif") == 1


def leftovers(folder: Path) -> list[str]:
    return sorted(p.name for p in folder.iterdir() if ".partial" in p.name)


def _default_sigint() -> None:
    # A test run started in the background by a shell ignores SIGINT, and so would the
    # render it starts (Python installs no Ctrl-C handler then): give it the default.
    signal.signal(signal.SIGINT, signal.SIG_DFL)


def start_render(folder: Path, output: str) -> subprocess.Popen:
    return subprocess.Popen([sys.executable, "-m", "app", "render", "dog", "--seconds", "60", "--size", "160x120",
                             "--msaa", "0", "-q", "-o", output], cwd=folder, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, preexec_fn=_default_sigint)


def wait_for_partial(folder: Path, process: subprocess.Popen, timeout: float = 60.0) -> None:
    """Until the render has written part of its temporary file (it is mid-clip)."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        assert process.poll() is None, process.communicate()
        if any(p.stat().st_size > 20_000 for p in folder.iterdir() if ".partial" in p.name):
            return
        time.sleep(0.05)
    raise AssertionError("the render never started writing")


@pytest.mark.gl
@pytest.mark.parametrize("output", ["walk.gif", "walk.mp4"])
@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGTERM])
def test_interrupted_render_leaves_nothing(tmp_path: Path, output: str, sig: signal.Signals) -> None:
    process = start_render(tmp_path, output)
    wait_for_partial(tmp_path, process)
    process.send_signal(sig)
    _, err = process.communicate(timeout=60)
    assert process.returncode == {signal.SIGINT: 130, signal.SIGTERM: 143}[sig]
    assert "interrupted; no output written" in err and "Traceback" not in err
    assert list(tmp_path.iterdir()) == []


@pytest.mark.gl
@pytest.mark.parametrize("output", ["walk.gif", "walk.mp4"])
def test_killed_render_leaves_no_output_and_the_next_run_sweeps_its_partial(tmp_path: Path, output: str) -> None:
    process = start_render(tmp_path, output)
    wait_for_partial(tmp_path, process)
    process.kill()
    process.communicate(timeout=60)
    assert not (tmp_path / output).exists()
    time.sleep(0.5)  # an orphaned ffmpeg finishes its temporary file on end of input
    again = subprocess.run([sys.executable, "-m", "app", "render", "dog", "--cycles", "0.5", "--size", "64x48",
                            "--msaa", "0", "-q", "-o", output], cwd=tmp_path, capture_output=True, text=True,
                           timeout=120)
    assert again.returncode == 0, again.stderr
    assert leftovers(tmp_path) == []
    assert (tmp_path / output).exists()
