"""The rig: everything the solver needs about a creature, as numpy arrays in SI units.

A rig is built from a creature file by :func:`app.rigging.build_rig`; nothing here knows
about files. Legs are ordered as the feet are named (:func:`app.gaits.foot_names`): front
pair first, left before right. A *girdle* is one leg pair, attached to the trunk at a
fraction of its length (0 the rear end, 1 the front end); girdles are indexed front first.

Each leg has its own frame: for knees that point forward or back (mammals) the sagittal
plane of the body; for knees that point out (insects, spiders) the vertical plane through
the hip and the foot's rest position, so the knee stands up and out.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass, field, replace

import numpy as np
from numpy.typing import NDArray

from ..choices import PLANTIGRADE_BELOW
from .gait import GaitParams, ground_speed, walking_weight

MIN_CROUCH = 0.6  # a girdle never stands lower than this fraction of its rest height
REACH_LIMIT = 0.985  # a planted foot's ball stays within this fraction of L_max, wherever the ground is
STANCE_BACK = 0.25  # of half the stride: how far behind the hip a rolling plantigrade ankle is at mid-stance
TAIL_DROOP = 0.4  # the tail's last segment hangs this much further (fraction of tail_angle)
RUN_STANCE_BACK = 0.37  # ... a runner's: its foot lands nearer under it and pushes off further behind


def stance_back(duty: float | NDArray[np.float64]) -> NDArray[np.float64]:
    """Of half the stride, how far behind the hip a rolling plantigrade ankle is at
    mid-stance at duty factor ``duty`` (any shape): a walker's :data:`STANCE_BACK` turning
    into a runner's :data:`RUN_STANCE_BACK` as the feet start to leave the ground together."""
    w = walking_weight(duty)
    return STANCE_BACK * w + RUN_STANCE_BACK * (1.0 - w)
SPRAWL_MARGIN = 0.95  # a sprawled foot's rest spot stays within this fraction of full reach, striding


def leg_lengths(femur: NDArray, tibia: NDArray, metatarsus: NDArray, ankle_lift: NDArray,
                natural_bend: NDArray, swing_rest: NDArray | float = 0.0) -> tuple[NDArray, NDArray, NDArray]:
    """Maximum, rest and minimum hip-to-ball distance of legs (all arrays (L,), metres).

    With the metatarsus at ``phi = ankle_lift + swing_rest`` from the perpendicular of the
    hip-ball line (``swing_rest`` is how far the rest direction of a sprawled leg is turned
    from vertical in its own plane), ``L_max = sqrt((f+t)^2 - (m cos phi)^2) + m sin phi``,
    ``L_rest = L_max * clamp(1 - bend, 0.2, 1)``, and ``L_min`` is the largest of
    ``0.2 L_max``, the distance below which the knee cannot fold (``|f - t| - m``) and, for
    a metatarsus longer than femur and tibia together, the distance below which the ankle
    cannot reach (``m - f - t``), with a small margin; ``L_max`` is never below ``L_min``.
    """
    reach = femur + tibia
    phi = ankle_lift + swing_rest
    flat = metatarsus * np.cos(phi)
    l_max = np.sqrt(np.maximum(reach ** 2 - flat ** 2, 0.0)) + metatarsus * np.sin(phi)
    l_rest = l_max * np.clip(1.0 - natural_bend, 0.2, 1.0)
    l_min = np.maximum.reduce([0.2 * l_max, np.abs(femur - tibia) - metatarsus, metatarsus - reach]) * 1.001
    # A metatarsus much longer than femur and tibia, turned far from the hip-ball line (a
    # sprawled leg's rest turn), gave an L_max below L_min: the ball was held beyond the
    # ankle's reach and the leg's bones stretched. Such a leg's range is L_min at least.
    l_max = np.maximum(l_max, l_min)
    return l_max, l_rest, l_min


