"""Gaitlab: procedural legged locomotion with analytic IK, travel over terrain, headless
rendering and gait analysis.

Public API::

    from app import load_creature, simulate
    spec = load_creature("dog").with_overrides({"gait.duty_factor": 0.7})
    motion = simulate(spec, seconds=4.0, fps=60, path="circle:r=3", terrain="hills:amp=0.2")
    motion.terrain.height(xz)    # (N, 2) -> (N,);  motion.terrain.normal(xz) -> (N, 3)
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from .kinematics import Motion, Pose, Rig
    from .kinematics.path import Path
    from .kinematics.terrain import Terrain
    from .rigging import build_rig
    from .spec import CreatureSpec, load_creature

__version__ = "0.2.0"

# The public names, imported from their homes on first use: ``gaitlab --version`` and
# ``--help`` start without loading numpy, scipy or the kinematics.
_HOMES = {"Motion": ".kinematics", "Pose": ".kinematics", "Rig": ".kinematics", "Path": ".kinematics.path",
          "Terrain": ".kinematics.terrain", "build_rig": ".rigging", "CreatureSpec": ".spec",
          "load_creature": ".spec"}


def __getattr__(name: str) -> Any:
    home = _HOMES.get(name)
    if home is None:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    value = getattr(importlib.import_module(home, __name__), name)
    globals()[name] = value
    return value


def simulate(creature: CreatureSpec | Rig | str, seconds: float = 4.0, fps: float = 60.0, *,
             path: str | Path | None = None, terrain: str | Terrain | None = None, in_place: bool = False,
             start_phase: float = 0.0) -> Motion:
    """Simulate a creature (a spec, a rig, or a preset name / file) for ``seconds`` at ``fps``
    (fixed dt = 1/fps), walking along ``path`` over ``terrain`` — each the same text the CLI
    takes (``"circle:r=3"``, ``"stairs:rise=0.1"``) or an object; default straight ahead on
    flat ground. ``in_place`` keeps the body at the origin and moves the ground instead."""
    from .kinematics import Rig
    from .kinematics.motion import simulate as simulate_rig
    from .rigging import build_rig
    from .spec import load_creature
    from .worlds import make_world

    if isinstance(creature, str):
        creature = load_creature(creature)
    rig = creature if isinstance(creature, Rig) else build_rig(creature)
    return simulate_rig(rig, seconds, fps, world=make_world(path, terrain, in_place), start_phase=start_phase)


__all__ = ["CreatureSpec", "Motion", "Path", "Pose", "Rig", "Terrain", "build_rig", "load_creature", "simulate"]
