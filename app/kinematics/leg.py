"""Analytic inverse kinematics of the four-bone parametric leg.

A leg is femur, tibia, metatarsus and toe. The IK target is the *ball* (the joint
between metatarsus and toe). The redundancy of the three-link chain is removed by
fixing the metatarsus angle first (the ankle lift, adjusted for how far the leg is
extended and how far it has swung), then the knee follows from the law of cosines on
the hip-ankle-knee triangle.

Vectorised: legs on the last axis, any number of leading batch axes (frames). The work
is done on scalar component arrays in each leg's own frame (forward, up, lateral), which
keeps numpy on contiguous arrays; :mod:`app.kinematics.leg_scalar` states the same
formulas for one leg in plain Python.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from .body import cross

JOINT_NAMES: tuple[str, ...] = ("hip", "knee", "ankle", "ball", "toe")
MAX_ANKLE_ANGLE = 0.75 * np.pi  # the ankle may pass over the ball a little, not fold flat forward
BAND_CLEARANCE = 0.02  # m: a knee's ceiling lowers a swinging ball no nearer the ground
_REACH_MARGIN = 1e-6  # keep the knee triangle this far (relative) from straight or folded flat


def _norm3(x: NDArray, y: NDArray, z: NDArray) -> NDArray:
    return np.sqrt(x * x + y * y + z * z)


def _reach_rotation(wf, wu, wl, hf, hu, hl, length, cos_target):
    """Directions (f, u, l) at angle acos(cos_target) from the hip direction, rotated from
    the wanted direction w towards (or away from) it; inputs are 1-D subsets."""
    inv = 1.0 / length
    tf, tu, tl = -hf * inv, -hu * inv, -hl * inv  # unit direction ball -> hip
    along = wf * tf + wu * tu + wl * tl
    sf, su, sl = wf - along * tf, wu - along * tu, wl - along * tl
    # When the wanted direction is (nearly) the hip direction itself, rotate in the
    # sagittal plane, towards the back.
    weak = _norm3(sf, su, sl) <= 1e-3
    back = -tf
    sf = np.where(weak, -1.0 - back * tf, sf)
    su = np.where(weak, -back * tu, su)
    sl = np.where(weak, -back * tl, sl)
    # ... and when that is the hip direction too (a horizontal leg), towards up.
    flat = _norm3(sf, su, sl) <= 1e-3
    sf = np.where(flat, -tu * tf, sf)
    su = np.where(flat, 1.0 - tu * tu, su)
    sl = np.where(flat, -tu * tl, sl)
    n = np.maximum(_norm3(sf, su, sl), 1e-300)
    sin_t = np.sqrt(np.maximum(1.0 - cos_target * cos_target, 0.0))
    df, du, dl = cos_target * tf + sin_t * sf / n, cos_target * tu + sin_t * su / n, cos_target * tl + sin_t * sl / n
    dn = _norm3(df, du, dl)
    return df / dn, du / dn, dl / dn


_CHUNK_LEGS = 16384  # legs solved per pass: keeps numpy's temporaries in the L2 cache


def solve_legs(
    hip: NDArray[np.float64],
    target: NDArray[np.float64],
    forward: NDArray[np.float64],
    up: NDArray[np.float64],
    toe_curl: NDArray[np.float64],
    *,
    femur: NDArray[np.float64],
    tibia: NDArray[np.float64],
    metatarsus: NDArray[np.float64],
    toe: NDArray[np.float64],
    ankle_lift: NDArray[np.float64],
    l_max: NDArray[np.float64],
    l_rest: NDArray[np.float64],
    l_min: NDArray[np.float64],
    knee_sign: NDArray[np.float64],
    swing_rest: NDArray[np.float64] | float = 0.0,
    ground_height: NDArray[np.float64] | float = 0.0,
    knee_pole: NDArray[np.float64] | None = None,
    ankle_angle: NDArray[np.float64] | None = None,
    ankle_weight: NDArray[np.float64] | None = None,
    toe_drop: NDArray[np.float64] | None = None,
    toe_weight: NDArray[np.float64] | None = None,
    dorsiflexion: NDArray[np.float64] | None = None,
    dorsi_weight: NDArray[np.float64] | None = None,
    knee_target: NDArray[np.float64] | None = None,
    knee_weight: NDArray[np.float64] | None = None,
    knee_floor: NDArray[np.float64] | None = None,
    knee_ceiling: NDArray[np.float64] | None = None,
    band_weight: NDArray[np.float64] | None = None,
) -> NDArray[np.float64]:
    """Solve legs for hip and ball positions.

    hip, target:   (..., L, 3) world positions (m) of each hip and its ball target
    forward, up:   (..., L, 3) orthonormal vectors of each leg's sagittal frame (body
                   heading and world up); broadcastable, e.g. (3,)
    toe_curl:      (..., L) in [0, 1]: 0 keeps the toe flat, 1 drops it by the ankle lift
    femur..knee_sign: (L,) rig arrays (m, radians, +1 knee forward / -1 back)
    swing_rest:    (L,) the rest angle (rad) of the hip-to-ball line from the frame's down
                   axis (a sprawled leg's abduction in its own plane; 0 for upright legs)
    knee_pole:     (L, 2) the direction the knee bends towards, as (forward, up) in the leg
                   frame (default (knee_sign, 0): forward or back); sprawled legs bend up
                   and out
    ground_height: height (m) of the ground under each ball, for keeping the toe above it
    ankle_angle, ankle_weight: (..., L) optional: a metatarsus angle (rad, ball-to-ankle
                   above the frame's backward horizontal; may be negative) that replaces the
                   leg's own by the weight in [0, 1] (a rolling foot)
    toe_drop, toe_weight: (..., L) optional: likewise the toe's angle below horizontal
    dorsiflexion, dorsi_weight: (..., L) optional: the ankle's dorsiflexion (rad, the foot
                   against the shank, 0 as it stands at rest) that replaces the metatarsus
                   angle by the weight (a swinging foot held against its shank)
    knee_target, knee_weight: (..., L) optional: a knee flexion (rad) that the foot turns
                   about its ball to give, by the weight (a walker's heel rise); the
                   metatarsus never turns below the ankle lift
    knee_floor, knee_ceiling, band_weight: (..., L) optional: the least and most knee
                   flexion (rad) a foot in the air keeps: a ball whose knee would be
                   straighter rises along the frame's up until the knee has the floor, one
                   more bent comes down to the ceiling (never nearer the ground than
                   BAND_CLEARANCE), by the weight (a walker's swing)

    Returns joints (..., L, 5, 3): hip, knee, ankle, ball, toe tip. Bone lengths are
    preserved exactly; the ball reaches the target when the target is within
    [L_min, L_max] of the hip; a farther target pulls it in along the hip-target line, a
    nearer one is lowered straight down to L_min (continuous as the target passes under the hip).
    """
    if knee_pole is None:
        knee_pole = np.stack([np.asarray(knee_sign, dtype=np.float64), np.zeros(np.shape(knee_sign))], axis=-1)
    rig = dict(femur=femur, tibia=tibia, metatarsus=metatarsus, toe=toe, ankle_lift=ankle_lift, l_max=l_max,
               l_rest=l_rest, l_min=l_min, knee_sign=knee_sign, swing_rest=swing_rest, knee_pole=knee_pole)
    hip = np.asarray(hip, dtype=np.float64)
    target = np.asarray(target, dtype=np.float64)
    shape = np.broadcast_shapes(hip.shape, target.shape)
    rows = int(np.prod(shape[:-2], dtype=np.int64)) if len(shape) > 2 else 1
    per_row = shape[-2]
    rolls = (ankle_angle, ankle_weight, toe_drop, toe_weight)
    foot_rules = (dorsiflexion, dorsi_weight, knee_target, knee_weight, knee_floor, knee_ceiling, band_weight)
    if len(shape) != 3 or rows * per_row <= 2 * _CHUNK_LEGS:
        return _solve(hip, target, forward, up, toe_curl, ground_height, rolls, foot_rules, **rig)
    # Long clips: solve blocks of frames. Per-frame inputs are sliced, shared ones passed whole.
    step = max(1, _CHUNK_LEGS // per_row)
    out = np.empty(shape[:-1] + (5, 3))

    def part(a, lo, hi):
        a = np.asarray(a, dtype=np.float64)
        return a[lo:hi] if a.ndim >= 2 and a.shape[0] == shape[0] else a

    for lo in range(0, shape[0], step):
        hi = min(lo + step, shape[0])
        out[lo:hi] = _solve(np.broadcast_to(hip, shape)[lo:hi], np.broadcast_to(target, shape)[lo:hi],
                            part(forward, lo, hi), part(up, lo, hi), part(toe_curl, lo, hi),
                            part(ground_height, lo, hi),
                            tuple(None if a is None else part(a, lo, hi) for a in rolls),
                            tuple(None if a is None else part(a, lo, hi) for a in foot_rules), **rig)
    return out


def _solve(hip, target, forward, up, toe_curl, ground_height, rolls=(None,) * 4, foot_rules=(None,) * 7, *,
           femur, tibia, metatarsus, toe, ankle_lift,
           l_max, l_rest, l_min, knee_sign, swing_rest=0.0, knee_pole=None) -> NDArray[np.float64]:
    """:func:`solve_legs` on one block (see there)."""
    shape = np.broadcast_shapes(hip.shape, target.shape)
    hip = np.broadcast_to(hip, shape)
    fwd = np.asarray(forward, dtype=np.float64)
    upv = np.asarray(up, dtype=np.float64)
    lat = cross(upv, fwd)
    shared_frame = fwd.ndim == 1 and upv.ndim == 1  # one frame for every leg: use BLAS
    basis = np.stack([fwd, upv, lat], axis=-2)  # rows: forward, up, lateral
    h = np.asarray(target, dtype=np.float64) - hip
    # Components in the leg frame: forward, up, lateral.
    if shared_frame:
        in_frame = h @ basis.T
        hf, hu, hl = in_frame[..., 0], in_frame[..., 1], in_frame[..., 2]
    else:
        hf, hu, hl = (np.einsum("...i,...i->...", h, axis) for axis in (fwd, upv, lat))

    # 1. Clamp the hip-to-ball distance into the leg's range. Too near: lower the ball
    #    straight down onto the sphere of radius L_min (continuous wherever the target
    #    goes, also when it passes under the hip). Too far: pull it in along the line.
    dist = _norm3(hf, hu, hl)
    near = dist < l_min
    if np.any(near):
        flat2 = hf * hf + hl * hl
        hu = np.where(near, -np.sqrt(np.maximum(l_min * l_min - flat2, 0.0)), hu)
        dist = _norm3(hf, hu, hl)
    length = np.clip(dist, l_min, l_max)
    zero = dist <= 1e-12
    s = length / np.where(zero, 1.0, dist)
    hf, hl = np.where(zero, 0.0, hf * s), np.where(zero, 0.0, hl * s)
    hu = np.where(zero, -length, hu * s)

    # 2. Metatarsus angle: rest lift, flattened when the leg is compressed, raised as it
    #    extends towards L_max, then rotated with the whole leg's swing about the hip.
    swing = np.arctan2(hf, -hu) - swing_rest  # > 0 when the foot is ahead of its rest direction
    extension = np.clip((length - l_rest) / np.maximum(l_max - l_rest, 1e-12), 0.0, 1.0)
    lift = ankle_lift * np.minimum(1.0, np.sqrt(length / l_rest)) \
        + (0.5 * np.pi - swing_rest - ankle_lift) * extension ** 2
    alpha = np.clip(lift - swing, 0.0, MAX_ANKLE_ANGLE)
    ankle_angle, ankle_weight, toe_angle, toe_weight = rolls
    if ankle_angle is not None:  # a rolling foot's metatarsus
        alpha = alpha + ankle_weight * (np.minimum(ankle_angle, MAX_ANKLE_ANGLE) - alpha)
    dorsiflexion, dorsi_weight, knee_target, knee_weight, knee_floor, knee_ceiling, band_weight = foot_rules
    if knee_target is not None and np.any(knee_weight > 0):
        # 2b. A foot that turns about its ball so that the knee has a wanted flexion (a
        #     walker's heel rising through late stance): the ankle at distance m from the
        #     ball and S from the hip, hf cos(a) - hu sin(a) = (l^2 + m^2 - S^2) / 2m.
        m = metatarsus
        span = np.sqrt(femur * femur + tibia * tibia + 2.0 * femur * tibia * np.cos(knee_target))
        radius = np.maximum(np.hypot(hf, hu), 1e-12)
        c = np.clip((length * length + m * m - span * span) / (2.0 * m * radius), -1.0, 1.0)
        phi = np.arctan2(hu, hf)
        options = np.stack([np.arccos(c) - phi, -np.arccos(c) - phi])
        options = np.mod(options - alpha + np.pi, 2.0 * np.pi) - np.pi + alpha  # the turns nearest alpha
        nearest = np.take_along_axis(options, np.argmin(np.abs(options - alpha), axis=0)[None], axis=0)[0]
        alpha = alpha + knee_weight * (np.clip(nearest, ankle_lift, MAX_ANKLE_ANGLE) - alpha)
    af, au, al, kf, ku, kl = _ankle_and_knee(alpha, hf, hu, hl, length, femur, tibia, metatarsus, knee_sign, knee_pole)
    holds = dorsiflexion is not None and np.any(dorsi_weight > 0)
    bands = knee_floor is not None and knee_ceiling is not None and np.any(band_weight > 0)
    if bands:  # the ball's planned level, and how far below it a ceiling may take it
        planned = banded = hu
        above = hip[..., 1] + hf * fwd[..., 1] + hu * upv[..., 1] + hl * lat[..., 1] - ground_height
        room = np.maximum(above - BAND_CLEARANCE, 0.0) / np.maximum(upv[..., 1], 0.5)
    for _ in range(3 if holds or bands else 0):
        # 4b. A foot held against its shank (a swinging walker's): the metatarsus angle that
        #     gives the wanted dorsiflexion depends on the shank, which depends on the ankle;
        #     three fixed-point passes settle it (the shank turns little as the foot does).
        mixed = alpha
        if holds:
            shank = np.arctan2(af - kf, -(au - ku))  # from the vertical, + with the ankle ahead of the knee
            wanted = np.clip(ankle_lift - dorsiflexion - shank, 0.0, MAX_ANKLE_ANGLE)
            mixed = alpha + dorsi_weight * (wanted - alpha)
        if bands:  # 4c. A knee within its band (see _band_level), settled unweighted, then weighed once
            span = _norm3(hf, banded, hl)
            af, au, al, _, _, _ = _ankle_and_knee(mixed, hf, banded, hl, span, femur, tibia, metatarsus, knee_sign,
                                                  knee_pole)
            banded = _band_level(af, au, al, banded, planned, room, knee_floor, knee_ceiling, femur, tibia)
            hu = planned + band_weight * (banded - planned)
            length = _norm3(hf, hu, hl)
        af, au, al, kf, ku, kl = _ankle_and_knee(mixed, hf, hu, hl, length, femur, tibia, metatarsus, knee_sign,
                                                 knee_pole)

    # 5. Toe: flat on the ground while planted, dropping by the ankle lift in the air, its
    #    tip never lower than half the ball's height (so it never touches down before
    #    the ball: it lands and lifts off flat, together with the ball).
    # The ball's height (world y) above the ground under it.
    height = hip[..., 1] + hf * fwd[..., 1] + hu * upv[..., 1] + hl * lat[..., 1] - ground_height
    room = np.arcsin(np.clip(0.5 * height / np.maximum(toe, 1e-12), 0.0, 1.0))
    drop = np.minimum(ankle_lift * np.clip(toe_curl, 0.0, 1.0), room)
    if toe_angle is not None:  # a rolling foot's toe; blending in the air, its tip never below the ground
        drop = drop + toe_weight * (toe_angle - drop)
        clear = np.arcsin(np.clip(height / np.maximum(toe, 1e-12), 0.0, 1.0))
        drop = np.where(toe_weight < 1.0, np.minimum(drop, clear), drop)
    tf, tu = hf + toe * np.cos(drop), hu - toe * np.sin(drop)

    # Back to world space: hip + f * forward + u * up + l * lateral, for all four joints.
    batch = shape[:-1]
    local = np.stack(np.broadcast_arrays(kf, ku, kl, af, au, al, hf, hu, hl, tf, tu, hl), axis=-1)
    local = local.reshape(batch + (4, 3))  # knee, ankle, ball, toe in (forward, up, lateral)
    joints = np.empty(batch + (5, 3))
    joints[..., 0, :] = hip
    if shared_frame:  # one BLAS product for every joint of every leg and frame
        joints[..., 1:, :] = (local.reshape(-1, 3) @ basis).reshape(local.shape) + hip[..., None, :]
    else:
        joints[..., 1:, :] = np.einsum("...jk,...kc->...jc", local, basis) + hip[..., None, :]
    return joints


def _band_level(af, au, al, hu, planned, room, floor, ceiling, femur, tibia):
    """Step 4c of :func:`_solve`: the ball's level (its up component relative to the hip)
    that keeps the knee between ``floor`` and ``ceiling`` flexion (rad), for an ankle at
    (af, au, al) now and the ball at ``hu`` (planned at ``planned``): up until the ankle is
    no farther from the hip than the floor's span; down until it is no nearer than the
    ceiling's, softly within ``room`` below the plan (a descent D wanted gives
    room (1 - exp(-D / room)): D while small, never all the room)."""
    lateral2 = af * af + al * al
    far = np.sqrt(femur * femur + tibia * tibia + 2.0 * femur * tibia * np.cos(floor))
    near = np.sqrt(femur * femur + tibia * tibia + 2.0 * femur * tibia * np.cos(ceiling))
    # The ankle's level for the floor (where even level with the hip it would be too far,
    # the floor asks nothing: no foot is lifted to the hip).
    highest = np.where(lateral2 < far * far, -np.sqrt(np.maximum(far * far - lateral2, 0.0)), -np.inf)
    lowest = -np.sqrt(np.maximum(near * near - lateral2, 0.0))  # ... and for the ceiling
    descent = np.maximum(planned - hu + np.maximum(au - lowest, 0.0), 0.0)  # below the plan, in all
    soft = room * -np.expm1(-descent / np.maximum(room, 1e-9))
    return np.where(au < highest, hu + highest - au, np.minimum(hu, planned - soft))


def _ankle_and_knee(alpha, hf, hu, hl, length, femur, tibia, metatarsus, knee_sign, knee_pole):
    """Steps 3 and 4 of :func:`_solve`: the ankle for metatarsus angle ``alpha`` (kept
    reachable) and the knee, as (forward, up, lateral) components relative to the hip:
    (af, au, al, kf, ku, kl)."""
    wf, wu = -np.cos(alpha), np.sin(alpha)  # wanted direction ball -> ankle (no lateral part)
    wl = np.zeros_like(wf)

    # 3. Keep the ankle reachable. It lies on a sphere of radius m about the ball; the
    #    points within [|f - t|, f + t] of the hip form a band of that sphere at angles
    #    phi from the hip direction with |ankle - hip|^2 = l^2 + m^2 - 2 l m cos(phi).
    #    Where the wanted direction is outside the band (rare), rotate it to the band's edge.
    m = metatarsus
    two_lm = 2.0 * length * m
    safe = np.where(two_lm > 1e-12, two_lm, 1.0)
    base = length * length + m * m
    reach_max = (femur + tibia) * (1.0 - _REACH_MARGIN)
    reach_min = np.abs(femur - tibia) * (1.0 + _REACH_MARGIN)
    cos_edge_far = (base - reach_max * reach_max) / safe  # need cos(phi) >= this
    cos_edge_near = (base - reach_min * reach_min) / safe  # need cos(phi) <= this
    cos_phi = (wf * hf + wu * hu) / -length
    fix = (two_lm > 1e-12) & ((cos_phi < cos_edge_far) | (cos_phi > cos_edge_near))
    if np.any(fix):
        idx = np.nonzero(fix)
        bshape = fix.shape
        pick = lambda a: np.broadcast_to(a, bshape)[idx]
        cos_t = np.clip(np.clip(cos_phi[idx], pick(cos_edge_far), pick(cos_edge_near)), -1.0, 1.0)
        rf, ru, rl = _reach_rotation(wf[idx], wu[idx], wl[idx], hf[idx], hu[idx], hl[idx], length[idx], cos_t)
        wf, wu, wl = wf.copy(), wu.copy(), wl.copy()
        wf[idx], wu[idx], wl[idx] = rf, ru, rl
    af, au, al = hf + m * wf, hu + m * wu, hl + m * wl  # ankle relative to the hip

    # 4. Knee: a = (d^2 + f^2 - t^2) / 2d along the hip-ankle line and h off it (Heron's
    #    factorised form, exact for nearly straight or folded legs), towards the pole:
    #    forward for knees, back for elbows.
    f, t = femur, tibia
    d = np.maximum(_norm3(af, au, al), 1e-12)
    ef, eu, el = af / d, au / d, al / d
    along = (d * d + f * f - t * t) / (2.0 * d)
    off = np.sqrt(np.maximum((f + t - d) * (d + t - f) * (d + f - t) * (d + f + t), 0.0)) / (2.0 * d)
    if knee_pole is None:
        pole_f, pole_u = knee_sign, 0.0
    else:
        pole_f, pole_u = knee_pole[..., 0], knee_pole[..., 1]
    dot = pole_f * ef + pole_u * eu  # the pole made perpendicular to the hip-ankle line
    pf, pu, pl = pole_f - dot * ef, pole_u - dot * eu, -dot * el
    pn = _norm3(pf, pu, pl)
    degenerate = pn <= 1e-12
    if np.any(degenerate):  # hip-ankle line along the pole: bend towards up instead
        pf, pu, pl = np.where(degenerate, -eu * ef, pf), np.where(degenerate, 1.0 - eu * eu, pu), \
            np.where(degenerate, -eu * el, pl)
        pn = np.maximum(_norm3(pf, pu, pl), 1e-300)
    kf, ku, kl = along * ef + off * pf / pn, along * eu + off * pu / pn, along * el + off * pl / pn

    return af, au, al, kf, ku, kl
