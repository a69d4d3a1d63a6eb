"""A Gaitlab motion on a rigged model's own skeleton: every joint's world transform, every
frame, in metres, ready for skinning with the model's own weights.

The body moves rigidly with the creature's hips (a weighted least-squares fit of the
model's hip joints, and lightly of the body's forward and up directions, to the
creature's, per frame). Each
leg is re-solved from the model's own hip with its own bone lengths: two-bone IK to the
creature's ankle (bending towards the creature's knee), then the foot's bones along the
creature's foot, so a planted ball stands where the creature plants it. Each leg bone
turns so that it points along its new direction with the body's side as its second axis;
every other joint keeps its rest transform relative to its parent, so every bone keeps
its length exactly.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from ..kinematics.appendages import Appendages, appendage_turns, heading_frames
from ..kinematics.body import cross, unit
from ..kinematics.herd import rotation_about, rotation_between
from ..kinematics.motion import Motion
from .gltf import RiggedModel
from .legs import ModelLegs

FIT_REACH = 1.0  # m: how far ahead and above the hips the body's extra fit points lie
FIT_HINT = 1e-3  # their weight against a hip's
SIDE, FRONT = np.array([1.0, 0.0, 0.0]), np.array([0.0, 0.0, 1.0])  # a model's left and front at rest (+x, +z)
ARM_OUT = np.radians(8.0)  # a biped model's arms hang this far out from its sides



def rest_in_metres(model: RiggedModel, scale: float) -> NDArray[np.float64]:
    """The model's rest transforms (J, 4, 4), rigid (the nearest rotation to each: a
    file's float32 rotations, or scales, are not quite orthonormal), positions in metres."""
    rest = model.rest.copy()
    u, _, vt = np.linalg.svd(rest[:, :3, :3])
    rest[:, :3, :3] = u @ vt
    rest[:, :3, 3] *= scale
    return rest


def body_fit(source: NDArray[np.float64], target: NDArray[np.float64],
             weights: NDArray[np.float64] | None = None) -> NDArray[np.float64]:
    """Rigid transforms (T, 4, 4) taking points ``source`` (K, 3) onto ``target``
    (T, K, 3) in the weighted least-squares sense (Kabsch, per frame; ``weights`` (K,))."""
    w = np.ones(len(source)) if weights is None else np.asarray(weights, dtype=np.float64)
    w = w / w.sum()
    c_src = w @ source
    c_dst = np.einsum("k,tki->ti", w, target)
    h = np.einsum("k,ki,tkj->tij", w, source - c_src, target - c_dst[:, None, :])
    u, _, vt = np.linalg.svd(h)
    d = np.sign(np.linalg.det(np.swapaxes(vt, 1, 2) @ np.swapaxes(u, 1, 2)))
    fix = np.tile(np.eye(3), (len(target), 1, 1))
    fix[:, 2, 2] = d
    rot = np.swapaxes(vt, 1, 2) @ fix @ np.swapaxes(u, 1, 2)
    out = np.tile(np.eye(4), (len(target), 1, 1))
    out[:, :3, :3] = rot
    out[:, :3, 3] = c_dst - np.einsum("tij,j->ti", rot, c_src)
    return out


def _order(parents: NDArray[np.int64]) -> list[int]:
    """Joints with every parent before its children."""
    depth = np.zeros(len(parents), dtype=np.int64)
    for j in range(len(parents)):
        p, d = int(parents[j]), 0
        while p >= 0:
            p, d = int(parents[p]), d + 1
        depth[j] = d
    return [int(j) for j in np.argsort(depth, kind="stable")]


def _girdle_fit(rest: NDArray[np.float64], tops: list[int], hips_now: NDArray[np.float64],
                root: NDArray[np.float64]) -> NDArray[np.float64]:
    """The rigid transforms (T, 4, 4) taking the model's leg tops ``tops`` (with a hint of
    the body's forward and up directions) onto the creature's hips ``hips_now`` (T, K, 3)."""
    hips_rest = rest[tops, :3, 3]
    centre = hips_rest.mean(axis=0)
    source = np.concatenate([hips_rest, [centre + [0.0, 0.0, FIT_REACH], centre + [0.0, FIT_REACH, 0.0]]])
    centre_now = hips_now.mean(axis=1)
    forward, up = root[:, :3, 2], root[:, :3, 1]
    target = np.concatenate([hips_now, (centre_now + FIT_REACH * forward)[:, None],
                             (centre_now + FIT_REACH * up)[:, None]], axis=1)
    # The hips decide (a girdle rolls on a slope); the two points ahead and above only
    # settle what the hips leave open (a biped's pitch about its hip line).
    weights = np.concatenate([np.ones(len(tops)), [FIT_HINT, FIT_HINT]])
    return body_fit(source, target, weights)


