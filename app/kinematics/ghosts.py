"""Key-pose ghosts: the creature at the key poses of the step it is in, placed along its
path where it stands at each (the viewer draws them faintly around the creature)."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
from numpy.typing import NDArray

from .motion import POINT_FIELDS, Motion, Pose, constant_gait_inputs, solve_motion, travel_per_cycle
from .poses import key_pose_phases
from .rig import Rig
from .world import World


def shift_pose(pose: Pose, offset: NDArray[np.float64]) -> Pose:
    """The pose moved by ``offset`` (3,) metres (its root too)."""
    moved = {name: getattr(pose, name) + offset for name in POINT_FIELDS}
    root = pose.root.copy()
    root[:3, 3] += offset
    return replace(pose, root=root, **moved)


def key_pose_ghosts(rig: Rig, world: World, clock: float, travel: float, phase: float) -> Motion:
    """The five key poses (contact, down, pass, up, next contact) of the step a creature is
    in: its clock (cycles) and travel (m) now, and ``phase`` its reference foot's phase.
    The gait is taken as steady; in place, each ghost stands where the ground will have
    carried it (ahead for poses to come, behind for poses past)."""
    clocks = clock - phase + key_pose_phases(first_step=phase < 0.5)
    origin = travel - travel_per_cycle(rig) * clock
    inputs = constant_gait_inputs(rig, world, clocks, clocks / rig.gait.frequency, origin=origin)
    motion = solve_motion(rig, world, inputs)
    if not world.in_place:
        return motion
    # In place every pose stands at the origin: spread them by how far each is along.
    ahead = np.zeros((clocks.shape[0], 3))
    ahead[:, 2] = inputs.travel - travel
    root = motion.root.copy()
    root[:, :3, 3] += ahead
    return replace(motion, root=root, joints=motion.joints + ahead[:, None, None], heel=motion.heel + ahead[:, None],
                   arms=motion.arms + ahead[:, None, None], spine=motion.spine + ahead[:, None],
                   neck=motion.neck + ahead[:, None], head=motion.head + ahead[:, None],
                   tail=motion.tail + ahead[:, None])
