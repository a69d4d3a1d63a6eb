"""The command line's shared options, each declared once: what a clip is of (a creature
or scene, ``--gait``, ``--set``, the animator's ``--style`` and ``--frames-per-cycle``,
``--speed``), where it walks (``--path``, ``--terrain``, ``--in-place``) and how long it
is. Values are checked as they are parsed (numbers through :class:`app.numbers.Range`),
so a bad one is a one-line usage error with exit status 2.

Imports only leaf modules: ``gaitlab --help`` and ``--version`` start without numpy.
"""

from __future__ import annotations

import argparse
from collections.abc import Callable
from pathlib import Path

from ..choices import MAX_CRF, MAX_HERD, MAX_SIZE, OVERLAYS, PANEL_TITLES
from ..gaits import GAIT_PRESETS
from ..limits import MAX_FPS, MAX_SECONDS, MAX_SPEED, MIN_FPS
from ..numbers import NumberProblem, Range
from ..styles import WALK_STYLES
from ..worlds.kinds import PATH_KINDS, TERRAIN_KINDS, path_usage, terrain_usage

EXIT_BAD_INPUT = 2


class Parser(argparse.ArgumentParser):
    """argparse, but a usage error is one line (and still exit status 2)."""

    def error(self, message: str) -> None:  # type: ignore[override]
        self.exit(EXIT_BAD_INPUT, f"{self.prog}: error: {message} (see '{self.prog} --help')\n")


def size(text: str) -> tuple[int, int]:
    """``WxH`` in pixels."""
    try:
        w_text, h_text = text.lower().split("x")
        w, h = int(w_text), int(h_text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r}: expected WIDTHxHEIGHT in pixels, e.g. 480x360") from None
    if not (1 <= w <= MAX_SIZE and 1 <= h <= MAX_SIZE):
        raise argparse.ArgumentTypeError(f"{text!r}: width and height must be between 1 and {MAX_SIZE} pixels")
    return w, h


def positive(name: str, upper: float, least: float | None = None) -> Callable[[str], float]:
    """A number in (0, ``upper``] of ``name`` (the unit, for the message); in
    [``least``, ``upper``] when ``least`` is given."""
    allowed = Range(0.0, upper, lo_open=True) if least is None else Range(least, upper)
    bounds = "greater than 0" if least is None else f"at least {least:g}"

    def parse(text: str) -> float:
        try:
            return allowed.check(text)
        except NumberProblem as exc:
            if str(exc) == "is not a number":
                raise argparse.ArgumentTypeError(f"{text!r}: expected a number") from None
            raise argparse.ArgumentTypeError(f"{text!r}: must be {bounds} and at most {upper:g} {name}") from None

    return parse


def jobs(text: str) -> int:
    """A number of worker processes, 1 to 64."""
    try:
        return int(Range(1, 64, integer=True).check(text))
    except NumberProblem:
        raise argparse.ArgumentTypeError(f"{text!r}: expected a whole number of processes from 1 to 64") from None


def seconds_from_zero(text: str) -> float:
    """A finite number of seconds >= 0."""
    try:
        return Range(0.0).check(text)
    except NumberProblem as exc:
        if str(exc) == "is not a number":
            raise argparse.ArgumentTypeError(f"{text!r}: expected a number of seconds") from None
        raise argparse.ArgumentTypeError(f"{text!r}: must be a finite number of seconds >= 0") from None


def speed(text: str) -> tuple[float, float]:
    """``V`` or a ramp ``V0:V1`` in m/s."""
    allowed = Range(0.0, MAX_SPEED, lo_open=True)
    parts = text.split(":")
    try:
        values = [allowed.check(p) for p in parts]
    except NumberProblem as exc:
        if str(exc) == "is not a number":
            raise argparse.ArgumentTypeError(f"{text!r}: expected a speed in m/s (e.g. 1.5) or a ramp V0:V1 "
                                             "(e.g. 0.5:6)") from None
        raise argparse.ArgumentTypeError(f"{text!r}: speeds must be in (0, {MAX_SPEED:g}] m/s, as V or V0:V1") from None
    if len(values) not in (1, 2):
        raise argparse.ArgumentTypeError(f"{text!r}: speeds must be in (0, {MAX_SPEED:g}] m/s, as V or V0:V1")
    return (values[0], values[-1])


def overlays(text: str) -> tuple[str, ...]:
    names = tuple(dict.fromkeys(n.strip() for n in text.split(",") if n.strip()))
    unknown = [n for n in names if n not in OVERLAYS]
    if unknown or not names:
        raise argparse.ArgumentTypeError(f"{text!r}: expected a comma-separated list of {', '.join(OVERLAYS)}")
    return names


def panels(text: str) -> tuple[str, ...]:
    """Panel titles from a comma-separated list of their names (``plots,key-poses``)."""
    by_name = {title.lower().replace(" ", "-"): title for title in PANEL_TITLES}
    names = [n.strip().lower() for n in text.split(",") if n.strip()]
    unknown = [n for n in names if n not in by_name]
    if unknown or not names:
        raise argparse.ArgumentTypeError(f"{text!r}: expected a comma-separated list of {', '.join(by_name)}")
    return tuple(dict.fromkeys(by_name[n] for n in names))