_PREPARED: dict[tuple[int, float], tuple] = {}  # (id(model), scale) -> (model, rest, local, order)


def _prepared(model: RiggedModel, scale: float) -> tuple[NDArray[np.float64], NDArray[np.float64], list[int]]:
    """The model's rest transforms in metres, each joint's rest transform in its parent's
    frame, and the joints parents first: worked out once per model (the viewer drives it
    every frame)."""
    key = (id(model), scale)
    known = _PREPARED.get(key)
    if known is None or known[0] is not model:
        rest = rest_in_metres(model, scale)
        local = np.array([np.linalg.inv(rest[p]) @ rest[j] if p >= 0 else rest[j] for j, p in enumerate(model.parents)])
        if len(_PREPARED) > 16:
            _PREPARED.clear()
        known = _PREPARED[key] = (model, rest, local, _order(model.parents))
    return known[1], known[2], known[3]


_LAYOUTS: dict[tuple[int, int, float, bool], tuple] = {}  # (id(model), id(legs), scale, arms) -> (model, legs, layout)


def _leg_layout(model: RiggedModel, legs: ModelLegs, scale: float, with_arms: bool
                ) -> tuple[set[int], dict[int, int], NDArray[np.bool_], NDArray[np.float64]]:
    """Where the limbs are in the model's skeleton (the legs, and ``with_arms`` a biped's
    arms after them), worked out once per model and legs: the joints in a limb, each
    limb's top joint -> its limb, which joints hang under a limb's top (the limb and what
    it carries, (J,)), and how far (m) each leg reaches, (L,) (just short of femur +
    tibia)."""
    key = (id(model), id(legs), scale, with_arms)
    known = _LAYOUTS.get(key)
    if known is None or known[0] is not model or known[1] is not legs:
        rest, _, order = _prepared(model, scale)
        limbs = legs.chains + (legs.arms if with_arms else ())
        in_chain = {j for c in limbs for j in c.joints}
        tops = {c.joints[0]: limb for limb, c in enumerate(limbs)}
        below_leg = np.zeros(len(model.parents), dtype=bool)
        for j in order:
            p = int(model.parents[j])
            below_leg[j] = j in in_chain or (p >= 0 and below_leg[p])
        reach = 0.999 * np.array([np.linalg.norm(np.diff(rest[list(c.joints[:3]), :3, 3], axis=0), axis=1).sum()
                                  for c in legs.chains])
        if len(_LAYOUTS) > 16:
            _LAYOUTS.clear()
        known = _LAYOUTS[key] = (model, legs, (in_chain, tops, below_leg, reach))
    return known[2]


def _path(parents: NDArray[np.int64], top: int, bottom: int) -> list[int] | None:
    """The joints from ``top`` (excluded) down to ``bottom`` (included), or None when
    ``bottom`` is not below ``top``."""
    path = []
    j = bottom
    while j >= 0 and j != top:
        path.append(j)
        j = int(parents[j])
    return path[::-1] if j == top else None


def drive_model(model: RiggedModel, legs: ModelLegs, scale: float, motion: Motion) -> NDArray[np.float64]:
    """Every joint's world transform (T, J, 4, 4) for ``motion`` of the model's creature
    (see :func:`drive_joints`)."""
    return drive_joints(model, legs, scale, motion.joints, motion.root, foot_angle=motion.rig.ankle_lift,
                        arms=motion.arms, turns=motion_turns(motion))


def motion_turns(motion) -> Appendages:
    """The turns of a clip's (or a pose's: any object with ``rig``, ``neck``, ``head``,
    ``tail`` and ``root``) neck, head and tail for a model's own to follow."""
    return appendage_turns(motion.rig, motion.neck, motion.head, motion.tail, motion.root)


