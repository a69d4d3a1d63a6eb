"""Which files ``gaitlab export`` writes (a leaf: the CLI's help imports it cheaply)."""

from __future__ import annotations

import os

from ..choices import EXPORT_FORMATS, ExportFormat
from ..output.files import format_by_suffix


def export_format(path: str | os.PathLike[str]) -> ExportFormat:
    """The export format of ``path`` from its suffix; :class:`OutputError` if unsupported."""
    allowed = ", ".join("." + f for f in EXPORT_FORMATS)
    return format_by_suffix(path, EXPORT_FORMATS, "export", allowed)  # type: ignore[return-value]
