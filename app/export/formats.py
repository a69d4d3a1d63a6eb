"""Which files ``gaitlab export`` writes (a leaf: the CLI's help imports it cheaply)."""

from __future__ import annotations

import os
from pathlib import Path
from typing import Literal

from ..errors import OutputError

ExportFormat = Literal["bvh", "glb", "usda", "usdc"]
EXPORT_FORMATS: tuple[str, ...] = ("bvh", "glb", "usda", "usdc")


def export_format(path: str | os.PathLike[str]) -> ExportFormat:
    """The export format of ``path`` from its suffix; :class:`OutputError` if unsupported."""
    suffix = Path(path).suffix.lower().lstrip(".")
    if suffix not in EXPORT_FORMATS:
        shown = f"'.{suffix}'" if suffix else "no suffix"
        raise OutputError(f"{os.fspath(path)}: export has {shown}; use {', '.join('.' + f for f in EXPORT_FORMATS)}")
    return suffix  # type: ignore[return-value]
