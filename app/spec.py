"""Creature files: load, validate, override, save.

A creature is a TOML file (see ``creatures/dog.toml`` for an annotated example) with the
tables ``[body]``, ``[legs.fore]``, ``[legs.hind]``, ``[gait]``, ``[motion]`` and ``[look]``.
Lengths are metres, angles degrees, phases fractions of a cycle, step height and stride
leg rest lengths. Every key is described once, in :data:`SCHEMA`; loading, overriding
and the error messages all come from that table, so a wrong file always gets one line
that names the file, the dotted key, the value and what is allowed.

The spec classes are frozen dataclasses holding the file's own values (degrees stay
degrees). Kinematic quantities derived from them live in :mod:`app.kinematics.rig`.
"""

from __future__ import annotations

import math
import os
import re
from dataclasses import dataclass, field, fields
from pathlib import Path
from typing import Any, Mapping

import tomli_w

from .choices import (KNEE_DIRECTIONS, POSTURES, WAVE_SHAPES, KneeDirection, LegType, Posture,  # noqa: F401
                      WaveShape, leg_type)
from .styles import DEFAULT_TIMING_FPS, WALK_STYLES
from .errors import SpecError, did_you_mean
from .output import atomic_write_text
from .tomlfile import TomlProblem, parse_toml, read_toml
from .gaits import GAIT_PRESETS, MAX_PAIRS, foot_names, gaits_for, phases_from_offsets, preset_phases
from .resources import creatures_dir, preset_creature_names

TETRAPOD_PAIRS: tuple[str, ...] = ("fore", "hind")  # the classic two-girdle form: [legs.fore], [legs.hind]
DUTY_RANGE = (0.05, 0.95)
BIAS_LIMIT = 50.0  # |b| <= 50 covers duty factors up to ~0.947


# --------------------------------------------------------------------------------------
# The schema: what each key means and which values it accepts
# --------------------------------------------------------------------------------------


@dataclass(frozen=True)
class Rule:
    """What one key accepts. ``kind`` is number, integer, text, choice, color, numbers."""

    kind: str
    lo: float | None = None
    hi: float | None = None
    lo_open: bool = False
    hi_open: bool = False
    choices: tuple[str, ...] = ()
    unit: str = ""
    doc: str = ""

    def allowed(self) -> str:
        """A short phrase for error messages: what values are allowed."""
        if self.kind == "choice":
            return "one of " + ", ".join(self.choices)
        if self.kind == "color":
            return 'a colour like "#a07850"'
        if self.kind == "text":
            return "a string"
        what = {"number": "a number", "integer": "a whole number", "numbers": "a list of numbers"}[self.kind]
        if self.kind == "numbers":
            what += " each"
        lo = None if self.lo is None else f"{'>' if self.lo_open else '>='} {self.lo:g}"
        hi = None if self.hi is None else f"{'<' if self.hi_open else '<='} {self.hi:g}"
        bounds = " and ".join(b for b in (lo, hi) if b)
        if self.lo is not None and self.hi is not None:
            left = "(" if self.lo_open else "["
            right = ")" if self.hi_open else "]"
            bounds = f"in {left}{self.lo:g}, {self.hi:g}{right}"
        return f"{what} {bounds}".strip() + (f" ({self.unit})" if self.unit else "")


def _num(lo=None, hi=None, *, lo_open=False, hi_open=False, unit="", doc="") -> Rule:
    return Rule("number", lo, hi, lo_open, hi_open, unit=unit, doc=doc)


def _length(doc: str, *, zero_ok: bool = False, hi: float = 50.0) -> Rule:
    return _num(0.0, hi, lo_open=not zero_ok, unit="m", doc=doc)


BODY_RULES: dict[str, Rule] = {
    "length": _length("distance from the hind hips to the fore shoulders along the spine"),
    "width": _length("distance between the left and right hips (and shoulders)"),
    "segments": Rule("integer", 2, 64, doc="number of body segments drawn along the spine"),
    "radius": Rule("numbers", 0.0, 10.0, lo_open=True, unit="m",
                   doc="body radius profile from rump to chest, interpolated along the spine"),
    "neck_length": _length("neck length (0 for none)", zero_ok=True),
    "neck_angle": _num(-90, 90, unit="deg", doc="neck elevation above the body axis"),
    "head_length": _length("head length, back of the skull to the nose"),
    "head_radius": _length("head radius"),
    "head_angle": _num(-90, 90, unit="deg", doc="head pitch below the body axis"),
    "ear_length": _length("ear length (0 for none)", zero_ok=True),
    "tail_length": _length("tail length (0 for none)", zero_ok=True),
    "tail_angle": _num(-90, 90, unit="deg", doc="tail droop below the body axis"),
    "tail_segments": Rule("integer", 1, 32, doc="number of tail segments"),
    "posture": Rule("choice", choices=POSTURES, doc="horizontal: the trunk runs from the hind to the fore legs; "
                    "upright: it rises from the hips (a human; one leg pair)"),
}

