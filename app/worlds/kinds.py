"""The one registry of path and terrain kinds: each kind's keys with their units,
accepted ranges, defaults, help and the range a slider covers.

The text parser (``--path circle:r=3``, ``--terrain hills:amp=0.2``), scene files, the
viewer's Path and Terrain panels, ``gaitlab render --help`` and the README's tables all
read these tables (a test checks the README against them), so a key is declared once.
"""

from __future__ import annotations

from dataclasses import dataclass

from ..numbers import Range

FAR = 1e4  # m: no path or terrain size beyond this (ten kilometres)


@dataclass(frozen=True)
class Key:
    """One key of a kind. ``range`` is what the text accepts (None for text and
    choices); ``slider`` the span the viewer's slider offers (a part of ``range``);
    ``fmt`` the slider's printf format; ``unit`` as the user reads it."""

    name: str
    help: str
    default: float | str | None = None
    range: Range | None = None
    slider: tuple[float, float] | None = None
    fmt: str = "%.3f"
    choices: tuple[str, ...] = ()
    unit: str = ""

    @property
    def integer(self) -> bool:
        return self.range is not None and self.range.integer

    def usage(self) -> str:
        """``amp=M`` style: the key and what it takes, for one-line help."""
        what = ("|".join(self.choices) if self.choices else "PATH" if self.name == "file" else
                "N" if self.integer else {"deg": "DEG", "m": "M"}.get(self.unit, "X"))
        return f"{self.name}={what}"


@dataclass(frozen=True)
class Kind:
    """A path or terrain kind: its name, a one-line description and its keys (the
    ``required`` ones must be given)."""

    name: str
    help: str
    keys: tuple[Key, ...] = ()
    required: tuple[str, ...] = ()
    example: str = ""

    def key(self, name: str) -> Key:
        return next(k for k in self.keys if k.name == name)

    def usage(self) -> str:
        """``hills[:amp=M,wavelength=M,seed=N]``: the kind and its keys, optional ones bracketed."""
        need = [k.usage() for k in self.keys if k.name in self.required]
        rest = [k.usage() for k in self.keys if k.name not in self.required]
        text = self.name + (":" + ",".join(need) if need else "")
        if rest:
            text += f"[{',' if need else ':'}{','.join(rest)}]"
        return text


def _m(name: str, help: str, default: float | None, lo: float | None, hi: float | None, slider=None,
       lo_open: bool = False, fmt: str = "%.3f m") -> Key:
    return Key(name, help, default, Range(lo, hi, lo_open=lo_open, unit="m"), slider, fmt, unit="m")


def _deg(name: str, help: str, default: float | None, lo: float | None = None, hi: float | None = None,
         slider=(-180.0, 180.0), fmt: str = "%.0f deg") -> Key:
    return Key(name, help, default, Range(lo, hi, unit="deg"), slider, fmt, unit="deg")


def _whole(name: str, help: str, default: int, lo: float, hi: float | None, slider) -> Key:
    return Key(name, help, default, Range(lo, hi, integer=True), slider, "%d")


HEADING = _deg("heading", "the direction the path starts in, degrees from +Z", 0.0, -3600.0, 3600.0)

PATH_KINDS: dict[str, Kind] = {kind.name: kind for kind in (
    Kind("straight", "straight ahead", (HEADING,)),
    Kind("circle", "a circle", (
        _m("r", "the radius", 2.0, 0.0, FAR, (0.2, 20.0), lo_open=True, fmt="%.2f m"),
        Key("dir", "which way it turns", "left", choices=("left", "right")),
        HEADING), required=("r",), example="circle:r=3"),
    Kind("figure-eight", "two touching circles, left loop then right", (
        _m("r", "each loop's radius", 2.0, 0.0, FAR, (0.2, 20.0), lo_open=True, fmt="%.2f m"),
        HEADING), required=("r",), example="figure-eight:r=2"),
    Kind("waypoints", "a smooth curve (centripetal Catmull-Rom) through x,z pairs in metres: "
                      "waypoints:0,0,2,1,4,0 (at least two points; add ',closed' to loop)",
         example="waypoints:0,0,1.5,2,0,4"),
)}
PATH_ALIASES = {"figure8": "figure-eight", "eight": "figure-eight", "spline": "waypoints"}
PATH_KEY_ALIASES = {"radius": "r"}

MAX_SLOPE = _deg("max_slope", "the steepest ground a foot may stand on", 40.0, 1.0, 89.0, slider=None)

TERRAIN_KINDS: dict[str, Kind] = {kind.name: kind for kind in (
    Kind("flat", "the plane y = 0"),
    Kind("slope", "a plane", (
        _deg("angle", "rise of the plane (negative: downhill ahead)", 10.0, -80.0, 80.0, slider=(-35.0, 35.0),
             fmt="%.1f deg"),
        _deg("dir", "the direction the slope rises, degrees from +Z", 0.0, -3600.0, 3600.0)), required=("angle",),
         example="slope:angle=15"),
    Kind("hills", "rolling hills", (
        _m("amp", "how high and low the hills go", 0.2, 0.0, 100.0, (0.0, 1.0)),
        _m("wavelength", "typical distance between hilltops", 3.0, 0.0, FAR, (0.2, 20.0), lo_open=True,
           fmt="%.2f m"),
        _whole("seed", "which random hills", 1, 0.0, None, (0, 99))), example="hills:amp=0.2"),
    Kind("stairs", "a flight of steps", (
        _m("rise", "each step's height (negative: down)", 0.1, -10.0, 10.0, (-0.5, 0.5)),
        _m("run", "each step's depth", 0.35, 0.005, FAR, (0.02, 2.0)),
        _whole("steps", "how many steps", 12, 1.0, 1000.0, (1, 60)),
        _m("start", "distance from the start to the first riser", 1.0, -FAR, FAR, (-10.0, 20.0), fmt="%.2f m"),
        _deg("dir", "the direction the flight climbs, degrees from +Z", 0.0, -3600.0, 3600.0)),
         example="stairs:rise=0.1,run=0.35"),
    Kind("heightmap", "a greyscale image (8- or 16-bit PNG)", (
        Key("file", "the image's path"),
        _m("size", "the image's width on the ground", 20.0, 0.0, None, (1.0, 200.0), lo_open=True, fmt="%.1f m"),
        _m("height", "the height of white pixels (black is 0)", 2.0, 0.0, FAR, (0.0, 10.0), fmt="%.2f m")),
         required=("file",), example="heightmap:file=ground.png"),
    Kind("mesh", "a mesh file (OBJ, PLY, STL, glTF) sampled into a height grid", (
        Key("file", "the mesh's path"),
        _m("cell", "the grid spacing (0: the mesh's size / 256)", 0.0, 0.0, None, (0.0, 2.0))),
         required=("file",), example="mesh:file=ground.obj"),
)}


def path_usage() -> list[str]:
    """One line per path kind, for ``--help``."""
    return [k.usage() if k.name != "waypoints" else "waypoints:X,Z,X,Z,...[,closed]" for k in PATH_KINDS.values()]


def terrain_usage() -> list[str]:
    """One line per terrain kind, for ``--help``."""
    return [k.usage() for k in TERRAIN_KINDS.values()]
