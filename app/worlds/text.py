"""Paths and terrains from their text form, ``KIND[:KEY=VALUE,...]``: ``--path circle:r=3``,
``--terrain hills:amp=0.2``, the same in scene files and the viewer's panels.

The kinds and keys are those of :mod:`.kinds`. Every mistake raises
:class:`~app.kinematics.world.WorldError` with one line naming the text, the key or
value, and what is allowed.
"""

from __future__ import annotations

import math
from pathlib import Path as FilePath
from typing import Any

import numpy as np

from ..errors import did_you_mean, shown
from ..kinematics.path import CirclePath, FigureEightPath, Path, StraightPath, WaypointPath
from ..kinematics.terrain import FlatTerrain, HillsTerrain, SlopeTerrain, StairsTerrain, Terrain
from ..kinematics.world import World, WorldError
from ..numbers import NumberProblem, Range
from .kinds import FAR, MAX_SLOPE, PATH_ALIASES, PATH_KEY_ALIASES, PATH_KINDS, TERRAIN_KINDS, Kind

_WAYPOINT = Range(-FAR, FAR, unit="m")


def _split(text: str, what: str) -> tuple[str, list[str]]:
    if not isinstance(text, str) or not text.strip():
        raise WorldError(f"{what} {shown(text)}: expected KIND or KIND:KEY=VALUE,...")
    kind, _, rest = text.strip().partition(":")
    items = [item.strip() for item in rest.split(",")] if rest.strip() else []
    if any(not item for item in items):
        raise WorldError(f"{what} {shown(text)}: empty item between commas")
    return kind.strip().lower(), items


def _number(text: str, key: str, what: str, allowed: Range) -> float:
    """``text`` as a number within ``allowed``, or one line: ``--terrain ...: amp=-1 must be >= 0 m``."""
    try:
        return allowed.check(text, phrasing="bound")
    except NumberProblem as exc:
        reason = str(exc)
        if reason.startswith(("is not", "not a finite", "expected")):
            word = "is not a finite number" if reason.startswith("not a finite") else "is not a number"
            raise WorldError(f"{what}: {key}={shown(text)} {word}") from None
        shown_value = text if not isinstance(text, str) else f"{float(text):g}"
        raise WorldError(f"{what}: {key}={shown_value} {reason}") from None


def _kind(kind: str, kinds: dict[str, Kind], what: str, text: str) -> Kind:
    kind = PATH_ALIASES.get(kind, kind)
    if kind not in kinds:
        raise WorldError(f"{what} {shown(text)}: unknown kind {shown(kind)}{did_you_mean(kind, kinds)}; kinds: "
                         f"{', '.join(kinds)}")
    return kinds[kind]


def read_values(kind: Kind, items: list[str], what: str, extra: tuple[Any, ...] = ()) -> dict[str, Any]:
    """The ``KEY=VALUE`` items of ``kind`` (and the ``extra`` keys every kind takes),
    checked against their ranges and choices, defaults filled in; a required key that
    is missing is one line with an example."""
    keys = {k.name: k for k in (*kind.keys, *extra)}
    given: dict[str, str] = {}
    for item in items:
        name, eq, value = item.partition("=")
        name = PATH_KEY_ALIASES.get(name.strip().lower(), name.strip().lower())
        if not eq:
            raise WorldError(f"{what}: {shown(item)} is not KEY=VALUE; keys here: {', '.join(keys)}")
        if name not in keys:
            raise WorldError(f"{what}: unknown key {shown(name)}{did_you_mean(name, keys)}; keys here: "
                             f"{', '.join(keys)}")
        if name in given:
            raise WorldError(f"{what}: {name} given twice")
        given[name] = value.strip()
    values: dict[str, Any] = {}
    for name, key in keys.items():
        if name not in given:
            if name in kind.required:
                example = kind.example or f"{kind.name}:{key.usage()}"
                unit = f" ({'metres, > 0' if key.unit == 'm' else 'degrees' if key.unit == 'deg' else key.help})"
                raise WorldError(f"{what}: give the {'radius' if name == 'r' else name}, e.g. {example}"
                                 f"{unit if key.range is not None else ''}")
            values[name] = key.default
        elif key.choices:
            choice = given[name].lower()
            if choice not in key.choices:
                raise WorldError(f"{what}: {name}={shown(choice)}; expected {' or '.join(key.choices)}")
            values[name] = choice
        elif key.range is None:
            values[name] = given[name]
        else:
            values[name] = _whole_or_number(given[name], key.range, name, what)
    return values