LEG_RULES: dict[str, Rule] = {
    "position": _num(-0.25, 1.25, doc="where the pair attaches along the trunk: 0 rear end, 1 front end "
                     "(default: fore 1, hind 0)"),
    "count": Rule("integer", 1, MAX_PAIRS, doc="how many pairs of this leg, spread evenly over span"),
    "span": Rule("numbers", -0.25, 1.25, doc="with count > 1: positions of the rearmost and the frontmost pair"),
    "hip_offset": _length("sideways distance of each hip from the spine (default: half the body width)",
                          zero_ok=True, hi=10.0),
    "abduction": _num(0, 80, unit="deg", doc="the leg's rest direction turned out from vertical (0 upright mammal "
                      "legs; 40-60 sprawled insect and spider legs)"),
    "splay": _num(-80, 80, unit="deg", doc="the foot's rest position turned forward (+) or back (-) about the hip"),
    "femur": _length("upper leg (femur / humerus)"),
    "tibia": _length("lower leg (tibia / radius)"),
    "metatarsus": _length("foot bone between ankle and ball (metatarsus / metacarpus)"),
    "toe": _length("toe length, 0 for hooves", zero_ok=True),
    "ankle_lift": _num(0, 90, unit="deg",
                       doc="metatarsus angle to the ground at rest: ~0 plantigrade, mid digitigrade, ~90 unguligrade"),
    "natural_bend": _num(0, 0.6, doc="rest length as a fraction below full extension: L_rest = L_max (1 - bend)"),
    "knee": Rule("choice", choices=KNEE_DIRECTIONS,
                  doc="which way the middle joint points: forward (knee), back (elbow), out (up and away from "
                      "the body: insects, spiders)"),
    "radius": _length("bone radius at the hip; bones taper towards the foot", hi=2.0),
    "roll": _num(0, 1, doc="foot roll: heel strike, roll to flat, heel rise, toe-off; scales its angles and "
                 "timing (0 lands and lifts the foot flat)"),
}

ARMS_RULES: dict[str, Rule] = {
    "upper": _length("upper arm, shoulder to elbow"),
    "fore": _length("forearm, elbow to wrist"),
    "hand": _length("hand, wrist to finger tips"),
    "radius": _length("bone radius at the shoulder", hi=2.0),
    "shoulder_width": _length("distance between the shoulders"),
    "position": _num(0, 1.25, doc="where the shoulders sit along the trunk: 0 the hips' end, 1 the front (top) end"),
    "elbow": _num(0, 150, unit="deg", doc="elbow bend at rest; it bends more as the arm swings forward"),
}

POSES_RULES: dict[str, Rule] = {
    "style": Rule("choice", choices=WALK_STYLES, doc="the walk style the key poses started from"),
    "contact_height": _num(-1, 1, unit="m", doc="body height at contact (heel strike), above (+) or below "
                           "rest height (reach caps it)"),
    "down_height": _num(-1, 1, unit="m", doc="body height at the down pose (a quarter step after contact)"),
    "pass_height": _num(-1, 1, unit="m", doc="body height at the passing pose (half a step after contact)"),
    "up_height": _num(-1, 1, unit="m", doc="body height at the up pose (three quarters of a step)"),
    "foot_angle": _num(-30, 60, unit="deg", doc="the foot's angle at contact, toes up (with legs.NAME.roll)"),
    "arm_swing": _num(0, 80, unit="deg", doc="how far the arms swing forward and back"),
    "torso_lean": _num(-30, 45, unit="deg", doc="the trunk's lean forward (+) or back (-) (upright bodies)"),
}

OVERLAP_RULES: dict[str, Rule] = {
    part: _num(0, 0.5, doc=f"how far (cycle fraction) the {what} follows through behind the body")
    for part, what in (("head", "head"), ("neck", "neck"), ("arms", "arms' swing"), ("tail", "tail"),
                       ("ears", "ears"))
}

GAIT_RULES: dict[str, Rule] = {
    "preset": Rule("choice", choices=tuple(GAIT_PRESETS), doc="gait preset the other keys adjust"),
    "frequency": _num(0.0, 20.0, lo_open=True, unit="Hz", doc="stride frequency (default: from the preset and hip height)"),
    "duty_factor": _num(*DUTY_RANGE, lo_open=True, hi_open=True, doc="fraction of the cycle each foot is planted"),
    "bias": _num(-BIAS_LIMIT, BIAS_LIMIT, doc="the seed's swing/stance bias b; duty = 1/2 + asin(ln(cosh b)/b)/pi"),
    "front_back": _num(-1, 1, doc="how far (cycle fraction) a foot lags the one behind it on its side"),
    "left_right": _num(-1, 1, doc="how far (cycle fraction) the right side lags the left"),
    "phases": _num(-1, 1, doc="explicit touchdown phase per foot (e.g. LF RF LH RH), rearmost left foot = 0"),
    "step_height": _num(0, 1, unit="leg rest lengths", doc="how high a foot lifts in swing"),
    "stride": _num(0, 2, unit="leg rest lengths", doc="fore-aft travel of a planted foot relative to its hip"),
    "wave": Rule("choice", choices=WAVE_SHAPES,
                 doc="planted: linear stance, exact duty; skewed-sine: the seed's two skewed waves"),
    "frames_per_cycle": _num(0, 10000, lo_open=True, unit="frames",
                             doc="timing as an animator gives it: frames per cycle (two steps) at timing_fps, "
                                 "instead of frequency"),
    "timing_fps": _num(1, 240, unit="fps", doc="the frame rate frames_per_cycle counts in (default 24)"),
}

