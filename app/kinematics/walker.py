"""How a walker's foot swings: the shapes of a person's swing, measured.

A foot that rolls heel to toe (a plantigrade foot with ``roll`` > 0: people) does not
swing along the smooth symmetric arc of the other feet. From the normative mean joint
angles of Schwartz, Rozumalski & Trost (2008, free speed, bundled in ``app/reference``),
put through a two-segment leg with a rigid foot (forward kinematics, the hip moving at
the stance foot's speed):

- the ball's progress along the stride in the world starts from rest (the foot is still
  on the ground at toe-off), is quick through the middle of the swing and settles onto
  the strike: :data:`WORLD_PROGRESS`; relative to the hip, which keeps moving, the foot
  first drifts on backwards as it did in stance;
- the ball lifts early, highest about a third of the way through the swing, and passes
  a couple of centimetres over the ground through the second half while the heel comes
  down to strike: :data:`BALL_LIFT`, as a fraction of the step height (the shape was
  first measured from the CMU walk 12_01, then held up in its second half so the toe
  tip clears the ground by ~1 cm, as people's does);
- at nine tenths of the swing the ball is a little further on (0.972 of its step, not
  the measured 0.963) and a little lower (0.25 of the step height, not 0.3), so the
  knee straightens through the last sixth of the swing as people's does instead of in
  its last frames (at free speed its largest turn in one 240 fps frame before the
  strike went from 4.8 to 2.8 degrees, the knee's RMS from the normative mean from 6.0
  to 5.1); further or lower, the foot hovers near the ground before it lands and
  ``analyze`` reads a longer stance (a duty factor of ~0.69 for 0.60);
- its knee, from late stance into the early swing, flexes as people's do: the heel
  rises about the ball just so much that the knee follows :data:`KNEE_NEAR_TOE_OFF`
  (by time from toe-off), nearly straight through terminal stance, ~35 degrees at
  toe-off;
- from early in the swing (36 % of a cycle before the strike) to just before the strike
  its knee keeps within :data:`KNEE_BAND` of :data:`KNEE_BEFORE_STRIKE` (by time to the
  strike): the swinging ball rises where the leg would straighten early and comes down
  (never nearer the ground than ``app.kinematics.leg.BAND_CLEARANCE``) where the knee
  would fold past its peak, so the knee peaks at ~72 % and straightens before the strike.

Both knee curves run on the normative walk's clock in the swing (by the swing's share,
so a slow walker's shorter swing goes through the whole of it), and a walker's
``poses.swing_knee`` scales their bend beyond a straight knee (:func:`knee_fold`): some
people fold the knee much more than the average, before toe-off and in the swing.

Runners (duty factor under one half) swing with the common smooth arc instead; the
walker's shapes fade out between duty factors 0.55 and 0.45.

Pure numpy and scipy, no GL.
"""

from __future__ import annotations

from functools import cache

import numpy as np
from numpy.typing import NDArray
from scipy.interpolate import PchipInterpolator

from .easing import smootherstep, smoothstep
from .gait import walking_weight
from .rig import Rig

SWING = np.linspace(0.0, 1.0, 11)
WORLD_PROGRESS = np.array([0.0, 0.041, 0.127, 0.24, 0.366, 0.504, 0.647, 0.779, 0.889, 0.972, 1.0])
BALL_LIFT = np.array([0.0, 0.7, 1.0, 1.0, 0.9, 0.8, 0.7, 0.6, 0.5, 0.25, 0.0])
# Knee flexion (deg) against time from toe-off (cycle fraction); Schwartz et al. 2008,
# free speed, whose toe-off is at 60 % of the cycle.
KNEE_FROM_TOE_OFF = np.arange(-0.32, 0.1201, 0.02)
KNEE_NEAR_TOE_OFF = np.array([11.3, 10.1, 9.0, 8.0, 7.2, 6.6, 6.2, 6.3, 6.8, 7.9, 9.5, 11.6, 14.5, 18.1, 22.6, 27.9,
                              33.9, 40.2, 46.3, 51.7, 55.7, 58.2, 59.1])
