"""Recording a creature to PNG, GIF or MP4: the single path used by ``gaitlab render``
and by the viewer's Record panel, so equal settings give equal pixels.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

import moderngl
import numpy as np

from .errors import GaitlabError
from .kinematics.motion import Motion, frame_count, solve_motion
from .kinematics.rig import Rig, build_rig
from .output import (GIF_MAX_FPS, MAX_SIZE, Mp4Writer, cannot_write, check_output_dir, output_format, write_gif,
                     write_png)
from .render.clip import ClipRenderer, ViewSettings, clip_camera, loop_grid_spacing
from .render.renderer import RenderOptions
from .spec import CreatureSpec

DEFAULT_CYCLES = 2.0
MAX_FPS = 240.0
MAX_SECONDS = 600.0

Progress = Callable[[int, int], None]


@dataclass(frozen=True)
class RecordRequest:
    """What to record. Give ``seconds`` or ``cycles`` (default: two whole cycles, which
    loop seamlessly); ``start`` is the time (s) of the first frame (of the only one, for
    PNG). ``view`` sets size, camera, multisampling and what is drawn."""

    spec: CreatureSpec
    output: Path
    fps: float = 25.0
    seconds: float | None = None
    cycles: float | None = None
    start: float = 0.0
    view: ViewSettings = field(default_factory=ViewSettings)

    def __post_init__(self) -> None:
        w, h = self.view.size
        if not (0 < self.fps <= MAX_FPS) or not math.isfinite(self.fps):
            raise GaitlabError(f"fps {self.fps:g}: must be greater than 0 and at most {MAX_FPS:g}")
        if not (1 <= w <= MAX_SIZE and 1 <= h <= MAX_SIZE):
            raise GaitlabError(f"size {w}x{h}: width and height must be between 1 and {MAX_SIZE}")
        if self.seconds is not None and self.cycles is not None:
            raise GaitlabError("give seconds or cycles, not both")
        for name in ("seconds", "cycles"):
            value = getattr(self, name)
            if value is not None and not (0 < value <= MAX_SECONDS and math.isfinite(value)):
                raise GaitlabError(f"{name} {value:g}: must be greater than 0 and at most {MAX_SECONDS:g}")
        if not math.isfinite(self.start) or self.start < 0:
            raise GaitlabError(f"time {self.start:g}: must be a finite number of seconds >= 0")


@dataclass(frozen=True)
class RecordResult:
    path: Path
    frames: int
    seconds: float
    cycles: float


def clip_motion(rig: Rig, fps: float, seconds: float | None = None, cycles: float | None = None,
                start: float = 0.0) -> tuple[Motion, float | None]:
    """The motion of a clip and, for whole-cycle clips, its cycle count.

    With ``cycles`` the frame count is ``round(cycles * fps / frequency)`` and the clock
    steps by exactly ``cycles / frames`` per frame (the frequency nudged by under half a
    frame per clip) so the last frame leads seamlessly into the first.
    """
    f = rig.gait.frequency
    start_clock = f * start
    if seconds is None:
        cycles = DEFAULT_CYCLES if cycles is None else cycles
        frames = max(1, int(round(cycles * fps / f)))
        clock = start_clock + cycles * np.arange(frames) / frames
    else:
        frames = frame_count(seconds, fps)
        clock = start_clock + f * np.arange(frames) / fps
        cycles = None
    times = start + np.arange(frames) / fps
    return solve_motion(rig, clock, times=times, fps=fps), cycles


def record(request: RecordRequest, progress: Progress | None = None,
           ctx: moderngl.Context | None = None) -> RecordResult:
    """Render ``request`` and write its file. Raises :class:`GaitlabError` on bad input
    or when the file cannot be written (nothing is left behind then).

    ``ctx``: an existing GL context to render in (the viewer's); default a new EGL one.
    """
    try:
        return _record(request, progress, ctx)
    except OSError as exc:
        raise cannot_write(request.output, exc) from None


def _record(request: RecordRequest, progress: Progress | None, ctx: moderngl.Context | None) -> RecordResult:
    fmt = output_format(request.output)
    check_output_dir(request.output)
    if fmt == "mp4" and (request.view.size[0] % 2 or request.view.size[1] % 2):
        w, h = request.view.size
        raise GaitlabError(f"{request.output}: MP4 (H.264, yuv420p) needs an even width and height, got {w}x{h}")
    rig = build_rig(request.spec)
    view = request.view
    if fmt == "png":
        cycle, _ = clip_motion(rig, request.fps, cycles=1.0)
        motion = solve_motion(rig, np.array([rig.gait.frequency * request.start]), times=np.array([request.start]),
                              fps=request.fps)
        camera = clip_camera(cycle, view)
        options = _with_grid(view.options, loop_grid_spacing(cycle, None))
        with ClipRenderer(view.size, view.samples, ctx=ctx) as renderer:
            image = renderer.frame(motion, 0, camera, options)
        write_png(request.output, image)
        if progress:
            progress(1, 1)
        return RecordResult(Path(request.output), 1, 0.0, 0.0)

    motion, cycles = clip_motion(rig, request.fps, request.seconds, request.cycles, request.start)
    camera = clip_camera(motion, view)
    options = _with_grid(view.options, loop_grid_spacing(motion, cycles))
    total = motion.frame_count
    with ClipRenderer(view.size, view.samples, ctx=ctx) as renderer:
        if fmt == "gif":
            frames = []
            for i in range(total):
                frames.append(renderer.frame(motion, i, camera, options))
                if progress:
                    progress(i + 1, total)
            samples = [frames[i] for i in sorted({0, total // 3, (2 * total) // 3})]
            write_gif(request.output, frames, request.fps, samples)
        else:
            writer = Mp4Writer(request.output, view.size, request.fps)
            ok = False
            try:
                for i in range(total):
                    writer.add(renderer.frame(motion, i, camera, options))
                    if progress:
                        progress(i + 1, total)
                ok = True
            finally:
                writer.close(ok)
    seconds = total / request.fps
    return RecordResult(Path(request.output), total, seconds,
                        cycles if cycles is not None else seconds * rig.gait.frequency)


def _with_grid(options: RenderOptions, spacing: float) -> RenderOptions:
    from dataclasses import replace

    return replace(options, grid_spacing=spacing)


def gif_fps_warning(fps: float) -> str | None:
    """A warning for GIF frame rates that browsers do not play at full speed."""
    if fps > GIF_MAX_FPS:
        return (f"warning: GIF frame delays under 20 ms ({fps:g} fps) are slowed down by most browsers; "
                f"use --fps {GIF_MAX_FPS} or less, or write .mp4")
    return None
