"""Paths, terrains and scenes from text and files: ``--path circle:r=3``, ``--terrain
hills:amp=0.2``, heightmap images, mesh files and scene TOML files.

The text form is ``KIND[:KEY=VALUE,...]``; ``gaitlab render --help`` lists every kind and
key. Every mistake raises :class:`~app.kinematics.world.WorldError` with one line naming
the text or file, the key or value, and what is allowed.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass, field
from pathlib import Path as FilePath
from typing import Any, Callable, Mapping

import numpy as np

from .tomlfile import TomlProblem, read_toml
from .kinematics.path import CirclePath, FigureEightPath, Path, StraightPath, WaypointPath
from .kinematics.terrain import (DEFAULT_MAX_SLOPE, FlatTerrain, HeightGrid, HillsTerrain, SlopeTerrain,
                                 StairsTerrain, Terrain)
from .kinematics.herd import MAX_HERD
from .kinematics.world import World, WorldError
from .errors import did_you_mean, shown

PATH_KINDS = {
    "straight": "straight ahead; heading=DEG turns the start (default 0: +Z)",
    "circle": "a circle; r=M (radius, > 0), dir=left|right (default left)",
    "figure-eight": "two touching circles, left loop then right; r=M (each loop's radius)",
    "waypoints": "a smooth curve (centripetal Catmull-Rom) through x,z pairs: waypoints:0,0,2,1,4,0 "
                 "(at least two points; add ',closed' to loop)",
}
TERRAIN_KINDS = {
    "flat": "the plane y = 0",
    "slope": "a plane; angle=DEG (rise, |angle| < 80), dir=DEG (uphill direction, 0 = +Z)",
    "hills": "rolling hills; amp=M (height, default 0.2), wavelength=M (default 3), seed=N",
    "stairs": "a flight of steps; rise=M (default 0.1), run=M (default 0.35), steps=N (default 12), "
              "start=M (first riser's distance, default 1), dir=DEG",
    "heightmap": "a greyscale image; file=PATH, size=M (width in metres, default 20), height=M (white, default 2)",
    "mesh": "a mesh file (OBJ, PLY, STL, glTF) sampled into a height grid; file=PATH, cell=M (grid spacing)",
}
COMMON_TERRAIN_KEYS = ("max_slope",)
FAR = 1e4  # m: no path or terrain size beyond this (ten kilometres)


def _split(text: str, what: str) -> tuple[str, list[str]]:
    if not isinstance(text, str) or not text.strip():
        raise WorldError(f"{what} {shown(text)}: expected KIND or KIND:KEY=VALUE,...")
    kind, _, rest = text.strip().partition(":")
    items = [item.strip() for item in rest.split(",")] if rest.strip() else []
    if any(not item for item in items):
        raise WorldError(f"{what} {shown(text)}: empty item between commas")
    return kind.strip().lower(), items


def _number(text: str, key: str, what: str, *, lo: float | None = None, hi: float | None = None,
            lo_open: bool = False, unit: str = "") -> float:
    try:
        value = float(text)
    except (TypeError, ValueError):
        raise WorldError(f"{what}: {key}={shown(text)} is not a number") from None
    if not math.isfinite(value):
        raise WorldError(f"{what}: {key}={shown(text)} is not a finite number")
    if lo is not None and (value < lo or (lo_open and value == lo)):
        raise WorldError(f"{what}: {key}={value:g} must be {'>' if lo_open else '>='} {lo:g}{unit}")
    if hi is not None and value > hi:
        raise WorldError(f"{what}: {key}={value:g} must be <= {hi:g}{unit}")
    return value


def _keys(items: list[str], allowed: Mapping[str, str], what: str) -> dict[str, str]:
    values: dict[str, str] = {}
    for item in items:
        key, eq, value = item.partition("=")
        key = key.strip().lower()
        if not eq:
            raise WorldError(f"{what}: {shown(item)} is not KEY=VALUE; keys here: {', '.join(allowed)}")
        if key not in allowed:
            raise WorldError(f"{what}: unknown key {shown(key)}{did_you_mean(key, allowed)}; keys here: "
                             f"{', '.join(allowed)}")
        if key in values:
            raise WorldError(f"{what}: {key} given twice")
        values[key] = value.strip()
    return values


def _kind(kind: str, kinds: Mapping[str, str], what: str, text: str) -> str:
    aliases = {"figure8": "figure-eight", "eight": "figure-eight", "spline": "waypoints"}
    kind = aliases.get(kind, kind)
    if kind not in kinds:
        raise WorldError(f"{what} {shown(text)}: unknown kind {shown(kind)}{did_you_mean(kind, kinds)}; kinds: "
                         f"{', '.join(kinds)}")
    return kind


def parse_path(text: str) -> Path:
    """A path from its text form, e.g. ``circle:r=3,dir=right``."""
    what = f"--path {shown(text)}" if isinstance(text, str) else "--path"
    kind, items = _split(text, "--path")
    kind = _kind(kind, PATH_KINDS, "--path", text)
    if kind == "waypoints":
        closed = "closed" in [i.lower() for i in items]
        numbers = [_number(i, "waypoint coordinate", what, lo=-FAR, hi=FAR, unit=" m") for i in items
                   if i.lower() != "closed"]
        if len(numbers) % 2:
            raise WorldError(f"{what}: waypoints are x,z pairs; got an odd count of numbers ({len(numbers)})")
        points = np.array(numbers).reshape(-1, 2)
        return waypoint_path(points, closed, what)
    keys = {"straight": ("heading",), "circle": ("r", "radius", "dir", "heading"),
            "figure-eight": ("r", "radius", "heading")}[kind]
    values = _keys(items, dict.fromkeys(keys, ""), what)
    heading = math.radians(_number(values["heading"], "heading", what)) if "heading" in values else 0.0
    if kind == "straight":
        return StraightPath(heading=heading)
    radius_text = values.get("r", values.get("radius"))
    if radius_text is None:
        raise WorldError(f"{what}: give the radius, e.g. {kind}:r=3 (metres, > 0)")
    radius = _number(radius_text, "r", what, lo=0.0, lo_open=True, unit=" m")
    if radius > FAR:
        raise WorldError(f"{what}: r={radius:g} must be <= {FAR:g} m")
    if kind == "circle":
        direction = values.get("dir", "left").lower()
        if direction not in ("left", "right"):
            raise WorldError(f"{what}: dir={shown(direction)}; expected left or right")
        return CirclePath(radius, direction, heading=heading)
    return FigureEightPath(radius, heading=heading)


def waypoint_path(points: np.ndarray, closed: bool, what: str) -> WaypointPath:
    if len(points) < 2:
        raise WorldError(f"{what}: a waypoint path needs at least two points (x,z pairs); got {len(points)}")
    if np.any(np.linalg.norm(np.diff(points, axis=0), axis=1) < 1e-6) or (
            closed and np.linalg.norm(points[0] - points[-1]) < 1e-6):
        raise WorldError(f"{what}: two waypoints in a row are the same point; give distinct points")
    if closed and len(points) < 3:
        raise WorldError(f"{what}: a closed waypoint path needs at least three points")
    return WaypointPath(points, closed=closed)


def parse_terrain(text: str, base: FilePath | None = None) -> Terrain:
    """A terrain from its text form, e.g. ``hills:amp=0.2,wavelength=3``. File names are
    relative to ``base`` (a scene file's folder) or the working folder."""
    what = f"--terrain {shown(text)}" if isinstance(text, str) else "--terrain"
    kind, items = _split(text, "--terrain")
    kind = _kind(kind, TERRAIN_KINDS, "--terrain", text)
    keys = {"flat": (), "slope": ("angle", "dir"), "hills": ("amp", "wavelength", "seed"),
            "stairs": ("rise", "run", "steps", "start", "dir"), "heightmap": ("file", "size", "height"),
            "mesh": ("file", "cell")}[kind] + COMMON_TERRAIN_KEYS
    values = _keys(items, dict.fromkeys(keys, ""), what)
    num = lambda key, default, **kw: (_number(values[key], key, what, **kw)  # noqa: E731
                                      if key in values else default)
    max_slope = math.radians(num("max_slope", math.degrees(DEFAULT_MAX_SLOPE), lo=1.0, hi=89.0, unit=" deg"))
    direction = math.radians(num("dir", 0.0))
    if kind == "flat":
        return FlatTerrain(max_slope)
    if kind == "slope":
        if "angle" not in values:
            raise WorldError(f"{what}: give the angle, e.g. slope:angle=15 (degrees)")
        angle = num("angle", 0.0, lo=-80.0, hi=80.0, unit=" deg")
        return SlopeTerrain(math.radians(angle), direction, max_slope)
    if kind == "hills":
        seed = num("seed", 1.0, lo=0.0)
        if seed != int(seed):
            raise WorldError(f"{what}: seed={seed:g} must be a whole number")
        return HillsTerrain(num("amp", 0.2, lo=0.0, hi=100.0, unit=" m"),
                            num("wavelength", 3.0, lo=0.0, lo_open=True, hi=FAR, unit=" m"),
                            int(seed), max_slope)
    if kind == "stairs":
        steps = num("steps", 12.0, lo=1.0, hi=1000.0)
        if steps != int(steps):
            raise WorldError(f"{what}: steps={steps:g} must be a whole number")
        return StairsTerrain(num("rise", 0.1, lo=-10.0, hi=10.0, unit=" m"),
                             num("run", 0.35, lo=0.005, hi=FAR, unit=" m"), int(steps),
                             num("start", 1.0, lo=-FAR, hi=FAR, unit=" m"), direction, max_slope)
    if "file" not in values or not values["file"]:
        raise WorldError(f"{what}: give the file, e.g. {kind}:file=ground.{'png' if kind == 'heightmap' else 'obj'}")
    file = FilePath(values["file"])
    if base is not None and not file.is_absolute():
        file = base / file
    if kind == "heightmap":
        return load_heightmap(file, num("size", 20.0, lo=0.0, lo_open=True, unit=" m"),
                              num("height", 2.0, lo=0.0, hi=FAR, unit=" m"), max_slope)
    return load_mesh_terrain(file, num("cell", 0.0, lo=0.0), max_slope)


def _check_file(file: FilePath) -> None:
    if not file.is_file():
        raise WorldError(f"{file}: no such file")


def load_heightmap(file: FilePath, size: float, height: float, max_slope: float = DEFAULT_MAX_SLOPE) -> HeightGrid:
    """A greyscale image as ground: its width spans ``size`` m (centred on the origin, rows
    along +Z), black at 0 and white at ``height`` m. 8- and 16-bit images keep their depth."""
    from PIL import Image, UnidentifiedImageError

    _check_file(file)
    try:
        with Image.open(file) as image:
            image.load()
            mode = image.mode
            if mode in ("I;16", "I;16B", "I;16L", "I"):
                data = np.asarray(image, dtype=np.float64)
                top = 65535.0 if mode.startswith("I;16") else max(float(data.max()), 1.0)
            elif mode == "F":
                data = np.asarray(image, dtype=np.float64)
                top = max(float(data.max()), 1e-12)
            else:
                data = np.asarray(image.convert("L"), dtype=np.float64)
                top = 255.0
    except (UnidentifiedImageError, OSError, SyntaxError, ValueError) as exc:
        raise WorldError(f"{file}: not an image Gaitlab can read as a heightmap ({type(exc).__name__}); "
                         "give a PNG (8- or 16-bit greyscale)") from None
    if data.ndim != 2 or min(data.shape) < 2:
        raise WorldError(f"{file}: a heightmap needs at least 2x2 pixels, got {data.shape[::-1]}")
    if not np.all(np.isfinite(data)):
        raise WorldError(f"{file}: the image holds values that are not finite numbers")
    rows, cols = data.shape
    depth = size * (rows - 1) / (cols - 1)
    heights = data / top * height
    return HeightGrid(heights, (-0.5 * size, -0.5 * depth), (size, depth),
                      label=f"heightmap:file={file},size={size:g},height={height:g}", max_slope=max_slope)


MAX_GRID = 1024


def load_mesh_terrain(file: FilePath, cell: float = 0.0, max_slope: float = DEFAULT_MAX_SLOPE) -> HeightGrid:
    """A mesh file (anything trimesh reads: OBJ, PLY, STL, glTF/GLB) as a height grid: the
    highest surface above each grid point, found by casting rays straight down (up is +Y).
    ``cell`` is the grid spacing in metres (default: the mesh's size / 256)."""
    import trimesh

    _check_file(file)
    try:
        loaded = trimesh.load(str(file), force="mesh")
    except Exception as exc:  # trimesh raises many kinds for broken files
        raise WorldError(f"{file}: cannot read the mesh ({type(exc).__name__}: {str(exc)[:80]})") from None
    faces = getattr(loaded, "faces", None)
    if faces is None or len(faces) == 0:
        raise WorldError(f"{file}: the mesh has no faces; a terrain mesh needs triangles")
    vertices = np.asarray(loaded.vertices, dtype=np.float64)
    if not np.all(np.isfinite(vertices)):
        raise WorldError(f"{file}: the mesh has vertices that are not finite numbers")
    lo, hi = vertices.min(axis=0), vertices.max(axis=0)
    extent = max(hi[0] - lo[0], hi[2] - lo[2])
    if extent <= 0:
        raise WorldError(f"{file}: the mesh has no extent on the ground (x, z)")
    cell = cell or extent / 256.0
    cols = int(min(MAX_GRID, math.ceil((hi[0] - lo[0]) / cell) + 1))
    rows = int(min(MAX_GRID, math.ceil((hi[2] - lo[2]) / cell) + 1))
    xs = np.linspace(lo[0], hi[0], max(cols, 2))
    zs = np.linspace(lo[2], hi[2], max(rows, 2))
    gx, gz = np.meshgrid(xs, zs, indexing="xy")
    origins = np.column_stack([gx.ravel(), np.full(gx.size, hi[1] + 1.0), gz.ravel()])
    directions = np.broadcast_to([0.0, -1.0, 0.0], origins.shape)
    heights = np.full(gx.size, lo[1])
    locations, index_ray, _ = loaded.ray.intersects_location(origins, directions, multiple_hits=False)
    if len(index_ray):
        hit = np.full(gx.size, -np.inf)
        np.maximum.at(hit, index_ray, locations[:, 1])
        heights = np.where(np.isfinite(hit), hit, lo[1])  # no surface above a point: the mesh's lowest
    grid = heights.reshape(len(zs), len(xs))
    return HeightGrid(grid, (float(lo[0]), float(lo[2])), (float(hi[0] - lo[0]), float(hi[2] - lo[2])),
                      label=f"mesh:file={file}", max_slope=max_slope)


# -- scenes ---------------------------------------------------------------------------


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
        parts = []
        for k, v in value.items():
            if k == "kind":
                continue
            if k == "points" and isinstance(v, list):
                parts += [f"{c:g}" if isinstance(c, (int, float)) else str(c) for pt in v for c in
                          (pt if isinstance(pt, list) else [pt])]
            elif k == "closed":
                if not isinstance(v, bool):
                    raise WorldError(f"{where}: {key}.closed = {shown(v)}: expected true or false")
                if v:
                    parts.append("closed")
            else:
                parts.append(f"{k}={v}")
        return f"{value['kind']}" + (":" + ",".join(parts) if parts else "")
    raise WorldError(f"{where}: {key} = {shown(value)}: expected a text like \"circle:r=3\" or a table with kind")


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

    def wrap(fn: Callable[[], Any], key: str) -> Any:
        try:
            return fn()
        except WorldError as exc:
            text = str(exc)
            raise WorldError(text if text.startswith(where) else f"{where}: {key}: {text}") from None

    terrain = wrap(lambda: parse_terrain(_text_or_table(data.get("terrain", "flat"), "terrain", where), base),
                   "terrain")
    paths_t = data.get("paths", {})
    if not isinstance(paths_t, Mapping):
        raise WorldError(f"{where}: paths must be a table of named paths ([paths.NAME])")
    paths = {name: wrap(lambda v=value, n=name: parse_path(_text_or_table(v, f"paths.{n}", where)), f"paths.{name}")
             for name, value in paths_t.items()}
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
            body_path = wrap(lambda v=path_value: parse_path(_text_or_table(v, f"{here}.path", where)),
                             f"{here}.path")
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
    name = data.get("name", path.stem)
    return Scene(name=str(name), terrain=terrain, creatures=tuple(creatures), source=str(path))


def scene_description(file: FilePath) -> str:
    """A scene file's one-line description (its ``description`` key), or its name."""
    try:
        data = read_toml(file)
    except TomlProblem:
        return FilePath(file).stem
    return str(data.get("description", data.get("name", FilePath(file).stem)))


def make_world(path: str | Path | None = None, terrain: str | Terrain | None = None,
               in_place: bool = False) -> World:
    """A World from text forms or objects (``None``: straight ahead, flat ground)."""
    body_path = parse_path(path) if isinstance(path, str) else (path or StraightPath())
    ground = parse_terrain(terrain) if isinstance(terrain, str) else (terrain or FlatTerrain())
    return World(path=body_path, terrain=ground, in_place=in_place)
