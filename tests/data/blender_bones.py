"""Run by a Python that has ``bpy`` (Blender as a Python module): import each glTF file
given and print, as JSON, every bone's head in world space at every animation key, in
glTF's axes (metres, Y up), so a test can compare them with Gaitlab's joints.

    python blender_bones.py FPS FILE.glb [FILE.glb ...]

Output: one line, "BONES " and {file: {"names": [...], "frames": [[[x, y, z], ...], ...],
"meshes": [{"vertices": N, "groups": G, "skinned": bool}, ...]}} (frames in key order).
"""

from __future__ import annotations

import json
import sys

import bpy


def bones_of(path: str, fps: int) -> dict:
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    scene.render.fps = fps  # the importer keys the clip at the scene's frame rate
    bpy.ops.import_scene.gltf(filepath=path)
    armature = next(o for o in scene.objects if o.type == "ARMATURE")
    action = armature.animation_data.action
    keys = sorted({round(k.co[0]) for curve in _curves(action) for k in curve.keyframe_points})
    names = [bone.name for bone in armature.pose.bones]
    frames = []
    for frame in keys:
        scene.frame_set(frame)
        heads = []
        for bone in armature.pose.bones:
            x, y, z = armature.matrix_world @ bone.head
            heads.append([x, z, -y])  # Blender's Z up back to glTF's Y up
        frames.append(heads)
    meshes = [{"vertices": len(o.data.vertices), "groups": len(o.vertex_groups),
               "skinned": any(m.type == "ARMATURE" and m.object == armature for m in o.modifiers)}
              for o in scene.objects if o.type == "MESH"]
    return {"names": names, "frames": frames, "meshes": meshes}


def _curves(action):
    """An action's F-curves: on the action itself (Blender 4) or in its layered slots (5)."""
    if getattr(action, "fcurves", None):
        return list(action.fcurves)
    curves = []
    for layer in action.layers:
        for strip in layer.strips:
            for bag in strip.channelbags:
                curves.extend(bag.fcurves)
    return curves


def main() -> None:
    fps = int(sys.argv[1])
    result = {path: bones_of(path, fps) for path in sys.argv[2:]}
    print("BONES " + json.dumps(result))  # one marked line: Blender prints its own lines too


if __name__ == "__main__":
    main()
