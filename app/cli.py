"""The ``gaitlab`` command.

Every user error ends the same way: one line on stderr naming the file, key or value and
what is allowed, exit status 2, no traceback, no partial output.
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path
from typing import Sequence

from . import __version__
from .choices import ANTIALIAS_MODES, ARC_JOINTS, DEFAULT_ANTIALIAS, OVERLAYS
from .errors import GaitlabError
from .gaits import GAIT_PRESETS
from .styles import WALK_STYLES
from .export.formats import EXPORT_FORMATS
from .output import DEFAULT_CRF, DEFAULT_GIF_QUALITY, GIF_QUALITIES, MAX_CRF, MAX_SIZE
from .render.camera import CAMERA_CHOICES, DEFAULT_CAMERA

EXIT_BAD_INPUT = 2
from .limits import MAX_FPS, MAX_SECONDS


class _Parser(argparse.ArgumentParser):
    """argparse, but a usage error is one line (and still exit status 2)."""

    def error(self, message: str) -> None:  # type: ignore[override]
        self.exit(EXIT_BAD_INPUT, f"{self.prog}: error: {message} (see '{self.prog} --help')\n")


def _size(text: str) -> tuple[int, int]:
    try:
        w_text, h_text = text.lower().split("x")
        w, h = int(w_text), int(h_text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r}: expected WIDTHxHEIGHT in pixels, e.g. 480x360") from None
    if not (1 <= w <= MAX_SIZE and 1 <= h <= MAX_SIZE):
        raise argparse.ArgumentTypeError(f"{text!r}: width and height must be between 1 and {MAX_SIZE} pixels")
    return w, h


def _positive(name: str, upper: float):
    def parse(text: str) -> float:
        try:
            value = float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{text!r}: expected a number") from None
        if not math.isfinite(value) or value <= 0 or value > upper:
            raise argparse.ArgumentTypeError(f"{text!r}: must be greater than 0 and at most {upper:g} {name}")
        return value

    return parse


def _non_negative(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r}: expected a number of seconds") from None
    if not math.isfinite(value) or value < 0:
        raise argparse.ArgumentTypeError(f"{text!r}: must be a finite number of seconds >= 0")
    return value


def _speed(text: str) -> tuple[float, float]:
    parts = text.split(":")
    try:
        values = [float(p) for p in parts]
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r}: expected a speed in m/s (e.g. 1.5) or a ramp V0:V1 "
                                         "(e.g. 0.5:6)") from None
    if len(values) not in (1, 2) or any(not math.isfinite(v) or v <= 0 or v > 30 for v in values):
        raise argparse.ArgumentTypeError(f"{text!r}: speeds must be in (0, 30] m/s, as V or V0:V1")
    return (values[0], values[-1])


def _overlays(text: str) -> tuple[str, ...]:
    names = tuple(dict.fromkeys(n.strip() for n in text.split(",") if n.strip()))
    unknown = [n for n in names if n not in OVERLAYS]
    if unknown or not names:
        raise argparse.ArgumentTypeError(f"{text!r}: expected a comma-separated list of {', '.join(OVERLAYS)}")
    return names


def _herd(text: str) -> int:
    from .kinematics.herd import MAX_HERD

    try:
        value = int(text)
    except ValueError:
        value = 0
    if not 1 <= value <= MAX_HERD:
        raise argparse.ArgumentTypeError(f"{text!r}: give 1 to {MAX_HERD} animals (the creature and N - 1 more)")
    return value


def _samples(text: str) -> int:
    if text not in ("0", "2", "4", "8"):
        raise argparse.ArgumentTypeError(f"{text!r}: expected 0 (off), 2, 4 or 8 samples")
    return int(text)


def _crf(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        value = -1
    if not 0 <= value <= MAX_CRF:
        raise argparse.ArgumentTypeError(f"{text!r}: expected a whole number from 0 to {MAX_CRF}")
    return value


EXPORT_EPILOG = """\
examples:
  gaitlab export dog --gait trot --cycles 2 -o dog.bvh
  gaitlab export dog --gait trot --cycles 2 -o dog.glb   for Blender, Godot, Unity, three.js
  gaitlab export dog --gait trot --cycles 2 --loop -o dog.usda   a closed cycle for USD tools
  gaitlab export horse --gait gallop --fps 60 --seconds 4 -o gallop.bvh
  gaitlab export spider --path circle:r=1 --terrain hills:amp=0.05 --seconds 6 -o spider.bvh
  gaitlab analyze dog.bvh                 the exported file measures as the motion itself

