"""Native file dialogs for the viewer's File panel (imgui-bundle's portable-file-dialogs),
with the path field as the fallback where no dialog can open (no zenity or kdialog, e.g.
on a bare Xvfb display)."""

from __future__ import annotations

import shutil
from typing import Any, Literal

DialogKind = Literal["open", "save"]
_TOOLS = ("zenity", "kdialog", "qarma", "matedialog")  # what portable-file-dialogs drives on Linux
_FILTERS = ["Creature files (*.toml)", "*.toml"]
_OPEN_FILTERS = ["Creatures and rigged models (*.toml *.glb *.gltf)", "*.toml *.glb *.gltf", *_FILTERS]


def dialogs_available() -> bool:
    """Whether a native file dialog can open on this system."""
    import sys

    return not sys.platform.startswith("linux") or any(shutil.which(tool) for tool in _TOOLS)


class FileDialog:
    """At most one dialog at a time, polled once per frame (the dialog runs on its own)."""

    def __init__(self) -> None:
        self._dialog: Any = None  # a portable_file_dialogs open_file or save_file while one is open
        self.kind: DialogKind | None = None

    @property
    def open(self) -> bool:
        return self._dialog is not None

    def start(self, kind: DialogKind, start_path: str) -> None:
        from imgui_bundle import portable_file_dialogs as pfd

        if self._dialog is not None:
            return
        self.kind = kind
        if kind == "open":
            self._dialog = pfd.open_file("Load a creature or a rigged model", start_path, _OPEN_FILTERS)
        else:
            self._dialog = pfd.save_file("Save the creature", start_path, _FILTERS)

    def poll(self) -> str | None:
        """The chosen path once the dialog closes (None while open or when cancelled)."""
        if self._dialog is None or not self._dialog.ready(0):
            return None
        result = self._dialog.result()
        self._dialog = None
        if isinstance(result, list):
            result = result[0] if result else ""
        return str(result) or None
