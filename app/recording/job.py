"""A recording in progress: a cast rendered frame by frame into its file."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import replace
from pathlib import Path

import moderngl
import numpy as np

from ..cast import Actor, cast_frames_at, cast_motions
from ..errors import GaitlabError
from ..kinematics.clip import clip_motion
from ..kinematics.herd import Herd, HerdTrack, follow_leader
from ..kinematics.motion import Motion
from ..kinematics.rig import Rig
from ..output import GifWriter, Mp4Writer, cannot_write, check_output_dir, output_format, write_png
from ..render.clip import ClipRenderer
from ..render.framing import clip_cameras, loop_grid_spacing
from ..render.herd import HerdInstances
from ..render.options import RenderOptions
from ..render.scene import SceneInstances, creature_points
from ..rigging import build_rig
from .request import RecordRequest, RecordResult

Progress = Callable[[int, int], None]


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
        lead = request.lead
        rig = build_rig(lead.spec)
        self.frequency = rig.gait.frequency
        view = request.view
        if self.format == "png":
            # Framed as the cycle around the frame would be (no jitter between frames of a
            # film strip made with --time).
            cycle, _ = clip_motion(rig, request.fps, cycles=1.0, start=request.start, world=lead.world)
            self.motions = cast_frames_at(request.cast, request.start, request.fps)
            framed = [cycle, *cast_motions(request.cast[1:], request.fps, cycle.frame_count / request.fps,
                                           start=request.start)[0]] if len(request.cast) > 1 else [cycle]
            herds = [_herd_track(actor, m, request.fps, view.options) for actor, m in zip(request.cast, framed)]
            self.cameras = clip_cameras(cycle, view, _points_in_view(framed, herds))[:1]
            # The herds as they are at the frame: the cycle's first.
            self._herds = [None if h is None else (h[0], h[1].first(), h[2]) for h in herds]
            self.options = replace(view.options, grid_spacing=loop_grid_spacing(cycle, None))
            self.cycles: float | None = None
        else:
            self.motions, self.cycles = cast_motions(request.cast, request.fps, request.seconds, request.cycles,
                                                     request.start)
            self._herds = [_herd_track(actor, m, request.fps, view.options)
                           for actor, m in zip(request.cast, self.motions)]
            self.cameras = clip_cameras(self.motion, view, _points_in_view(self.motions, self._herds))
            self.options = replace(view.options, grid_spacing=loop_grid_spacing(self.motion, self.cycles))
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

    @property
    def motion(self) -> Motion:
        """The first creature's motion (it times the clip; the camera follows it)."""
        return self.motions[0]

    def _arc_source(self, rig: Rig, request: RecordRequest):
        """The motion the arcs are drawn from (the first creature's), how many frames a
        cycle has, and whether the whole cycle is drawn in every frame: a PNG shows the
        cycle up to its frame; a constant gait in place shows its closed loop; otherwise
        the trail grows behind."""
        if not request.arcs:
            return None
        from ..kinematics.arcs import arc_points

        source = self.motion
        world, speed = request.lead.world, request.lead.speed
        # Frames a cycle takes, from the clip's own clock (a speed ramp changes it).
        step = float(np.median(np.diff(source.clock))) if source.frame_count > 1 else rig.gait.frequency / request.fps
        per_cycle = max(2, int(round(1.0 / max(step, 1e-9))))
        whole = self.format == "png" or (source.in_place and speed is None)
        if self.format == "png":
            period = 1.0 / rig.gait.frequency
            source, _ = clip_motion(rig, request.fps, cycles=1.0, start=request.start - period, world=world,
                                    closed=True)
        elif whole:
            source, _ = clip_motion(rig, request.fps, cycles=1.0, start=request.start, world=world)
        try:
            points = {joint: arc_points(source, joint) for joint in request.arcs}
        except ValueError as exc:
            raise GaitlabError(f"--arcs: {exc}") from None
        return source, points, per_cycle, whole

    def _arc_shapes(self, index: int) -> SceneInstances:
        from ..kinematics.arcs import key_pose_frames, trail
        from ..render.arcs import arc_instances

        source, points, per_cycle, whole = self._arcs
        end = source.frame_count - 1 if whole else index
        keys = key_pose_frames(source, end, per_cycle)
        trails = {joint: trail(p, end, per_cycle) for joint, p in points.items()}
        markers = {joint: p[keys] for joint, p in points.items()}
        return arc_instances(trails, markers, 0.012 * source.rig.hip_height)

    def _render(self, index: int) -> np.ndarray:
        assert self._renderer is not None
        extra = []
        for motion, herd in zip(self.motions, self._herds):
            if herd is not None:
                animals, track, instances = herd
                extra.append(instances.frame(track.apply(animals, min(index, len(track.phase) - 1)),
                                             None if motion.terrain.flat else motion.terrain.height))
        if self._arcs is not None:
            extra.append(self._arc_shapes(index))
        return self._renderer.frame(self.motions, index, self.cameras[index], self.options, extra)

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


HerdParts = tuple[Herd, HerdTrack, HerdInstances]


def _herd_track(actor: Actor, motion: Motion, fps: float, options: RenderOptions) -> HerdParts | None:
    """An actor's herd following it over ``motion`` (its animals, their track and their
    instances), or None without a herd."""
    if actor.herd <= 1:
        return None
    points, tangents = motion.path.sample(motion.travel)
    heading = np.unwrap(np.arctan2(tangents[:, 0], tangents[:, 1]))
    herd = Herd(motion.rig, actor.herd - 1)
    ground = None if motion.terrain.flat else motion.terrain.height
    return herd, follow_leader(herd, points, heading, fps, ground), HerdInstances(herd, options.joints, options.body,
                                                                          options.side_colors)


def _herd_box(motion: Motion, herd: HerdParts, frames: int) -> np.ndarray:
    """Corners of each animal's box (T, 8 N, 3) over a herd's track, for the camera."""
    _animals, track, _ = herd
    rig = motion.rig
    top = float(rig.hip_height + rig.body.head_radius)
    reach = 0.75 * float(rig.body_length + rig.body.head_length) * 1.1  # nose and tail of the largest
    position = track.position[:frames]
    ground = motion.terrain.height(position)  # (T, N): the animals stand on the terrain
    xyz = np.stack([position[..., 0], ground, position[..., 1]], axis=-1)
    corners = [np.array([dx, dy, dz]) for dx in (-reach, reach) for dy in (0.0, top) for dz in (-reach, reach)]
    return np.concatenate([xyz + c for c in corners], axis=1)


def _points_in_view(motions: list[Motion], herds: list[HerdParts | None]) -> np.ndarray | None:
    """Points (T, N, 3) besides the first creature's that the camera keeps in frame: the
    other creatures' and every herd's; None when there are none."""
    frames = motions[0].frame_count
    parts = [creature_points(m) for m in motions[1:]]
    parts += [_herd_box(m, h, frames) for m, h in zip(motions, herds) if h is not None]
    return np.concatenate(parts, axis=1) if parts else None
