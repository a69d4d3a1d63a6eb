"""Scene files: a terrain, named paths and one or more creatures (``scenes/*.toml``)."""

from __future__ import annotations

import math
import os
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from pathlib import Path as FilePath
from typing import Any, TypeVar

from ..choices import MAX_HERD
from ..errors import did_you_mean, shown
from ..kinematics.path import Path
from ..kinematics.terrain import Terrain
from ..kinematics.world import World, WorldError
from ..tomlfile import TomlProblem, read_toml
from .text import parse_path, parse_terrain

T = TypeVar("T")


@dataclass(frozen=True)
class SceneCreature:
    """One creature in a scene: a preset name or creature file, its gait, its path (a
    World), an optional speed (m/s) and creature-file overrides."""

    creature: str
    world: World
    gait: str | None = None
    speed: float | None = None
    overrides: dict[str, Any] = field(default_factory=dict)
    herd: int = 1  # animals in all: this creature and herd - 1 more of its kind following it


@dataclass(frozen=True)
class Scene:
    """A scene file: terrain, named paths and one or more creatures."""

    name: str
    terrain: Terrain
    creatures: tuple[SceneCreature, ...]
    source: str = ""


SCENE_KEYS = ("name", "description", "terrain", "paths", "creatures")
CREATURE_KEYS = ("creature", "gait", "path", "speed", "set", "herd")


def _text_or_table(value: Any, key: str, where: str) -> str:
    """A path/terrain given as text or as a table {kind = ..., KEY = VALUE}."""
    if isinstance(value, str):
        return value
    if isinstance(value, Mapping):
        if "kind" not in value:
            raise WorldError(f"{where}: {key} needs kind = \"...\"")
        if not isinstance(value["kind"], str) or not value["kind"] or any(c in value["kind"] for c in ":,="):
            raise WorldError(f"{where}: {key}.kind = {shown(value['kind'])}: expected a name alone, e.g. \"circle\" "
                             "(its settings are keys beside it)")
        parts = []
        for k, v in value.items():
            if k == "kind":
                continue
            if k == "points":
                pairs_ok = isinstance(v, list) and all(
                    isinstance(pt, list) and len(pt) == 2 and all(_is_number(c) for c in pt) for pt in v)
                if not pairs_ok:
                    raise WorldError(f"{where}: {key}.points = {shown(v)}: expected [[x, z], [x, z], ...], pairs "
                                     "of numbers (metres)")
                parts += [_exact(c) for pt in v for c in pt]
            elif k == "closed":
                if not isinstance(v, bool):
                    raise WorldError(f"{where}: {key}.closed = {shown(v)}: expected true or false")
                if v:
                    parts.append("closed")
            elif _is_number(v) or (isinstance(v, str) and v and "," not in v):  # (a comma would split the text)
                parts.append(f"{k}={_exact(v)}" if _is_number(v) else f"{k}={v}")
            else:
                raise WorldError(f"{where}: {key}.{k} = {shown(v)}: expected a number, or a word or file name "
                                 "without commas")
        return f"{value['kind']}" + (":" + ",".join(parts) if parts else "")
    raise WorldError(f"{where}: {key} = {shown(value)}: expected a text like \"circle:r=3\" or a table with kind")


def _is_number(value: Any) -> bool:
    """An int or float from TOML (not a bool, which Python counts as an int)."""
    return isinstance(value, (int, float)) and not isinstance(value, bool)


def _exact(number: float) -> str:
    """A number as text that reads back as the same number (an int as written)."""
    return str(number) if isinstance(number, int) else repr(float(number))


MAX_SCENE_CREATURES = 256


