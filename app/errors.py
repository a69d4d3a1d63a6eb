"""User-facing errors.

Everything a user can get wrong (a creature file, a ``--set`` value, an output path, a
missing system library) raises a :class:`GaitlabError` whose message is one line that
names the file/key/value and says what is allowed. The CLI prints that line and exits
with status 2; it never shows a traceback for these.
"""

from __future__ import annotations

import difflib
import os
from collections.abc import Iterable


class GaitlabError(Exception):
    """A problem the user can fix, described in one line."""


class SpecError(GaitlabError):
    """A creature file or override is invalid (syntax, unknown key, bad value, geometry)."""


class OutputError(GaitlabError):
    """An output path cannot be written, or has a format we do not write."""


class GLContextError(GaitlabError):
    """No OpenGL context could be created (missing EGL/Mesa, no display, too old GL)."""


def shown(value: object, limit: int = 60) -> str:
    """``repr(value)`` for a message, cut short so one bad value cannot flood the line."""
    text = repr(value)
    return text if len(text) <= limit else text[:limit - 4] + "...'"


def did_you_mean(word: str, options: Iterable[str]) -> str:
    """' (did you mean 'x'?)' for the closest of ``options``, or ''."""
    match = difflib.get_close_matches(word, list(options), n=1, cutoff=0.6)
    return f" (did you mean {match[0]!r}?)" if match else ""


def not_a_file(path: str | os.PathLike[str]) -> str:
    """Why ``path``, which is not a readable regular file, cannot be read: for a message
    after the path ("no such file", "is a folder, not a file", ...)."""
    try:
        if os.path.isdir(path):
            return "is a folder, not a file"
        if os.path.exists(path):
            return "is not a regular file (a device or a pipe)"
    except (OSError, ValueError):  # a name too long, a NUL in it
        pass
    return "no such file"
