"""glTF 2.0 export (.glb): the skeleton as a skin, the creature's mesh skinned to it, one
animation with root motion.

The mesh is what the renderer draws — capsules for the bones and trunk, ellipsoids for
the head, eyes and ears — posed as in the first frame and bound rigidly to the bone it
belongs to (each vertex weighs 1 on one joint), with vertex colours. Joints are nodes
with their first frame's local transform; the animation moves every joint's rotation and
the translation of the joints whose offset changes (the root carries the travel).
Written with pygltflib; checked by the Khronos validator in the tests.
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pygltflib as gl
from numpy.typing import NDArray
from scipy.spatial.transform import Rotation

from ..kinematics.motion import Motion
from ..kinematics.skeleton import SkeletonClip
from ..output import AtomicPath
from ..render.meshes import unit_capsule, unit_sphere
from ..render.scene import motion_instances

CAPSULE_MESH = (8, 14)
SPHERE_MESH = (8, 12)


def _quaternions(rotation: NDArray[np.float64]) -> NDArray[np.float64]:
    """(T, 3, 3) -> (T, 4) xyzw, signs kept continuous over time (no 360-degree spins)."""
    q = Rotation.from_matrix(rotation).as_quat()
    flip = np.einsum("ti,ti->t", q[1:], q[:-1]) < 0
    sign = np.concatenate([[1.0], np.where(np.cumsum(flip) % 2 == 1, -1.0, 1.0)])
    return q * sign[:, None]


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


class _Blob:
    """The binary buffer, its views and accessors."""

    def __init__(self, doc: gl.GLTF2) -> None:
        self.doc = doc
        self.data = bytearray()

    def add(self, array: NDArray, kind: str, component: int, target: int | None = None,
            bounds: bool = False) -> int:
        array = np.ascontiguousarray(array)
        while len(self.data) % 4:
            self.data.append(0)
        view = gl.BufferView(buffer=0, byteOffset=len(self.data), byteLength=array.nbytes, target=target)
        self.data.extend(array.tobytes())
        self.doc.bufferViews.append(view)
        count = array.shape[0]
        accessor = gl.Accessor(bufferView=len(self.doc.bufferViews) - 1, componentType=component, count=count,
                               type=kind)
        if bounds:
            flat = array.reshape(count, -1)
            accessor.min = [float(v) for v in flat.min(axis=0)]
            accessor.max = [float(v) for v in flat.max(axis=0)]
        self.doc.accessors.append(accessor)
        return len(self.doc.accessors) - 1


GROUND_MARGIN = 1.0  # m of ground around what the creature covers
GROUND_MAX_CELLS = 300  # per side: the ground mesh's resolution is capped


def _ground(motion: Motion, blob: "_Blob", doc: gl.GLTF2) -> int:
    """A mesh of the ground under the clip (the terrain over the area the creature covers);
    the index of its node."""
    points = np.concatenate([motion.joints.reshape(-1, 3), motion.spine.reshape(-1, 3)])
    lo = points[:, [0, 2]].min(axis=0) - GROUND_MARGIN
    hi = points[:, [0, 2]].max(axis=0) + GROUND_MARGIN
    cell = max(0.05, float((hi - lo).max()) / GROUND_MAX_CELLS)
    position, normal, indices = motion.terrain.surface((float(lo[0]), float(lo[1])), (float(hi[0]), float(hi[1])), cell)
    attributes = gl.Attributes(POSITION=blob.add(position.astype(np.float32), gl.VEC3, gl.FLOAT, gl.ARRAY_BUFFER,
                                                 bounds=True),
                               NORMAL=blob.add(normal.astype(np.float32), gl.VEC3, gl.FLOAT, gl.ARRAY_BUFFER))
    doc.materials.append(gl.Material(name="ground", pbrMetallicRoughness=gl.PbrMetallicRoughness(
        baseColorFactor=[0.77, 0.72, 0.64, 1.0], metallicFactor=0.0, roughnessFactor=0.9)))
    doc.meshes.append(gl.Mesh(name="ground", primitives=[gl.Primitive(
        attributes=attributes, material=len(doc.materials) - 1,
        indices=blob.add(indices.astype(np.uint32), gl.SCALAR, gl.UNSIGNED_INT, gl.ELEMENT_ARRAY_BUFFER))]))
    doc.nodes.append(gl.Node(name="ground", mesh=len(doc.meshes) - 1))
    return len(doc.nodes) - 1


def gltf_document(motion: Motion, clip: SkeletonClip, ground: bool = False) -> gl.GLTF2:
    """The clip as a glTF document with its binary blob attached; ``ground`` adds the
    terrain under the clip as a second mesh (not for in-place clips, whose ground moves)."""
    skeleton = clip.skeleton
    J, T = skeleton.count, clip.frame_count
    doc = gl.GLTF2(asset=gl.Asset(generator="Gaitlab", version="2.0"))
    blob = _Blob(doc)

    # The mesh, as drawn in the first frame, bound rigidly to the joints.
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
    position = np.concatenate([p[0] for p in parts]).astype(np.float32)
    normal = np.concatenate([p[1] for p in parts]).astype(np.float32)
    color = np.concatenate([p[2] for p in parts]).astype(np.float32)
    bone = np.concatenate([p[4] for p in parts])
    joints0 = np.zeros((len(bone), 4), np.uint16)
    joints0[:, 0] = bone
    weights0 = np.zeros((len(bone), 4), np.float32)
    weights0[:, 0] = 1.0
    indices = np.concatenate(faces_all).astype(np.uint32).reshape(-1)
    attributes = gl.Attributes(
        POSITION=blob.add(position, gl.VEC3, gl.FLOAT, gl.ARRAY_BUFFER, bounds=True),
        NORMAL=blob.add(normal, gl.VEC3, gl.FLOAT, gl.ARRAY_BUFFER),
        COLOR_0=blob.add(color, gl.VEC3, gl.FLOAT, gl.ARRAY_BUFFER),
        JOINTS_0=blob.add(joints0, gl.VEC4, gl.UNSIGNED_SHORT, gl.ARRAY_BUFFER),
        WEIGHTS_0=blob.add(weights0, gl.VEC4, gl.FLOAT, gl.ARRAY_BUFFER))
    material = gl.Material(name="creature", pbrMetallicRoughness=gl.PbrMetallicRoughness(
        baseColorFactor=[1.0, 1.0, 1.0, 1.0], metallicFactor=0.0, roughnessFactor=0.7))
    doc.materials.append(material)
    doc.meshes.append(gl.Mesh(name=f"{motion.rig.name if hasattr(motion.rig, 'name') else 'creature'}",
                              primitives=[gl.Primitive(attributes=attributes, material=0, indices=blob.add(
                                  indices, gl.SCALAR, gl.UNSIGNED_INT, gl.ELEMENT_ARRAY_BUFFER))]))

    # Joints: nodes with the first frame's local transform.
    q0 = Rotation.from_matrix(clip.local_rotation[0]).as_quat()
    for j in range(J):
        children = skeleton.children(j)
        doc.nodes.append(gl.Node(name=skeleton.names[j], translation=[float(v) for v in clip.local_translation[0, j]],
                                 rotation=[float(v) for v in q0[j]], children=children or None))
    world = np.tile(np.eye(4), (J, 1, 1))
    world[:, :3, :3] = clip.world_rotation[0]
    world[:, :3, 3] = clip.world_position[0]
    inverse_bind = np.linalg.inv(world).transpose(0, 2, 1).astype(np.float32)  # column-major
    doc.skins.append(gl.Skin(name="skeleton", joints=list(range(J)), skeleton=0,
                             inverseBindMatrices=blob.add(inverse_bind, gl.MAT4, gl.FLOAT)))
    doc.nodes.append(gl.Node(name="creature", mesh=0, skin=0))
    roots = [0, J]
    if ground:
        roots.append(_ground(motion, blob, doc))
    doc.scenes.append(gl.Scene(name="gaitlab", nodes=roots))
    doc.scene = 0

    # The animation: rotations of every joint, translations where offsets change.
    times = (clip.times - clip.times[0]).astype(np.float32)
    time_accessor = blob.add(times, gl.SCALAR, gl.FLOAT, bounds=True)
    animation = gl.Animation(name="clip", channels=[], samplers=[])
    moving = np.ptp(clip.local_translation, axis=0).max(axis=-1) > 1e-9
    for j in range(J):
        q = _quaternions(clip.local_rotation[:, j]).astype(np.float32)
        animation.samplers.append(gl.AnimationSampler(input=time_accessor, output=blob.add(q, gl.VEC4, gl.FLOAT),
                                                      interpolation="LINEAR"))
        animation.channels.append(gl.AnimationChannel(sampler=len(animation.samplers) - 1,
                                                      target=gl.AnimationChannelTarget(node=j, path="rotation")))
        if j == 0 or moving[j]:
            t = clip.local_translation[:, j].astype(np.float32)
            animation.samplers.append(gl.AnimationSampler(input=time_accessor,
                                                          output=blob.add(t, gl.VEC3, gl.FLOAT),
                                                          interpolation="LINEAR"))
            animation.channels.append(gl.AnimationChannel(sampler=len(animation.samplers) - 1, target=(
                gl.AnimationChannelTarget(node=j, path="translation"))))
    doc.animations.append(animation)
    while len(blob.data) % 4:
        blob.data.append(0)
    doc.buffers.append(gl.Buffer(byteLength=len(blob.data)))
    doc.set_binary_blob(bytes(blob.data))
    return doc


def write_glb(path: str | os.PathLike[str], motion: Motion, clip: SkeletonClip, ground: bool = False) -> Path:
    """Write the clip as a binary glTF (.glb), atomically (``ground``: see :func:`gltf_document`)."""
    doc = gltf_document(motion, clip, ground)
    with AtomicPath(path) as out:
        out.tmp.write_bytes(b"".join(doc.save_to_bytes()))
    return Path(path)
