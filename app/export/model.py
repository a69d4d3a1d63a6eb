"""A creature's motion written on a user's rigged model: the model's own glTF (skeleton,
rest pose, meshes, materials, its own animations kept after) with one more animation,
first, moving its own joints as Gaitlab walked them.

Per frame each joint's world transform (:func:`app.rigged.drive.drive_joints`, metres)
is taken back to the model's units and to its parent's frame, and written as the node's
translation and rotation; its scale stays the rest scale. A joint stored as a matrix is
rewritten as the same translation, rotation and scale (glTF animates those only).
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pygltflib as gl
from numpy.typing import NDArray
from scipy.spatial.transform import Rotation

from ..kinematics.motion import Motion
from ..output import AtomicPath
from ..rigged.drive import drive_joints, motion_turns
from ..rigged.gltf import node_matrix, world_matrices
from ..rigged.loaded import load_model

ANIMATION_NAME = "gaitlab walk"


def _quaternions(rotation: NDArray[np.float64]) -> NDArray[np.float64]:
    """Unit quaternions (T, 4) as x, y, z, w of rotations (T, 3, 3), each in the same
    hemisphere as the one before (no flips between frames)."""
    q = Rotation.from_matrix(rotation).as_quat()
    flip = np.concatenate([[False], np.sum(q[1:] * q[:-1], axis=-1) < 0.0])
    sign = np.where(np.logical_xor.accumulate(flip), -1.0, 1.0)
    return q * sign[:, None]


def _rotation_only(m: NDArray[np.float64]) -> NDArray[np.float64]:
    """The nearest rotations (..., 3, 3) to ``m``."""
    u, _, vt = np.linalg.svd(m)
    r = u @ vt
    return r


def write_model_glb(motion: Motion, output: str | os.PathLike[str], fps: float) -> Path:
    """Write ``motion`` of a model's creature onto the model's own glTF at ``output``
    (.glb), atomically."""
    loaded = load_model(motion.rig.model)
    model = loaded.model
    gltf = gl.GLTF2().load(str(model.path))
    gltf.convert_buffers(gl.BufferFormat.BINARYBLOB)
    blob = bytearray(gltf.binary_blob() or b"")
    world_m = drive_joints(model, loaded.legs, loaded.scale, motion.joints, motion.root, loaded.clearance,
                           motion.rig.ankle_lift, motion.arms, motion_turns(motion))  # (T, J, 4, 4) metres
    frames = len(world_m)
    # Back to the model's units: its rest scales in the rotation part, positions / scale.
    rest_rot = _rotation_only(model.rest[:, :3, :3])
    shape = np.swapaxes(rest_rot, 1, 2) @ model.rest[:, :3, :3]  # (J, 3, 3) what the rest adds to a rotation
    world = world_m.copy()
    world[..., :3, :3] = world_m[..., :3, :3] @ shape
    world[..., :3, 3] = world_m[..., :3, 3] / loaded.scale
    nodes = gltf.nodes
    skin_index = next(n.skin for n in nodes if n.skin is not None and n.mesh is not None)
    joint_nodes = list(gltf.skins[skin_index].joints)
    joint_of = {node: k for k, node in enumerate(joint_nodes)}
    parent_node = {child: p for p, n in enumerate(nodes) for child in (n.children or [])}
    static = world_matrices(gltf)
    channels, samplers = [], []
    times = np.arange(frames, dtype=np.float32) / np.float32(fps)
    time_accessor = _append(gltf, blob, times.reshape(-1, 1), "SCALAR", with_bounds=True)
    for k, node_index in enumerate(joint_nodes):
        p = parent_node.get(node_index, -1)
        if p in joint_of:
            above = world[:, joint_of[p]]
        else:
            above = np.broadcast_to(static[p] if p >= 0 else np.eye(4), (frames, 4, 4))
        local = np.linalg.solve(above, world[:, k])  # (T, 4, 4)
        node = nodes[node_index]
        if node.matrix is not None:  # animated nodes take translation, rotation and scale
            rest_local = node_matrix(node)
            scale = np.linalg.norm(rest_local[:3, :3], axis=0)
            rot = rest_local[:3, :3] / scale
            node.translation = [float(v) for v in rest_local[:3, 3]]
            node.rotation = [float(v) for v in _quaternions(rot[None])[0]]
            node.scale = [float(v) for v in scale]
            node.matrix = None
        scale = np.array(node.scale if node.scale is not None else [1.0, 1.0, 1.0], dtype=np.float64)
        rotation = _quaternions(_rotation_only(local[:, :3, :3] / scale[None, None, :]))
        for path, values, kind in (("translation", local[:, :3, 3], "VEC3"), ("rotation", rotation, "VEC4")):
            accessor = _append(gltf, blob, values.astype(np.float32), kind)
            samplers.append(gl.AnimationSampler(input=time_accessor, output=accessor, interpolation="LINEAR"))
            channels.append(gl.AnimationChannel(sampler=len(samplers) - 1,
                                                target=gl.AnimationChannelTarget(node=node_index, path=path)))
    gltf.animations = [gl.Animation(name=ANIMATION_NAME, channels=channels, samplers=samplers),
                       *(gltf.animations or [])]
    gltf.buffers[0].byteLength = len(blob)
    gltf.set_binary_blob(bytes(blob))
    with AtomicPath(output) as out:
        out.tmp.write_bytes(b"".join(gltf.save_to_bytes()))
    return Path(output)


def _append(gltf: gl.GLTF2, blob: bytearray, values: NDArray[np.float32], kind: str, with_bounds: bool = False) -> int:
    """Append ``values`` (N, C) float32 to the binary blob as a buffer view and accessor;
    returns the accessor's index."""
    while len(blob) % 4:
        blob.append(0)
    data = np.ascontiguousarray(values, dtype=np.float32).tobytes()
    gltf.bufferViews.append(gl.BufferView(buffer=0, byteOffset=len(blob), byteLength=len(data)))
    blob.extend(data)
    accessor = gl.Accessor(bufferView=len(gltf.bufferViews) - 1, componentType=gl.FLOAT, count=len(values),
                           type=kind)
    if with_bounds:
        accessor.min = [float(v) for v in values.min(axis=0)]
        accessor.max = [float(v) for v in values.max(axis=0)]
    gltf.accessors.append(accessor)
    return len(gltf.accessors) - 1
