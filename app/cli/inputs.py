"""From the command line's words to what a command works on: the creature with its
changes (``--gait``, ``--set``, ``--style``, ``--frames-per-cycle``), and the cast of a
clip (that creature on ``--path`` / ``--terrain``, or every creature of a scene file)."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import TYPE_CHECKING

from ..errors import GaitlabError, did_you_mean
from ..gaits import GAIT_PRESETS
from ..styles import WALK_STYLES

if TYPE_CHECKING:
    from ..cast import Cast
    from ..spec import CreatureSpec


def is_scene(name: str) -> bool:
    """Whether a .toml argument is a scene file (it has [[creatures]], or what only scenes
    have, a terrain, paths or a misspelt [[creature]], and no creature's [body]) rather
    than a creature."""
    from ..tomlfile import TomlProblem, read_toml

    path = Path(name)
    if path.suffix.lower() != ".toml" or not path.is_file():
        return False
    try:
        data = read_toml(path)
    except TomlProblem:
        return False  # the creature loader reports it
    return "creatures" in data or ("body" not in data and bool(SCENE_ONLY_KEYS & data.keys()))


SCENE_ONLY_KEYS = {"terrain", "paths", "creature"}  # top-level keys no creature file has


def creature_changes(args: argparse.Namespace) -> dict[str, object]:
    """The overrides ``--gait``, ``--frames-per-cycle`` and ``--set`` ask for (``--set``
    keys are checked against the creature when they are applied)."""
    overrides: dict[str, object] = {}
    if args.gait is not None:
        if args.gait not in GAIT_PRESETS:
            raise GaitlabError(f"--gait {args.gait!r}: unknown gait{did_you_mean(args.gait, GAIT_PRESETS)}; "
                               f"gaits are: {', '.join(GAIT_PRESETS)}")
        overrides["gait.preset"] = args.gait
    if args.frames_per_cycle is not None:
        if getattr(args, "speed", None) is not None:
            raise GaitlabError(f"--frames-per-cycle {args.frames_per_cycle:g} with --speed: the speed sets the timing "
                               "(the gait's frequency follows it); give one of them")
        overrides["gait.frames_per_cycle"] = args.frames_per_cycle
    return overrides


def _not_the_model_s(name: str, key: str, given: str) -> None:
    """Refuse a change to what a rigged model's creature takes from the model (its bones'
    lengths, hip spacing, body size, arms): its skeleton cannot follow."""
    from ..rigged import is_model_path, model_owns

    if is_model_path(name) and model_owns(key):
        raise GaitlabError(f"{given}: {Path(name).name} is a rigged model, and its bones' lengths and body size are "
                           "its own; change its gait, speed, path or ground instead")


def load_creature_args(args: argparse.Namespace, creature: str | None = None,
                       base_overrides: dict[str, object] | None = None, origin: str = "--set") -> CreatureSpec:
    """The creature named on the command line (or in a scene) with the scene's settings,
    then --gait, --frames-per-cycle, --set and --style applied."""
    from ..rigged import is_model_path
    from ..spec import parse_override

    name = creature or args.creature
    spec = named_creature(args, name)
    if base_overrides:
        for key in base_overrides:
            _not_the_model_s(name, key, f"{origin} {key}")
        _one_of_each_pair(base_overrides, f"{origin} ({spec.name}): ")
        spec = spec.with_overrides(base_overrides, origin=origin)
    overrides = creature_changes(args)
    for text in args.overrides:
        key, value = parse_override(text, spec)
        _not_the_model_s(name, key, f"--set {text}")
        overrides[key] = value
    flags = {"gait.frames_per_cycle": "--frames-per-cycle"} if args.frames_per_cycle is not None else {}
    _one_of_each_pair(overrides, "", flags)
    if overrides:  # a problem names the options given (and, in a scene, the creature)
        given = [f"--gait {args.gait}"] if args.gait is not None else []
        given += [f"--frames-per-cycle {args.frames_per_cycle:g}"] if args.frames_per_cycle is not None else []
        given += ["--set"] if args.overrides else []
        spec = spec.with_overrides(overrides, origin=" with ".join(given) + (f" ({spec.name})" if creature else ""))
    style = args.style
    if style is not None:
        from ..rigging import apply_style

        if style not in WALK_STYLES:
            raise GaitlabError(f"--style {style!r}: unknown style{did_you_mean(style, WALK_STYLES)}; styles are: "
                               f"{', '.join(WALK_STYLES)}")
        # The style is scaled to the creature as edited; the file's own key-pose and
        # stride settings on the command line then adjust it.
        spec = apply_style(spec, style)
        mine = {k: v for k, v in overrides.items() if k.startswith("poses.") or k == "gait.stride"}
        spec = spec.with_overrides(mine) if mine else spec
        if getattr(args, "speed", None) is not None and not getattr(args, "quiet", False):
            print(f"note: --style {style} with --speed: the speed sets the stride; the style's key poses apply",
                  file=sys.stderr)
    if is_model_path(name) and not getattr(args, "quiet", False):
        tell_model_notes(args, name)
    return spec


def named_creature(args: argparse.Namespace, name: str) -> CreatureSpec:
    """The creature ``name`` gives as it stands: a preset, a creature .toml, or a rigged
    model driven through ``--rig``'s map (or its joints' names)."""
    from ..rigged import is_model_path
    from ..rigged.creature import model_creature
    from ..spec import load_creature

    rig_map = getattr(args, "rig", None)
    if rig_map is not None and not is_model_path(name):
        raise GaitlabError(f"--rig {rig_map}: names a rigged model's legs; give a .glb or .gltf, not {name!r}")
    if not is_model_path(name):
        return load_creature(name)
    from ..rigged.loaded import use_rig_map

    use_rig_map(name, rig_map or "")  # this command's map, or none (names decide)
    return model_creature(name)


def _one_of_each_pair(overrides: dict[str, object], where: str, flags: dict[str, str] | None = None) -> None:
    """Refuse both keys of a pair that set one thing (the later would silently win);
    ``flags`` names the command-line options some keys came from."""
    said = flags or {}
    for pair, what in ((("gait.duty_factor", "gait.bias"), "the duty factor, or the bias that sets it"),
                       (("gait.frequency", "gait.frames_per_cycle"), "the timing as a frequency or in frames")):
        if all(key in overrides for key in pair):
            first, second = (said.get(key, key) for key in pair)
            raise GaitlabError(f"{where}{first} and {second} both given: give one ({what})")


def tell_model_notes(args: argparse.Namespace, model: str) -> None:
    """Print what the rigged model at ``model`` could be read only in part, once a command
    (a scene may hold the model several times)."""
    from ..rigged.loaded import model_notes

    told: set[tuple[str, str]] = vars(args).setdefault("_notes_told", set())
    for note in model_notes(model):
        if (model, note) not in told:
            told.add((model, note))
            print(f"note: {model}: {note}", file=sys.stderr)


def load_cast(args: argparse.Namespace) -> Cast:
    """What the command films, exports or shows: the creature on --path / --terrain (or in
    place) at --speed with --herd, or every creature of a scene file, each with the
    command line's creature changes (the scene's own speed and herd unless given)."""
    from ..cast import Actor, cast_of_scene
    from ..worlds import load_scene, make_world

    speed = getattr(args, "speed", None)
    herd = getattr(args, "herd", None)
    if is_scene(args.creature):
        given = [flag for flag, value in (("--path", args.path), ("--terrain", args.terrain),
                                          ("--in-place", args.in_place)) if value]
        if given:
            raise GaitlabError(f"{', '.join(given)}: a scene file sets its own path and terrain")
        scene = load_scene(args.creature)

        def creature(entry) -> CreatureSpec:
            overrides = {**entry.overrides, **({"gait.preset": entry.gait} if entry.gait else {})}
            return load_creature_args(args, entry.creature, overrides, origin=args.creature)

        return cast_of_scene(scene, creature, speed, herd)
    world = make_world(args.path, args.terrain, args.in_place)
    return (Actor(load_creature_args(args), world, speed, herd or 1),)


def choose_fps(args: argparse.Namespace, spec: CreatureSpec, speed: tuple[float, float] | None) -> float:
    """--fps, or the creature's timing frame rate when it gives frames per cycle (so a
    cycle of 24 frames at 24 fps is 24 frames in the file), or the command's default."""
    if args.fps is not None:
        return float(args.fps)
    from ..styles import DEFAULT_TIMING_FPS

    timed = spec.gait.frames_per_cycle is not None and speed is None
    return float(spec.gait.timing_fps or DEFAULT_TIMING_FPS) if timed else float(args.default_fps)
