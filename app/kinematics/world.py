"""Where a creature walks: a path for its body and a terrain under its feet."""

from __future__ import annotations

from dataclasses import dataclass, field

from ..errors import GaitlabError
from .path import Path, StraightPath
from .terrain import FlatTerrain, Terrain


class WorldError(GaitlabError):
    """A path, terrain or scene the creature cannot walk (one line, for the user)."""


@dataclass(frozen=True)
class World:
    """The path the body's centre follows and the ground. ``in_place`` keeps the creature
    at the origin while the ground moves under it (only on flat ground along a straight
    path): the view for studying a cycle, and what the golden images show."""

    path: Path = field(default_factory=StraightPath)
    terrain: Terrain = field(default_factory=FlatTerrain)
    in_place: bool = False

    def __post_init__(self) -> None:
        if self.in_place and not (isinstance(self.path, StraightPath) and self.terrain.flat):
            raise WorldError(f"in place needs flat ground and a straight path (got path {self.path.describe()}, "
                             f"terrain {self.terrain.describe()}); drop --in-place to travel")


IN_PLACE = World(in_place=True)
