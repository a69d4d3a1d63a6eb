"""The interactive viewer's main loop: window, scene, UI, input, screenshots, recording.

``gaitlab view`` calls :func:`run_viewer`. A scripted run (``frames=N``) steps the
animation by a fixed 1/60 s per frame, so its screenshot is reproducible.
"""

from __future__ import annotations

import json
import statistics
import sys
import time
from dataclasses import dataclass, field, replace
from pathlib import Path

import moderngl
import numpy as np
from imgui_bundle import imgui, implot

from ..cast import Cast
from ..errors import GaitlabError
from ..kinematics.motion import Pose
from ..output import atomic_write_text, write_png
from ..recording import Recording
from ..render.arcs import arc_instances
from ..render.bodies import pose_body, shared_body_cache
from ..render.camera import eye_ray, ground_point, point3
from ..render.herd import HerdInstances
from ..render.options import GroundView
from ..render.overlays import Overlays
from ..render.renderer import SceneRenderer, ShadowCast
from ..render.scene import KEY_POSE_COLORS, SceneInstances, frame_instances, ghost_instances, pose_instances
from .file_dialog import FileDialog, dialogs_available
from .imgui_renderer import Backdrop, ImguiRenderer
from .monitor import GaitMonitor
from .panels import SIDEBAR_COLOR, SIDEBAR_WIDTH, PanelContext, draw_ui
from .playback import FRAME_DT
from .state import ViewerState
from .style import setup_style
from .window import GlfwWindow

CLICK_SLOP = 4.0  # px: a press that moves no further than this before its release is a click
DUMP_EVERY = 0.2  # s: the state dump is written every 20 frames, and at least this often on a slow machine


@dataclass
class ViewerOptions:
    """How to run the viewer (``gaitlab view`` options)."""

    size: tuple[int, int] = (1280, 720)
    vsync: bool = True
    samples: int = 0
    frames: int | None = None  # run this many frames, then exit (fixed 1/60 s steps)
    screenshot: Path | None = None  # save the window (with UI) after the last frame
    hide_ui: bool = False
    report_fps: bool = False
    dump_state: Path | None = None  # write the viewer state as JSON (automation, tests)
    presets: list[str] = field(default_factory=list)
    overlays: tuple[str, ...] = ()  # turned on at start: footprints, targets, support
    panels: tuple[str, ...] = ()  # sidebar panels opened at start (titles)


@dataclass(frozen=True)
class FrameContent:
    """What one frame of the 3-D view draws, gathered before it is drawn."""

    instances: SceneInstances
    ground: GroundView
    overlays: Overlays | None
    cast: ShadowCast | None = None  # its shapes and shadow, issued to the GL ahead of the frame


def _ema(old: float, new: float, k: float = 0.1) -> float:
    return new if old == 0.0 else old + (new - old) * k


