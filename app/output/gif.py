"""Looping GIFs written frame by frame, with one palette, frame differencing and an
optional gifsicle pass.

Memory stays at a couple of frames whatever the clip's length: each frame is mapped to a
palette chosen up front from a few sample frames (so colours never flicker), reduced to
the rectangle that changed since the previous frame with unchanged pixels transparent,
and LZW-encoded by Pillow (its frame-by-frame GIF API) straight into the file. When
``gifsicle`` is installed it re-optimises the frames (``-O2``, and ``--lossy`` for the
smaller qualities), which about halves a typical clip: part by part, in the background
while later frames render, then joins the parts. Without it the GIF is still written,
only larger.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import tempfile
import threading
import time
from dataclasses import dataclass
from pathlib import Path
from typing import IO

import numpy as np
from numpy.typing import NDArray

from ..choices import DEFAULT_GIF_QUALITY, GIF_QUALITIES, GifQuality
from ..errors import OutputError
from .background import BackgroundWriter
from .files import AtomicPath, cannot_write

GIF_MAX_FPS = 50  # browsers slow down frame delays under 20 ms
GIFSICLE_MAX_PIXELS = 3000 * 480 * 360  # frames x width x height: gifsicle joins it all in memory
CHUNK_FRAMES = 200  # frames per part optimised by gifsicle while later ones render
MAX_GIFSICLES = 2  # parts optimised at once


@dataclass(frozen=True)
class GifProfile:
    """How a quality is made: palette size, and gifsicle's ``--lossy`` (0: lossless)."""

    colors: int
    lossy: int
    description: str


GIF_PROFILES: dict[str, GifProfile] = {
    "best": GifProfile(255, 0, "255 colours, lossless compression"),
    "good": GifProfile(96, 20, "96 colours, mildly lossy compression: about half the size, no visible loss"),
    "small": GifProfile(48, 60, "48 colours, lossy compression: about a third of 'best', some banding and grain"),
}


def gif_durations(frame_count: int, fps: float) -> list[int]:
    """Per-frame GIF delays in ms, multiples of 10 (GIF's resolution), each within 10 ms of
    1000/fps, placed so the cumulative time never drifts more than 5 ms from exact."""
    edges = np.round(np.arange(frame_count + 1) * (100.0 / fps)) * 10  # centiseconds -> ms
    return [int(d) for d in np.diff(edges)]


def _frame_duration(index: int, fps: float) -> int:
    """The delay (ms) of frame ``index``: the same numbers as :func:`gif_durations`."""
    edges = np.round(np.array([index, index + 1]) * (100.0 / fps)) * 10
    return int(edges[1] - edges[0])


def gifsicle_path() -> str | None:
    """The gifsicle executable, or None when it is not installed."""
    return shutil.which("gifsicle")


def choose_palette(samples: list[NDArray[np.uint8]], colors: int):
    """A ``colors``-entry palette image (Pillow "P") for frames like ``samples``."""
    from PIL import Image

    mosaic = Image.fromarray(np.concatenate(samples, axis=0))
    return mosaic.quantize(colors=colors, method=Image.Quantize.MEDIANCUT, dither=Image.Dither.NONE, kmeans=2)


