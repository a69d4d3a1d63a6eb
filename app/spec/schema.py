"""The creature-file schema: every key, what it means and which values it accepts.

Each table of a creature file (``[body]``, ``[legs.NAME]``, ``[gait]``, ...) is a dict of
:class:`Rule`; loading, overriding, ``gaitlab creatures --keys``, the viewer's tooltips
and every error message read them, so a key is described once. :func:`check_value`
validates one value against its rule (numbers through :class:`app.numbers.Range`, the
one number check).
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from typing import Any

from ..choices import KNEE_DIRECTIONS, POSTURES, WAVE_SHAPES
from ..errors import SpecError, did_you_mean
from ..gaits import GAIT_PRESETS, MAX_PAIRS
from ..numbers import NumberProblem, Range
from ..styles import WALK_STYLES

TETRAPOD_PAIRS: tuple[str, ...] = ("fore", "hind")  # the classic two-girdle form: [legs.fore], [legs.hind]
DUTY_RANGE = (0.05, 0.95)
BIAS_LIMIT = 50.0  # |b| <= 50 covers duty factors up to ~0.947


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

    @property
    def range(self) -> Range:
        """The numbers this key accepts (number, integer and numbers kinds)."""
        return Range(self.lo, self.hi, self.lo_open, self.hi_open, self.unit, integer=self.kind == "integer")

    def allowed(self) -> str:
        """A short phrase for error messages: what values are allowed."""
        if self.kind == "choice":
            return "one of " + ", ".join(self.choices)
        if self.kind == "color":
            return 'a colour like "#a07850"'
        if self.kind == "text":
            return "a string"
        if self.kind == "numbers":
            return "a list of numbers each" + self.range.allowed().removeprefix("a number")
        return self.range.allowed()


def _num(lo=None, hi=None, *, lo_open=False, hi_open=False, unit="", doc="") -> Rule:
    return Rule("number", lo, hi, lo_open, hi_open, unit=unit, doc=doc)


def _length(doc: str, *, zero_ok: bool = False, hi: float = 50.0) -> Rule:
    return _num(0.0, hi, lo_open=not zero_ok, unit="m", doc=doc)


# Body keys that are lengths (m): a fitted or model-driven creature scales them with its legs.
SCALED_BODY_KEYS = ("length", "neck_length", "head_length", "head_radius", "tail_length", "tail_radius", "ear_length",
                    "mane", "wings", "beak", "hump")

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
    "ear_length": _length("ear length (0 for none; an arthropod's antennae: elbowed, reaching forward)", zero_ok=True),
    "tail_length": _length("tail length (0 for none)", zero_ok=True),
    "tail_angle": _num(-90, 90, unit="deg", doc="tail droop below the body axis"),
    "tail_segments": Rule("integer", 1, 32, doc="number of tail segments"),
    "tail_curl": _num(-180, 180, unit="deg", doc="how far the tail turns from its first segment to its last: "
                      "+ curving up (a dog's sickle, a cat's J), - falling (a horse's hair)"),
    "tail_radius": _length("the tail's radius at its base, tapering to a quarter at the tip (default: a third "
                           "of the rump's radius; a lizard's or theropod's thick muscular tail: about two thirds)"),
    "mane": _length("the height of a mane of hair along the top of the neck, from the poll to the withers "
                    "(0 for none; a horse's: about 0.1)", zero_ok=True),
    "wings": _length("a bird's folded wings: how far each reaches back along the flank from the shoulder "
                     "(0 for none; an ostrich's: about 0.4)", zero_ok=True),
    "beak": _length("a bird's beak: its length back from the tip of the head, broad, flat and round-tipped, "
                    "in look.beak_color (0: a muzzle; at most the head's length)", zero_ok=True),
    "hump": _length("how far a hump over the shoulders stands above the back (0 for none; a grizzly's "
                    "muscle: about 0.08, a bison's: 0.3)", zero_ok=True),
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
    "heel": _length("how far a plantigrade foot's heel reaches behind its ankle (the calcaneus; 0 puts the "
                    "heel under the ankle); it strikes first and the foot rolls down about it", zero_ok=True, hi=1.0),
    "natural_bend": _num(0, 0.6, doc="rest length as a fraction below full extension: L_rest = L_max (1 - bend)"),
    "knee": Rule("choice", choices=KNEE_DIRECTIONS,
                  doc="which way the middle joint points: forward (knee), back (elbow), out (up and away from "
                      "the body: insects, spiders)"),
    "radius": _length("bone radius at the hip; bones taper towards the foot", hi=2.0),
    "toes": Rule("integer", 0, 4, doc="splayed toes instead of a sole, paw or hoof (0: the foot its leg type "
                 "gives): 2 an ostrich's, 3 a theropod's, 4 a bird's three forward and one back (legs whose "
                 "knees point forward or back; a sprawled leg's foot is its last segment)"),
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
    "swing_knee": _num(55, 90, unit="deg", doc="a walker's knee at its most bent in the swing (feet that roll heel "
                       "to toe, walking); the push-off's knee scales with it (people: about 60)"),
}

OVERLAP_RULES: dict[str, Rule] = {
    part: _num(0, 0.5, doc=f"how far (cycle fraction) the {what} follows through behind the body")
    for part, what in (("head", "head"), ("neck", "neck"), ("arms", "arms' swing"), ("tail", "tail"),
                       ("ears", "ears"))
}

GAIT_RULES: dict[str, Rule] = {
    "preset": Rule("choice", choices=tuple(GAIT_PRESETS), doc="gait preset the other keys adjust"),
    "frequency": _num(0.05, 20.0, unit="Hz", doc="stride frequency (default: from the preset and hip height)"),
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
    "sway": _num(0, 0.5, unit="m", doc="how far the hips move sideways towards the stance foot, either way"),
    "spine_flex": _num(0, 3, doc="scales how far the spine flexes and the trunk pitches in bounds and gallops "
                       "(1: as the gait and the creature's build give; 0: a stiff back)"),
}

SPEED_RULES: dict[str, Rule] = {
    "walk_trot": _num(0.05, 5.0, doc="Froude number v^2/(g h) at which a speed-driven walk becomes a trot (a "
                      "biped's walk a run, a hexapod's tetrapod gait the tripod)"),
    "trot_gallop": _num(0.1, 20.0, doc="Froude number at which a speed-driven trot becomes a gallop"),
    "hysteresis": _num(0.0, 0.5, doc="fraction above (below) a threshold at which the gait changes up (down)"),
    "gallop": Rule("choice", choices=("gallop", "rotary-gallop"), doc="which gallop fast speeds use"),
}

LOOK_RULES: dict[str, Rule] = {
    "body_color": Rule("color", doc="the coat: the body, and every part the look gives no colour of its own"),
    "left_color": Rule("color", doc="colour of the left legs"),
    "right_color": Rule("color", doc="colour of the right legs"),
    "leg_color": Rule("color", doc="the lower legs and feet, from the ankle down, on a smooth body (a bird's "
                      "scaly feet, a horse's socks; default: the body colour)"),
    "neck_color": Rule("color", doc="the neck and head on a smooth body (an ostrich's bare neck; default: the "
                       "body colour)"),
    "beak_color": Rule("color", doc="the beak (body.beak; default: horn)"),
    "plume_color": Rule("color", doc="the wings' and tail's feathers (body.wings; default: the body colour)"),
    "countershade": _num(0.0, 1.0, doc="how much lighter the smooth body is underneath (0: one colour all "
                         "round, as a person's skin; 0.35: a mammal's coat)"),
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
COLOR_RE = re.compile(r"^#[0-9a-fA-F]{6}$")
MAX_LIST = 256  # numbers in a list value (a body's radius profile: a handful give its shape)
FOOT_RE = re.compile(r"^[LR]([FH]|[0-9]{1,2})?$")

# (ankle lift in degrees, toe length as a fraction of the metatarsus) typical of each type.
LEG_TYPE_SHAPES: dict[str, tuple[float, float]] = {
    "plantigrade": (8.0, 0.6), "digitigrade": (62.0, 0.5), "unguligrade": (84.0, 0.18)}

# -- one value --------------------------------------------------------------------------


def check_value(key: str, value: Any, rule: Rule, where: str) -> Any:
    """Validate one value against its rule; returns it in the spec's type."""

    prefix = at(where)

    def bad(reason: str = "") -> SpecError:
        return SpecError(f"{prefix}{key} = {show(value)}: {reason or 'expected ' + rule.allowed()}")

    if rule.kind == "text":
        if not isinstance(value, str):
            raise bad()
        return value
    if rule.kind == "choice":
        if value not in rule.choices:
            raise SpecError(f"{prefix}{key} = {show(value)}: unknown{did_you_mean(str(value), rule.choices)}; "
                            f"expected {rule.allowed()}")
        return value
    if rule.kind == "color":
        if not isinstance(value, str) or not COLOR_RE.match(value):
            raise bad()
        return value.lower()
    if rule.kind == "numbers":
        if not isinstance(value, (list, tuple)) or not value:
            raise bad()
        if len(value) > MAX_LIST:
            raise SpecError(f"{prefix}{key}: a list of {len(value):,} numbers; at most {MAX_LIST} are read")
        return tuple(_number(v, rule, bad) for v in value)
    return _number(value, rule, bad)


def _number(value: Any, rule: Rule, bad) -> float:
    if isinstance(value, str):  # a file's "1.5" is text, not a number
        raise bad()
    try:
        return rule.range.check(value)
    except NumberProblem as exc:
        raise bad(str(exc) if str(exc).startswith("not a finite") else "") from None


def show(value: Any, limit: int = 60) -> str:
    """A value as TOML-ish text for a message, cut short if long."""
    if isinstance(value, float) and not math.isfinite(value):
        return str(value)
    if isinstance(value, str):
        return repr(value if len(value) <= limit else value[:limit] + "...")
    text = str(value).lower() if isinstance(value, bool) else str(value)
    return text if len(text) <= limit else text[:limit] + "..."


def at(where: str) -> str:
    """The "file: " prefix of an error message, or nothing when there is no origin."""
    return f"{where}: " if where else ""
