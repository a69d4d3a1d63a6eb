"""``gaitlab render``: a creature, or every creature of a scene, to PNG, GIF or MP4 (headless)."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from ..choices import (
    ANTIALIAS_MODES,
    ARC_JOINTS,
    BODY_STYLES,
    CAMERA_CHOICES,
    DEFAULT_ANTIALIAS,
    DEFAULT_CAMERA,
    DEFAULT_CRF,
    DEFAULT_GIF_QUALITY,
    GIF_QUALITIES,
    MAX_CRF,
)
from ..errors import GaitlabError
from .options import (
    add_clip,
    add_creature,
    add_speed,
    add_world,
    crf,
    herd,
    samples,
    seconds_from_zero,
    size,
    world_help,
)

EPILOG = """\
examples:
  gaitlab render                                   dog.gif: the dog walking ahead, two seamless cycles
  gaitlab render horse --gait gallop -o horse.mp4  a galloping horse as H.264 video
  gaitlab render cat -o cat.png --time 0.3         one frame, 0.3 s into the walk
  gaitlab render bear --camera side --cycles 3 --fps 30 --size 640x360
  gaitlab render dog --path circle:r=2 --terrain hills:amp=0.15 --seconds 8
  gaitlab render spider --terrain stairs:rise=0.08 --seconds 10 -o climb.mp4
  gaitlab render ant --path waypoints:0,0,1,1,2,0,3,1 --seconds 6
  gaitlab render dog --in-place                    the cycle on a treadmill (the ground moves)
  gaitlab render scenes/paddock.toml               a scene file: every creature on its own path
  gaitlab render dog --set gait.duty_factor=0.8 --set legs.hind.femur=0.25 -o slow.gif