--path and --terrain take the kinds and keys 'gaitlab render --help' lists.
Joints: root (the middle of the trunk), spineN along the trunk, neck, head, nose,
tailN, and per foot NAME_hip, NAME_knee, NAME_ankle, NAME_ball, NAME_toe. Joints whose
offset changes (trunk, hips, neck and tail bases) carry position channels.
"""

RENDER_EPILOG = """\
examples:
  gaitlab render                                   dog.gif: the dog walking ahead, two seamless cycles
  gaitlab render horse --gait gallop -o horse.mp4  a galloping horse as H.264 video
  gaitlab render cat -o cat.png --time 0.3         one frame, 0.3 s into the walk
  gaitlab render bear --camera side --cycles 3 --fps 30 --size 640x360
  gaitlab render dog --path circle:r=2 --terrain hills:amp=0.15 --seconds 8
  gaitlab render spider --terrain stairs:rise=0.08 --seconds 10 -o climb.mp4
  gaitlab render ant --path waypoints:0,0,1,1,2,0,3,1 --seconds 6
  gaitlab render dog --in-place                    the cycle on a treadmill (the ground moves)
  gaitlab render scenes/hillside.toml              a scene file: terrain, path, creature
  gaitlab render dog --set gait.duty_factor=0.8 --set legs.hind.femur=0.25 -o slow.gif

CREATURE is a preset (see 'gaitlab creatures'), a creature .toml file or a scene .toml.
The creature walks along --path over --terrain (default: straight ahead on flat ground)
and the camera follows it, keeping the preset's angle to its heading.
--path KIND[:KEY=VALUE,...]:
  straight[:heading=DEG]  circle:r=M[,dir=left|right]  figure-eight:r=M
  waypoints:X,Z,X,Z,...[,closed]   (a smooth curve through the points, metres)
--terrain KIND[:KEY=VALUE,...]  (every kind also takes max_slope=DEG, default 40):
  flat  slope:angle=DEG[,dir=DEG]  hills[:amp=M,wavelength=M,seed=N]
  stairs[:rise=M,run=M,steps=N,start=M,dir=DEG]  heightmap:file=PNG[,size=M,height=M]
  mesh:file=OBJ|PLY|STL|GLB[,cell=M]
--gait replaces the creature's gait with a preset and drops its gait adjustments; add
--set gait.KEY=VALUE to adjust the new gait. --set takes any key a creature file has
('gaitlab creatures --keys' lists them); values are TOML (numbers, "strings").
Without --seconds the clip is two whole gait cycles, which loop without a seam.
"""


VIEW_EPILOG = """\
examples:
  gaitlab view                                  the dog, walking ahead (the camera follows)
  gaitlab view horse --gait gallop
  gaitlab view spider --path circle:r=2 --terrain hills:amp=0.1
  gaitlab view scenes/hillside.toml             a scene file
  gaitlab view dog --in-place                   on the spot, the ground moving under it
  xvfb-run -s "-screen 0 1280x800x24" gaitlab view --frames 120 --screenshot shot.png
  gaitlab view --no-vsync --report-fps --frames 600     measure the frame rate

mouse: left drag orbit, right/middle drag pan, wheel zoom, double-click focus.
keys: Space play/pause, Right step, R reset view, F12 screenshot (the 3-D view;
      Shift+F12 the whole window), G record, Ctrl+Z/Ctrl+Y undo/redo, Tab hide UI,
      F1 help, Ctrl+Q quit.
"""


ANALYZE_EPILOG = """\
examples:
  gaitlab analyze dog --gait trot                 Gaitlab's own trot: measured vs requested
  gaitlab analyze ant --path circle:r=2           a tripod on a turn: also the path error
  gaitlab analyze horse --speed 0.5:8 --seconds 10     walk -> trot -> gallop, gait per time span
  gaitlab analyze walk.bvh --plot walk.png        motion capture (feet found by joint names)
  gaitlab analyze dog.bvh --feet LH=b_LeftAnkle:b_LeftToe,RH=b_RightAnkle:b_RightToe,...
  gaitlab analyze feet.csv --json                 CSV columns: time, NAME_x, NAME_y, NAME_z [, NAME_toe_x ...]

Phases follow Hildebrand: the left hind foot (the left foot of a biped, the rearmost left
foot of a many-legged creature) touches down at 0.
"""


def _world_arguments(parser: argparse.ArgumentParser) -> None:
    group = parser.add_argument_group("where it walks")
    group.add_argument("--path", metavar="KIND[:K=V,...]",
                       help="the body's path: straight (default), circle:r=3, figure-eight:r=2, "
                            "waypoints:0,0,2,1,4,0 (see the list below)")
    group.add_argument("--terrain", metavar="KIND[:K=V,...]",
                       help="the ground: flat (default), slope:angle=15, hills:amp=0.2, stairs:rise=0.1,run=0.35, "
                            "heightmap:file=map.png, mesh:file=ground.obj")
    group.add_argument("--in-place", action="store_true",
                       help="walk on the spot while the ground moves under the feet (flat, straight only)")


POSES_EPILOG = """examples:
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


def _clip_arguments(parser: argparse.ArgumentParser, output_help: str, cycles_help: str, fps: float) -> None:
    """What a clip is of and how long (shared by render and export)."""
    parser.add_argument("creature", nargs="?", default="dog", metavar="CREATURE",
                        help="preset name, creature .toml or scene .toml (default: dog)")
    parser.add_argument("-o", "--output", metavar="OUT", type=Path, help=output_help)
    parser.add_argument("--gait", metavar="G", help=f"gait preset: {', '.join(GAIT_PRESETS)}")
    length = parser.add_mutually_exclusive_group()
    length.add_argument("--seconds", metavar="S", type=_positive("seconds", MAX_SECONDS), help="clip length in seconds")
    length.add_argument("--cycles", metavar="N", type=_positive("cycles", MAX_SECONDS), help=cycles_help)
    parser.add_argument("--fps", metavar="F", type=_positive("frames per second", MAX_FPS), default=None,
                        help=f"frames per second (default: {fps:g}, or the creature's timing frame rate when its "
                             "timing is given in frames per cycle)")
    parser.set_defaults(default_fps=fps)


