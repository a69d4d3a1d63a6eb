"""Pure-numpy kinematics: oscillators, leg IK, spine, gait and motion. No OpenGL here."""

from .motion import Motion, Pose, frame_count, simulate, solve_motion
from .rig import Rig, build_rig

__all__ = ["Motion", "Pose", "Rig", "build_rig", "frame_count", "simulate", "solve_motion"]