MOTION_RULES: dict[str, Rule] = {
    "bob": _num(0, 0.2, unit="leg rest lengths", doc="body bob amplitude (default: the gait preset's)"),
    "bob_phase": _num(-1, 1, doc="bob timing relative to the feet, cycle fraction"),
    "yaw": _num(0, 30, unit="deg", doc="how far the hips and shoulders turn with the feet"),
    "tail_sway": _num(0, 60, unit="deg", doc="side-to-side tail swing"),
    "pelvis_tilt": _num(0, 20, unit="deg", doc="how far the hips drop on the side of the swinging leg"),
    "spine_flex": _num(0, 3, doc="scales how far the spine flexes and the trunk pitches in bounds and gallops "
                       "(1: as the gait and the creature's build give; 0: a stiff back)"),
}

SPEED_RULES: dict[str, Rule] = {
    "walk_trot": _num(0.05, 5.0, doc="Froude number v^2/(g h) at which a speed-driven walk becomes a trot"),
    "trot_gallop": _num(0.1, 20.0, doc="Froude number at which a speed-driven trot becomes a gallop"),
    "hysteresis": _num(0.0, 0.5, doc="fraction above (below) a threshold at which the gait changes up (down)"),
    "gallop": Rule("choice", choices=("gallop", "rotary-gallop"), doc="which gallop fast speeds use"),
}

LOOK_RULES: dict[str, Rule] = {
    "body_color": Rule("color", doc="body, neck, head and tail colour"),
    "left_color": Rule("color", doc="colour of the left legs"),
    "right_color": Rule("color", doc="colour of the right legs"),
}

TOP_RULES: dict[str, Rule] = {
    "name": Rule("text", doc="creature name"),
    "description": Rule("text", doc="one line describing the creature"),
}

TABLES: dict[str, dict[str, Rule]] = {
    "body": BODY_RULES,
    "gait": GAIT_RULES,
    "motion": MOTION_RULES,
    "speed": SPEED_RULES,
    "look": LOOK_RULES,
    "arms": ARMS_RULES,
    "poses": POSES_RULES,
    "overlap": OVERLAP_RULES,
}
_COLOR_RE = re.compile(r"^#[0-9a-fA-F]{6}$")
_FOOT_RE = re.compile(r"^[LR]([FH]|[0-9]{1,2})?$")


# --------------------------------------------------------------------------------------
# The spec classes
# --------------------------------------------------------------------------------------


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
    def preset_spec(self):
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
    spine_flex: float = 1.0


@dataclass(frozen=True)
class SpeedSpec:
    """How speed picks the gait (``--speed``): Froude thresholds (walk -> trot at 0.5 and
    trot -> gallop at 2.5 by default, Alexander 1976) and their hysteresis."""

    walk_trot: float = 0.5
    trot_gallop: float = 2.5
    hysteresis: float = 0.15
    gallop: str = "gallop"


@dataclass(frozen=True)
class LookSpec:
    """Colours, as ``#rrggbb`` strings."""

    body_color: str = "#b59a7a"
    left_color: str = "#2f8f9d"
    right_color: str = "#d8664f"


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

    @property
    def shaped(self) -> bool:
        """Whether the key poses set the body's height (a style or any height is given)."""
        return self.style is not None or any(
            v is not None for v in (self.contact_height, self.down_height, self.pass_height, self.up_height))


@dataclass(frozen=True)
class OverlapSpec:
    """Follow-through delays (cycle fractions) of body parts behind the body's motion."""

    head: float = 0.0
    neck: float = 0.0
    arms: float = 0.0
    tail: float = 0.0
    ears: float = 0.0


