"""Which files ``gaitlab export`` writes (a leaf: the CLI's help imports it cheaply)."""

from __future__ import annotations

import os
from typing import Literal

from ..output.files import format_by_suffix

ExportFormat = Literal["bvh", "glb", "usda", "usdc"]
EXPORT_FORMATS: tuple[str, ...] = ("bvh", "glb", "usda", "usdc")


def export_format(path: str | os.PathLike[str]) -> ExportFormat:
    """The export format of ``path`` from its suffix; :class:`OutputError` if unsupported."""
    allowed = ", ".join("." + f for f in EXPORT_FORMATS)
    return format_by_suffix(path, EXPORT_FORMATS, "export", allowed)  # type: ignore[return-value]
