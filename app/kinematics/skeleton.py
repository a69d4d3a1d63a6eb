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
from functools import lru_cache

import numpy as np
from numpy.typing import NDArray

from .body import cross
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
    return v / np.maximum(np.sqrt(np.sum(v * v, axis=-1, keepdims=True)), 1e-12)


def skeleton_layout(motion: Motion) -> SkeletonLayout:
    """The layout a clip's first frame gives (roll axes left to :func:`skeleton_clip`)."""
    spine, root = motion.spine[0], motion.root[0, :3, 3]

    def nearest(point: NDArray[np.float64]) -> int:
        # Of two spine points as near as each other (within a micrometre: the root halfway
        # between two segments' centres), the rear one, whatever the rounding.
        distance = np.linalg.norm(spine - point, axis=-1)
        return int(np.nonzero(distance <= distance.min() + 1e-6)[0][0])

    return SkeletonLayout(middle=nearest(root), leg_spine=tuple(nearest(p) for p in motion.joints[0, :, 0]),
                          arm_spine=tuple(nearest(p) for p in motion.arms[0, :, 0]))


@dataclass(frozen=True)
class _Plan:
    """What a skeleton is made of, worked out once per shape of clip and layout: the
    hierarchy; each joint's point as an index into the clip's points stacked as
    :func:`_stacked_points` stacks them; each joint's primary child; the spine joints
    whose +Y is the spine's own tangent (its segment, and -1 going backwards); and the
    joints :func:`skeleton_clip` aims at their primary child, frames, or leaves with
    their parent's frame (the ends)."""

    skeleton: Skeleton
    sources: NDArray[np.int64]  # (J,)
    primary: tuple[int, ...]
    spine_joints: NDArray[np.int64]
    spine_segments: NDArray[np.int64]
    spine_signs: NDArray[np.float64]
    aims: NDArray[np.int64]
    aim_children: NDArray[np.int64]
    ends: NDArray[np.int64]
    framed: NDArray[np.int64]


@lru_cache(maxsize=64)
def _plan(middle: int, leg_spine: tuple[int, ...], arm_spine: tuple[int, ...], spine_count: int, tail_count: int,
          leg_names: tuple[str, ...], arm_count: int) -> _Plan:
    names: list[str] = ["root"]
    parents: list[int] = [-1]
    sources: list[int] = [0]
    primary: list[int] = [-1]

    def add(name: str, parent: int, source: int) -> int:
        names.append(name)
        parents.append(parent)
        sources.append(source)
        primary.append(-1)
        if primary[parent] == -1 and parent != 0:
            primary[parent] = len(names) - 1
        return len(names) - 1

    spine_at, neck_at = 1, 1 + spine_count  # where each part starts in the stacked points
    tail_at = neck_at + 3
    legs_at = tail_at + tail_count
    arms_at = legs_at + len(leg_names) * len(LEG_JOINTS)
    spine_index: dict[int, int] = {}
    spine_joints: list[tuple[int, int, float]] = []  # joint, segment, sign
    parent = 0
    for s in range(middle, spine_count):  # forwards: trunk, neck, head, nose
        parent = spine_index[s] = add(f"spine{s}", parent, spine_at + s)
        spine_joints.append((parent, s, 1.0))
    parent = add("neck", parent, neck_at)
    parent = add("head", parent, neck_at + 1)
    add("nose", parent, neck_at + 2)
    parent = 0
    for s in range(middle - 1, -1, -1):  # backwards: trunk, tail
        parent = spine_index[s] = add(f"spine{s}", parent, spine_at + s)
        spine_joints.append((parent, s, -1.0))
    for k in range(tail_count):
        parent = add(f"tail{k}", parent, tail_at + k)
    for leg, leg_name in enumerate(leg_names):
        parent = spine_index[leg_spine[leg]]
        for k, part in enumerate(LEG_JOINTS):
            parent = add(f"{leg_name}_{part}", parent, legs_at + leg * len(LEG_JOINTS) + k)
    for arm, side in zip(range(arm_count), "LR"):
        parent = spine_index[arm_spine[arm]]
        for k, part in enumerate(ARM_JOINTS):
            parent = add(f"{side}_{part}", parent, arms_at + arm * len(ARM_JOINTS) + k)
    own = {j for j, _, _ in spine_joints}
    count = len(names)
    aims = [j for j in range(1, count) if j not in own and primary[j] >= 0]
    ends = [j for j in range(1, count) if j not in own and primary[j] < 0]
    index = np.array([j for j, _, _ in spine_joints], dtype=np.int64)
    return _read_only(_Plan(skeleton=Skeleton(tuple(names), tuple(parents)), sources=np.array(sources, dtype=np.int64),
                 primary=tuple(primary), spine_joints=index,
                 spine_segments=np.array([s for _, s, _ in spine_joints], dtype=np.int64),
                 spine_signs=np.array([sign for _, _, sign in spine_joints]),
                 aims=np.array(aims, dtype=np.int64), aim_children=np.array([primary[j] for j in aims], dtype=np.int64),
                 ends=np.array(ends, dtype=np.int64),
                 framed=np.array([j for j in range(1, count) if j not in ends], dtype=np.int64)))


def _read_only(plan: _Plan) -> _Plan:
    """``plan`` with its arrays locked: every clip of its shape shares them (cached)."""
    for value in vars(plan).values():
        if isinstance(value, np.ndarray):
            value.flags.writeable = False
    return plan