@dataclass(frozen=True)
class CreatureSpec:
    """A whole creature, as in its TOML file. Frozen: use :meth:`with_overrides`."""

    name: str
    body: BodySpec
    legs: tuple[LegSpec, ...]
    gait: GaitSpec = GaitSpec()
    motion: MotionSpec = MotionSpec()
    speed: SpeedSpec = SpeedSpec()
    look: LookSpec = LookSpec()
    arms: ArmsSpec | None = None
    poses: PosesSpec = PosesSpec()
    overlap: OverlapSpec = OverlapSpec()
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

    def with_overrides(self, overrides: Mapping[str, Any], origin: str = "--set") -> "CreatureSpec":
        """A copy with dotted keys replaced, e.g. ``{"gait.duty_factor": 0.7}``.

        Setting ``gait.preset`` resets the other gait keys to the new preset's values,
        except those set in the same call. The result is validated as a whole; errors
        start with ``origin`` (where the values came from; "" for none).
        """
        data = self.to_dict()
        items = sorted(overrides.items(), key=lambda kv: kv[0] != "gait.preset")
        for key, value in items:
            _apply_override(data, key, value, self, origin)
        return creature_from_dict(data, source=self.source or f"<{self.name}>", origin=origin)

    def save(self, path: str | os.PathLike[str]) -> Path:
        """Write the creature as TOML, atomically (temporary file, then rename)."""
        path = Path(path)
        text = "# Gaitlab creature (saved)\n" + tomli_w.dumps(self.to_dict())
        return atomic_write_text(path, text)


_LEG_DEFAULTS = {"count": 1, "abduction": 0.0, "splay": 0.0, "roll": 0.0}  # left out of saved files


def _leg_table(leg: LegSpec) -> dict[str, Any]:
    table = {k: v for k, v in _table(leg, skip=("name",)).items() if _LEG_DEFAULTS.get(k, None) != v}
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


# --------------------------------------------------------------------------------------
# Loading and validation
# --------------------------------------------------------------------------------------


def load_creature(name_or_path: str | os.PathLike[str]) -> CreatureSpec:
    """Load a preset by name (``"dog"``) or a creature TOML file by path."""
    text_name = os.fspath(name_or_path)
    path = Path(text_name)
    looks_like_path = text_name.endswith(".toml") or os.sep in text_name or "/" in text_name
    if not looks_like_path:
        preset = creatures_dir() / f"{text_name}.toml"
        if preset.is_file():
            path = preset
        elif not path.is_file():
            known = preset_creature_names()
            hint = did_you_mean(text_name, known)
            raise SpecError(f"unknown creature {text_name!r}{hint}; presets are: {', '.join(known)} "
                            "(or give a path to a .toml file)")
    if not path.is_file():
        raise SpecError(f"{text_name}: no such creature file")
    try:
        data = read_toml(path)
    except TomlProblem as exc:
        raise SpecError(f"{text_name}: {exc}") from None
    return creature_from_dict(data, source=str(path))


def creature_from_dict(data: Mapping[str, Any], source: str = "<dict>", origin: str | None = None) -> CreatureSpec:
    """Build and validate a creature from a TOML-shaped dict. Raises :class:`SpecError`."""
    where = origin or source
    tables = ("body", "legs", "gait", "motion", "speed", "look", "arms", "poses", "overlap")
    _check_keys(data, {**TOP_RULES, **dict.fromkeys(tables)}, "", where, tables=tables)
    name = _value(data, "name", TOP_RULES["name"], where, required=False, default=Path(source).stem)
    description = _value(data, "description", TOP_RULES["description"], where, required=False, default="")

    body_t = _subtable(data, "body", where, required=True)
    body = BodySpec(**_read_table(body_t, BODY_RULES, "body", where, required=("length", "width", "radius")))

    legs = _read_legs(_subtable(data, "legs", where, required=True), where)
    pairs = sum(leg.count for leg in legs)

    gait = _read_gait(_subtable(data, "gait", where, required=False), foot_names(pairs), where)
    motion = MotionSpec(**_read_table(_subtable(data, "motion", where, required=False), MOTION_RULES, "motion", where))
    speed = SpeedSpec(**_read_table(_subtable(data, "speed", where, required=False), SPEED_RULES, "speed", where))
    if speed.trot_gallop <= speed.walk_trot:
        raise SpecError(f"{_at(where)}speed.trot_gallop = {speed.trot_gallop:g} must be above speed.walk_trot = "
                        f"{speed.walk_trot:g}")
    look = LookSpec(**_read_table(_subtable(data, "look", where, required=False), LOOK_RULES, "look", where))
    arms_t = _subtable(data, "arms", where, required=False)
    arms = ArmsSpec(**_read_table(arms_t, ARMS_RULES, "arms", where, required=("upper", "fore", "hand"))) \
        if "arms" in data else None
    poses = PosesSpec(**_read_table(_subtable(data, "poses", where, required=False), POSES_RULES, "poses", where))
    overlap = OverlapSpec(**_read_table(_subtable(data, "overlap", where, required=False), OVERLAP_RULES,
                                        "overlap", where))
    if body.posture == "upright" and pairs != 1:
        raise SpecError(f"{_at(where)}body.posture = 'upright' is for bipeds (one leg pair); this creature has "
                        f"{pairs} pairs")

    spec = CreatureSpec(name=name, description=description, body=body, legs=tuple(legs),
                        gait=gait, motion=motion, speed=speed, look=look, arms=arms, poses=poses, overlap=overlap,
                        source=source)
    _check_geometry(spec, where)
    return spec