CREATURE is a preset (see 'gaitlab creatures'), a creature .toml file or a scene .toml.
The creature walks along --path over --terrain (default: straight ahead on flat ground)
and the camera follows it, keeping the preset's angle to its heading; in a scene it
follows the first creature and keeps every other one in frame.
""" + "{world}" + """\
--gait replaces the creature's gait with a preset and drops its gait adjustments; add
--set gait.KEY=VALUE to adjust the new gait. --set takes any key a creature file has
('gaitlab creatures --keys' lists them); values are TOML (numbers, "strings").
Without --seconds the clip is two whole gait cycles, which loop without a seam.
"""


def add_parser(sub: argparse._SubParsersAction) -> None:
    parser = sub.add_parser("render", help="render a creature or a scene to PNG, GIF or MP4 (headless)",
                            description="Render a creature (or every creature of a scene) headless (EGL) to a PNG "
                                        "frame, a looping GIF or an H.264 MP4.",
                            epilog=EPILOG.replace("{world}", world_help()),
                            formatter_class=argparse.RawDescriptionHelpFormatter)
    add_creature(parser)
    add_clip(parser, output_help="output file: .png, .gif or .mp4 (default: CREATURE.gif)",
             cycles_help="clip length in gait cycles (default: 2; loops seamlessly)", fps=25.0)
    parser.add_argument("--time", metavar="T", type=seconds_from_zero, default=0.0,
                        help="time in seconds of the PNG frame, or of a clip's first frame (default: 0)")
    add_speed(parser)
    add_world(parser)
    look = parser.add_argument_group("the picture")
    look.add_argument("--size", metavar="WxH", type=size, default=(480, 360), help="image size (default: 480x360)")
    look.add_argument("--herd", metavar="N", type=herd, default=None,
                      help="N animals in all: the creature and N - 1 more of its kind following it, each a "
                           "little different in size (+-10%%), speed and step (travelling only; default: 1, or "
                           "the scene's)")
    look.add_argument("--camera", choices=CAMERA_CHOICES, default=DEFAULT_CAMERA,
                      help=f"camera preset (default: {DEFAULT_CAMERA}); a travelling creature is followed "
                           "at the preset's angle to its heading; 'chase' films from behind, looking ahead; "
                           "'follow' is the default angle")
    look.add_argument("--antialias", choices=ANTIALIAS_MODES, default=None,
                      help="smooth edges: fxaa (one fast pass over the creature), msaa (multisampling: the "
                           "finest edges, about twice the time without a GPU) or off (default: fxaa)")
    look.add_argument("--msaa", metavar="N", type=samples, default=None,
                      help="multisampling with N samples: 2, 4 or 8; 0 turns antialiasing off "
                           "(the same as --antialias msaa or off; default: 4 with --antialias msaa)")
    look.add_argument("--gif-quality", choices=GIF_QUALITIES, default=None,
                      help="GIF size against fidelity: best (255 colours, lossless), good (about half the size, "
                           "no visible loss), small (about a third, some grain); smaller GIFs need gifsicle "
                           f"installed (default: {DEFAULT_GIF_QUALITY})")
    look.add_argument("--crf", metavar="N", type=crf, default=None,
                      help=f"MP4 quality: H.264 constant rate factor, 0 (lossless, large) to {MAX_CRF} "
                           f"(smallest); +6 roughly halves the file (default: {DEFAULT_CRF})")
    look.add_argument("--no-grid", action="store_true", help="plain ground without grid lines")
    look.add_argument("--no-shadow", action="store_true", help="no shadow")
    look.add_argument("--no-joints", action="store_true", help="no joint markers on the legs (the parts body's: --body parts)")
    look.add_argument("--body", choices=BODY_STYLES, default="skin",
                      help="skin: one smooth skinned body (the default); parts: the capsules and ellipsoids it is "
                           "made from")
    look.add_argument("--side-colors", action="store_true",
                      help="colour legs and arms by side (the look's left and right colours; with --body parts)")
    look.add_argument("--no-path", action="store_true",
                      help="do not draw a turning path on the ground (a straight one never is)")
    look.add_argument("--arcs", metavar="JOINTS",
                      help=f"draw the paths of joints over the last cycle, beaded at the key poses: any of "
                           f"{', '.join(ARC_JOINTS)}, separated by commas (e.g. toe,hand)")
    parser.add_argument("-q", "--quiet", action="store_true", help="no progress bar or summary")


def _view(args: argparse.Namespace, turns: bool):
    from ..render.options import RenderOptions, ViewSettings

    antialias = args.antialias or (DEFAULT_ANTIALIAS if args.msaa is None else "msaa" if args.msaa else "off")
    if args.antialias is not None and args.antialias != "msaa" and args.msaa:
        raise GaitlabError(f"--msaa {args.msaa} asks for multisampling but --antialias is {args.antialias}; "
                           "give one of them")
    return ViewSettings(size=args.size, camera=args.camera, antialias=antialias,
                        samples=4 if args.msaa is None else args.msaa,
                        options=RenderOptions(grid=not args.no_grid, shadow=not args.no_shadow,
                                              joints=not args.no_joints, path=turns and not args.no_path,
                                              body=args.body, side_colors=args.side_colors))


def _arcs(args: argparse.Namespace) -> tuple[str, ...]:
    if args.arcs is None:
        return ()
    from ..kinematics.arcs import parse_arc_joints

    try:
        return parse_arc_joints(args.arcs)
    except ValueError as exc:
        raise GaitlabError(str(exc)) from None


def run(args: argparse.Namespace) -> int:
    from ..kinematics.path import StraightPath
    from ..output import output_format
    from ..recording import RecordRequest, gif_fps_warning
    from .inputs import choose_fps, load_cast

    output = args.output or Path(f"{Path(args.creature).stem}.gif")
    fmt = output_format(output)
    for option, value, wants in (("--crf", args.crf, "mp4"), ("--gif-quality", args.gif_quality, "gif")):
        if value is not None and fmt != wants:
            raise GaitlabError(f"{option} {value} sets a .{wants}'s quality, and {output} is a .{fmt}; drop it or "
                               f"write a .{wants}")
    if fmt == "png":
        _refuse_clip_options(args, output)
    if args.side_colors and args.body != "parts":
        raise GaitlabError("--side-colors colours the parts' legs and arms by side: give it with --body parts")
    cast = load_cast(args)
    lead = cast[0]
    fps = choose_fps(args, lead.spec, lead.speed)
    turns = any(not isinstance(actor.world.path, StraightPath) for actor in cast)  # a straight line says little
    request = RecordRequest(cast=cast, output=output, fps=fps, seconds=args.seconds, cycles=args.cycles,
                            start=args.time, view=_view(args, turns), gif_quality=args.gif_quality or DEFAULT_GIF_QUALITY,
                            crf=DEFAULT_CRF if args.crf is None else args.crf,
                            arcs=_arcs(args))
    if fmt == "gif" and (warning := gif_fps_warning(fps)) and not args.quiet:
        print(warning, file=sys.stderr)
    result = _record_with_progress(request, output, show=fmt != "png" and not args.quiet and sys.stderr.isatty())
    for note in result.notes:
        print(f"note: {note}", file=sys.stderr)
    if not args.quiet:
        size_kib = result.path.stat().st_size / 1024
        w, h = args.size
        names = _and([a.spec.name for a in cast])
        if fmt == "png":
            print(f"wrote {result.path} ({w}x{h}, {names} {lead.spec.gait.preset} at t = {args.time:g} s, "
                  f"{size_kib:.0f} KiB)")
        else:
            gaits = " -> ".join(result.gaits) if result.gaits else lead.spec.gait.preset
            what = f"{len(cast)} creatures: {names}" if len(cast) > 1 else f"{names} {gaits}"
            print(f"wrote {result.path}: {result.frames} frames, {result.seconds:.2f} s at {fps:g} fps "
                  f"({result.cycles:.2f} cycles of {what}), {w}x{h}, {size_kib:.0f} KiB")
    return 0


def _refuse_clip_options(args: argparse.Namespace, output: Path) -> None:
    """A PNG is one frame: a clip's length means nothing there, nor does its frame rate
    (except as the sampling of --arcs, drawn over the cycle up to the frame)."""
    given = [("--seconds", args.seconds, "length"), ("--cycles", args.cycles, "length")]
    if not args.arcs:
        given.append(("--fps", args.fps, "frame rate"))
    for option, value, what in given:
        if value is not None:
            raise GaitlabError(f"{option} {value:g} sets a clip's {what}, and {output} is one frame: drop it "
                               "(--time T picks the frame) or write a .gif or .mp4")


def _and(names: list[str]) -> str:
    """``horse, dog and cat``."""
    return names[0] if len(names) == 1 else ", ".join(names[:-1]) + " and " + names[-1]


def _record_with_progress(request, output: Path, show: bool):
    """Record, with a progress bar on a terminal."""
    from ..recording import record

    if not show:
        return record(request)
    from tqdm import tqdm

    bar = tqdm(total=0, unit="frame", desc=f"render {output.name}", leave=False, dynamic_ncols=True)

    def progress(done: int, total: int) -> None:
        if bar.total != total:
            bar.reset(total=total)
        bar.update(done - bar.n)

    try:
        return record(request, progress=progress)
    finally:
        bar.close()