def _whole_or_number(text: str, allowed: Range, name: str, what: str) -> float:
    if not allowed.integer:
        return _number(text, name, what, allowed)
    number = _number(text, name, what, Range(allowed.lo, allowed.hi, unit=allowed.unit))
    if number != int(number):
        raise WorldError(f"{what}: {name}={number:g} must be a whole number")
    return int(number)


def parse_path(text: str) -> Path:
    """A path from its text form, e.g. ``circle:r=3,dir=right``."""
    what = f"--path {shown(text)}" if isinstance(text, str) else "--path"
    name, items = _split(text, "--path")
    kind = _kind(name, PATH_KINDS, "--path", text)
    if kind.name == "waypoints":
        closed = "closed" in [i.lower() for i in items]
        numbers = [_number(i, "waypoint coordinate", what, _WAYPOINT) for i in items if i.lower() != "closed"]
        if len(numbers) % 2:
            raise WorldError(f"{what}: waypoints are x,z pairs; got an odd count of numbers ({len(numbers)})")
        return waypoint_path(np.array(numbers).reshape(-1, 2), closed, what)
    values = read_values(kind, items, what)
    heading = math.radians(values["heading"])
    if kind.name == "straight":
        return StraightPath(heading=heading)
    if kind.name == "circle":
        return CirclePath(values["r"], values["dir"], heading=heading)
    return FigureEightPath(values["r"], heading=heading)


def waypoint_path(points: np.ndarray, closed: bool, what: str, start_direction: np.ndarray | None = None
                  ) -> WaypointPath:
    """A smooth path through ``points`` (N, 2) x, z in metres (leaving along
    ``start_direction`` when given); one line for too few or repeated points."""
    if len(points) < 2:
        raise WorldError(f"{what}: a waypoint path needs at least two points (x,z pairs); got {len(points)}")
    if np.any(np.linalg.norm(np.diff(points, axis=0), axis=1) < 1e-6) or (
            closed and np.linalg.norm(points[0] - points[-1]) < 1e-6):
        raise WorldError(f"{what}: two waypoints in a row are the same point; give distinct points")
    if closed and len(points) < 3:
        raise WorldError(f"{what}: a closed waypoint path needs at least three points")
    return WaypointPath(points, closed=closed, start_direction=start_direction)


def parse_terrain(text: str, base: FilePath | None = None) -> Terrain:
    """A terrain from its text form, e.g. ``hills:amp=0.2,wavelength=3``. File names are
    relative to ``base`` (a scene file's folder) or the working folder."""
    from .files import load_heightmap, load_mesh_terrain

    what = f"--terrain {shown(text)}" if isinstance(text, str) else "--terrain"
    name, items = _split(text, "--terrain")
    kind = _kind(name, TERRAIN_KINDS, "--terrain", text)
    values = read_values(kind, items, what, extra=(MAX_SLOPE,))
    max_slope = math.radians(values["max_slope"])
    if kind.name == "flat":
        return FlatTerrain(max_slope)
    if kind.name == "slope":
        return SlopeTerrain(math.radians(values["angle"]), math.radians(values["dir"]), max_slope)
    if kind.name == "hills":
        return HillsTerrain(values["amp"], values["wavelength"], values["seed"], max_slope)
    if kind.name == "stairs":
        return StairsTerrain(values["rise"], values["run"], values["steps"], values["start"],
                             math.radians(values["dir"]), max_slope)
    if not values["file"]:
        raise WorldError(f"{what}: give the file, e.g. {kind.example}")
    file = FilePath(values["file"])
    if base is not None and not file.is_absolute():
        file = base / file
    if kind.name == "heightmap":
        return load_heightmap(file, values["size"], values["height"], max_slope)
    return load_mesh_terrain(file, values["cell"], max_slope)


def make_world(path: str | Path | None = None, terrain: str | Terrain | None = None,
               in_place: bool = False) -> World:
    """A World from text forms or objects (``None``: straight ahead, flat ground)."""
    body_path = parse_path(path) if isinstance(path, str) else (path or StraightPath())
    ground = parse_terrain(terrain) if isinstance(terrain, str) else (terrain or FlatTerrain())
    return World(path=body_path, terrain=ground, in_place=in_place)
