"""The features a skinned body carries on its surface rather than in it: the eyes, a
mammal's nose and a mane, as a second mesh skinned to the same joints (drawn and
exported with the body, so they stay on the skin however it bends)."""

from __future__ import annotations

from functools import lru_cache

import numpy as np
from numpy.typing import NDArray

FeatureMesh = tuple[NDArray[np.float32], NDArray[np.float32], NDArray[np.float32], NDArray[np.int32],
                    NDArray[np.int32], NDArray[np.float32]]  # positions, normals, colours, faces, joints, weights
SEAT_SINK = 0.5  # of a seated feature's reach along its way out: how much of it lies under the skin
FEATURE_DETAIL = 1  # icosphere subdivisions of each feature's ellipsoid (42 vertices, 80 triangles: 14 mane tufts)


def feature_mesh(rows: NDArray[np.float64], positions: NDArray[np.float64], joints: NDArray[np.integer],
                 weights: NDArray[np.floating]) -> FeatureMesh | None:
    """Each feature's ellipsoid (``rows`` (K, 18): centre, x, y and z axes, radii along
    them, linear colour; :class:`app.render.scene.Ell`) as an icosphere in the body's bind
    pose, bound with the joints and weights of the body's vertex nearest its centre (the
    body's ``positions`` (V, 3), ``joints`` and ``weights`` (V, 4)): the features'
    positions, normals, colours (N, 3), faces (F, 3), joints and weights (N, 4); None
    without any."""
    from scipy.spatial import cKDTree

    if not len(rows):
        return None
    unit, faces = _unit_sphere()
    axes = np.stack([rows[:, 3:6], rows[:, 6:9], rows[:, 9:12]], axis=1)  # (K, 3, 3): rows x, y, z
    radii = rows[:, 12:15]
    points = rows[:, None, 0:3] + np.einsum("vi,ki,kij->kvj", unit, radii, axes)
    normals = np.einsum("vi,ki,kij->kvj", unit, 1.0 / radii, axes)
    normals /= np.linalg.norm(normals, axis=-1, keepdims=True)
    count = len(unit)
    mirrored = np.linalg.det(axes) < 0  # a left-handed frame turns the sphere inside out: wind it back
    wound = np.where(mirrored[:, None, None], faces[None, :, ::-1], faces[None])
    _, nearest = cKDTree(np.asarray(positions, np.float64)).query(rows[:, 0:3])
    return (points.reshape(-1, 3).astype(np.float32), normals.reshape(-1, 3).astype(np.float32),
            np.repeat(rows[:, 15:18], count, axis=0).astype(np.float32),
            (wound + count * np.arange(len(rows))[:, None, None]).reshape(-1, 3).astype(np.int32),
            np.repeat(np.asarray(joints)[nearest], count, axis=0).astype(np.int32),
            np.repeat(np.asarray(weights)[nearest], count, axis=0).astype(np.float32))


def seat_on_skin(rows: NDArray[np.float64], anchors: NDArray[np.float64], positions: NDArray[np.float64],
                 faces: NDArray[np.integer], sink: float = SEAT_SINK) -> NDArray[np.float64]:
    """The feature ellipsoids ``rows`` (K, 18) with those that have an anchor (``anchors``
    (K, 3), NaN: none) moved out along the line from the anchor through their centre until
    ``sink`` of their reach along it lies under the skin (the mesh ``positions`` (V, 3),
    ``faces`` (F, 3)): an eye set half into the skin, wherever the skin's blend put the
    surface. Never moved in (a bird's eyes bulge from its head); a row whose line leaves
    no skin stays."""
    rows = np.array(rows, dtype=np.float64)
    seated = np.flatnonzero(np.all(np.isfinite(anchors), axis=1))
    if not len(seated) or not len(faces):
        return rows
    origin = anchors[seated]
    offset = rows[seated, 0:3] - origin
    along = np.linalg.norm(offset, axis=1)
    direction = offset / np.maximum(along, 1e-12)[:, None]
    hit = _first_hit(origin, direction, np.asarray(positions, np.float64)[np.asarray(faces)])
    axes = np.stack([rows[seated, 3:6], rows[seated, 6:9], rows[seated, 9:12]], axis=1)  # (K, 3, 3)
    reach = np.linalg.norm(rows[seated, 12:15] * np.einsum("kij,kj->ki", axes, direction), axis=1)
    wanted = np.where(np.isfinite(hit), np.maximum(along, hit - sink * reach), along)
    rows[seated, 0:3] = origin + direction * wanted[:, None]
    return rows


def _first_hit(origin: NDArray[np.float64], direction: NDArray[np.float64],
               triangles: NDArray[np.float64]) -> NDArray[np.float64]:
    """How far (K,) each ray (``origin``, unit ``direction`` (K, 3)) goes before it meets
    a triangle (``triangles`` (F, 3, 3)), either side; inf where it meets none
    (Moller-Trumbore, every ray against every triangle)."""
    a, b, c = triangles[:, 0], triangles[:, 1], triangles[:, 2]
    e1, e2 = b - a, c - a  # (F, 3)
    p = np.cross(direction[:, None, :], e2[None])  # (K, F, 3)
    det = np.einsum("kfi,fi->kf", p, e1)
    ok = np.abs(det) > 1e-15
    inv = 1.0 / np.where(ok, det, 1.0)
    s = origin[:, None, :] - a[None]
    u = np.einsum("kfi,kfi->kf", s, p) * inv
    q = np.cross(s, e1[None])
    v = np.einsum("ki,kfi->kf", direction, q) * inv
    t = np.einsum("kfi,fi->kf", q, e2) * inv
    meets = ok & (u >= 0.0) & (v >= 0.0) & (u + v <= 1.0) & (t > 0.0)
    return np.where(meets, t, np.inf).min(axis=1)


@lru_cache(maxsize=1)
def _unit_sphere() -> tuple[NDArray[np.float64], NDArray[np.int64]]:
    """A unit icosphere's vertices (V, 3) and triangles (F, 3), wound outwards."""
    import trimesh

    sphere = trimesh.creation.icosphere(subdivisions=FEATURE_DETAIL)
    return np.asarray(sphere.vertices, np.float64), np.asarray(sphere.faces, np.int64)