HEEL_FROM = -0.30  # of the cycle before toe-off: where the knee starts to steer the heel
# Knee flexion (deg) against time to the strike (cycle fraction), the same source: the
# terminal swing, in which the knee straightens from its peak to ~5 just before the strike.
KNEE_TO_STRIKE = np.arange(-0.36, 0.0001, 0.02)
KNEE_BEFORE_STRIKE = np.array([46.3, 51.7, 55.7, 58.2, 59.1, 58.7, 56.9, 53.9, 49.8, 44.7, 38.8, 32.4, 25.5, 18.7,
                               12.5, 7.6, 4.6, 4.0, 5.4])
FLOOR_FADE = (0.05, 0.015)  # of the cycle before the strike: the knee band lets go between these
KNEE_BAND = 3.0  # deg either side of the terminal swing's knee
CEILING_FADE = (-0.14, -0.08)  # of the cycle before the strike: the band's ceiling lets go between these
# A runner's knee near toe-off (deg, by the same clock): extending through the push-off
# to ~20 at toe-off, then folding fast in the swing (Novacheck 1998, Gait Posture 7:77).
RUN_KNEE_FROM_TOE_OFF = np.array([-0.20, -0.16, -0.12, -0.08, -0.04, 0.0, 0.04, 0.08, 0.12])
RUN_KNEE_NEAR_TOE_OFF = np.array([45.0, 42.0, 38.0, 32.0, 25.0, 20.0, 38.0, 60.0, 80.0])
RUN_HEEL_FROM = -0.20
SWING_KNEE = float(KNEE_BEFORE_STRIKE.max())  # deg: the curves' knee at its most bent in the swing
KNEE_STRAIGHT = 5.0  # deg: the curves' nearly straight knee; a walker's ``swing_knee`` scales the bend beyond it
# deg: the swing knees a walker may be given. Below ~57 the swing's own foot path bends
# the knee that far anyway (only the push-off would fold less); above 90 the fold whips.
SWING_KNEE_RANGE = (55.0, 90.0)
NORMATIVE_DUTY = 0.60  # the curves' toe-off (Schwartz et al.'s free speed): their clocks scale to a walker's swing


@cache  # one per curve name (five; an lru_cache of four thrashed, building a curve every call)
def _curve(name: str) -> PchipInterpolator:
    if name == "knee":
        return PchipInterpolator(KNEE_FROM_TOE_OFF, np.radians(KNEE_NEAR_TOE_OFF), extrapolate=False)
    if name == "terminal knee":
        return PchipInterpolator(KNEE_TO_STRIKE, np.radians(KNEE_BEFORE_STRIKE), extrapolate=False)
    if name == "run knee":
        return PchipInterpolator(RUN_KNEE_FROM_TOE_OFF, np.radians(RUN_KNEE_NEAR_TOE_OFF), extrapolate=False)
    values = WORLD_PROGRESS if name == "progress" else BALL_LIFT
    return PchipInterpolator(SWING, values)


def heel_to_toe(rig: Rig) -> NDArray[np.bool_]:
    """Which legs (L,) swing as a walker's: plantigrade feet that roll heel to toe."""
    return (rig.roll_amount > 0) & (rig.heel_length > 0)


def walker_ease(swing: NDArray[np.float64], duty: NDArray[np.float64]) -> NDArray[np.float64]:
    """Progress (...) from lift-off to landing relative to the hip's neutral point at swing
    progress ``swing``, for feet of duty factor ``duty`` (broadcastable): the world
    progress of :data:`WORLD_PROGRESS` less the body's own travel through the swing (the
    body moves 1 - duty of a stride while the foot moves a whole one)."""
    s = np.clip(swing, 0.0, 1.0)
    d = np.clip(duty, 1e-3, 1.0)
    relative = (_curve("progress")(s) - (1.0 - d) * s) / d
    w = walking_weight(duty)
    return relative * w + smootherstep(s) * (1.0 - w)


def walker_lift(swing: NDArray[np.float64], duty: NDArray[np.float64], lift: NDArray[np.float64]
                ) -> NDArray[np.float64]:
    """The ball's lift (fraction of the step height) at swing progress ``swing``: the
    measured walker's shape, faded into the oscillator's own ``lift`` for runners."""
    w = walking_weight(duty)
    return _curve("lift")(np.clip(swing, 0.0, 1.0)) * w + lift * (1.0 - w)


