"""Arcs: the paths chosen joints trace over a cycle, as an animator checks a walk's flow.

A trail is the joint's position sampled every frame (world space, or relative to the body
walking in place), with markers where the key poses fall. Pure numpy, no GL.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from ..choices import ARC_JOINTS, ArcJoint  # noqa: F401 (re-exported)
from .motion import Motion
from .poses import key_pose_phases


def arc_points(motion: Motion, joint: str) -> NDArray[np.float64]:
    """Where ``joint`` is on each side or leg in every frame, (T, K, 3): toe tips, heels,
    knees and hips of every leg; hand tips of both arms; the nose; the tail tip. Raises
    ValueError for an unknown joint, or one the creature does not have (hands, tail)."""
    if joint not in ARC_JOINTS:
        raise ValueError(f"arc joint {joint!r}: choose from {', '.join(ARC_JOINTS)}")
    if joint in ("toe", "knee", "hip"):
        return motion.joints[:, :, {"toe": 4, "knee": 1, "hip": 0}[joint]]
    if joint == "heel":
        return motion.heel
    if joint == "hand":
        if motion.arms.shape[1] == 0:
            raise ValueError(f"arc joint 'hand': the {motion.rig.name} has no arms")
        return motion.arms[:, :, 3]
    if joint == "head":
        return motion.head[:, 1:2]
    if motion.rig.body.tail_length <= 0:
        raise ValueError(f"arc joint 'tail': the {motion.rig.name} has no tail")
    return motion.tail[:, -1:]


def parse_arc_joints(text: str) -> tuple[str, ...]:
    """``"toe,hand"`` -> ("toe", "hand"). Raises ValueError naming a bad joint."""
    names = tuple(dict.fromkeys(p.strip() for p in text.split(",") if p.strip()))
    if not names:
        raise ValueError(f"--arcs {text!r}: give joints separated by commas, from {', '.join(ARC_JOINTS)}")
    for name in names:
        if name not in ARC_JOINTS:
            raise ValueError(f"--arcs: unknown joint {name!r}; choose from {', '.join(ARC_JOINTS)}")
    return names


def trail(points: NDArray[np.float64], index: int, frames_per_cycle: int) -> NDArray[np.float64]:
    """The last cycle of a trail up to frame ``index`` (inclusive): points (T, K, 3) ->
    (N, K, 3), N <= frames_per_cycle + 1."""
    start = max(0, index - frames_per_cycle)
    return points[start:index + 1]


def key_pose_frames(motion: Motion, index: int, frames_per_cycle: int) -> NDArray[np.int64]:
    """Frames in the trail ending at ``index`` where the key poses fall (contact, down,
    pass, up of both steps): the frames nearest each key-pose phase of the cycle."""
    start = max(0, index - frames_per_cycle)
    phase = motion.phase[start:index + 1, motion.rig.leg_count - 2]
    keys = np.unique(np.mod(np.concatenate([key_pose_phases(True), key_pose_phases(False)]), 1.0))
    distance = np.abs(np.mod(phase[:, None] - keys[None, :] + 0.5, 1.0) - 0.5)  # (N, 8)
    step = 0.5 / max(frames_per_cycle, 1)
    near = distance <= step + 1e-12
    # The one nearest frame for each key phase present in the trail.
    best = np.argmin(np.where(near, distance, np.inf), axis=0)
    return np.unique(best[near.any(axis=0)]) + start