@dataclass(frozen=True)
class BodyShape:
    """Trunk, neck, head and tail. Metres and radians.

    length: rear end to front end of the trunk along the spine (a tetrapod's hind hips to
    fore shoulders); radius (R,) the trunk's profile from rear to front.
    """

    length: float
    width: float
    radius: NDArray[np.float64]
    segments: int
    neck_length: float
    neck_angle: float
    head_length: float
    head_radius: float
    head_angle: float
    ear_length: float
    tail_length: float
    tail_angle: float
    tail_segments: int
    upright: bool = False  # the trunk rises from its one girdle (a human) instead of running between girdles
    tail_radius: float | None = None  # m at the base (None: a third of the rump's radius)
    mane: float = 0.0  # m: the height of a mane along the top of the neck (0: none)
    tail_curl: float = 0.0  # rad the tail turns up (+) from its first segment to its last
    wings: float = 0.0  # m: how far a bird's folded wings reach back from the shoulders (0: none)
    beak: float = 0.0  # m: a beak's length back from the head's tip (0: a muzzle)
    hump: float = 0.0  # m: a hump's height over the back behind the shoulders (0: none)

    def tail_droop(self, segments: int | None = None) -> NDArray[np.float64]:
        """Each tail segment's droop below the body axis at rest (rad, (K,), base to tip):
        the tail angle, a little more towards the tip (:data:`TAIL_DROOP`), less the curl
        (up to hanging straight down)."""
        count = self.tail_segments if segments is None else segments
        k = np.arange(count)
        along = k / max(count - 1, 1)
        droop = self.tail_angle * (1.0 + TAIL_DROOP * k / max(count, 1)) - self.tail_curl * along
        return np.minimum(droop, 0.5 * np.pi)


@dataclass(frozen=True)
class SecondaryMotion:
    """yaw: how far (rad) the girdles turn with their feet (the shoulders of an upright
    body turn the other way); tail_sway (rad); bob_phase (cycle fraction) shifts the body
    bob relative to the feet; pelvis_tilt (rad): how far a girdle drops on the side of its
    swinging leg; sway (m): how far a girdle moves sideways towards its stance foot."""

    yaw: float = 0.0
    tail_sway: float = 0.0
    bob_phase: float = 0.0
    pelvis_tilt: float = 0.0
    sway: float = 0.0


@dataclass(frozen=True)
class ArmShape:
    """Two arms: bone lengths (m), bone radius at the shoulder (m), the distance between
    the shoulders (m), where they sit along the trunk (0 rear/bottom, 1 front/top) and the
    elbow's rest bend (rad)."""

    upper: float
    fore: float
    hand: float
    radius: float
    shoulder_width: float
    position: float
    elbow: float


@dataclass(frozen=True)
class KeyPoses:
    """The key poses of a step. heights (4,): the body's height (m) at contact, down,
    pass and up relative to its rest height, or None (the gait's own bob);
    foot_angle (rad, toes up at contact, with the legs' roll); arm_swing (rad either
    way); torso_lean (rad forward, upright bodies); swing_knee (rad: a walker's knee at
    its most bent in the swing; None: people's, ``app.kinematics.walker.SWING_KNEE``)."""

    heights: NDArray[np.float64] | None = None
    foot_angle: float = 0.35
    arm_swing: float = 0.4
    torso_lean: float = 0.0
    swing_knee: float | None = None


@dataclass(frozen=True)
class Overlap:
    """Follow-through delays (cycle fractions) of the head, neck, arms, tail and ears."""

    head: float = 0.0
    neck: float = 0.0
    arms: float = 0.0
    tail: float = 0.0
    ears: float = 0.0


@dataclass(frozen=True)
class Look:
    """Colours as ``#rrggbb`` strings (sRGB); ``countershade`` in [0, 1] how much lighter
    the smooth body is underneath."""

    body_color: str = "#b59a7a"
    left_color: str = "#2f8f9d"
    right_color: str = "#d8664f"
    countershade: float = 0.35
    leg_color: str | None = None  # the lower legs and feet on a smooth body (None: the body's)
    neck_color: str | None = None  # the neck and head (None: the body's)
    beak_color: str | None = None  # the beak (None: horn)
    plume_color: str | None = None  # the wings' and tail's feathers (None: the body's)


