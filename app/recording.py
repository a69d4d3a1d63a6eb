"""Recording a creature to PNG, GIF or MP4: the single path used by ``gaitlab render``
and by the viewer's Record panel, so equal settings give equal pixels.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Callable

import moderngl
import numpy as np

from .errors import GaitlabError
from .limits import MAX_FPS, MAX_SECONDS, MAX_SPEED, check_clip  # noqa: F401  (re-exported)
from .kinematics.clip import clip_motion, frame_at
from .kinematics.herd import Herd, HerdTrack, check_herd_size, follow_leader
from .kinematics.world import World
from .output import (DEFAULT_CRF, DEFAULT_GIF_QUALITY, GIF_MAX_FPS, GIF_QUALITIES, MAX_SIZE, GifQuality, GifWriter,
                     Mp4Writer, cannot_write, check_crf, check_output_dir, output_format, write_png)
from .render.clip import ClipRenderer, ViewSettings, clip_cameras, loop_grid_spacing
from .render.herd import HerdInstances
from .render.renderer import RenderOptions
from .rigging import build_rig
from .spec import CreatureSpec


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
    speed: tuple[float, float] | None = None  # m/s at the first and last frame: speed-driven gaits
    world: World = field(default_factory=World)  # path and terrain (default: straight ahead, flat)
    gif_quality: GifQuality = DEFAULT_GIF_QUALITY  # GIF size against fidelity: best, good, small
    crf: int = DEFAULT_CRF  # MP4 (H.264) constant rate factor: 0 lossless .. 51 smallest
    herd: int = 1  # animals in all: the creature and herd - 1 more of its kind following it
    arcs: tuple[str, ...] = ()  # joints whose paths over the last cycle are drawn (see kinematics.arcs)

    def __post_init__(self) -> None:
        if self.gif_quality not in GIF_QUALITIES:
            raise GaitlabError(f"GIF quality {self.gif_quality!r}: choose one of {', '.join(GIF_QUALITIES)}")
        check_crf(self.crf)
        w, h = self.view.size
        if not (1 <= w <= MAX_SIZE and 1 <= h <= MAX_SIZE):
            raise GaitlabError(f"size {w}x{h}: width and height must be between 1 and {MAX_SIZE}")
        check_clip(self.fps, self.seconds, self.cycles, self.start, self.speed)
        check_herd_size(self.herd)
        if self.herd > 1 and self.world.in_place:
            raise GaitlabError(f"a herd of {self.herd} travels: drop --in-place")


@dataclass(frozen=True)
class RecordResult:
    path: Path
    frames: int
    seconds: float
    cycles: float
    gaits: tuple[str, ...] = ()  # the gaits a speed-driven clip went through, in order
    notes: tuple[str, ...] = ()  # things the user should know about the file (e.g. an optimiser missing)


class Recording:
    """A recording in progress, rendered a few frames at a time so a UI can show progress
    and stay responsive. :func:`record` drives one to the end; the viewer steps one per
    UI frame. Both produce the same file for the same request.

    Frames stream to the writer as they are rendered (memory does not grow with the
    clip); the writer encodes on a background thread. Nothing is left at the output path
    unless :meth:`finish` succeeds.

    Raises :class:`GaitlabError` (nothing written) for bad requests or unwritable paths.
    """

    def __init__(self, request: RecordRequest, ctx: moderngl.Context | None = None) -> None:
        self.request = request
        self.format = output_format(request.output)
        check_output_dir(request.output)
        w, h = request.view.size
        if self.format == "mp4" and (w % 2 or h % 2):
            raise GaitlabError(f"{request.output}: MP4 (H.264, yuv420p) needs an even width and height, "
                               f"got {w}x{h}")
        rig = build_rig(request.spec)
        self.frequency = rig.gait.frequency
        view = request.view
        world = request.world
        self._herd: tuple[Herd, HerdTrack, HerdInstances] | None = None
        if self.format == "png":
            # Framed as the cycle around the frame would be (no jitter between frames of a
            # film strip made with --time).
            cycle, _ = clip_motion(rig, request.fps, cycles=1.0, start=request.start, world=world)
            self.motion = frame_at(rig, request.start, request.fps, world)
            self.cameras = clip_cameras(cycle, view, self._herd_points(rig, cycle, request))[:1]
            if self._herd is not None:  # the herd as it is at the frame: the cycle's first
                self._herd = (self._herd[0], _first_frame(self._herd[1]), self._herd[2])
            self.options = _with_grid(view.options, loop_grid_spacing(cycle, None))
            self.cycles: float | None = None
        else:
            self.motion, self.cycles = clip_motion(rig, request.fps, request.seconds, request.cycles, request.start,
                                                   request.speed, world=world)
            self.cameras = clip_cameras(self.motion, view, self._herd_points(rig, self.motion, request))
            self.options = _with_grid(view.options, loop_grid_spacing(self.motion, self.cycles))
        self.total = self.motion.frame_count
        self._arcs = self._arc_source(rig, request)
        self.done = 0
        self._png: np.ndarray | None = None
        self._renderer: ClipRenderer | None = ClipRenderer(view.size, view.antialias, view.samples, ctx=ctx)
        self._writer: GifWriter | Mp4Writer | None = None
        try:
            if self.format == "mp4":
                self._writer = Mp4Writer(request.output, view.size, request.fps, crf=request.crf)
            elif self.format == "gif":
                # One palette for the whole clip, from frames spread over it.
                samples = [self._render(i) for i in sorted({0, self.total // 3, (2 * self.total) // 3})]
                self._writer = GifWriter(request.output, view.size, request.fps, samples, request.gif_quality,
                                         frame_count=self.total)
        except OSError as exc:
            self.cancel()
            raise cannot_write(request.output, exc) from None
        except BaseException:
            self.cancel()
            raise

    def _herd_points(self, rig, motion, request: RecordRequest) -> np.ndarray | None:
        """With a herd: simulate it after the creature over ``motion`` and return every
        animal's body point per frame (T, N, 3), for the camera to keep in view."""
        if request.herd <= 1:
            return None
        points, tangents = motion.path.sample(motion.travel)
        heading = np.unwrap(np.arctan2(tangents[:, 0], tangents[:, 1]))
        herd = Herd(rig, request.herd - 1)
        track = follow_leader(herd, points, heading, request.fps)
        self._herd = (herd, track, HerdInstances(herd, request.view.options.joints))
        top = float(rig.hip_height + rig.body.head_radius)
        reach = 0.75 * float(rig.body_length + rig.body.head_length) * 1.1  # nose and tail of the largest
        ground = motion.terrain.height(track.position)  # (T, N): the animals stand on the terrain
        xyz = np.stack([track.position[..., 0], ground, track.position[..., 1]], axis=-1)
        corners = [np.array([dx, dy, dz]) for dx in (-reach, reach) for dy in (0.0, top) for dz in (-reach, reach)]
        return np.concatenate([xyz + c for c in corners], axis=1)

    def _arc_source(self, rig, request: RecordRequest):
        """The motion the arcs are drawn from, how many frames a cycle has, and whether the
        whole cycle is drawn in every frame: a PNG shows the cycle up to its frame; a
        constant gait in place shows its closed loop; otherwise the trail grows behind."""
        if not request.arcs:
            return None
        from .kinematics.arcs import arc_points

        source = self.motion
        # Frames a cycle takes, from the clip's own clock (a speed ramp changes it).
        step = float(np.median(np.diff(source.clock))) if source.frame_count > 1 else rig.gait.frequency / request.fps
        per_cycle = max(2, int(round(1.0 / max(step, 1e-9))))
        whole = self.format == "png" or (source.in_place and request.speed is None)
        if self.format == "png":
            period = 1.0 / rig.gait.frequency
            source, _ = clip_motion(rig, request.fps, cycles=1.0, start=request.start - period, world=request.world,
                                    closed=True)
        elif whole:
            source, _ = clip_motion(rig, request.fps, cycles=1.0, start=request.start, world=request.world)
        try:
            points = {joint: arc_points(source, joint) for joint in request.arcs}
        except ValueError as exc:
            raise GaitlabError(f"--arcs: {exc}") from None
        return source, points, per_cycle, whole

    def _arc_shapes(self, index: int):
        from .kinematics.arcs import key_pose_frames, trail
        from .render.arcs import arc_instances

        source, points, per_cycle, whole = self._arcs
        end = source.frame_count - 1 if whole else index
        keys = key_pose_frames(source, end, per_cycle)
        trails = {joint: trail(p, end, per_cycle) for joint, p in points.items()}
        markers = {joint: p[keys] for joint, p in points.items()}
        return arc_instances(trails, markers, 0.012 * source.rig.hip_height)

    def _render(self, index: int) -> np.ndarray:
        assert self._renderer is not None
        extra = None
        if self._herd is not None:
            herd, track, instances = self._herd
            extra = instances.frame(track.apply(herd, min(index, len(track.phase) - 1)), self.motion.terrain.height)
        if self._arcs is not None:
            shapes = self._arc_shapes(index)
            extra = shapes if extra is None else extra + shapes
        return self._renderer.frame(self.motion, index, self.cameras[index], self.options, extra)

    @property
    def finished(self) -> bool:
        return self.done >= self.total

    @property
    def progress(self) -> float:
        """Fraction of frames rendered, [0, 1]."""
        return self.done / self.total

    def step(self, frames: int = 1) -> bool:
        """Render up to ``frames`` more frames; True when all are rendered."""
        try:
            for _ in range(min(frames, self.total - self.done)):
                image = self._render(self.done)
                if self._writer is not None:
                    self._writer.add(image)
                else:
                    self._png = image
                self.done += 1
        except OSError as exc:
            self.cancel()
            raise cannot_write(self.request.output, exc) from None
        except BaseException:
            self.cancel()
            raise
        return self.finished

    def finish(self) -> RecordResult:
        """Render what is left, finish the file (atomically) and free the renderer."""
        request = self.request
        notes: tuple[str, ...] = ()
        try:
            self.step(self.total - self.done)
            if self._writer is None:
                assert self._png is not None
                write_png(request.output, self._png)
            else:
                writer, self._writer = self._writer, None
                try:
                    writer.close(ok=True)
                except BaseException:
                    writer.close(ok=False)
                    raise
                notes = tuple(getattr(writer, "notes", ()))
        except OSError as exc:
            self.cancel()
            raise cannot_write(request.output, exc) from None
        except BaseException:
            self.cancel()
            raise
        self._release()
        if self.format == "png":
            return RecordResult(Path(request.output), 1, 0.0, 0.0)
        seconds = self.total / request.fps
        gaits = tuple(dict.fromkeys(self.motion.gaits))
        if gaits:
            cycles = float(self.motion.clock[-1] - self.motion.clock[0]) + float(np.diff(self.motion.clock[:2]).sum())
        else:
            cycles = self.cycles if self.cycles is not None else seconds * self.frequency
        return RecordResult(Path(request.output), self.total, seconds, cycles, gaits, notes)

    def cancel(self) -> None:
        """Stop without writing anything (a partial file is deleted)."""
        if self._writer is not None:
            try:
                self._writer.close(ok=False)
            finally:
                self._writer = None
        self._release()

    def _release(self) -> None:
        self._png = None
        if self._renderer is not None:
            self._renderer.release()
            self._renderer = None


def record(request: RecordRequest, progress: Progress | None = None,
           ctx: moderngl.Context | None = None) -> RecordResult:
    """Render ``request`` and write its file. Raises :class:`GaitlabError` on bad input
    or when the file cannot be written (nothing is left behind then).

    ``ctx``: an existing GL context to render in (the viewer's); default a new EGL one.
    """
    try:
        job = Recording(request, ctx)
    except OSError as exc:
        raise cannot_write(request.output, exc) from None
    while not job.finished:
        job.step(1)
        if progress:
            progress(job.done, job.total)
    return job.finish()


def _first_frame(track: HerdTrack) -> HerdTrack:
    return HerdTrack(track.position[:1], track.heading[:1], track.phase[:1])


def _with_grid(options: RenderOptions, spacing: float) -> RenderOptions:
    return replace(options, grid_spacing=spacing)


def gif_fps_warning(fps: float) -> str | None:
    """A warning for GIF frame rates that browsers do not play at full speed."""
    if fps > GIF_MAX_FPS:
        return (f"warning: GIF frame delays under 20 ms ({fps:g} fps) are slowed down by most browsers; "
                f"use --fps {GIF_MAX_FPS} or less, or write .mp4")
    return None