def _animator_arguments(parser) -> None:
    """Walk style and timing as an animator gives them (render, export, analyze, view, poses)."""
    parser.add_argument("--style", metavar="STYLE",
                        help=f"walk style to start the key poses from: {', '.join(WALK_STYLES)} (writes the "
                             "style's heights, foot angle, arm swing, torso lean and stride; --set adjusts them)")
    parser.add_argument("--frames-per-cycle", metavar="N", type=_positive("frames per cycle", 10000),
                        help="timing in frames per cycle (two steps) instead of a frequency, counted at the "
                             "creature's gait.timing_fps (24 unless it gives one): a normal walk is 24 (a step on "
                             "twelves); the same as --set gait.frames_per_cycle=N")


def _creature_arguments(parser: argparse.ArgumentParser, time_help: str) -> None:
    """When the clip starts, creature overrides and speed (shared by render and export)."""
    parser.add_argument("--time", metavar="T", type=_non_negative, default=0.0, help=time_help)
    parser.add_argument("--set", metavar="KEY=VALUE", action="append", default=[], dest="overrides",
                        help="override a creature key, e.g. gait.duty_factor=0.7 (repeatable)")
    _animator_arguments(parser)
    parser.add_argument("--speed", metavar="V[:V1]", type=_speed,
                        help="speed in m/s, or a ramp V0:V1 over the clip: the gait follows the speed "
                             "(walk, trot, gallop by Froude number); default length 4 s")


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(prog="gaitlab", description="Procedural legged locomotion: tetrapods, bipeds (a human, a "
                     "bird, a theropod), insects, spiders and centipedes walking paths over terrain, their legs "
                     "driven by gait oscillators and analytic IK, with an animator's key poses, styles and arcs, "
                     "rendered headless or live.",
                     epilog="Run 'gaitlab COMMAND --help' for a command's options.")
    parser.add_argument("--version", action="version", version=f"gaitlab {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)

    creatures = sub.add_parser("creatures", help="list preset creatures and gaits",
                               description="List the preset creatures and gaits, one line each.")
    creatures.add_argument("--keys", action="store_true", help="also list every key a creature file can set")

    render = sub.add_parser("render", help="render a creature to PNG, GIF or MP4 (headless)",
                            description="Render a creature headless (EGL) to a PNG frame, a looping GIF or an "
                                        "H.264 MP4.", epilog=RENDER_EPILOG,
                            formatter_class=argparse.RawDescriptionHelpFormatter)
    _clip_arguments(render, output_help="output file: .png, .gif or .mp4 (default: CREATURE.gif)",
                    cycles_help="clip length in gait cycles (default: 2; loops seamlessly)", fps=25.0)
    render.add_argument("--size", metavar="WxH", type=_size, default=(480, 360), help="image size (default: 480x360)")
    render.add_argument("--herd", metavar="N", type=_herd, default=1,
                        help="N animals in all: the creature and N - 1 more of its kind following it, each a "
                             "little different in size (+-10%%), speed and step (travelling only)")
    render.add_argument("--camera", choices=CAMERA_CHOICES, default=DEFAULT_CAMERA,
                        help=f"camera preset (default: {DEFAULT_CAMERA}); a travelling creature is followed "
                             "at the preset's angle to its heading; 'chase' films from behind, looking ahead; "
                             "'follow' is the default angle")
    _creature_arguments(render, time_help="time in seconds of the PNG frame, or of a clip's first frame (default: 0)")
    _world_arguments(render)
    render.add_argument("--antialias", choices=ANTIALIAS_MODES, default=None,
                        help="smooth edges: fxaa (one fast pass over the creature), msaa (multisampling: the "
                             "finest edges, about twice the time without a GPU) or off (default: fxaa)")
    render.add_argument("--msaa", metavar="N", type=_samples, default=None,
                        help="multisampling with N samples: 2, 4 or 8; 0 turns antialiasing off "
                             "(the same as --antialias msaa or off; default: 4 with --antialias msaa)")
    render.add_argument("--gif-quality", choices=GIF_QUALITIES, default=DEFAULT_GIF_QUALITY,
                        help="GIF size against fidelity: best (255 colours, lossless), good (about half the size, "
                             "no visible loss), small (about a third, some grain); smaller GIFs need gifsicle "
                             f"installed (default: {DEFAULT_GIF_QUALITY})")
    render.add_argument("--crf", metavar="N", type=_crf, default=DEFAULT_CRF,
                        help=f"MP4 quality: H.264 constant rate factor, 0 (lossless, large) to {MAX_CRF} "
                             f"(smallest); +6 roughly halves the file (default: {DEFAULT_CRF})")
    render.add_argument("--no-grid", action="store_true", help="plain ground without grid lines")
    render.add_argument("--no-shadow", action="store_true", help="no shadow")
    render.add_argument("--no-joints", action="store_true", help="no joint markers on the legs")
    render.add_argument("--no-path", action="store_true",
                        help="do not draw a turning path on the ground (a straight one never is)")
    render.add_argument("--arcs", metavar="JOINTS",
                        help=f"draw the paths of joints over the last cycle, beaded at the key poses: any of "
                             f"{', '.join(ARC_JOINTS)}, separated by commas (e.g. toe,hand)")
    render.add_argument("-q", "--quiet", action="store_true", help="no progress bar or summary")

    analyze = sub.add_parser("analyze", help="measure a gait: foot events, duty factor, phase, slip, gait name",
                             description="Find each foot's stance, lift, liftoff, strike and landing times, then "
                                         "duty factor, phase (Hildebrand: left hind = 0), stride, slip and skating, "
                                         "and name the gait the pattern most resembles. SOURCE is a creature "
                                         "(preset or .toml: Gaitlab's own motion), a BVH file or a CSV of foot "
                                         "positions.", epilog=ANALYZE_EPILOG,
                             formatter_class=argparse.RawDescriptionHelpFormatter)
    analyze.add_argument("creature", nargs="?", default="dog", metavar="SOURCE",
                         help="creature name or .toml, or a .bvh / .csv motion file (default: dog)")
    analyze.add_argument("--json", action="store_true", help="print the report as JSON")
    analyze.add_argument("--csv", metavar="OUT", type=Path, help="write the events as CSV (foot, kind, time)")
    analyze.add_argument("--plot", metavar="OUT", type=Path,
                         help="write a PNG: each foot's height with its events, and the gait diagram")
    creature = analyze.add_argument_group("for a creature")
    creature.add_argument("--gait", metavar="G", help=f"gait preset: {', '.join(GAIT_PRESETS)}")
    creature.add_argument("--cycles", metavar="N", type=_positive("cycles", 200), help="cycles to simulate (default 4)")
    creature.add_argument("--seconds", metavar="S", type=_positive("seconds", 600),
                          help="seconds to simulate (default with --speed: 4)")
    creature.add_argument("--speed", metavar="V[:V1]", type=_speed,
                          help="speed-driven gait: m/s, or a ramp V0:V1 (the report lists the gait per time span)")
    creature.add_argument("--set", metavar="KEY=VALUE", action="append", default=[], dest="overrides",
                          help="override a creature key (repeatable)")
    _animator_arguments(creature)
    creature.add_argument("--path", metavar="KIND[:K=V,...]", help="the body's path (as for render)")
    creature.add_argument("--terrain", metavar="KIND[:K=V,...]", help="the ground (as for render)")
    creature.add_argument("--in-place", action="store_true", help="walk on the spot (the ground moves)")
    files = analyze.add_argument_group("for a BVH or CSV file")
    files.add_argument("--feet", metavar="MAP", help="BVH foot joints: NAME=ANKLE[:TOE],... e.g. "
                                                     "L=LeftFoot:LeftToeBase,R=RightFoot:RightToeBase")
    files.add_argument("--units", choices=("auto", "m", "cm", "mm", "in", "ft", "cmu"), default="auto",
                       help="length units of the file (default: detected from the hip height; CSV: m)")
    files.add_argument("--up", choices=("auto", "y", "z"), default="auto", help="up axis (default: detected; CSV: y)")

    export = sub.add_parser("export", help="export the animation as a skeleton: BVH, glTF (.glb) or USD",
                            description="Export a creature's motion as a skeleton (joint hierarchy with local "
                                        "rotations and translations every frame): a BVH file (Y up, metres, Euler "
                                        "angles in degrees, ZXY unless a joint nears gimbal lock), a binary glTF "
                                        "with the creature's mesh skinned to the skeleton and one animation with "
                                        "root motion, or a USD "
                                        "stage (UsdSkel; .usda text or .usdc binary; needs usd-core).",
                            epilog=EXPORT_EPILOG,
                            formatter_class=argparse.RawDescriptionHelpFormatter)
    _clip_arguments(export, output_help=f"output file: {', '.join('.' + f for f in EXPORT_FORMATS)} "
                                        "(default: CREATURE.bvh)",
                    cycles_help="clip length in gait cycles (default: 2)", fps=30.0)
    _creature_arguments(export, time_help="time in seconds of the first frame (default: 0)")
    export.add_argument("--loop", action="store_true",
                        help="whole cycles plus the frame that closes the loop (the last frame equals the first; "
                             "in place, or shifted by the travel): what animation packages expect of a cycle")
    export.add_argument("--ground", action="store_true",
                        help="glTF: add the ground under the clip (the terrain) as a second mesh")
    _world_arguments(export)
    export.add_argument("-q", "--quiet", action="store_true", help="no summary")

    poses = sub.add_parser("poses", help="render the key poses of a walk side by side (PNG)",
                           description="Render a creature's key poses - contact, down, pass, up and the next "
                                       "contact (the other foot's, the mirror of the first) - side by side from the "
                                       "side, each labelled with its cycle phase and frame. Edit them with "
                                       "--set poses.down_height=-0.08 etc., or start from a --style.",
                           epilog=POSES_EPILOG, formatter_class=argparse.RawDescriptionHelpFormatter)
    poses.add_argument("creature", nargs="?", default="human", metavar="CREATURE",
                       help="preset name or creature .toml (default: human)")
    poses.add_argument("-o", "--output", metavar="OUT", type=Path, help="output .png (default: CREATURE-poses.png)")
    poses.add_argument("--gait", metavar="G", help=f"gait preset: {', '.join(GAIT_PRESETS)}")
    poses.add_argument("--set", metavar="KEY=VALUE", action="append", default=[], dest="overrides",
                       help="override a creature key, e.g. poses.down_height=-0.08 (repeatable)")
    _animator_arguments(poses)
    poses.add_argument("--size", metavar="WxH", type=_size, default=(320, 360),
                       help="size of each pose's picture (default: 320x360; the sheet is five wide)")
    poses.add_argument("--second-step", action="store_true",
                       help="the second step (right foot's contact to the left's): the first mirrored")
    poses.add_argument("-q", "--quiet", action="store_true", help="no summary")

    view = sub.add_parser("view", help="open the interactive viewer (needs a display; try xvfb-run)",
                          description="Open a window in which the creature walks and every parameter is a live "
                                      "control. F1 in the window lists the keyboard and mouse controls.",
                          epilog=VIEW_EPILOG, formatter_class=argparse.RawDescriptionHelpFormatter)
    view.add_argument("creature", nargs="?", default="dog", metavar="CREATURE",
                      help="preset name, creature .toml or scene .toml (default: dog)")
    view.add_argument("--gait", metavar="G", help=f"gait preset: {', '.join(GAIT_PRESETS)}")
    view.add_argument("--set", metavar="KEY=VALUE", action="append", default=[], dest="overrides",
                      help="override a creature key (repeatable)")
    _animator_arguments(view)
    _world_arguments(view)
    view.add_argument("--size", metavar="WxH", type=_size, default=(1280, 720), help="window size (default: 1280x720)")
    view.add_argument("--no-vsync", action="store_true", help="do not wait for the display (for measuring)")
    view.add_argument("--msaa", metavar="N", type=_samples, default=0,
                      help="window antialiasing samples: 0, 2, 4 or 8 (default: 0, fastest without a GPU)")
    view.add_argument("--frames", metavar="N", type=int, help="run N frames (fixed 1/60 s steps), then exit")
    view.add_argument("--screenshot", metavar="PATH", type=Path,
                      help="with --frames: save the window (with UI) as PNG after the last frame")
    view.add_argument("--herd", metavar="N", type=_herd, default=1,
                      help="N animals in all: the creature you edit and N - 1 more of its kind following it "
                           "(size +-10%%, speed, step), keeping apart from each other")
    view.add_argument("--overlays", metavar="LIST", type=_overlays, default=(),
                      help=f"draw on the ground (View panel): {', '.join(OVERLAYS)} - the last footprints, "
                           "where swinging feet will land, the planted feet's support polygon with the trunk's "
                           "centre in it (e.g. --overlays footprints,support)")
    view.add_argument("--hide-ui", action="store_true", help="start with the panels hidden (Tab shows them)")
    view.add_argument("--report-fps", action="store_true", help="print the frame rate and time split at exit")
    view.add_argument("--dump-state", metavar="PATH", type=Path, help=argparse.SUPPRESS)
    return parser


# -- commands ----------------------------------------------------------------------------


def cmd_creatures(args: argparse.Namespace) -> int:
    from .gaits import gaits_for
    from .rigging import build_rig
    from .resources import preset_creature_names
    from .spec import leg_type, load_creature

    print("Creatures (gaitlab render NAME):")
    rows = []
    for name in preset_creature_names():
        spec = load_creature(name)
        rig = build_rig(spec)
        kind = leg_type(spec.girdles[-1][0].ankle_lift)
        pairs = spec.pair_count
        rows.append((name, f"{spec.description}  [{pairs} leg pair{'s' if pairs > 1 else ''}, {kind}, hip height "
                           f"{rig.hip_height:.2f} m, gait {spec.gait.preset}; gaits: {', '.join(gaits_for(pairs))}]"))
    _print_rows(rows)
    print("\nGaits (--gait NAME):")
    _print_rows([(g.name, f"{g.description}  [duty factor {g.duty_factor:.2f}; for {g.fits_text}]")
                 for g in GAIT_PRESETS.values()])
    from .resources import scenes_dir
    from .scenes import scene_description

    print("\nExample scenes (gaitlab render PATH, gaitlab view PATH):")
    _print_rows([(str(path), scene_description(path)) for path in sorted(scenes_dir().glob("*.toml"))])
    if args.keys:
        from .spec import override_keys, rule_for

        print("\nCreature file keys (--set KEY=VALUE):")
        _print_rows([(key, f"{rule.doc}; {rule.allowed()}") for key in override_keys()
                     if (rule := rule_for(key)) is not None])
    return 0


def _print_rows(rows: list[tuple[str, str]]) -> None:
    width = max(len(name) for name, _ in rows)
    for name, text in rows:
        print(f"  {name:<{width}}  {text}")


def cmd_render(args: argparse.Namespace) -> int:
    from .output import output_format
    from .recording import RecordRequest, gif_fps_warning, record
    from .render.clip import ViewSettings
    from .render.renderer import RenderOptions

    output = args.output or Path(f"{Path(args.creature).stem}.gif")
    fmt = output_format(output)
    spec, world, speed = _creature_and_world(args)
    _choose_fps(args, spec)
    from .kinematics.path import StraightPath

    turns = not isinstance(world.path, StraightPath)  # a straight line under the body says little
    antialias = args.antialias or (DEFAULT_ANTIALIAS if args.msaa is None else "msaa" if args.msaa else "off")
    if args.antialias is not None and args.antialias != "msaa" and args.msaa:
        raise GaitlabError(f"--msaa {args.msaa} asks for multisampling but --antialias is {args.antialias}; "
                           "give one of them")
    view = ViewSettings(size=args.size, camera=args.camera, antialias=antialias,
                        samples=4 if args.msaa is None else args.msaa,
                        options=RenderOptions(grid=not args.no_grid, shadow=not args.no_shadow,
                                              joints=not args.no_joints, path=turns and not args.no_path))
    arcs: tuple[str, ...] = ()
    if args.arcs is not None:
        from .kinematics.arcs import parse_arc_joints

        try:
            arcs = parse_arc_joints(args.arcs)
        except ValueError as exc:
            raise GaitlabError(str(exc)) from None
    request = RecordRequest(spec=spec, output=output, fps=args.fps, seconds=args.seconds, cycles=args.cycles,
                            start=args.time, view=view, speed=speed, world=world, gif_quality=args.gif_quality,
                            crf=args.crf, herd=args.herd, arcs=arcs)
    if fmt == "gif" and (warning := gif_fps_warning(args.fps)) and not args.quiet:
        print(warning, file=sys.stderr)

    bar = None
    progress = None
    if fmt != "png" and not args.quiet and sys.stderr.isatty():
        from tqdm import tqdm

        bar = tqdm(total=0, unit="frame", desc=f"render {output.name}", leave=False, dynamic_ncols=True)

        def progress(done: int, total: int) -> None:
            if bar.total != total:
                bar.reset(total=total)
            bar.update(done - bar.n)

    try:
        result = record(request, progress=progress)
    finally:
        if bar is not None:
            bar.close()
    for note in result.notes:
        print(f"note: {note}", file=sys.stderr)
    if not args.quiet:
        size = result.path.stat().st_size
        w, h = args.size
        if fmt == "png":
            print(f"wrote {result.path} ({w}x{h}, {spec.name} {spec.gait.preset} at t = {args.time:g} s, "
                  f"{size / 1024:.0f} KiB)")
        else:
            gaits = " -> ".join(result.gaits) if result.gaits else spec.gait.preset
            print(f"wrote {result.path}: {result.frames} frames, {result.seconds:.2f} s at {args.fps:g} fps "
                  f"({result.cycles:.2f} cycles of {spec.name} {gaits}), {w}x{h}, {size / 1024:.0f} KiB")
    return 0


def _choose_fps(args: argparse.Namespace, spec) -> None:
    """--fps, or the creature's timing frame rate when it gives frames per cycle (so a cycle
    of 24 frames at 24 fps is 24 frames in the file), or the command's default."""
    if args.fps is None:
        from .styles import DEFAULT_TIMING_FPS

        timed = spec.gait.frames_per_cycle is not None and args.speed is None
        args.fps = (spec.gait.timing_fps or DEFAULT_TIMING_FPS) if timed else args.default_fps


def _is_scene(name: str) -> bool:
    """Whether a .toml argument is a scene file (it has [[creatures]]) rather than a creature."""
    from .tomlfile import TomlProblem, read_toml

    path = Path(name)
    if path.suffix.lower() != ".toml" or not path.is_file():
        return False
    try:
        return "creatures" in read_toml(path)
    except TomlProblem:
        return False  # the creature loader reports it


def _creature_and_world(args: argparse.Namespace):
    """The creature (with --gait and --set), its world (--path, --terrain, --in-place, or a
    scene file's) and its speed (--speed, or the scene's)."""
    from .scenes import load_scene, make_world

    speed = getattr(args, "speed", None)
    if _is_scene(args.creature):
        given = [flag for flag, value in (("--path", args.path), ("--terrain", args.terrain),
                                          ("--in-place", args.in_place)) if value]
        if given:
            raise GaitlabError(f"{', '.join(given)}: a scene file sets its own path and terrain")
        scene = load_scene(args.creature)
        first = scene.creatures[0]
        specs = []
        for entry in scene.creatures:  # every creature must load, even those not filmed yet
            overrides = {**entry.overrides}
            if entry.gait:
                overrides["gait.preset"] = entry.gait
            specs.append(_load_with_overrides(args, entry.creature, overrides, origin=args.creature))
        spec = specs[0]
        args.scene_members = list(zip(specs[1:], [entry.world for entry in scene.creatures[1:]]))
        if len(specs) > 1 and not getattr(args, "quiet", False) and args.command != "view":
            print(f"note: {args.creature} has {len(specs)} creatures; {args.command} films the first ({spec.name}); "
                  "gaitlab view shows them all", file=sys.stderr)
        if speed is None and first.speed is not None:
            speed = (first.speed, first.speed)
        if getattr(args, "herd", None) == 1 and first.herd > 1:  # the scene's herd, unless --herd says
            args.herd = first.herd
        return spec, first.world, speed
    world = make_world(args.path, args.terrain, args.in_place)
    return _load_with_overrides(args), world, speed


def _load_with_overrides(args: argparse.Namespace, creature: str | None = None,
                         base_overrides: dict[str, object] | None = None, origin: str = "--set"):
    """The creature named on the command line (or in a scene) with the scene's settings,
    --gait and --set applied."""
    from .spec import did_you_mean, load_creature, parse_override

    spec = load_creature(creature or args.creature)
    if base_overrides:
        spec = spec.with_overrides(base_overrides, origin=origin)
    overrides: dict[str, object] = {}
    if args.gait is not None:
        if args.gait not in GAIT_PRESETS:
            raise GaitlabError(f"--gait {args.gait!r}: unknown gait{did_you_mean(args.gait, GAIT_PRESETS)}; "
                               f"gaits are: {', '.join(GAIT_PRESETS)}")
        overrides["gait.preset"] = args.gait
    style = getattr(args, "style", None)
    if getattr(args, "frames_per_cycle", None) is not None:
        if getattr(args, "speed", None) is not None:
            raise GaitlabError(f"--frames-per-cycle {args.frames_per_cycle:g} with --speed: the speed sets the timing "
                               "(the gait's frequency follows it); give one of them")
        overrides["gait.frames_per_cycle"] = args.frames_per_cycle
    for text in args.overrides:
        key, value = parse_override(text)
        overrides[key] = value
    spec = spec.with_overrides(overrides) if overrides else spec
    if style is not None:
        from .rigging import apply_style

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
    return spec


def cmd_view(args: argparse.Namespace) -> int:
    from .output import check_output_dir, output_format
    from .resources import preset_creature_names

    if args.frames is not None and args.frames < 1:
        raise GaitlabError(f"--frames {args.frames}: must be at least 1")
    if args.screenshot is not None:
        if args.frames is None:
            raise GaitlabError("--screenshot needs --frames N (the screenshot is taken after the last frame); "
                               "in the window, press F12")
        if output_format(args.screenshot) != "png":
            raise GaitlabError(f"--screenshot {args.screenshot}: screenshots are PNG; use a .png name")
        check_output_dir(args.screenshot)
    spec, world, _ = _creature_and_world(args)
    from .ui.viewer import ViewerOptions, run_viewer

    options = ViewerOptions(size=args.size, vsync=not args.no_vsync, samples=args.msaa, frames=args.frames,
                            screenshot=args.screenshot, hide_ui=args.hide_ui, report_fps=args.report_fps,
                            dump_state=args.dump_state, presets=preset_creature_names(), overlays=args.overlays,
                            herd=args.herd, scene_members=tuple(getattr(args, "scene_members", ())))
    return run_viewer(spec, options, world)


def cmd_analyze(args: argparse.Namespace) -> int:
    import json

    from .analysis import analyze_tracks, tracks_from_motion
    from .analysis.metrics import path_error
    from .analysis.plot import write_plot
    from .analysis.report import format_table, write_events_csv
    from .analysis.sources import load_tracks
    from .kinematics.clip import clip_motion
    from .output import check_output_dir
    from .rigging import build_rig

    for option, suffix in ((args.plot, ".png"), (args.csv, ".csv")):
        if option is not None:
            if option.suffix.lower() != suffix:
                raise GaitlabError(f"{option}: use a {suffix} file name")
            check_output_dir(option)
    suffix = Path(args.creature).suffix.lower()
    if suffix not in ("", ".toml", ".bvh", ".csv"):
        raise GaitlabError(f"{args.creature}: unknown file type {suffix!r}; analyze reads a creature (preset name "
                           "or .toml), a .bvh or a .csv file")
    is_file = suffix in (".bvh", ".csv")
    requested = None
    path_report = None
    if is_file:
        given = [name for name, value in (("--gait", args.gait), ("--cycles", args.cycles), ("--seconds", args.seconds),
                                          ("--speed", args.speed), ("--set", args.overrides), ("--path", args.path),
                                          ("--terrain", args.terrain), ("--in-place", args.in_place),
                                          ("--style", args.style), ("--frames-per-cycle", args.frames_per_cycle))
                 if value]
        if given:
            raise GaitlabError(f"{', '.join(given)}: for creatures; a motion file has its own gait")
        tracks, notes = load_tracks(args.creature, feet=args.feet, units=args.units, up=args.up)
        gait = None
    else:
        given = [name for name, value in (("--feet", args.feet), ("--units", args.units != "auto"),
                                          ("--up", args.up != "auto")) if value]
        if given:
            raise GaitlabError(f"{', '.join(given)}: for BVH or CSV files, not creatures")
        if args.cycles is not None and args.seconds is not None:
            raise GaitlabError("give --cycles or --seconds, not both")
        spec, world, speed = _creature_and_world(args)
        args.speed = speed
        rig = build_rig(spec)
        frequency = rig.gait.frequency
        if args.speed is not None:
            from .kinematics.speed import gait_at_speed

            frequency = max(gait_at_speed(rig, v).gait.frequency for v in args.speed)
        fps = float(max(120, math.ceil(200 * frequency)))  # ~200 frames per stride: sub-percent timing
        seconds = args.seconds
        if args.speed is None and seconds is None:
            cycles = args.cycles or 4.0
            motion, _ = clip_motion(rig, fps, cycles=cycles, world=world)
        else:
            motion, _ = clip_motion(rig, fps, seconds=seconds, cycles=args.cycles, speed=args.speed, world=world)
        tracks = tracks_from_motion(motion)
        path_report = path_error(motion)
        gait = None if args.speed is not None else spec.gait.preset
        notes = f"{motion.frame_count} frames at {fps:g} fps"
        if args.speed is None:
            requested = {name: (rig.gait.duty_factor, float(phase)) for name, phase in zip(rig.leg_names,
                                                                                           rig.gait.offsets)}
    report = analyze_tracks(tracks, requested_gait=gait)
    if not is_file:
        report.path_error = path_report
    if args.csv is not None:
        write_events_csv(report, args.csv)
    if args.plot is not None:
        write_plot(report, args.plot)
    if args.json:
        print(json.dumps(report.to_json(), indent=2))
    else:
        print(format_table(report, requested, notes))
    return 0


def cmd_export(args: argparse.Namespace) -> int:
    from .export import export_clip

    output = args.output or Path(f"{Path(args.creature).stem}.bvh")
    spec, world, speed = _creature_and_world(args)
    _choose_fps(args, spec)
    result = export_clip(spec, output, fps=args.fps, seconds=args.seconds, cycles=args.cycles, start=args.time,
                         speed=speed, world=world, loop=args.loop, ground=args.ground)
    if not args.quiet:
        size = result.path.stat().st_size
        frames = f"{result.frames} frame{'' if result.frames == 1 else 's'}"
        print(f"wrote {result.path}: {result.joints} joints, {frames} at {args.fps:g} fps "
              f"({result.seconds:.2f} s of {spec.name} {spec.gait.preset}), {result.units}, {size / 1024:.0f} KiB")
    return 0


def cmd_poses(args: argparse.Namespace) -> int:
    from .output import output_format
    from .sheet import write_pose_sheet

    output = args.output or Path(f"{Path(args.creature).stem}-poses.png")
    if output.suffix.lower() != ".png" or output_format(output) != "png":
        raise GaitlabError(f"{output}: the poses sheet is a PNG; give a file name ending in .png")
    if Path(args.creature).suffix.lower() == ".toml" and _is_scene(args.creature):
        raise GaitlabError(f"{args.creature}: a scene file; give one creature (a preset name or creature .toml)")
    spec = _load_with_overrides(args)
    sheet = write_pose_sheet(spec, output, args.size, args.second_step)
    if not args.quiet:
        h, w = sheet.image.shape[:2]
        print(f"wrote {output} ({w}x{h}: {', '.join(sheet.names)} of the {spec.name}'s "
              f"{'second' if args.second_step else 'first'} step, {output.stat().st_size / 1024:.0f} KiB)")
    return 0


COMMANDS = {"creatures": cmd_creatures, "render": cmd_render, "export": cmd_export, "analyze": cmd_analyze,
            "view": cmd_view, "poses": cmd_poses}


class Terminated(KeyboardInterrupt):
    """SIGTERM, raised like Ctrl-C so the same clean-up runs (exit status 143)."""


def _terminate(signum: int, frame: object) -> None:
    raise Terminated


def main(argv: Sequence[str] | None = None) -> int:
    import signal
    import threading

    if threading.current_thread() is threading.main_thread():
        signal.signal(signal.SIGTERM, _terminate)
    parser = build_parser()
    args = parser.parse_args(argv)
    if args.command is None:
        parser.print_help()
        return EXIT_BAD_INPUT
    try:
        return COMMANDS[args.command](args)
    except GaitlabError as exc:
        print(f"gaitlab {args.command}: error: {exc}", file=sys.stderr)
        return EXIT_BAD_INPUT
    except KeyboardInterrupt as exc:
        print(f"gaitlab {args.command}: interrupted; no output written", file=sys.stderr)
        return 143 if isinstance(exc, Terminated) else 130
    except BrokenPipeError:  # the reader went away (gaitlab creatures | head): stop quietly
        import os

        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 0


if __name__ == "__main__":
    sys.exit(main())