@dataclass(frozen=True)
class SpeedGaits:
    """How speed picks the gait: ``ladder`` lists (gait, the Froude number from which it is
    used) slow to fast, the first from 0 (one gait: speed only scales it); ``hysteresis``
    is the fraction above (below) a threshold at which the gait changes up (down);
    ``gaits`` holds each gait with its phases, step heights and bob resolved for this
    creature."""

    ladder: tuple[tuple[str, float], ...]
    hysteresis: float
    gaits: dict[str, GaitParams] = field(default_factory=dict)

    @property
    def order(self) -> tuple[str, ...]:
        """The gaits, slow to fast."""
        return tuple(name for name, _ in self.ladder)


def _frozen(values: NDArray[np.float64]) -> NDArray[np.float64]:
    """``values``, read-only: a rig's derived arrays are computed once and shared."""
    values.flags.writeable = False
    return values


@dataclass(frozen=True)
class Rig:
    """Per-leg arrays (shape (L,) unless noted) and the per-creature values.

    Lengths in metres, angles in radians. ``hip_side`` is +1 for left legs (+X) and -1 for
    right legs; ``girdle`` is each leg's girdle index (0 = front pair); ``knee_out`` marks
    sprawled legs whose knee points up and out (``knee_pole``); ``swing_rest`` is the angle (rad) of a
    leg's rest hip-to-foot direction from its frame's down axis (the abduction of a
    sprawled leg, 0 for the others).
    """

    name: str
    leg_names: tuple[str, ...]
    femur: NDArray[np.float64]
    tibia: NDArray[np.float64]
    metatarsus: NDArray[np.float64]
    toe: NDArray[np.float64]
    ankle_lift: NDArray[np.float64]
    l_max: NDArray[np.float64]
    l_rest: NDArray[np.float64]
    l_min: NDArray[np.float64]
    knee_sign: NDArray[np.float64]
    knee_out: NDArray[np.bool_]
    knee_pole: NDArray[np.float64]  # (L, 2) where the knee bends, as (forward, up) in the leg frame
    swing_rest: NDArray[np.float64]
    bone_radius: NDArray[np.float64]
    hip_side: NDArray[np.float64]
    girdle: NDArray[np.int64]
    hip_offset: NDArray[np.float64]
    abduction: NDArray[np.float64]
    splay: NDArray[np.float64]
    girdle_position: NDArray[np.float64]  # (G,) along the trunk: 0 rear end, 1 front end
    girdle_rest_height: NDArray[np.float64]  # (G,) hip height of each girdle at rest
    body: BodyShape
    gait: GaitParams
    motion: SecondaryMotion = SecondaryMotion()
    look: Look = Look()
    speed: SpeedGaits | None = None
    arms: ArmShape | None = None
    poses: KeyPoses = KeyPoses()
    overlap: Overlap = Overlap()
    roll: NDArray[np.float64] | None = None  # (L,) foot roll amount 0..1 (None: all 0)
    heel: NDArray[np.float64] | None = None  # (L,) m a plantigrade heel reaches behind the ankle (None: all 0)
    toes: NDArray[np.int64] | None = None  # (L,) splayed toes drawn (0: the leg type's sole, paw or hoof; None: all 0)
    model: str = ""  # the rigged model (a .glb/.gltf path) whose own skeleton and mesh this creature drives

    @property
    def leg_count(self) -> int:
        return len(self.leg_names)

    @functools.cached_property
    def roll_amount(self) -> NDArray[np.float64]:
        """Each foot's roll amount (L,), 0 (lands flat) to 1."""
        return np.zeros(self.leg_count) if self.roll is None else np.asarray(self.roll, dtype=np.float64)

    @functools.cached_property
    def heel_length(self) -> NDArray[np.float64]:
        """How far (m) behind the ball a foot's heel touches the ground (L,): the flat
        metatarsus of a plantigrade foot and its heel behind the ankle
        (:attr:`heel`), 0 for feet that stand on their toes."""
        heel = np.zeros(self.leg_count) if self.heel is None else np.asarray(self.heel, dtype=np.float64)
        return np.where(self.ankle_lift < np.radians(PLANTIGRADE_BELOW), self.metatarsus * np.cos(self.ankle_lift) + heel,
                        0.0)

    @property
    def hip_height(self) -> float:
        """Mean rest hip height over the girdles (m): the ``h`` of the Froude number."""
        return float(self.girdle_rest_height.mean())

    @property
    def body_length(self) -> float:
        return self.body.length

    @functools.cached_property
    def leg_scale(self) -> float:
        """The mean leg rest length (m): the unit of the gait's stride."""
        return float(self.l_rest.mean())

    @functools.cached_property
    def stride_length(self) -> NDArray[np.float64]:
        """Fore-aft travel of each planted foot relative to its hip (m), shape (L,).

        One length for all feet (the gait's stride times the mean rest length) so that
        every planted foot moves at the same ground speed.
        """
        return _frozen(np.full(self.leg_count, self.gait.stride * self.leg_scale))

    @functools.cached_property
    def step_height(self) -> NDArray[np.float64]:
        """Swing height of each foot (m), shape (L,): step height times the leg's L_rest."""
        return _frozen(self.gait.step_height * self.l_rest)

    @property
    def ground_speed(self) -> float:
        """Travel speed (m/s): the planted feet's speed relative to the body."""
        return float(ground_speed(self.gait.stride * self.leg_scale, self.gait.duty_factor, self.gait.frequency))

    @functools.cached_property
    def sideways_reach(self) -> NDArray[np.float64]:
        """How far (m) each foot's rest spot lies out from its hip, (L,): the abducted rest
        length, brought in where a stride from there would need more than the leg can
        reach even with the body crouched (a sprawled leg at full stretch)."""
        reach = self.l_rest * np.sin(self.abduction)
        half = 0.5 * self.stride_length
        low = MIN_CROUCH * self.l_rest * np.cos(self.abduction)
        lean = np.abs(np.sin(self.splay))
        # The farthest a planted foot gets, horizontally: r^2 + half^2 + 2 r half |sin splay|.
        limit = (SPRAWL_MARGIN * self.l_max) ** 2 - low ** 2 - half ** 2
        room = -half * lean + np.sqrt(np.maximum((half * lean) ** 2 + limit, 0.0))
        return _frozen(np.clip(np.minimum(reach, room), 0.0, None))

    def stance_extent(self, half_stride: NDArray[np.float64]) -> NDArray[np.float64]:
        """The farthest (m) a planted foot gets from its hip horizontally, for planted feet
        travelling ``half_stride`` (..., L) m either side of their rest spot."""
        reach = self.sideways_reach
        return np.sqrt(reach ** 2 + half_stride ** 2 + 2.0 * reach * half_stride * np.abs(np.sin(self.splay)))

    @functools.cached_property
    def four_legged_mammal(self) -> bool:
        """Four or more upright-kneed legs under a horizontal trunk: a mammal's deep neck,
        its tail set high on the croup, a mane's hair on its tail."""
        return self.leg_count >= 4 and not bool(self.knee_out.any()) and not self.body.upright

    @property
    def stance_back(self) -> float:
        """:func:`stance_back` at the gait's duty factor."""
        return float(stance_back(self.gait.duty_factor))

    @functools.cached_property
    def neutral_feet(self) -> NDArray[np.float64]:
        """Each foot's rest position relative to its girdle's centre on the ground, in the
        body frame (x left, z forward), shape (L, 2): the hip's lateral offset plus the
        leg's abducted reach, turned forward or back by its splay (and a rolling
        plantigrade foot's flat metatarsus ahead)."""
        reach = self.sideways_reach
        lateral = self.hip_side * (self.hip_offset + reach * np.cos(self.splay))
        # A rolling plantigrade foot stands with its ankle a little behind the hip at
        # mid-stance, the ball ahead: it strikes with its heel about a third of a stride
        # ahead of the hip and pushes off well behind it, as walkers do.
        ahead = np.where((self.roll_amount > 0) & (self.heel_length > 0),
                         self.metatarsus * np.cos(self.ankle_lift) - self.stance_back * 0.5 * self.stride_length, 0.0)
        return _frozen(np.stack([lateral, reach * np.sin(self.splay) + ahead], axis=-1))

    def with_gait(self, gait: GaitParams) -> Rig:
        return replace(self, gait=gait)
