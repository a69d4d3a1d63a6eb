"""Gaitlab: procedural tetrapod locomotion with analytic IK, headless rendering and gait analysis.

Public API::

    from app import load_creature, simulate
    spec = load_creature("dog").with_overrides({"gait.duty_factor": 0.7})
    motion = simulate(spec, seconds=4.0, fps=60)
"""

from .kinematics import Motion, Pose, Rig, build_rig, simulate
from .spec import CreatureSpec, load_creature

__all__ = ["CreatureSpec", "Motion", "Pose", "Rig", "build_rig", "load_creature", "simulate"]
__version__ = "0.1.0"
