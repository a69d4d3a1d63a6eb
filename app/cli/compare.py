"""``gaitlab compare``: a creature's sagittal joint angles over a cycle against a real
clip (BVH) or a normative curve file (CSV)."""

from __future__ import annotations

import argparse
import json
import math
from pathlib import Path

from ..errors import GaitlabError, not_a_file
from .options import add_creature, add_world, positive

EPILOG = """\
examples:
  gaitlab compare human                              against the bundled normative walk (Schwartz et al. 2008)
  gaitlab compare human --reference walk.bvh --plot cmp.png   against a motion-capture clip
  gaitlab compare human --reference norms.csv --json
  gaitlab compare dog --reference dog_walk.bvh --leg LH        a quadruped's hind limb

Angle conventions (degrees, in the sagittal plane of the body's forward direction and
up; a cycle runs from a foot's strike, 0 %, to its next strike, 100 %):
  hip    the thigh against the vertical, + flexion (the knee ahead of the hip). Clinical
         hip flexion is against the pelvis: it reads higher by the pelvis's forward tilt.
  knee   flexion: the angle between thigh and shank, 0 straight, + bent.
  ankle  dorsiflexion: the foot against the shank, 0 at the standing pose, + toes towards
         the shin, - plantarflexion.
A normative CSV has a phase column (0-100 %) and, per joint, JOINT_mean and JOINT_sd.
A BVH clip's legs are found as 'gaitlab analyze' finds feet: the knee is the ankle
joint's parent and the hip the knee's; its ankle's zero is the skeleton's rest pose.
"""

BUNDLED = "human_walk_schwartz2008.csv"


def add_parser(sub: argparse._SubParsersAction) -> None:
    parser = sub.add_parser("compare", help="compare a creature's joint angles with a real clip or normative curves",
                            description="Compare a creature's sagittal joint angles (hip, knee, ankle) over a "
                                        "normalised cycle with a reference: a motion-capture clip (BVH) or a "
                                        "normative curve file (CSV). Prints the RMS difference per joint and the "
                                        "events clinicians read (knee at strike, loading peak, swing peak, ankle "
                                        "push-off ...), and can plot the curves side by side.",
                            epilog=EPILOG, formatter_class=argparse.RawDescriptionHelpFormatter)
    add_creature(parser, default="human", scenes=False)
    parser.add_argument("--reference", metavar="FILE",
                        help=f"a .bvh clip or a .csv of normative curves (default: the bundled {BUNDLED}, a "
                             "human walk at free speed, for two-legged creatures; others need a reference of their "
                             "kind)")
    parser.add_argument("--leg", metavar="NAME",
                        help="which leg to compare: a foot name such as L or LH (default: the left, or left hind, "
                             "foot of both)")
    parser.add_argument("--cycles", metavar="N", type=positive("cycles", 50), default=6.0,
                        help="cycles of the creature to average (default 6)")
    parser.add_argument("--plot", metavar="OUT", type=Path, help="write a PNG of the curves side by side")
    parser.add_argument("--json", action="store_true", help="print the comparison as JSON")
    add_world(parser)


def _reference(args: argparse.Namespace, leg: str):
    from ..analysis.compare import leg_curves, read_normative
    from ..analysis.limbs import bvh_legs
    from ..resources import reference_dir

    path = args.reference or str(reference_dir() / BUNDLED)
    suffix = Path(path).suffix.lower()
    if suffix == ".csv":
        return read_normative(path)
    if suffix != ".bvh":
        raise GaitlabError(f"--reference {path}: expected a .bvh clip or a .csv of normative curves")
    if not Path(path).is_file():
        raise GaitlabError(f"--reference {path}: {not_a_file(path)}")
    legs = bvh_legs(path)
    name = leg if leg in legs.angles else next((n for n in ("L", "LH", "L1") if n in legs.angles), None)
    if name is None:
        raise GaitlabError(f"--reference {path}: no leg {leg!r} among {', '.join(legs.angles)}; give --leg")
    return leg_curves(legs, name)


def run(args: argparse.Namespace) -> int:
    from ..analysis.compare import compare_curves, format_comparison, leg_curves, write_comparison_plot
    from ..analysis.limbs import motion_legs
    from ..kinematics.clip import clip_motion
    from ..output import check_output_dir
    from ..rigging import build_rig
    from .inputs import is_scene, load_cast

    if Path(args.creature).suffix.lower() == ".toml" and is_scene(args.creature):
        raise GaitlabError(f"{args.creature}: a scene file; compare measures one creature (a preset name, creature "
                           ".toml or rigged model)")
    if args.plot is not None:
        if args.plot.suffix.lower() != ".png":
            raise GaitlabError(f"{args.plot}: use a .png file name")
        check_output_dir(args.plot)
    args.speed = None
    actor = load_cast(args)[0]
    rig = build_rig(actor.spec)
    if args.reference is None and rig.leg_count != 2:
        raise GaitlabError(f"{actor.spec.name}: the bundled reference is a person's walk, and the "
                           f"{actor.spec.name} has {rig.leg_count} legs; give --reference FILE (a clip or normative "
                           "curves of its kind)")
    first_left = next(n for n in ("L", "LH", f"L{rig.leg_count // 2}") if n in rig.leg_names)
    leg = first_left if args.leg is None else args.leg
    if leg not in rig.leg_names:
        raise GaitlabError(f"--leg {leg!r}: the {actor.spec.name} has feet {', '.join(rig.leg_names)}")
    reference = _reference(args, leg)
    fps = float(max(120, math.ceil(200 * rig.gait.frequency)))
    # A cycle and a half more than asked, so that many whole strides are found (a strike at the very start is not
    # seen, and the last needs its next).
    motion, _ = clip_motion(rig, fps, cycles=max(args.cycles + 1.5, 2.25), world=actor.world)
    gait = leg_curves(motion_legs(motion), leg, contact_fraction=rig.gait.duty_factor)
    gait = type(gait)(name=f"{actor.spec.name} {actor.spec.gait.preset}, {leg}", mean=gait.mean, sd=gait.sd,
                      cycles=gait.cycles, toe_off=gait.toe_off)
    comparison = compare_curves(gait, reference)
    if not comparison.rms:
        raise GaitlabError(f"{reference.name}: it gives none of the joints hip, knee, ankle")
    if args.plot is not None:
        write_comparison_plot(comparison, args.plot)
    if args.json:
        print(json.dumps(comparison.to_json(), indent=2))
    else:
        print(format_comparison(comparison))
        if args.plot is not None:
            print(f"\nwrote {args.plot}")
    return 0
