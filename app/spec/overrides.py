"""Changing a creature by dotted keys (``legs.hind.femur``, ``gait.duty_factor``): the
``--set`` option, scene files' ``set`` tables and every viewer control; reading a
key's value; each foot's phase."""

from __future__ import annotations

from collections.abc import Mapping
from functools import lru_cache
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..errors import SpecError, did_you_mean
from ..gaits import phases_from_offsets, preset_phases
from ..tomlfile import TomlProblem, parse_toml
from .load import creature_from_dict
from .model import CreatureSpec, GaitSpec
from .schema import FOOT_RE, GAIT_RULES, LEG_RULES, TABLES, TOP_RULES, Rule, check_value, show


def apply_overrides(spec: CreatureSpec, overrides: Mapping[str, Any], origin: str = "--set") -> CreatureSpec:
    """``spec`` with dotted keys replaced (see :meth:`CreatureSpec.with_overrides`)."""
    data = spec.to_dict()
    items = sorted(overrides.items(), key=lambda kv: kv[0] != "gait.preset")
    for key, value in items:
        _apply_override(data, key, value, spec, origin)
    return creature_from_dict(data, source=spec.source or f"<{spec.name}>", origin=origin)


def override_keys(spec: CreatureSpec | None = None) -> list[str]:
    """Every dotted key that :meth:`CreatureSpec.with_overrides` accepts: for ``spec``,
    with its own leg pairs and feet (``legs.rear.femur``, ``gait.phases.L3``); without one,
    with the placeholders ``legs.NAME.KEY`` and ``gait.phases.FOOT``."""
    pairs = [leg.name for leg in spec.legs] if spec is not None else ["NAME"]
    feet = list(spec.foot_names) if spec is not None else ["FOOT"]
    keys = [f"{table}.{k}" for table, rules in TABLES.items() for k in rules if k != "phases"]
    keys += [f"legs.{pair}.{k}" for pair in pairs for k in LEG_RULES]
    keys += [f"gait.phases.{foot}" for foot in feet]
    keys += list(TOP_RULES)
    return keys


def _unknown_key(key: str, origin: str, spec: CreatureSpec | None) -> SpecError:
    """The one line for a key no creature file has, with the nearest of the creature's own."""
    example = (f"legs.{spec.legs[-1].name}.femur, gait.phases.{spec.foot_names[0]}" if spec is not None
               else "legs.hind.femur, gait.phases.LF")
    return SpecError(f"{origin + ' ' if origin else ''}{key}: unknown key{did_you_mean(key, override_keys(spec))}; "
                     f"keys look like body.length, gait.duty_factor, {example}")


@lru_cache(maxsize=1024)
def rule_for(key: str) -> Rule | None:
    """The rule that governs a dotted key, or ``None`` if there is no such key (remembered:
    the panels ask for every slider's rule every frame)."""
    parts = key.split(".")
    if len(parts) == 1:
        return TOP_RULES.get(parts[0])
    if parts[0] == "legs" and len(parts) == 3:
        return LEG_RULES.get(parts[2])
    if parts[:2] == ["gait", "phases"] and len(parts) == 3 and FOOT_RE.match(parts[2]):
        return GAIT_RULES["phases"]
    if len(parts) == 2 and parts[0] in TABLES and parts[1] != "phases":
        return TABLES[parts[0]].get(parts[1])
    return None


def _apply_override(data: dict[str, Any], key: str, value: Any, spec: CreatureSpec, origin: str = "--set") -> None:
    rule = rule_for(key)
    if rule is None:
        raise _unknown_key(key, origin, spec)
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


def parse_override(text: str, spec: CreatureSpec | None = None) -> tuple[str, Any]:
    """Parse a ``KEY=VALUE`` command-line override; VALUE is read as a TOML value. An
    unknown key is named with the nearest key of ``spec`` (its own legs and feet)."""
    if "=" not in text:
        raise SpecError(f"--set {show(text)}: expected KEY=VALUE, e.g. --set gait.duty_factor=0.7")
    key, raw = (s.strip() for s in text.split("=", 1))
    if rule_for(key) is None:
        raise _unknown_key(key, "--set", spec)
    try:
        value = parse_toml(f"v = {raw}")["v"]
    except (TomlProblem, KeyError):
        value = raw  # a bare word such as a preset name; validated against the key's rule
    return key, value


def resolve_phases(gait: GaitSpec, feet: tuple[str, ...]) -> NDArray[np.float64]:
    """Each foot's touchdown phase for a gait spec, shape (len(feet),), in [0, 1)."""
    preset = gait.preset_spec
    if gait.phases is not None:
        given = dict(gait.phases)
        return np.mod(np.array([given[f] for f in feet], dtype=np.float64), 1.0)
    if preset.symmetric:
        fb = preset.front_back if gait.front_back is None else gait.front_back
        lr = preset.left_right if gait.left_right is None else gait.left_right
        return phases_from_offsets(float(fb or 0.0), float(lr or 0.0), feet)
    return preset_phases(gait.preset, feet)