def knee_fold(swing_knee: float | None) -> float:
    """How much more (> 1) or less a walker's knee bends than people's on average, from its
    most bent knee in the swing (rad; None: people's, :data:`SWING_KNEE`)."""
    if swing_knee is None:
        return 1.0
    straight = np.radians(KNEE_STRAIGHT)
    return float((swing_knee - straight) / (np.radians(SWING_KNEE) - straight))


def _folded(knee: NDArray[np.float64], fold: float) -> NDArray[np.float64]:
    """People's knee curve (rad) with its bend beyond :data:`KNEE_STRAIGHT` scaled by ``fold``."""
    if fold == 1.0:
        return knee
    straight = np.radians(KNEE_STRAIGHT)
    return np.where(knee > straight, straight + (knee - straight) * fold, knee)


def walker_knee(phase: NDArray[np.float64], duty: NDArray[np.float64], contact: NDArray[np.bool_],
                swing: NDArray[np.float64], lifting: NDArray[np.float64], fold: float = 1.0
                ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The knee a walker's foot turns about its ball to give (rad) and its weight, (T, L)
    each: from :data:`HEEL_FROM` before toe-off through the stance, then while the
    lift-off pose lasts in the swing (``lifting`` (T, L) in [0, 1]); a runner's from
    :data:`RUN_HEEL_FROM`. phase, duty, contact, swing: the plan's (T, L); ``fold``:
    :func:`knee_fold` of the walker's swing knee."""
    since_toe_off = np.where(contact, phase - duty, swing * (1.0 - duty))
    # In the swing the walk's clock runs by the swing's share: a slow walker's shorter
    # swing (a higher duty factor) goes through the same knee (it folds and straightens
    # within it) rather than starting it part way.
    walk_clock = np.where(contact, since_toe_off, swing * (1.0 - NORMATIVE_DUTY))
    walk = _folded(_curve("knee")(np.clip(walk_clock, KNEE_FROM_TOE_OFF[0], KNEE_FROM_TOE_OFF[-1])), fold)
    run = _curve("run knee")(np.clip(since_toe_off, RUN_KNEE_FROM_TOE_OFF[0], RUN_KNEE_FROM_TOE_OFF[-1]))
    w = walking_weight(duty)
    target = walk * w + run * (1.0 - w)
    start = HEEL_FROM * w + RUN_HEEL_FROM * (1.0 - w)
    ramp = smoothstep((since_toe_off - start) / (0.06 * w + 0.1 * (1.0 - w)))
    weight = np.where(contact, ramp, (lifting > 0).astype(np.float64))
    return target, weight


def walker_knee_band(swing: NDArray[np.float64], duty: NDArray[np.float64], fold: float = 1.0
                     ) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """The least and the most knee flexion (rad) a walker's swinging foot keeps, and their
    weight, (T, L) each, from ``swing`` progress and ``duty`` (the plan's): the swing of
    :data:`KNEE_BEFORE_STRIKE` less and more :data:`KNEE_BAND`, from early in the swing
    (the first entry of :data:`KNEE_TO_STRIKE`; the foot neither skims the ground on a
    straight leg nor folds up past the peak), letting go just before the strike (:data:`FLOOR_FADE`) so the foot lands on
    its foothold; the ceiling lets go earlier (:data:`CEILING_FADE`), once past the peak.
    ``fold``: as in :func:`walker_knee`."""
    s = np.clip(swing, 0.0, 1.0)
    to_strike = -(1.0 - s) * (1.0 - NORMATIVE_DUTY)  # by the swing's share, as in walker_knee
    knee = _folded(_curve("terminal knee")(np.clip(to_strike, KNEE_TO_STRIKE[0], KNEE_TO_STRIKE[-1])), fold)
    start, end = FLOOR_FADE
    begin = smoothstep((to_strike - KNEE_TO_STRIKE[0]) / 0.04)
    weight = walking_weight(duty) * begin * (1.0 - smoothstep((to_strike + start) / (start - end)))
    band = np.radians(KNEE_BAND)
    # The ceiling only shapes the peak: in the terminal swing the foot comes down to the
    # ground on its own, the knee no more bent than its swing makes it.
    late, gone = CEILING_FADE
    ceiling_weight = 1.0 - smoothstep((to_strike - late) / (gone - late))
    return knee - band, knee + band + (1.0 - ceiling_weight) * 0.5 * np.pi, weight
