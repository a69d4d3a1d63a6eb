"""The gait library: named footfall patterns with the numbers real animals use.

Phases are fractions of a cycle at which each foot touches down, with the left hind foot
at 0 (Hildebrand's convention, see ``../shared/reference/README.md``). Symmetrical gaits
are given by two offsets, ``front_back`` (how far a fore foot lags the hind foot on its
side) and ``left_right`` (how far the right side lags the left); they work for any
number of leg pairs. Asymmetrical gaits (canter, gallops, half-bound) give an explicit
phase per foot and are defined for four-legged creatures.

``cadence`` is the Froude-scaled stride frequency ``f * sqrt(h / g)`` (h = hip height),
so one preset gives a horse and a cat each their own natural frequency. ``stride`` is
the fore-aft travel of a planted foot relative to its hip, and ``step_height`` the swing
height, both in leg rest lengths.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Mapping

TETRAPOD_FEET: tuple[str, ...] = ("LF", "RF", "LH", "RH")


@dataclass(frozen=True)
class GaitPreset:
    """One named gait. Either ``front_back``/``left_right`` or ``phases`` is set."""

    name: str
    description: str
    duty_factor: float
    cadence: float
    stride: float
    step_height: float
    bob: float
    front_back: float | None = None
    left_right: float | None = None
    phases: Mapping[str, float] | None = None

    @property
    def symmetric(self) -> bool:
        """True when the gait is given by front/back and left/right offsets."""
        return self.phases is None


def _asymmetric(rh: float, lh: float, rf: float, lf: float) -> dict[str, float]:
    """Phases from the reference table's form (offsets from the trailing right hind foot),
    re-expressed with the left hind foot at 0."""
    return {name: round((value - lh) % 1.0, 6) for name, value in
            (("LF", lf), ("RF", rf), ("LH", lh), ("RH", rh))}


GAIT_PRESETS: dict[str, GaitPreset] = {
    preset.name: preset
    for preset in (
        GaitPreset("walk", "lateral-sequence walk: LH, LF, RH, RF a quarter cycle apart (dog, horse)",
                   duty_factor=0.70, cadence=0.33, stride=0.65, step_height=0.12, bob=0.025,
                   front_back=0.25, left_right=0.5),
        GaitPreset("diagonal-walk", "diagonal-sequence walk: each hind foot is followed by the opposite fore foot (primates)",
                   duty_factor=0.70, cadence=0.33, stride=0.60, step_height=0.12, bob=0.025,
                   front_back=0.70, left_right=0.5),
        GaitPreset("amble", "running walk / tölt: walk footfalls at a run's duty factor, always one foot down",
                   duty_factor=0.45, cadence=0.45, stride=0.65, step_height=0.14, bob=0.02,
                   front_back=0.25, left_right=0.5),
        GaitPreset("trot", "diagonal pairs move together, a short flight between them",
                   duty_factor=0.40, cadence=0.55, stride=0.70, step_height=0.18, bob=0.035,
                   front_back=0.5, left_right=0.5),
        GaitPreset("pace", "lateral pairs move together (camel, giraffe, some dogs)",
                   duty_factor=0.40, cadence=0.50, stride=0.70, step_height=0.16, bob=0.03,
                   front_back=0.0, left_right=0.5),
        GaitPreset("canter", "three-beat: RH, then LH with RF, then the leading LF",
                   duty_factor=0.42, cadence=0.60, stride=0.80, step_height=0.22, bob=0.045,
                   phases=_asymmetric(rh=0.0, lh=0.27, rf=0.27, lf=0.50)),
        GaitPreset("gallop", "transverse gallop: RH, LH, RF, LF in quick succession, then flight (horse)",
                   duty_factor=0.26, cadence=0.70, stride=0.90, step_height=0.25, bob=0.05,
                   phases=_asymmetric(rh=0.0, lh=0.12, rf=0.35, lf=0.48)),
        GaitPreset("rotary-gallop", "rotary gallop: RH, LH, LF, RF with two flights (cheetah, greyhound)",
                   duty_factor=0.26, cadence=0.75, stride=0.95, step_height=0.25, bob=0.05,
                   phases=_asymmetric(rh=0.0, lh=0.12, rf=0.52, lf=0.40)),
        GaitPreset("half-bound", "hind feet together, fore feet one after the other (rabbit, small mammals)",
                   duty_factor=0.40, cadence=0.70, stride=0.85, step_height=0.25, bob=0.05,
                   phases=_asymmetric(rh=0.0, lh=0.0, rf=0.40, lf=0.50)),
        GaitPreset("bound", "both hind feet together, then both fore feet half a cycle later",
                   duty_factor=0.40, cadence=0.70, stride=0.85, step_height=0.25, bob=0.05,
                   front_back=0.5, left_right=0.0),
        GaitPreset("pronk", "all four feet together: a stiff-legged spring (springbok stott)",
                   duty_factor=0.35, cadence=0.60, stride=0.50, step_height=0.22, bob=0.04,
                   front_back=0.0, left_right=0.0),
    )
}


def gait_names() -> list[str]:
    """Gait preset names in library order (slow to fast, symmetrical first)."""
    return list(GAIT_PRESETS)
