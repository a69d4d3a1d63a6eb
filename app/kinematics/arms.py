"""Arms: shoulder, elbow, wrist and hand tip, swinging opposite to the legs.

Each arm hangs from its shoulder and swings in the body's sagittal plane like a pendulum
driven by the legs: the left arm is farthest forward when the right foot touches down
(and so the right arm with the left foot), a cosine of the opposite foot's phase, delayed
by the arms' overlap. The elbow keeps its rest bend and bends further as the arm swings
forward; the hand carries on from the forearm, a little flexed. Vectorised over frames.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from .body import cross
from .frames import UP
from .rig import ArmShape

RUN_ELBOW = np.radians(80.0)  # a runner's elbows at rest in the swing (held near 80-100 degrees)
RUN_ARM_BACK = np.radians(15.0)  # a runner's arms swing about a line this far behind the vertical (more back than forward)
FORWARD_BEND = 0.6  # extra elbow bend per radian of forward swing
RUN_ELBOW_SWING = 0.8  # a runner's elbow bends more (less) per radian its arm is ahead of (behind) the swing's middle
RUN_FIST = 2.0  # a runner's hand turns in across the body this much more than the forearm (a loose fist, palm in)
RUN_ARM_IN = 0.35  # a runner's forearms turn in towards the body's middle (the hands cross in front of it)
WRIST_FLEX = 0.15  # rad the hand turns further than the forearm
ARM_SPREAD = 0.06  # rad the arms hang out from the body


def arm_swing(swing: float, delay: float, opposite_phase: NDArray[np.float64]) -> NDArray[np.float64]:
    """Each arm's swing angle (T, 2), rad forward, left then right: ``swing`` times the
    cosine of the opposite foot's phase (T, 2: the right foot's for the left arm, the left
    foot's for the right), ``delay`` cycles later."""
    return swing * np.cos(2.0 * np.pi * (opposite_phase - delay))


def arm_chains(arms: ArmShape, centre: NDArray[np.float64], lateral: NDArray[np.float64],
               angle: NDArray[np.float64], running: NDArray[np.float64] | float = 0.0) -> NDArray[np.float64]:
    """Arm joints (T, 2, 4, 3): shoulder, elbow, wrist and hand tip of the left and right
    arm. centre (T, 3) the point between the shoulders; lateral (T, 3) the unit axis to
    the body's left through them; angle (T, 2) each arm's swing (rad, forward); running
    (T,) in [0, 1]: how far the elbows bend towards a runner's :data:`RUN_ELBOW`, the
    swing moves back by :data:`RUN_ARM_BACK`, the elbow closes ahead of the swing's middle
    and opens behind it (:data:`RUN_ELBOW_SWING`), the forearm turns in towards the
    body's middle (:data:`RUN_ARM_IN`) and the hand turns in across the body (a loose fist, :data:`RUN_FIST`)."""
    lateral = lateral - np.sum(lateral * UP, axis=-1, keepdims=True) * UP
    lateral = lateral / np.maximum(np.linalg.norm(lateral, axis=-1, keepdims=True), 1e-12)
    forward = cross(lateral, UP)  # (T, 3): left x up = forward
    side = np.array([1.0, -1.0])[None, :, None]
    shoulder = centre[:, None, :] + side * 0.5 * arms.shoulder_width * lateral[:, None, :]
    out = side * np.sin(ARM_SPREAD) * lateral[:, None, :]
    f, u = forward[:, None, :], UP[None, None, :]

    def direction(theta):
        return np.sin(theta)[..., None] * f - np.cos(theta)[..., None] * u + out

    run = np.reshape(np.asarray(running, dtype=np.float64), (-1, 1))
    rest = arms.elbow + (max(RUN_ELBOW, arms.elbow) - arms.elbow) * run
    swing = angle  # about the swing's middle
    angle = angle - RUN_ARM_BACK * run  # driving the elbows back, the hands coming forward only to the chest
    # A walker's elbow bends as the arm comes forward; a runner's closes ahead and opens
    # behind about its rest, the forearm rising to the chest (not held out like a tray).
    bend = rest + (1.0 - run) * FORWARD_BEND * np.maximum(angle, 0.0) + run * RUN_ELBOW_SWING * swing
    inward = -side * (RUN_ARM_IN * run)[..., None] * lateral[:, None, :]  # (T, 2, 3)
    elbow = shoulder + arms.upper * _unit(direction(angle))
    wrist = elbow + arms.fore * _unit(direction(angle + bend) + inward)
    across = -side * lateral[:, None, :]  # (T, 2, 3): towards the body's middle
    fist = (RUN_FIST * run)[..., None]  # (T, 1, 1)
    hand = wrist + arms.hand * _unit(_unit(direction(angle + bend + WRIST_FLEX) + inward) + fist * across)
    return np.stack([shoulder, elbow, wrist, hand], axis=2)


def _unit(v: NDArray[np.float64]) -> NDArray[np.float64]:
    return v / np.linalg.norm(v, axis=-1, keepdims=True)
