"""``gaitlab export``: the animation as skeletons: BVH, glTF (.glb) or USD."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from ..choices import EXPORT_FORMATS
from .options import add_clip, add_creature, add_speed, add_world, seconds_from_zero

EPILOG = """\
examples:
  gaitlab export dog --gait trot --cycles 2 -o dog.bvh
  gaitlab export dog --gait trot --cycles 2 -o dog.glb   for Blender, Godot, Unity, three.js
  gaitlab export dog --gait trot --cycles 2 --loop -o dog.usda   a closed cycle for USD tools
  gaitlab export horse --gait gallop --fps 60 --seconds 4 -o gallop.bvh
  gaitlab export spider --path circle:r=1 --terrain hills:amp=0.05 --seconds 6 -o spider.bvh
  gaitlab export scenes/paddock.toml -o paddock.glb    every creature of a scene, one skeleton each
  gaitlab analyze dog.bvh                 the exported file measures as the motion itself

--path and --terrain take the kinds and keys 'gaitlab render --help' lists.
Joints: root (the middle of the trunk), spineN along the trunk, neck, head, nose,
tailN, and per foot NAME_hip, NAME_knee, NAME_ankle, NAME_ball, NAME_toe. Joints whose
offset changes (trunk, hips, neck and tail bases) carry position channels. A scene's
creatures go into one glTF or USD file (a skeleton each, joints named CREATURE:JOINT in
glTF), or one BVH file each (OUT-CREATURE.bvh).
"""


def add_parser(sub: argparse._SubParsersAction) -> None:
    parser = sub.add_parser("export", help="export the animation as a skeleton: BVH, glTF (.glb) or USD",
                            description="Export a creature's motion (or every creature of a scene) as a skeleton "
                                        "(joint hierarchy with local rotations and translations every frame): a BVH "
                                        "file (Y up, metres, Euler angles in degrees, ZXY unless a joint nears "
                                        "gimbal lock), a binary glTF with the creature's mesh skinned to the "
                                        "skeleton and one animation with root motion, or a USD stage (UsdSkel; "
                                        ".usda text or .usdc binary; needs usd-core).",
                            epilog=EPILOG, formatter_class=argparse.RawDescriptionHelpFormatter)
    add_creature(parser)
    add_clip(parser, output_help=f"output file: {', '.join('.' + f for f in EXPORT_FORMATS)} "
                                 "(default: CREATURE.bvh; a rigged model's: MODEL.glb)",
             cycles_help="clip length in gait cycles (default: 2)", fps=30.0)
    parser.add_argument("--time", metavar="T", type=seconds_from_zero, default=0.0,
                        help="time in seconds of the first frame (default: 0)")
    add_speed(parser)
    parser.add_argument("--loop", action="store_true",
                        help="whole cycles plus the frame that closes the loop (the last frame equals the first; "
                             "in place, or shifted by the travel): what animation packages expect of a cycle")
    parser.add_argument("--ground", action="store_true",
                        help="glTF: add the ground under the clip (the terrain) as a second mesh")
    add_world(parser)
    parser.add_argument("-q", "--quiet", action="store_true", help="no summary")


def run(args: argparse.Namespace) -> int:
    from ..export import export_cast
    from ..rigged import is_model_path
    from .inputs import choose_fps, load_cast

    # A rigged model's walk is written onto the model itself: a .glb beside it by default.
    suffix = ".glb" if is_model_path(str(args.creature)) else ".bvh"
    output = args.output or Path(f"{Path(args.creature).stem}{suffix}")
    cast = load_cast(args)
    lead = cast[0]
    fps = choose_fps(args, lead.spec, lead.speed)
    result = export_cast(cast, output, fps=fps, seconds=args.seconds, cycles=args.cycles, start=args.time,
                         loop=args.loop, ground=args.ground)
    if not args.quiet:
        for actor in cast:
            if actor.herd > 1:
                print(f"note: the herd of {actor.herd} {actor.spec.name}s is exported as its lead animal (a herd's "
                      "followers are drawn by render and view, not exported)", file=sys.stderr)
        frames = f"{result.frames} frame{'' if result.frames == 1 else 's'}"
        if len(cast) == 1:
            size = result.path.stat().st_size
            print(f"wrote {result.path}: {result.joints} joints, {frames} at {fps:g} fps "
                  f"({result.seconds:.2f} s of {lead.spec.name} {lead.spec.gait.preset}), {result.units}, "
                  f"{size / 1024:.0f} KiB")
        else:
            size = sum(p.stat().st_size for p in result.paths)
            files = ", ".join(str(p) for p in result.paths)
            where = f"one file per creature: {files}" if len(result.paths) > 1 else str(result.path)
            print(f"wrote {where}: {result.skeletons} skeletons ({', '.join(a.spec.name for a in cast)}), "
                  f"{result.joints} joints, {frames} at {fps:g} fps ({result.seconds:.2f} s), {result.units}, "
                  f"{size / 1024:.0f} KiB")
    return 0
