"""Signed distances (m, negative inside) of a creature's parts and their smooth union.

Parts are the renderer's instances: tapered capsules (two end points, a radius at each)
and ellipsoids (a centre, three unit axes, three radii). The union is the soft minimum
``-k log(sum exp(-d_i / k))``: smooth where parts meet (a blend about ``k`` wide), equal
to the nearest part's distance away from the joins.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray


def capsule_distance(points: NDArray[np.float64], a: NDArray[np.float64], b: NDArray[np.float64],
                     r0: float, r1: float) -> NDArray[np.float64]:
    """Distance (N,) from points (N, 3) to a capsule from ``a`` to ``b`` (3,) whose radius
    goes from ``r0`` to ``r1`` (a round cone, measured across its axis: close enough for
    gentle tapers)."""
    axis = b - a
    length2 = float(axis @ axis)
    t = np.clip(((points - a) @ axis) / length2, 0.0, 1.0) if length2 > 1e-18 else np.zeros(len(points))
    nearest = a + t[:, None] * axis
    return np.linalg.norm(points - nearest, axis=1) - (r0 + (r1 - r0) * t)


def ellipsoid_distance(points: NDArray[np.float64], centre: NDArray[np.float64], axes: NDArray[np.float64],
                       radii: NDArray[np.float64]) -> NDArray[np.float64]:
    """Approximate distance (N,) from points (N, 3) to an ellipsoid: ``axes`` (3, 3) rows
    are its unit axes, ``radii`` (3,) its semi-axes (the k0 (k0 - 1) / k1 bound, exact on
    the surface and for spheres)."""
    local = (points - centre) @ axes.T  # (N, 3) along each axis
    r = np.maximum(radii, 1e-9)
    k0 = np.linalg.norm(local / r, axis=1)
    k1 = np.linalg.norm(local / (r * r), axis=1)
    return np.where(k1 > 1e-12, k0 * (k0 - 1.0) / np.maximum(k1, 1e-12), -float(r.min()))


def part_distances(points: NDArray[np.float64], capsules: NDArray[np.float64],
                   ellipsoids: NDArray[np.float64]) -> NDArray[np.float64]:
    """Each part's distance (P, N) at points (N, 3): capsules (C, >=8: a, b, r0, r1) first,
    then ellipsoids (E, >=15: centre, x, y, z axes, radii)."""
    rows = [capsule_distance(points, c[0:3], c[3:6], float(c[6]), float(c[7])) for c in capsules]
    rows += [ellipsoid_distance(points, e[0:3], np.stack([e[3:6], e[6:9], e[9:12]]), e[12:15]) for e in ellipsoids]
    return np.stack(rows) if rows else np.full((0, len(points)), np.inf)


def smooth_union(distances: NDArray[np.float64], blend: float) -> NDArray[np.float64]:
    """The soft minimum (N,) over parts (P, N) with blend width ``blend`` (m)."""
    nearest = distances.min(axis=0)
    return nearest - blend * np.log(np.sum(np.exp(-(distances - nearest) / blend), axis=0))


def limb_union(distances: NDArray[np.float64], blend: float, legs: NDArray[np.int64], arms: NDArray[np.int64],
               tail: NDArray[np.bool_], narrow: float) -> NDArray[np.float64]:
    """The union :func:`union_on_grid` samples, at any points: (N,) from the parts'
    distances (P, N) there, joined limb by limb as it describes."""
    def union(mask: NDArray[np.bool_], width: float) -> NDArray[np.float64]:
        return smooth_union(distances[mask], width) if mask.any() else np.full(distances.shape[1], np.inf)

    trunk = (legs == 0) & (arms == 0)
    joined = [union(trunk & ~tail, blend), union(trunk & tail, narrow)]
    if legs.any():
        joined.append(smooth_union(np.stack([union(legs == k, blend) for k in np.unique(legs[legs > 0])]), narrow))
    present = [j for j in joined if np.isfinite(j).any()]
    bodies = [smooth_union(np.stack(present), blend)] if present else []  # none: only arms
    if arms.any():
        bodies += [union(arms == k, blend) for k in np.unique(arms[arms > 0])]
    return smooth_union(np.stack(bodies), narrow)


def union_on_grid(axes: tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]],
                  capsules: NDArray[np.float64], ellipsoids: NDArray[np.float64], blend: float,
                  legs: NDArray[np.int64] | None = None, arms: NDArray[np.int64] | None = None,
                  narrow: float | None = None, tail: NDArray[np.bool_] | None = None) -> NDArray[np.float32]:
    """The smooth union sampled on the grid ``axes`` (x (X,), y (Y,), z (Z,) coordinates):
    (X, Y, Z) float32. Each part is evaluated only in its bounding box widened by four
    blend widths (beyond, its share of the soft minimum is under 2 % of ``blend``), and the
    soft minimum is accumulated part by part (a running minimum and rescaled sum), so
    memory stays one grid a group whatever the number of parts.

    ``legs`` and ``arms`` (P,): each part's leg or arm (1, 2, ...; 0: the trunk, head and
    tail). A limb's own parts blend by ``blend``; a leg joins the trunk by ``blend`` too (a
    hip's fillet) but other legs only by the ``narrow`` width, and an arm everything by
    ``narrow``: limbs close together in the bind pose (a person's thighs, a spider's
    neighbouring legs, an arm hanging by the trunk) stay apart instead of joined by a web
    that skinning then stretches. ``tail`` (P,): the tail's parts, which join each other
    by ``narrow`` (a thin tail's segments, overlapping at each joint, bulged there by
    the full blend into a string of beads) and the trunk by ``blend``."""
    count = len(capsules) + len(ellipsoids)
    legs = np.zeros(count, np.int64) if legs is None else legs
    arms = np.zeros(count, np.int64) if arms is None else arms
    tail = np.zeros(count, bool) if tail is None else tail
    if narrow is None or not (legs.any() or arms.any() or tail.any()):
        return _union_on_grid(axes, capsules, ellipsoids, blend)

    def parts(mask: NDArray[np.bool_]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        return capsules[mask[:len(capsules)]], ellipsoids[mask[len(capsules):]]

    body = _union_on_grid(axes, *parts((legs == 0) & (arms == 0) & ~tail), blend)
    if tail.any():
        tail_union = _union_on_grid(axes, *parts(tail & (legs == 0) & (arms == 0)), narrow, reach=4.0 * blend)
        body = smooth_union(np.stack([body, tail_union]), blend).astype(np.float32)
    if legs.any():
        limbs = _narrow_union(axes, [parts(legs == k) for k in np.unique(legs[legs > 0])], blend, narrow)
        body = smooth_union(np.stack([body, limbs]), blend).astype(np.float32)
    if arms.any():
        unions = [body] + [_union_on_grid(axes, *parts(arms == k), blend) for k in np.unique(arms[arms > 0])]
        body = smooth_union(np.stack(unions), narrow).astype(np.float32)
    return body


class _SoftMin:
    """A soft minimum by ``width`` over a grid of ``shape``, accumulated one term at a time
    over any box of it (a running minimum and a rescaled sum of exponentials: one grid's
    memory whatever the number of terms); where no term came, ``outside``."""

    def __init__(self, shape: tuple[int, ...], width: float, outside: float) -> None:
        self.nearest = np.full(shape, np.inf, dtype=np.float32)
        self.total = np.zeros(shape, dtype=np.float32)
        self.width, self.outside = width, outside

    def add(self, box: tuple[slice, ...], values: NDArray[np.float32]) -> None:
        m_old = self.nearest[box]
        m_new = np.minimum(m_old, values)
        scale = np.where(np.isfinite(m_old), np.exp(-(m_old - m_new) / self.width), 0.0)
        self.total[box] = self.total[box] * scale + np.exp(-(values - m_new) / self.width)
        self.nearest[box] = m_new

    def result(self) -> NDArray[np.float32]:
        union = np.full(self.nearest.shape, self.outside, dtype=np.float32)
        inside = np.isfinite(self.nearest)
        union[inside] = self.nearest[inside] - self.width * np.log(np.maximum(self.total[inside], 1e-30))
        return union


def _narrow_union(axes: tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]],
                  groups: list[tuple[NDArray[np.float64], NDArray[np.float64]]], blend: float,
                  narrow: float) -> NDArray[np.float32]:
    """The soft minimum by ``narrow`` of the groups' own unions (each its parts' by
    ``blend``, worked out over the groups' own boxes only: a centipede's thirty legs cost
    thirty small boxes, not thirty grids)."""
    union = _SoftMin(tuple(len(a) for a in axes), narrow, 4.0 * blend + 1.0)
    for capsules, ellipsoids in groups:
        lo = np.min([*capsules[:, 0:3] - capsules[:, 6:8].max(axis=1, keepdims=True),
                     *capsules[:, 3:6] - capsules[:, 6:8].max(axis=1, keepdims=True),
                     *ellipsoids[:, 0:3] - ellipsoids[:, 12:15].max(axis=1, keepdims=True)], axis=0) - 8.0 * blend
        hi = np.max([*capsules[:, 0:3] + capsules[:, 6:8].max(axis=1, keepdims=True),
                     *capsules[:, 3:6] + capsules[:, 6:8].max(axis=1, keepdims=True),
                     *ellipsoids[:, 0:3] + ellipsoids[:, 12:15].max(axis=1, keepdims=True)], axis=0) + 8.0 * blend
        box = tuple(slice(int(np.searchsorted(a, lo[k])), int(np.searchsorted(a, hi[k], side="right")))
                    for k, a in enumerate(axes))
        if any(b.stop <= b.start for b in box):
            continue
        union.add(box, _union_on_grid(tuple(a[b] for a, b in zip(axes, box)), capsules, ellipsoids,  # type: ignore[arg-type]
                                      blend))
    return union.result()


def _union_on_grid(axes: tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]],
                   capsules: NDArray[np.float64], ellipsoids: NDArray[np.float64], blend: float,
                   reach: float | None = None) -> NDArray[np.float32]:
    """The parts' soft minimum by ``blend``, each part evaluated within ``reach`` (m;
    default four blends) of its box: a group joined to others by a wider blend than its
    own needs their reach; beyond every part's, a value past every reach."""
    reach = 4.0 * blend if reach is None else reach
    xs, ys, zs = axes
    union = _SoftMin((len(xs), len(ys), len(zs)), blend, reach + 1.0)
    boxes = [(np.minimum(c[0:3], c[3:6]) - max(c[6], c[7]), np.maximum(c[0:3], c[3:6]) + max(c[6], c[7]))
             for c in capsules]
    boxes += [(e[0:3] - e[12:15].max(), e[0:3] + e[12:15].max()) for e in ellipsoids]
    parts = [("c", c) for c in capsules] + [("e", e) for e in ellipsoids]
    for (lo, hi), (kind, p) in zip(boxes, parts):
        lo, hi = lo - reach, hi + reach
        ix = slice(int(np.searchsorted(xs, lo[0])), int(np.searchsorted(xs, hi[0], side="right")))
        iy = slice(int(np.searchsorted(ys, lo[1])), int(np.searchsorted(ys, hi[1], side="right")))
        iz = slice(int(np.searchsorted(zs, lo[2])), int(np.searchsorted(zs, hi[2], side="right")))
        gx, gy, gz = np.meshgrid(xs[ix], ys[iy], zs[iz], indexing="ij")
        if gx.size == 0:
            continue
        points = np.stack([gx.ravel(), gy.ravel(), gz.ravel()], axis=1)
        if kind == "c":
            d = capsule_distance(points, p[0:3], p[3:6], float(p[6]), float(p[7]))
        else:
            d = ellipsoid_distance(points, p[0:3], np.stack([p[3:6], p[6:9], p[9:12]]), p[12:15])
        union.add((ix, iy, iz), d.reshape(gx.shape).astype(np.float32))
    return union.result()
