"""The features a skinned body carries on its surface rather than in it: the eyes, a
mammal's nose and a mane, as a second mesh skinned to the same joints (drawn and
exported with the body, so they stay on the skin however it bends)."""

from __future__ import annotations

from functools import lru_cache

import numpy as np
from numpy.typing import NDArray

FeatureMesh = tuple[NDArray[np.float32], NDArray[np.float32], NDArray[np.float32], NDArray[np.int32],
                    NDArray[np.int32], NDArray[np.float32]]  # positions, normals, colours, faces, joints, weights
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


@lru_cache(maxsize=1)
def _unit_sphere() -> tuple[NDArray[np.float64], NDArray[np.int64]]:
    """A unit icosphere's vertices (V, 3) and triangles (F, 3), wound outwards."""
    import trimesh

    sphere = trimesh.creation.icosphere(subdivisions=FEATURE_DETAIL)
    return np.asarray(sphere.vertices, np.float64), np.asarray(sphere.faces, np.int64)
