"""The creature as data: frozen dataclasses holding a creature file's own values
(lengths in metres, angles in degrees, phases in cycles), and their TOML form.

Build one with :func:`app.spec.load_creature` or :func:`app.spec.creature_from_dict`;
change one with :meth:`CreatureSpec.with_overrides`. Kinematic quantities derived from
them live in :mod:`app.kinematics.rig`.
"""

from __future__ import annotations

import os
from collections.abc import Mapping
from dataclasses import dataclass, field, fields
from pathlib import Path
from typing import TYPE_CHECKING, Any

from ..choices import KneeDirection, Posture, WaveShape
from ..gaits import GAIT_PRESETS, foot_names
from ..kinematics.rig import Look, Overlap

if TYPE_CHECKING:
    from ..gaits import GaitPreset



@dataclass(frozen=True)
class BodySpec:
    """The trunk, neck, head and tail. Lengths in metres, angles in degrees."""

    length: float
    width: float
    radius: tuple[float, ...]
    segments: int = 8
    neck_length: float = 0.0
    neck_angle: float = 30.0
    head_length: float = 0.2
    head_radius: float = 0.06
    head_angle: float = 20.0
    ear_length: float = 0.0
    tail_length: float = 0.0
    tail_angle: float = 30.0
    tail_segments: int = 6
    tail_radius: float | None = None
    tail_curl: float = 0.0
    mane: float = 0.0
    wings: float = 0.0
    beak: float = 0.0
    hump: float = 0.0
    posture: Posture = "horizontal"


@dataclass(frozen=True)
class LegSpec:
    """One left/right pair of legs (or ``count`` identical pairs spread over ``span``):
    four bones, ankle lift (degrees), natural bend, and where the hips sit."""

    name: str
    femur: float
    tibia: float
    metatarsus: float
    toe: float
    ankle_lift: float
    knee: KneeDirection
    position: float
    natural_bend: float = 0.1
    radius: float = 0.03
    count: int = 1
    span: tuple[float, ...] | None = None
    hip_offset: float | None = None
    abduction: float = 0.0
    splay: float = 0.0
    roll: float = 0.0
    heel: float = 0.0
    toes: int = 0

    @property
    def positions(self) -> tuple[float, ...]:
        """Trunk position of each pair of this kind, rear to front."""
        if self.count == 1:
            return (self.position,)
        lo, hi = self.span if self.span is not None else (0.0, 1.0)
        return tuple(lo + (hi - lo) * i / (self.count - 1) for i in range(self.count))


@dataclass(frozen=True)
class GaitSpec:
    """A gait preset and the keys that adjust it; ``None`` means "from the preset"."""

    preset: str = "walk"
    frequency: float | None = None
    duty_factor: float | None = None
    bias: float | None = None
    front_back: float | None = None
    left_right: float | None = None
    phases: tuple[tuple[str, float], ...] | None = None
    step_height: float | None = None
    stride: float | None = None
    wave: WaveShape = "planted"
    frames_per_cycle: float | None = None
    timing_fps: float | None = None

    @property
    def preset_spec(self) -> GaitPreset:
        """The :class:`app.gaits.GaitPreset` this gait adjusts."""
        return GAIT_PRESETS[self.preset]


@dataclass(frozen=True)
class MotionSpec:
    """Secondary body motion. ``bob=None`` takes the gait preset's bob."""

    bob: float | None = None
    bob_phase: float = 0.0
    yaw: float = 4.0
    tail_sway: float = 8.0
    pelvis_tilt: float = 0.0
    sway: float = 0.0
    spine_flex: float = 1.0


@dataclass(frozen=True)
class SpeedSpec:
    """How speed picks the gait (``--speed``): Froude thresholds (walk -> trot at 0.5 and
    trot -> gallop at 2.5 by default, Alexander 1976) and their hysteresis."""

    walk_trot: float = 0.5
    trot_gallop: float = 2.5
    hysteresis: float = 0.15
    gallop: str = "gallop"


# The look and the follow-through delays mean the same in the file and to the solver: one
# declaration each (in the rig), used here as they are.
LookSpec = Look
OverlapSpec = Overlap


@dataclass(frozen=True)
class ArmsSpec:
    """Two arms at the shoulders: bones in metres, the elbow's rest bend in degrees."""

    upper: float
    fore: float
    hand: float
    radius: float = 0.03
    shoulder_width: float | None = None
    position: float = 1.0
    elbow: float = 20.0


