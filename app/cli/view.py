"""``gaitlab view``: the interactive viewer (needs a display; try xvfb-run)."""

from __future__ import annotations

import argparse
from pathlib import Path

from ..choices import OVERLAYS
from ..errors import GaitlabError
from .options import add_creature, add_world, herd, overlays, panels, samples, size

EPILOG = """\
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


def add_parser(sub: argparse._SubParsersAction) -> None:
    parser = sub.add_parser("view", help="open the interactive viewer (needs a display; try xvfb-run)",
                            description="Open a window in which the creature (or every creature of a scene) walks "
                                        "and every parameter is a live control. F1 in the window lists the keyboard "
                                        "and mouse controls.",
                            epilog=EPILOG, formatter_class=argparse.RawDescriptionHelpFormatter)
    add_creature(parser)
    add_world(parser)
    window = parser.add_argument_group("the window")
    window.add_argument("--size", metavar="WxH", type=size, default=(1280, 720),
                        help="window size (default: 1280x720)")
    window.add_argument("--no-vsync", action="store_true", help="do not wait for the display (for measuring)")
    window.add_argument("--msaa", metavar="N", type=samples, default=0,
                        help="window antialiasing samples: 0, 2, 4 or 8 (default: 0, fastest without a GPU)")
    window.add_argument("--frames", metavar="N", type=int, help="run N frames (fixed 1/60 s steps), then exit")
    window.add_argument("--screenshot", metavar="PATH", type=Path,
                        help="with --frames: save the window (with UI) as PNG after the last frame")
    window.add_argument("--herd", metavar="N", type=herd, default=None,
                        help="N animals in all: the creature you edit and N - 1 more of its kind following it "
                             "(size +-10%%, speed, step), keeping apart from each other")
    window.add_argument("--overlays", metavar="LIST", type=overlays, default=(),
                        help=f"draw on the ground (View panel): {', '.join(OVERLAYS)} - the last footprints, "
                             "where swinging feet will land, the planted feet's support polygon with the trunk's "
                             "centre in it (e.g. --overlays footprints,support)")
    window.add_argument("--hide-ui", action="store_true", help="start with the panels hidden (Tab shows them)")
    window.add_argument("--panels", metavar="LIST", type=panels, default=(),
                        help="start with these sidebar panels open and the others closed, e.g. --panels "
                             "plots,key-poses (creature, gait, key-poses, body, view, terrain, path, playback, plots, "
                             "record, file)")
    window.add_argument("--report-fps", action="store_true", help="print the frame rate and time split at exit")
    window.add_argument("--dump-state", metavar="PATH", type=Path, help=argparse.SUPPRESS)


def run(args: argparse.Namespace) -> int:
    from ..output import check_output_dir, output_format
    from ..resources import preset_creature_names
    from .inputs import load_cast

    if args.frames is not None and args.frames < 1:
        raise GaitlabError(f"--frames {args.frames}: must be at least 1")
    if args.screenshot is not None:
        if args.frames is None:
            raise GaitlabError("--screenshot needs --frames N (the screenshot is taken after the last frame); "
                               "in the window, press F12")
        if output_format(args.screenshot) != "png":
            raise GaitlabError(f"--screenshot {args.screenshot}: screenshots are PNG; use a .png name")
        check_output_dir(args.screenshot)
    args.speed = None
    cast = load_cast(args)
    from ..ui.viewer import ViewerOptions, run_viewer

    options = ViewerOptions(size=args.size, vsync=not args.no_vsync, samples=args.msaa, frames=args.frames,
                            screenshot=args.screenshot, hide_ui=args.hide_ui, report_fps=args.report_fps,
                            dump_state=args.dump_state, presets=preset_creature_names(), overlays=args.overlays,
                            panels=args.panels)
    return run_viewer(cast, options)
