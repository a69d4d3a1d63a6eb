"""Foot roll: heel strike, roll to flat, heel rise, roll over the ball, toe-off.

A rolling foot is a rigid heel-ball-toe that turns about whichever point touches the
ground, so that point never slips (it is fixed in the world for as long as it touches).
Over a stance (``u`` = phase / duty, 0 at touchdown, 1 at lift-off), for roll amount r:

- ``0 <= u < a``: the heel has struck with the toes up by the contact foot angle
  ``r * foot_angle``; the foot rolls down about the heel to flat (angle ``(1 - u/a)^2``);
  a negative foot angle lands toes first, on the ball, and lowers the heel;
- ``a <= u < b``: flat; heel and ball on the ground;
- ``b <= u < c``: the heel rises about the ball (by up to ``r * HEEL_RISE``);
- ``c <= u <= 1``: the foot rolls over the toe tip, the ball rising (by up to
  ``r * TOE_OFF`` of toe angle), until the toe leaves the ground.

with ``a = r * HEEL_PART``, ``b = 1 - r * RISE_PART``, ``c = 1 - r * TOE_PART``. A plantigrade
foot's heel is its flat metatarsus behind the ball (:attr:`Rig.heel_length`); a foot that
stands on its toes strikes with its ball (the toes up) and lifts over its toe tip.

The leg's IK is then told the ball target (moved about the pivot), the metatarsus angle
(plantigrade feet: the rigid foot's) and the toe angle; in swing these blend from the
lift-off pose and into the strike pose, so nothing jumps. Roll 0 changes nothing.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from .easing import smoothstep
from .footfalls import FootPlan
from .rig import REACH_LIMIT, Rig
from .walker import knee_fold, walker_knee, walker_knee_band, walking_weight

HEEL_PART = 0.2  # of the stance, at roll 1: heel strike to foot flat
RISE_PART = 0.5  # of the stance before lift-off, at roll 1: where the heel starts to rise
TOE_PART = 0.2  # of the stance before lift-off, at roll 1: the roll over the toes
HEEL_RISE = np.radians(30.0)  # how far the heel rises about the ball before the toe roll, at roll 1
RUN_HEEL_RISE = np.radians(50.0)  # ... a runner's, pushing off on a steep foot
TOE_OFF = np.radians(12.0)  # the toe's angle at lift-off, at roll 1
STRAIGHT_KNEE = np.radians(3.0)  # a rolling plantigrade stance leg is never straighter than this
SWING_DORSIFLEXION = 0.0  # rad: the swinging plantigrade foot's ankle between lift-off and strike
LAND = 0.3  # of the swing, before the strike: how long the strike pose builds
BLEND = 0.4  # of the swing: how long the lift-off pose fades and the strike pose builds
STRIKE_DROP = 1.0  # of the foot's length: how fast (per swing) a rolling foot meets the ground, so it strikes


@dataclass(frozen=True)
class FootRoll:
    """What the roll asks of each leg (T, L, ...): the ball target; the metatarsus angle
    (rad, the ball-to-ankle direction above the foot's backward horizontal) and the toe's
    drop (rad below horizontal), each with a weight in [0, 1] against the leg's own; the
    foot's forward direction (unit, 3) with its weight against the body's heading; the
    ankle (T, L, 3) of the rolled foot (the ball for feet that keep their own ankle angle)
    and ``reach`` (L,) how far a hip may be from that point (m); ``sets_ankle`` (L,) which
    legs' ankle angle the roll sets (rolling plantigrade feet); in mid-swing such a foot
    is held against its shank instead: ``dorsiflexion`` (rad) with ``dorsi_weight``
    (T, L) against the metatarsus angle; from late stance into the early swing its heel
    turns about the ball to give the ``knee`` (rad) a walker's has, by ``knee_weight``
    (:func:`app.kinematics.walker.walker_knee`); through most of the swing its knee
    flexes between ``knee_floor`` and ``knee_ceiling`` (rad), by ``band_weight``
    (:func:`app.kinematics.walker.walker_knee_band`)."""

    ball: NDArray[np.float64]
    ankle_angle: NDArray[np.float64]
    ankle_weight: NDArray[np.float64]
    toe_drop: NDArray[np.float64]
    toe_weight: NDArray[np.float64]
    forward: NDArray[np.float64]
    forward_weight: NDArray[np.float64]
    ankle: NDArray[np.float64]
    reach: NDArray[np.float64]
    sets_ankle: NDArray[np.bool_]
    dorsiflexion: NDArray[np.float64]
    dorsi_weight: NDArray[np.float64]
    knee: NDArray[np.float64]
    knee_weight: NDArray[np.float64]
    knee_floor: NDArray[np.float64]
    knee_ceiling: NDArray[np.float64]
    band_weight: NDArray[np.float64]


def _foot_frame(direction: NDArray[np.float64], normal: NDArray[np.float64]) -> NDArray[np.float64]:
    """The foot's forward (..., 3): its horizontal direction (..., 2) made perpendicular to
    the ground normal (..., 3)."""
    f = np.stack([direction[..., 0], np.zeros(direction.shape[:-1]), direction[..., 1]], axis=-1)
    f = f - np.sum(f * normal, axis=-1, keepdims=True) * normal
    return f / np.maximum(np.linalg.norm(f, axis=-1, keepdims=True), 1e-12)


def _stance(rig: Rig, foot_angle: float, u: NDArray[np.float64], foothold: NDArray[np.float64],
            forward: NDArray[np.float64], normal: NDArray[np.float64], heel_rise: NDArray[np.float64]):
    """The rolled foot at stance fraction u (T, L) on a foothold (T, L, 3) (the flat ball's
    place), its heel rising by up to ``heel_rise`` (rad, (T, L)) at roll 1: ball (T, L, 3),
    metatarsus angle and toe drop (T, L)."""
    r = rig.roll_amount
    a, b, c = r * HEEL_PART, 1.0 - r * RISE_PART, 1.0 - r * TOE_PART
    rolls = a > 1e-9  # a roll too small to last a frame is none
    x_heel = np.clip(u / np.where(rolls, a, 1.0), 0.0, 1.0)
    heel_pitch = np.where(rolls, r * foot_angle * (1.0 - x_heel) ** 2, 0.0)  # toes up, about the heel
    rise = r * heel_rise * smoothstep((u - b) / np.maximum(c - b, 1e-9))
    x_toe = np.clip((u - c) / np.where(rolls, 1.0 - c, 1.0), 0.0, 1.0)
    toe_pitch = np.where(rolls, r * TOE_OFF * x_toe ** 2, 0.0)  # ball up, about the toe tip
    heel = rig.heel_length
    toe = rig.toe
    on_heel = np.maximum(heel_pitch, 0.0)  # toes up: the foot turns about its heel; toes down: about its ball
    along = heel * (np.cos(on_heel) - 1.0) + toe * (1.0 - np.cos(toe_pitch))
    up = heel * np.sin(on_heel) + toe * np.sin(toe_pitch)
    ball = foothold + along[..., None] * forward + up[..., None] * normal
    ankle = rig.ankle_lift - heel_pitch + rise + toe_pitch
    drop = toe_pitch - on_heel
    return ball, ankle, drop


def straight_leg(rig: Rig, knee: float = STRAIGHT_KNEE) -> NDArray[np.float64]:
    """How far (m) femur and tibia span from hip to ankle with the knee flexed by
    ``knee`` (rad), (L,): the law of cosines."""
    f, t = rig.femur, rig.tibia
    return np.sqrt(f * f + t * t + 2.0 * f * t * np.cos(knee))


def foot_roll(rig: Rig, plan: FootPlan, ball: NDArray[np.float64], foot_angle: float) -> FootRoll | None:
    """The roll of every foot over a plan (None when no leg rolls). ball (T, L, 3) the
    flat foot's ball targets (:func:`~app.kinematics.footfalls.foot_targets`);
    foot_angle (rad) the toes-up angle at contact for roll 1."""
    r = rig.roll_amount
    if not np.any(r > 0):
        return None
    rolling = (r > 0)[None, :]
    plantigrade = (rig.heel_length > 0)[None, :]
    f_start = _foot_frame(plan.start_dir, plan.start_normal)
    f_end = _foot_frame(plan.end_dir, plan.end_normal)
    u = np.clip(plan.phase / plan.duty, 0.0, 1.0)
    walk = walking_weight(plan.duty)
    heel_rise = HEEL_RISE * walk + RUN_HEEL_RISE * (1.0 - walk)
    stance_ball, stance_ankle, stance_drop = _stance(rig, foot_angle, u, plan.start, f_start, plan.start_normal,
                                                     heel_rise)
    one = np.ones_like(u)
    _, lift_ankle, lift_drop = _stance(rig, foot_angle, one, plan.start, f_start, plan.start_normal, heel_rise)

    s = plan.swing
    contact = plan.contact
    # Lift-off: the toe-off pose fades over the first part of the swing.
    w_lift = 1.0 - smoothstep(s / BLEND)
    # Landing: the foot turns rigidly about its heel to the strike angle over the last part
    # (its heel follows the swing down), held to the landing pose from mid-swing on.
    pitch = r * foot_angle * smoothstep((s - (1.0 - BLEND)) / BLEND)
    on_heel = np.maximum(pitch, 0.0)
    land_offset = (rig.heel_length * (np.cos(on_heel) - 1.0))[..., None] * f_end \
        + (rig.heel_length * np.sin(on_heel))[..., None] * plan.end_normal
    w_land = smoothstep((s - (1.0 - LAND)) / LAND)
    land_ankle, land_drop = rig.ankle_lift - pitch, -on_heel
    # The swing eases onto the ground; a rolling foot comes down with some speed instead,
    # so it strikes (a kink in its height, as a real heel strike).
    strike = STRIKE_DROP * (rig.heel_length + rig.toe) * r * (1.0 - s) * w_land
    # The toe-off pose fades as a turn back about the toe tip (which stays where the swing
    # carries it, clear of the ground); the toe-off pose is all toe turn (the heel's part
    # is over by then).
    toe_turn = r * TOE_OFF * w_lift
    lift_offset = (rig.toe * (1.0 - np.cos(toe_turn)))[..., None] * f_start \
        + (rig.toe * np.sin(toe_turn))[..., None] * plan.start_normal
    swing_ball = ball + lift_offset + land_offset + strike[..., None] * plan.end_normal
    out_ball = np.where((contact & rolling)[..., None], stance_ball, np.where(rolling[..., None], swing_ball, ball))
    weight = np.clip(w_lift + w_land, 1e-12, None)
    # Between the two poses (both weights nil) the strike pose's angle, which the blend
    # tends to as the strike pose builds: no jump where the foot is held to its shank.
    blended = np.where(w_lift + w_land > 1e-9, (w_lift * lift_ankle + w_land * land_ankle) / weight, land_ankle)
    ankle = np.where(contact, stance_ankle, blended)
    drop = np.where(contact, stance_drop, (w_lift * lift_drop + w_land * land_drop) / weight)
    w = np.where(contact, 1.0, w_lift + w_land) * rolling
    forward = np.where(contact[..., None], f_start, (w_lift[..., None] * f_start + w_land[..., None] * f_end))
    forward = forward / np.maximum(np.linalg.norm(forward, axis=-1, keepdims=True), 1e-12)
    # The rolled ankle, where the leg's reach is measured from (femur and tibia span it).
    normal = np.where(contact[..., None], plan.start_normal, plan.end_normal)
    sets_ankle = (rolling & plantigrade)[..., None]
    ankle_point = out_ball + rig.metatarsus[:, None] * (-np.cos(ankle)[..., None] * forward
                                                       + np.sin(ankle)[..., None] * normal)
    ankle_point = np.where(sets_ankle, ankle_point, out_ball)
    reach = np.where(sets_ankle[0, :, 0], straight_leg(rig), REACH_LIMIT * rig.l_max)
    # Between the lift-off and strike poses a plantigrade foot swings held against its
    # shank, at right angles to it as a walker's is by mid-swing (not level with the ground).
    held = sets_ankle[..., 0] & ~contact
    ankle_weight = np.where(held, 1.0, w * plantigrade)
    fold = knee_fold(rig.poses.swing_knee)
    knee, knee_weight = walker_knee(plan.phase, plan.duty, contact, s, w_lift, fold)
    knee_weight = knee_weight * sets_ankle[..., 0]
    floor, ceiling, band_weight = walker_knee_band(s, plan.duty, fold)
    band_weight = np.where(contact, 0.0, band_weight * sets_ankle[..., 0])
    dorsi_weight = np.where(held, 1.0 - np.clip(w, 0.0, 1.0), 0.0)
    return FootRoll(ball=out_ball, ankle_angle=ankle, ankle_weight=ankle_weight, toe_drop=drop, toe_weight=w,
                    forward=forward, forward_weight=w, ankle=ankle_point, reach=reach, sets_ankle=sets_ankle[0, :, 0],
                    dorsiflexion=np.full(u.shape, SWING_DORSIFLEXION), dorsi_weight=dorsi_weight, knee=knee,
                    knee_weight=knee_weight, knee_floor=floor, knee_ceiling=ceiling,
                    band_weight=band_weight)


def heel_points(rig: Rig, joints: NDArray[np.float64], forward: NDArray[np.float64],
                up: NDArray[np.float64]) -> NDArray[np.float64]:
    """Each foot's heel (T, L, 3): where a rigid plantigrade foot touches behind the ball,
    from the solved ankle and ball (the metatarsus turned back by the ankle lift to lie
    along the sole); the ball itself for feet that do not roll or stand on their toes.
    forward, up: each leg's frame (broadcastable to (T, L, 3))."""
    ball, ankle = joints[..., 3, :], joints[..., 2, :]
    heel_length = np.where(rig.roll_amount > 0, rig.heel_length, 0.0)
    if not np.any(heel_length > 0):
        return ball.copy()
    fwd = np.broadcast_to(forward, ball.shape)
    upv = np.broadcast_to(up, ball.shape)
    m = (ball - ankle) / rig.metatarsus[:, None]
    uf, uu = np.sum(m * fwd, axis=-1), np.sum(m * upv, axis=-1)
    c, s = np.cos(rig.ankle_lift), np.sin(rig.ankle_lift)
    sole = (uf * c - uu * s)[..., None] * fwd + (uf * s + uu * c)[..., None] * upv
    return ball - heel_length[:, None] * sole


def roll_part(rig: Rig, foot_angle: float, phase: NDArray[np.float64], duty: NDArray[np.float64]
              ) -> NDArray[np.int64]:
    """Which point of each foot bears it at each frame (T, L): 0 the heel (rolling down
    after a heel strike), 1 the ball (flat, and through the heel rise), 2 the toe tip (the
    toe roll). Meaningful while planted."""
    r = rig.roll_amount
    u = phase / duty
    on_heel = (u < r * HEEL_PART) & (rig.heel_length > 0) & (foot_angle > 0)
    on_toe = (u >= 1.0 - r * TOE_PART) & (r > 0)
    return np.where(on_heel, 0, np.where(on_toe, 2, 1))


def contact_points(rig: Rig, foot_angle: float, phase: NDArray[np.float64], duty: NDArray[np.float64],
                   contact: NDArray[np.bool_], heel: NDArray[np.float64], joints: NDArray[np.float64]
                   ) -> NDArray[np.float64]:
    """The point of each planted foot that touches the ground and must not slip (T, L, 3):
    the heel while it rolls down, the ball while flat and through the heel rise, the toe
    tip in the toe roll (NaN for feet in the air). See :func:`roll_part`."""
    part = roll_part(rig, foot_angle, phase, duty)[..., None]
    point = np.where(part == 0, heel, np.where(part == 2, joints[..., 4, :], joints[..., 3, :]))
    return np.where(contact[..., None], point, np.nan)


def bearing_points(motion) -> tuple[NDArray[np.float64], NDArray[np.bool_]]:
    """A motion's bearing points (T, L, 3) (see :func:`contact_points`), in the ground's
    frame (in place, moved on by the ground's travel), and where a foot bears on the same
    point in two frames running (T-1, L): those points must not move."""
    rig = motion.rig
    duty = np.broadcast_to(rig.gait.duty_factor, motion.phase.shape)
    points = contact_points(rig, rig.poses.foot_angle, motion.phase, duty, motion.contact, motion.heel, motion.joints)
    points[..., 2] += motion.ground_offset[:, None]
    part = roll_part(rig, rig.poses.foot_angle, motion.phase, duty)
    same = motion.contact[1:] & motion.contact[:-1] & (motion.phase[1:] > motion.phase[:-1]) & (part[1:] == part[:-1])
    return points, same
