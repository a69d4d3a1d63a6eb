"""The gait library: named footfall patterns with the numbers real animals use.

Phases are fractions of a cycle at which each foot touches down, with the rearmost left
foot at 0 (Hildebrand's convention: the left hind foot of a tetrapod; see
``../shared/reference/README.md``). Symmetrical gaits are given by two offsets,
``front_back`` (how far a foot lags the foot behind it on its side) and ``left_right``
(how far the right side lags the left); pair i counted from the rear touches down at
``i * front_back`` (left) and ``i * front_back + left_right`` (right), which works for any
number of leg pairs. Asymmetrical gaits (canter, gallops, half-bound) give an explicit
phase per foot and are defined for four-legged creatures.

Each preset says how many leg pairs it fits (:attr:`GaitPreset.pairs`): the eleven
tetrapod gaits two (walk, bound and pronk also one: a biped's walk, and its hop with both
feet), the biped run one, the hexapod tripod and tetrapod three, the metachronal wave
three or more.

``flex`` (degrees, either way) is how far the spine flexes and extends with the hind legs'
stance and swing, and ``pitch`` (degrees, over a cycle) how far the trunk pitches through
the flights, in the bounding gaits (gallops, bounds); a creature scales both by its build
(largest for small digitigrades, see :func:`app.rigging.trunk_factor`).

``cadence`` is the Froude-scaled stride frequency ``f * sqrt(h / g)`` (h = hip height),
so one preset gives a horse and a cat each their own natural frequency. ``stride`` is
the fore-aft travel of a planted foot relative to its hip, and ``step_height`` the swing
height, both in leg rest lengths.

A leaf module: it imports nothing from Gaitlab.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    import numpy as np

TETRAPOD_FEET: tuple[str, ...] = ("LF", "RF", "LH", "RH")
BIPED_FEET: tuple[str, ...] = ("L", "R")
MAX_PAIRS = 32


def foot_names(pairs: int) -> tuple[str, ...]:
    """Foot names in array order, front pair first and left before right: ``L R`` for one
    pair, ``LF RF LH RH`` for two, ``L1 R1 L2 R2 ...`` (counted from the front) for more."""
    if pairs == 1:
        return BIPED_FEET
    if pairs == 2:
        return TETRAPOD_FEET
    return tuple(f"{side}{i}" for i in range(1, pairs + 1) for side in "LR")


@dataclass(frozen=True)
class GaitPreset:
    """One named gait. Either ``front_back``/``left_right`` or ``phases`` is set;
    ``pairs`` is the (fewest, most) leg pairs it fits."""

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
    pairs: tuple[int, int] = (2, 2)
    biped: str = ""  # what the gait is on two legs, where that differs from the description
    flex: float = 0.0  # degrees the spine flexes and extends either way with the hind legs (bounding gaits)
    pitch: float = 0.0  # degrees the trunk pitches over a cycle, through the stances and flights

    def describe(self, pairs: int) -> str:
        """The description for a body with ``pairs`` leg pairs."""
        return self.biped if pairs == 1 and self.biped else self.description

    @property
    def symmetric(self) -> bool:
        """True when the gait is given by front/back and left/right offsets."""
        return self.phases is None

    def fits(self, pairs: int) -> bool:
        """Whether a creature with ``pairs`` leg pairs can use this gait."""
        return self.pairs[0] <= pairs <= self.pairs[1]

    @property
    def fits_text(self) -> str:
        """"2 pairs", "1-2 pairs", "3+ pairs" for listings and errors."""
        lo, hi = self.pairs
        if lo == hi:
            return f"{lo} pair{'s' if lo > 1 else ''}"
        return f"{lo}+ pairs" if hi >= MAX_PAIRS else f"{lo}-{hi} pairs"


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
                   front_back=0.25, left_right=0.5, pairs=(1, 2),
                   biped="walk: left and right feet half a cycle apart, each down over half the cycle, both down "
                         "at each change of feet (human, bird)"),
        GaitPreset("diagonal-walk", "diagonal-sequence walk: each hind foot is followed by the opposite fore foot (primates)",
                   duty_factor=0.70, cadence=0.33, stride=0.60, step_height=0.12, bob=0.025,
                   front_back=0.70, left_right=0.5, pairs=(2, 2)),
        GaitPreset("amble", "running walk / tölt: walk footfalls at a run's duty factor, always one foot down",
                   duty_factor=0.45, cadence=0.45, stride=0.65, step_height=0.14, bob=0.02,
                   front_back=0.25, left_right=0.5, pairs=(2, 2)),
        GaitPreset("trot", "diagonal pairs move together, a short flight between them",
                   duty_factor=0.40, cadence=0.43, stride=0.90, step_height=0.18, bob=0.035,
                   front_back=0.5, left_right=0.5, pairs=(2, 2)),
        GaitPreset("pace", "lateral pairs move together (camel, giraffe, some dogs)",
                   duty_factor=0.40, cadence=0.50, stride=0.70, step_height=0.16, bob=0.03,
                   front_back=0.0, left_right=0.5, pairs=(2, 2)),
        GaitPreset("run", "biped run: the feet alternate with a flight between steps (human, bird)",
                   duty_factor=0.36, cadence=0.45, stride=0.9, step_height=0.22, bob=0.04,
                   front_back=0.0, left_right=0.5, pairs=(1, 1)),
        GaitPreset("canter", "three-beat: RH, then LH with RF, then the leading LF",
                   duty_factor=0.42, cadence=0.60, stride=0.80, step_height=0.22, bob=0.045,
                   phases=_asymmetric(rh=0.0, lh=0.27, rf=0.27, lf=0.50), flex=3.0, pitch=4.0),
        GaitPreset("gallop", "transverse gallop: RH, LH, RF, LF in quick succession, then flight (horse)",
                   duty_factor=0.26, cadence=0.70, stride=0.90, step_height=0.25, bob=0.05,
                   phases=_asymmetric(rh=0.0, lh=0.12, rf=0.35, lf=0.48), flex=5.0, pitch=6.0),
        GaitPreset("rotary-gallop", "rotary gallop: RH, LH, LF, RF with two flights (cheetah, greyhound)",
                   duty_factor=0.26, cadence=0.75, stride=0.95, step_height=0.25, bob=0.05,
                   phases=_asymmetric(rh=0.0, lh=0.12, rf=0.52, lf=0.40), flex=9.0, pitch=7.0),
        GaitPreset("half-bound", "hind feet together, fore feet one after the other (rabbit, small mammals)",
                   duty_factor=0.40, cadence=0.70, stride=0.85, step_height=0.25, bob=0.05,
                   phases=_asymmetric(rh=0.0, lh=0.0, rf=0.40, lf=0.50), flex=8.0, pitch=7.0),
        GaitPreset("bound", "both hind feet together, then both fore feet half a cycle later",
                   duty_factor=0.40, cadence=0.70, stride=0.85, step_height=0.25, bob=0.05,
                   front_back=0.5, left_right=0.0, pairs=(1, 2), flex=10.0, pitch=8.0),
        GaitPreset("pronk", "all four feet together: a stiff-legged spring (springbok stott)",
                   duty_factor=0.35, cadence=0.60, stride=0.50, step_height=0.22, bob=0.04,
                   front_back=0.0, left_right=0.0, pairs=(1, 2)),
        GaitPreset("tripod", "hexapod tripod: front and rear legs of one side with the middle leg of the other, "
                   "alternating (fast insects)", duty_factor=0.50, cadence=0.45, stride=0.55, step_height=0.18,
                   bob=0.01, front_back=0.5, left_right=0.5, pairs=(3, 3)),
        GaitPreset("tetrapod", "hexapod tetrapod gait: three diagonal pairs in turn, four feet always down "
                   "(slow insects)", duty_factor=0.67, cadence=0.35, stride=0.50, step_height=0.16, bob=0.01,
                   front_back=1 / 3, left_right=2 / 3, pairs=(3, 3)),
        GaitPreset("metachronal", "metachronal wave: steps run from the rear pair to the front, each pair a lag "
                   "behind the one before; the sides half a cycle apart (spiders, centipedes)",
                   duty_factor=0.65, cadence=0.40, stride=0.50, step_height=0.16, bob=0.008, front_back=0.2,
                   left_right=0.5, pairs=(3, MAX_PAIRS)),
    )
}


def gait_names() -> list[str]:
    """Gait preset names in library order (slow to fast, symmetrical first)."""
    return list(GAIT_PRESETS)


def phases_from_offsets(front_back: float, left_right: float, feet: tuple[str, ...]) -> np.ndarray:
    """Touchdown phases of symmetrical gaits in the order of ``feet`` (any number of pairs,
    see :func:`foot_names`), in [0, 1): pair i from the rear at ``i * fb`` (left) and
    ``i * fb + lr`` (right); for a tetrapod ``LH=0, RH=lr, LF=fb, RF=fb+lr``."""
    pairs = len(feet) // 2
    import numpy as np

    from_rear = pairs - 1 - np.arange(len(feet)) // 2
    right = np.arange(len(feet)) % 2
    return np.mod(from_rear * front_back + right * left_right, 1.0)


def preset_phases(name: str, feet: tuple[str, ...]) -> np.ndarray:
    """The touchdown phases of gait preset ``name`` for ``feet``, shape (len(feet),)."""
    preset = GAIT_PRESETS[name]
    if preset.symmetric:
        return phases_from_offsets(float(preset.front_back or 0.0), float(preset.left_right or 0.0), feet)
    assert preset.phases is not None
    import numpy as np

    return np.mod(np.array([preset.phases[f] for f in feet], dtype=np.float64), 1.0)


def gaits_for(pairs: int) -> list[str]:
    """The gait presets a creature with ``pairs`` leg pairs can use, in library order."""
    return [name for name, preset in GAIT_PRESETS.items() if preset.fits(pairs)]
