"""Recording a cast (one creature, or every creature of a scene) to PNG, GIF or MP4: the
single path used by ``gaitlab render`` and by the viewer's Record panel, so equal
settings give equal pixels.

- :mod:`.request`: what to record (:class:`RecordRequest`; no OpenGL);
- :mod:`.job`: rendering it frame by frame into the file (:class:`Recording`, :func:`record`).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from .request import RecordRequest, RecordResult, gif_fps_warning

if TYPE_CHECKING:
    from .job import Recording, record

__all__ = ["RecordRequest", "RecordResult", "Recording", "gif_fps_warning", "record"]


def __getattr__(name: str) -> Any:
    if name in ("Recording", "record"):
        from . import job

        return getattr(job, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
