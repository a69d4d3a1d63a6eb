"""Looping GIFs written frame by frame, with one palette, frame differencing and an
optional gifsicle pass.

Memory stays at a couple of frames whatever the clip's length: each frame is mapped to a
palette chosen up front from a few sample frames (so colours never flicker), reduced to
the rectangle that changed since the previous frame with unchanged pixels transparent,
and LZW-encoded by Pillow (its frame-by-frame GIF API) straight into the file. When
``gifsicle`` is installed it then re-optimises the file (``-O2``, and ``--lossy`` for the
smaller qualities), which about halves a typical clip; without it the GIF is still
written, only larger.
"""

from __future__ import annotations

import os
import shutil
import subprocess
from dataclasses import dataclass
from pathlib import Path
from typing import IO, Literal

import numpy as np
from numpy.typing import NDArray

from ..errors import OutputError
from .background import BackgroundWriter
from .files import AtomicPath, cannot_write

GIF_MAX_FPS = 50  # browsers slow down frame delays under 20 ms
GifQuality = Literal["best", "good", "small"]
GIF_QUALITIES: tuple[str, ...] = ("best", "good", "small")
DEFAULT_GIF_QUALITY: GifQuality = "good"
GIFSICLE_MAX_BYTES = 96 * 2**20  # gifsicle holds the whole file in memory: skip it above this


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
    palette). ``quality``: one of :data:`GIF_QUALITIES`. After :meth:`close`,
    :attr:`notes` says what, if anything, the user should know (e.g. gifsicle missing).
    """

    def __init__(self, path: str | os.PathLike[str], size: tuple[int, int], fps: float,
                 palette_samples: list[NDArray[np.uint8]], quality: GifQuality = DEFAULT_GIF_QUALITY) -> None:
        if quality not in GIF_PROFILES:
            raise OutputError(f"GIF quality {quality!r}: choose one of {', '.join(GIF_QUALITIES)}")
        if not palette_samples:
            raise OutputError(f"{os.fspath(path)}: no frames to choose the GIF's colours from")
        self.profile = GIF_PROFILES[quality]
        self.size = (int(size[0]), int(size[1]))
        self.fps = float(fps)
        self.notes: list[str] = []
        self._palette = choose_palette(palette_samples, self.profile.colors)
        self._transparent = len(self._palette.getpalette()) // 3  # the first index after the colours
        self._atomic = AtomicPath(path)
        self._file: IO[bytes] | None = open(self._atomic.tmp, "wb")
        self._previous: NDArray[np.uint8] | None = None
        self._count = 0
        self._pipe = BackgroundWriter(self._encode, name="gif")

    # -- the worker thread ------------------------------------------------------------

    def _encode(self, frame: NDArray[np.uint8]) -> None:
        from PIL import GifImagePlugin, Image

        indices = np.asarray(Image.fromarray(frame).quantize(palette=self._palette, dither=Image.Dither.NONE))
        delay = _frame_duration(self._count, self.fps)
        assert self._file is not None
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

    # -- the caller's thread ----------------------------------------------------------

    def add(self, frame: NDArray[np.uint8]) -> None:
        h, w = frame.shape[:2]
        if (w, h) != self.size:
            raise OutputError(f"{self._atomic.final}: frame is {w}x{h}, the GIF is {self.size[0]}x{self.size[1]}")
        self._pipe.put(frame)

    def close(self, ok: bool) -> Path | None:
        """Finish the file and commit it when ``ok``; otherwise delete it."""
        if not ok:
            self._pipe.abort()
            self._close_file()
            self._atomic.discard()
            return None
        try:
            self._pipe.close()
            if self._count == 0:
                raise OutputError(f"{self._atomic.final}: no frames to write")
            assert self._file is not None
            self._file.write(b";")  # the GIF trailer
            self._close_file()
            self._optimise()
        except OSError as exc:
            self._close_file()
            self._atomic.discard()
            raise cannot_write(self._atomic.final, exc) from None
        except BaseException:
            self._close_file()
            self._atomic.discard()
            raise
        return self._atomic.commit()

    def _close_file(self) -> None:
        if self._file is not None:
            self._file.close()
            self._file = None

    def _optimise(self) -> None:
        """Run gifsicle over the written file, in place (through a second temporary file)."""
        exe = gifsicle_path()
        if exe is None:
            self.notes.append("gifsicle is not installed, so this GIF is about twice the size it could be "
                              "(install it: apt install gifsicle, brew install gifsicle)")
            return
        size = self._atomic.tmp.stat().st_size
        if size > GIFSICLE_MAX_BYTES:
            self.notes.append(f"the GIF is {size / 2**20:.0f} MiB before optimisation; gifsicle, which would hold "
                              "it all in memory, was skipped (write .mp4 for long takes)")
            return
        optimised = AtomicPath(self._atomic.final)
        command = [exe, "--no-warnings", "-O2"]
        if self.profile.lossy:
            command.append(f"--lossy={self.profile.lossy}")
        try:
            done = subprocess.run([*command, str(self._atomic.tmp), "-o", str(optimised.tmp)],
                                  stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
        except BaseException:
            optimised.discard()
            raise
        if done.returncode != 0 or optimised.tmp.stat().st_size == 0:
            optimised.discard()
            detail = done.stderr.decode("utf-8", "replace").strip().splitlines()
            self.notes.append(f"gifsicle failed ({detail[-1] if detail else done.returncode}); "
                              "the GIF was written unoptimised")
            return
        os.replace(optimised.tmp, self._atomic.tmp)
