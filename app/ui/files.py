"""The viewer's files: loading creatures, saving them (never over a preset), exporting
and recording what the view shows."""

from __future__ import annotations

import time
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Literal

import numpy as np

from ..choices import (
    DEFAULT_ANTIALIAS,
    DEFAULT_CAMERA,
    DEFAULT_CRF,
    DEFAULT_GIF_QUALITY,
    MAX_CRF,
    Antialias,
    ExportFormat,
    GifQuality,
)
from ..errors import GaitlabError
from ..recording.request import RecordRequest
from ..render.options import RenderOptions, ViewSettings
from ..resources import creatures_dir
from ..spec import CreatureSpec, load_creature
from .base import StateBase

RecordFormat = Literal["gif", "mp4"]
LengthUnit = Literal["cycles", "seconds"]


def is_shipped(path: str | Path) -> bool:
    """Whether ``path`` is one of Gaitlab's preset creature files: in the installed
    presets' folder, or in any folder that holds the whole set (a source checkout's
    ``creatures/``, whichever copy is installed)."""
    try:
        folder = Path(path).resolve().parent
        if folder == creatures_dir().resolve():
            return True
        presets = {p.name for p in creatures_dir().glob("*.toml")}
        return Path(path).name in presets and presets <= {p.name for p in folder.glob("*.toml")}
    except OSError:
        return False


@dataclass
class RecordSettings:
    """The Record panel: what to write and how (same meaning as ``gaitlab render``)."""

    format: RecordFormat = "gif"
    unit: LengthUnit = "cycles"
    length: float = 2.0
    width: int = 480
    height: int = 360
    fps: float = 25.0
    camera: str = DEFAULT_CAMERA
    folder: str = "."
    name: str = ""  # default: <creature>.<format>
    gif_quality: GifQuality = DEFAULT_GIF_QUALITY
    crf: int = DEFAULT_CRF
    antialias: Antialias = DEFAULT_ANTIALIAS
    export_format: ExportFormat = "glb"  # File panel: the skeleton's motion as BVH, glTF or USD

    def path(self, creature: str) -> Path:
        return Path(self.folder) / f"{self.name or creature}.{self.format}"


