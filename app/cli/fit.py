"""``gaitlab fit``: a creature made to move like a motion-capture clip (see
:mod:`app.fitting`)."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from ..errors import GaitlabError

EPILOG = """\
examples:
  gaitlab fit walk.bvh -o walker.toml             a person's walk: body, gait and key poses
  gaitlab fit dog_trot.bvh -o trotter.toml        a quadruped's trot: body and gait
  gaitlab fit run.bvh -o runner.toml --feet L=lfoot:ltoes,R=rfoot:rtoes
then
  gaitlab analyze walker.toml                     its gait, measured as the clip's was
  gaitlab compare walker.toml --reference walk.bvh   its joint angles against the clip's
  gaitlab render walker.toml                      a GIF of it

What it fits: each leg's segment lengths and the hips' width from the skeleton (a
quadruped's trunk between its girdles, a biped's arms), the rest scaled from the human
or dog preset by leg length; frequency, duty factor, each foot's phase, stride and step
height from the clip's analysis; for a biped the four key-pose heights, foot angle, leg
bend, roll and step height refined (scipy's Nelder-Mead, about 300 short motions, a few
seconds) against the clip's hip and knee angles; then the gait calibrated until
Gaitlab's own measurement of the creature gives the clip's duty, cycle and speed.
"""


def add_parser(sub: argparse._SubParsersAction) -> None:
    parser = sub.add_parser("fit", help="make a creature that moves like a motion-capture clip (BVH)",
                            description="Make a creature that moves like a BVH clip: its body from the clip's "
                                        "skeleton, its gait from the clip's analysis, refined against the clip's "
                                        "joint angles. Prints what it fitted and how close it came, and writes the "
                                        "creature as a TOML file any other command reads.",
                            epilog=EPILOG, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("clip", metavar="CLIP", help="a .bvh motion-capture clip (a biped or a quadruped)")
    parser.add_argument("-o", "--output", metavar="OUT", type=Path, required=True,
                        help="the creature file to write (.toml)")
    parser.add_argument("--name", help="the creature's name (default: the output file's name)")
    parser.add_argument("--feet", metavar="MAP", help="the clip's foot joints, as for 'gaitlab analyze --feet' "
                                                      "(default: found by the usual names)")
    parser.add_argument("--units", choices=("auto", "m", "cm", "mm", "in", "ft", "cmu"), default="auto",
                        help="length units of the file (default: detected from the hip height)")
    parser.add_argument("--up", choices=("auto", "y", "z"), default="auto", help="the file's up axis")
    parser.add_argument("--no-refine", action="store_true",
                        help="skip the refinement against the joint angles (body and gait only; under a second)")
    parser.add_argument("-q", "--quiet", action="store_true", help="no progress line")


def run(args: argparse.Namespace) -> int:
    from ..analysis.sources import parse_feet
    from ..fitting import fit_clip
    from ..output import check_output_dir

    output: Path = args.output
    if output.suffix.lower() != ".toml":
        raise GaitlabError(f"-o {output}: a creature file ends in .toml")
    check_output_dir(output)
    show = not args.quiet and sys.stderr.isatty()

    def progress(text: str) -> None:
        if show:
            print(f"\r\033[K{text}", end="", file=sys.stderr, flush=True)

    try:
        result = fit_clip(args.clip, parse_feet(args.feet) if args.feet else None, args.units, args.up,
                          name=args.name or output.stem, refine=not args.no_refine, progress=progress)
    finally:
        if show:
            print("\r\033[K", end="", file=sys.stderr, flush=True)
    result.spec.save(output)
    print(result.summary())
    print(f"\nwrote {output}")
    return 0
