"""The rig: a creature's spec turned into numpy arrays, one entry per leg.

Legs are ordered as the feet ``LF, RF, LH, RH`` (fore pair first). Everything that does
not change from frame to frame is derived here once: SI units, radians, the leg's
maximum / rest / minimum hip-to-ball lengths, which way its knee points, where its hip
sits on the body, and the resolved gait.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from ..spec import CreatureSpec, LegSpec
from .gait import GaitParams, resolve_gait

G = 9.81  # m/s^2


def leg_lengths(femur: NDArray, tibia: NDArray, metatarsus: NDArray, ankle_lift: NDArray,
                natural_bend: NDArray) -> tuple[NDArray, NDArray, NDArray]:
    """Maximum, rest and minimum hip-to-ball distance of legs (all arrays (L,), metres).

    ``L_max = sqrt((f+t)^2 - (m cos A)^2) + m sin A`` (ball straight below the hip at the
    rest ankle lift), ``L_rest = L_max * clamp(1 - bend, 0.2, 1)``, and ``L_min`` is the
    largest of ``0.2 L_max``, the distance below which the knee cannot fold
    (``|f - t| - m``) and, for a metatarsus longer than femur and tibia together, the
    distance below which the ankle cannot reach (``m - f - t``), with a small margin.
    """
    reach = femur + tibia
    flat = metatarsus * np.cos(ankle_lift)
    l_max = np.sqrt(np.maximum(reach ** 2 - flat ** 2, 0.0)) + metatarsus * np.sin(ankle_lift)
    l_rest = l_max * np.clip(1.0 - natural_bend, 0.2, 1.0)
    l_min = np.maximum.reduce([0.2 * l_max, np.abs(femur - tibia) - metatarsus, metatarsus - reach]) * 1.001
    return l_max, l_rest, l_min


@dataclass(frozen=True)
class Rig:
    """Per-leg arrays (shape (L,) unless noted) and the few per-creature scalars.

    Lengths in metres, angles in radians. ``hip_side`` is +1 for left legs (+X) and -1
    for right legs; ``pair_index`` is 0 for fore legs and 1 for hind legs.
    """

    spec: CreatureSpec
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
    bone_radius: NDArray[np.float64]
    hip_side: NDArray[np.float64]
    pair_index: NDArray[np.int64]
    pair_position: NDArray[np.float64]  # (2,) fore, hind: fraction along the spine
    pair_rest_height: NDArray[np.float64]  # (2,) hip height of each pair at rest
    half_width: float
    body_length: float
    gait: GaitParams

    @property
    def leg_count(self) -> int:
        return len(self.leg_names)

    @property
    def hip_height(self) -> float:
        """Mean rest hip height over the pairs (m): the ``h`` of the Froude number."""
        return float(self.pair_rest_height.mean())

    @property
    def stride_length(self) -> NDArray[np.float64]:
        """Fore-aft travel of each planted foot relative to its hip (m), shape (L,).

        One length for all feet (the gait's stride times the mean rest length) so that
        every planted foot moves at the same ground speed.
        """
        return np.full(self.leg_count, self.gait.stride * float(self.l_rest.mean()))

    @property
    def step_height(self) -> NDArray[np.float64]:
        """Swing height of each foot (m), shape (L,): step height times the leg's L_rest."""
        return self.gait.step_height * self.l_rest

    @property
    def ground_speed(self) -> float:
        """Speed of the ground under the planted feet (m/s): stride * frequency / duty."""
        return float(self.stride_length[0] * self.gait.frequency / self.gait.duty_factor)


def _per_leg(fore: LegSpec, hind: LegSpec, attr: str) -> NDArray[np.float64]:
    f, h = float(getattr(fore, attr)), float(getattr(hind, attr))
    return np.array([f, f, h, h])


def build_rig(spec: CreatureSpec) -> Rig:
    """Derive the rig of a (validated) creature spec."""
    fore, hind = spec.leg("fore"), spec.leg("hind")
    femur = _per_leg(fore, hind, "femur")
    tibia = _per_leg(fore, hind, "tibia")
    meta = _per_leg(fore, hind, "metatarsus")
    lift = np.radians(_per_leg(fore, hind, "ankle_lift"))
    bend = _per_leg(fore, hind, "natural_bend")
    l_max, l_rest, l_min = leg_lengths(femur, tibia, meta, lift, bend)
    knee = np.array([1.0 if leg.knee == "forward" else -1.0 for leg in (fore, fore, hind, hind)])
    rest_height = np.array([l_rest[0], l_rest[2]])
    return Rig(
        spec=spec,
        leg_names=spec.foot_names,
        femur=femur,
        tibia=tibia,
        metatarsus=meta,
        toe=_per_leg(fore, hind, "toe"),
        ankle_lift=lift,
        l_max=l_max,
        l_rest=l_rest,
        l_min=l_min,
        knee_sign=knee,
        bone_radius=_per_leg(fore, hind, "radius"),
        hip_side=np.array([1.0, -1.0, 1.0, -1.0]),
        pair_index=np.array([0, 0, 1, 1]),
        pair_position=np.array([fore.position, hind.position]),
        pair_rest_height=rest_height,
        half_width=0.5 * spec.body.width,
        body_length=spec.body.length,
        gait=resolve_gait(spec.gait, spec.foot_names, float(rest_height.mean()), bob=spec.motion.bob),
    )
