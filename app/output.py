"""Writing frames to PNG, GIF and MP4 files, atomically.

Every writer renders into a temporary file next to the destination and renames it into
place only when the whole file is written, so a failure or Ctrl-C never leaves a
half-written output (and never clobbers an existing file with one).
"""

from __future__ import annotations

import os
import tempfile
from pathlib import Path
from typing import Iterable, Literal

import numpy as np
from numpy.typing import NDArray

from .errors import OutputError

OutputFormat = Literal["png", "gif", "mp4"]
OUTPUT_FORMATS: tuple[str, ...] = ("png", "gif", "mp4")
MAX_SIZE = 8192
GIF_MAX_FPS = 50  # browsers slow down frame delays under 20 ms


def output_format(path: str | os.PathLike[str]) -> OutputFormat:
    """The format of an output path from its suffix; :class:`OutputError` if unsupported."""
    suffix = Path(path).suffix.lower().lstrip(".")
    if suffix not in OUTPUT_FORMATS:
        shown = f"'.{suffix}'" if suffix else "no suffix"
        raise OutputError(f"{os.fspath(path)}: output has {shown}; use .png (one frame), .gif or .mp4")
    return suffix  # type: ignore[return-value]


def check_output_dir(path: str | os.PathLike[str]) -> None:
    """Fail early (before rendering) if ``path`` cannot be written."""
    path = Path(path)
    parent = path.parent if str(path.parent) else Path(".")
    if not parent.is_dir():
        raise OutputError(f"{os.fspath(path)}: output folder {os.fspath(parent)!r} does not exist")
    if path.is_dir():
        raise OutputError(f"{os.fspath(path)}: is a folder; give a file name ending in .png, .gif or .mp4")
    try:  # a real probe: permission bits say nothing for root or for special file systems
        fd, probe = tempfile.mkstemp(prefix=".gaitlab-probe-", dir=parent)
        os.close(fd)
        os.unlink(probe)
    except OSError as exc:
        raise OutputError(f"{os.fspath(path)}: output folder {os.fspath(parent)!r} is not writable "
                          f"({exc.strerror or exc})") from None


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def cannot_write(path: str | os.PathLike[str], exc: OSError) -> OutputError:
    """The one-line error for an OS failure while writing ``path``."""
    return OutputError(f"{os.fspath(path)}: cannot write: {exc.strerror or exc}")


def gif_durations(frame_count: int, fps: float) -> list[int]:
    """Per-frame GIF delays in ms, multiples of 10 (GIF's resolution), each within 10 ms of
    1000/fps, placed so the cumulative time never drifts more than 5 ms from exact."""
    edges = np.round(np.arange(frame_count + 1) * (100.0 / fps)) * 10  # centiseconds -> ms
    return [int(d) for d in np.diff(edges)]


class AtomicPath:
    """A temporary path next to ``final`` (same suffix) that is renamed into place on commit."""

    def __init__(self, final: str | os.PathLike[str]) -> None:
        self.final = Path(final)
        check_output_dir(self.final)
        try:
            fd, tmp = tempfile.mkstemp(prefix=f".{self.final.stem}.", suffix=f".partial{self.final.suffix}",
                                       dir=self.final.parent)
        except OSError as exc:
            raise cannot_write(self.final, exc) from None
        os.close(fd)
        self.tmp = Path(tmp)

    def commit(self) -> Path:
        try:
            os.chmod(self.tmp, 0o666 & ~_umask())  # as a plain open() would (mkstemp makes 0600)
            os.replace(self.tmp, self.final)
        except OSError as exc:
            self.discard()
            raise cannot_write(self.final, exc) from None
        return self.final

    def discard(self) -> None:
        self.tmp.unlink(missing_ok=True)

    def __enter__(self) -> "AtomicPath":
        return self

    def __exit__(self, exc_type, exc, tb) -> None:
        if exc_type is None:
            self.commit()
            return
        self.discard()
        if isinstance(exc, OSError):
            raise cannot_write(self.final, exc) from None


def atomic_write_text(path: str | os.PathLike[str], text: str) -> Path:
    """Write ``text`` (UTF-8) to ``path`` through a temporary file renamed into place."""
    with AtomicPath(path) as out:
        out.tmp.write_text(text, encoding="utf-8")
    return Path(path)


def write_png(path: str | os.PathLike[str], image: NDArray[np.uint8]) -> Path:
    """Save one (H, W, 3) uint8 image as PNG, atomically."""
    from PIL import Image

    with AtomicPath(path) as out:
        Image.fromarray(image).save(out.tmp, format="PNG", optimize=False)
    return Path(path)


def _gif_palette(samples: list[NDArray[np.uint8]]):
    from PIL import Image

    mosaic = Image.fromarray(np.concatenate(samples, axis=0))
    return mosaic.quantize(colors=255, method=Image.Quantize.MEDIANCUT, dither=Image.Dither.NONE)


def write_gif(path: str | os.PathLike[str], frames: Iterable[NDArray[np.uint8]], fps: float,
              palette_samples: list[NDArray[np.uint8]]) -> Path:
    """Save frames as a GIF that loops forever, atomically.

    One palette for the whole clip (from ``palette_samples``, a few representative
    frames) so colours do not flicker between frames; no dithering.
    """
    from PIL import Image

    palette = _gif_palette(palette_samples)
    images = [Image.fromarray(f).quantize(palette=palette, dither=Image.Dither.NONE) for f in frames]
    if not images:
        raise OutputError(f"{os.fspath(path)}: no frames to write")
    with AtomicPath(path) as out:
        images[0].save(out.tmp, format="GIF", save_all=True, append_images=images[1:], loop=0,
                       duration=gif_durations(len(images), fps), disposal=1, optimize=False)
    return Path(path)


class Mp4Writer:
    """Streams frames into an H.264 MP4 (imageio-ffmpeg's bundled ffmpeg), atomically."""

    def __init__(self, path: str | os.PathLike[str], size: tuple[int, int], fps: float) -> None:
        import imageio_ffmpeg

        w, h = size
        if w % 2 or h % 2:
            raise OutputError(f"{os.fspath(path)}: MP4 (H.264, yuv420p) needs an even width and height, "
                              f"got {w}x{h}")
        self._atomic = AtomicPath(path)
        self._gen = imageio_ffmpeg.write_frames(
            str(self._atomic.tmp), (w, h), fps=fps, codec="libx264", pix_fmt_in="rgb24", pix_fmt_out="yuv420p",
            macro_block_size=1, quality=None, ffmpeg_log_level="error",
            output_params=["-crf", "18", "-preset", "medium", "-movflags", "+faststart"])
        self._gen.send(None)

    def add(self, frame: NDArray[np.uint8]) -> None:
        self._gen.send(np.ascontiguousarray(frame))

    def close(self, ok: bool) -> Path | None:
        """Finish the file; commit it when ``ok``, otherwise delete it."""
        try:
            self._gen.close()
        except BaseException:
            self._atomic.discard()
            raise
        if ok:
            return self._atomic.commit()
        self._atomic.discard()
        return None
