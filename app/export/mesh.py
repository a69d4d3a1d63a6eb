"""The creature's mesh for export: the capsules and ellipsoids the renderer draws, posed
as in a clip's first frame, each vertex bound to the one joint its part moves with."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from ..kinematics.motion import Motion
from ..kinematics.skeleton import SkeletonClip
from ..render.meshes import unit_capsule, unit_sphere
from ..render.scene import motion_instances

CAPSULE_MESH = (8, 14)
SPHERE_MESH = (8, 12)


@dataclass(frozen=True)
class CreatureMesh:
    """Vertices (V,) in the bind pose (the clip's first frame), world space, metres;
    colours linear RGB; faces (F, 3); joint (V,) the joint each vertex follows."""

    positions: NDArray[np.float64]
    normals: NDArray[np.float64]
    colors: NDArray[np.float64]
    faces: NDArray[np.int64]
    joint: NDArray[np.int64]


def _capsule_vertices(caps: NDArray[np.float64]) -> tuple[NDArray, NDArray, NDArray, NDArray, NDArray]:
    """World vertices, normals, colours, faces and instance index of capsules (N, 11)."""
    unit, faces = unit_capsule(*CAPSULE_MESH)
    d, end = unit[:, :3].astype(np.float64), unit[:, 3].astype(np.float64)
    a, b, radius, color = caps[:, 0:3], caps[:, 3:6], caps[:, 6:8], caps[:, 8:11]
    axis = b - a
    length = np.linalg.norm(axis, axis=1, keepdims=True)
    y = np.where(length > 1e-9, axis / np.maximum(length, 1e-12), [0.0, 1.0, 0.0])
    helper = np.where(np.abs(y[:, 1:2]) < 0.99, [0.0, 1.0, 0.0], [1.0, 0.0, 0.0])
    x = np.cross(helper, y)
    x /= np.linalg.norm(x, axis=1, keepdims=True)
    z = np.cross(x, y)
    direction = (x[:, None] * d[None, :, 0:1] + y[:, None] * d[None, :, 1:2] + z[:, None] * d[None, :, 2:3])
    r = radius[:, 0:1] + (radius[:, 1:2] - radius[:, 0:1]) * end[None, :]
    centre = a[:, None] + axis[:, None] * end[None, :, None]
    position = centre + direction * r[..., None]
    slope = np.where(length > 1e-9, (radius[:, 0:1] - radius[:, 1:2]) / np.maximum(length, 1e-12), 0.0)
    normal = direction + y[:, None] * (slope[:, :, None] * (1.0 - np.abs(d[None, :, 1:2])))
    normal /= np.linalg.norm(normal, axis=-1, keepdims=True)
    n, v = len(caps), len(unit)
    colors = np.repeat(color[:, None], v, axis=1)
    all_faces = (faces.reshape(-1, 3)[None] + (np.arange(n) * v)[:, None, None]).reshape(-1, 3)
    owner = np.repeat(np.arange(n), v)
    return position.reshape(-1, 3), normal.reshape(-1, 3), colors.reshape(-1, 3), all_faces, owner


def _ellipsoid_vertices(ells: NDArray[np.float64]) -> tuple[NDArray, NDArray, NDArray, NDArray, NDArray]:
    """The same for ellipsoids (M, 18): centre, three axes, radii, colour."""
    unit, faces = unit_sphere(*SPHERE_MESH)
    p = unit.astype(np.float64)
    centre, ax, ay, az, radii, color = (ells[:, 3 * k:3 * k + 3] for k in range(6))
    scaled = p[None] * radii[:, None]
    position = centre[:, None] + ax[:, None] * scaled[..., 0:1] + ay[:, None] * scaled[..., 1:2] \
        + az[:, None] * scaled[..., 2:3]
    inv = p[None] / np.maximum(radii[:, None], 1e-12)
    normal = ax[:, None] * inv[..., 0:1] + ay[:, None] * inv[..., 1:2] + az[:, None] * inv[..., 2:3]
    normal /= np.linalg.norm(normal, axis=-1, keepdims=True)
    m, v = len(ells), len(unit)
    colors = np.repeat(color[:, None], v, axis=1)
    all_faces = (faces.reshape(-1, 3)[None] + (np.arange(m) * v)[:, None, None]).reshape(-1, 3)
    owner = np.repeat(np.arange(m), v)
    return position.reshape(-1, 3), normal.reshape(-1, 3), colors.reshape(-1, 3), all_faces, owner


def _bind_joints(points: NDArray[np.float64], ends: NDArray[np.float64] | None, clip: SkeletonClip) -> NDArray:
    """For each part (its start point (N, 3) and, for capsules, end point): the joint it
    moves with. A capsule belongs to the joint at its start whose bone runs towards its
    end; an ellipsoid to the nearest joint."""
    joints = clip.world_position[0]  # (J, 3)
    near = np.linalg.norm(points[:, None] - joints[None], axis=-1)  # (N, J)
    if ends is None:
        return np.argmin(near, axis=1)
    y = clip.world_rotation[0, :, :, 1]  # each joint's bone direction
    along = np.einsum("njk,jk->nj", (ends - points)[:, None, :] / np.maximum(
        np.linalg.norm(ends - points, axis=1)[:, None, None], 1e-12), y)
    return np.argmin(near - 0.01 * along, axis=1)  # nearest start; ties go to the bone pointing the right way


def creature_mesh(motion: Motion, clip: SkeletonClip) -> CreatureMesh:
    """The first frame's capsules and ellipsoids as one mesh bound to ``clip``'s joints."""
    instances = motion_instances(motion, show_joints=False).frame(0)
    caps, ells = np.asarray(instances.capsules, np.float64), np.asarray(instances.ellipsoids, np.float64)
    parts = []
    if len(caps):
        pos, nor, col, faces, owner = _capsule_vertices(caps)
        parts.append((pos, nor, col, faces, _bind_joints(caps[:, 0:3], caps[:, 3:6], clip)[owner]))
    if len(ells):
        pos, nor, col, faces, owner = _ellipsoid_vertices(ells)
        parts.append((pos, nor, col, faces, _bind_joints(ells[:, 0:3], None, clip)[owner]))
    offset, faces_all = 0, []
    for p in parts:
        faces_all.append(p[3] + offset)
        offset += len(p[0])
    return CreatureMesh(positions=np.concatenate([p[0] for p in parts]), normals=np.concatenate([p[1] for p in parts]),
                        colors=np.concatenate([p[2] for p in parts]), faces=np.concatenate(faces_all).astype(np.int64),
                        joint=np.concatenate([p[4] for p in parts]).astype(np.int64))
