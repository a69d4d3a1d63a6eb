"""The natural walk's body heights: the hips carried over the stance leg as walkers carry
them, an inverted pendulum on a nearly straight leg with a brief give in loading.

For each key pose of a step (contact, down, pass, up) the hips stand as high as the
leading stance leg allows with its knee flexed as a walker's is at that moment (about
5 degrees at contact, 19 in loading response, 14 and 7 towards mid-stance: Schwartz,
Rozumalski & Trost 2008, the free-speed mean), and never higher than a trailing foot
still on the ground allows with its knee all but straight. The feet are where the gait
puts them (they do not depend on the body's height), so one solve of the four key frames
gives them. The body crests once a step, at the pass (mid-stance). The heights are
offsets from the girdle's rest height, as key poses are: the ``normal`` style of a
creature whose feet roll heel to toe.

Pure numpy, no GL.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
from numpy.typing import NDArray

from .motion import constant_gait_inputs, solve_motion
from .poses import key_pose_phases, reference_foot
from .rig import Rig
from .roll import straight_leg
from .world import World

STANCE_KNEE = np.radians([5.6, 19.0, 13.5, 6.7])  # the leading leg's knee at contact, down, pass and up
PAST_CREST = 0.003  # m: how far the up pose stands below the pass


def natural_heights(rig: Rig) -> NDArray[np.float64]:
    """Key-pose heights (4,) in metres from the rest height (contact, down, pass, up) of
    a walk whose hips ride over the stance leg (see the module docstring)."""
    high = np.full(4, 0.5 * rig.hip_height)  # out of reach: the legs decide where the hips are
    probe = replace(rig, poses=replace(rig.poses, heights=high))
    clock = key_pose_phases(first_step=True)[:4]
    world = World(in_place=True)
    motion = solve_motion(probe, world, constant_gait_inputs(probe, world, clock, clock / rig.gait.frequency))
    lead = reference_foot(rig)
    trail = lead + 1
    hips, ankles = motion.joints[:, :, 0], motion.joints[:, :, 2]
    centre = 0.5 * (hips[:, lead, 1] + hips[:, trail, 1])

    def centre_for(leg: int, span: NDArray[np.float64]) -> NDArray[np.float64]:
        """The girdle centre's height (T,) that puts ``leg``'s hip ``span`` from its ankle."""
        across = np.linalg.norm((hips[:, leg] - ankles[:, leg])[:, [0, 2]], axis=-1)
        hip = ankles[:, leg, 1] + np.sqrt(np.maximum(span ** 2 - across ** 2, 0.0))
        return hip - (hips[:, leg, 1] - centre)

    f, t = rig.femur[lead], rig.tibia[lead]
    bent = np.sqrt(f * f + t * t + 2.0 * f * t * np.cos(STANCE_KNEE))
    height = centre_for(lead, bent)
    trailing = motion.contact[:, trail]
    cap = centre_for(trail, np.full(4, straight_leg(rig)[trail]))
    height = np.where(trailing, np.minimum(height, cap), height)
    # One crest per step, at mid-stance: the up pose comes down from the pass, as the body
    # falls towards the other foot's strike.
    height[3] = min(height[3], height[2] - PAST_CREST)
    return height - rig.girdle_rest_height[rig.girdle[lead]]
