"""Key poses: the body's height through a step as an animator keys it.

A step runs from one foot's contact to the other's (half a cycle). Its key poses fall at
fixed fractions of it (:data:`app.styles.KEY_POSE_TIMES`): contact 0, down 1/4, pass 1/2,
up 3/4; the next contact starts the mirrored step. The in-betweens follow a periodic
monotone cubic (PCHIP) through the four heights: smooth (C1), no overshoot, so the lowest
and highest points of the curve are key poses themselves — moving the lowest key moves the
body's lowest point by exactly as much, and no other key pose moves. (In the natural walk,
:mod:`app.kinematics.natural`, the lowest key is the contact: the body is lowest in double
support and crests at the pass. A lowest contact gets a narrow trough, two more knots at
:data:`CONTACT_TROUGH` either side on the secants to its neighbours: the strike turns the
body's fall into a rise at once, as a walker's stance leg vaults it.)

A run is no walk: once the feet leave the ground together (duty factor under one half) a
biped's body flies ballistically between stances (:func:`flight_height`), its keys set
aside, faded in over :data:`RUN_BLEND` of duty factor.

Pure numpy and scipy, no GL.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np
from numpy.typing import NDArray
from scipy.interpolate import PchipInterpolator

from ..styles import KEY_POSE_TIMES
from .gait import G
from .rig import Rig, stance_back
from .roll import TOE_OFF


def reference_foot(rig: Rig) -> int:
    """The foot whose touchdown starts a cycle: the rearmost left foot (Hildebrand)."""
    return rig.leg_count - 2


def step_phase(rig: Rig, phase: NDArray[np.float64]) -> NDArray[np.float64]:
    """Where each frame is within its step, [0, 1): 0 at the reference foot's contact and
    again at the other side's, half a cycle later. phase (T, L) feet's phases since touchdown."""
    return np.mod(2.0 * phase[..., reference_foot(rig)], 1.0)


CONTACT_TROUGH = 0.05  # of a step: the knots either side of a lowest contact key


@lru_cache(maxsize=64)
def _curve(heights: tuple[float, ...]) -> PchipInterpolator:
    times = np.asarray(KEY_POSE_TIMES)
    values = np.asarray(heights)
    # Two keys either side wrap the step around, so the slopes at contact match (periodic).
    t = np.concatenate([times[-2:] - 1.0, times, times[:2] + 1.0, [times[2] + 1.0]])
    v = np.concatenate([values[-2:], values, values[:2], [values[2]]])
    if values[0] < min(values[1], values[2], values[3]):
        # A lowest contact: the heel strike turns the body's fall into a rise at once, as
        # the stance leg vaults it up (a walker's knee flexes in loading response only as
        # the body rides up: its peak comes at ~14 %, not at once). Knots either side at
        # CONTACT_TROUGH, on the secants to the neighbouring keys, keep the trough narrow;
        # the lowest point is still the contact key's.
        pairs = [(time, height) for time, height in zip(t, v)]
        for contact in (0.0, 1.0):
            for side, key in ((-1.0, values[3]), (1.0, values[1])):
                span = 1.0 - times[3] if side < 0 else times[1]
                pairs.append((contact + side * CONTACT_TROUGH,
                              values[0] + (key - values[0]) * CONTACT_TROUGH / span))
        pairs.sort()
        t = np.array([time for time, _ in pairs])
        v = np.array([height for _, height in pairs])
    return PchipInterpolator(t, v)


def pose_height(heights: NDArray[np.float64], u: NDArray[np.float64]) -> NDArray[np.float64]:
    """The body's height offset (m) at step phases ``u`` (...), through the key poses'
    heights (4,) (contact, down, pass, up)."""
    curve = _curve(tuple(round(float(h), 9) for h in heights))  # nanometres: no overflowing slopes
    return curve(np.mod(u, 1.0))


def key_pose_phases(first_step: bool = True) -> NDArray[np.float64]:
    """Cycle phases of contact, down, pass, up and the next contact (5,), for the first
    step (or the second, mirrored one)."""
    start = 0.0 if first_step else 0.5
    return start + 0.5 * np.append(np.asarray(KEY_POSE_TIMES), 1.0)


RUN_KNEE = np.radians(48.0)  # a runner's stance knee at mid-stance, its lowest point (40-50)
STRIKE_KNEE = np.radians(20.0)  # ... at touchdown (15-25)
TOE_OFF_THIGH = np.radians(-15.0)  # ... the thigh against the vertical at toe-off (-10 to -20: behind the hip)
TOE_OFF_KNEE = np.radians(22.0)  # ... the knee at toe-off (~20)
TOE_OFF_ANKLE = np.radians(-26.0)  # ... the ankle at toe-off, plantarflexed (-20 to -30)
TAKE_OFF_SPEED = 0.1  # m/s: the least a runner's body still rises at toe-off
LOWEST_AT = 0.45  # of the stance: where a runner's body is lowest (a little before mid-stance)
RUN_BLEND = 0.06  # of duty factor below one half: how far the run's flights fade in


def _step_times(duty: NDArray[np.float64], frequency: NDArray[np.float64]
                ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """How long (s) a running step's foot is down and how long the body flies, (T,) each:
    a step is half a cycle, its foot down for ``duty`` of the cycle."""
    period = 1.0 / np.maximum(frequency, 1e-6)
    contact = np.clip(duty, 1e-3, 0.5) * period
    return contact, 0.5 * period - contact


def _quintic(h: NDArray[np.float64], start: tuple[NDArray[np.float64], ...], end: tuple[NDArray[np.float64], ...],
             t: NDArray[np.float64]) -> NDArray[np.float64]:
    """The quintic through (height, speed, acceleration) ``start`` at time 0 and ``end`` at
    ``h`` (s), at times ``t`` (all broadcastable)."""
    y0, v0, a0 = start
    y1, v1, a1 = end
    s = np.clip(t / h, 0.0, 1.0)
    s2, s3 = s * s, s * s * s
    h0 = 1.0 - 10.0 * s3 + 15.0 * s3 * s - 6.0 * s3 * s2
    h1 = s - 6.0 * s3 + 8.0 * s3 * s - 3.0 * s3 * s2
    h2 = 0.5 * (s2 - 3.0 * s3 + 3.0 * s3 * s - s3 * s2)
    h3 = 0.5 * (s3 - 2.0 * s3 * s + s3 * s2)
    h4 = -4.0 * s3 + 7.0 * s3 * s - 3.0 * s3 * s2
    h5 = 10.0 * s3 - 15.0 * s3 * s + 6.0 * s3 * s2
    return y0 * h0 + v0 * h * h1 + a0 * h * h * h2 + a1 * h * h * h3 + v1 * h * h4 + y1 * h5


# Gauss-Legendre nodes and weights on [0, 1]: three integrate a quintic's squared jerk
# (a quartic) exactly.
_GAUSS_S = 0.5 + 0.5 * np.array([-np.sqrt(0.6), 0.0, np.sqrt(0.6)])
_GAUSS_W = np.array([5.0, 8.0, 5.0]) / 18.0


def _quintic_jerk(h: NDArray[np.float64], start: tuple[NDArray[np.float64], ...], end: tuple[NDArray[np.float64], ...]
                  ) -> NDArray[np.float64]:
    """The third derivative (m/s^3) of :func:`_quintic` at the Gauss nodes, (3, ...)."""
    y0, v0, a0 = start
    y1, v1, a1 = end
    s = _GAUSS_S.reshape((3,) + (1,) * np.ndim(h))
    d0 = -60.0 + 360.0 * s - 360.0 * s * s
    d1 = -36.0 + 192.0 * s - 180.0 * s * s
    d2 = -9.0 + 36.0 * s - 30.0 * s * s
    d3 = 3.0 - 24.0 * s + 30.0 * s * s
    d4 = -24.0 + 168.0 * s - 180.0 * s * s
    return ((y0 - y1) * d0 + v0 * h * d1 + a0 * h * h * d2 + a1 * h * h * d3 + v1 * h * d4) / h ** 3  # (y1's basis: -d0)


def _lowest_acceleration(first: NDArray[np.float64], second: NDArray[np.float64], drop: NDArray[np.float64],
                         rise: NDArray[np.float64], land: NDArray[np.float64], lift: NDArray[np.float64]
                         ) -> NDArray[np.float64]:
    """The body's upward acceleration (m/s^2) at its lowest point that makes the stance's two
    quintics (``first`` s falling ``drop`` m from landing at ``land`` m/s, ``second`` s
    rising ``rise`` m to lift off at ``lift`` m/s, -g at both ends) as smooth as they can
    be: the least squared jerk over the whole stance. The jerk is linear in that
    acceleration and the squared jerk a quartic in time, integrated exactly (three-point
    Gauss-Legendre), so the least is found exactly: a ratio of two sums."""
    zero = np.zeros_like(first)
    one = zero + 1.0
    num = zero.copy()
    den = zero.copy()
    for h, ends in ((first, lambda a: ((zero, -land, -G + zero), (-drop, zero, a))),
                    (second, lambda a: ((zero, zero, a), (rise, lift, -G + zero)))):
        base = _quintic_jerk(h, *ends(zero))
        slope = _quintic_jerk(h, *ends(one)) - base
        w = _GAUSS_W.reshape((3,) + (1,) * np.ndim(h)) * h
        num = num + np.sum(w * base * slope, axis=0)
        den = den + np.sum(w * slope * slope, axis=0)
    return -num / np.maximum(den, 1e-12)


def flight_height(u: NDArray[np.float64], duty: NDArray[np.float64], frequency: NDArray[np.float64],
                  heights: tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]
                  ) -> NDArray[np.float64]:
    """A biped's body height offset (m) through a running step, (T,): ballistic in flight
    (falling at g) from toe-off to touchdown, and in stance two quintics falling from the
    touchdown to the lowest point (at :data:`LOWEST_AT` of the stance) and rising to the
    toe-off, whose heights, speeds and accelerations meet the flight's at both ends (no
    jolt). u (T,) step phase (0 at a touchdown); duty (T,) each foot's duty factor (below
    0.5: the step's stance is 2 duty of it); frequency (T,) cycles/s; heights: the
    touchdown's, the lowest point's and the toe-off's (m, (T,) each, from
    :func:`running_heights`)."""
    touchdown, low, toe_off = heights
    contact, flight = _step_times(duty, frequency)
    air = np.maximum(flight, 1e-6)
    lift = (touchdown - toe_off) / air + 0.5 * G * flight  # m/s up at toe-off
    land = G * flight - lift  # m/s down at touchdown
    t = np.mod(u, 1.0) * (contact + flight)
    first, second = LOWEST_AT * contact, (1.0 - LOWEST_AT) * contact
    a = _lowest_acceleration(first, second, touchdown - low, toe_off - low, land, lift)
    still, fall = np.zeros_like(a), np.full_like(a, -G)
    falling = _quintic(first, (touchdown, -land, fall), (low, still, a), t)
    rising = _quintic(second, (low, still, a), (toe_off, lift, fall), t - first)
    in_air = t - contact
    ballistic = toe_off + lift * in_air - 0.5 * G * in_air ** 2
    return np.where(in_air > 0.0, ballistic, np.where(t < first, falling, rising))


def running_heights(rig: Rig, leg: int, stride: NDArray[np.float64], duty: NDArray[np.float64],
                    frequency: NDArray[np.float64]
                    ) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """A runner's body height offsets (m from the girdle's rest height), (T,) each, for a
    planted foot travelling ``stride`` m (T,) under its hip: at touchdown, the heel striking
    ahead of the hip (:func:`~app.kinematics.rig.stance_back`) with the knee at
    :data:`STRIKE_KNEE`; at its lowest, the knee :data:`RUN_KNEE` over a flat foot; at
    toe-off, the leg behind the hip (:data:`TOE_OFF_THIGH`, :data:`TOE_OFF_KNEE`) on a
    plantarflexed foot (:data:`TOE_OFF_ANKLE`), no higher than that leg reaches its ball
    and than lets the body still rise (:data:`TAKE_OFF_SPEED`) and fall back to the
    touchdown in the flight between."""
    f, t, m = rig.femur[leg], rig.tibia[leg], rig.metatarsus[leg]
    lift = rig.ankle_lift[leg]
    ankle = m * np.sin(lift)  # a flat foot's ankle above the ground
    back_of_stance = stance_back(duty)
    ahead = 0.5 * (1.0 - back_of_stance) * stride  # the ankle at touchdown, ahead of the hip
    # The foot strikes on its heel, toes up by the roll's contact angle: the ankle higher
    # and further back than over a flat foot.
    toes_up = rig.roll_amount[leg] * rig.poses.foot_angle
    heel = rig.heel_length[leg] - m * np.cos(lift)  # the heel behind the ankle
    strike = heel * np.sin(toes_up) + ankle * np.cos(toes_up)
    ahead = ahead - heel * (1.0 - np.cos(toes_up)) - ankle * np.sin(toes_up)

    def span(knee: float) -> float:
        return float(np.sqrt(f * f + t * t + 2.0 * f * t * np.cos(knee)))

    rest = float(rig.girdle_rest_height[rig.girdle[leg]])
    touchdown = strike + np.sqrt(np.maximum(span(STRIKE_KNEE) ** 2 - ahead ** 2, 0.0)) - rest
    low = np.minimum(ankle + span(RUN_KNEE) - rest, touchdown)
    # Toe-off: the leg's shape (knee and ankle) set, the thigh's angle or the ball's place
    # behind the hip decides the height, whichever is lower.
    shank = TOE_OFF_THIGH - TOE_OFF_KNEE  # from the vertical, + ahead
    foot = min(lift - shank - TOE_OFF_ANKLE, 0.5 * np.pi)  # the metatarsus below the horizontal
    ball = rig.toe[leg] * np.sin(rig.roll_amount[leg] * TOE_OFF)  # the ball above the ground, over the toe tip
    by_thigh = f * np.cos(TOE_OFF_THIGH) + t * np.cos(shank) + m * np.sin(foot) + ball - rest
    chain = np.array([f * np.sin(TOE_OFF_THIGH) + t * np.sin(shank) + m * np.cos(foot),
                      f * np.cos(TOE_OFF_THIGH) + t * np.cos(shank) + m * np.sin(foot)])
    behind = 0.5 * (1.0 + back_of_stance) * stride - m * np.cos(lift)  # the ball behind the hip at toe-off
    by_reach = np.sqrt(np.maximum(float(chain @ chain) - behind ** 2, 0.0)) + ball - rest
    _, flight = _step_times(duty, frequency)
    rise = np.minimum(TAKE_OFF_SPEED, 0.5 * G * flight)
    highest = touchdown + (0.5 * G * flight - rise) * flight
    lowest = touchdown - 0.5 * G * flight * flight
    toe_off = np.clip(np.minimum(by_thigh, by_reach), lowest, highest)
    return touchdown, np.minimum(low, toe_off), toe_off


def body_height(rig: Rig, phase: NDArray[np.float64], duty: NDArray[np.float64], frequency: NDArray[np.float64],
                stride: NDArray[np.float64]) -> NDArray[np.float64]:
    """A posed body's height offset (m), (T,): the key poses' curve while a foot is always
    down, the running step's (:func:`flight_height`) once the duty factor falls below one
    half, faded in over :data:`RUN_BLEND`. phase, duty (T, L); frequency (T,) Hz; stride
    (T,) m: how far the reference foot travels under its hip while planted."""
    assert rig.poses.heights is not None, "body_height is for posed bodies"
    ref = reference_foot(rig)
    u = step_phase(rig, phase)
    walk = pose_height(rig.poses.heights, u)
    d = duty[:, ref]
    run_weight = np.clip((0.5 - d) / RUN_BLEND, 0.0, 1.0) if rig.leg_count == 2 else np.zeros_like(d)
    if not np.any(run_weight):
        return walk
    w = run_weight * run_weight * (3.0 - 2.0 * run_weight)
    run = flight_height(u, d, frequency, running_heights(rig, ref, stride, d, frequency))
    return walk * (1.0 - w) + run * w


HEIGHT_SETTLE = 0.25  # s: how long a jump in a posed body's height (a change of duty factor) takes to die away


def height_jump(rig: Rig, phase: NDArray[np.float64], before: NDArray[np.float64], now: NDArray[np.float64],
                frequency: float, stride: float, dt: float) -> tuple[float, float]:
    """How much higher (m) and faster rising (m/s) a posed body would stand at this frame by
    the feet's duty factors ``before`` (L,) than it does by ``now`` (L,): the jump their
    change makes in :func:`body_height`, to be eased away (:func:`settle`). phase (L,) the
    feet's phases; frequency cycles/s; stride (m) the reference foot's travel under its hip;
    dt (s) the frame's length (the speeds are differences over it)."""
    back = phase - frequency * dt
    phases = np.stack([phase, back, phase, back])
    duties = np.stack([before, before, now, now])
    heights = body_height(rig, phases, duties, np.full(4, frequency), np.full(4, stride))
    jump = float(heights[0] - heights[2])
    speed = float((heights[0] - heights[1]) - (heights[2] - heights[3])) / max(dt, 1e-9)
    return jump, speed


def settle(jump: float, speed: float, elapsed: NDArray[np.float64] | float,
           duration: float = HEIGHT_SETTLE) -> NDArray[np.float64]:
    """What is left (m) ``elapsed`` s after it of a height jump of ``jump`` m rising at
    ``speed`` m/s: a quintic from the jump (with its speed, no acceleration) to nothing at
    rest after ``duration`` s, so that the body keeps the height and speed it had
    (inertialization)."""
    t = np.asarray(elapsed, dtype=np.float64)
    zero = np.zeros_like(t)
    eased = _quintic(np.full_like(t, duration), (jump + zero, speed + zero, zero), (zero, zero, zero), t)
    return np.where(t < duration, eased, 0.0)
