"""The ``gaitlab`` command.

Every user error ends the same way: one line on stderr naming the file, key or value and
what is allowed, exit status 2, no traceback, no partial output.

One module per command (``creatures``, ``render``, ``analyze``, ``export``, ``poses``,
``view``), each with ``add_parser`` and ``run``; :mod:`.options` declares the options
they share once, :mod:`.inputs` turns them into a creature or a cast. Building the
parser imports no numpy, so ``gaitlab --version`` and ``--help`` start at once.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence

from .. import __version__
from ..errors import GaitlabError
from . import analyze, compare, creatures, export, fit, poses, render, view
from .options import EXIT_BAD_INPUT, Parser

COMMANDS = {"creatures": creatures, "render": render, "export": export, "analyze": analyze, "compare": compare,
            "fit": fit, "view": view, "poses": poses}


def build_parser() -> argparse.ArgumentParser:
    parser = Parser(prog="gaitlab", description="Procedural legged locomotion: tetrapods, bipeds (a human, a "
                    "bird, a theropod), insects, spiders and centipedes walking paths over terrain, their legs "
                    "driven by gait oscillators and analytic IK, with an animator's key poses, styles and arcs, "
                    "rendered headless or live.",
                    epilog="Run 'gaitlab COMMAND --help' for a command's options.")
    parser.add_argument("--version", action="version", version=f"gaitlab {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=Parser)
    for module in (creatures, render, analyze, compare, fit, export, poses, view):
        module.add_parser(sub)
    return parser


class Terminated(KeyboardInterrupt):
    """SIGTERM, raised like Ctrl-C so the same clean-up runs (exit status 143)."""


def _terminate(signum: int, frame: object) -> None:
    raise Terminated


def main(argv: Sequence[str] | None = None) -> int:
    import signal
    import threading

    previous = None
    if threading.current_thread() is threading.main_thread():
        previous = signal.signal(signal.SIGTERM, _terminate)
    try:
        parser = build_parser()
        args = parser.parse_args(argv)
        if args.command is None:
            parser.print_help()
            return EXIT_BAD_INPUT
        return _run(args)
    finally:
        if previous is not None:
            signal.signal(signal.SIGTERM, previous)


def _run(args: argparse.Namespace) -> int:
    try:
        return COMMANDS[args.command].run(args)
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
