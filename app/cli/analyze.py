"""``gaitlab analyze``: measure a gait (foot events, duty factor, phase, slip, gait name)
of a creature's own motion, a BVH clip or a CSV of foot positions."""

from __future__ import annotations

import argparse
import json
import math
import sys
from pathlib import Path

from ..errors import GaitlabError
from .options import add_creature, add_speed, add_world, jobs, positive

EPILOG = """\
examples:
  gaitlab analyze dog --gait trot                 Gaitlab's own trot: measured vs requested
  gaitlab analyze ant --path circle:r=2           a tripod on a turn: also the path error
  gaitlab analyze horse --speed 0.5:8 --seconds 10     walk -> trot -> gallop, gait per time span
  gaitlab analyze walk.bvh --plot walk.png        motion capture (feet found by joint names)
  gaitlab analyze dog.bvh --feet LH=b_LeftAnkle:b_LeftToe,RH=b_RightAnkle:b_RightToe,...
  gaitlab analyze feet.csv --json                 CSV columns: time, NAME_x, NAME_y, NAME_z [, NAME_toe_x ...]
  gaitlab analyze clips/ --csv table.csv --jobs 2 every .bvh and .csv under a folder: one row per clip

Phases follow Hildebrand: the left hind foot (the left foot of a biped, the rearmost left
foot of a many-legged creature) touches down at 0.
"""

_CREATURE_ONLY = (("--gait", "gait"), ("--cycles", "cycles"), ("--seconds", "seconds"), ("--speed", "speed"),
                  ("--set", "overrides"), ("--path", "path"), ("--terrain", "terrain"), ("--in-place", "in_place"),
                  ("--style", "style"), ("--frames-per-cycle", "frames_per_cycle"))


def add_parser(sub: argparse._SubParsersAction) -> None:
    parser = sub.add_parser("analyze", help="measure a gait: foot events, duty factor, phase, slip, gait name",
                            description="Find each foot's stance, lift, liftoff, strike and landing times, then "
                                        "duty factor, phase (Hildebrand: left hind = 0), stride, slip and skating, "
                                        "and name the gait the pattern most resembles. SOURCE is a creature "
                                        "(preset or .toml: Gaitlab's own motion), a BVH file or a CSV of foot "
                                        "positions.", epilog=EPILOG, formatter_class=argparse.RawDescriptionHelpFormatter)
    add_creature(parser)
    parser.add_argument("--json", action="store_true", help="print the report as JSON")
    parser.add_argument("--csv", metavar="OUT", type=Path, help="write the events as CSV (foot, kind, time)")
    parser.add_argument("--plot", metavar="OUT", type=Path,
                        help="write a PNG: each foot's height with its events, and the gait diagram")
    creature = parser.add_argument_group("for a creature")
    creature.add_argument("--cycles", metavar="N", type=positive("cycles", 200), help="cycles to simulate (default 4)")
    creature.add_argument("--seconds", metavar="S", type=positive("seconds", 600),
                          help="seconds to simulate (default with --speed: 4)")
    add_speed(creature, default_seconds=False)
    add_world(parser)
    files = parser.add_argument_group("for a BVH or CSV file")
    files.add_argument("--feet", metavar="MAP", help="BVH foot joints: NAME=ANKLE[:TOE],... e.g. "
                                                     "L=LeftFoot:LeftToeBase,R=RightFoot:RightToeBase; namespaced "
                                                     "names keep their colons (L=mixamorig7:LeftFoot:mixamorig7:"
                                                     "LeftToeBase) and JOINT/End is a joint's End Site (a toe tip). "
                                                     "Without it, biped feet are found by the usual names (CMU, "
                                                     "Mixamo, ASF lfoot/ltoes, L_Foot, Bip01 L Foot, foot.L)")
    files.add_argument("--units", choices=("auto", "m", "cm", "mm", "in", "ft", "cmu"), default="auto",
                       help="length units of the file (default: detected from the hip height; CSV: m)")
    files.add_argument("--up", choices=("auto", "y", "z"), default="auto", help="up axis (default: detected; CSV: y)")
    folder = parser.add_argument_group("for a folder of clips (SOURCE is a folder)")
    folder.add_argument("--jobs", metavar="N", type=jobs,
                        help="processes analysing clips side by side (default: one per core); --csv then writes "
                             "one row per clip (source, gait, cycle, speed, duty and phase per foot, notes, error)")


def _check_outputs(args: argparse.Namespace) -> None:
    from ..output import check_output_dir

    for option, suffix in ((args.plot, ".png"), (args.csv, ".csv")):
        if option is not None:
            if option.suffix.lower() != suffix:
                raise GaitlabError(f"{option}: use a {suffix} file name")
            check_output_dir(option)


def _file_tracks(args: argparse.Namespace):
    from ..analysis.sources import load_tracks

    given = [flag for flag, name in _CREATURE_ONLY if getattr(args, name)]
    if given:
        raise GaitlabError(f"{', '.join(given)}: for creatures; a motion file has its own gait")
    return load_tracks(args.creature, feet=args.feet, units=args.units, up=args.up)