def load_scene(file: str | os.PathLike[str]) -> Scene:
    """Read and check a scene TOML file (see ``scenes/`` for examples)."""
    path = FilePath(file)
    if not path.is_file():
        raise WorldError(f"{path}: no such scene file")
    try:
        data = read_toml(path)
    except TomlProblem as exc:
        raise WorldError(f"{path}: {exc}") from None
    where = str(path)
    for key in data:
        if key not in SCENE_KEYS:
            raise WorldError(f"{where}: unknown key {shown(key)}{did_you_mean(key, SCENE_KEYS)}; a scene has "
                             f"{', '.join(SCENE_KEYS)}")
    base = path.parent

    def wrap(fn: Callable[[], T], key: str) -> T:
        try:
            return fn()
        except WorldError as exc:
            text = str(exc)
            raise WorldError(text if text.startswith(where) else f"{where}: {key}: {text}") from None

    terrain: Terrain = wrap(lambda: parse_terrain(_text_or_table(data.get("terrain", "flat"), "terrain", where), base),
                            "terrain")
    paths_t = data.get("paths", {})
    if not isinstance(paths_t, Mapping):
        raise WorldError(f"{where}: paths must be a table of named paths ([paths.NAME])")
    def path_named(value: Any, key: str) -> Path:
        return wrap(lambda: parse_path(_text_or_table(value, key, where)), key)

    paths = {name: path_named(value, f"paths.{name}") for name, value in paths_t.items()}
    creatures_t = data.get("creatures")
    if not isinstance(creatures_t, list) or not creatures_t:
        raise WorldError(f"{where}: a scene needs at least one [[creatures]] table with creature = \"dog\" (or a "
                         ".toml file)")
    if len(creatures_t) > MAX_SCENE_CREATURES:
        raise WorldError(f"{where}: {len(creatures_t)} [[creatures]] tables; a scene holds at most "
                         f"{MAX_SCENE_CREATURES}")
    creatures = []
    for i, entry in enumerate(creatures_t):
        here = f"creatures[{i}]"
        if not isinstance(entry, Mapping):
            raise WorldError(f"{where}: {here} must be a table ([[creatures]])")
        for key in entry:
            if key not in CREATURE_KEYS:
                raise WorldError(f"{where}: {here}: unknown key {shown(key)}{did_you_mean(key, CREATURE_KEYS)}; allowed: "
                                 f"{', '.join(CREATURE_KEYS)}")
        name = entry.get("creature")
        if not isinstance(name, str) or not name:
            raise WorldError(f"{where}: {here}: give creature = \"dog\" (a preset) or a .toml file")
        if name.endswith(".toml") and not FilePath(name).is_absolute():
            name = str(base / name)
        path_value = entry.get("path", "straight")
        if isinstance(path_value, str) and path_value in paths:
            body_path = paths[path_value]
        else:
            body_path = path_named(path_value, f"{here}.path")
        speed = entry.get("speed")
        if speed is not None and (isinstance(speed, bool) or not isinstance(speed, (int, float))
                                  or not math.isfinite(speed) or not 0 < speed <= 30):
            raise WorldError(f"{where}: {here}.speed = {shown(speed)}: expected m/s in (0, 30]")
        overrides = entry.get("set", {})
        if not isinstance(overrides, Mapping):
            raise WorldError(f"{where}: {here}.set must be a table of creature keys, e.g. "
                             "set = { \"gait.duty_factor\" = 0.6 }")
        gait = entry.get("gait")
        if gait is not None and not isinstance(gait, str):
            raise WorldError(f"{where}: {here}.gait = {shown(gait)}: expected a gait name")
        herd = entry.get("herd", 1)
        if isinstance(herd, bool) or not isinstance(herd, int) or not 1 <= herd <= MAX_HERD:
            raise WorldError(f"{where}: {here}.herd = {shown(herd)}: give 1 to {MAX_HERD} animals (the creature "
                             "and herd - 1 more following it)")
        creatures.append(SceneCreature(creature=name, world=World(path=body_path, terrain=terrain), gait=gait,
                                       speed=None if speed is None else float(speed), overrides=dict(overrides),
                                       herd=herd))
    for key in ("name", "description"):
        if not isinstance(data.get(key, ""), str):
            raise WorldError(f"{where}: {key} = {shown(data[key])}: expected a text in quotes")
    name = data.get("name", path.stem)
    return Scene(name=str(name), terrain=terrain, creatures=tuple(creatures), source=str(path))


def scene_description(file: FilePath) -> str:
    """A scene file's one-line description (its ``description`` key), or its name."""
    try:
        data = read_toml(file)
    except TomlProblem:
        return FilePath(file).stem
    return str(data.get("description", data.get("name", FilePath(file).stem)))