class GifWriter:
    """Streams (H, W, 3) uint8 frames into a looping GIF, atomically.

    ``palette_samples``: a few frames representative of the clip (their colours make the
    palette). ``quality``: one of :data:`GIF_QUALITIES`. ``frame_count``: how many frames
    will come, if known; clips up to :data:`GIFSICLE_MAX_PIXELS` pixel-frames are
    optimised by gifsicle in chunks of :data:`CHUNK_FRAMES` while later frames are still
    rendering, then joined. After :meth:`close`, :attr:`notes` says what, if anything, the
    user should know (e.g. gifsicle missing).
    """

    def __init__(self, path: str | os.PathLike[str], size: tuple[int, int], fps: float,
                 palette_samples: list[NDArray[np.uint8]], quality: GifQuality = DEFAULT_GIF_QUALITY,
                 frame_count: int | None = None) -> None:
        if quality not in GIF_PROFILES:
            raise OutputError(f"GIF quality {quality!r}: choose one of {', '.join(GIF_QUALITIES)}")
        if not palette_samples:
            raise OutputError(f"{os.fspath(path)}: no frames to choose the GIF's colours from")
        self.profile = GIF_PROFILES[quality]
        self.size = (int(size[0]), int(size[1]))
        self.fps = float(fps)
        self.notes: list[str] = []
        self._palette = choose_palette(palette_samples, self.profile.colors)
        colours = self._palette.getpalette()
        count = len(colours) // 3
        if count & (count - 1) == 0:  # a power of two fills its colour table: make room for one more
            self._palette.putpalette(colours + colours[-3:])
        self._transparent = count  # the first index after the colours: inside the table
        self.final = Path(path)
        self._gifsicle = gifsicle_path()
        pixels = (frame_count or 0) * self.size[0] * self.size[1]
        if self._gifsicle is None:
            self.notes.append("gifsicle is not installed, so this GIF is about twice the size it could be "
                              "(install it: apt install gifsicle, brew install gifsicle)")
        elif frame_count is None or pixels > GIFSICLE_MAX_PIXELS:
            self.notes.append(f"a long GIF ({frame_count} frames of {self.size[0]}x{self.size[1]}) is not optimised "
                              "by gifsicle, which would hold it all in memory; write .mp4 for long takes")
            self._gifsicle = None
        self._chunks: list[_Chunk] = []  # written (and being optimised), in order
        self._lock = threading.Lock()  # the chunk list is read by close() and the worker thread
        self._file: IO[bytes] | None = None
        self._in_chunk = 0
        self._previous: NDArray[np.uint8] | None = None
        self._count = 0
        self._output = AtomicPath(path)  # checks the folder; the joined result goes here
        self._pipe = BackgroundWriter(self._encode, name="gif")

    # -- the worker thread ------------------------------------------------------------

    def _start_chunk(self) -> None:
        chunk = _Chunk(AtomicPath(self.final))
        with self._lock:
            self._chunks.append(chunk)
        self._file = open(chunk.raw.tmp, "wb")  # noqa: SIM115  (open across add() calls; closed by the chunk)
        self._in_chunk = 0
        self._previous = None  # every chunk opens with a whole frame (it is a GIF of its own)

    def _end_chunk(self) -> None:
        """Close the chunk being written and queue it for gifsicle (never waits for it)."""
        assert self._file is not None
        self._file.write(b";")  # the GIF trailer
        self._file.close()
        self._file = None
        if self._gifsicle is not None:
            self._chunks[-1].waiting = True
            self._start_waiting()

    def _start_waiting(self) -> None:
        """Start gifsicle on waiting chunks, oldest first, at most two running at once."""
        assert self._gifsicle is not None
        with self._lock:
            running = sum(c.running for c in self._chunks)
            for chunk in self._chunks:
                if running >= MAX_GIFSICLES or self._pipe_aborted():
                    break
                if chunk.waiting:
                    chunk.optimise(self._gifsicle, self.profile.lossy)
                    running += 1

    def _pipe_aborted(self) -> bool:
        pipe = getattr(self, "_pipe", None)
        return pipe is not None and pipe.aborted

    def _encode(self, frame: NDArray[np.uint8]) -> None:
        from PIL import GifImagePlugin, Image

        if self._file is None:
            self._start_chunk()
        assert self._file is not None
        indices = np.asarray(Image.fromarray(frame).quantize(palette=self._palette, dither=Image.Dither.NONE))
        delay = _frame_duration(self._count, self.fps)
        if self._previous is None:
            first = Image.fromarray(indices, "P")
            first.putpalette(self._palette.getpalette())
            header, _ = GifImagePlugin.getheader(first, None, {"loop": 0, "optimize": False})
            self._file.write(b"".join(header))
            blocks = GifImagePlugin.getdata(first, (0, 0), duration=delay, disposal=1)
        else:
            changed = indices != self._previous
            rows, cols = np.flatnonzero(changed.any(axis=1)), np.flatnonzero(changed.any(axis=0))
            if rows.size == 0:  # nothing moved: one transparent pixel carries the delay
                y0, y1, x0, x1 = 0, 1, 0, 1
            else:
                y0, y1, x0, x1 = int(rows[0]), int(rows[-1]) + 1, int(cols[0]), int(cols[-1]) + 1
            patch = np.where(changed[y0:y1, x0:x1], indices[y0:y1, x0:x1], self._transparent).astype(np.uint8)
            image = Image.fromarray(patch, "P")
            blocks = GifImagePlugin.getdata(image, (x0, y0), duration=delay, disposal=1,
                                            transparency=self._transparent)
        self._file.write(b"".join(blocks))
        self._previous = indices
        self._count += 1
        self._in_chunk += 1
        if self._gifsicle is not None and self._in_chunk >= CHUNK_FRAMES:
            self._end_chunk()

    # -- the caller's thread ----------------------------------------------------------

    def add(self, frame: NDArray[np.uint8]) -> None:
        h, w = frame.shape[:2]
        if (w, h) != self.size:
            raise OutputError(f"{self.final}: frame is {w}x{h}, the GIF is {self.size[0]}x{self.size[1]}")
        self._pipe.put(frame)

    def close(self, ok: bool) -> Path | None:
        """Finish the file and commit it when ``ok``; otherwise delete everything written."""
        if not ok:
            self._kill_chunks()  # first, so nothing the worker waits on keeps running
            self._pipe.abort()
            self._discard()
            return None
        try:
            self._pipe.close()
            if self._count == 0:
                raise OutputError(f"{self.final}: no frames to write")
            if self._file is not None:
                self._end_chunk()
            self._join()
        except OSError as exc:
            self._discard()
            raise cannot_write(self.final, exc) from None
        except BaseException:
            self._kill_chunks()
            self._pipe.abort()
            self._discard()
            raise
        for chunk in self._chunks:
            chunk.discard()
        return self._output.commit()

    def _kill_chunks(self) -> None:
        with self._lock:
            for chunk in self._chunks:
                chunk.waiting = False
                chunk.kill()

    def _join(self) -> None:
        """The chunks (optimised where gifsicle ran) as one GIF at the output's temporary path."""
        if self._gifsicle is not None:
            while not self._pipe_aborted() and any(c.waiting or c.running for c in self._chunks):
                self._start_waiting()
                time.sleep(0.02)
        parts = [chunk.result(self.notes) for chunk in self._chunks]
        if len(parts) == 1:
            os.replace(parts[0], self._output.tmp)
            return
        assert self._gifsicle is not None  # several chunks only when gifsicle optimises them
        done = subprocess.run([self._gifsicle, "--no-warnings", "--merge", *map(str, parts), "-o",
                               str(self._output.tmp)], stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL,
                              stderr=subprocess.PIPE)
        if done.returncode != 0:
            detail = done.stderr.decode("utf-8", "replace").strip().splitlines()
            raise OutputError(f"{self.final}: cannot join the GIF's parts with gifsicle: "
                              f"{detail[-1] if detail else done.returncode}")

    def _discard(self) -> None:
        if self._file is not None:
            file, self._file = self._file, None
            try:
                file.close()  # flushes: on a full disk it fails again, and the part is deleted below anyway
            except OSError:
                pass
        for chunk in self._chunks:
            chunk.discard()
        self._output.discard()


