"""One creature of the viewer's scene, and the per-creature view of the viewer's state.

:class:`CreatureSession` holds everything that belongs to one creature: the creature as
loaded and as edited, its live motion and world, its edit history, its herd and its
route. The viewer's state keeps a list of sessions and a selected index; its
per-creature attributes (``state.spec``, ``state.live``, ...) are :class:`PerCreature`
views of the selected session, so selecting another creature copies nothing.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Generic, TypeVar

from ..errors import GaitlabError
from ..kinematics.herd import Herd
from ..kinematics.live import LiveMotion
from ..kinematics.world import World
from ..rigging import build_rig
from ..spec import CreatureSpec

T = TypeVar("T")


@dataclass
class CreatureSession:
    """One creature the viewer shows: ``base`` (as loaded: what reset goes back to),
    ``spec`` (as edited), its live motion in ``world``, the file it saves to, its undo
    and redo history (creatures), its herd, and its route's waypoints (x, z) with their
    arc lengths along the path."""

    base: CreatureSpec
    world: World
    spec: CreatureSpec = field(init=False)
    live: LiveMotion = field(init=False)
    file_path: str = ""
    undo: list[CreatureSpec] = field(default_factory=list)
    redo: list[CreatureSpec] = field(default_factory=list)
    last_edit: tuple[str, float] = ("", 0.0)  # the control last changed, and when
    herd: Herd | None = None
    waypoints: list[tuple[float, float]] = field(default_factory=list)
    waypoint_s: list[float] = field(default_factory=list)
    path_kind: str = "straight"

    def __post_init__(self) -> None:
        self.spec = self.base
        self.live = LiveMotion(build_rig(self.base), self.world)  # raises GaitlabError for a world it cannot walk
        if self.world.path.kind in PATH_KINDS:  # the Path panel shows the route it was started on
            self.path_kind = self.world.path.kind

    @classmethod
    def start(cls, spec: CreatureSpec, world: World, file_path: str = "") -> CreatureSession:
        """A new session, or :class:`GaitlabError` naming the creature when it cannot walk there."""
        try:
            return cls(spec, world, file_path=file_path)
        except GaitlabError as exc:
            raise GaitlabError(f"{spec.name}: {exc}") from None


PATH_KINDS = ("straight", "circle", "figure-eight", "waypoints")  # the Path panel's kinds


class PerCreature(Generic[T]):
    """An attribute of the viewer's state that is the selected creature's: reading and
    writing it reads and writes ``state.session.<field>``."""

    def __init__(self, field_name: str) -> None:
        self.field_name = field_name

    def __get__(self, obj: Any, owner: type | None = None) -> T:
        if obj is None:
            return self  # type: ignore[return-value]
        return getattr(obj.session, self.field_name)

    def __set__(self, obj: Any, value: T) -> None:
        setattr(obj.session, self.field_name, value)
