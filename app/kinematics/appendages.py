"""How a creature's neck, head and tail turn away from where they rest, for a rigged
model's own neck and tail bones to turn the same way (``app.rigged.drive``).

The creature holds its neck ``neck_angle`` above the level heading, its head
``head_angle`` below it, and each tail segment drooping behind (``body.py``); its nod,
follow-through and tail sway turn them from there. Per frame, the turn of each part
from that resting direction to its direction now, in the heading frame (side, up, level
forward): a model keeps its own neck and tail shape and adds the creature's motion.
Pure numpy, no GL.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from .body import cross, pitch, unit
from .frames import UP
from .herd import rotation_between
from .rig import Rig


@dataclass(frozen=True)
class Appendages:
    """Turns (rotation matrices, heading frame) from each part's resting direction to its
    direction now: neck (T, 3, 3), head (T, 3, 3), tail (T, K, 3, 3), K tail segments."""

    neck: NDArray[np.float64]
    head: NDArray[np.float64]
    tail: NDArray[np.float64]

    def at(self, frames: NDArray[np.intp]) -> Appendages:
        """The turns at the given frame indices (N,)."""
        return Appendages(self.neck[frames], self.head[frames], self.tail[frames])


def heading_frames(root: NDArray[np.float64]) -> NDArray[np.float64]:
    """Rotations (T, 3, 3) whose columns are the body's side, up and level forward, from
    body transforms ``root`` (T, 4, 4) (forward is their third column)."""
    forward = unit(root[:, :3, 2] * np.array([1.0, 0.0, 1.0]) + np.array([0.0, 0.0, 1e-12]))
    side = cross(UP, forward)
    return np.stack([side, np.broadcast_to(UP, forward.shape), forward], axis=-1)


def appendage_turns(rig: Rig, neck: NDArray[np.float64], head: NDArray[np.float64], tail: NDArray[np.float64],
                    root: NDArray[np.float64]) -> Appendages:
    """The turns of a creature's neck (T, 2, 3: base, top), head (T, 2, 3: back of skull,
    nose) and tail (T, K + 1, 3: base to tip) from their resting directions, for body
    transforms ``root`` (T, 4, 4)."""
    body = rig.body
    frames = heading_frames(root)  # (T, 3, 3)
    forward = frames[..., 2]
    droop = body.tail_droop(tail.shape[1] - 1)  # (K,)
    rest = {"neck": pitch(forward, body.neck_angle), "head": pitch(forward, -body.head_angle),
            "tail": pitch(-forward[:, None, :], -droop[None, :])}
    now = {"neck": unit(neck[:, 1] - neck[:, 0]), "head": unit(head[:, 1] - head[:, 0]),
           "tail": unit(np.diff(tail, axis=1))}
    turns = {}
    for part in ("neck", "head", "tail"):
        world = rotation_between(rest[part], now[part])  # (T, 3, 3) or (T, K, 3, 3)
        f = frames if world.ndim == 3 else frames[:, None]
        turns[part] = np.swapaxes(f, -1, -2) @ world @ f
    return Appendages(turns["neck"], turns["head"], turns["tail"])
