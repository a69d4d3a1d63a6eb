"""What a clip may ask for, checked the same way by ``render`` and ``export`` (a leaf)."""

from __future__ import annotations

import math

from .errors import GaitlabError

MIN_FPS = 1.0
MAX_FPS = 240.0
MAX_START = 86400.0  # s: the clock a clip may start at (beyond a day the clock's numbers lose the frame)
MAX_SECONDS = 600.0
MAX_SPEED = 30.0


def check_clip(fps: float, seconds: float | None, cycles: float | None, start: float,
               speed: tuple[float, float] | None) -> None:
    """Raise :class:`GaitlabError` (one line) for a clip Gaitlab will not make."""
    if not (MIN_FPS <= fps <= MAX_FPS) or not math.isfinite(fps):
        raise GaitlabError(f"fps {fps:g}: must be at least {MIN_FPS:g} and at most {MAX_FPS:g}")
    if seconds is not None and cycles is not None:
        raise GaitlabError("give seconds or cycles, not both")
    for name, value in (("seconds", seconds), ("cycles", cycles)):
        if value is not None and not (0 < value <= MAX_SECONDS and math.isfinite(value)):
            raise GaitlabError(f"{name} {value:g}: must be greater than 0 and at most {MAX_SECONDS:g}")
    if not math.isfinite(start) or not 0 <= start <= MAX_START:
        raise GaitlabError(f"time {start:g}: must be a number of seconds from 0 to {MAX_START:g}")
    if speed is not None:
        if any(not (0 < v <= MAX_SPEED and math.isfinite(v)) for v in speed):
            raise GaitlabError(f"speed {speed[0]:g}:{speed[1]:g}: speeds must be in (0, {MAX_SPEED:g}] m/s")
        if cycles is not None and speed[0] != speed[1]:
            raise GaitlabError("with a changing --speed give the length in --seconds (cycles vary in length)")
