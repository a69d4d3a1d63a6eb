"""The leg IK of :mod:`app.kinematics.leg` for one leg in plain Python (``math`` only).

A readable statement of the same formulas, step by step, used to cross-check the
vectorised solver and as the per-leg-loop baseline in ``bench/bench_core.py``. Not used
in the frame path.
"""

from __future__ import annotations

import math

Vec = tuple[float, float, float]

_REACH_MARGIN = 1e-6
_MAX_ANKLE_ANGLE = 0.75 * math.pi


def _add(a: Vec, b: Vec, s: float = 1.0) -> Vec:
    return (a[0] + s * b[0], a[1] + s * b[1], a[2] + s * b[2])


def _dot(a: Vec, b: Vec) -> float:
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def _scale(a: Vec, s: float) -> Vec:
    return (a[0] * s, a[1] * s, a[2] * s)


def _unit(a: Vec, fallback: Vec) -> Vec:
    n = math.sqrt(_dot(a, a))
    return _scale(a, 1.0 / n) if n > 1e-12 else fallback


def solve_leg(hip: Vec, target: Vec, fwd: Vec, up: Vec, toe_curl: float, femur: float, tibia: float,
              metatarsus: float, toe: float, ankle_lift: float, l_max: float, l_rest: float, l_min: float,
              knee_sign: float, swing_rest: float = 0.0) -> list[Vec]:
    """Joints [hip, knee, ankle, ball, toe tip] of one leg (see ``solve_legs``)."""
    h = _add(target, hip, -1.0)
    dist = math.sqrt(_dot(h, h))
    if dist < l_min:  # lower the ball straight down onto the sphere of radius L_min
        vert = _dot(h, up)
        flat = _add(h, up, -vert)
        h = _add(flat, up, -math.sqrt(max(l_min ** 2 - _dot(flat, flat), 0.0)))
        dist = math.sqrt(_dot(h, h))
    direction = _unit(h, _scale(up, -1.0))
    length = min(max(dist, l_min), l_max)
    h = _scale(direction, length)
    ball = _add(hip, h)

    h_fwd, h_up = _dot(h, fwd), _dot(h, up)
    swing = math.atan2(h_fwd, -h_up) - swing_rest
    extension = min(max((length - l_rest) / max(l_max - l_rest, 1e-12), 0.0), 1.0)
    lift = ankle_lift * min(1.0, math.sqrt(length / l_rest)) + (0.5 * math.pi - swing_rest - ankle_lift) * extension ** 2
    alpha = min(max(lift - swing, 0.0), _MAX_ANKLE_ANGLE)
    wanted = _add(_scale(fwd, -math.cos(alpha)), up, math.sin(alpha))

    to_hip = _scale(direction, -1.0)
    reach_max = (femur + tibia) * (1.0 - _REACH_MARGIN)
    reach_min = abs(femur - tibia) * (1.0 + _REACH_MARGIN)
    two_lm = 2.0 * length * metatarsus
    base = length ** 2 + metatarsus ** 2
    safe = max(two_lm, 1e-300)
    phi_max = math.acos(min(max((base - reach_max ** 2) / safe, -1.0), 1.0))
    phi_min = math.acos(min(max((base - reach_min ** 2) / safe, -1.0), 1.0))
    phi = math.acos(min(max(_dot(wanted, to_hip), -1.0), 1.0))
    clamped = min(max(phi, phi_min), phi_max)
    direction_ankle = wanted
    if clamped != phi and two_lm > 1e-12:
        side = _add(wanted, to_hip, -_dot(wanted, to_hip))
        if math.sqrt(_dot(side, side)) <= 1e-3:
            back = _scale(fwd, -1.0)
            side = _add(back, to_hip, -_dot(back, to_hip))
        side = _unit(side, up)
        direction_ankle = _unit(_add(_scale(to_hip, math.cos(clamped)), side, math.sin(clamped)), to_hip)
    ankle = _add(ball, direction_ankle, metatarsus)

    d_vec = _add(ankle, hip, -1.0)
    d = max(math.sqrt(_dot(d_vec, d_vec)), 1e-12)
    e = _scale(d_vec, 1.0 / d)
    f, t = femur, tibia
    along = (d * d + f * f - t * t) / (2.0 * d)
    off = math.sqrt(max((f + t - d) * (d + t - f) * (d + f - t) * (d + f + t), 0.0)) / (2.0 * d)
    pole = _scale(fwd, knee_sign)
    perp = _add(pole, e, -_dot(pole, e))
    fallback = _unit(_add(up, e, -_dot(up, e)), up)
    knee = _add(_add(hip, e, along), _unit(perp, fallback), off)

    height = _dot(ball, up)
    room = math.asin(min(max(0.5 * height / max(toe, 1e-12), 0.0), 1.0))
    drop = min(ankle_lift * min(max(toe_curl, 0.0), 1.0), room)
    toe_tip = _add(ball, _add(_scale(fwd, math.cos(drop)), up, -math.sin(drop)), toe)
    return [hip, knee, ankle, ball, toe_tip]
