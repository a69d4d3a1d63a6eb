"""Where a foot may stand: the acceptable ground nearest to an ideal spot.

Like the terrain seed's grid search, but vectorised over every foothold at once: around
each ideal (x, z) a disc of candidate spots (rings of points) is tested, and the nearest
acceptable one wins. A spot is acceptable when

- the ground there is no steeper than the terrain's ``max_slope``, and
- the foot's footprint lies on one plane: probes from the heel to beyond the toe tip and
  to both sides, at least ``EDGE_MARGIN`` away, all sit within a small tolerance of the
  tangent plane at the spot. This keeps a foot off a riser and away from a step's edge,
  on any terrain (an exact staircase or a heightmap alike).

Feet are placed on the surface itself (y = ground height there), never under or above it.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from .terrain import Terrain

EDGE_MARGIN = 0.012  # m: the least distance from a foot's ball to an edge of its ground
RINGS = 5
RING_POINTS = 16
PLANE_TOLERANCE = 0.004  # m, plus PLANE_SLACK of the probe distance (room for curved ground)
PLANE_SLACK = 0.04


@dataclass(frozen=True)
class Footholds:
    """points (N, 3) on the ground; normals (N, 3); ok (N,) False where no acceptable spot
    lies within the search radius (the point is then the ideal spot, on the ground)."""

    points: NDArray[np.float64]
    normals: NDArray[np.float64]
    ok: NDArray[np.bool_]


def _candidates(radius: NDArray[np.float64]) -> NDArray[np.float64]:
    """Offsets (N, C, 2) of the candidate spots: the centre, then rings out to ``radius``."""
    rings = np.arange(1, RINGS + 1) / RINGS
    angles = 2.0 * np.pi * np.arange(RING_POINTS) / RING_POINTS
    unit = np.stack([np.sin(angles), np.cos(angles)], axis=-1)  # (P, 2)
    offsets = np.concatenate([np.zeros((1, 2)), (rings[:, None, None] * unit[None]).reshape(-1, 2)])
    return radius[:, None, None] * offsets[None]


def place_feet(terrain: Terrain, ideal: NDArray[np.float64], heading: NDArray[np.float64],
               front: NDArray[np.float64], back: NDArray[np.float64], side: NDArray[np.float64],
               search: NDArray[np.float64]) -> Footholds:
    """Acceptable footholds nearest to ideal ground spots.

    ideal (N, 2) x, z; heading (N, 2) unit direction the foot points; front, back, side
    (N,) the footprint's reach (m) ahead of the ball (toe), behind it (heel) and to each
    side; search (N,) the largest distance (m) to look from the ideal spot.
    """
    n = ideal.shape[0]
    if n == 0:
        return Footholds(np.zeros((0, 3)), np.zeros((0, 3)), np.zeros(0, dtype=bool))
    offsets = _candidates(search)  # (N, C, 2)
    spots = ideal[:, None, :] + offsets
    count = spots.shape[1]
    flat_spots = spots.reshape(-1, 2)
    height = terrain.height(flat_spots).reshape(n, count)
    normal = terrain.normal(flat_spots).reshape(n, count, 3)
    steep_ok = normal[..., 1] >= np.cos(terrain.max_slope) - 1e-12

    # Footprint probes: toe, heel, both sides, each at least EDGE_MARGIN from the ball.
    lateral = np.stack([heading[:, 1], -heading[:, 0]], axis=-1)
    reach = np.stack([np.maximum(front, EDGE_MARGIN), np.maximum(back, EDGE_MARGIN),
                      np.maximum(side, EDGE_MARGIN), np.maximum(side, EDGE_MARGIN)], axis=-1)  # (N, 4)
    direction = np.stack([heading, -heading, lateral, -lateral], axis=1)  # (N, 4, 2)
    probe_offsets = direction * reach[..., None]  # (N, 4, 2)
    probes = spots[:, :, None, :] + probe_offsets[:, None, :, :]  # (N, C, 4, 2)
    probe_h = terrain.height(probes.reshape(-1, 2)).reshape(n, count, 4)
    # Tangent plane at the spot: dh = -(nx dx + nz dz) / ny.
    slope = -normal[..., [0, 2]] / np.maximum(normal[..., 1:2], 1e-6)  # (N, C, 2)
    predicted = height[..., None] + np.einsum("ncd,nkd->nck", slope, probe_offsets)
    tolerance = PLANE_TOLERANCE + PLANE_SLACK * reach[:, None, :]
    plane_ok = np.all(np.abs(probe_h - predicted) <= tolerance, axis=-1)

    ok = steep_ok & plane_ok
    distance = np.linalg.norm(offsets, axis=-1) + np.where(ok, 0.0, np.inf)
    best = distance.argmin(axis=1)
    rows = np.arange(n)
    found = ok[rows, best]
    choice = np.where(found, best, 0)
    xz = spots[rows, choice]
    points = np.column_stack([xz[:, 0], height[rows, choice], xz[:, 1]])
    return Footholds(points=points, normals=normal[rows, choice], ok=found)
