"""What a frame shows and how it is filmed: plain values, no OpenGL (the viewer's state,
recordings and tests use them without a GL context)."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from ..choices import DEFAULT_ANTIALIAS, DEFAULT_CAMERA, Antialias, BodyStyle, CameraChoice
from ..kinematics.path import Path
from ..kinematics.terrain import FlatTerrain, Terrain


@dataclass(frozen=True)
class RenderOptions:
    """What to draw. Colours are ``#rrggbb`` (sRGB)."""

    grid: bool = True
    shadow: bool = True
    joints: bool = True  # markers at the knees, ankles and balls (with the parts body: see joint_markers)
    grid_spacing: float = 0.25  # metres between minor grid lines
    sky_color: str = "#cfd9e6"
    horizon_color: str = "#eef0ee"
    ground_color: str = "#e3ddd2"
    line_color: str = "#a89f91"
    path: bool = False  # draw the body's path on the ground
    path_color: str = "#3b7dd8"
    footprints: bool = False  # the last footprint_count footprints, fading (viewer overlays)
    footprint_count: int = 24
    targets: bool = False  # where the swinging feet will land
    support: bool = False  # the planted feet's support polygon and the trunk's centre in it
    arcs: tuple[str, ...] = ()  # joints whose paths over the last cycle are drawn (viewer; see kinematics.arcs)
    body: BodyStyle = "skin"  # one smooth skinned body, or the capsules and ellipsoids it is made from
    side_colors: bool = False  # colour legs and arms by side (left / right), as a diagnostic

    @property
    def joint_markers(self) -> bool:
        """Whether the joint markers are drawn: with the parts body only. A skinned body
        covers them (a spider's thin legs let a few pixels through), and hidden they still
        cost a software rasteriser a few percent of the frame."""
        return self.joints and self.body == "parts"


@dataclass(frozen=True)
class GroundView:
    """The ground under a frame: the terrain, how far the ground has moved back (in place),
    and the path to draw around the body's arc length ``travel`` (m) along it, as a
    ribbon ``path_width`` (m, each side of the path) wide scaled to the creature that
    walks it (:func:`path_half_width`; None: to the scene's bounds)."""

    terrain: Terrain = field(default_factory=FlatTerrain)
    offset: float = 0.0
    path: Path | None = None
    travel: float = 0.0
    path_width: float | None = None


def path_half_width(hip_height: float, body_length: float) -> float:
    """How wide (m, each side) a path ribbon is for a creature whose hips stand
    ``hip_height`` m high on a body ``body_length`` m long: a line its own size, under
    its feet (an ant's as a dog's; a long low centipede's still visible far off)."""
    return 0.02 * hip_height + 0.004 * body_length + 0.0005


@dataclass(frozen=True)
class ViewSettings:
    """How a clip is filmed: image size (pixels), camera preset, antialiasing, options.

    ``antialias``: "fxaa" (the default: one pass over the pixels near the creature,
    about half the time of multisampling on a software renderer, nearly the same look),
    "msaa" (``samples`` per pixel, the finest edges) or "off"."""

    size: tuple[int, int] = (480, 360)
    camera: CameraChoice = DEFAULT_CAMERA
    antialias: Antialias = DEFAULT_ANTIALIAS
    samples: int = 4  # multisampling's samples per pixel, for antialias "msaa"
    options: RenderOptions = field(default_factory=RenderOptions)


def nice_grid_spacing(scale: float) -> float:
    """A round grid spacing (1, 2.5 or 5 x 10^k m) near a quarter of ``scale`` (m)."""
    raw = max(scale / 4.0, 1e-3)
    exponent = math.floor(math.log10(raw))
    for step in (1.0, 2.5, 5.0, 10.0):
        if raw <= step * 10 ** exponent * 1.5:
            return step * 10 ** exponent
    return 10.0 ** (exponent + 1)
