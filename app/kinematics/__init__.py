"""Pure-numpy kinematics: oscillators, leg IK, paths, terrain, footfalls, body and motion.

No OpenGL, no files: a :class:`Rig` (built from a creature file by :mod:`app.rigging`)
and the world (a :class:`~app.kinematics.path.Path` and a
:class:`~app.kinematics.terrain.Terrain`) go in, :class:`Motion` comes out.
"""

from .motion import Motion, Pose, frame_count, simulate, solve_motion
from .rig import Rig

__all__ = ["Motion", "Pose", "Rig", "frame_count", "simulate", "solve_motion"]
