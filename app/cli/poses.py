"""``gaitlab poses``: the key poses of a walk side by side (PNG)."""

from __future__ import annotations

import argparse
from pathlib import Path

from ..errors import GaitlabError
from ..styles import WALK_STYLES
from .options import add_creature, size

EPILOG = """examples:
  gaitlab poses human -o poses.png                       the five key poses of a normal walk
  gaitlab poses human --style double-bounce -o db.png    a style's key poses
  gaitlab poses human --set poses.down_height=-0.1       a deeper down pose
  gaitlab poses human --second-step                      the mirrored step

Key poses (a step, half a cycle): contact at 0, down at 1/4, pass at 1/2, up at 3/4 of
the step; the next contact starts the other foot's step. Their heights (poses.*_height,
metres from the rest height), foot_angle, arm_swing and torso_lean live in the creature
file's [poses] table; the in-betweens follow a smooth curve through them.
Styles: """ + ", ".join(WALK_STYLES) + """.
"""


def add_parser(sub: argparse._SubParsersAction) -> None:
    parser = sub.add_parser("poses", help="render the key poses of a walk side by side (PNG)",
                            description="Render a creature's key poses - contact, down, pass, up and the next "
                                        "contact (the other foot's, the mirror of the first) - side by side from the "
                                        "side, each labelled with its cycle phase and frame. Edit them with "
                                        "--set poses.down_height=-0.08 etc., or start from a --style.",
                            epilog=EPILOG, formatter_class=argparse.RawDescriptionHelpFormatter)
    add_creature(parser, default="human", scenes=False)
    parser.add_argument("-o", "--output", metavar="OUT", type=Path, help="output .png (default: CREATURE-poses.png)")
    parser.add_argument("--size", metavar="WxH", type=size, default=(320, 360),
                        help="size of each pose's picture (default: 320x360; the sheet is five wide)")
    parser.add_argument("--second-step", action="store_true",
                        help="the second step (right foot's contact to the left's): the first mirrored")
    parser.add_argument("-q", "--quiet", action="store_true", help="no summary")


def run(args: argparse.Namespace) -> int:
    from ..output import output_format
    from ..sheet import write_pose_sheet
    from .inputs import is_scene, load_creature_args

    output = args.output or Path(f"{Path(args.creature).stem}-poses.png")
    if output.suffix.lower() != ".png" or output_format(output) != "png":
        raise GaitlabError(f"{output}: the poses sheet is a PNG; give a file name ending in .png")
    if Path(args.creature).suffix.lower() == ".toml" and is_scene(args.creature):
        raise GaitlabError(f"{args.creature}: a scene file; give one creature (a preset name or creature .toml)")
    spec = load_creature_args(args)
    sheet = write_pose_sheet(spec, output, args.size, args.second_step)
    if not args.quiet:
        h, w = sheet.image.shape[:2]
        print(f"wrote {output} ({w}x{h}: {', '.join(sheet.names)} of the {spec.name}'s "
              f"{'second' if args.second_step else 'first'} step, {output.stat().st_size / 1024:.0f} KiB)")
    return 0
