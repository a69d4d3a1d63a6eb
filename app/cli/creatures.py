"""``gaitlab creatures``: the presets, gaits and scenes, one line each; ``--keys``: every
key a creature file can set."""

from __future__ import annotations

import argparse

from ..errors import GaitlabError


def add_parser(sub: argparse._SubParsersAction) -> None:
    parser = sub.add_parser("creatures", help="list preset creatures and gaits",
                            description="List the preset creatures, gaits and example scenes, one line each.")
    parser.add_argument("--keys", nargs="?", const="dog", metavar="CREATURE",
                        help="also list every key a creature file can set, with its legs and feet named as "
                             "CREATURE's (a preset, .toml or rigged model .glb/.gltf; default: dog)")
    parser.add_argument("--rig", metavar="MAP.toml",
                        help="with --keys MODEL.glb: which of the model's joints are its legs, when their names do "
                             "not say (as for render)")


def rows(items: list[tuple[str, str]]) -> None:
    width = max(len(name) for name, _ in items)
    for name, text in items:
        print(f"  {name:<{width}}  {text}")


def run(args: argparse.Namespace) -> int:
    from ..gaits import GAIT_PRESETS, gaits_for
    from ..resources import preset_creature_names, scenes_dir
    from ..rigging import build_rig
    from ..spec import leg_type, load_creature
    from ..worlds import scene_description

    keyed = None
    if args.rig is not None and args.keys is None:
        raise GaitlabError(f"--rig {args.rig}: maps a rigged model's legs for --keys MODEL.glb; give --keys")
    if args.keys is not None:  # read before anything is printed: a bad name is one line, not a listing and then an error
        from ..rigged import is_model_path
        from .inputs import is_scene, named_creature, tell_model_notes

        if is_scene(args.keys):
            raise GaitlabError(f"--keys {args.keys}: a scene file; give a creature (a preset name, creature .toml or "
                               "rigged model)")
        keyed = named_creature(args, args.keys)
        if is_model_path(args.keys):
            tell_model_notes(args, args.keys)
    print("Creatures (gaitlab render NAME):")
    found = []
    for name in preset_creature_names():
        spec = load_creature(name)
        rig = build_rig(spec)
        kind = leg_type(spec.girdles[-1][0].ankle_lift)
        pairs = spec.pair_count
        found.append((name, f"{spec.description}  [{pairs} leg pair{'s' if pairs > 1 else ''}, {kind}, hip height "
                            f"{rig.hip_height:.2f} m, gait {spec.gait.preset}; gaits: {', '.join(gaits_for(pairs))}]"))
    rows(found)
    print("\nGaits (--gait NAME):")
    rows([(g.name, f"{g.description}  [duty factor {g.duty_factor:.2f}; for {g.fits_text}]")
          for g in GAIT_PRESETS.values()])
    print("\nExample scenes (gaitlab render PATH, gaitlab view PATH):")
    rows([(str(path), scene_description(path)) for path in sorted(scenes_dir().glob("*.toml"))])
    if keyed is not None:
        from ..spec import override_keys, rule_for

        print(f"\nCreature file keys (--set KEY=VALUE), with the {keyed.name}'s leg pairs and feet:")
        rows([(key, f"{rule.doc}; {rule.allowed()}") for key in override_keys(keyed)
              if (rule := rule_for(key)) is not None])
    return 0
