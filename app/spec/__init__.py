"""Creature files: the schema, the data model, loading and overrides.

A creature is a TOML file (see ``creatures/dog.toml`` for an annotated example) with the
tables ``[body]``, ``[legs.NAME]``, ``[gait]``, ``[motion]``, ``[speed]``, ``[look]`` and,
for some, ``[arms]``, ``[poses]`` and ``[overlap]``. Lengths are metres, angles degrees,
phases fractions of a cycle, step height and stride leg rest lengths.

- :mod:`.schema`: every key once, with what it means and what it accepts (:class:`Rule`);
- :mod:`.model`: the frozen dataclasses (:class:`CreatureSpec` and its tables);
- :mod:`.load`: file or dict to a validated spec, or one line naming what is wrong;
- :mod:`.overrides`: dotted keys (``--set``, scene files, the viewer) and phases.
"""

from __future__ import annotations

from ..choices import LegType, leg_type
from ..errors import SpecError, did_you_mean
from .load import creature_from_dict, load_creature
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
from .overrides import override_keys, parse_override, resolve_phases, rule_for, spec_value, without_adjustment
from .schema import LEG_TYPE_SHAPES, SCALED_BODY_KEYS, TABLES, Rule, check_value

__all__ = ["LEG_TYPE_SHAPES", "SCALED_BODY_KEYS", "TABLES", "ArmsSpec", "BodySpec", "CreatureSpec", "GaitSpec",
           "LegSpec", "LegType",
           "LookSpec", "MotionSpec", "OverlapSpec", "PosesSpec", "Rule", "SpecError", "SpeedSpec", "check_value",
           "creature_from_dict", "did_you_mean", "leg_type", "load_creature", "override_keys", "parse_override",
           "resolve_phases", "rule_for", "spec_value", "without_adjustment"]
