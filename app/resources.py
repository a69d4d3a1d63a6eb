"""Locating the files that ship with Gaitlab: GLSL shaders, preset creatures, example scenes.

In a source checkout (or an editable install) they are the top-level ``shaders/``,
``creatures/`` and ``scenes/`` folders; in an installed wheel they are copied to
``app/shaders``, ``app/creatures`` and ``app/scenes`` (see ``pyproject.toml``). Either way
callers ask this module.
"""

from __future__ import annotations

from functools import cache
from pathlib import Path

_PACKAGE_DIR = Path(__file__).resolve().parent


@cache
def _data_dir(name: str) -> Path:
    for candidate in (_PACKAGE_DIR / name, _PACKAGE_DIR.parent / name):
        if candidate.is_dir():
            return candidate
    raise FileNotFoundError(f"Gaitlab's {name}/ folder is missing from the installation ({_PACKAGE_DIR})")


def shaders_dir() -> Path:
    """The folder holding the GLSL sources."""
    return _data_dir("shaders")


def creatures_dir() -> Path:
    """The folder holding one TOML file per preset creature."""
    return _data_dir("creatures")


def scenes_dir() -> Path:
    """The folder holding the example scene files."""
    return _data_dir("scenes")


def reference_dir() -> Path:
    """The folder holding the reference curves (normative gait data, with their README)."""
    return _data_dir("reference")


def preset_creature_names() -> list[str]:
    """Names of the preset creatures, sorted (file stems of ``creatures/*.toml``)."""
    return sorted(p.stem for p in creatures_dir().glob("*.toml"))
