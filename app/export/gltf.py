"""glTF 2.0 export (.glb): the skeleton as a skin, the creature's mesh skinned to it, one
animation with root motion.

The mesh is the creature's skinned body (:mod:`app.skin`: one closed smooth surface,
what the renderer draws) in the first frame, each vertex bound to up to four joints,
with vertex colours, and a second primitive of its features (eyes, nose, mane) skinned
to the same joints. Joints are nodes
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

from ..errors import OutputError
from ..kinematics.motion import Motion
from ..kinematics.skeleton import SkeletonClip
from ..output import AtomicPath
from ..skin import SkinnedBody
from .mesh import creature_features, creature_mesh


def continuous_quaternions(rotation: NDArray[np.float64]) -> NDArray[np.float64]:
    """(T, 3, 3) -> (T, 4) xyzw, signs kept continuous over time (no 360-degree spins)."""
    q = Rotation.from_matrix(rotation).as_quat()
    flip = np.einsum("ti,ti->t", q[1:], q[:-1]) < 0
    sign = np.concatenate([[1.0], np.where(np.cumsum(flip) % 2 == 1, -1.0, 1.0)])
    return q * sign[:, None]


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
GROUND_MAX_CELLS = 600  # per side: the ground mesh's resolution is capped
GROUND_MAX_CELL = 0.25  # m: coarser cells would no longer follow the terrain the feet stand on


def _ground(motions: list[Motion], blob: _Blob, doc: gl.GLTF2) -> int:
    """A mesh of the ground under the clip (the terrain over the area the creatures
    cover); the index of its node."""
    points = np.concatenate([p for m in motions for p in (m.joints.reshape(-1, 3), m.spine.reshape(-1, 3))])
    lo = points[:, [0, 2]].min(axis=0) - GROUND_MARGIN
    hi = points[:, [0, 2]].max(axis=0) + GROUND_MARGIN
    extent = float((hi - lo).max())
    cell = max(0.05, extent / GROUND_MAX_CELLS)
    if cell > GROUND_MAX_CELL:
        raise OutputError(f"--ground: the clip covers {extent:.0f} m; the ground mesh is made for clips up to "
                          f"{GROUND_MAX_CELL * GROUND_MAX_CELLS:.0f} m across (export a shorter clip, or without "
                          "--ground)")
    terrain = motions[0].terrain
    position, normal, indices = terrain.surface((float(lo[0]), float(lo[1])), (float(hi[0]), float(hi[1])), cell)
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


def _skinned_mesh(motion: Motion, clip: SkeletonClip, name: str, blob: _Blob, doc: gl.GLTF2
                  ) -> tuple[int, NDArray[np.float64]]:
    """The creature's skinned body in its bind pose, each vertex bound to up to four
    joints, and its features (eyes, nose, mane) as a second primitive; the index of the
    mesh and the joints' bind matrices (J, 4, 4)."""
    mesh = creature_mesh(motion, clip)
    features = creature_features(motion, clip)
    if not doc.materials or doc.materials[0].name != "creature":
        doc.materials.insert(0, gl.Material(name="creature", pbrMetallicRoughness=gl.PbrMetallicRoughness(
            baseColorFactor=[1.0, 1.0, 1.0, 1.0], metallicFactor=0.0, roughnessFactor=0.7)))
    primitives = [_primitive(part, blob) for part in (mesh, features) if part is not None]
    doc.meshes.append(gl.Mesh(name=name, primitives=primitives))
    return len(doc.meshes) - 1, mesh.bind


def _primitive(mesh: SkinnedBody, blob: _Blob) -> gl.Primitive:
    """A skinned mesh's triangles with vertex colours, joints and weights (material 0)."""
    position, normal, color = (a.astype(np.float32) for a in (mesh.positions, mesh.normals, mesh.colors))
    attributes = gl.Attributes(
        POSITION=blob.add(position, gl.VEC3, gl.FLOAT, gl.ARRAY_BUFFER, bounds=True),
        NORMAL=blob.add(normal, gl.VEC3, gl.FLOAT, gl.ARRAY_BUFFER),
        COLOR_0=blob.add(color, gl.VEC3, gl.FLOAT, gl.ARRAY_BUFFER),
        JOINTS_0=blob.add(mesh.joints.astype(np.uint16), gl.VEC4, gl.UNSIGNED_SHORT, gl.ARRAY_BUFFER),
        WEIGHTS_0=blob.add(mesh.weights.astype(np.float32), gl.VEC4, gl.FLOAT, gl.ARRAY_BUFFER))
    indices = mesh.faces.astype(np.uint32).reshape(-1)
    return gl.Primitive(attributes=attributes, material=0,
                        indices=blob.add(indices, gl.SCALAR, gl.UNSIGNED_INT, gl.ELEMENT_ARRAY_BUFFER))