class Viewer:
    """One viewer window and its GL/ImGui resources."""

    def __init__(self, cast: Cast, options: ViewerOptions) -> None:
        lead = cast[0]
        self.options = options
        self.imgui_ctx = imgui.create_context()
        imgui.get_io().set_ini_filename("")
        self.implot_ctx = implot.create_context()
        self.window = GlfwWindow(options.size, f"Gaitlab - {lead.spec.name}", vsync=options.vsync,
                                 samples=options.samples)
        self.ctx = moderngl.create_context(require=330)
        self.scale = self.window.content_scale
        icons = setup_style(self.scale)
        self.scene = SceneRenderer(self.ctx)
        self.ui = ImguiRenderer(self.ctx, self.scene.shaders)
        self.state = ViewerState(lead.spec, world=lead.world)
        self.state.show_ui = not options.hide_ui
        for actor in cast[1:]:
            if not self.state.add_creature(actor.spec, actor.world):
                raise GaitlabError(self.state.error or "scene")
        for index, actor in enumerate(cast):
            self.state.selected = index
            if actor.herd > 1 and not self.state.set_herd(actor.herd):
                raise GaitlabError(self.state.error or "herd")
        self.state.selected = 0
        self._herd_instances: dict[int, HerdInstances] = {}
        if options.overlays:
            self.state.options = replace(self.state.options, footprints="footprints" in options.overlays,
                                         targets="targets" in options.overlays, support="support" in options.overlays)
        _, _, vw, vh = self._scene_viewport()
        if vw > 0 and vh > 0:  # frame the creature for the part of the window the scene gets
            self.state.aspect = vw / vh
            self.state.frame_view()
        self.monitor = GaitMonitor()
        self.panel = PanelContext(presets=options.presets, scale=self.scale, icons=icons, monitor=self.monitor,
                                  file_dialog=FileDialog(), dialogs_available=dialogs_available(),
                                  open_at_start=options.panels)
        self.recording: Recording | None = None
        self._pick: tuple[float, float] | None = None
        self._click_start: tuple[float, float] | None = None  # where the left button went down
        self._dragging = False  # the left button, down, has moved beyond CLICK_SLOP: an orbit
        self._press: tuple[np.ndarray, int | None, tuple[float, float], int] | None = None  # waypoint press
        self.frame_times: list[tuple[float, float, float, float, bool]] = []  # simulate, scene, ui, frame, synced
        self.extra_panels: tuple = ()
        self._next: FrameContent | None = None  # the next frame, solved while the GL draws this one
        self._dumped = 0.0  # when the state dump was last written (perf_counter seconds)

    # -- input ------------------------------------------------------------------------

    def _shortcuts(self) -> None:
        state, io = self.state, imgui.get_io()
        if io.want_text_input:
            return
        pressed = lambda key, repeat=False: imgui.is_key_pressed(key, repeat)
        if pressed(imgui.Key.space):
            state.toggle_play()
        down = imgui.is_key_down
        if state.driver is None and (pressed(imgui.Key.w) or pressed(imgui.Key.up_arrow)) and not io.key_ctrl:
            state.start_driving()
        if state.driver is not None:
            throttle = float(down(imgui.Key.w) or down(imgui.Key.up_arrow)) - float(
                down(imgui.Key.s) or down(imgui.Key.down_arrow))
            steer = float(down(imgui.Key.a) or down(imgui.Key.left_arrow)) - float(
                down(imgui.Key.d) or down(imgui.Key.right_arrow))
            state.drive_input = (0.0, 0.0) if io.key_ctrl else (throttle, steer)
            if pressed(imgui.Key.escape) and not state.show_help:
                state.stop_driving()
        elif pressed(imgui.Key.right_arrow, True):
            state.step_frame()
        if pressed(imgui.Key.r) and not io.key_ctrl:
            state.default_view()
        if io.key_ctrl and (pressed(imgui.Key.y, True) or (io.key_shift and pressed(imgui.Key.z, True))):
            state.redo()
        elif io.key_ctrl and pressed(imgui.Key.z, True):
            state.undo()
        if pressed(imgui.Key.f12):
            state.screenshot_requested = True
            state.screenshot_with_ui = io.key_shift
        if pressed(imgui.Key.g):
            state.record_requested = True
        if pressed(imgui.Key.tab):
            state.show_ui = not state.show_ui
        if pressed(imgui.Key.f1):
            state.show_help = not state.show_help
        if pressed(imgui.Key.escape):
            state.show_help = False

    def _mouse(self, view_height: float) -> None:
        state, io = self.state, imgui.get_io()
        if io.want_capture_mouse:
            return
        dx, dy = io.mouse_delta.x, io.mouse_delta.y
        if imgui.is_mouse_clicked(0):
            self._click_start = (io.mouse_pos.x, io.mouse_pos.y)
            self._dragging = False
        if imgui.is_mouse_down(0) and not self._dragging:
            # A press is a click until it moves beyond the slop, however few frames that
            # takes (a jump read in the press's own frame is not a drag).
            self._dragging = self._moved_since_press()
            dx = dy = 0.0
        if state.waypoint_edit and self._edit_waypoints():
            pass  # the mouse edited the route
        elif len(state.names) > 1 and imgui.is_mouse_released(0) and self._click_selects():
            pass  # a click on another creature put it in the panels
        elif imgui.is_mouse_double_clicked(0):
            self._pick = (io.mouse_pos.x, io.mouse_pos.y)
        elif imgui.is_mouse_down(0) and self._dragging and (dx or dy):
            state.orbit(dx, dy)
        if (imgui.is_mouse_down(1) or imgui.is_mouse_down(2)) and (dx or dy):
            state.pan(dx, dy, view_height)
        if io.mouse_wheel:
            state.zoom(io.mouse_wheel)

    def _mouse_in_view(self) -> tuple[tuple[float, float], float] | None:
        """The mouse as a point of the 3-D view (x, y in -1..1) and the view's aspect, or
        None when it is off the view."""
        io = imgui.get_io()
        vx, vy, vw, vh = self._scene_viewport()
        fb_w, fb_h = self.window.framebuffer_size
        win_w, win_h = self.window.window_size
        x = io.mouse_pos.x * fb_w / max(win_w, 1)
        y = fb_h - io.mouse_pos.y * fb_h / max(win_h, 1)
        if not (vx <= x < vx + vw and vy <= y < vy + vh) or vw <= 0 or vh <= 0:
            return None
        return (2.0 * (x - vx) / vw - 1.0, 2.0 * (y - vy) / vh - 1.0), vw / vh

    def _mouse_ray(self) -> tuple[np.ndarray, np.ndarray] | None:
        """The eye ray (origin, unit direction) under the mouse, or None off the 3-D view."""
        where = self._mouse_in_view()
        return None if where is None else eye_ray(self.state.camera, where[1], where[0])

    def _moved_since_press(self) -> bool:
        """Whether the mouse is more than :data:`CLICK_SLOP` pixels from where the left
        button went down (no press known: it has)."""
        io, start = imgui.get_io(), self._click_start
        return start is None or (io.mouse_pos.x - start[0]) ** 2 + (io.mouse_pos.y - start[1]) ** 2 > CLICK_SLOP ** 2

    def _click_selects(self) -> bool:
        """A click (no drag) on a scene creature other than the selected one selects it."""
        if self._dragging or self._moved_since_press():
            return False  # a drag (orbit), not a click
        ray = self._mouse_ray()
        index = None if ray is None else self.state.pick_creature(*ray)
        if index is None or index == self.state.selected:
            return False
        return self.state.select(index)

    def _creature_screen_points(self) -> list[list[float]]:
        """Each scene creature's root in window pixels (x, y from the top left), file order."""
        vx, vy, vw, vh = self._scene_viewport()
        fb_w, fb_h = self.window.framebuffer_size
        win_w, win_h = self.window.window_size
        vp = np.array(self.state.camera.view_proj(vw / max(vh, 1)), dtype=np.float64)
        out = []
        for session in self.state.sessions:
            clip = vp @ np.append(session.live.pose().root[:3, 3], 1.0)
            ndc = clip[:2] / clip[3] if clip[3] > 1e-9 else np.array([9.0, 9.0])
            x = (vx + (ndc[0] + 1.0) * 0.5 * vw) * win_w / max(fb_w, 1)
            y = (fb_h - (vy + (ndc[1] + 1.0) * 0.5 * vh)) * win_h / max(fb_h, 1)
            out.append([float(x), float(y)])
        return out

    def _ground_under_mouse(self) -> np.ndarray | None:
        """The ground point (x, y, z) under the mouse, or None (the sky, or off the view)."""
        where = self._mouse_in_view()
        if where is None:
            return None
        point = ground_point(self.state.camera, where[1], where[0], self.state.world.terrain.height)
        # Only the ground that is drawn: it fades into the horizon a few body sizes away.
        rig = self.state.live.rig
        root = self.state.pose().root[:3, 3]
        if point is None or np.linalg.norm((point - root)[[0, 2]]) > 5.0 * (rig.body_length + rig.hip_height):
            return None
        return point

    def _edit_waypoints(self) -> bool:
        """Waypoint editing on the ground: a click adds one, a drag from one moves it, a
        right-click deletes the nearest. True when the mouse did one of these (no orbit);
        a drag that starts away from every waypoint orbits as usual."""
        state, io = self.state, imgui.get_io()
        grab = 0.35 * state.live.rig.body_length  # m: how near a waypoint a press takes it
        mouse = (io.mouse_pos.x, io.mouse_pos.y)
        if imgui.is_mouse_clicked(0):
            point = self._ground_under_mouse()
            if point is None:
                self._press = None
                state.error = "no ground under the cursor: click on the ground to add a waypoint"
                return True
            self._press = (point, state.nearest_waypoint(point[0], point[2], grab), mouse, len(state.waypoints))
            return self._press[1] is not None
        if self._press is None:
            if imgui.is_mouse_clicked(1):
                point = self._ground_under_mouse()
                index = None if point is None else state.nearest_waypoint(point[0], point[2], grab)
                if index is not None:
                    state.delete_waypoint(index)
                    return True
            return False
        point, index, start, count = self._press
        moved = (mouse[0] - start[0]) ** 2 + (mouse[1] - start[1]) ** 2 > CLICK_SLOP ** 2
        if imgui.is_mouse_down(0):
            if index is not None and len(state.waypoints) != count:
                self._press = (point, None, start, count)  # a waypoint was reached meanwhile: the drag ends
                return True
            if index is not None and moved:
                here = self._ground_under_mouse()
                if here is not None:
                    state.move_waypoint(index, float(here[0]), float(here[2]))
            return index is not None
        self._press = None  # released
        if index is None and not moved:
            state.add_waypoint(float(point[0]), float(point[2]))
        return True

    def _scene_viewport(self) -> tuple[int, int, int, int]:
        fb_w, fb_h = self.window.framebuffer_size
        if not self.state.show_ui:
            return (0, 0, fb_w, fb_h)
        win_w = max(self.window.window_size[0], 1)
        left = int(round(SIDEBAR_WIDTH * self.scale * fb_w / win_w))
        left = min(left, max(fb_w - 1, 0))
        return (left, 0, fb_w - left, fb_h)

    def _backdrop(self, viewport: tuple[int, int, int, int]) -> Backdrop | None:
        """The sidebar's strip left of the 3-D view, filled under the panels (they draw no
        background); none when the UI is hidden. In a multisampled window the sidebar
        is drawn every frame (a layer cannot be copied into it), over its own fill."""
        if viewport[0] <= 0:
            return None
        if self.options.samples > 0:
            r, g, b = SIDEBAR_COLOR
            self.ctx.screen.clear(r, g, b, 1.0, viewport=(0, 0, viewport[0], self.window.framebuffer_size[1]))
            return None
        return Backdrop(viewport[0], SIDEBAR_COLOR)

    def _resolve_pick(self, viewport: tuple[int, int, int, int]) -> None:
        """Focus on the scene point under a double-click (depth read back), or the creature."""
        if self._pick is None:
            return
        fb_w, fb_h = self.window.framebuffer_size
        win_w, win_h = self.window.window_size
        x = int(self._pick[0] * fb_w / max(win_w, 1))
        y = int(fb_h - 1 - self._pick[1] * fb_h / max(win_h, 1))
        self._pick = None
        vx, vy, vw, vh = viewport
        if not (vx <= x < vx + vw and vy <= y < vy + vh):
            return
        depth = np.frombuffer(self.ctx.screen.read(viewport=(x, y, 1, 1), components=1, attachment=-1, dtype="f4"),
                              dtype="f4")[0]
        if depth >= 1.0:
            self.state.focus(None)
            return
        ndc = np.array([2 * (x - vx) / vw - 1, 2 * (y - vy) / vh - 1, 2 * depth - 1, 1.0])
        inverse = np.linalg.inv(np.array(self.state.camera.view_proj(vw / vh), dtype=np.float64))
        world = inverse @ ndc
        self.state.focus(point3(world[:3] / world[3]))

    def _instances(self, pose: Pose) -> SceneInstances:
        """What the 3-D view draws this frame: every creature of the scene, their herds,
        the selected one's key-pose ghosts and arcs (one set, as recordings draw)."""
        state = self.state
        options = state.options
        joints, skin, by_side = options.joint_markers, options.body == "skin", options.side_colors
        creatures = [(pose, state.live.rig), *((other, session.live.rig) for other, session in state.creature_poses())]
        parts = []
        for p, rig in creatures:
            shapes = pose_instances(p, rig, joints, parts=not skin, by_side=by_side)
            if skin:
                shapes = replace(shapes, bodies=(pose_body(p, rig, shared_body_cache(), live=True),))
            parts.append(shapes)
        for session in state.sessions:
            if session.herd is None:
                continue
            cached = self._herd_instances.get(id(session.herd))
            if cached is None or not cached.matches(joints, options.body, by_side):
                cached = self._herd_instances[id(session.herd)] = HerdInstances(session.herd, joints, options.body,
                                                                                by_side)
            terrain = session.world.terrain
            parts.append(cached.frame(session.herd, None if terrain.flat else terrain.height))
        parts += [ghost_instances(ghost, state.live.rig, color)
                  for ghost, color in zip(state.ghost_poses(), KEY_POSE_COLORS)]
        if state.options.arcs:
            trails, beads = state.arcs.trails()
            parts.append(arc_instances(trails, beads, 0.012 * state.live.rig.hip_height))
        return frame_instances(parts)

    # -- outputs ----------------------------------------------------------------------

    def _read_window(self, viewport: tuple[int, int, int, int] | None = None) -> np.ndarray:
        fb_w, fb_h = self.window.framebuffer_size
        x, y, w, h = viewport or (0, 0, fb_w, fb_h)
        data = self.ctx.screen.read(viewport=(x, y, w, h), components=3, alignment=1)
        return np.frombuffer(data, dtype=np.uint8).reshape(h, w, 3)[::-1]

    def _screenshot(self, path: Path | None = None, viewport: tuple[int, int, int, int] | None = None) -> None:
        """Save the window (or just ``viewport``, the 3-D view) as PNG."""
        state = self.state
        state.screenshot_requested = False
        state.screenshot_with_ui = False
        if path is None:
            stamp = time.strftime("%Y%m%d-%H%M%S")
            path = Path(state.record.folder) / f"gaitlab-{state.spec.name}-{stamp}.png"
            count = 2
            while path.exists():  # two in one second
                path = path.with_name(f"gaitlab-{state.spec.name}-{stamp}-{count}.png")
                count += 1
        fb_w, fb_h = self.window.framebuffer_size
        if fb_w <= 0 or fb_h <= 0:
            return
        try:
            write_png(path, self._read_window(viewport))
        except GaitlabError as exc:
            state.error = str(exc)
            return
        state.status = f"screenshot saved: {Path(path).resolve()}"

    def _record_step(self) -> None:
        state = self.state
        if state.record_requested and self.recording is None:
            state.record_requested = False
            try:
                if state.confirm_record():
                    self.recording = Recording(state.record_request(), self.ctx)
            except GaitlabError as exc:
                state.error = str(exc)
        if self.recording is None:
            self.panel.recording_progress = None
            return
        job = self.recording
        try:
            job.step(2)
            if job.finished:
                result = job.finish()
                self.recording = None
                state.recorded(result.path)
                state.status = (f"wrote {Path(result.path).resolve()}: {result.frames} frames, {result.seconds:.2f} s"
                                + "".join(f"; note: {note}" for note in result.notes))
                state.error = None
        except GaitlabError as exc:
            self.recording = None
            state.error = str(exc)
        if self.recording is not None:
            self.panel.recording_progress = job.progress
            self.panel.recording_label = f"recording {job.done}/{job.total}"
        else:
            self.panel.recording_progress = None

    def _dump(self, path: Path, frame: int) -> None:
        state = self.state
        doc = {
            "frame": frame, "playing": state.playing, "show_ui": state.show_ui, "show_help": state.show_help,
            "creature": state.spec.to_dict(), "model_bones": state.bones_from_model,
            "duty_factor": state.get("gait.duty_factor"),
            "gait": state.spec.gait.preset, "clock": state.live.clock, "time": state.live.time,
            "camera": {"target": list(state.camera.target), "azimuth": state.camera.azimuth,
                       "elevation": state.camera.elevation, "distance": state.camera.distance,
                       "ortho": state.camera.ortho},
            "error": state.error, "status": state.status,
            "root": [float(v) for v in state.pose().root[:3, 3]], "travel": state.live.travel,
            "terrain": state.world.terrain.describe(), "planted_jump_max": state.planted_jump_max,
            "waypoints": [list(p) for p in state.waypoints], "path": state.world.path.describe(),
            "path_panel": {"kind": state.path_kind, **state.path_values[state.path_kind]},
            "herd": 1 if state.herd is None else state.herd.count + 1,
            "scene": state.names, "selected": state.selected, "screen": self._creature_screen_points(),
            "arcs": {joint: int(points.shape[0]) for joint, points in state.arcs.trails()[0].items()},
            "arc_beads": int(sum(len(b) for b in state.arcs.trails()[1].values())),
            "ghosts": len(state.ghost_poses()),
            "drive": None if state.driver is None else {
                "speed": state.driver.ground_speed, "target": state.driver.target_speed,
                "froude": state.driver.ground_froude, "gait": state.driver.gait,
                "curvature": state.driver.curvature},
            "measured": None if self.monitor.report is None else self.monitor.report.to_json(),
            "window": {"size": list(self.window.window_size), "framebuffer": list(self.window.framebuffer_size)},
            "widgets": {k: list(v) for k, v in state.widget_rects.items()},
        }
        atomic_write_text(path, json.dumps(doc, indent=1))

    # -- loop -------------------------------------------------------------------------

    def run(self) -> int:
        """The window's loop until it closes (or, scripted, for ``frames`` frames)."""
        frames = self.options.frames
        frame = 0
        while not self.window.should_close and (frames is None or frame < frames):
            self._frame(frame, last=frames is not None and frame == frames - 1)
            frame += 1
        if self.options.dump_state is not None:
            self._dump(self.options.dump_state, frame)
        if self.recording is not None:
            self.recording.cancel()
        if self.options.report_fps:
            self.report()
        return 0

    def _frame(self, frame: int, last: bool) -> None:
        """One frame: input, the 3-D view, the UI, the next frame's motion, outputs, swap;
        timed. With ``--report-fps`` every 8th frame waits for the GL after each stage to
        time it; the other frames run freely and give the frame rate.

        The 3-D view is handed to the GL (flushed) before the UI is built, and the UI
        before the next frame's motion is solved, so a software renderer rasterises on its
        threads while Python works. The next frame is solved after this frame's UI, so an
        edit made in the UI shows in the next frame, as it would if it were solved at that
        frame's start; its shadow map is cast at once, so it is ready when that frame's
        view is drawn (its creatures read it)."""
        opts, state, window, clock = self.options, self.state, self.window, time.perf_counter
        start = clock()
        dt = window.begin_frame(FRAME_DT if opts.frames is not None else None)
        fb_w, fb_h = window.framebuffer_size
        minimized = fb_w <= 0 or fb_h <= 0
        imgui.new_frame()
        self._shortcuts()
        viewport = self._scene_viewport()
        self._mouse(max(viewport[3], 1))
        sync = opts.report_fps and frame % 8 == 0
        t0 = clock()
        content = self._next if self._next is not None else self._prepare(dt)
        self._next = None
        t1 = clock()
        if not minimized and viewport[2] > 0:
            self._draw_view(content, viewport, sync)
            window.flush()
        t2 = clock()
        draw_ui(state, self.panel, self.extra_panels)
        imgui.render()
        if not minimized:
            self.ui.render(imgui.get_draw_data(), self.ctx.screen, self._backdrop(viewport))
            window.flush()
            if sync:
                self.ctx.finish()
        t3 = clock()
        if not last:
            self._next = self._prepare(dt)
        t4 = clock()
        if self._next is not None and not minimized and viewport[2] > 0:
            self._next = replace(self._next, cast=self.scene.cast(
                self._next.instances, self._next.ground.terrain, self.state.camera, viewport, self.state.options))
            if sync:
                self.ctx.finish()
        t5 = clock()
        self._outputs(frame, last, minimized)
        if minimized:
            time.sleep(0.05)  # nothing to draw: do not spin
        else:
            window.swap()
        self._time(start, (t1 - t0) + (t4 - t3), (t2 - t1) + (t5 - t4), t3 - t2, clock(), sync)

    def _prepare(self, dt: float) -> FrameContent:
        """Move the scene on by ``dt`` and gather what its next frame draws."""
        pose = self._simulate(dt)
        state = self.state
        return FrameContent(self._instances(pose), state.ground(pose), state.overlays(pose))

    def _simulate(self, dt: float) -> Pose:
        """Move the scene on by ``dt`` and return the selected creature's pose to draw.
        The motion is sampled at a fixed rate while the Plots panel measures it (it asked
        last frame), once per frame otherwise."""
        state = self.state
        state.fine_sampling = self.monitor.wanted or self.options.dump_state is not None
        state.advance(dt)
        sampled = self.monitor.record_samples(state.live.rig, state.world, state.take_samples(),
                                              state.live.frequency)
        # The last sample is this frame's pose (unless two wave shapes are cross-fading).
        if sampled is not None and not state.live.cross_fading:
            pose = sampled.pose(sampled.frame_count - 1)
        else:
            pose = state.pose()
        if not (state.waypoint_edit and self._press is not None):  # the camera holds still under a waypoint press
            state.follow_creature(dt, pose)
        state.note_pose(pose)
        if self.options.dump_state is not None:
            self.monitor.measure(state.live.time)  # in step with the dumped state
        elif self.monitor.wanted:
            self.monitor.update(state.live.time)  # in a worker process: never stalls a frame
        self.monitor.wanted = False
        return pose

    def _draw_view(self, content: FrameContent, viewport: tuple[int, int, int, int], sync: bool) -> None:
        """The 3-D view."""
        state = self.state
        state.aspect = viewport[2] / max(viewport[3], 1)
        self.ctx.screen.use()
        self.scene.draw_instances(content.instances, content.ground, state.camera, self.ctx.screen,
                                  state.options, viewport, multisampled=self.options.samples > 0,
                                  overlays=content.overlays, clear_target=True, cast=content.cast)
        self._resolve_pick(viewport)
        if state.screenshot_requested and not state.screenshot_with_ui:
            self._screenshot(viewport=viewport)  # the 3-D view alone, before the UI
        if sync:
            self.ctx.finish()

    def _outputs(self, frame: int, last: bool, minimized: bool) -> None:
        """Screenshots, the recording's next frames and the state dump."""
        if self.state.screenshot_requested and not minimized:
            self._screenshot()
        if last and self.options.screenshot is not None and not minimized:
            self._screenshot(self.options.screenshot)
        self._record_step()
        now = time.perf_counter()
        if self.options.dump_state is not None and (frame % 20 == 0 or last or now - self._dumped >= DUMP_EVERY):
            self._dump(self.options.dump_state, frame)
            self._dumped = now

    def _time(self, start: float, simulate: float, scene: float, ui: float, end: float, sync: bool) -> None:
        """Keep the frame's timings (seconds spent simulating, drawing the scene and the
        UI; for --report-fps) and the HUD's averages."""
        self.frame_times.append((simulate, scene, ui, end - start, sync))
        s = self.panel.stats
        s.frame_ms = _ema(s.frame_ms, (end - start) * 1000)
        s.fps = 1000.0 / max(s.frame_ms, 1e-3)
        s.simulate_ms = _ema(s.simulate_ms, simulate * 1000)
        s.scene_ms = _ema(s.scene_ms, scene * 1000)
        s.ui_ms = _ema(s.ui_ms, ui * 1000)

    def report(self) -> None:
        """Print the frame rate (median over free-running frames) and the time split
        (medians over the frames that waited for the GPU after each stage)."""
        times = self.frame_times[10:] or self.frame_times
        free = [t for t in times if not t[4]] or times
        synced = [t for t in times if t[4]] or times
        if not times:
            return
        frame_ms = statistics.median(t[3] for t in free) * 1000
        split = [statistics.median(t[i] for t in synced) * 1000 for i in range(3)]
        rest = statistics.median(t[3] - t[0] - t[1] - t[2] for t in synced) * 1000  # per frame: never below 0
        fb_w, fb_h = self.window.framebuffer_size
        print(f"viewer {fb_w}x{fb_h}, UI {'shown' if self.state.show_ui else 'hidden'}: {1000 / frame_ms:.1f} fps "
              f"(median frame {frame_ms:.2f} ms over {len(free)} frames); split over {len(synced)} synced frames: "
              f"simulate {split[0]:.2f}, draw scene {split[1]:.2f}, draw UI {split[2]:.2f}, "
              f"swap and rest {rest:.2f} ms")

    def close(self) -> None:
        if self.recording is not None:
            self.recording.cancel()
        self.monitor.close()
        self.ui.release()
        self.scene.release()
        implot.destroy_context(self.implot_ctx)
        imgui.destroy_context(self.imgui_ctx)
        self.window.close()


def run_viewer(cast: Cast, options: ViewerOptions) -> int:
    """Open the viewer on the cast (one creature, or a scene's); returns the exit status."""
    viewer = Viewer(cast, options)
    try:
        return viewer.run()
    finally:
        viewer.close()


if __name__ == "__main__":  # pragma: no cover
    from ..cast import Actor
    from ..spec import load_creature

    sys.exit(run_viewer((Actor(load_creature("dog")),), ViewerOptions()))