_BONES = ("femur", "tibia", "metatarsus", "toe", "ankle_lift")


def _read_legs(legs_t: Mapping[str, Any], where: str) -> list[LegSpec]:
    """The leg tables: ``[legs.fore]`` and ``[legs.hind]`` (the tetrapod form, positions 1
    and 0 by default) or any names, each with a ``position`` (or ``count`` and ``span``)."""
    if not legs_t:
        raise SpecError(f"{_at(where)}[legs] has no leg pairs; give [legs.fore] and [legs.hind], or any "
                        "[legs.NAME] tables with a position along the trunk")
    given = set(legs_t) & set(TETRAPOD_PAIRS)
    if len(given) == 1:
        missing = (set(TETRAPOD_PAIRS) - given).pop()
        raise SpecError(f"{_at(where)}missing table [legs.{missing}]: [legs.fore] and [legs.hind] come together "
                        "(for other layouts name the pairs freely, each with a position)")
    legs = []
    for pair in legs_t:
        table = _subtable(legs_t, pair, where, required=True, prefix="legs.")
        values = _read_table(table, LEG_RULES, f"legs.{pair}", where, required=_BONES)
        values.setdefault("knee", "back" if pair == "fore" else "forward")
        count = values.get("count", 1)
        if "span" in values:
            if len(values["span"]) != 2:
                raise SpecError(f"{_at(where)}legs.{pair}.span = {list(values['span'])}: expected two positions "
                                "[rearmost, frontmost], e.g. [0.1, 0.9]")
            if count == 1:
                raise SpecError(f"{_at(where)}legs.{pair}.span is for repeated pairs (count > 1); a single pair "
                                "takes a position")
        if count > 1 and "position" in values:
            raise SpecError(f"{_at(where)}legs.{pair}: give count with span = [rear, front], not a position")
        if "position" not in values:
            if pair in TETRAPOD_PAIRS:
                values["position"] = 1.0 if pair == "fore" else 0.0
            elif count == 1:
                raise SpecError(f"{_at(where)}missing key legs.{pair}.position ({LEG_RULES['position'].doc}; "
                                f"{LEG_RULES['position'].allowed()})")
            else:
                values["position"] = values.get("span", (0.0, 1.0))[-1]
        legs.append(LegSpec(name=pair, **values))
    positions = sorted((p, leg.name) for leg in legs for p in leg.positions)
    for (p0, n0), (p1, n1) in zip(positions, positions[1:]):
        if p1 - p0 < 1e-6:
            raise SpecError(f"{_at(where)}legs.{n0} and legs.{n1}: two leg pairs at trunk position {p0:g}; give "
                            "each pair its own position")
    if given:
        fore = next(leg for leg in legs if leg.name == "fore")
        hind = next(leg for leg in legs if leg.name == "hind")
        if fore.position <= hind.position:
            raise SpecError(f"{_at(where)}legs.fore.position = {fore.position:g} must be ahead of "
                            f"legs.hind.position = {hind.position:g}")
    pairs = len(positions)
    if pairs > MAX_PAIRS:
        raise SpecError(f"{_at(where)}legs: {pairs} leg pairs; a creature has 1 to {MAX_PAIRS}")
    return legs


