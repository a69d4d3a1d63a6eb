"""Analytic inverse kinematics of the four-bone parametric leg.

A leg is femur, tibia, metatarsus and toe. The IK target is the *ball* (the joint
between metatarsus and toe). The redundancy of the three-link chain is removed by
fixing the metatarsus angle first (the ankle lift, adjusted for how far the leg is
extended and how far it has swung), then the knee follows from the law of cosines on
the hip-ankle-knee triangle. Every function is vectorised: legs on the last axis, any
number of leading batch axes (frames, creatures).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

JOINT_NAMES: tuple[str, ...] = ("hip", "knee", "ankle", "ball", "toe")
MAX_ANKLE_ANGLE = 0.75 * np.pi  # the ankle may pass over the ball a little, not fold flat forward
_REACH_MARGIN = 1e-6  # keep the knee triangle this far (relative) from straight or folded flat


def _dot(a: NDArray, b: NDArray) -> NDArray:
    return np.einsum("...i,...i->...", a, b)


def _unit(v: NDArray, fallback: NDArray) -> NDArray:
    n = np.linalg.norm(v, axis=-1, keepdims=True)
    return np.where(n > 1e-12, v / np.where(n > 1e-12, n, 1.0), fallback)


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
    ground_height: NDArray[np.float64] | float = 0.0,
) -> NDArray[np.float64]:
    """Solve legs for hip and ball positions.

    hip, target:   (..., L, 3) world positions (m) of each hip and its ball target
    forward, up:   (..., L, 3) unit vectors of each leg's sagittal frame (body heading
                   and world up); broadcastable, e.g. (3,)
    toe_curl:      (..., L) in [0, 1]: 0 keeps the toe flat, 1 drops it by the ankle lift
    femur..knee_sign: (L,) rig arrays (m, radians, +1 knee forward / -1 back)
    ground_height: height (m) of the ground under each ball, for keeping the toe above it

    Returns joints (..., L, 5, 3): hip, knee, ankle, ball, toe tip. Bone lengths are
    preserved exactly; the ball reaches the target when the target is within
    [L_min, L_max] of the hip; a farther target pulls it in along the hip-target line, a
    nearer one slides it away horizontally at the target's height.
    """
    hip = np.asarray(hip, dtype=np.float64)
    target = np.asarray(target, dtype=np.float64)
    fwd = np.broadcast_to(np.asarray(forward, dtype=np.float64), hip.shape)
    upv = np.broadcast_to(np.asarray(up, dtype=np.float64), hip.shape)

    # 1. Clamp the hip-to-ball distance into the leg's range. Too far: pull the ball in
    #    along the hip line (it rises). Too near: slide it away along the ground, keeping
    #    its height, so a low hip never pushes the foot underground.
    h = target - hip
    dist = np.linalg.norm(h, axis=-1)
    h_vert = _dot(h, upv)[..., None] * upv
    h_flat = h - h_vert
    flat_len = np.linalg.norm(h_flat, axis=-1)
    flat_dir = _unit(h_flat, -fwd)
    need = np.sqrt(np.maximum(l_min ** 2 - _dot(h, upv) ** 2, 0.0))
    slid = h_vert + flat_dir * np.maximum(need, flat_len)[..., None]
    h = np.where((dist < l_min)[..., None], slid, h)
    dist = np.linalg.norm(h, axis=-1)
    direction = _unit(h, -upv)
    length = np.clip(dist, l_min, l_max)
    h = direction * length[..., None]
    ball = hip + h

    # 2. Metatarsus angle: rest lift, flattened when the leg is compressed, raised as it
    #    extends towards L_max, then rotated with the whole leg's swing about the hip.
    h_fwd = _dot(h, fwd)
    h_up = _dot(h, upv)
    swing_angle = np.arctan2(h_fwd, -h_up)  # > 0 when the foot is ahead of the hip
    span = np.maximum(l_max - l_rest, 1e-12)
    extension = np.clip((length - l_rest) / span, 0.0, 1.0)
    lift = ankle_lift * np.minimum(1.0, np.sqrt(length / l_rest)) + (0.5 * np.pi - ankle_lift) * extension ** 2
    alpha = np.clip(lift - swing_angle, 0.0, MAX_ANKLE_ANGLE)

    cos_a = np.cos(alpha)[..., None]
    sin_a = np.sin(alpha)[..., None]
    m = metatarsus[..., None]
    wanted = -cos_a * fwd + sin_a * upv  # unit direction ball -> ankle

    # 3. Keep the ankle reachable: it lies on a sphere of radius m about the ball, and the
    #    points within [|f - t|, f + t] of the hip form a band of that sphere around the
    #    direction to the hip: angle phi from it with
    #    |ankle - hip|^2 = l^2 + m^2 - 2 l m cos(phi). Rotate the wanted direction
    #    towards (or away from) the hip until it lies in the band.
    to_hip = -direction
    reach_max = (femur + tibia) * (1.0 - _REACH_MARGIN)
    reach_min = np.abs(femur - tibia) * (1.0 + _REACH_MARGIN)
    two_lm = 2.0 * length * metatarsus
    safe = np.maximum(two_lm, 1e-300)
    base = length ** 2 + metatarsus ** 2
    phi_max = np.arccos(np.clip((base - reach_max ** 2) / safe, -1.0, 1.0))
    phi_min = np.arccos(np.clip((base - reach_min ** 2) / safe, -1.0, 1.0))
    phi = np.arccos(np.clip(_dot(wanted, to_hip), -1.0, 1.0))
    clamped = np.clip(phi, phi_min, phi_max)
    # Rotate within the plane of the wanted direction, or (when that is nearly the hip
    # direction itself) within the sagittal plane, towards the back.
    side_wanted = wanted - _dot(wanted, to_hip)[..., None] * to_hip
    side_back = -fwd - _dot(-fwd, to_hip)[..., None] * to_hip
    well_defined = np.linalg.norm(side_wanted, axis=-1, keepdims=True) > 1e-3
    side = np.where(well_defined, _unit(side_wanted, upv), _unit(side_back, upv))
    adjusted = _unit(np.cos(clamped)[..., None] * to_hip + np.sin(clamped)[..., None] * side, to_hip)
    use = ((clamped != phi) & (two_lm > 1e-12))[..., None]
    ankle = ball + m * np.where(use, adjusted, wanted)

    # 4. Knee from the law of cosines, bent towards the knee's pole (forward or back). The
    #    knee sits a = (d^2 + f^2 - t^2) / 2d along the hip-ankle line and h off it, with h
    #    from Heron's factorised form, which stays exact for nearly straight or folded legs.
    d_vec = ankle - hip
    d = np.maximum(np.linalg.norm(d_vec, axis=-1), 1e-12)
    e = d_vec / d[..., None]
    f, t = femur, tibia
    along = (d * d + f * f - t * t) / (2.0 * d)
    heron = (f + t - d) * (d + t - f) * (d + f - t) * (d + f + t)
    off = np.sqrt(np.maximum(heron, 0.0)) / (2.0 * d)
    pole = knee_sign[..., None] * fwd
    perp = pole - _dot(pole, e)[..., None] * e
    fallback = upv - _dot(upv, e)[..., None] * e
    p_hat = _unit(perp, _unit(fallback, upv))
    knee = hip + along[..., None] * e + off[..., None] * p_hat

    # 5. Toe: flat on the ground while planted, dropping by the ankle lift in the air,
    #    never below the ground.
    height = _dot(ball, upv) - ground_height
    safe_toe = np.maximum(toe, 1e-12)
    room = np.arcsin(np.clip(height / safe_toe, 0.0, 1.0))
    drop = np.minimum(ankle_lift * np.clip(toe_curl, 0.0, 1.0), room)
    toe_dir = np.cos(drop)[..., None] * fwd - np.sin(drop)[..., None] * upv
    toe_tip = ball + toe[..., None] * toe_dir

    return np.stack([hip, knee, ankle, ball, toe_tip], axis=-2)
