"""What every part of the viewer's state may use: the attributes of
:class:`~app.ui.state.ViewerState`, declared once for the parts (mixins) that work on
them, and the methods one part calls on another."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from ..cast import Cast
    from ..kinematics.arcs import ArcTrail
    from ..kinematics.drive import Driver
    from ..kinematics.herd import Herd
    from ..kinematics.live import LiveMotion
    from ..kinematics.motion import Pose
    from ..kinematics.overlays import FootprintTrail
    from ..kinematics.world import World
    from ..render.camera import Camera
    from ..render.options import RenderOptions
    from ..spec import CreatureSpec
    from .files import RecordSettings
    from .session import CreatureSession


class StateBase:
    """Declarations only (see :class:`~app.ui.state.ViewerState` for what each holds)."""

    if TYPE_CHECKING:
        sessions: list[CreatureSession]
        selected: int
        base: CreatureSpec
        spec: CreatureSpec
        live: LiveMotion
        world: World
        file_path: str
        herd: Herd | None
        waypoints: list[tuple[float, float]]
        path_kind: str
        _undo: list[CreatureSpec]
        _redo: list[CreatureSpec]
        _last_edit: tuple[str, float]
        drag_held: bool
        _waypoint_s: list[float]
        error: str | None
        status: str
        playing: bool
        time_scale: float
        camera: Camera
        camera_preset: str
        follow: bool
        options: RenderOptions
        aspect: float
        record: RecordSettings
        recent: list[str]
        reset_pending: bool
        samples: list[dict[str, Any]]
        fine_sampling: bool
        driver: Driver | None
        drive_input: tuple[float, float]
        terrain_kind: str
        terrain_values: dict[str, dict[str, Any]]
        path_values: dict[str, dict[str, Any]]
        footprints: FootprintTrail
        arcs: ArcTrail
        show_ghosts: bool
        waypoint_edit: bool
        planted_jump: float
        planted_jump_max: float
        compromised_told: int
        _last_pose: Pose | None
        _ghosts: tuple[Any, ...] | None
        _style_check: tuple[Any, ...] | None
        _confirm_overwrite: str | None
        _confirm_record: str | None
        _confirm_switch: str | None
        _asked_at: float
        _known_files: dict[str, tuple[int, int]]
        _follow_height: float | None
        _heading: float | None
        _follow_ahead: float
        _elevation: float | None
        _lowering_in: float

        @property
        def session(self) -> CreatureSession: ...
        @property
        def others(self) -> list[CreatureSession]: ...
        def cast(self) -> Cast: ...
        def frame_view(self, preset: str | None = None, ortho: bool = False) -> None: ...
        def stop_driving(self) -> None: ...
        def leave_in_place(self) -> None: ...
        def pose(self) -> Pose: ...
        def _apply(self, spec: CreatureSpec, blend: bool = True, edit: str | None = "") -> bool: ...
        def _save_path_for(self, spec: CreatureSpec) -> str: ...
        def _here(self) -> tuple[Any, float]: ...
        def _drop_passed_waypoints(self) -> None: ...
        def _init_terrain_values(self) -> None: ...