def _read_gait(table: Mapping[str, Any], feet: tuple[str, ...], where: str) -> GaitSpec:
    values = _read_table(table, {k: v for k, v in GAIT_RULES.items() if k != "phases"}, "gait", where,
                         extra=("phases",))
    if "phases" in table:
        phases_t = table["phases"]
        if not isinstance(phases_t, Mapping):
            raise SpecError(f"{_at(where)}gait.phases must be a table like {{ LF = 0.25, RF = 0.75, LH = 0, RH = 0.5 }}")
        _check_keys(phases_t, dict.fromkeys(feet), "gait.phases.", where)
        missing = [f for f in feet if f not in phases_t]
        if missing:
            raise SpecError(f"{_at(where)}gait.phases is missing {', '.join(missing)}; give a phase for each of "
                            f"{', '.join(feet)}")
        values["phases"] = tuple((foot, _value(phases_t, foot, GAIT_RULES["phases"], where, prefix="gait.phases."))
                                 for foot in feet)
    gait = GaitSpec(**values)
    pairs = len(feet) // 2
    if not gait.preset_spec.fits(pairs):
        fitting = ", ".join(gaits_for(pairs))
        raise SpecError(f"{_at(where)}gait.preset = {gait.preset!r} is a gait for {gait.preset_spec.fits_text}; this "
                        f"creature has {pairs} leg pair{'s' if pairs > 1 else ''}: use one of {fitting}")
    if gait.duty_factor is not None and gait.bias is not None:
        raise SpecError(f"{_at(where)}gait: give duty_factor or bias, not both (duty_factor = {gait.duty_factor:g}, "
                        f"bias = {gait.bias:g})")
    if gait.bias is not None:
        from .kinematics.oscillator import duty_from_bias

        duty = float(duty_from_bias(gait.bias))
        lo, hi = DUTY_RANGE
        if not lo < duty < hi:
            raise SpecError(f"{_at(where)}gait.bias = {gait.bias:g} gives duty factor {duty:.3f}; "
                            f"the duty factor must be in ({lo:g}, {hi:g})")
    if gait.frames_per_cycle is not None and gait.frequency is not None:
        raise SpecError(f"{_at(where)}gait: give frequency or frames_per_cycle, not both (frequency = "
                        f"{gait.frequency:g}, frames_per_cycle = {gait.frames_per_cycle:g})")
    if gait.frames_per_cycle is not None:
        fps = gait.timing_fps or DEFAULT_TIMING_FPS
        top = GAIT_RULES["frequency"].hi
        if fps / gait.frames_per_cycle > top:
            raise SpecError(f"{_at(where)}gait.frames_per_cycle = {gait.frames_per_cycle:g} at {fps:g} fps is "
                            f"{fps / gait.frames_per_cycle:.3g} Hz; strides are at most {top:g} Hz: give at least "
                            f"{fps / top:g} frames")
    if gait.phases is not None and (gait.front_back is not None or gait.left_right is not None):
        raise SpecError(f"{_at(where)}gait: give phases or front_back/left_right, not both")
    if not gait.preset_spec.symmetric and gait.phases is None and (
            gait.front_back is not None or gait.left_right is not None):
        raise SpecError(f"{_at(where)}gait.preset = {gait.preset!r} is asymmetric (explicit per-foot phases); "
                        "adjust it with gait.phases.LF etc., not front_back/left_right")
    return gait


def _check_geometry(spec: CreatureSpec, where: str) -> None:
    """Reject creatures whose legs cannot stand: the rest pose must be reachable.

    At rest the ball is straight below the hip at the rest length and the metatarsus
    rises behind it at the ankle lift; the hip-to-ankle distance must then lie within
    what femur and tibia can span, [|femur - tibia|, femur + tibia].
    """
    for leg in spec.legs:
        lift = math.radians(leg.ankle_lift)
        reach = leg.femur + leg.tibia
        flat = leg.metatarsus * math.cos(lift)
        if reach <= flat:
            raise SpecError(f"{_at(where)}legs.{leg.name}: unreachable geometry: femur + tibia ({reach:g} m) must be "
                            f"longer than the flat part of the metatarsus ({flat:.3g} m)")
        l_max = math.sqrt(reach ** 2 - flat ** 2) + leg.metatarsus * math.sin(lift)
        l_rest = l_max * min(1.0, max(0.2, 1.0 - leg.natural_bend))
        ankle_at_rest = math.hypot(flat, l_rest - leg.metatarsus * math.sin(lift))
        fold = abs(leg.femur - leg.tibia)
        if leg.metatarsus - reach > 0.8 * l_rest:
            raise SpecError(f"{_at(where)}legs.{leg.name}: unreachable geometry: metatarsus {leg.metatarsus:g} "
                            f"is too long for femur + tibia {reach:g} at the rest length {l_rest:.3g} m")
        if ankle_at_rest < fold * 1.02:
            raise SpecError(f"{_at(where)}legs.{leg.name}: unreachable geometry: femur {leg.femur:g} and tibia "
                            f"{leg.tibia:g} cannot fold to the rest pose (hip to ankle {ankle_at_rest:.3g} m < "
                            f"|femur - tibia| = {fold:.3g} m); make them closer in length or lower natural_bend")
        offset = spec.body.width / 2 if leg.hip_offset is None else leg.hip_offset
        if leg.radius * 2 > max(spec.body.width, 2 * offset) * 1.5:
            raise SpecError(f"{_at(where)}legs.{leg.name}.radius = {leg.radius:g} m is too thick for "
                            f"body.width = {spec.body.width:g} m (legs would overlap)")


# -- table readers ---------------------------------------------------------------------


def _check_keys(table: Mapping[str, Any], allowed: Mapping[str, Any], prefix: str, where: str,
                tables: tuple[str, ...] = ()) -> None:
    for key in table:
        if key not in allowed:
            full = f"{prefix}{key}" if not prefix or prefix.endswith(".") else f"{prefix}.{key}"
            names = [f"{prefix}{k}" if prefix.endswith(".") or not prefix else f"{prefix}.{k}" for k in allowed]
            raise SpecError(f"{_at(where)}unknown key {full!r}{did_you_mean(full, names)}; allowed here: "
                            f"{', '.join(names)}")
        if key in tables and not isinstance(table[key], Mapping):
            raise SpecError(f"{_at(where)}{prefix}{key} must be a table ([{prefix}{key}])")