def drive_joints(model: RiggedModel, legs: ModelLegs, scale: float, leg_joints: NDArray[np.float64],
                 root: NDArray[np.float64], clearance: NDArray[np.float64] | None = None,
                 foot_angle: NDArray[np.float64] | None = None,
                 arms: NDArray[np.float64] | None = None, turns: Appendages | None = None) -> NDArray[np.float64]:
    """Every joint's world transform (T, J, 4, 4), rigid, in metres, for the creature's
    leg joints ``leg_joints`` (T, L, 5, 3; legs in the order of ``legs.chains``) and body
    transforms ``root`` (T, 4, 4). ``clearance`` (L,) m: how far above its sole each
    leg's last joint stands in the model (the creature's foot joints touch the ground;
    the model's foot is raised by that much). ``foot_angle`` (L,) rad: the creature's
    metatarsus angle above the ground when its foot stands flat (its ankle lift).
    ``arms`` (T, 2, 4, 3): the creature's arms (shoulder, elbow, wrist, hand tip; left,
    right); a biped model's arms (``legs.arms``) swing as they do, each solved from the
    model's own shoulder to where the creature's wrist is from its shoulder. ``turns``:
    how the creature's neck, head and tail turn from rest (:mod:`app.kinematics.appendages`);
    the model's neck and tail bones (``legs.neck``, ``legs.tail``) turn as much from their
    own rest, its head as the creature's head.

    The hind girdle (the joint the hindmost legs hang from) moves with the creature's
    hind hips; with two pairs of legs the spine between it and the fore girdle turns, in
    one piece about the hind girdle, to reach where the creature's fore hips put the fore
    girdle, which then turns with them (the back bends and the shoulders roll on their
    own, as the creature's do). Where a leg's hip is then too far from its foot (the
    model's rigid spine cannot stretch as the creature's hips part on a hill), the whole
    body comes down until every foot is within reach.

    A foot's bones turn as the creature's foot turns from standing flat (with
    ``foot_angle``; without it, they lie along the creature's foot), so a model's foot
    keeps its own shape on the ground: its ball stands where the creature's does, and the
    ankle is put where the model's foot puts it."""
    rest, local, order = _prepared(model, scale)
    frames = len(leg_joints)
    parents = model.parents
    chains = legs.chains
    hind = [chains[-2].joints[0], chains[-1].joints[0]]
    body = _girdle_fit(rest, hind, leg_joints[:, -2:, 0], root)  # (T, 4, 4)
    fore_girdle, spine, fore = -1, None, None
    if len(legs.pairs) >= 2:
        fore_girdle = int(parents[chains[0].joints[0]])
        spine = _path(parents, int(parents[hind[0]]), fore_girdle)
        if spine is not None and spine:
            fore = _girdle_fit(rest, [chains[0].joints[0], chains[1].joints[0]], leg_joints[:, :2, 0], root)
    side_now = body[:, :3, 0]
    world = np.zeros((frames, len(parents), 4, 4))
    arm_chains = legs.arms if arms is not None and len(legs.arms) == arms.shape[1] > 0 else ()
    in_chain, tops, below_leg, reach = _leg_layout(model, legs, scale, bool(arm_chains))
    # The body first (every joint not in or below a limb), and where each limb's top is.
    top_at = np.zeros((frames, len(chains) + len(arm_chains), 3))
    following = _followers(legs, rest, turns, root)
    for j in order:
        p = int(parents[j])
        if j in tops:
            top_at[:, tops[j]] = ((world[:, p] if p >= 0 else body) @ (local[j] if p >= 0 else rest[j]))[:, :3, 3]
        if below_leg[j]:
            continue
        above = body if p < 0 else world[:, p]
        world[:, j] = above @ (rest[j] if p < 0 else local[j])
        if fore is not None and spine is not None and j == spine[0]:
            world[:, j] = _aim_spine(world[:, j], world[:, p, :3, 3], rest, spine, fore)
        if fore is not None and j == fore_girdle:
            world[:, j, :3, :3] = fore[:, :3, :3] @ rest[j, :3, :3]
        if j in following:
            world[:, j] = _follow(world, rest, local, parents, j, following[j])
    forward = unit(root[:, :3, 2] * np.array([1.0, 0.0, 1.0]) + np.array([0.0, 0.0, 1e-12]))  # (T, 3) level heading
    solved = []
    for leg, chain in enumerate(chains):
        target = leg_joints[:, leg].copy()
        if clearance is not None:
            target[:, 2:, 1] += clearance[leg]
            if foot_angle is not None and len(chain.joints) >= 5:  # the ball stands at its own height, not the toe's
                target[:, 3:, 1] += rest[chain.joints[3], 1, 3] - rest[chain.joints[-1], 1, 3]
        angle = None if foot_angle is None else float(foot_angle[leg])
        solved.append(_foot(rest, chain.joints, target, forward, angle))
    # Down, where a foot is out of its leg's reach (every leg at once).
    v = np.stack([ankle for ankle, _, _ in solved], axis=1) - top_at[:, :len(chains)]  # (T, L, 3) hip to ankle
    across = np.sum(v[..., [0, 2]] ** 2, axis=-1)
    drop = np.clip((-np.sqrt(np.maximum(reach ** 2 - across, 0.0)) - v[..., 1]).max(axis=1), 0.0, None)
    world[:, ~below_leg, 1, 3] -= drop[:, None]
    top_at[..., 1] -= drop[:, None]
    for leg, chain in enumerate(chains):
        ankle, feet, last = solved[leg]
        _solve_chain(world, rest, chain.joints, ankle, feet, last, leg_joints[:, leg], side_now, top_at[:, leg])
    if arm_chains:
        assert arms is not None
        forward_now = body[:, :3, 2]
        for a, chain in enumerate(arm_chains):
            shoulder = top_at[:, len(chains) + a]
            # The creature's arm from its shoulder, turned a little out from the side (the
            # model's chest is as wide as its shoulders: arms hung straight would pass into it).
            out = rotation_about(forward_now, ARM_OUT if chain.side == "L" else -ARM_OUT)  # (T, 3, 3)
            arm = np.einsum("tij,tkj->tki", out, arms[:, a, [0, 1, 2, 3, 3]] - arms[:, a, :1])
            target = shoulder[:, None, :] + arm  # (T, 5, 3): shoulder, elbow, wrist, hand, hand
            _solve_chain(world, rest, chain.joints, target[:, 2], [], None, target, forward_now, shoulder,
                         axis_rest=FRONT, steady=False)
    for j in order:  # what hangs below the legs, carried
        p = int(parents[j])
        if below_leg[j] and j not in in_chain:
            world[:, j] = world[:, p] @ local[j]
    return world


