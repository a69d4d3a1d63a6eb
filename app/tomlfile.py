"""Reading TOML text safely: every failure of the parser becomes one message.

``tomllib`` raises :class:`tomllib.TOMLDecodeError` for syntax errors, but also
:class:`RecursionError` for deeply nested arrays or tables and :class:`ValueError` for
integers longer than Python converts (4300 digits); files are also capped in size so a
stray multi-gigabyte file is refused before it is read.
"""

from __future__ import annotations

import os
import tomllib
from pathlib import Path
from typing import Any

MAX_TOML_BYTES = 16 * 2**20


class TomlProblem(ValueError):
    """Why a TOML text or file could not be read; the message is one line."""


def parse_toml(text: str) -> dict[str, Any]:
    """``tomllib.loads`` with every parser failure as :class:`TomlProblem`."""
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise TomlProblem(f"TOML syntax error: {exc}") from None
    except RecursionError:
        raise TomlProblem("TOML syntax error: arrays or tables nested too deeply") from None
    except ValueError as exc:  # e.g. an integer with more digits than Python converts
        raise TomlProblem(f"TOML value error: {str(exc).split(';')[0]}") from None


def read_toml(path: str | os.PathLike[str]) -> dict[str, Any]:
    """A TOML file's contents; :class:`TomlProblem` for unreadable, oversized or invalid files."""
    path = Path(path)
    try:
        with open(path, "rb") as fh:
            data = fh.read(MAX_TOML_BYTES + 1)  # not stat(): pipes and /proc files say 0
        if len(data) > MAX_TOML_BYTES:
            raise TomlProblem(f"the file is over {MAX_TOML_BYTES // 2**20} MiB; TOML files up to that size are read")
        text = data.decode("utf-8-sig")  # -sig: an editor's byte-order mark is not part of the TOML
    except IsADirectoryError:
        raise TomlProblem("is a folder; give a .toml file") from None
    except OSError as exc:
        raise TomlProblem(f"cannot read: {exc.strerror or exc}") from None
    except UnicodeDecodeError as exc:
        raise TomlProblem(f"not UTF-8 text ({exc.reason} at byte {exc.start})") from None
    return parse_toml(text)