def _subtable(data: Mapping[str, Any], key: str, where: str, required: bool, prefix: str = "") -> Mapping[str, Any]:
    if key not in data:
        if required:
            raise SpecError(f"{_at(where)}missing table [{prefix}{key}]")
        return {}
    value = data[key]
    if not isinstance(value, Mapping):
        raise SpecError(f"{_at(where)}{prefix}{key} must be a table ([{prefix}{key}]), got {_show(value)}")
    return value


def _read_table(table: Mapping[str, Any], rules: Mapping[str, Rule], name: str, where: str,
                required: tuple[str, ...] = (), extra: tuple[str, ...] = ()) -> dict[str, Any]:
    _check_keys(table, {**rules, **dict.fromkeys(extra)}, f"{name}.", where)
    out: dict[str, Any] = {}
    for key in required:
        if key not in table:
            raise SpecError(f"{_at(where)}missing key {name}.{key} ({rules[key].doc}; {rules[key].allowed()})")
    for key, rule in rules.items():
        if key in table:
            out[key] = _value(table, key, rule, where, prefix=f"{name}.")
    return out


def _value(table: Mapping[str, Any], key: str, rule: Rule, where: str, prefix: str = "",
           required: bool = True, default: Any = None) -> Any:
    if key not in table:
        if required:
            raise SpecError(f"{_at(where)}missing key {prefix}{key}")
        return default
    return check_value(f"{prefix}{key}", table[key], rule, where)


def check_value(key: str, value: Any, rule: Rule, where: str) -> Any:
    """Validate one value against its rule; returns it in the spec's type."""

    prefix = f"{_at(where)}" if where else ""

    def bad(reason: str = "") -> SpecError:
        return SpecError(f"{prefix}{key} = {_show(value)}: {reason or 'expected ' + rule.allowed()}")

    if rule.kind == "text":
        if not isinstance(value, str):
            raise bad()
        return value
    if rule.kind == "choice":
        if value not in rule.choices:
            raise SpecError(f"{prefix}{key} = {_show(value)}: unknown{did_you_mean(str(value), rule.choices)}; "
                            f"expected {rule.allowed()}")
        return value
    if rule.kind == "color":
        if not isinstance(value, str) or not _COLOR_RE.match(value):
            raise bad()
        return value.lower()
    if rule.kind == "numbers":
        if not isinstance(value, (list, tuple)) or not value:
            raise bad()
        return tuple(_number(v, rule, bad) for v in value)
    if rule.kind == "integer":
        try:
            whole = not isinstance(value, bool) and isinstance(value, (int, float)) and math.isfinite(value) \
                and float(value) == int(value)
        except OverflowError:  # an integer too large for a float
            whole = False
        if not whole:
            raise bad()
        value = int(value)
    return _number(value, rule, bad)


def _number(value: Any, rule: Rule, bad) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise bad()
    try:
        number = float(value) if rule.kind != "integer" else int(value)
    except OverflowError:
        raise bad() from None
    if not math.isfinite(number):
        raise bad("not a finite number; expected " + rule.allowed())
    if rule.lo is not None and (number < rule.lo or (rule.lo_open and number == rule.lo)):
        raise bad()
    if rule.hi is not None and (number > rule.hi or (rule.hi_open and number == rule.hi)):
        raise bad()
    return number


def _show(value: Any, limit: int = 60) -> str:
    """A value as TOML-ish text for a message, cut short if long."""
    if isinstance(value, float) and not math.isfinite(value):
        return str(value)
    if isinstance(value, str):
        return repr(value if len(value) <= limit else value[:limit] + "...")
    text = str(value).lower() if isinstance(value, bool) else str(value)
    return text if len(text) <= limit else text[:limit] + "..."


def _at(where: str) -> str:
    """The "file: " prefix of an error message, or nothing when there is no origin."""
    return f"{where}: " if where else ""


# -- overrides -------------------------------------------------------------------------


def override_keys() -> list[str]:
    """Every dotted key that :meth:`CreatureSpec.with_overrides` accepts."""
    keys = [f"{table}.{k}" for table, rules in TABLES.items() for k in rules if k != "phases"]
    keys += [f"legs.{pair}.{k}" for pair in TETRAPOD_PAIRS for k in LEG_RULES]
    keys += [f"gait.phases.{foot}" for foot in foot_names(2)]
    keys += list(TOP_RULES)
    return keys


def rule_for(key: str) -> Rule | None:
    """The rule that governs a dotted key, or ``None`` if there is no such key."""
    parts = key.split(".")
    if len(parts) == 1:
        return TOP_RULES.get(parts[0])
    if parts[0] == "legs" and len(parts) == 3:
        return LEG_RULES.get(parts[2])
    if parts[:2] == ["gait", "phases"] and len(parts) == 3 and _FOOT_RE.match(parts[2]):
        return GAIT_RULES["phases"]
    if len(parts) == 2 and parts[0] in TABLES and parts[1] != "phases":
        return TABLES[parts[0]].get(parts[1])
    return None


