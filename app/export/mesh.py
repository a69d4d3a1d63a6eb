"""The creature's mesh for export: the very body the viewer and renders draw (the shared
body cache's, :mod:`app.render.bodies`) in its own bind pose, each vertex bound to the
same four joints with the same weights; the files' inverse bind matrices are the body's.
Its features, the eyes, a mammal's nose and a mane (drawn on the skin rather than in it),
go with it as a second mesh on the same skeleton."""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from ..kinematics.motion import Motion
from ..kinematics.skeleton import SkeletonClip, SkeletonLayout, skeleton_clip
from ..render.bodies import shared_body_cache
from ..skin import SkinnedBody
from ..skin.body import joint_matrices


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
    """The creature's eyes, nose and mane as one skinned mesh on the body's skeleton (the
    body's :attr:`~app.skin.SkinnedBody.features`, drawn with it in the viewer), bound as
    :func:`creature_mesh` is. None for a creature without any (a user's model has its
    own)."""
    body = shared_body_cache().get(motion.rig)
    return None if body.features is None else _for_clip(body.features, body, motion, clip)


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
