"""The viewer's state and everything its controls do — no imgui, no OpenGL.

Panels (``app/ui/panels.py``) only draw widgets and call these methods, so the logic of
every control is unit-tested without a window. Edits go through
:meth:`CreatureSpec.with_overrides`, so the UI accepts exactly what a creature file
accepts; a rejected value leaves the creature unchanged and shows the error.

The state is one scene of creatures (:class:`~app.ui.session.CreatureSession` each) and
a selected index; the per-creature attributes (``spec``, ``live``, ``world``, ...) are
the selected session's. Its parts, one job each:

- :mod:`.editing`: keys, undo and redo;
- :mod:`.files`: load, save, export, the Record panel;
- :mod:`.playback`: play, step, drive, herd;
- :mod:`.world_edits`: the Terrain and Path panels;
- :mod:`.view`: cameras, overlays, ghosts;
- :mod:`.scene`: the scene's creatures, selecting and picking them.
"""

from __future__ import annotations

import time
from typing import Any

from ..choices import DEFAULT_CAMERA
from ..kinematics.arcs import ArcTrail
from ..kinematics.drive import Driver
from ..kinematics.herd import Herd
from ..kinematics.live import LiveMotion
from ..kinematics.motion import Pose
from ..kinematics.overlays import FootprintTrail
from ..kinematics.path import CirclePath, FigureEightPath, StraightPath
from ..kinematics.world import World
from ..render.camera import Camera
from ..render.options import RenderOptions
from ..spec import CreatureSpec
from .editing import EditingMixin
from .files import FilesMixin, RecordSettings
from .playback import PlaybackMixin
from .scene import SceneMixin
from .session import CreatureSession, PerCreature
from .view import ViewMixin
from .world_edits import WorldMixin


class ViewerState(EditingMixin, FilesMixin, PlaybackMixin, WorldMixin, ViewMixin, SceneMixin):
    """Everything the viewer shows and edits."""

    # The selected creature's (see CreatureSession).
    base = PerCreature[CreatureSpec]("base")
    spec = PerCreature[CreatureSpec]("spec")
    live = PerCreature[LiveMotion]("live")
    world = PerCreature[World]("world")
    file_path = PerCreature[str]("file_path")
    herd = PerCreature[Herd | None]("herd")
    waypoints = PerCreature[list]("waypoints")
    path_kind = PerCreature[str]("path_kind")
    _undo = PerCreature[list]("undo")
    _redo = PerCreature[list]("redo")
    _last_edit = PerCreature[tuple]("last_edit")
    _waypoint_s = PerCreature[list]("waypoint_s")

    def __init__(self, base: CreatureSpec, world: World | None = None) -> None:
        world = world or World()
        self.message: tuple[str, str, str] | None = None  # (kind, text, time) shown in the bar
        self.error: str | None = None
        self.status = ""
        self.sessions = [CreatureSession(base, world, file_path=self._save_path_for(base))]
        self.selected = 0  # which creature the panels show
        self.playing = True
        self.time_scale = 1.0
        self.camera = Camera()
        self.camera_preset: str = DEFAULT_CAMERA
        self.follow = True
        # A turning path: show where it is going.
        self.options = RenderOptions(path=not isinstance(world.path, StraightPath))
        self.show_ui = True
        self.show_help = False
        self.record = RecordSettings()
        self.aspect = 16.0 / 9.0
        self.screenshot_requested = False
        self.screenshot_with_ui = False  # F12: the 3-D view alone; Shift+F12: the whole window
        self.record_requested = False
        self.widget_rects: dict[str, tuple[float, float, float, float]] = {}
        self.drag_held = False  # the control being changed was already held by the mouse last frame
        self.samples: list[dict[str, Any]] = []  # sub-step inputs for the gait monitor
        self.fine_sampling = True  # sub-step at SAMPLE_RATE (the viewer turns it off while nobody measures)
        self.reset_pending = False  # "reset everything" asked once
        self.recent: list[str] = []  # files saved or loaded this session, newest first
        self.terrain_kind = "flat"  # the Terrain panel's kind and values
        self.terrain_values: dict[str, dict[str, Any]] = {}
        self.path_values: dict[str, dict[str, Any]] = {
            "straight": {}, "circle": {"r": 2.0, "dir": "left"}, "figure-eight": {"r": 2.0}, "waypoints": {}}
        if isinstance(world.path, (CirclePath, FigureEightPath)):  # the values of the route it was started on
            self.path_values[world.path.kind]["r"] = world.path.radius
        if isinstance(world.path, CirclePath):
            self.path_values["circle"]["dir"] = world.path.direction
        self.footprints = FootprintTrail()
        self.arcs = ArcTrail()
        self.show_ghosts = False  # the key poses of the current step drawn faintly along the path
        self.waypoint_edit = False  # mouse on the ground: click adds, drag moves, right-click deletes
        self.planted_jump = 0.0  # m a planted foot moved last frame (see note_pose)
        self.planted_jump_max = 0.0
        self.compromised_told = 0  # compromised footholds already reported on the message line
        self.driver: Driver | None = None  # drive mode: W/S speed, A/D turn
        self.drive_input = (0.0, 0.0)  # held keys: throttle (S -1 .. W 1), steer (D -1 .. A 1)
        self._last_pose: Pose | None = None
        self._ghosts: tuple | None = None
        self._style_check: tuple | None = None
        self._confirm_overwrite: str | None = None  # asked once to overwrite this
        self._confirm_record: str | None = None  # ... and to record over this
        self._confirm_switch: str | None = None  # ... and to switch to this preset, dropping edits
        self._asked_at = 0.0  # when reset everything or the preset switch asked (monotonic s)
        self._known_files: dict[str, tuple[int, int]] = {}  # files this viewer read or wrote: (mtime ns, size)
        self._follow_height: float | None = None  # camera target above the root
        self._heading: float | None = None  # path heading last frame (degrees)
        self._follow_ahead = 0.0  # m the camera aims ahead of the root
        self._elevation: float | None = None  # the user's camera elevation
        self._lowering_in = 0.0  # seconds before the follow camera may ease down from a raised view
        self._init_terrain_values()
        self.frame_view()

    @property
    def session(self) -> CreatureSession:
        """The selected creature's session."""
        return self.sessions[self.selected]

    def __setattr__(self, name: str, value: Any) -> None:
        super().__setattr__(name, value)
        # One message line: each new status or error replaces the last, stamped with the
        # time; clearing an error clears its message (never a stale one).
        if name in ("error", "status"):
            if value:
                super().__setattr__("message", ("error" if name == "error" else "ok", str(value),
                                                time.strftime("%H:%M:%S")))
            elif name == "error" and (message := getattr(self, "message", None)) and message[0] == "error":
                super().__setattr__("message", None)