def _apply_override(data: dict[str, Any], key: str, value: Any, spec: CreatureSpec, origin: str = "--set") -> None:
    rule = rule_for(key)
    if rule is None:
        raise SpecError(f"{origin + ' ' if origin else ''}{key}: unknown key{did_you_mean(key, override_keys())}; "
                        "keys look like body.length, legs.hind.femur, gait.duty_factor, gait.phases.LF")
    value = check_value(key, value, rule, origin)
    parts = key.split(".")
    if parts[0] == "legs" and parts[1] not in data.get("legs", {}):
        pairs = ", ".join(data.get("legs", {}))
        raise SpecError(f"{origin + ' ' if origin else ''}{key}: {spec.name} has no leg pair {parts[1]!r}"
                        f"{did_you_mean(parts[1], data.get('legs', {}))}; its pairs are: {pairs}")
    if key == "gait.preset":
        data["gait"] = {"preset": value, "wave": data.get("gait", {}).get("wave", "planted")}
        return
    if parts[:2] == ["gait", "phases"]:
        gait = data.setdefault("gait", {})
        if parts[2] not in spec.foot_names:
            raise SpecError(f"{origin + ' ' if origin else ''}{key}: {spec.name} has no foot {parts[2]}; its feet are "
                            f"{', '.join(spec.foot_names)}")
        if "phases" not in gait:
            phases = resolve_phases(spec.gait, spec.foot_names)
            gait["phases"] = dict(zip(spec.foot_names, (float(p) for p in phases)))
            gait.pop("front_back", None)
            gait.pop("left_right", None)
        gait["phases"][parts[2]] = value
        return
    if key in ("gait.duty_factor", "gait.bias"):
        data.setdefault("gait", {}).pop("bias" if key == "gait.duty_factor" else "duty_factor", None)
    if key in ("gait.frequency", "gait.frames_per_cycle"):
        data.setdefault("gait", {}).pop("frames_per_cycle" if key == "gait.frequency" else "frequency", None)
    if key in ("gait.front_back", "gait.left_right"):
        data.setdefault("gait", {}).pop("phases", None)
    node = data
    for part in parts[:-1]:
        node = node.setdefault(part, {})
    node[parts[-1]] = value


def spec_value(spec: CreatureSpec, key: str) -> Any:
    """The value a creature file holds for a dotted key (``None`` for a gait or motion key
    left to its preset)."""
    if rule_for(key) is None:
        raise KeyError(key)
    parts = key.split(".")
    if parts[0] == "legs":
        return getattr(spec.leg(parts[1]), parts[2])
    if parts[:2] == ["gait", "phases"]:
        return None if spec.gait.phases is None else dict(spec.gait.phases)[parts[2]]
    node: Any = spec
    for part in parts:
        node = getattr(node, part)
    return node


def without_adjustment(spec: CreatureSpec, key: str) -> CreatureSpec:
    """A copy with an optional gait/motion key (one that may be ``None``) given back to its
    preset, e.g. ``gait.duty_factor``; ``gait.phases.LF`` clears all per-foot phases."""
    data = spec.to_dict()
    table, name = key.split(".")[0], key.split(".")[1]
    data.get(table, {}).pop(name, None)
    return creature_from_dict(data, source=spec.source or f"<{spec.name}>")


# (ankle lift in degrees, toe length as a fraction of the metatarsus) typical of each type.
LEG_TYPE_SHAPES: dict[str, tuple[float, float]] = {
    "plantigrade": (8.0, 0.6), "digitigrade": (62.0, 0.5), "unguligrade": (84.0, 0.18)}


def parse_override(text: str) -> tuple[str, Any]:
    """Parse a ``KEY=VALUE`` command-line override; VALUE is read as a TOML value."""
    if "=" not in text:
        raise SpecError(f"--set {_show(text)}: expected KEY=VALUE, e.g. --set gait.duty_factor=0.7")
    key, raw = (s.strip() for s in text.split("=", 1))
    if rule_for(key) is None:
        raise SpecError(f"--set {key}: unknown key{did_you_mean(key, override_keys())}; "
                        "keys look like body.length, legs.hind.femur, gait.duty_factor, gait.phases.LF")
    try:
        value = parse_toml(f"v = {raw}")["v"]
    except (TomlProblem, KeyError):
        value = raw  # a bare word such as a preset name; validated against the key's rule
    return key, value


def resolve_phases(gait: GaitSpec, feet: tuple[str, ...]) -> Any:
    """Each foot's touchdown phase for a gait spec, shape (len(feet),), in [0, 1)."""
    import numpy as np

    preset = gait.preset_spec
    if gait.phases is not None:
        given = dict(gait.phases)
        return np.mod(np.array([given[f] for f in feet], dtype=np.float64), 1.0)
    if preset.symmetric:
        fb = preset.front_back if gait.front_back is None else gait.front_back
        lr = preset.left_right if gait.left_right is None else gait.left_right
        return phases_from_offsets(float(fb), float(lr), feet)
    return preset_phases(gait.preset, feet)