def _followers(legs: ModelLegs, rest: NDArray[np.float64], turns: Appendages | None,
               root: NDArray[np.float64]) -> dict[int, tuple]:
    """For each joint of the model's neck and tail: (the chain, its place in it, its turn
    (T, 3, 3) in the heading frame, the heading frames (T, 3, 3), whether it is the head
    (turned whole) rather than a bone's start (aimed))."""
    if turns is None:
        return {}
    heading = heading_frames(root)
    out: dict[int, tuple] = {}
    if len(legs.neck) >= 2:
        for i, j in enumerate(legs.neck):
            last = i == len(legs.neck) - 1
            out[j] = (legs.neck, i, turns.head if last else turns.neck, heading, last)
    if len(legs.tail) >= 2:
        points = rest[list(legs.tail), :3, 3]
        along = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(points, axis=0), axis=1))])
        along /= max(float(along[-1]), 1e-12)
        segments = turns.tail.shape[1]
        for i, j in enumerate(legs.tail[:-1]):  # (the tip's joint is carried)
            k = min(int(0.5 * (along[i] + along[i + 1]) * segments), segments - 1)
            out[j] = (legs.tail, i, turns.tail[:, k], heading, False)
    return out


def _follow(world: NDArray[np.float64], rest: NDArray[np.float64], local: NDArray[np.float64],
            parents: NDArray[np.int64], j: int, how: tuple) -> NDArray[np.float64]:
    """Joint ``j`` of a neck or tail (T, 4, 4), carried so far: its bone aimed where its
    rest direction, carried by the chain's parent, turns by the creature's turn (or, the
    head, the whole joint so turned). Positions stay: every bone keeps its length."""
    chain, i, turn, heading, whole = how
    top = int(parents[chain[0]])
    carried = world[:, top, :3, :3] @ rest[top, :3, :3].T if top >= 0 else np.eye(3)  # (T, 3, 3) the parent's turn
    turn_world = heading @ turn @ np.swapaxes(heading, -1, -2)
    out = world[:, j].copy()
    if whole:
        out[:, :3, :3] = turn_world @ carried @ rest[j, :3, :3]
        return out
    child = chain[i + 1]
    want = turn_world @ carried @ unit(rest[child, :3, 3] - rest[j, :3, 3])  # (T, 3)
    have = unit((out @ local[child])[:, :3, 3] - out[:, :3, 3])
    out[:, :3, :3] = rotation_between(have, want) @ out[:, :3, :3]
    return out