def herd(text: str) -> int:
    try:
        return int(Range(1, MAX_HERD, integer=True).check(text))
    except NumberProblem:
        raise argparse.ArgumentTypeError(f"{text!r}: give 1 to {MAX_HERD} animals (the creature and N - 1 "
                                         "more)") from None


def samples(text: str) -> int:
    if text not in ("0", "2", "4", "8"):
        raise argparse.ArgumentTypeError(f"{text!r}: expected 0 (off), 2, 4 or 8 samples")
    return int(text)


def crf(text: str) -> int:
    try:
        return int(Range(0, MAX_CRF, integer=True).check(text))
    except NumberProblem:
        raise argparse.ArgumentTypeError(f"{text!r}: expected a whole number from 0 to {MAX_CRF}") from None


# -- groups ----------------------------------------------------------------------------


def add_creature(parser: argparse.ArgumentParser, default: str = "dog", scenes: bool = True) -> None:
    """The creature (or scene file) and the changes to it: ``--gait``, ``--set``,
    ``--style`` and ``--frames-per-cycle``."""
    what = "preset name, creature .toml, a rigged model .glb/.gltf" + (" or scene .toml" if scenes else "")
    parser.add_argument("creature", nargs="?", default=default, metavar="CREATURE", help=f"{what} (default: {default})")
    group = parser.add_argument_group("the creature")
    group.add_argument("--rig", metavar="MAP.toml",
                       help="for a rigged model: which of its joints are its legs, when their names do not say "
                            "([legs] with LF = [\"shoulder\", \"elbow\", \"wrist\"], RF, LH, RH, ... front pair "
                            "first, each list from the top of the leg down to the foot; a biped's [arms] with L "
                            "and R, each upper arm, forearm and wrist; [neck] and [tail], each joints = [...] from "
                            "the base out)")
    group.add_argument("--gait", metavar="G", help=f"gait preset: {', '.join(GAIT_PRESETS)}")
    group.add_argument("--set", metavar="KEY=VALUE", action="append", default=[], dest="overrides",
                       help="override a creature key, e.g. gait.duty_factor=0.7 (repeatable; 'gaitlab creatures "
                            "--keys' lists them)")
    group.add_argument("--style", metavar="STYLE",
                       help=f"walk style to start the key poses from: {', '.join(WALK_STYLES)} (writes the "
                            "style's heights, foot angle, arm swing, torso lean and stride; --set adjusts them)")
    group.add_argument("--frames-per-cycle", metavar="N", type=positive("frames per cycle", 10000),
                       help="timing in frames per cycle (two steps) instead of a frequency, counted at the "
                            "creature's gait.timing_fps (24 unless it gives one): a normal walk is 24 (a step on "
                            "twelves); the same as --set gait.frames_per_cycle=N")


def add_speed(parser: argparse.ArgumentParser, default_seconds: bool = True) -> None:
    parser.add_argument("--speed", metavar="V[:V1]", type=speed,
                        help="speed in m/s, or a ramp V0:V1 over the clip: the gait follows the speed (by Froude "
                             "number: walk, trot, gallop for four legs; walk, run for two; the creature's own gait "
                             "scaled for more)" + ("; default length 4 s" if default_seconds else ""))


def add_world(parser: argparse.ArgumentParser) -> None:
    group = parser.add_argument_group("where it walks")
    group.add_argument("--path", metavar="KIND[:K=V,...]",
                       help="the body's path: " + ", ".join(k.example or k.name for k in PATH_KINDS.values())
                            + " (see the list below)")
    group.add_argument("--terrain", metavar="KIND[:K=V,...]",
                       help="the ground: " + ", ".join(k.example or k.name for k in TERRAIN_KINDS.values()))
    group.add_argument("--in-place", action="store_true",
                       help="walk on the spot while the ground moves under the feet (flat, straight only)")


def add_clip(parser: argparse.ArgumentParser, output_help: str, cycles_help: str, fps: float) -> None:
    """The output and the clip's length (render and export)."""
    parser.add_argument("-o", "--output", metavar="OUT", type=Path, help=output_help)
    length = parser.add_mutually_exclusive_group()
    length.add_argument("--seconds", metavar="S", type=positive("seconds", MAX_SECONDS), help="clip length in seconds")
    length.add_argument("--cycles", metavar="N", type=positive("cycles", MAX_SECONDS), help=cycles_help)
    parser.add_argument("--fps", metavar="F", type=positive("frames per second", MAX_FPS, least=MIN_FPS), default=None,
                        help=f"frames per second (default: {fps:g}, or the creature's timing frame rate when its "
                             "timing is given in frames per cycle)")
    parser.set_defaults(default_fps=fps)


def world_help() -> str:
    """The --path and --terrain kinds and keys, from the registry (for epilogs)."""
    return ("--path KIND[:KEY=VALUE,...]:\n  " + "  ".join(path_usage()) + "\n"
            "--terrain KIND[:KEY=VALUE,...]  (every kind also takes max_slope=DEG, default 40):\n  "
            + "\n  ".join(terrain_usage()) + "\n")