class FilesMixin(StateBase):
    """Load, save, export and the Record panel's request."""

    def load_preset(self, name: str) -> bool:
        """Load a preset; with edits to the current creature unsaved, ask first (once, on the
        message line) and load when the same preset is chosen again."""
        if self.spec != self.base and name != self.spec.name and self._confirm_switch != name:
            self._confirm_switch = name
            self._asked_at = time.monotonic()
            self.status = (f"{self.spec.name} has edits that {name} would discard (not undoable): choose {name} "
                           "again to switch, or save first (File)")
            return False
        self._confirm_switch = None
        return self.load(name)

    def load(self, name_or_path: str) -> bool:
        """Load a preset, a creature file or a rigged model (.glb, .gltf). A file that
        fails to load leaves the current creature untouched and shows its error."""
        from ..rigged import MODEL_SUFFIXES, is_model_path
        from ..rigged.creature import model_creature

        text = str(name_or_path)
        try:
            spec = model_creature(text) if is_model_path(text) else load_creature(name_or_path)
            if is_model_path(text):
                from ..rigged.loaded import model_notes

                notes = model_notes(text)
        except GaitlabError as exc:
            self.error = str(exc)
            return False
        if not self._apply(spec, blend=False, edit=None):
            return False
        self._undo.clear()  # a new creature: its own history
        self._redo.clear()
        self.base = spec
        self.file_path = self._save_path_for(spec)
        from_file = text.lower().endswith((".toml", *MODEL_SUFFIXES))
        if from_file:
            self._remember_file(spec.source)
            if text.endswith(".toml"):
                self._know(spec.source)
        self.status = f"loaded {spec.name}" + (f" from {Path(spec.source).resolve()}" if from_file else "")
        if is_model_path(text):
            self.status += "".join(f"; note: {note}" for note in notes)
        self.frame_view()
        return True

    def _know(self, path: str | Path) -> None:
        """Note a file as this viewer last read or wrote it (its time and size): writing
        over it again needs no asking while nobody else has changed it."""
        try:
            info = Path(path).stat()
        except OSError:
            return
        self._known_files[str(Path(path).resolve())] = (info.st_mtime_ns, info.st_size)

    def _must_ask(self, path: str | Path) -> bool:
        """True when writing ``path`` would overwrite a file this viewer has not just read or
        written itself (someone else's, or changed since)."""
        target = Path(path)
        if not target.exists():
            return False
        info = target.stat()
        return self._known_files.get(str(target.resolve())) != (info.st_mtime_ns, info.st_size)

    def confirm_record(self) -> bool:
        """Whether to record now: asks first (once, on the message line) before writing over
        a file this viewer did not write itself; pressing record again goes ahead."""
        target = self.record.path(self.spec.name)
        resolved = str(target.resolve())
        if self._must_ask(target) and self._confirm_record != resolved:
            self._confirm_record = resolved
            self.status = f"{resolved} exists: record again to overwrite it"
            return False
        self._confirm_record = None
        return True

    def recorded(self, path: str | Path) -> None:
        """A recording was written to ``path``: this viewer's own from now on."""
        self._know(path)

    def _remember_file(self, path: str) -> None:
        full = str(Path(path).resolve())
        self.recent = [full] + [p for p in self.recent if p != full][:7]

    @property
    def overwrite_pending(self) -> bool:
        """True when *save* has been asked once for the existing file in the path field."""
        return self._confirm_overwrite is not None and self._confirm_overwrite == str(Path(self.file_path).resolve())

    @staticmethod
    def _save_path_for(spec: CreatureSpec) -> str:
        """Where *save* writes by default: the user's own file when one was loaded, else
        ``<name>.toml`` in the working folder — never a shipped preset."""
        if spec.source.endswith(".toml") and not is_shipped(spec.source):
            return spec.source
        return f"{spec.name}.toml"

    def save(self, path: str | None = None) -> bool:
        """Save the current creature as TOML (atomically). A shipped preset is never
        overwritten; an existing file this viewer did not just read or write itself (someone
        else's, or changed since) only when *save* is asked twice for it in a row (the first
        time says so)."""
        target = str(path or self.file_path)
        if is_shipped(target):
            self.error = (f"{Path(target).resolve()}: is one of Gaitlab's preset creatures; save under a name of "
                          f"your own, e.g. my{self.spec.name}.toml")
            return False
        resolved = str(Path(target).resolve())
        if self._must_ask(target) and self._confirm_overwrite != resolved:
            self._confirm_overwrite = resolved
            self.status = f"{resolved} exists: save again to overwrite it"
            return False
        self._confirm_overwrite = None
        try:
            written = self.spec.save(target)
        except GaitlabError as exc:
            self.error = str(exc)
            return False
        except OSError as exc:
            self.error = f"{target}: cannot write: {exc.strerror or exc}"
            return False
        self.file_path = str(written)
        self._remember_file(str(written))
        self._know(written)
        self.status = f"saved {Path(written).resolve()}"
        self.error = None
        return True

    def export(self) -> bool:
        """Export what is on screen — every creature as edited, its gait and world — as
        skeletons of the Record panel's length and frame rate from the current time, to the
        Record panel's folder and name with the chosen export format."""
        from ..export import export_cast

        r = self.record
        path = Path(r.folder) / f"{r.name or self.spec.name}.{r.export_format}"
        try:
            result = export_cast(self.cast(), path, fps=float(r.fps),
                                 seconds=r.length if r.unit == "seconds" else None,
                                 cycles=r.length if r.unit == "cycles" else None,
                                 start=float(self.live.clock) / self.live.rig.gait.frequency,
                                 loop=r.unit == "cycles" and float(r.length).is_integer())  # (whole cycles loop)
        except GaitlabError as exc:
            self.error = str(exc)
            return False
        except OSError as exc:
            self.error = f"{path}: cannot write: {exc.strerror or exc}"
            return False
        files = ", ".join(str(Path(p).resolve()) for p in result.paths)
        self.status = (f"exported {files}: {result.joints} joints, {result.frames} frames ({result.units})")
        self.error = None
        return True

    def record_request(self) -> RecordRequest:
        """The request the Record panel describes (what ``gaitlab render`` would get): every
        creature the view shows, the selected one first (the camera follows it)."""
        r = self.record
        seconds = r.length if r.unit == "seconds" else None
        cycles = r.length if r.unit == "cycles" else None
        view = ViewSettings(size=(int(r.width), int(r.height)), camera=r.camera,  # type: ignore[arg-type]
                            antialias=r.antialias,
                            options=replace(RenderOptions(), grid=self.options.grid, shadow=self.options.shadow,
                                            joints=self.options.joints, path=self.options.path,
                                            body=self.options.body, side_colors=self.options.side_colors))
        return RecordRequest(cast=self.cast(), output=r.path(self.spec.name), fps=float(r.fps), seconds=seconds,
                             cycles=cycles, view=view, gif_quality=r.gif_quality, crf=int(np.clip(r.crf, 0, MAX_CRF)))
