"""Where a foot may stand: the acceptable ground nearest to an ideal spot.

Like the terrain seed's grid search, but vectorised over every foothold at once: around
each ideal (x, z) a disc of candidate spots (rings of points) is tested, and the nearest
acceptable one wins. A spot is acceptable when

- the ground there is no steeper than the terrain's ``max_slope``, and
- the foot's footprint lies on one plane: probes on a ring around the spot as wide as the
  foot's reach (its toe or heel, whichever is longer, at least ``EDGE_MARGIN``), in
  every direction — the body may turn the foot while it stands — or, for a rigid sole
  that keeps its heading through the stance, along that sole (toe ahead, heel behind,
  its half-width across) — all sit within a small
  tolerance of the tangent plane at the spot, plus the bend of ground as curved as
  :data:`WALKABLE_CURVATURE` (a hilltop or a hollow takes a foot; a riser does not). This
  keeps a foot off a riser and away from a step's edge, on any terrain (an exact staircase
  or a heightmap alike).

When no acceptable spot lies within the search radius, the foot takes the least-bad
spot there that is no steeper than ``max_slope`` — a *compromised* foothold (its footprint does not lie on one
plane: a ridge, a lip), counted and reported, not an error. Only ground steeper than
``max_slope`` everywhere in reach is refused.

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
PLANE_TOLERANCE = 0.004  # m, plus PLANE_SLACK of the probe distance, plus the bend of curved ground
PLANE_SLACK = 0.04
WALKABLE_CURVATURE = 2.0  # 1/m: ground curving as tightly as a 0.5 m radius still takes a foot
PROBES = 8


@dataclass(frozen=True)
class Footholds:
    """points (N, 3) on the ground; normals (N, 3); ok (N,) False where all the ground in
    reach is steeper than ``max_slope`` (the point is then the ideal spot, on the ground);
    compromised (N,) True where the foot stands on the least-bad spot, uneven under it."""

    points: NDArray[np.float64]
    normals: NDArray[np.float64]
    ok: NDArray[np.bool_]
    compromised: NDArray[np.bool_]


def _candidates(radius: NDArray[np.float64]) -> NDArray[np.float64]:
    """Offsets (N, C, 2) of the candidate spots: the centre, then rings out to ``radius``."""
    rings = np.arange(1, RINGS + 1) / RINGS
    angles = 2.0 * np.pi * np.arange(RING_POINTS) / RING_POINTS
    unit = np.stack([np.sin(angles), np.cos(angles)], axis=-1)  # (P, 2)
    offsets = np.concatenate([np.zeros((1, 2)), (rings[:, None, None] * unit[None]).reshape(-1, 2)])
    return radius[:, None, None] * offsets[None]


def place_feet(terrain: Terrain, ideal: NDArray[np.float64], front: NDArray[np.float64],
               back: NDArray[np.float64], side: NDArray[np.float64], search: NDArray[np.float64],
               max_slope: NDArray[np.float64] | None = None,
               heading: NDArray[np.float64] | None = None) -> Footholds:
    """Acceptable footholds nearest to ideal ground spots.

    ideal (N, 2) x, z; front, back, side (N,) the footprint's reach (m) ahead of the ball
    (toe), behind it (heel) and to each side; search (N,) the largest distance (m) to look
    from the ideal spot; max_slope (N,) rad the steepest ground each foot stands on
    (default: the terrain's ``max_slope``); heading (N, 2) the (x, z) unit direction of
    a foot that keeps it through its stance (a rigid sole: its footprint reaches ``front``
    ahead and ``back`` behind along it, ``side`` across), NaN (or None for all) for a foot
    the body may turn while it stands (its footprint is a disc of its longest reach).
    """
    n = ideal.shape[0]
    if n == 0:
        return Footholds(np.zeros((0, 3)), np.zeros((0, 3)), np.zeros(0, dtype=bool), np.zeros(0, dtype=bool))
    if terrain.flat:  # every spot of the plane is level and even: the ideal ones, as they are
        points = np.stack([ideal[:, 0], np.zeros(n), ideal[:, 1]], axis=-1)
        normals = np.broadcast_to(np.array([0.0, 1.0, 0.0]), (n, 3)).copy()
        return Footholds(points, normals, np.ones(n, dtype=bool), np.zeros(n, dtype=bool))
    steepest = np.full(n, terrain.max_slope) if max_slope is None else np.asarray(max_slope, dtype=np.float64)
    probe_offsets = footprint_probes(front, back, side, heading)
    # Most ideal spots are fine as they are: test them first, search only around the rest.
    points, normals, ok, _, _ = _judge(terrain, ideal[:, None, :], probe_offsets, steepest)
    held = Footholds(points=points[:, 0], normals=normals[:, 0], ok=ok[:, 0], compromised=np.zeros(n, dtype=bool))
    redo = np.nonzero(~held.ok)[0]
    if redo.size:
        offsets = _candidates(search[redo])  # (M, C, 2)
        points, normals, ok, steep_ok, unevenness = _judge(terrain, ideal[redo, None, :] + offsets,
                                                           probe_offsets[redo], steepest[redo])
        distance = np.linalg.norm(offsets, axis=-1) + np.where(ok, 0.0, np.inf)
        best = distance.argmin(axis=1)
        rows = np.arange(redo.size)
        found = ok[rows, best]
        # None acceptable: the least-bad spot no steeper than max_slope, nearest among equals.
        score = unevenness + 1e-3 * np.linalg.norm(offsets, axis=-1) + np.where(steep_ok, 0.0, np.inf)
        least_bad = score.argmin(axis=1)
        usable = found | steep_ok[rows, least_bad]
        choice = np.where(found, best, np.where(usable, least_bad, 0))
        held.points[redo] = points[rows, choice]
        held.normals[redo] = normals[rows, choice]
        held.ok[redo] = usable
        held.compromised[redo] = usable & ~found
    return held


def footprint_probes(front: NDArray[np.float64], back: NDArray[np.float64], side: NDArray[np.float64],
                     heading: NDArray[np.float64] | None = None) -> NDArray[np.float64]:
    """Where each footprint is probed, (N, 2P, 2) (x, z) offsets from its ball: a ring at its
    reach and another at half of it, every reach at least :data:`EDGE_MARGIN`. A foot
    with a ``heading`` (N, 2) (not NaN) reaches ``front`` ahead, ``back`` behind and
    ``side`` across it; any other is a disc of its longest reach, in every direction.
    front, back, side (N,) m."""
    n = front.shape[0]
    angles = 2.0 * np.pi * np.arange(PROBES) / PROBES
    ring = np.stack([np.sin(angles), np.cos(angles)], axis=-1)  # (P, 2): (across, along)
    reach = np.maximum.reduce([front, back, side, np.full(n, EDGE_MARGIN)])  # (N,)
    disc = ring[None] * reach[:, None, None]  # (N, P, 2)
    if heading is not None:
        along = np.where(ring[None, :, 1] > 0, np.maximum(front, EDGE_MARGIN)[:, None],
                         np.maximum(back, EDGE_MARGIN)[:, None]) * ring[None, :, 1]  # (N, P)
        across = np.maximum(side, EDGE_MARGIN)[:, None] * ring[None, :, 0]
        h = np.nan_to_num(heading)
        left = np.stack([h[:, 1], -h[:, 0]], axis=-1)  # (x, z) turned a quarter about +Y
        oriented = along[..., None] * h[:, None, :] + across[..., None] * left[:, None, :]
        rigid: NDArray[np.bool_] = np.all(np.isfinite(heading), axis=-1)
        disc = np.where(rigid[:, None, None], oriented, disc)
    return np.concatenate([disc, 0.5 * disc], axis=1)


def _judge(terrain: Terrain, spots: NDArray[np.float64], probe_offsets: NDArray[np.float64],
           max_slope: NDArray[np.float64]):
    """Ground points (N, C, 3), normals (N, C, 3), acceptability (N, C), whether the
    ground is no steeper than ``max_slope`` (N,) rad (N, C) and how uneven the footprint
    is (N, C: the largest excess over the plane tolerance, as a fraction of it) of
    candidate spots (N, C, 2) for feet probed at ``probe_offsets`` (N, K, 2) m around
    their ball (:func:`footprint_probes`)."""
    n, count = spots.shape[:2]
    flat_spots = spots.reshape(-1, 2)
    height = terrain.height(flat_spots).reshape(n, count)
    normal = terrain.normal(flat_spots).reshape(n, count, 3)
    steep_ok = normal[..., 1] >= np.cos(max_slope)[:, None] - 1e-12
    probe_count = probe_offsets.shape[1]
    probes = spots[:, :, None, :] + probe_offsets[:, None, :, :]  # (N, C, 2P, 2)
    probe_h = terrain.height(probes.reshape(-1, 2)).reshape(n, count, probe_count)
    # Tangent plane at the spot: dh = -(nx dx + nz dz) / ny.
    slope = -normal[..., [0, 2]] / np.maximum(normal[..., 1:2], 1e-6)  # (N, C, 2)
    predicted = height[..., None] + np.einsum("ncd,nkd->nck", slope, probe_offsets)
    r = np.linalg.norm(probe_offsets, axis=-1)[:, None, :]
    tolerance = PLANE_TOLERANCE + PLANE_SLACK * r + 0.5 * WALKABLE_CURVATURE * r * r
    excess = (np.abs(probe_h - predicted) - tolerance) / tolerance
    plane_ok = np.all(excess <= 0.0, axis=-1)
    points = np.stack([spots[..., 0], height, spots[..., 1]], axis=-1)
    return points, normal, steep_ok & plane_ok, steep_ok, np.maximum(excess.max(axis=-1), 0.0)
