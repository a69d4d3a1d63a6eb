"""The cast of a clip: the creatures a recording films or an export writes, each with
its world (path, terrain, in place), its speed and its herd. ``gaitlab render`` and
``export`` of a scene file, and the viewer's Record and File panels, all describe what
they make as a cast."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

from .errors import GaitlabError
from .kinematics.clip import clip_motion, frame_at
from .kinematics.herd import check_herd_size
from .kinematics.motion import Motion
from .kinematics.world import World
from .rigging import build_rig
from .spec import CreatureSpec
from .worlds import Scene, SceneCreature


@dataclass(frozen=True)
class Actor:
    """One creature of a clip: its creature, where it walks, its speed in m/s at the
    first and last frame (None: the gait's own) and its herd (animals in all: it and
    ``herd - 1`` more of its kind following it)."""

    spec: CreatureSpec
    world: World = field(default_factory=World)
    speed: tuple[float, float] | None = None
    herd: int = 1

    def __post_init__(self) -> None:
        check_herd_size(self.herd)
        if self.herd > 1 and self.world.in_place:
            raise GaitlabError(f"a herd of {self.herd} travels: drop --in-place")


Cast = tuple[Actor, ...]


def cast_of_scene(scene: Scene, creature: Callable[[SceneCreature], CreatureSpec],
                  speed: tuple[float, float] | None = None, herd: int | None = None) -> Cast:
    """Every creature of a scene file, in file order; ``creature`` loads each entry's
    creature (with the command line's own changes); ``speed`` and ``herd`` replace the
    file's for every creature when given."""
    actors = []
    for entry in scene.creatures:
        own = None if entry.speed is None else (entry.speed, entry.speed)
        actors.append(Actor(creature(entry), entry.world, speed if speed is not None else own,
                            entry.herd if herd is None else herd))
    return tuple(actors)


def cast_motions(cast: Cast, fps: float, seconds: float | None = None, cycles: float | None = None,
                 start: float = 0.0, closed: bool = False) -> tuple[list[Motion], float | None]:
    """Every actor's motion over one clip, and the clip's cycle count (whole-cycle clips).

    The first actor sets the length (``cycles`` are its gait's); the others are solved
    over the same frames at the same times, each on its own path and speed."""
    lead = cast[0]
    motion, cycles_out = clip_motion(build_rig(lead.spec), fps, seconds, cycles, start, lead.speed, world=lead.world,
                                     closed=closed)
    motions = [motion]
    for actor in cast[1:]:
        other, _ = clip_motion(build_rig(actor.spec), fps, motion.frame_count / fps, None, start, actor.speed, world=actor.world)
        motions.append(other)
    return motions, cycles_out


def cast_frames_at(cast: Cast, time: float, fps: float) -> list[Motion]:
    """Every actor as a one-frame motion at ``time`` s (a PNG of a scene)."""
    return [frame_at(build_rig(actor.spec), time, fps, actor.world) for actor in cast]

