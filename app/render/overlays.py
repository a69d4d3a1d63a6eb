"""Overlays on the ground: footprints, touchdown targets and the support polygon, as
shapes the renderer draws (instanced flat ellipsoids and ribbons; no GL here).

The geometry comes from :mod:`app.kinematics.overlays`; this module only decides how it
looks: footprints are flat discs in the leg's side colour fading into the ground colour
with age, touchdown targets are amber rings (a dark disc under a lighter one), and the
support polygon is a ribbon on the ground with the trunk's centre as a dot, green when
it lies inside (statically stable) and red when outside.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from ..kinematics.path import left_of
from ..kinematics.terrain import FlatTerrain, Terrain
from .scene import ELLIPSOID_FLOATS

TARGET_COLOR = np.array([0.95, 0.55, 0.05]) ** 2  # amber (linear)
STABLE_COLOR = np.array([0.20, 0.75, 0.30]) ** 2
UNSTABLE_COLOR = np.array([0.90, 0.20, 0.15]) ** 2
SUPPORT_COLOR = np.array([0.30, 0.30, 0.34]) ** 2
WAYPOINT_COLOR = np.array([0.23, 0.49, 0.85]) ** 2  # the path's blue
LEADER_COLOR = np.array([0.98, 0.80, 0.20]) ** 2  # gold: the herd's leader (the creature being edited)
LEADER_DOTS = 20


@dataclass(frozen=True)
class Overlays:
    """What to draw on the ground (world space, metres). ``size``: a foot's size (m),
    which scales every marker. Empty arrays draw nothing."""

    size: float
    footprints: NDArray[np.float64] = field(default_factory=lambda: np.zeros((0, 3)))  # (N, 3)
    footprint_age: NDArray[np.float64] = field(default_factory=lambda: np.zeros(0))  # (N,) 0 new .. 1 oldest
    footprint_colors: NDArray[np.float64] = field(default_factory=lambda: np.zeros((0, 3)))  # (N, 3) linear
    targets: NDArray[np.float64] = field(default_factory=lambda: np.zeros((0, 3)))  # (S, 3)
    waypoints: NDArray[np.float64] = field(default_factory=lambda: np.zeros((0, 3)))  # (W, 3) the route's points
    support: NDArray[np.float64] | None = None  # (K, 2) the polygon's corners (x, z), in order
    centre: NDArray[np.float64] | None = None  # (2,) the trunk's centre on the ground (x, z)
    stable: bool = False  # the centre lies inside the support polygon
    leader: NDArray[np.float64] | None = None  # (3,) under a herd's leader: a gold ring
    leader_radius: float = 0.0  # m, the ring's outer radius

    def markers(self, ground_color: NDArray[np.float64], terrain: Terrain | None = None) -> NDArray[np.float32]:
        """Flat ellipsoid rows (M, 18) for footprints, targets and the centre dot, on
        ``terrain`` (default: flat ground)."""
        terrain = terrain or FlatTerrain()
        s = self.size
        fade = self.footprint_age[:, None]
        rows = [_discs(self.footprints, terrain, 0.45 * s, 0.015 * s,
                       self.footprint_colors * (1.0 - fade) + ground_color * fade)]
        if len(self.targets):
            rows.append(_discs(self.targets, terrain, 0.55 * s, 0.015 * s, TARGET_COLOR * 0.35))
            rows.append(_discs(self.targets, terrain, 0.38 * s, 0.03 * s, TARGET_COLOR))
        if len(self.waypoints):
            rows.append(_discs(self.waypoints, terrain, 1.1 * s, 0.03 * s, WAYPOINT_COLOR * 0.3))
            rows.append(_discs(self.waypoints, terrain, 0.8 * s, 0.06 * s, WAYPOINT_COLOR))
        if self.leader is not None and self.leader_radius > 0:  # a ring of gold dots (the grid shows through)
            r = self.leader_radius
            a = np.linspace(0.0, 2.0 * np.pi, LEADER_DOTS, endpoint=False)
            ring = self.leader[None, :] + r * np.column_stack([np.cos(a), np.zeros_like(a), np.sin(a)])
            rows.append(_discs(ring, terrain, 0.09 * r, 0.01 * r, LEADER_COLOR))
        if self.centre is not None:
            c = np.array([[self.centre[0], 0.0, self.centre[1]]])
            rows.append(_discs(c, terrain, 0.35 * s, 0.04 * s, STABLE_COLOR if self.stable else UNSTABLE_COLOR))
        return np.concatenate(rows).astype(np.float32)

    def outline(self, terrain: Terrain | None = None) -> NDArray[np.float32] | None:
        """The support polygon as a closed ribbon (a triangle strip of (x, y, z) points)
        draped over the ground; two feet give their segment; None for fewer."""
        terrain = terrain or FlatTerrain()
        if self.support is None or len(self.support) < 2:
            return None
        corners = np.asarray(self.support, dtype=np.float64)
        closed = len(corners) >= 3  # two feet support along a line: the segment alone
        # Densify each edge so the ribbon follows the ground between feet.
        n = 8
        t = np.arange(n)[None, :, None] / n
        ends = np.roll(corners, -1, axis=0) if closed else corners[1:]
        starts = corners if closed else corners[:1]
        ring = (starts[:, None] + t * (ends - starts)[:, None]).reshape(-1, 2)
        ring = np.concatenate([ring, ring[:1] if closed else corners[1:]])
        tangent = np.roll(ring, -1, axis=0) - np.roll(ring, 1, axis=0)
        if closed:
            tangent[0] = tangent[-1] = ring[1] - ring[-2]
        else:
            tangent[:] = ring[-1] - ring[0]
        tangent /= np.maximum(np.linalg.norm(tangent, axis=1, keepdims=True), 1e-12)
        side = left_of(tangent) * (0.09 * self.size)
        y = terrain.height(ring) + 0.03 * self.size
        strip = np.empty((2 * len(ring), 3))
        for k, points in enumerate((ring + side, ring - side)):
            strip[k::2] = np.column_stack([points[:, 0], y, points[:, 1]])
        return strip.astype(np.float32)


def _discs(points: NDArray[np.float64], terrain: Terrain, radius: float, thickness: float,
           colors: NDArray[np.float64]) -> NDArray[np.float64]:
    """Flat discs (N, 18) lying on the ground at ``points`` (N, 3; their x, z), lifted
    by their thickness so they sit just above it."""
    n = len(points)
    if n == 0:
        return np.zeros((0, ELLIPSOID_FLOATS))
    xz = points[:, [0, 2]]
    normal = terrain.normal(xz).reshape(n, 3)
    x_axis = np.cross(normal, [0.0, 0.0, 1.0])
    x_axis /= np.maximum(np.linalg.norm(x_axis, axis=1, keepdims=True), 1e-12)
    z_axis = np.cross(x_axis, normal)
    centre = np.column_stack([xz[:, 0], terrain.height(xz), xz[:, 1]]) + normal * (1.5 * thickness)
    radii = np.broadcast_to([radius, thickness, radius], (n, 3))
    return np.concatenate([centre, x_axis, normal, z_axis, radii, np.broadcast_to(colors, (n, 3))], axis=1)
