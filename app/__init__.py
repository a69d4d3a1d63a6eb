"""Gaitlab: procedural legged locomotion with analytic IK, travel over terrain, headless
rendering and gait analysis.

Public API::

    from app import load_creature, simulate
    spec = load_creature("dog").with_overrides({"gait.duty_factor": 0.7})
    motion = simulate(spec, seconds=4.0, fps=60, path="circle:r=3", terrain="hills:amp=0.2")
    motion.terrain.height(xz)    # (N, 2) -> (N,);  motion.terrain.normal(xz) -> (N, 3)
"""

from __future__ import annotations

from .kinematics import Motion, Pose, Rig
from .kinematics.path import Path
from .kinematics.terrain import Terrain
from .rigging import build_rig
from .spec import CreatureSpec, load_creature

__version__ = "0.2.0"


def simulate(creature: CreatureSpec | Rig | str, seconds: float = 4.0, fps: float = 60.0, *,
             path: str | Path | None = None, terrain: str | Terrain | None = None, in_place: bool = False,
             start_phase: float = 0.0) -> Motion:
    """Simulate a creature (a spec, a rig, or a preset name / file) for ``seconds`` at ``fps``
    (fixed dt = 1/fps), walking along ``path`` over ``terrain`` — each the same text the CLI
    takes (``"circle:r=3"``, ``"stairs:rise=0.1"``) or an object; default straight ahead on
    flat ground. ``in_place`` keeps the body at the origin and moves the ground instead."""
    from .kinematics.motion import simulate as simulate_rig
    from .scenes import make_world

    if isinstance(creature, str):
        creature = load_creature(creature)
    rig = creature if isinstance(creature, Rig) else build_rig(creature)
    return simulate_rig(rig, seconds, fps, world=make_world(path, terrain, in_place), start_phase=start_phase)


__all__ = ["CreatureSpec", "Motion", "Path", "Pose", "Rig", "Terrain", "build_rig", "load_creature", "simulate"]
