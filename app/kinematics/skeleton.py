"""A solved clip as a skeleton: a joint hierarchy with per-frame local rotations and
translations, for export (BVH, glTF) and for anything that wants bones, not points.

The hierarchy, from the body's root (the middle of the trunk):

- forwards along the spine's segment centres to the neck's base, the head (the neck's
  top) and the nose;
- backwards along the spine to the tail's base and along the tail to its tip;
- each leg from the spine joint nearest its hip: hip, knee, ankle, ball, toe tip;
- each arm (bipeds) from the spine joint nearest its shoulder: shoulder, elbow, wrist, hand.

Every joint's frame points its +Y axis at its first child (the bone's direction; an end
joint keeps its parent's frame). The bone's roll comes from one of the body's axes,
chosen per joint as the axis most perpendicular to the bone in the first frame, so it
never flips while the bone swings. Positions rebuilt from the local transforms equal
the clip's joints to rounding; leg bones keep their lengths.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import NDArray

from .motion import Motion

LEG_JOINTS = ("hip", "knee", "ankle", "ball", "toe")
ARM_JOINTS = ("shoulder", "elbow", "wrist", "hand")


@dataclass(frozen=True)
class Skeleton:
    """Joint names and parents (index, -1 for the root), parents before children."""

    names: tuple[str, ...]
    parents: tuple[int, ...]

    @property
    def count(self) -> int:
        return len(self.names)

    def children(self, index: int) -> list[int]:
        return [j for j, p in enumerate(self.parents) if p == index]

    def index(self, name: str) -> int:
        return self.names.index(name)


@dataclass(frozen=True)
class SkeletonLayout:
    """The choices a skeleton's first frame makes: the spine point nearest the root (where
    the trunk splits forwards and backwards), the spine point each leg and arm hangs from,
    and each joint's roll axis (the body axis most perpendicular to its bone). A clip laid
    out like another has the same joints, in the same order, turning the same way."""

    middle: int
    leg_spine: tuple[int, ...]
    arm_spine: tuple[int, ...]
    roll_axes: tuple[int, ...] = ()


@dataclass(frozen=True)
class SkeletonClip:
    """A skeleton's animation. T frames, J joints; metres, Y up.

    world_position (T, J, 3), world_rotation (T, J, 3, 3) (columns: the joint's x, y, z
    axes); local_rotation (T, J, 3, 3) and local_translation (T, J, 3) relative to the
    parent (the root's are its world values); times (T,) seconds.
    """

    skeleton: Skeleton
    times: NDArray[np.float64]
    world_position: NDArray[np.float64]
    world_rotation: NDArray[np.float64]
    local_rotation: NDArray[np.float64]
    local_translation: NDArray[np.float64]
    fps: float
    layout: SkeletonLayout | None = None  # how it was laid out (pose another clip the same way)

    @property
    def frame_count(self) -> int:
        return int(self.times.shape[0])


def _unit(v: NDArray[np.float64]) -> NDArray[np.float64]:
    n = np.linalg.norm(v, axis=-1, keepdims=True)
    return v / np.maximum(n, 1e-12)


def skeleton_layout(motion: Motion) -> SkeletonLayout:
    """The layout a clip's first frame gives (roll axes left to :func:`skeleton_clip`)."""
    spine, root = motion.spine[0], motion.root[0, :3, 3]

    def nearest(point: NDArray[np.float64]) -> int:
        return int(np.argmin(np.linalg.norm(spine - point, axis=-1)))

    return SkeletonLayout(middle=nearest(root), leg_spine=tuple(nearest(p) for p in motion.joints[0, :, 0]),
                          arm_spine=tuple(nearest(p) for p in motion.arms[0, :, 0]))


def skeleton_points(motion: Motion, layout: SkeletonLayout | None = None
                    ) -> tuple[Skeleton, NDArray[np.float64], list[int], dict[int, NDArray]]:
    """The hierarchy and every joint's world position (T, J, 3); each joint's primary
    child (-1 for end joints), whose direction is the joint's +Y; and the spine joints'
    own directions (the spine's tangent, pointing away from the root): the neck's base
    and the tail's root lie within millimetres of the end segments' centres, too close to
    aim at. ``layout`` (default: the first frame's) says where the trunk splits and
    where the limbs hang."""
    layout = layout or skeleton_layout(motion)
    spine = motion.spine  # (T, S, 3), rear to front
    root = motion.root[:, :3, 3]
    S = spine.shape[1]
    names: list[str] = ["root"]
    parents: list[int] = [-1]
    points: list[NDArray] = [root]
    primary: list[int] = [-1]

    def add(name: str, parent: int, point: NDArray) -> int:
        names.append(name)
        parents.append(parent)
        points.append(point)
        primary.append(-1)
        if primary[parent] == -1 and parent != 0:
            primary[parent] = len(names) - 1
        return len(names) - 1

    middle = layout.middle
    spine_index: dict[int, int] = {}
    directions: dict[int, NDArray] = {}
    parent = 0
    for s in range(middle, S):  # forwards: trunk, neck, head, nose
        parent = spine_index[s] = add(f"spine{s}", parent, spine[:, s])
        directions[parent] = _unit(motion.spine_tangent[:, s])
    parent = add("neck", parent, motion.neck[:, 0])
    parent = add("head", parent, motion.neck[:, 1])
    add("nose", parent, motion.head[:, 1])
    parent = 0
    for s in range(middle - 1, -1, -1):  # backwards: trunk, tail
        parent = spine_index[s] = add(f"spine{s}", parent, spine[:, s])
        directions[parent] = -_unit(motion.spine_tangent[:, s])
    for k in range(motion.tail.shape[1]):
        parent = add(f"tail{k}", parent, motion.tail[:, k])
    joints = motion.joints  # (T, L, 5, 3)
    for leg, leg_name in enumerate(motion.leg_names):
        parent = spine_index[layout.leg_spine[leg]]
        for k, part in enumerate(LEG_JOINTS):
            parent = add(f"{leg_name}_{part}", parent, joints[:, leg, k])
    for arm, side in zip(range(motion.arms.shape[1]), "LR"):
        parent = spine_index[layout.arm_spine[arm]]
        for k, part in enumerate(ARM_JOINTS):
            parent = add(f"{side}_{part}", parent, motion.arms[:, arm, k])
    # The root's frame is the body's own.
    return Skeleton(tuple(names), tuple(parents)), np.stack(points, axis=1), primary, directions


def skeleton_clip(motion: Motion, layout: SkeletonLayout | None = None) -> SkeletonClip:
    """The clip as a skeleton with orientations (see the module's description), laid out
    as its first frame says or as ``layout`` does (another clip's, e.g. a skinned body's
    bind pose: then the same joints turn the same way in both). Each joint's roll is
    measured from the body axis most perpendicular to its bone in the first frame."""
    skeleton, position, primary, directions = skeleton_points(motion, layout)
    roll_axes = layout.roll_axes if layout is not None and layout.roll_axes else None
    T, J = position.shape[:2]
    body = motion.root[:, :3, :3]  # (T, 3, 3) columns: left, up, forward
    rotation = np.empty((T, J, 3, 3))
    rotation[:, 0] = body
    parents_all = np.array(skeleton.parents)
    # Each joint's +Y: its own direction (spine), towards its primary child, or (an end
    # joint) its parent's frame whole. Every joint but the ends at once.
    y = np.zeros((T, J, 3))
    aims = np.array([j for j in range(1, J) if j not in directions and primary[j] >= 0], dtype=np.int64)
    if aims.size:
        bone = position[:, np.array([primary[j] for j in aims])] - position[:, aims]
        length = np.linalg.norm(bone, axis=-1, keepdims=True)
        y[:, aims] = bone / np.maximum(length, 1e-12)
        short = np.nonzero((length[..., 0] <= 1e-9).any(axis=0))[0]
    else:
        short = np.zeros(0, dtype=np.int64)
    for j, d in directions.items():
        y[:, j] = d
    ends = [j for j in range(1, J) if j not in directions and primary[j] < 0]
    framed = np.array([j for j in range(1, J) if j not in ends], dtype=np.int64)
    axes = [0] * J
    for k in short:  # a bone of no length (a creature without a neck) takes its parent's direction, in order
        j = int(aims[k])
        zero = np.linalg.norm(position[:, primary[j]] - position[:, j], axis=-1) <= 1e-9
        parent_y = y[:, parents_all[j]] if parents_all[j] > 0 else body[:, :, 1]
        y[:, j] = np.where(zero[:, None], parent_y, y[:, j])
    if framed.size:
        yf = y[:, framed]  # (T, F, 3)
        if roll_axes is None:
            # The roll reference: the body axis most perpendicular to the bone at the start.
            chosen = np.argmin(np.abs(np.einsum("ik,fi->fk", body[0], yf[0])), axis=1)
        else:
            chosen = np.array([roll_axes[j] for j in framed])
        for j, a in zip(framed, chosen):
            axes[int(j)] = int(a)
        ref = np.moveaxis(body[:, :, chosen], -1, 1)  # (T, F, 3): each joint's chosen body axis
        x = _unit(ref - np.sum(ref * yf, axis=-1, keepdims=True) * yf)
        z = np.cross(x, yf)
        rotation[:, framed] = np.stack([x, yf, z], axis=-1)
    for j in ends:  # parents come first
        rotation[:, j] = rotation[:, parents_all[j]]
        axes[j] = axes[parents_all[j]]
    parents = np.array(skeleton.parents)
    parent_rot = rotation[:, np.maximum(parents, 0)]
    parent_pos = position[:, np.maximum(parents, 0)]
    local_rot = np.einsum("tjki,tjkl->tjil", parent_rot, rotation)  # R_parent^T R
    local_pos = np.einsum("tjki,tjk->tji", parent_rot, position - parent_pos)
    local_rot[:, 0] = rotation[:, 0]
    local_pos[:, 0] = position[:, 0]
    return SkeletonClip(skeleton=skeleton, times=np.asarray(motion.times, dtype=np.float64),
                        world_position=position, world_rotation=rotation, local_rotation=local_rot,
                        local_translation=local_pos, fps=float(motion.fps),
                        layout=replace(layout or skeleton_layout(motion), roll_axes=tuple(axes)))


def forward_kinematics(skeleton: Skeleton, local_rotation: NDArray[np.float64],
                       local_translation: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """World positions (T, J, 3) and rotations (T, J, 3, 3) from local transforms."""
    T, J = local_translation.shape[:2]
    position = np.empty((T, J, 3))
    rotation = np.empty((T, J, 3, 3))
    for j, p in enumerate(skeleton.parents):
        if p < 0:
            rotation[:, j] = local_rotation[:, j]
            position[:, j] = local_translation[:, j]
        else:
            rotation[:, j] = rotation[:, p] @ local_rotation[:, j]
            position[:, j] = position[:, p] + np.einsum("tik,tk->ti", rotation[:, p], local_translation[:, j])
    return position, rotation
