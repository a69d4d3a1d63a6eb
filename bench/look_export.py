"""Look at an export: a frame drawn from the .glb alone (its skinned mesh, vertex colours,
joint animation and inverse bind matrices, with matplotlib) beside Gaitlab's own frame.

    python bench/look_export.py [OUT.png]      # default: export_side_by_side.png

A check by eye that the file moves the mesh as Gaitlab does (the tests check the numbers).
"""

from __future__ import annotations

import sys
from pathlib import Path

import matplotlib
import numpy as np
import pygltflib
from PIL import Image

ROOT = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(ROOT), str(ROOT / "tests")]

from test_export import glb_world_positions

from app import build_rig, load_creature
from app.export import write_glb
from app.kinematics.clip import clip_motion
from app.kinematics.skeleton import skeleton_clip
from app.render.clip import ClipRenderer
from app.render.framing import clip_cameras
from app.render.options import RenderOptions, ViewSettings


def main() -> None:
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    out = Path(sys.argv[1] if len(sys.argv) > 1 else "export_side_by_side.png")
    glb = out.with_suffix(".glb")
    motion, _ = clip_motion(build_rig(load_creature("dog").with_overrides({"gait.preset": "trot"})), 30.0, cycles=2)
    write_glb(glb, motion, skeleton_clip(motion))
    doc = pygltflib.GLTF2().load(str(glb))
    blob = doc.binary_blob()

    def read(index: int, dtype=np.float32) -> np.ndarray:
        accessor = doc.accessors[index]
        view = doc.bufferViews[accessor.bufferView]
        width = {"SCALAR": 1, "VEC3": 3, "VEC4": 4, "MAT4": 16}[accessor.type]
        return np.frombuffer(blob, dtype=dtype, count=accessor.count * width,
                             offset=view.byteOffset).reshape(accessor.count, width)

    prim = doc.meshes[0].primitives[0]
    vertices = read(prim.attributes.POSITION).astype(float)
    faces = read(prim.indices, np.uint32).reshape(-1, 3)
    colors = read(prim.attributes.COLOR_0).astype(float)
    joint = read(prim.attributes.JOINTS_0, np.uint16)[:, 0]
    names, position, rotation, inverse_bind = glb_world_positions(glb, motion.times - motion.times[0], True)
    t = motion.frame_count // 2
    world = np.tile(np.eye(4), (len(names), 1, 1))
    world[:, :3, :3], world[:, :3, 3] = rotation[t], position[t]
    skinned = np.einsum("vij,vj->vi", (world @ inverse_bind)[joint], np.c_[vertices, np.ones(len(vertices))])[:, :3]

    fig = plt.figure(figsize=(4.8, 3.6), dpi=100)
    ax = fig.add_subplot(111, projection="3d")
    normal = np.cross(skinned[faces[:, 1]] - skinned[faces[:, 0]], skinned[faces[:, 2]] - skinned[faces[:, 0]])
    normal /= np.linalg.norm(normal, axis=1, keepdims=True) + 1e-12
    light = np.clip(normal @ np.array([-0.45, 0.8, 0.35]), 0.3, 1.0)[:, None]
    ax.add_collection3d(Poly3DCollection(skinned[faces][:, :, [2, 0, 1]], edgecolor="none",
                                         facecolors=np.clip(np.sqrt(colors[faces].mean(axis=1)) * light, 0, 1)))
    centre, half = skinned.mean(axis=0), np.ptp(skinned, axis=0).max() / 2 * 0.8
    ax.set_xlim(centre[2] - half, centre[2] + half)
    ax.set_ylim(centre[0] - half, centre[0] + half)
    ax.set_zlim(centre[1] - half, centre[1] + half)
    ax.set_box_aspect((1, 1, 1))
    ax.view_init(elev=4, azim=-90)
    ax.set_axis_off()
    ax.set_position([0, 0, 1, 1])
    drawn = out.with_suffix(".glb.png")
    fig.savefig(drawn)
    view = ViewSettings(size=(480, 360), camera="side")
    ours = ClipRenderer(view.size, "msaa").frame(motion, t, clip_cameras(motion, view)[t], RenderOptions())
    theirs = np.asarray(Image.open(drawn).convert("RGB").resize((480, 360)))
    Image.fromarray(np.concatenate([ours, theirs], axis=1)).save(out)
    print(f"wrote {out}: frame {t}, Gaitlab's renderer left, the .glb alone right")


if __name__ == "__main__":
    main()
