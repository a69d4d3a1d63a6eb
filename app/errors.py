"""User-facing errors.

Everything a user can get wrong (a creature file, a ``--set`` value, an output path, a
missing system library) raises a :class:`GaitlabError` whose message is one line that
names the file/key/value and says what is allowed. The CLI prints that line and exits
with status 2; it never shows a traceback for these.
"""

from __future__ import annotations

import difflib
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