@dataclass(frozen=True)
class PosesSpec:
    """The key poses of a step (``None``: from the style, or for heights: the gait's own
    body bob when no height and no style is given). Heights in metres, angles in degrees."""

    style: str | None = None
    contact_height: float | None = None
    down_height: float | None = None
    pass_height: float | None = None
    up_height: float | None = None
    foot_angle: float | None = None
    arm_swing: float | None = None
    torso_lean: float | None = None
    swing_knee: float | None = None

    @property
    def shaped(self) -> bool:
        """Whether the key poses set the body's height (a style or any height is given)."""
        return self.style is not None or any(
            v is not None for v in (self.contact_height, self.down_height, self.pass_height, self.up_height))


@dataclass(frozen=True)
class CreatureSpec:
    """A whole creature, as in its TOML file. Frozen: use :meth:`with_overrides`."""

    name: str
    body: BodySpec
    legs: tuple[LegSpec, ...]
    gait: GaitSpec = GaitSpec()
    motion: MotionSpec = MotionSpec()
    speed: SpeedSpec = SpeedSpec()
    look: LookSpec = field(default_factory=LookSpec)
    arms: ArmsSpec | None = None
    poses: PosesSpec = PosesSpec()
    overlap: OverlapSpec = field(default_factory=OverlapSpec)
    description: str = ""
    source: str = field(default="", compare=False)

    # -- access ---------------------------------------------------------------------

    def leg(self, name: str) -> LegSpec:
        """The leg table called ``name`` (e.g. ``fore`` or ``hind``)."""
        for leg in self.legs:
            if leg.name == name:
                return leg
        raise KeyError(name)

    @property
    def girdles(self) -> tuple[tuple[LegSpec, float], ...]:
        """Every leg pair as (its leg table, its trunk position), front pair first."""
        pairs = [(leg, p) for leg in self.legs for p in leg.positions]
        return tuple(sorted(pairs, key=lambda lp: -lp[1]))

    @property
    def pair_count(self) -> int:
        return sum(leg.count for leg in self.legs)

    @property
    def foot_names(self) -> tuple[str, ...]:
        """Foot names in array order, front pair first: ``LF RF LH RH`` for two pairs, ``L R``
        for one, ``L1 R1 L2 R2 ...`` for more."""
        return foot_names(self.pair_count)

    # -- conversion -----------------------------------------------------------------

    def to_dict(self) -> dict[str, Any]:
        """The TOML document for this creature (keys with ``None`` values left out)."""
        doc: dict[str, Any] = {"name": self.name}
        if self.description:
            doc["description"] = self.description
        doc["body"] = _table(self.body)
        doc["legs"] = {leg.name: _leg_table(leg) for leg in self.legs}
        gait = _table(self.gait)
        if self.gait.phases is not None:
            gait["phases"] = dict(self.gait.phases)
        doc["gait"] = gait
        doc["motion"] = _table(self.motion)
        doc["speed"] = _table(self.speed)
        doc["look"] = _table(self.look)
        if self.arms is not None:
            doc["arms"] = _table(self.arms)
        for name in ("poses", "overlap"):
            table = {k: v for k, v in _table(getattr(self, name)).items() if v != 0.0 or name == "poses"}
            if table:
                doc[name] = table
        return doc

    def with_overrides(self, overrides: Mapping[str, Any], origin: str = "--set") -> CreatureSpec:
        """A copy with dotted keys replaced, e.g. ``{"gait.duty_factor": 0.7}``.

        Setting ``gait.preset`` resets the other gait keys to the new preset's values,
        except those set in the same call. The result is validated as a whole; errors
        start with ``origin`` (where the values came from; "" for none).
        """
        from .overrides import apply_overrides

        return apply_overrides(self, overrides, origin)

    def save(self, path: str | os.PathLike[str]) -> Path:
        """Write the creature as TOML, atomically (temporary file, then rename)."""
        import tomli_w

        from ..output.files import atomic_write_text

        text = "# Gaitlab creature (saved)\n" + tomli_w.dumps(self.to_dict())
        return atomic_write_text(Path(path), text)


_LEG_DEFAULTS = {"count": 1, "abduction": 0.0, "splay": 0.0, "roll": 0.0, "heel": 0.0, "toes": 0}  # left out of saved files


def _leg_table(leg: LegSpec) -> dict[str, Any]:
    table = {k: v for k, v in _table(leg, skip=("name",)).items() if _LEG_DEFAULTS.get(k) != v}
    if leg.count > 1:
        table.pop("position", None)  # repeated pairs are placed by their span
    return table


def _table(obj: Any, skip: tuple[str, ...] = ()) -> dict[str, Any]:
    out: dict[str, Any] = {}
    for f in fields(obj):
        if f.name in skip or f.name == "phases":
            continue
        value = getattr(obj, f.name)
        if value is None:
            continue
        out[f.name] = list(value) if isinstance(value, tuple) else value
    return out