def _stacked_points(motion: Motion) -> NDArray[np.float64]:
    """Every point a skeleton may stand a joint on (T, P, 3): the root, the spine's
    segment centres, the neck's base and top and the nose, the tail, every leg's joints
    and every arm's (the order :func:`_plan`'s sources index)."""
    frames = motion.spine.shape[0]
    return np.concatenate([motion.root[:, None, :3, 3], motion.spine, motion.neck[:, :2], motion.head[:, 1:2],
                           motion.tail, motion.joints.reshape(frames, -1, 3), motion.arms.reshape(frames, -1, 3)],
                          axis=1)


def _plan_for(motion: Motion, layout: SkeletonLayout) -> _Plan:
    return _plan(layout.middle, tuple(layout.leg_spine), tuple(layout.arm_spine), motion.spine.shape[1],
                 motion.tail.shape[1], tuple(motion.leg_names), motion.arms.shape[1])


def _spine_directions(motion: Motion, plan: _Plan) -> NDArray[np.float64]:
    """The spine joints' own +Y (T, K, 3): the spine's tangent, away from the root."""
    return _unit(motion.spine_tangent[:, plan.spine_segments]) * plan.spine_signs[:, None]


def skeleton_points(motion: Motion, layout: SkeletonLayout | None = None
                    ) -> tuple[Skeleton, NDArray[np.float64], list[int], dict[int, NDArray]]:
    """The hierarchy and every joint's world position (T, J, 3); each joint's primary
    child (-1 for end joints), whose direction is the joint's +Y; and the spine joints'
    own directions (the spine's tangent, pointing away from the root): the neck's base
    and the tail's root lie within millimetres of the end segments' centres, too close to
    aim at. ``layout`` (default: the first frame's) says where the trunk splits and
    where the limbs hang."""
    plan = _plan_for(motion, layout or skeleton_layout(motion))
    own = _spine_directions(motion, plan)
    directions = {int(j): own[:, k] for k, j in enumerate(plan.spine_joints)}
    return plan.skeleton, _stacked_points(motion)[:, plan.sources], list(plan.primary), directions


def skeleton_clip(motion: Motion, layout: SkeletonLayout | None = None) -> SkeletonClip:
    """The clip as a skeleton with orientations (see the module's description), laid out
    as its first frame says or as ``layout`` does (another clip's, e.g. a skinned body's
    bind pose: then the same joints turn the same way in both). Each joint's roll is
    measured from the body axis most perpendicular to its bone in the first frame."""
    layout = layout or skeleton_layout(motion)
    plan = _plan_for(motion, layout)
    skeleton, aims, framed = plan.skeleton, plan.aims, plan.framed
    position = _stacked_points(motion)[:, plan.sources]
    roll_axes = layout.roll_axes or None
    T, J = position.shape[:2]
    body = motion.root[:, :3, :3]  # (T, 3, 3) columns: left, up, forward
    rotation = np.empty((T, J, 3, 3))
    rotation[:, 0] = body
    parents_all = np.array(skeleton.parents)
    # Each joint's +Y: its own direction (spine), towards its primary child, or (an end
    # joint) its parent's frame whole. Every joint but the ends at once.
    y = np.zeros((T, J, 3))
    if aims.size:
        bone = position[:, plan.aim_children] - position[:, aims]
        length = np.sqrt(np.sum(bone * bone, axis=-1, keepdims=True))
        y[:, aims] = bone / np.maximum(length, 1e-12)
        short = np.nonzero((length[..., 0] <= 1e-9).any(axis=0))[0]
    else:
        short = np.zeros(0, dtype=np.int64)
    y[:, plan.spine_joints] = _spine_directions(motion, plan)
    axes = np.zeros(J, dtype=np.int64)
    for k in short:  # a bone of no length (a creature without a neck) takes its parent's direction, in order
        j = int(aims[k])
        zero = np.linalg.norm(position[:, plan.primary[j]] - position[:, j], axis=-1) <= 1e-9
        parent_y = y[:, parents_all[j]] if parents_all[j] > 0 else body[:, :, 1]
        y[:, j] = np.where(zero[:, None], parent_y, y[:, j])
    if framed.size:
        yf = y[:, framed]  # (T, F, 3)
        if roll_axes is None:
            # The roll reference: the body axis most perpendicular to the bone at the start.
            chosen = np.argmin(np.abs(np.einsum("ik,fi->fk", body[0], yf[0])), axis=1)
        else:
            chosen = np.asarray(roll_axes, dtype=np.int64)[framed]
        axes[framed] = chosen
        ref = np.swapaxes(body, 1, 2)[:, chosen]  # (T, F, 3): each joint's chosen body axis
        x = _unit(ref - np.sum(ref * yf, axis=-1, keepdims=True) * yf)
        frame = rotation[:, framed]
        frame[..., 0], frame[..., 1], frame[..., 2] = x, yf, cross(x, yf)
        rotation[:, framed] = frame
    ends = plan.ends  # leaves: their parents are framed joints (a parent has a child)
    rotation[:, ends] = rotation[:, parents_all[ends]]
    axes[ends] = axes[parents_all[ends]]
    parents = np.maximum(parents_all, 0)
    parent_rot = rotation[:, parents]
    parent_pos = position[:, parents]
    local_rot = np.einsum("tjki,tjkl->tjil", parent_rot, rotation)  # R_parent^T R
    local_pos = np.einsum("tjki,tjk->tji", parent_rot, position - parent_pos)
    local_rot[:, 0] = rotation[:, 0]
    local_pos[:, 0] = position[:, 0]
    return SkeletonClip(skeleton=skeleton, times=np.asarray(motion.times, dtype=np.float64),
                        world_position=position, world_rotation=rotation, local_rotation=local_rot,
                        local_translation=local_pos, fps=float(motion.fps),
                        layout=replace(layout, roll_axes=tuple(axes.tolist())))


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