class _Chunk:
    """Part of a GIF: the frames as written, and gifsicle's optimised copy when it runs."""

    def __init__(self, raw: AtomicPath) -> None:
        self.raw = raw
        self.optimised: AtomicPath | None = None
        self.process: subprocess.Popen | None = None
        self.waiting = False  # written, gifsicle not started yet
        self._log: IO[bytes] | None = None

    @property
    def running(self) -> bool:
        return self.process is not None and self.process.poll() is None

    def kill(self) -> None:
        if self.running:
            assert self.process is not None
            self.process.kill()
            self.process.wait()

    def optimise(self, exe: str, lossy: int) -> None:
        self.waiting = False
        self.optimised = AtomicPath(self.raw.final)
        self._log = tempfile.TemporaryFile()  # noqa: SIM115  (gifsicle writes to it until it ends)
        command = [exe, "--no-warnings", "-O2"] + ([f"--lossy={lossy}"] if lossy else [])
        self.process = subprocess.Popen([*command, str(self.raw.tmp), "-o", str(self.optimised.tmp)],
                                        stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=self._log,
                                        start_new_session=True)

    def result(self, notes: list[str]) -> Path:
        """The best finished file of this chunk (waits for gifsicle)."""
        if self.process is None or self.optimised is None:
            return self.raw.tmp
        status = self.process.wait()
        if status == 0 and self.optimised.tmp.stat().st_size > 0:
            return self.optimised.tmp
        assert self._log is not None
        self._log.seek(0)
        detail = self._log.read().decode("utf-8", "replace").strip().splitlines()
        notes.append(f"gifsicle failed ({detail[-1] if detail else status}); part of the GIF is unoptimised")
        return self.raw.tmp

    def discard(self) -> None:
        self.kill()
        if self._log is not None:
            self._log.close()
        self.raw.discard()
        if self.optimised is not None:
            self.optimised.discard()
