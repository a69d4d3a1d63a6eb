"""Key-pose ghosts: the creature at the key poses of the step it is in, placed along its
path where it stands at each (the viewer draws them faintly around the creature)."""

from __future__ import annotations

import numpy as np

from .footfalls import plan_constant_gait
from .gait import ground_speed
from .motion import Motion, MotionInputs, solve_motion
from .poses import key_pose_phases, reference_foot
from .rig import Rig
from .world import World


def key_pose_ghosts(rig: Rig, world: World, clock: float, travel: float, phase: float) -> Motion:
    """The five key poses (contact, down, pass, up, next contact) of the step a creature is
    in: its clock (cycles) and travel (m) now, and ``phase`` its reference foot's phase.
    The gait is taken as steady; in place, each ghost stands where the ground will have
    carried it (ahead for poses to come, behind for poses past)."""
    first = phase < 0.5
    clocks = clock - phase + key_pose_phases(first_step=first)
    per_cycle = float(ground_speed(rig.gait.stride * rig.leg_scale, rig.gait.duty_factor))
    origin = travel - per_cycle * clock
    plan = plan_constant_gait(rig, world, clocks, per_cycle, origin=origin)
    inputs = MotionInputs(clock=clocks, times=clocks / rig.gait.frequency, plan=plan, travel=origin + per_cycle * clocks,
                          stride=np.broadcast_to(rig.stride_length, plan.phase.shape),
                          bob=np.full(clocks.shape[0], rig.gait.bob), wave=rig.gait.wave)
    motion = solve_motion(rig, world, inputs)
    if world.in_place:  # spread along the ground: each where it is relative to the creature now
        ahead = np.zeros((clocks.shape[0], 3))
        ahead[:, 2] = inputs.travel - travel
        from dataclasses import replace

        motion = replace(motion, joints=motion.joints + ahead[:, None, None], heel=motion.heel + ahead[:, None],
                         arms=motion.arms + ahead[:, None, None], spine=motion.spine + ahead[:, None],
                         neck=motion.neck + ahead[:, None], head=motion.head + ahead[:, None],
                         tail=motion.tail + ahead[:, None])
    return motion


__all__ = ["key_pose_ghosts", "reference_foot"]
