"""The creature's mesh for export: the very body the viewer and renders draw (the shared
body cache's, :mod:`app.render.bodies`) in its own bind pose, each vertex bound to the
same four joints with the same weights; the files' inverse bind matrices are the body's.
Its features, the eyes, a mammal's nose and a mane (drawn on the skin rather than in it),
go with it as a second mesh on the same skeleton."""

from __future__ import annotations

from dataclasses import replace
from functools import lru_cache

import numpy as np
from numpy.typing import NDArray

from ..kinematics.motion import Motion
from ..kinematics.skeleton import SkeletonClip, SkeletonLayout, skeleton_clip
from ..render.bodies import bind_motion, shared_body_cache
from ..skin import SkinnedBody
from ..skin.body import joint_matrices

FEATURE_DETAIL = 1  # icosphere subdivisions of each feature's ellipsoid (42 vertices, 80 triangles: 14 mane tufts)


def export_layout(motion: Motion) -> SkeletonLayout | None:
    """How to lay out an exported clip so its joints turn as the body's do (the body's own
    skeleton layout): pass it to :func:`skeleton_clip`."""
    return shared_body_cache().get(motion.rig).layout


def creature_mesh(motion: Motion, clip: SkeletonClip) -> SkinnedBody:
    """The skinned body of ``motion``'s creature for ``clip``: the cached body itself (its
    bind pose, vertices, weights and ``bind`` matrices as the viewer skins them) when the
    clip is laid out as the body is (:func:`export_layout`), so a file skins exactly as
    the viewer draws; for a clip laid out otherwise, the body posed into the clip's first
    frame and bound there (the same surface at that frame; in between, joints that roll
    otherwise twist it a little)."""
    body = shared_body_cache().get(motion.rig)
    return _for_clip(body, body, motion, clip)


def creature_features(motion: Motion, clip: SkeletonClip) -> SkinnedBody | None:
    """The creature's eyes, nose and mane as one skinned mesh on the body's skeleton, bound
    as :func:`creature_mesh` is; each feature moves with the joints of the body's vertex
    nearest its centre (an eye with the head, a mane's tuft with the neck's skin under
    it). None for a creature without any (a user's model has its own)."""
    body = shared_body_cache().get(motion.rig)
    features = _features(motion.rig, body)
    return None if features is None else _for_clip(features, body, motion, clip)


def _for_clip(mesh: SkinnedBody, body: SkinnedBody, motion: Motion, clip: SkeletonClip) -> SkinnedBody:
    """``mesh`` (bound as ``body``, in its bind pose) for ``clip``: itself when the clip is
    laid out as the body is, else posed into the clip's first frame and bound there."""
    if clip.layout == body.layout:
        return mesh
    posing = skeleton_clip(motion, body.layout)
    skin = body.skin_matrices(posing, 0)  # (J, 4, 4)
    blended = np.einsum("vk,vkij->vij", mesh.weights.astype(np.float64), skin[mesh.joints])  # (V, 4, 4)
    positions = np.einsum("vij,vj->vi", blended[:, :3, :3], mesh.positions.astype(np.float64)) + blended[:, :3, 3]
    normals = np.einsum("vij,vj->vi", blended[:, :3, :3], mesh.normals.astype(np.float64))
    normals /= np.maximum(np.linalg.norm(normals, axis=-1, keepdims=True), 1e-12)
    return replace(mesh, positions=positions.astype(np.float32), normals=normals.astype(np.float32),
                   bind=joint_matrices(clip, 0), shadow=None, far=None)


def _features(rig, body: SkinnedBody) -> SkinnedBody | None:
    """The features' mesh in the body's bind pose (None without any)."""
    from scipy.spatial import cKDTree

    from ..render.scene import Ell, motion_instances

    rows = np.asarray(motion_instances(bind_motion(rig), show_joints=False, parts=False).frame(0).ellipsoids,
                      np.float64)  # (K, 18): what a skinned body is drawn with
    if not len(rows):
        return None
    unit, faces = _unit_sphere()
    axes = np.stack([rows[:, a] for a in Ell.AXES], axis=1)  # (K, 3, 3): rows x, y, z
    radii = rows[:, Ell.RADII]
    positions = rows[:, None, Ell.CENTRE] + np.einsum("vi,ki,kij->kvj", unit, radii, axes)
    normals = np.einsum("vi,ki,kij->kvj", unit, 1.0 / radii, axes)
    normals /= np.linalg.norm(normals, axis=-1, keepdims=True)
    count = len(unit)
    _, nearest = cKDTree(body.positions.astype(np.float64)).query(rows[:, Ell.CENTRE])
    return replace(body, positions=positions.reshape(-1, 3).astype(np.float32),
                   normals=normals.reshape(-1, 3).astype(np.float32),
                   colors=np.repeat(rows[:, Ell.COLOR], count, axis=0).astype(np.float32),
                   faces=(faces[None] + count * np.arange(len(rows))[:, None, None]).reshape(-1, 3).astype(np.int32),
                   joints=np.repeat(body.joints[nearest], count, axis=0),
                   weights=np.repeat(body.weights[nearest], count, axis=0), shadow=None, far=None)


@lru_cache(maxsize=1)
def _unit_sphere() -> tuple[NDArray[np.float64], NDArray[np.int64]]:
    """A unit icosphere's vertices (V, 3) and triangles (F, 3), wound outwards."""
    import trimesh

    sphere = trimesh.creation.icosphere(subdivisions=FEATURE_DETAIL)
    return np.asarray(sphere.vertices, np.float64), np.asarray(sphere.faces, np.int64)
