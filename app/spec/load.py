"""Loading and validating creature files: a preset name or a TOML file to a
:class:`~app.spec.model.CreatureSpec`, or one line naming the file, the key, the value
and what is allowed."""

from __future__ import annotations

import os
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import SpecError, did_you_mean, not_a_file
from ..gaits import MAX_PAIRS, foot_names, gaits_for
from ..kinematics.rig import leg_lengths
from ..resources import creatures_dir, preset_creature_names
from ..styles import DEFAULT_TIMING_FPS
from ..tomlfile import TomlProblem, read_toml
from .model import (
    ArmsSpec,
    BodySpec,
    CreatureSpec,
    GaitSpec,
    LegSpec,
    LookSpec,
    MotionSpec,
    OverlapSpec,
    PosesSpec,
    SpeedSpec,
)
from .schema import (
    ARMS_RULES,
    BODY_RULES,
    DUTY_RANGE,
    GAIT_RULES,
    LEG_RULES,
    LOOK_RULES,
    MOTION_RULES,
    OVERLAP_RULES,
    POSES_RULES,
    SPEED_RULES,
    TETRAPOD_PAIRS,
    TOP_RULES,
    Rule,
    at,
    check_value,
    show,
)


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
        why = not_a_file(path)
        raise SpecError(f"{text_name}: {'no such creature file' if why == 'no such file' else why}")
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
        raise SpecError(f"{at(where)}speed.trot_gallop = {speed.trot_gallop:g} must be above speed.walk_trot = "
                        f"{speed.walk_trot:g}")
    look = LookSpec(**_read_table(_subtable(data, "look", where, required=False), LOOK_RULES, "look", where))
    arms_t = _subtable(data, "arms", where, required=False)
    arms = ArmsSpec(**_read_table(arms_t, ARMS_RULES, "arms", where, required=("upper", "fore", "hand"))) \
        if "arms" in data else None
    poses = PosesSpec(**_read_table(_subtable(data, "poses", where, required=False), POSES_RULES, "poses", where))
    overlap = OverlapSpec(**_read_table(_subtable(data, "overlap", where, required=False), OVERLAP_RULES,
                                        "overlap", where))
    if body.beak > body.head_length:
        raise SpecError(f"{at(where)}body.beak = {body.beak:g} m is longer than the head (body.head_length = "
                        f"{body.head_length:g} m); the beak is the front of the head")
    if body.posture == "upright" and pairs != 1:
        raise SpecError(f"{at(where)}body.posture = 'upright' is for bipeds (one leg pair); this creature has "
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
        raise SpecError(f"{at(where)}[legs] has no leg pairs; give [legs.fore] and [legs.hind], or any "
                        "[legs.NAME] tables with a position along the trunk")
    given = set(legs_t) & set(TETRAPOD_PAIRS)
    if len(given) == 1:
        missing = (set(TETRAPOD_PAIRS) - given).pop()
        raise SpecError(f"{at(where)}missing table [legs.{missing}]: [legs.fore] and [legs.hind] come together "
                        "(for other layouts name the pairs freely, each with a position)")
    legs = []
    for pair in legs_t:
        table = _subtable(legs_t, pair, where, required=True, prefix="legs.")
        values = _read_table(table, LEG_RULES, f"legs.{pair}", where, required=_BONES)
        values.setdefault("knee", "back" if pair == "fore" else "forward")
        count = values.get("count", 1)
        if "span" in values:
            if len(values["span"]) != 2:
                raise SpecError(f"{at(where)}legs.{pair}.span = {list(values['span'])}: expected two positions "
                                "[rearmost, frontmost], e.g. [0.1, 0.9]")
            if count == 1:
                raise SpecError(f"{at(where)}legs.{pair}.span is for repeated pairs (count > 1); a single pair "
                                "takes a position")
        if count > 1 and "position" in values:
            raise SpecError(f"{at(where)}legs.{pair}: give count with span = [rear, front], not a position")
        if "position" not in values:
            if pair in TETRAPOD_PAIRS:
                values["position"] = 1.0 if pair == "fore" else 0.0
            elif count == 1:
                raise SpecError(f"{at(where)}missing key legs.{pair}.position ({LEG_RULES['position'].doc}; "
                                f"{LEG_RULES['position'].allowed()})")
            else:
                values["position"] = values.get("span", (0.0, 1.0))[-1]
        legs.append(LegSpec(name=pair, **values))
    positions = sorted((p, leg.name) for leg in legs for p in leg.positions)
    for (p0, n0), (p1, n1) in zip(positions, positions[1:]):
        if p1 - p0 < 1e-6:
            raise SpecError(f"{at(where)}legs.{n0} and legs.{n1}: two leg pairs at trunk position {p0:g}; give "
                            "each pair its own position")
    if given:
        fore = next(leg for leg in legs if leg.name == "fore")
        hind = next(leg for leg in legs if leg.name == "hind")
        if fore.position <= hind.position:
            raise SpecError(f"{at(where)}legs.fore.position = {fore.position:g} must be ahead of "
                            f"legs.hind.position = {hind.position:g}")
    pairs = len(positions)
    if pairs > MAX_PAIRS:
        raise SpecError(f"{at(where)}legs: {pairs} leg pairs; a creature has 1 to {MAX_PAIRS}")
    return legs


def _read_gait(table: Mapping[str, Any], feet: tuple[str, ...], where: str) -> GaitSpec:
    values = _read_table(table, {k: v for k, v in GAIT_RULES.items() if k != "phases"}, "gait", where,
                         extra=("phases",))
    if "phases" in table:
        phases_t = table["phases"]
        if not isinstance(phases_t, Mapping):
            raise SpecError(f"{at(where)}gait.phases must be a table like {{ LF = 0.25, RF = 0.75, LH = 0, RH = 0.5 }}")
        _check_keys(phases_t, dict.fromkeys(feet), "gait.phases.", where)
        missing = [f for f in feet if f not in phases_t]
        if missing:
            raise SpecError(f"{at(where)}gait.phases is missing {', '.join(missing)}; give a phase for each of "
                            f"{', '.join(feet)}")
        values["phases"] = tuple((foot, _value(phases_t, foot, GAIT_RULES["phases"], where, prefix="gait.phases."))
                                 for foot in feet)
    gait = GaitSpec(**values)
    pairs = len(feet) // 2
    if not gait.preset_spec.fits(pairs):
        fitting = ", ".join(gaits_for(pairs))
        raise SpecError(f"{at(where)}gait.preset = {gait.preset!r} is a gait for {gait.preset_spec.fits_text}; this "
                        f"creature has {pairs} leg pair{'s' if pairs > 1 else ''}: use one of {fitting}")
    if gait.duty_factor is not None and gait.bias is not None:
        raise SpecError(f"{at(where)}gait: give duty_factor or bias, not both (duty_factor = {gait.duty_factor:g}, "
                        f"bias = {gait.bias:g})")
    if gait.bias is not None:
        from ..kinematics.oscillator import duty_from_bias

        duty = float(duty_from_bias(gait.bias))
        lo, hi = DUTY_RANGE
        if not lo < duty < hi:
            raise SpecError(f"{at(where)}gait.bias = {gait.bias:g} gives duty factor {duty:.3f}; "
                            f"the duty factor must be in ({lo:g}, {hi:g})")
    if gait.frames_per_cycle is not None and gait.frequency is not None:
        raise SpecError(f"{at(where)}gait: give frequency or frames_per_cycle, not both (frequency = "
                        f"{gait.frequency:g}, frames_per_cycle = {gait.frames_per_cycle:g})")
    if gait.frames_per_cycle is not None:
        fps = gait.timing_fps or DEFAULT_TIMING_FPS
        top = float(GAIT_RULES["frequency"].hi or 0.0)
        if fps / gait.frames_per_cycle > top:
            raise SpecError(f"{at(where)}gait.frames_per_cycle = {gait.frames_per_cycle:g} at {fps:g} fps is "
                            f"{fps / gait.frames_per_cycle:.3g} Hz; strides are at most {top:g} Hz: give at least "
                            f"{fps / top:g} frames")
    if gait.phases is not None and (gait.front_back is not None or gait.left_right is not None):
        raise SpecError(f"{at(where)}gait: give phases or front_back/left_right, not both")
    if not gait.preset_spec.symmetric and gait.phases is None and (
            gait.front_back is not None or gait.left_right is not None):
        raise SpecError(f"{at(where)}gait.preset = {gait.preset!r} is asymmetric (explicit per-foot phases); "
                        "adjust it with gait.phases.LF etc., not front_back/left_right")
    return gait


def _check_geometry(spec: CreatureSpec, where: str) -> None:
    """Reject creatures whose legs cannot stand: the rest pose must be reachable.

    At rest the ball is straight below the hip at the rest length (the rig's own
    :func:`~app.kinematics.rig.leg_lengths`) and the metatarsus rises behind it at the
    ankle lift; the hip-to-ankle distance must then lie within what femur and tibia can
    span, [|femur - tibia|, femur + tibia].
    """
    for leg in spec.legs:
        lift = float(np.radians(leg.ankle_lift))
        reach = leg.femur + leg.tibia
        flat = leg.metatarsus * float(np.cos(lift))
        if reach <= flat:
            raise SpecError(f"{at(where)}legs.{leg.name}: unreachable geometry: femur + tibia ({reach:g} m) must be "
                            f"longer than the flat part of the metatarsus ({flat:.3g} m)")
        _, rest, _ = leg_lengths(*(np.array([v]) for v in (leg.femur, leg.tibia, leg.metatarsus, lift,
                                                             leg.natural_bend)))
        l_rest = float(rest[0])
        ankle_at_rest = float(np.hypot(flat, l_rest - leg.metatarsus * np.sin(lift)))
        fold = abs(leg.femur - leg.tibia)
        if leg.metatarsus - reach > 0.8 * l_rest:
            raise SpecError(f"{at(where)}legs.{leg.name}: unreachable geometry: metatarsus {leg.metatarsus:g} "
                            f"is too long for femur + tibia {reach:g} at the rest length {l_rest:.3g} m")
        if ankle_at_rest < fold * 1.02:
            raise SpecError(f"{at(where)}legs.{leg.name}: unreachable geometry: femur {leg.femur:g} and tibia "
                            f"{leg.tibia:g} cannot fold to the rest pose (hip to ankle {ankle_at_rest:.3g} m < "
                            f"|femur - tibia| = {fold:.3g} m); make them closer in length or lower natural_bend")
        offset = spec.body.width / 2 if leg.hip_offset is None else leg.hip_offset
        if leg.radius * 2 > max(spec.body.width, 2 * offset) * 1.5:
            raise SpecError(f"{at(where)}legs.{leg.name}.radius = {leg.radius:g} m is too thick for "
                            f"body.width = {spec.body.width:g} m (legs would overlap)")


# -- table readers ---------------------------------------------------------------------


def _check_keys(table: Mapping[str, Any], allowed: Mapping[str, Any], prefix: str, where: str,
                tables: tuple[str, ...] = ()) -> None:
    for key in table:
        if key not in allowed:
            full = f"{prefix}{key}" if not prefix or prefix.endswith(".") else f"{prefix}.{key}"
            names = [f"{prefix}{k}" if prefix.endswith(".") or not prefix else f"{prefix}.{k}" for k in allowed]
            raise SpecError(f"{at(where)}unknown key {full!r}{did_you_mean(full, names)}; allowed here: "
                            f"{', '.join(names)}")
        if key in tables and not isinstance(table[key], Mapping):
            raise SpecError(f"{at(where)}{prefix}{key} must be a table ([{prefix}{key}])")


def _subtable(data: Mapping[str, Any], key: str, where: str, required: bool, prefix: str = "") -> Mapping[str, Any]:
    if key not in data:
        if required:
            raise SpecError(f"{at(where)}missing table [{prefix}{key}]")
        return {}
    value = data[key]
    if not isinstance(value, Mapping):
        raise SpecError(f"{at(where)}{prefix}{key} must be a table ([{prefix}{key}]), got {show(value)}")
    return value


def _read_table(table: Mapping[str, Any], rules: Mapping[str, Rule], name: str, where: str,
                required: tuple[str, ...] = (), extra: tuple[str, ...] = ()) -> dict[str, Any]:
    _check_keys(table, {**rules, **dict.fromkeys(extra)}, f"{name}.", where)
    out: dict[str, Any] = {}
    for key in required:
        if key not in table:
            raise SpecError(f"{at(where)}missing key {name}.{key} ({rules[key].doc}; {rules[key].allowed()})")
    for key, rule in rules.items():
        if key in table:
            out[key] = _value(table, key, rule, where, prefix=f"{name}.")
    return out


def _value(table: Mapping[str, Any], key: str, rule: Rule, where: str, prefix: str = "",
           required: bool = True, default: Any = None) -> Any:
    if key not in table:
        if required:
            raise SpecError(f"{at(where)}missing key {prefix}{key}")
        return default
    return check_value(f"{prefix}{key}", table[key], rule, where)