def _aim_spine(first: NDArray[np.float64], pivot: NDArray[np.float64], rest: NDArray[np.float64],
               spine: list[int], fore: NDArray[np.float64]) -> NDArray[np.float64]:
    """The spine's first joint (T, 4, 4), turned about ``pivot`` (T, 3; the hind girdle)
    so that the spine's end (the fore girdle) points where ``fore`` puts it."""
    end_rest = rest[spine[-1]]
    # Where the end lies now, carried rigidly with the first joint, and where it should.
    first_rest_inv = np.linalg.inv(rest[spine[0]])
    carried = (first @ (first_rest_inv @ end_rest))[:, :3, 3]
    wanted = (fore @ end_rest)[:, :3, 3]
    turn = rotation_between(unit(carried - pivot), unit(wanted - pivot))
    out = first.copy()
    out[:, :3, :3] = turn @ first[:, :3, :3]
    out[:, :3, 3] = pivot + np.einsum("tij,tj->ti", turn, first[:, :3, 3] - pivot)
    return out


def _foot(rest: NDArray[np.float64], joints: tuple[int, ...], target: NDArray[np.float64],
          forward: NDArray[np.float64], angle: float | None
          ) -> tuple[NDArray[np.float64], list[NDArray[np.float64]], NDArray[np.float64] | None]:
    """Where one leg's ankle goes (T, 3) and the directions (T, 3) of its foot's bones
    (ankle -> ball -> toe ...), for the creature's leg ``target`` (T, 5, 3: hip, knee,
    ankle, ball, toe). Without ``angle`` the bones lie along the creature's foot from its
    ankle. With it (the creature's flat-foot metatarsus angle, rad) each of the model's
    foot bones turns from its rest direction as the creature's foot bone turns from
    standing flat (facing the level heading ``forward`` (T, 3)), the ankle is set back
    from the creature's ball along the model's foot, and the last joint's turn (T, 3, 3)
    from its rest is given: as the creature's toes turn (the last joint, a ball whose
    vertices are the toes: the toes stay flat on the ground as the heel rises), or for a
    leg that ends at its ankle (a wrist, a rigid paw below it), as the creature's toes
    turn too, about the creature's ball (the paw stands flat while the creature's heel
    rises), the wrist set back from that ball. None without ``angle``."""
    points_rest = rest[list(joints), :3, 3]
    lengths = np.linalg.norm(np.diff(points_rest, axis=0), axis=1)
    bones = len(joints) - 3  # the foot's bones below the ankle
    if angle is None:
        ankle = target[:, 2]
        dirs = [unit(target[:, min(k + 1, 4)] - target[:, min(k, 3)]) for k in range(2, 2 + bones)]
        return ankle, dirs, None
    facing = rotation_between(np.broadcast_to([0.0, 0.0, 1.0], forward.shape), forward)  # the model's front -> now
    up = np.array([0.0, 1.0, 0.0])
    flat = [np.cos(angle) * forward - np.sin(angle) * up, forward]  # the creature's flat foot: metatarsus, toe
    now = [unit(target[:, 3] - target[:, 2]), unit(target[:, 4] - target[:, 3])]
    if bones <= 0:  # the leg ends at the ankle (a fox's wrist, its rigid paw below): the paw turns as the
        # creature's toes do, about the creature's ball (where the creature's flat foot puts it under the wrist)
        turn = rotation_between(flat[1], now[1]) @ facing
        length = np.linalg.norm(target[:, 3] - target[:, 2], axis=-1)[:, None]
        ball = length * np.array([0.0, -np.sin(angle), np.cos(angle)])  # (T, 3) from the wrist, at rest
        return target[:, 3] - np.einsum("tij,tj->ti", turn, ball), [], turn
    dirs = []
    for k in range(bones):
        c = min(k, 1)
        turn = rotation_between(flat[c], now[c])
        u_rest = unit(points_rest[3 + k] - points_rest[2 + k])
        dirs.append(np.einsum("tij,tj->ti", turn @ facing, np.broadcast_to(u_rest, forward.shape)))
    # The last joint (the ball: the toes' vertices are its) turns as the creature's toes do.
    ankle = target[:, 3] - lengths[2] * dirs[0]  # the model's ball where the creature's is
    return ankle, dirs, rotation_between(flat[1], now[1]) @ facing


