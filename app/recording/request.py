"""What a recording makes (plain values, no OpenGL: the viewer's state builds one)."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

from ..cast import Actor, Cast
from ..choices import DEFAULT_CRF, DEFAULT_GIF_QUALITY, GIF_QUALITIES, MAX_SIZE, GifQuality
from ..errors import GaitlabError
from ..kinematics.world import World
from ..limits import check_clip
from ..output.gif import GIF_MAX_FPS
from ..output.video import check_crf
from ..render.options import ViewSettings
from ..spec import CreatureSpec


@dataclass(frozen=True)
class RecordRequest:
    """What to record: a cast (one creature, or every creature of a scene, each with its
    world, speed and herd). Give ``seconds`` or ``cycles`` (of the first creature's gait;
    default: two whole cycles, which loop seamlessly); ``start`` is the time (s) of the
    first frame (of the only one, for PNG). ``view`` sets size, camera, antialiasing and
    what is drawn; the camera follows the first creature and keeps the others in frame."""

    cast: Cast
    output: Path
    fps: float = 25.0
    seconds: float | None = None
    cycles: float | None = None
    start: float = 0.0
    view: ViewSettings = field(default_factory=ViewSettings)
    gif_quality: GifQuality = DEFAULT_GIF_QUALITY  # GIF size against fidelity: best, good, small
    crf: int = DEFAULT_CRF  # MP4 (H.264) constant rate factor: 0 lossless .. 51 smallest
    arcs: tuple[str, ...] = ()  # joints whose paths over the last cycle are drawn (see kinematics.arcs)

    @classmethod
    def of(cls, spec: CreatureSpec, output: Path, *, world: World | None = None,
           speed: tuple[float, float] | None = None, herd: int = 1, **settings: object) -> RecordRequest:
        """A request for one creature (``settings``: the other fields)."""
        return cls(cast=(Actor(spec, world or World(), speed, herd),), output=Path(output), **settings)  # type: ignore[arg-type]

    @property
    def lead(self) -> Actor:
        """The first creature: its gait times the clip, the camera follows it."""
        return self.cast[0]

    def __post_init__(self) -> None:
        if not self.cast:
            raise GaitlabError("a recording needs at least one creature")
        if self.gif_quality not in GIF_QUALITIES:
            raise GaitlabError(f"GIF quality {self.gif_quality!r}: choose one of {', '.join(GIF_QUALITIES)}")
        check_crf(self.crf)
        w, h = self.view.size
        if not (1 <= w <= MAX_SIZE and 1 <= h <= MAX_SIZE):
            raise GaitlabError(f"size {w}x{h}: width and height must be between 1 and {MAX_SIZE}")
        for actor in self.cast:
            check_clip(self.fps, self.seconds, self.cycles, self.start, actor.speed)


@dataclass(frozen=True)
class RecordResult:
    path: Path
    frames: int
    seconds: float
    cycles: float
    gaits: tuple[str, ...] = ()  # the gaits a speed-driven clip went through, in order
    notes: tuple[str, ...] = ()  # things the user should know about the file (e.g. an optimiser missing)


def gif_fps_warning(fps: float) -> str | None:
    """A warning for GIF frame rates that browsers do not play at full speed."""
    if fps > GIF_MAX_FPS:
        return (f"warning: GIF frame delays under 20 ms ({fps:g} fps) are slowed down by most browsers; "
                f"use --fps {GIF_MAX_FPS} or less, or write .mp4")
    return None
