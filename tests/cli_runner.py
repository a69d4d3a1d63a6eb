"""Running ``gaitlab`` in the test process: ``cli.main(argv)`` with its working folder,
standard output and error captured (with the warnings a process would print), and its exit status — the same three things a
subprocess gives, without starting Python and importing numpy, scipy and moderngl again
for each command (which cost 1.5-3 s a call).

A handful of tests still start a real process, on purpose: the console script, signals
(Ctrl-C, SIGTERM, SIGKILL), a missing EGL library and the viewer's window.
"""

from __future__ import annotations

import contextlib
import io
import os
import subprocess
import sys
import warnings
from dataclasses import dataclass
from pathlib import Path


@dataclass(frozen=True)
class Completed:
    """What :func:`gaitlab` gives back (the fields of ``subprocess.CompletedProcess``
    that the tests read)."""

    args: tuple[str, ...]
    returncode: int
    stdout: str
    stderr: str


def gaitlab(*args: str | os.PathLike[str], cwd: Path | str | None = None) -> Completed:
    """``gaitlab ARGS`` run in this process, in ``cwd`` (default: the current folder)."""
    from app.cli import main

    argv = tuple(str(a) for a in args)
    out, err = io.StringIO(), io.StringIO()
    here = os.getcwd()
    try:
        if cwd is not None:
            os.chdir(cwd)
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err), \
                warnings.catch_warnings(record=True) as caught:
            # The warnings a real process would print (Python's default filters: each
            # once, deprecations and resource warnings not at all), printed as it would.
            warnings.simplefilter("default")
            for quiet in (DeprecationWarning, PendingDeprecationWarning, ImportWarning, ResourceWarning):
                warnings.simplefilter("ignore", quiet)
            try:
                code = main(list(argv))
            except SystemExit as exc:  # argparse: --help, --version and usage errors
                code = exc.code if isinstance(exc.code, int) else (0 if exc.code is None else 2)
    finally:
        os.chdir(here)
    printed = "".join(warnings.formatwarning(w.message, w.category, w.filename, w.lineno, w.line) for w in caught)
    return Completed(argv, int(code), out.getvalue(), printed + err.getvalue())


def gaitlab_process(*args: str | os.PathLike[str], cwd: Path | str | None = None, env: dict | None = None,
                    timeout: float = 300) -> subprocess.CompletedProcess:
    """``python -m app ARGS`` as a real process (for what only a process shows)."""
    return subprocess.run([sys.executable, "-m", "app", *map(str, args)], capture_output=True, text=True, cwd=cwd,
                          env={**os.environ, **(env or {})}, timeout=timeout)
