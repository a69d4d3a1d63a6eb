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
from .rig import Rig


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


RUN_KNEE = np.radians(40.0)  # a runner's stance knee at mid-stance, its lowest point
STRIKE_KNEE = np.radians(15.0)  # ... and never straighter than this at touchdown and lift-off
RUN_BLEND = 0.06  # of duty factor below one half: how far the run's flights fade in


def _step_times(duty: NDArray[np.float64], frequency: NDArray[np.float64]
                ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """How long (s) a running step's foot is down and how long the body flies, (T,) each:
    a step is half a cycle, its foot down for ``duty`` of the cycle."""
    period = 1.0 / np.maximum(frequency, 1e-6)
    contact = np.clip(duty, 1e-3, 0.5) * period
    return contact, 0.5 * period - contact


def flight_height(u: NDArray[np.float64], duty: NDArray[np.float64], frequency: NDArray[np.float64],
                  low: NDArray[np.float64]) -> NDArray[np.float64]:
    """A biped's body height offset (m) through a running step, (T,): ballistic in flight
    (falling at g), a half sine in stance whose slopes meet the flight's at touchdown and
    lift-off, lowest (``low``, m) at mid-stance. u (T,) step phase (0 at a touchdown);
    duty (T,) each foot's duty factor (below 0.5: the step's stance is 2 duty of it);
    frequency (T,) cycles/s."""
    contact, flight = _step_times(duty, frequency)
    t = np.mod(u, 1.0) * (contact + flight)
    v0 = 0.5 * G * flight  # the take-off (and landing) speed, m/s
    dip = v0 * contact / np.pi  # how far the stance sinks below touchdown
    in_air = t - contact
    stance = low + dip * (1.0 - np.sin(np.pi * np.clip(t / contact, 0.0, 1.0)))
    air = low + dip + v0 * in_air - 0.5 * G * in_air ** 2
    return np.where(in_air > 0.0, air, stance)


def running_low(rig: Rig, leg: int, ahead: NDArray[np.float64], duty: NDArray[np.float64],
                frequency: NDArray[np.float64]) -> NDArray[np.float64]:
    """The height offset (m from the girdle's rest height), (T,), of a runner's mid-stance:
    its knee flexed :data:`RUN_KNEE` over a flat foot, lowered if need be so that a foot
    landing ``ahead`` m in front of the hip (T,) reaches with its knee bent at least
    :data:`STRIKE_KNEE`."""
    f, t = rig.femur[leg], rig.tibia[leg]
    ankle = rig.metatarsus[leg] * np.sin(rig.ankle_lift[leg])  # a flat foot's ankle above the ground

    def span(knee: float) -> float:
        return float(np.sqrt(f * f + t * t + 2.0 * f * t * np.cos(knee)))

    rest = float(rig.girdle_rest_height[rig.girdle[leg]])
    low = ankle + span(RUN_KNEE) - rest
    touchdown = ankle + np.sqrt(np.maximum(span(STRIKE_KNEE) ** 2 - ahead ** 2, 0.0)) - rest
    contact, flight = _step_times(duty, frequency)
    dip = 0.5 * G * flight * contact / np.pi
    return np.minimum(low, touchdown - dip)


def body_height(rig: Rig, phase: NDArray[np.float64], duty: NDArray[np.float64], frequency: NDArray[np.float64],
                ahead: NDArray[np.float64]) -> NDArray[np.float64]:
    """A posed body's height offset (m), (T,): the key poses' curve while a foot is always
    down, the running step's (:func:`flight_height`) once the duty factor falls below one
    half, faded in over :data:`RUN_BLEND`. phase, duty (T, L); frequency (T,) Hz; ahead
    (T,) m: how far in front of its hip the reference foot lands."""
    assert rig.poses.heights is not None, "body_height is for posed bodies"
    ref = reference_foot(rig)
    u = step_phase(rig, phase)
    walk = pose_height(rig.poses.heights, u)
    d = duty[:, ref]
    run_weight = np.clip((0.5 - d) / RUN_BLEND, 0.0, 1.0) if rig.leg_count == 2 else np.zeros_like(d)
    if not np.any(run_weight):
        return walk
    w = run_weight * run_weight * (3.0 - 2.0 * run_weight)
    run = flight_height(u, d, frequency, running_low(rig, ref, ahead, d, frequency))
    return walk * (1.0 - w) + run * w
