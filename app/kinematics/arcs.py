"""Arcs: the paths chosen joints trace over a cycle, as an animator checks a walk's flow.

A trail is the joint's position sampled every frame (world space, or relative to the body
walking in place), with markers where the key poses fall. Pure numpy, no GL.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from ..choices import ARC_JOINTS
from ..errors import did_you_mean
from .motion import Motion
from .poses import key_pose_phases, reference_foot


def _others(joint: str) -> str:
    return ", ".join(j for j in ARC_JOINTS if j not in (joint, "hand", "tail"))


def arc_points(motion, joint: str) -> NDArray[np.float64]:
    """Where ``joint`` is on each side or leg, (T, K, 3) for a :class:`Motion` ((K, 3) for
    a single Pose): toe tips, heels, knees and hips of every leg; hand tips of both arms;
    the nose; the tail tip. Raises ValueError for an unknown joint, or one the creature
    does not have (hands, tail)."""
    if joint not in ARC_JOINTS:
        raise ValueError(f"arc joint {joint!r}: choose from {', '.join(ARC_JOINTS)}")
    if joint in ("toe", "knee", "hip"):
        return motion.joints[..., {"toe": 4, "knee": 1, "hip": 0}[joint], :]
    if joint == "heel":
        return motion.heel
    if joint == "hand":
        if motion.arms.shape[-3] == 0:
            raise ValueError(f"arc joint 'hand': this creature has no arms; choose from {_others('hand')}")
        return motion.arms[..., 3, :]
    if joint == "head":
        return motion.head[..., 1:2, :]
    if np.linalg.norm(motion.tail[..., -1, :] - motion.tail[..., 0, :], axis=-1).max() <= 1e-9:
        raise ValueError(f"arc joint 'tail': this creature has no tail; choose from {_others('tail')}")
    return motion.tail[..., -1:, :]


class ArcTrail:
    """The last cycle of arc points of a live creature, frame by frame (the viewer's
    arcs): :meth:`record` each drawn pose, :meth:`trails` for what to draw."""

    def __init__(self) -> None:
        self.times: list[float] = []
        self.phases: list[float] = []
        self.points: list[dict[str, NDArray[np.float64]]] = []

    def clear(self) -> None:
        self.times, self.phases, self.points = [], [], []

    def record(self, pose, joints: tuple[str, ...], time: float, period: float, reference: int) -> None:
        """Add a pose's points for ``joints`` at animation ``time`` (s), keeping ``period``
        seconds; ``reference`` is the foot whose phase places the key poses. Joints the
        creature lacks are left out."""
        if self.times and time < self.times[-1]:
            self.clear()  # time went back (a scrub or a reset): start over
        paused = bool(self.times) and time == self.times[-1]  # the same frame drawn again
        row = {j: p for j, p in self.points[-1].items() if j in joints} if paused else {}
        if paused:
            self.points[-1] = row
        for joint in joints:
            if joint in row:
                continue
            try:
                row[joint] = arc_points(pose, joint)
            except ValueError:
                continue
        if paused:
            return
        self.times.append(time)
        self.phases.append(float(pose.phase[reference]))
        self.points.append(row)
        while self.times and self.times[0] < time - period:
            self.times.pop(0)
            self.phases.pop(0)
            self.points.pop(0)

    def trails(self) -> tuple[dict[str, NDArray[np.float64]], dict[str, NDArray[np.float64]]]:
        """Each joint's trail (N, K, 3) and its key-pose beads (M, K, 3)."""
        if not self.points:
            return {}, {}
        # A joint ticked a moment ago draws from the frame it was first recorded.
        trails = {}
        for j in self.points[-1]:
            rows = [row[j] for row in self.points if j in row]
            trails[j] = np.stack(rows)
        phase = np.asarray(self.phases)
        keys = key_phases()
        # A key pose falls between two recorded frames where the phase passes it.
        before, after = phase[:-1, None], phase[1:, None]
        passed = ((before <= keys) & (after > keys)) | ((before > after) & ((keys >= before) | (keys < after)))
        frames = np.unique(np.nonzero(passed)[0] + 1)
        beads = {}
        for j, t in trails.items():
            offset = len(self.points) - len(t)  # the rows before this joint was ticked
            beads[j] = t[frames[frames >= offset] - offset]
        return trails, beads


def key_phases() -> NDArray[np.float64]:
    """The cycle phases (8,) of the key poses of both steps, in [0, 1)."""
    return np.unique(np.mod(np.concatenate([key_pose_phases(True), key_pose_phases(False)]), 1.0))


def parse_arc_joints(text: str) -> tuple[str, ...]:
    """``"toe,hand"`` -> ("toe", "hand"). Raises ValueError naming a bad joint."""
    names = tuple(dict.fromkeys(p.strip() for p in text.split(",") if p.strip()))
    if not names:
        raise ValueError(f"--arcs {text!r}: give joints separated by commas, from {', '.join(ARC_JOINTS)}")
    for name in names:
        if name not in ARC_JOINTS:
            raise ValueError(f"--arcs: unknown joint {name!r}{did_you_mean(name, ARC_JOINTS)}; choose from "
                             f"{', '.join(ARC_JOINTS)}")
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
    phase = motion.phase[start:index + 1, reference_foot(motion.rig)]
    keys = key_phases()
    distance = np.abs(np.mod(phase[:, None] - keys[None, :] + 0.5, 1.0) - 0.5)  # (N, 8)
    step = 0.5 / max(frames_per_cycle, 1)
    near = distance <= step + 1e-12
    # The one nearest frame for each key phase present in the trail.
    best = np.argmin(np.where(near, distance, np.inf), axis=0)
    return np.unique(best[near.any(axis=0)]) + start