def _creature_tracks(args: argparse.Namespace):
    """Gaitlab's own motion at ~200 frames per stride: its tracks, a note, the path
    error, the gait asked for and each foot's requested duty and phase (None with a speed)."""
    from ..analysis import tracks_from_motion
    from ..analysis.metrics import path_error
    from ..kinematics.clip import clip_motion
    from ..rigging import build_rig
    from .inputs import load_cast

    given = [flag for flag, value in (("--feet", args.feet), ("--units", args.units != "auto"),
                                      ("--up", args.up != "auto")) if value]
    if given:
        raise GaitlabError(f"{', '.join(given)}: for BVH or CSV files, not creatures")
    if args.cycles is not None and args.seconds is not None:
        raise GaitlabError("give --cycles or --seconds, not both")
    cast = load_cast(args)
    if len(cast) > 1 and not args.json:
        print(f"note: {args.creature} has {len(cast)} creatures; analyze measures the first ({cast[0].spec.name})",
              file=sys.stderr)
    actor = cast[0]
    rig = build_rig(actor.spec)
    frequency = rig.gait.frequency
    if actor.speed is not None:
        from ..kinematics.speed import gait_at_speed

        frequency = max(gait_at_speed(rig, v).gait.frequency for v in actor.speed)
    fps = float(max(120, math.ceil(200 * frequency)))  # ~200 frames per stride: sub-percent timing
    if actor.speed is None and args.seconds is None:
        motion, _ = clip_motion(rig, fps, cycles=args.cycles or 4.0, world=actor.world)
    else:
        motion, _ = clip_motion(rig, fps, seconds=args.seconds, cycles=args.cycles, speed=actor.speed,
                                world=actor.world)
    requested = None
    if actor.speed is None:
        requested = {name: (rig.gait.duty_factor, float(phase)) for name, phase in zip(rig.leg_names,
                                                                                       rig.gait.offsets)}
    gait = None if actor.speed is not None else actor.spec.gait.preset
    return (tracks_from_motion(motion), f"{motion.frame_count} frames at {fps:g} fps", path_error(motion), gait,
            requested)


def _run_folder(args: argparse.Namespace) -> int:
    """Every clip under a folder, one row each; exit 2 when any could not be analysed."""
    from tqdm import tqdm

    from ..analysis.batch import analyse_folder, clips_under, default_jobs, table_csv, table_text
    from ..output import atomic_write_text

    given = [flag for flag, name in _CREATURE_ONLY if getattr(args, name)]
    given += ["--plot"] if args.plot is not None else []
    if given:
        raise GaitlabError(f"{', '.join(given)}: for one creature or clip, not a folder of clips")
    folder = Path(args.creature)
    clips = clips_under(folder, skip=args.csv)
    jobs = args.jobs or default_jobs()
    with tqdm(total=len(clips), unit="clip", desc="analysing", disable=None, file=sys.stderr) as bar:
        rows = analyse_folder(clips, jobs, feet=args.feet, units=args.units, up=args.up,
                              progress=lambda row: bar.update(1))
    if args.csv is not None:
        atomic_write_text(args.csv, table_csv(rows))
    if args.json:
        print(json.dumps([{"source": r.source, "gait": r.gait, "cycle_seconds": r.cycle, "speed": r.speed,
                           "duty": r.duty, "phase": r.phase, "notes": list(r.notes), "error": r.error or None}
                          for r in rows], indent=2))
    else:
        print(table_text(rows, folder))
    failed = [r for r in rows if not r.ok]
    if failed:
        print(f"gaitlab analyze: {len(failed)} of {len(rows)} clips could not be analysed"
              + (f" (see the error column of {args.csv})" if args.csv is not None else ""), file=sys.stderr)
        return 2
    if args.csv is not None:
        print(f"wrote {args.csv}: {len(rows)} clips", file=sys.stderr)
    return 0


def run(args: argparse.Namespace) -> int:
    from ..analysis import analyze_tracks
    from ..analysis.plot import save_plot
    from ..analysis.report import events_csv, format_table
    from ..output import write_together

    _check_outputs(args)
    if Path(args.creature).is_dir():
        return _run_folder(args)
    if args.jobs is not None:
        raise GaitlabError("--jobs: for a folder of clips (give a folder as SOURCE)")
    suffix = Path(args.creature).suffix.lower()
    if suffix not in ("", ".toml", ".bvh", ".csv"):
        raise GaitlabError(f"{args.creature}: unknown file type {suffix!r}; analyze reads a creature (preset name "
                           "or .toml), a .bvh or a .csv file")
    if suffix in (".bvh", ".csv"):
        tracks, notes = _file_tracks(args)
        report = analyze_tracks(tracks, requested_gait=None)
        requested = None
    else:
        tracks, notes, path_report, gait, requested = _creature_tracks(args)
        report = analyze_tracks(tracks, requested_gait=gait)
        report.path_error = path_report
    outputs = [(args.csv, lambda tmp: tmp.write_text(events_csv(report), encoding="utf-8")),
               (args.plot, lambda tmp: save_plot(report, tmp))]
    write_together([(path, write) for path, write in outputs if path is not None])  # both or neither
    if args.json:
        print(json.dumps(report.to_json(), indent=2))
    else:
        print(format_table(report, requested, notes))
    return 0
