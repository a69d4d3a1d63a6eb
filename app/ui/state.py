"""The viewer's state and everything its controls do — no imgui, no OpenGL.

Panels (``app/ui/panels.py``) only draw widgets and call these methods, so the logic of
every control is unit-tested without a window. Edits go through
:meth:`CreatureSpec.with_overrides`, so the UI accepts exactly what a creature file
accepts; a rejected value leaves the creature unchanged and shows the error.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any, Literal

import numpy as np
from numpy.typing import NDArray

from ..choices import DEFAULT_ANTIALIAS, Antialias
from ..errors import GaitlabError
from ..gaits import GAIT_PRESETS
from ..kinematics.arcs import ArcTrail
from ..kinematics.drive import Driver
from ..kinematics.ghosts import key_pose_ghosts, shift_pose
from ..kinematics.poses import reference_foot
from ..kinematics.herd import Herd
from ..kinematics.live import LiveMotion
from ..kinematics.overlays import (FootprintTrail, inside_polygon, planted_points, support_polygon,
                                   touchdown_targets, trunk_centre)
from ..kinematics.motion import Pose
from ..kinematics.path import Path as GroundPath
from ..kinematics.path import SplicedPath, StraightPath, WaypointPath
from ..kinematics.roll import contact_points, roll_part
from ..kinematics.world import World
from ..export import export_clip
from ..export.formats import ExportFormat
from ..output import DEFAULT_CRF, DEFAULT_GIF_QUALITY, MAX_CRF, GifQuality
from ..recording import RecordRequest
from ..render.camera import (CAMERA_PRESETS, CHASE_LOOK_AHEAD, DEFAULT_CAMERA, Camera, clear_elevations, frame_points,
                             look_ahead)
from ..render.clip import ViewSettings
from ..render.overlays import Overlays
from ..render.renderer import GroundView, RenderOptions, nice_grid_spacing
from ..render.scene import leg_colors
from ..resources import creatures_dir
from ..rigging import apply_style, build_rig
from ..styles import DEFAULT_TIMING_FPS, style_heights
from ..spec import (LEG_TYPE_SHAPES, CreatureSpec, GaitSpec, LegType, leg_type, load_creature, spec_value,
                    without_adjustment)

def is_shipped(path: str | Path) -> bool:
    """Whether ``path`` is one of Gaitlab's preset creature files: in the installed
    presets' folder, or in any folder that holds the whole set (a source checkout's
    ``creatures/``, whichever copy is installed)."""
    try:
        folder = Path(path).resolve().parent
        if folder == creatures_dir().resolve():
            return True
        presets = {p.name for p in creatures_dir().glob("*.toml")}
        return Path(path).name in presets and presets <= {p.name for p in folder.glob("*.toml")}
    except OSError:
        return False


FRAME_DT = 1.0 / 60.0
SAMPLE_RATE = 240.0  # Hz: how often the live gait measurement samples the motion
UNDO_DEPTH = 200  # edits kept for undo
UNDO_MERGE_SECONDS = 0.75  # changes of one control closer together than this are one edit (a drag)  # the single-step size, and the fixed step of scripted runs
RecordFormat = Literal["gif", "mp4"]
LengthUnit = Literal["cycles", "seconds"]

# Gait keys whose value, when not set in the file, comes from the gait preset: the UI shows
# the resolved number.
_RESOLVED = {"gait.frequency", "gait.duty_factor", "gait.bias", "gait.step_height", "gait.stride",
             "gait.front_back", "gait.left_right", "motion.bob"}


@dataclass
class RecordSettings:
    """The Record panel: what to write and how (same meaning as ``gaitlab render``)."""

    format: RecordFormat = "gif"
    unit: LengthUnit = "cycles"
    length: float = 2.0
    width: int = 480
    height: int = 360
    fps: float = 25.0
    camera: str = DEFAULT_CAMERA
    folder: str = "."
    name: str = ""  # default: <creature>.<format>
    gif_quality: GifQuality = DEFAULT_GIF_QUALITY
    crf: int = DEFAULT_CRF
    antialias: Antialias = DEFAULT_ANTIALIAS
    export_format: ExportFormat = "glb"  # File panel: the skeleton's motion as BVH, glTF or USD

    def path(self, creature: str) -> Path:
        return Path(self.folder) / f"{self.name or creature}.{self.format}"


@dataclass
class SceneMember:
    """A creature of the scene other than the one in the panels: what selecting it brings
    back (its creature as loaded and as edited, its motion and path, its history)."""

    base: CreatureSpec
    spec: CreatureSpec
    live: LiveMotion
    world: World
    file_path: str = ""
    undo: list = field(default_factory=list)
    redo: list = field(default_factory=list)
    herd: Herd | None = None
    waypoints: list = field(default_factory=list)
    waypoint_s: list = field(default_factory=list)
    path_kind: str = "straight"



@dataclass
class ViewerState:
    """Everything the viewer shows and edits."""

    base: CreatureSpec  # the creature as loaded: what "reset" goes back to
    world: World = field(default_factory=World)  # where it walks (path and terrain)
    spec: CreatureSpec = field(init=False)
    live: LiveMotion = field(init=False)
    playing: bool = True
    time_scale: float = 1.0
    camera: Camera = field(default_factory=Camera)
    camera_preset: str = DEFAULT_CAMERA
    follow: bool = True
    options: RenderOptions = field(default_factory=RenderOptions)
    show_ui: bool = True
    show_help: bool = False
    error: str | None = None
    status: str = ""
    file_path: str = ""
    record: RecordSettings = field(default_factory=RecordSettings)
    aspect: float = 16.0 / 9.0
    screenshot_requested: bool = False
    screenshot_with_ui: bool = False  # F12: the 3-D view alone; Shift+F12: the whole window
    record_requested: bool = False
    widget_rects: dict[str, tuple[float, float, float, float]] = field(default_factory=dict)
    samples: list[dict] = field(default_factory=list, repr=False)  # sub-step inputs for the gait monitor
    fine_sampling: bool = True  # sub-step at SAMPLE_RATE (the viewer turns it off while nobody measures)
    _follow_height: float | None = field(default=None, init=False, repr=False)  # camera target above the root
    _heading: float | None = field(default=None, init=False, repr=False)  # path heading last frame (degrees)
    _follow_ahead: float = field(default=0.0, init=False, repr=False)  # m the camera aims ahead of the root
    _elevation: float | None = field(default=None, init=False, repr=False)  # the user's camera elevation
    _confirm_overwrite: str | None = field(default=None, init=False, repr=False)  # asked once to overwrite this
    reset_pending: bool = False  # "reset everything" asked once
    recent: list[str] = field(default_factory=list)  # files saved or loaded this session, newest first
    message: tuple[str, str, str] | None = field(default=None, init=False)  # (kind, text, time) shown in the bar
    terrain_kind: str = field(default="flat", init=False)  # the Terrain panel's kind and values
    terrain_values: dict[str, dict[str, Any]] = field(default_factory=dict, init=False)
    footprints: FootprintTrail = field(default_factory=FootprintTrail, init=False, repr=False)
    arcs: ArcTrail = field(default_factory=ArcTrail, init=False, repr=False)
    show_ghosts: bool = False  # the key poses of the current step drawn faintly along the path
    _ghosts: tuple | None = field(default=None, init=False, repr=False)
    _style_check: tuple | None = field(default=None, init=False, repr=False)
    waypoints: list[tuple[float, float]] = field(default_factory=list, init=False)  # (x, z) the route goes through
    waypoint_edit: bool = False  # mouse on the ground: click adds, drag moves, right-click deletes
    path_values: dict[str, dict[str, Any]] = field(default_factory=lambda: {
        "straight": {}, "circle": {"r": 2.0, "dir": "left"}, "figure-eight": {"r": 2.0}, "waypoints": {}},
        init=False)
    path_kind: str = field(default="straight", init=False)
    _waypoint_s: list[float] = field(default_factory=list, init=False, repr=False)
    planted_jump: float = field(default=0.0, init=False)  # m a planted foot moved last frame (see note_pose)
    planted_jump_max: float = field(default=0.0, init=False)
    _last_pose: Pose | None = field(default=None, init=False, repr=False)
    driver: Driver | None = field(default=None, init=False)  # drive mode: W/S speed, A/D turn
    herd: Herd | None = field(default=None, init=False)  # more animals of the creature's kind following it
    members: list[SceneMember | None] = field(default_factory=list, init=False)  # a scene's creatures (None: selected)
    selected: int = field(default=0, init=False)  # which of them the panels show
    drive_input: tuple[float, float] = (0.0, 0.0)  # held keys: throttle (S -1 .. W 1), steer (D -1 .. A 1)
    _undo: list[CreatureSpec] = field(default_factory=list, init=False, repr=False)
    _redo: list[CreatureSpec] = field(default_factory=list, init=False, repr=False)
    _last_edit: tuple[str, float] = field(default=("", 0.0), init=False, repr=False)  # key(s), when

    def __setattr__(self, name: str, value: Any) -> None:
        super().__setattr__(name, value)
        # One message line: each new status or error replaces the last, stamped with the
        # time; clearing an error clears its message (never a stale one).
        if name in ("error", "status"):
            if value:
                super().__setattr__("message", ("error" if name == "error" else "ok", str(value),
                                                time.strftime("%H:%M:%S")))
            elif name == "error" and getattr(self, "message", None) and self.message[0] == "error":
                super().__setattr__("message", None)

    def __post_init__(self) -> None:
        if not isinstance(self.world.path, StraightPath):  # a turning path: show where it is going
            self.options = replace(self.options, path=True)
        self.spec = self.base
        self.live = LiveMotion(build_rig(self.base), self.world)
        self.file_path = self._save_path_for(self.base)
        self._init_terrain_values()
        self.frame_view()

    # -- reading values ---------------------------------------------------------------

    def get(self, key: str) -> Any:
        """The value a control shows: the file's value, or the number the gait preset
        gives when the file leaves it open (e.g. the duty factor of a preset gait)."""
        gait = self.live.rig.gait
        if key.startswith("poses.") or key == "gait.frames_per_cycle":
            value = spec_value(self.spec, key)
            return value if value is not None else self._resolved_pose(key)
        if key in _RESOLVED or key.startswith("gait.phases."):
            if key.startswith("gait.phases."):
                return float(gait.offsets[self.live.rig.leg_names.index(key.rsplit(".", 1)[1])])
            if key in ("gait.front_back", "gait.left_right"):
                value = spec_value(self.spec, key)
                if value is not None:
                    return value
                preset = self.spec.gait.preset_spec
                return getattr(preset, key.split(".")[1]) if preset.symmetric else 0.0
            return {"gait.frequency": gait.frequency, "gait.duty_factor": gait.duty_factor, "gait.bias": gait.bias,
                    "gait.step_height": gait.step_height, "gait.stride": gait.stride, "motion.bob": gait.bob}[key]
        return spec_value(self.spec, key)

    def _resolved_pose(self, key: str) -> Any:
        """A key pose value the file leaves open: as the creature walks it; a height of a
        creature whose bob is not keyed shows the normal style's (where editing starts)."""
        rig = self.live.rig
        poses = rig.poses
        if key == "gait.frames_per_cycle":
            return (self.spec.gait.timing_fps or DEFAULT_TIMING_FPS) / rig.gait.frequency
        if key == "poses.style":
            return "normal"
        names = ("contact_height", "down_height", "pass_height", "up_height")
        name = key.split(".", 1)[1]
        if name in names:
            heights = poses.heights if poses.heights is not None else style_heights("normal", rig.hip_height)
            return float(heights[names.index(name)])
        return float(np.degrees({"foot_angle": poses.foot_angle, "arm_swing": poses.arm_swing,
                                 "torso_lean": poses.torso_lean}[name]))

    @property
    def style_edited(self) -> bool:
        """Whether the key poses differ from their style's values (the button shows a *)."""
        style = self.spec.poses.style
        if style is None:
            return False
        cached = self._style_check
        if cached is None or cached[0] is not self.spec:
            try:
                mine, styled = build_rig(self.spec), build_rig(apply_style(self.spec, style))
                a, b = mine.poses, styled.poses
                edited = (a.heights is None or not np.allclose(a.heights, b.heights, atol=1e-4)
                          or not np.allclose([a.foot_angle, a.arm_swing, a.torso_lean, mine.gait.stride],
                                             [b.foot_angle, b.arm_swing, b.torso_lean, styled.gait.stride], atol=1e-4))
            except GaitlabError:
                edited = True
            cached = self._style_check = (self.spec, edited)
        return cached[1]

    def set_style(self, name: str) -> bool:
        """Start the key poses from a walk style (its heights, angles and stride)."""
        try:
            spec = apply_style(self.spec, name)
        except GaitlabError as exc:
            self.error = str(exc)
            return False
        return self._apply(spec, edit="style")

    def base_value(self, key: str) -> Any:
        return spec_value(self.base, key)

    def is_modified(self, key: str) -> bool:
        """True when ``key`` differs from the loaded creature (the reset button is live)."""
        return spec_value(self.spec, key) != spec_value(self.base, key)

    @property
    def creature_label(self) -> str:
        """The creature's name, with a * once it differs from the loaded one."""
        return self.spec.name + ("*" if self.spec != self.base else "")

    @property
    def gait_label(self) -> str:
        """The gait preset's name, with a * once any of its values is adjusted."""
        gait = self.spec.gait
        return gait.preset + ("*" if gait != GaitSpec(preset=gait.preset, wave=gait.wave) else "")

    @property
    def gait_is_symmetric(self) -> bool:
        return self.spec.gait.preset_spec.symmetric and self.spec.gait.phases is None

    # -- editing ----------------------------------------------------------------------

    def _apply(self, spec: CreatureSpec, blend: bool = True, edit: str | None = "") -> bool:
        """Walk with ``spec`` from now on; a creature the world cannot take (a path too tight
        for it) keeps the current one and shows why. ``edit`` names the change for undo
        (consecutive changes of one slider within a moment are one step); ``None`` for
        changes that are not edits (undo itself, loading)."""
        previous = self.spec
        try:
            rig = build_rig(spec)
            if self.driver is not None:  # the speed picks the gait; the rest of the creature applies
                self.driver.set_rig(rig)
            else:
                self.live.set_rig(rig, blend=blend)
            if self.herd is not None:
                self.herd.set_rig(rig)
        except GaitlabError as exc:
            self.error = str(exc)
            return False
        self.spec = spec
        self.error = None
        if edit is not None and spec != previous:
            now = time.monotonic()
            same_drag = edit and edit == self._last_edit[0] and now - self._last_edit[1] < UNDO_MERGE_SECONDS
            if not same_drag:
                self._undo.append(previous)
                del self._undo[:-UNDO_DEPTH]
            self._redo.clear()
            self._last_edit = (edit, now)
        return True

    def undo(self) -> bool:
        """Take back the last edit (Ctrl+Z)."""
        return self._travel_history(self._undo, self._redo, "undo")

    def redo(self) -> bool:
        """Make an undone edit again (Ctrl+Y or Ctrl+Shift+Z)."""
        return self._travel_history(self._redo, self._undo, "redo")

    def _travel_history(self, source: list[CreatureSpec], target: list[CreatureSpec], word: str) -> bool:
        """Go to the newest creature of ``source``, keeping the current one on ``target``."""
        if not source:
            self.status = f"nothing to {word}"
            return False
        spec, current = source.pop(), self.spec
        if not self._apply(spec, edit=None):
            source.append(spec)
            return False
        target.append(current)
        self._last_edit = ("", 0.0)
        self.status = f"{word}ne"
        return True

    def set(self, key: str, value: Any) -> bool:
        """Set a creature key; on a rejected value keep the creature and show why."""
        return self.set_many({key: value})

    def set_many(self, overrides: dict[str, Any]) -> bool:
        try:
            spec = self.spec.with_overrides(overrides, origin="")
        except GaitlabError as exc:
            self.error = str(exc)
            return False
        return self._apply(spec, edit=",".join(sorted(overrides)))

    def reset(self, key: str) -> bool:
        """Give ``key`` its value from the loaded creature."""
        value = self.base_value(key)
        if value is not None:
            return self.set(key, value)
        try:
            spec = without_adjustment(self.spec, key)
        except GaitlabError as exc:
            self.error = str(exc)
            return False
        return self._apply(spec)

    def reset_all(self, confirmed: bool = False) -> bool:
        """Back to the loaded creature, blending the gait. Every change is lost, so the
        first call only asks (the button then reads "really reset"); a second call, or
        ``confirmed``, resets."""
        if not confirmed and not self.reset_pending:
            self.reset_pending = True
            self.error = "reset every change to the loaded creature? press reset again to do it"
            return False
        self.reset_pending = False
        return self._apply(self.base)

    def set_gait(self, name: str) -> bool:
        """Switch gait preset (its adjustments reset to the new preset's values)."""
        if name not in GAIT_PRESETS:
            self.error = f"unknown gait {name!r}"
            return False
        return self.set("gait.preset", name)

    def set_duty(self, duty: float) -> bool:
        """Set the duty factor; the bias b shown beside it follows (closed form)."""
        return self.set("gait.duty_factor", float(duty))

    def set_bias(self, bias: float) -> bool:
        """Set the seed's swing/stance bias b; the duty factor follows (closed form)."""
        return self.set("gait.bias", float(bias))

    def set_leg_type(self, pair: str, kind: LegType) -> bool:
        """Make a leg pair plantigrade, digitigrade or unguligrade: the loaded creature's
        own ankle lift and toe when it is of that type (the dog's 72 degrees, not a typical
        62), otherwise typical ones (both stay editable)."""
        own = self.base.leg(pair) if pair in {leg.name for leg in self.base.legs} else None
        if own is not None and leg_type(own.ankle_lift) == kind:
            return self.set_many({f"legs.{pair}.ankle_lift": own.ankle_lift, f"legs.{pair}.toe": own.toe})
        lift, toe_ratio = LEG_TYPE_SHAPES[kind]
        meta = self.spec.leg(pair).metatarsus
        return self.set_many({f"legs.{pair}.ankle_lift": lift, f"legs.{pair}.toe": round(meta * toe_ratio, 4)})

    def leg_type(self, pair: str) -> LegType:
        return leg_type(self.spec.leg(pair).ankle_lift)

    def load_preset(self, name: str) -> bool:
        return self.load(name)

    def load(self, name_or_path: str) -> bool:
        """Load a preset or a creature file. A file that fails to load leaves the current
        creature untouched and shows its error."""
        try:
            spec = load_creature(name_or_path)
        except GaitlabError as exc:
            self.error = str(exc)
            return False
        if not self._apply(spec, blend=False, edit=None):
            return False
        self._undo.clear()  # a new creature: its own history
        self._redo.clear()
        self.base = spec
        self.file_path = self._save_path_for(spec)
        if str(name_or_path).endswith(".toml"):
            self._remember_file(spec.source)
        self.status = f"loaded {spec.name}" + (f" from {Path(spec.source).resolve()}"
                                               if str(name_or_path).endswith(".toml") else "")
        self.frame_view()
        return True

    def _remember_file(self, path: str) -> None:
        full = str(Path(path).resolve())
        self.recent = [full] + [p for p in self.recent if p != full][:7]

    @property
    def overwrite_pending(self) -> bool:
        """True when *save* has been asked once for the existing file in the path field."""
        return self._confirm_overwrite is not None and self._confirm_overwrite == str(Path(self.file_path).resolve())

    @staticmethod
    def _save_path_for(spec: CreatureSpec) -> str:
        """Where *save* writes by default: the user's own file when one was loaded, else
        ``<name>.toml`` in the working folder — never a shipped preset."""
        if spec.source.endswith(".toml") and not is_shipped(spec.source):
            return spec.source
        return f"{spec.name}.toml"

    def save(self, path: str | None = None) -> bool:
        """Save the current creature as TOML (atomically). A shipped preset is never
        overwritten; an existing file only when *save* is asked twice for it in a row
        (the first time says so)."""
        target = str(path or self.file_path)
        if is_shipped(target):
            self.error = (f"{Path(target).resolve()}: is one of Gaitlab's preset creatures; save under a name of "
                          f"your own, e.g. my{self.spec.name}.toml")
            return False
        resolved = str(Path(target).resolve())
        if Path(target).exists() and self._confirm_overwrite != resolved:
            self._confirm_overwrite = resolved
            self.error = f"{resolved} exists: save again to overwrite it"
            return False
        self._confirm_overwrite = None
        try:
            written = self.spec.save(target)
        except GaitlabError as exc:
            self.error = str(exc)
            return False
        except OSError as exc:
            self.error = f"{target}: cannot write: {exc.strerror or exc}"
            return False
        self.file_path = str(written)
        self._remember_file(str(written))
        self.status = f"saved {Path(written).resolve()}"
        self.error = None
        return True

    def export(self) -> bool:
        """Export what is on screen — this creature, gait and world — as a skeleton clip
        of the Record panel's length and frame rate from the current time, to the Record
        panel's folder and name with the chosen export format."""
        r = self.record
        path = Path(r.folder) / f"{r.name or self.spec.name}.{r.export_format}"
        try:
            result = export_clip(self.spec, path, fps=float(r.fps),
                                 seconds=r.length if r.unit == "seconds" else None,
                                 cycles=r.length if r.unit == "cycles" else None,
                                 start=float(self.live.clock) / self.live.rig.gait.frequency, world=self.world,
                                 loop=r.unit == "cycles")
        except GaitlabError as exc:
            self.error = str(exc)
            return False
        except OSError as exc:
            self.error = f"{path}: cannot write: {exc.strerror or exc}"
            return False
        self.status = (f"exported {Path(result.path).resolve()}: {result.joints} joints, {result.frames} frames "
                       f"({result.units})")
        self.error = None
        return True

    # -- playback ---------------------------------------------------------------------

    def toggle_play(self) -> None:
        self.playing = not self.playing

    def advance(self, dt: float) -> None:
        """Move the animation on by ``dt`` seconds of wall time (if playing)."""
        if self.playing:
            self._step(dt * self.time_scale)

    def step_frame(self) -> None:
        """One frame forward (pauses playback)."""
        self.playing = False
        self._step(FRAME_DT * max(self.time_scale, 1e-3))

    def _step(self, dt: float) -> None:
        """Step the motion in sub-steps of at most 1/SAMPLE_RATE s (with ``fine_sampling``),
        keeping each sub-step's inputs in :attr:`samples`: the live gait measurement
        samples the motion at this fixed rate, whatever the frame rate."""
        rate = SAMPLE_RATE if self.fine_sampling else 0.0
        steps = max(1, int(np.ceil(dt * rate - 1e-9))) if dt > 0 else 0
        try:
            for _ in range(steps):
                if self.driver is not None:
                    self.driver.step(dt / steps, *self.drive_input)
                else:
                    self.live.step(dt / steps)
                self.samples.append(self.live.frame_inputs())
            for member in self.others:  # the scene's other creatures walk on (a handful)
                member.live.step(dt)
            if self.herd is not None and dt > 0:
                if self.herd.rig.gait.preset != self.live.rig.gait.preset:  # driving switched gait
                    self.herd.set_rig(self.live.rig)
                point, heading = self._here()
                speed = self.live.travel_per_cycle() * self.live.frequency
                self.herd.step(dt, point, heading, leader_speed=speed)
        except GaitlabError as exc:  # ground with no foothold ahead: stop there and say why
            self.playing = False
            self.error = f"paused: {exc}"

    # -- terrain ----------------------------------------------------------------------

    def _init_terrain_values(self) -> None:
        """The Terrain panel's starting values: sized to the creature, then the world's own."""
        rig = self.live.rig
        h, length = rig.hip_height, rig.body_length
        self.terrain_values = {
            "flat": {},
            "slope": {"angle": 10.0, "dir": 0.0},
            "hills": {"amp": round(0.12 * h, 3), "wavelength": round(3.0 * length, 2), "seed": 1},
            "stairs": {"rise": round(0.2 * h, 3), "run": round(max(0.6 * rig.leg_scale, 0.12), 3), "steps": 6,
                       "start": round(0.8 * length, 2), "dir": 0.0},
            "heightmap": {"file": "", "size": 20.0, "height": 1.0},
            "mesh": {"file": "", "cell": 0.0},
        }
        kind, _, rest = self.world.terrain.describe().partition(":")
        kind = {"grid": "heightmap"}.get(kind, kind)
        if kind in self.terrain_values:
            self.terrain_kind = kind
            for item in filter(None, rest.split(",")):
                key, _, value = item.partition("=")
                if key in self.terrain_values[kind]:
                    old = self.terrain_values[kind][key]
                    try:
                        self.terrain_values[kind][key] = value if isinstance(old, str) else type(old)(float(value))
                    except ValueError:
                        pass

    def terrain_text(self, kind: str | None = None) -> str:
        """The Terrain panel's ground as ``--terrain`` text."""
        kind = kind or self.terrain_kind
        values = self.terrain_values.get(kind, {})
        items = [f"{k}={v}" if isinstance(v, (str, int)) else f"{k}={v:g}" for k, v in values.items()
                 if not (k == "cell" and not v)]
        return kind + (":" + ",".join(items) if items else "")

    def set_terrain(self, kind: str | None = None, **values: Any) -> bool:
        """Regenerate the ground from the Terrain panel's kind and values (given ones
        replace the panel's) while the creature walks: planted feet stay where they stand
        until they lift, later footholds are on the new ground. A value out of range, a
        file that does not load or ground the creature cannot walk shows the error and
        changes nothing (the panel keeps its previous values)."""
        from ..scenes import parse_terrain

        kind = kind or self.terrain_kind
        if kind not in self.terrain_values:
            self.error = f"unknown terrain {kind!r}"
            return False
        saved = (self.terrain_kind, {k: dict(v) for k, v in self.terrain_values.items()})
        self.terrain_values[kind].update(values)
        text = self.terrain_text(kind)
        try:
            if kind in ("heightmap", "mesh") and not self.terrain_values[kind]["file"]:
                raise GaitlabError(f"{kind}: give the file to load")
            terrain = parse_terrain(text)
            world = World(path=self.world.path, terrain=terrain, in_place=self.world.in_place and terrain.flat)
            others = [(m, replace(m.world, terrain=terrain)) for m in self.others]
            for member, member_world in others:  # every creature of the scene must find footholds
                member.live.check_world(member_world)
            self.live.set_world(world)
            for member, member_world in others:
                member.live.set_world(member_world)
                member.world = member_world
        except GaitlabError as exc:
            self.terrain_kind, self.terrain_values = saved
            message = str(exc)
            self.error = message if text in message or message.startswith("--terrain") else f"terrain {text}: {message}"
            return False
        self.terrain_kind = kind
        self.world = world
        self.error = None
        return True

    # -- scene creatures ------------------------------------------------------------

    def add_creature(self, spec: CreatureSpec, world: World) -> bool:
        """Another creature of the scene, walking its own path on the same ground."""
        try:
            live = LiveMotion(build_rig(spec), replace(world, terrain=self.world.terrain))
        except GaitlabError as exc:
            self.error = f"{spec.name}: {exc}"
            return False
        if not self.members:
            self.members.append(None)  # the creature in the panels
        self.members.append(SceneMember(base=spec, spec=spec, live=live, world=live.world,
                                        file_path=self._save_path_for(spec)))
        return True

    @property
    def others(self) -> list[SceneMember]:
        """The scene's creatures other than the selected one, in file order."""
        return [m for m in self.members if m is not None]

    @property
    def names(self) -> list[str]:
        """Every scene creature's name in file order (just this one outside a scene)."""
        return [self.spec.name if m is None else m.spec.name for m in self.members] or [self.spec.name]

    def select(self, index: int) -> bool:
        """Put scene creature ``index`` (file order) in the panels; the one there walks on."""
        if not 0 <= index < len(self.names):
            self.error = f"no creature {index + 1} in this scene"
            return False
        if index == self.selected:
            return True
        if self.driver is not None:
            self.stop_driving()
        chosen = self.members[index]
        assert chosen is not None
        self.members[self.selected] = SceneMember(
            base=self.base, spec=self.spec, live=self.live, world=self.world, file_path=self.file_path,
            undo=self._undo, redo=self._redo, herd=self.herd, waypoints=self.waypoints,
            waypoint_s=self._waypoint_s, path_kind=self.path_kind)
        self.members[index] = None
        self.base, self.spec, self.live, self.world = chosen.base, chosen.spec, chosen.live, chosen.world
        self.file_path, self._undo, self._redo, self.herd = chosen.file_path, chosen.undo, chosen.redo, chosen.herd
        self.waypoints, self._waypoint_s, self.path_kind = chosen.waypoints, chosen.waypoint_s, chosen.path_kind
        self.selected = index
        self._last_edit = ("", 0.0)  # a new creature's edits never merge with the last one's
        self.footprints.clear()
        self.arcs.clear()
        self._last_pose = None
        self.status = f"selected {self.spec.name} ({index + 1} of {len(self.members)})"
        self.frame_view()
        return True

    def ghost_poses(self) -> list[Pose]:
        """The key poses of the step the creature is in, along its path (Key poses panel's
        ghosts); none unless asked for. Solved once a step; in place, where the ground has
        carried them since."""
        if not self.show_ghosts:
            return []
        live = self.live
        ref = reference_foot(live.rig)
        phase = float(live.foot_phase()[ref])
        step = (round(live.clock - phase, 6), phase < 0.5)
        cached = self._ghosts
        if cached is None or cached[0] is not live.rig or cached[1] is not live.world or cached[2] != step:
            try:
                motion = key_pose_ghosts(live.rig, live.world, live.clock, live.travel, phase)
            except GaitlabError:
                return []
            cached = self._ghosts = (live.rig, live.world, step, live.travel,
                                     [motion.pose(i) for i in range(motion.frame_count)])
        poses = cached[4]
        if live.world.in_place and live.travel != cached[3]:  # the ground has moved on under them
            back = np.array([0.0, 0.0, cached[3] - live.travel])
            poses = [shift_pose(p, back) for p in poses]
        return poses

    def creature_poses(self) -> list[tuple[Pose, SceneMember]]:
        """Poses of the scene's other creatures (file order, the selected one left out)."""
        return [(m.live.pose(), m) for m in self.others]

    def pick_creature(self, origin: NDArray[np.float64], direction: NDArray[np.float64]) -> int | None:
        """The scene creature (file order) a ray from ``origin`` along unit ``direction``
        points at: of the bodies it meets (each a sphere of half its length plus a third
        of its hip height around its root), the one it passes most nearly through the
        middle of (bodies overlap on screen: the nearest would hide the one clicked);
        None when it meets none."""
        bodies = []
        for index, member in enumerate(self.members or [None]):
            live = self.live if member is None else member.live
            pose = live.pose()
            radius = 0.5 * live.rig.body_length + 0.3 * live.rig.hip_height
            bodies.append((index, pose.root[:3, 3], radius))
        best, best_fit = None, np.inf
        for index, centre, radius in bodies:
            rel = centre - origin
            t = float(rel @ direction)
            fit = float(np.linalg.norm(rel - t * direction)) / radius  # 0: straight through its middle
            if t > 0 and fit <= 1.0 and fit < best_fit:
                best, best_fit = index, fit
        return best

    # -- herd -------------------------------------------------------------------------

    def set_herd(self, count: int) -> bool:
        """``count`` animals in all: this creature and ``count - 1`` more of its kind
        following it (1: none). Out of range shows the error and changes nothing."""
        from ..kinematics.herd import check_herd_size

        try:
            count = check_herd_size(count)
            if count > 1:
                self.leave_in_place()
        except GaitlabError as exc:
            self.error = str(exc)
            return False
        if count == 1:
            self.herd = None
            return True
        point, heading = self._here()
        self.herd = Herd(self.live.rig, count - 1, leader=(float(point[0]), float(point[1])), heading=heading)
        self.frame_view()
        return True

    # -- paths ------------------------------------------------------------------------

    def _here(self) -> tuple[NDArray[np.float64], float]:
        """The body's point on its path (x, z) and its heading (radians) now."""
        (point,), (tangent,) = self.world.path.sample(np.array([self.live.travel]))
        return point, float(np.arctan2(tangent[0], tangent[1]))

    def _take_route(self, route: GroundPath) -> bool:
        """Go on along ``route`` (which starts where the body is, along its heading) from
        now, the path behind kept; on a route the creature cannot take, say why and keep
        the current one."""
        try:
            path = SplicedPath(self.world.path, self.live.travel, route)
            world = World(path=path, terrain=self.world.terrain)
            self.live.set_world(world)  # checks first; changes nothing when it refuses
        except GaitlabError as exc:
            self.error = str(exc)
            return False
        if self.driver is not None:  # the route, not the keys, steers from now on
            self.driver = None
            self.drive_input = (0.0, 0.0)
            try:
                self.live.set_rig(build_rig(self.spec))
            except GaitlabError:
                pass
        self.world = world
        self.options = replace(self.options, path=True)
        self.error = None
        return True

    def set_path(self, kind: str | None = None, **values: Any) -> bool:
        """From here on, follow a path of ``kind`` (straight, circle, figure-eight, or the
        waypoints) with the Path panel's values (given ones replace them), starting where
        the body is, along its heading. Bad values show the error and change nothing."""
        from ..scenes import parse_path

        kind = kind or self.path_kind
        if kind not in self.path_values:
            self.error = f"unknown path {kind!r}; choose one of {', '.join(self.path_values)}"
            return False
        if kind == "waypoints":
            return self.set_waypoints(self.waypoints)  # (sets the kind when it succeeds)
        merged = {**self.path_values[kind], **values}
        text = kind + (":" + ",".join(f"{k}={v:g}" if not isinstance(v, str) else f"{k}={v}"
                                      for k, v in merged.items()) if merged else "")
        point, heading = self._here()
        try:
            route = parse_path(text)
        except GaitlabError as exc:
            self.error = str(exc)
            return False
        route.start, route.heading = (float(point[0]), float(point[1])), heading
        if not self._take_route(route):
            return False
        self.path_kind = kind
        self.path_values[kind] = merged
        self.waypoints, self._waypoint_s = [], []  # another kind of route: no waypoints ahead
        return True

    def leave_in_place(self) -> None:
        """Walk in the world (the view and the ground then agree, for picking on it)."""
        if self.world.in_place:
            world = replace(self.world, in_place=False)
            self.live.set_world(world)
            self.world = world

    def set_waypoints(self, points: list[tuple[float, float]]) -> bool:
        """Go through ``points`` (x, z, m) from here, in order; none: straight on. A first
        point within half a body length of the body counts as reached; a first point behind
        the body gets turning points on its side, so the route turns round in a loop
        (over two body lengths across) instead of on the spot."""
        from ..scenes import waypoint_path

        point, heading = self._here()
        length = self.live.rig.body_length
        forward = np.array([np.sin(heading), np.cos(heading)])
        lead = point + 0.8 * length * forward
        pts = [tuple(map(float, p)) for p in points]
        while pts and np.all(np.isfinite(pts[0])) and np.linalg.norm(np.asarray(pts[0]) - point) <= 0.5 * length:
            pts.pop(0)  # the next waypoint is under the creature: reached
        turn: list = []
        lead_points = [lead]
        if pts and np.all(np.isfinite(pts[0])) and np.linalg.norm(np.asarray(pts[0]) - point) < 1.6 * 0.8 * length:
            lead_points = []  # a first waypoint just ahead: go straight for it
        if pts and np.all(np.isfinite(pts[0])):
            to_first = np.asarray(pts[0]) - point
            if to_first @ forward < 0.5 * np.linalg.norm(to_first):  # more than 60 degrees off the heading
                left = np.array([forward[1], -forward[0]])
                side = 1.0 if to_first @ left >= 0 else -1.0
                turn = [point + length * (1.2 * forward + 1.2 * side * left)]
                if to_first @ forward < 0:  # behind: round the half loop
                    turn.append(point + length * (0.4 * forward + 2.6 * side * left))
        try:
            if not pts:
                route: GroundPath = StraightPath(start=(float(point[0]), float(point[1])), heading=heading)
            else:
                if not all(np.all(np.isfinite(p)) and max(abs(p[0]), abs(p[1])) <= 1e4 for p in pts):
                    raise GaitlabError("a waypoint must be within 10 km of the origin")
                route = waypoint_path(np.array([point, *lead_points, *turn, *pts]), False, "waypoints")
        except GaitlabError as exc:
            self.error = str(exc)
            return False
        if not self._take_route(route):
            return False
        self.waypoints = pts
        # Where along the path each waypoint lies (m), to drop those the body has passed.
        first = 1 + len(lead_points) + len(turn)  # the knot of the first waypoint
        knots = np.arange(first, first + len(pts)) * WaypointPath.SAMPLES_PER_SEGMENT
        self._waypoint_s = (self.live.travel + route._table.s[knots]).tolist() if pts else []
        self.path_kind = "waypoints"
        return True

    def _drop_passed_waypoints(self) -> None:
        """Waypoints the body has reached are done: they leave the list (the route stays)."""
        passed = sum(1 for s in self._waypoint_s if s <= self.live.travel)
        if passed:
            del self.waypoints[:passed]
            del self._waypoint_s[:passed]

    def add_waypoint(self, x: float, z: float) -> bool:
        return self.set_waypoints([*self.waypoints, (x, z)])

    def move_waypoint(self, index: int, x: float, z: float) -> bool:
        """Move waypoint ``index``; False (nothing changes) when there is no such waypoint
        any more (reached, or dropped for being under the creature)."""
        if not 0 <= index < len(self.waypoints):
            return False
        points = list(self.waypoints)
        points[index] = (x, z)
        return self.set_waypoints(points)

    def delete_waypoint(self, index: int) -> bool:
        if not 0 <= index < len(self.waypoints):
            return False
        return self.set_waypoints([p for i, p in enumerate(self.waypoints) if i != index])

    def nearest_waypoint(self, x: float, z: float, within: float) -> int | None:
        """The waypoint nearest (x, z) if within ``within`` m, else None."""
        if not self.waypoints:
            return None
        d = np.linalg.norm(np.array(self.waypoints) - np.array([x, z]), axis=1)
        i = int(d.argmin())
        return i if d[i] <= within else None

    # -- drive mode -------------------------------------------------------------------

    def start_driving(self) -> bool:
        """Drive the creature: W/S (Up/Down) set the speed, A/D (Left/Right) turn; the gait
        follows the speed. The path from here on is laid down by the steering."""
        if self.driver is not None:
            return True
        before = self.live.world
        try:
            if before.in_place:  # driving means travelling
                self.live.world = replace(before, in_place=False)
            self.driver = Driver(self.live, build_rig(self.spec))
        except GaitlabError as exc:
            self.live.world = before
            self.error = f"cannot drive: {exc}"
            return False
        self.world = self.live.world
        self.options = replace(self.options, path=True)
        self.playing = True
        self.status = "driving: W/S or Up/Down speed, A/D or Left/Right turn, Esc to stop"
        return True

    def stop_driving(self) -> None:
        """Back to the panels' gait, going straight on along the path driven so far."""
        if self.driver is None:
            return
        self.driver.release()
        self.driver = None
        self.drive_input = (0.0, 0.0)
        try:
            self.live.set_rig(build_rig(self.spec))
        except GaitlabError as exc:
            self.error = str(exc)
            return
        self.status = "stopped driving: the gait is the Gait panel's again"

    def take_samples(self) -> list[dict]:
        """The sub-steps' inputs since the last call (see :meth:`_step`)."""
        samples, self.samples = self.samples, []
        return samples

    def scrub(self, phase: float) -> None:
        """Put the gait clock at ``phase`` of the current cycle (pauses playback)."""
        self.playing = False
        self.live.set_phase(phase)

    def pose(self) -> Pose:
        return self.live.pose()

    # -- view -------------------------------------------------------------------------

    def frame_view(self, preset: str | None = None, ortho: bool = False) -> None:
        """Point a camera preset at the creature, framing a whole gait cycle (around where
        the creature is now, at the preset's angle to its heading). Each preset sets its
        own projection: perspective, unless ``ortho``."""
        from ..kinematics.clip import clip_motion
        from ..render.scene import motion_bounds

        preset = preset or self.camera_preset
        if preset not in CAMERA_PRESETS:
            self.error = f"unknown camera {preset!r}"
            return
        self.camera_preset = preset
        motion, _ = clip_motion(self.live.rig, 30.0, cycles=1.0, world=World(in_place=True))
        length = self.live.rig.body_length
        cam = frame_points(look_ahead(motion_bounds(motion), preset, length), preset, aspect=self.aspect)
        # The chase camera aims ahead of the creature (the framed box reaches forward).
        self._follow_ahead = 0.5 * CHASE_LOOK_AHEAD * length if preset == "chase" else 0.0
        if not self.world.in_place:
            root = self.live.pose().root
            heading = float(np.degrees(np.arctan2(root[0, 2], root[2, 2])))
            tx, ty, tz = cam.target
            c, s = np.cos(np.radians(heading)), np.sin(np.radians(heading))
            target = (float(root[0, 3] + c * tx + s * tz), ty, float(root[2, 3] - s * tx + c * tz))
            cam = replace(cam, target=target, azimuth=cam.azimuth + heading)
        if self.herd is not None:  # back off so the group behind the creature is in view
            extent = float(np.abs(self.herd.slot).max()) + length
            cam = replace(cam, distance=cam.distance * max(1.0, 0.4 * extent / length))
        self.camera = replace(cam, ortho=ortho)
        self._follow_height = None
        self._elevation = self.camera.elevation
        self.options = replace(self.options, grid_spacing=nice_grid_spacing(self.live.rig.hip_height * 1.6))

    def default_view(self) -> None:
        """The view the viewer starts with (R): the default preset, in perspective."""
        self.frame_view(DEFAULT_CAMERA)

    def side_ortho(self) -> None:
        """The animator's view: orthographic, from the side."""
        self.frame_view("side", ortho=True)

    def set_ortho(self, ortho: bool) -> None:
        self.camera = replace(self.camera, ortho=ortho)

    def orbit(self, dx_pixels: float, dy_pixels: float) -> None:
        self.camera = self.camera.orbit(-0.3 * dx_pixels, 0.3 * dy_pixels)
        self._elevation = self.camera.elevation

    def pan(self, dx_pixels: float, dy_pixels: float, view_height: float) -> None:
        self.camera = self.camera.pan(dx_pixels / max(view_height, 1.0), dy_pixels / max(view_height, 1.0))

    def zoom(self, wheel: float) -> None:
        self.camera = self.camera.zoom(0.88 ** wheel)

    def focus(self, point: tuple[float, float, float] | None) -> None:
        """Aim at ``point`` (world), or at the creature when it is ``None``."""
        if point is None:
            root = self.pose().root[:3, 3]
            point = (float(root[0]), float(root[1]), float(root[2]))
        self.camera = replace(self.camera, target=tuple(float(v) for v in point))

    def follow_creature(self, pose: Pose | None = None) -> None:
        """Keep the camera on the creature: the target over its root, its height eased
        towards the root's (stairs, hills), and the view turning with the path's heading."""
        pose = pose or self.pose()
        root = pose.root[:3, 3]
        _, tangent = self.world.path.sample(np.array([pose.travel]))
        heading = float(np.degrees(np.arctan2(tangent[0, 0], tangent[0, 1])))
        previous = heading if self._heading is None else self._heading
        self._heading = heading
        if not self.follow:
            return
        tx, ty, tz = self.camera.target
        offset = self._follow_height
        if offset is None:
            offset = self._follow_height = ty - float(root[1])
        ty = ty + (float(root[1]) + offset - ty) * 0.08
        turn = (heading - previous + 180.0) % 360.0 - 180.0
        ahead = self._follow_ahead * tangent[0] if not self.world.in_place else np.zeros(2)
        if self.herd is not None:  # aim between the creature and its herd's middle
            ahead = ahead + 0.5 * (self.herd.position.mean(axis=0) - root[[0, 2]])
        camera = replace(self.camera, target=(float(root[0] + ahead[0]), ty, float(root[2] + ahead[1])),
                         azimuth=self.camera.azimuth + (0.0 if self.world.in_place else turn))
        if not self.world.terrain.flat and not camera.top_down:
            # Rise over hills that would hide the creature, easing back down after them.
            base = camera.elevation if self._elevation is None else self._elevation
            self._elevation = base
            need = clear_elevations(np.array([camera.target]), np.array([camera.azimuth]), base, camera.distance,
                                    self.world.terrain.height, margin=0.1 * self.live.rig.hip_height)[0]
            camera = replace(camera, elevation=camera.elevation + (max(base, need) - camera.elevation) * 0.08)
        self.camera = camera

    # -- recording --------------------------------------------------------------------

    def record_request(self) -> RecordRequest:
        """The request the Record panel describes (what ``gaitlab render`` would get)."""
        r = self.record
        seconds = r.length if r.unit == "seconds" else None
        cycles = r.length if r.unit == "cycles" else None
        view = ViewSettings(size=(int(r.width), int(r.height)), camera=r.camera,  # type: ignore[arg-type]
                            antialias=r.antialias,
                            options=replace(RenderOptions(), grid=self.options.grid, shadow=self.options.shadow,
                                            joints=self.options.joints, path=self.options.path))
        return RecordRequest(spec=self.spec, output=r.path(self.spec.name), fps=float(r.fps), seconds=seconds,
                             cycles=cycles, view=view, world=self.world, gif_quality=r.gif_quality,
                             crf=int(np.clip(r.crf, 0, MAX_CRF)))

    def note_pose(self, pose: Pose) -> None:
        """Take in the pose drawn this frame: record new footprints, and how far any foot
        planted in both this frame and the last moved between them (:attr:`planted_jump`,
        m; the largest since the viewer started in :attr:`planted_jump_max`)."""
        self.footprints.record(pose, self.live.time)
        rig = self.live.rig
        if self.options.arcs:
            self.arcs.record(pose, self.options.arcs, self.live.time, 1.0 / self.live.frequency, reference_foot(rig))
        else:
            self.arcs.clear()
        self._drop_passed_waypoints()
        last = self._last_pose
        self._last_pose = pose
        if last is None or len(last.contact) != len(pose.contact):
            return
        # What bears each planted foot (a rolling foot's heel, ball or toe tip in turn).
        duty = self.live.duty
        part = roll_part(rig, rig.poses.foot_angle, pose.phase, duty)
        last_part = roll_part(rig, rig.poses.foot_angle, last.phase, duty)
        still = last.contact & pose.contact & (pose.phase > last.phase) & (part == last_part)
        offset = np.array([0.0, 0.0, pose.ground_offset - last.ground_offset])  # in place: the ground moves
        if still.any():
            now = contact_points(rig, rig.poses.foot_angle, pose.phase, duty, pose.contact, pose.heel, pose.joints)
            before = contact_points(rig, rig.poses.foot_angle, last.phase, duty, last.contact, last.heel, last.joints)
            moved = np.linalg.norm(now[still] + offset - before[still], axis=-1)
            self.planted_jump = float(moved.max())
            self.planted_jump_max = max(self.planted_jump_max, self.planted_jump)

    def overlays(self, pose: Pose) -> Overlays | None:
        """The View panel's overlays for ``pose`` (None when all are off): the last
        footprints (recorded here, every frame), the swinging feet's touchdown targets and
        the support polygon with the trunk's centre."""
        o = self.options
        marks = self.waypoints if (self.waypoint_edit or self.path_kind == "waypoints") else []
        if not (o.footprints or o.targets or o.support or marks):
            return None
        rig = self.live.rig
        size = 0.12 * float(np.mean(rig.l_rest))
        parts: dict = {}
        if o.footprints:
            points, legs, age = self.footprints.recent(o.footprint_count, pose.ground_offset)
            parts.update(footprints=points, footprint_age=age, footprint_colors=leg_colors(rig)[legs] * 0.55)
        if o.targets:
            targets = touchdown_targets(self.live)[0]
            parts["targets"] = targets - np.array([0.0, 0.0, pose.ground_offset])  # in place: the ground moved
        if o.support:
            hull = support_polygon(planted_points(pose)[:, [0, 2]])
            centre = trunk_centre(pose)[[0, 2]]
            parts.update(support=hull, centre=centre, stable=inside_polygon(centre, hull))
        if marks:
            parts["waypoints"] = np.column_stack([np.array(marks)[:, 0], np.zeros(len(marks)), np.array(marks)[:, 1]])
        return Overlays(size=size, **parts)

    def ground(self, pose: Pose) -> GroundView:
        """What the renderer draws under ``pose``."""
        return GroundView(terrain=self.world.terrain, offset=pose.ground_offset,
                          path=None if self.world.in_place else self.world.path, travel=pose.travel)