def _solve_chain(world: NDArray[np.float64], rest: NDArray[np.float64], joints: tuple[int, ...],
                 ankle: NDArray[np.float64], feet: list[NDArray[np.float64]], last: NDArray[np.float64] | None,
                 target: NDArray[np.float64], side: NDArray[np.float64], top: NDArray[np.float64],
                 axis_rest: NDArray[np.float64] = SIDE, steady: bool = True) -> None:
    """One leg's joints into ``world`` (T, J, 4, 4): from ``top`` (T, 3) by two-bone IK to
    ``ankle`` (T, 3), bending towards the creature's knee (``target`` (T, 5, 3): hip,
    knee, ankle, ball, toe), then the foot's bones along ``feet`` (each (T, 3)); the last
    joint turned by ``last`` (T, 3, 3) from its rest (None: with the bone above it). Each
    bone turns from rest so that ``axis_rest`` (the body's side at rest; an arm: its
    front) goes to ``side`` (T, 3) across it; ``steady``: a leg's knee is steadied in the
    body's side plane by the way the model's knee bends at rest."""
    points_rest = rest[list(joints), :3, 3]
    lengths = np.linalg.norm(np.diff(points_rest, axis=0), axis=1)
    femur, tibia = lengths[0], lengths[1]
    to_ankle = ankle - top
    reach = np.clip(np.linalg.norm(to_ankle, axis=-1), abs(femur - tibia) + 1e-9, femur + tibia - 1e-9)
    along = unit(to_ankle)
    # Towards the creature's knee, steadied by the way the model's own knee bends at rest
    # across the body's side (a straight leg's knee says little about its way).
    hip_r, knee_r, ankle_r = points_rest[:3]
    # (none when the rest leg is all but straight: its way is then noise)
    way = np.dot(knee_r - hip_r, cross(np.array([1.0, 0.0, 0.0]), unit(ankle_r - hip_r)))
    way = np.sign(way) * min(abs(way) / (0.05 * femur), 1.0) if steady else 0.0
    bend = target[:, 1] - target[:, 0] + way * 0.3 * femur * unit(cross(side, along))
    bend = unit(bend - np.sum(bend * along, axis=-1, keepdims=True) * along)
    cos_a = np.clip((femur ** 2 + reach ** 2 - tibia ** 2) / (2.0 * femur * reach), -1.0, 1.0)
    knee = top + femur * (cos_a[:, None] * along + np.sqrt(1.0 - cos_a ** 2)[:, None] * bend)
    new = [top, knee, top + along * reach[:, None]]
    for k in range(3, len(joints)):  # the foot's bones
        new.append(new[-1] + lengths[k - 1] * feet[k - 3])
    points = np.stack(new, axis=1)  # (T, n, 3)
    for k, j in enumerate(joints):
        world[:, j, :3, 3] = points[:, k]
        if k + 1 < len(joints):
            u_rest, u_new = unit(points_rest[k + 1] - points_rest[k]), unit(points[:, k + 1] - points[:, k])
        elif last is not None:
            world[:, j, :3, :3] = last @ rest[j, :3, :3]
            world[:, j, 3, 3] = 1.0
            continue
        else:  # the last joint turns with the bone above it
            u_rest, u_new = unit(points_rest[k] - points_rest[k - 1]), unit(points[:, k] - points[:, k - 1])
        frame_rest = _frame(u_rest[None], axis_rest[None])[0]
        frame_new = _frame(u_new, side)
        turn = frame_new @ frame_rest.T
        world[:, j, :3, :3] = turn @ rest[j, :3, :3]
        world[:, j, 3, 3] = 1.0


def _frame(u: NDArray[np.float64], side: NDArray[np.float64]) -> NDArray[np.float64]:
    """Orthonormal frames (T, 3, 3) whose columns are ``u``, the part of ``side``
    across it, and their cross product."""
    s = side - np.sum(side * u, axis=-1, keepdims=True) * u
    fallback = cross(u, np.array([0.0, 0.0, 1.0]))
    s = np.where(np.linalg.norm(s, axis=-1, keepdims=True) < 1e-6, fallback, s)
    s = unit(s)
    return np.stack([u, s, cross(u, s)], axis=-1)