def _skeleton(clip: SkeletonClip, prefix: str, bind: NDArray[np.float64], blob: _Blob, doc: gl.GLTF2
              ) -> tuple[int, int]:
    """The joints as nodes with the first frame's local transform, and their skin (inverse
    bind matrices from the mesh's ``bind`` (J, 4, 4)); the index of the first joint's node
    and of the skin."""
    skeleton = clip.skeleton
    first = len(doc.nodes)
    q0 = Rotation.from_matrix(clip.local_rotation[0]).as_quat()
    for j in range(skeleton.count):
        children = [first + c for c in skeleton.children(j)]
        doc.nodes.append(gl.Node(name=prefix + skeleton.names[j],
                                 translation=[float(v) for v in clip.local_translation[0, j]],
                                 rotation=[float(v) for v in q0[j]], children=children or None))
    inverse_bind = np.linalg.inv(bind).transpose(0, 2, 1).astype(np.float32)  # column-major
    doc.skins.append(gl.Skin(name=f"{prefix}skeleton", joints=list(range(first, first + skeleton.count)),
                             skeleton=first, inverseBindMatrices=blob.add(inverse_bind, gl.MAT4, gl.FLOAT)))
    return first, len(doc.skins) - 1


def _animate(clip: SkeletonClip, first: int, times: int, blob: _Blob, animation: gl.Animation) -> None:
    """Channels for a skeleton's joints (nodes from ``first``): rotations of every joint,
    translations where offsets change (the root carries the travel)."""
    moving = np.ptp(clip.local_translation, axis=0).max(axis=-1) > 1e-9
    for j in range(clip.skeleton.count):
        q = continuous_quaternions(clip.local_rotation[:, j]).astype(np.float32)
        animation.samplers.append(gl.AnimationSampler(input=times, output=blob.add(q, gl.VEC4, gl.FLOAT),
                                                      interpolation="LINEAR"))
        animation.channels.append(gl.AnimationChannel(sampler=len(animation.samplers) - 1,
                                                      target=gl.AnimationChannelTarget(node=first + j,
                                                                                       path="rotation")))
        if j == 0 or moving[j]:
            t = clip.local_translation[:, j].astype(np.float32)
            animation.samplers.append(gl.AnimationSampler(input=times, output=blob.add(t, gl.VEC3, gl.FLOAT),
                                                          interpolation="LINEAR"))
            animation.channels.append(gl.AnimationChannel(sampler=len(animation.samplers) - 1, target=(
                gl.AnimationChannelTarget(node=first + j, path="translation"))))


def gltf_document(motion: Motion | list[Motion], clip: SkeletonClip | list[SkeletonClip],
                  ground: bool = False, names: list[str] | None = None) -> gl.GLTF2:
    """A clip (or several: a scene's creatures, each its own skeleton, skin and mesh, in
    one animation) as a glTF document with its binary blob attached; ``ground`` adds the
    terrain under the clip as a mesh (not for in-place clips, whose ground moves).
    ``names`` prefix each creature's joints (needed when there are several)."""
    motions = motion if isinstance(motion, list) else [motion]
    clips = clip if isinstance(clip, list) else [clip]
    prefixes = [f"{n}:" for n in names] if names else [""] * len(clips)
    doc = gl.GLTF2(asset=gl.Asset(generator="Gaitlab", version="2.0"))
    blob = _Blob(doc)
    meshes = [_skinned_mesh(m, c, m.rig.name, blob, doc) for m, c in zip(motions, clips)]
    roots = []
    skeletons = []
    for c, prefix, (_, bind) in zip(clips, prefixes, meshes):
        skeletons.append(_skeleton(c, prefix, bind, blob, doc))
        roots.append(skeletons[-1][0])
    for (_, skin), (mesh, _), m in zip(skeletons, meshes, motions):
        doc.nodes.append(gl.Node(name=m.rig.name if len(clips) > 1 else "creature", mesh=mesh, skin=skin))
        roots.append(len(doc.nodes) - 1)
    if ground:
        roots.append(_ground(motions, blob, doc))
    doc.scenes.append(gl.Scene(name="gaitlab", nodes=roots))
    doc.scene = 0
    times = (clips[0].times - clips[0].times[0]).astype(np.float32)
    time_accessor = blob.add(times, gl.SCALAR, gl.FLOAT, bounds=True)
    animation = gl.Animation(name="clip", channels=[], samplers=[])
    for c, (first, _) in zip(clips, skeletons):
        _animate(c, first, time_accessor, blob, animation)
    doc.animations.append(animation)
    while len(blob.data) % 4:
        blob.data.append(0)
    doc.buffers.append(gl.Buffer(byteLength=len(blob.data)))
    doc.set_binary_blob(bytes(blob.data))
    return doc


def write_glb(path: str | os.PathLike[str], motion: Motion | list[Motion], clip: SkeletonClip | list[SkeletonClip],
              ground: bool = False, names: list[str] | None = None) -> Path:
    """Write the clip(s) as a binary glTF (.glb), atomically (see :func:`gltf_document`)."""
    doc = gltf_document(motion, clip, ground, names)
    with AtomicPath(path) as out:
        out.tmp.write_bytes(b"".join(doc.save_to_bytes()))
    return Path(path)
