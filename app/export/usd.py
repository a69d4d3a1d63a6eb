"""USD export (.usda text, .usdc binary) as a UsdSkel skeleton animation.

The stage is Y up in metres at the clip's frame rate. ``/Creature`` is a SkelRoot holding
the Skeleton (joints as paths, bind transforms from the body's bind pose, rest transforms
from the first frame), its SkelAnimation (every joint's local translation and rotation at
every frame) and the creature's skinned body (the viewer's, up to four joints a vertex)
with vertex colours, and its features (eyes, nose, mane: ``/Creature/Features``) skinned
to the same skeleton.
Needs Pixar's ``usd-core`` package (``pip install usd-core``, an optional dependency).
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from ..errors import OutputError
from ..kinematics.motion import Motion
from ..kinematics.skeleton import SkeletonClip
from ..output import AtomicPath
from ..skin import SkinnedBody
from .gltf import continuous_quaternions
from .mesh import creature_features, creature_mesh


def _pxr():
    try:
        from pxr import Gf, Sdf, Usd, UsdGeom, UsdSkel, Vt
    except ImportError:
        raise OutputError("USD export needs Pixar's usd-core: pip install usd-core (or write .glb or .bvh)") from None
    return Gf, Sdf, Usd, UsdGeom, UsdSkel, Vt


def joint_paths(clip: SkeletonClip) -> list[str]:
    """Each joint as a USD joint path ("root/spine4/LF_hip/...")."""
    names, parents = clip.skeleton.names, clip.skeleton.parents
    paths: list[str] = []
    for j, p in enumerate(parents):
        paths.append(names[j] if p < 0 else f"{paths[p]}/{names[j]}")
    return paths


def _matrices(rotation: NDArray[np.float64], translation: NDArray[np.float64], Gf) -> list:
    """(J, 3, 3) and (J, 3) -> Gf.Matrix4d (USD's row-vector convention)."""
    out = []
    for r, t in zip(rotation, translation):
        m = np.eye(4)
        m[:3, :3] = r.T
        m[3, :3] = t
        out.append(Gf.Matrix4d(m.tolist()))
    return out


def write_usd(path: str | os.PathLike[str], motion: Motion | list[Motion], clip: SkeletonClip | list[SkeletonClip],
              names: list[str] | None = None) -> Path:
    """Write the clip as a UsdSkel stage (.usda or .usdc by suffix), atomically: one
    creature at ``/Creature``, or several (a scene's), each its own SkelRoot
    ``/Scene/NAME``."""
    _Gf, _Sdf, Usd, UsdGeom, _UsdSkel, _Vt = _pxr()
    motions = motion if isinstance(motion, list) else [motion]
    clips = clip if isinstance(clip, list) else [clip]
    out = AtomicPath(path)
    try:
        stage = Usd.Stage.CreateNew(str(out.tmp))
        UsdGeom.SetStageUpAxis(stage, UsdGeom.Tokens.y)
        UsdGeom.SetStageMetersPerUnit(stage, 1.0)
        T = clips[0].frame_count
        stage.SetTimeCodesPerSecond(clips[0].fps)
        stage.SetFramesPerSecond(clips[0].fps)
        stage.SetStartTimeCode(0)
        stage.SetEndTimeCode(max(T - 1, 0))
        if len(clips) == 1:
            root = _creature(stage, "/Creature", motions[0], clips[0])
        else:
            root = UsdGeom.Xform.Define(stage, "/Scene")
            for m, c, name in zip(motions, clips, names or [f"creature{i}" for i in range(len(clips))]):
                _creature(stage, f"/Scene/{_prim_name(name)}", m, c)
        stage.SetDefaultPrim(root.GetPrim())
        stage.GetRootLayer().Save()
    except OutputError:
        out.discard()
        raise
    except Exception as exc:  # pxr raises Tf.ErrorException with several lines of context
        out.discard()
        if type(exc).__module__.startswith("pxr"):
            raise OutputError(f"{os.fspath(path)}: cannot write USD: {usd_error_text(exc)}") from None
        raise
    except BaseException:
        out.discard()
        raise
    return out.commit()


def _prim_name(name: str) -> str:
    """A valid USD prim name from a creature name."""
    clean = "".join(c if c.isalnum() or c == "_" else "_" for c in name)
    return clean if clean and not clean[0].isdigit() else f"_{clean}"


def _creature(stage, where: str, motion: Motion, clip: SkeletonClip):
    """One creature's SkelRoot at ``where``: skeleton, animation, skinned mesh and its
    features (eyes, nose, mane) as a second skinned mesh."""
    Gf, _Sdf, _Usd, _UsdGeom, UsdSkel, Vt = _pxr()
    root = UsdSkel.Root.Define(stage, where)
    skeleton = UsdSkel.Skeleton.Define(stage, f"{where}/Skeleton")
    paths = joint_paths(clip)
    skeleton.CreateJointsAttr(paths)
    mesh_data = creature_mesh(motion, clip)  # its bind pose is the skeleton's
    skeleton.CreateBindTransformsAttr(Vt.Matrix4dArray(
        _matrices(mesh_data.bind[:, :3, :3], mesh_data.bind[:, :3, 3], Gf)))
    skeleton.CreateRestTransformsAttr(Vt.Matrix4dArray(
        _matrices(clip.local_rotation[0], clip.local_translation[0], Gf)))
    animation = UsdSkel.Animation.Define(stage, f"{where}/Skeleton/Motion")
    animation.CreateJointsAttr(paths)
    translations = animation.CreateTranslationsAttr()
    rotations = animation.CreateRotationsAttr()
    animation.CreateScalesAttr().Set(Vt.Vec3hArray([Gf.Vec3h(1, 1, 1)] * len(paths)))
    quat = np.stack([continuous_quaternions(clip.local_rotation[:, j]) for j in range(len(paths))], axis=1)
    for t in range(clip.frame_count):
        translations.Set(Vt.Vec3fArray.FromNumpy(clip.local_translation[t].astype(np.float32)), t)
        rotations.Set(Vt.QuatfArray([Gf.Quatf(float(q[3]), float(q[0]), float(q[1]), float(q[2]))
                                     for q in quat[t]]), t)
    UsdSkel.BindingAPI.Apply(skeleton.GetPrim()).CreateAnimationSourceRel().SetTargets([animation.GetPath()])

    _skinned_prim(stage, f"{where}/Body", mesh_data, skeleton)
    features = creature_features(motion, clip)
    if features is not None:
        _skinned_prim(stage, f"{where}/Features", features, skeleton)
    return root


def _skinned_prim(stage, where: str, mesh_data: SkinnedBody, skeleton) -> None:
    """A mesh prim at ``where`` with vertex colours, skinned to ``skeleton``."""
    Gf, Sdf, _Usd, UsdGeom, UsdSkel, Vt = _pxr()
    mesh = UsdGeom.Mesh.Define(stage, where)
    mesh.CreatePointsAttr(Vt.Vec3fArray.FromNumpy(mesh_data.positions.astype(np.float32)))
    mesh.CreateFaceVertexCountsAttr(Vt.IntArray([3] * len(mesh_data.faces)))
    mesh.CreateFaceVertexIndicesAttr(Vt.IntArray.FromNumpy(mesh_data.faces.reshape(-1).astype(np.int32)))
    mesh.CreateNormalsAttr(Vt.Vec3fArray.FromNumpy(mesh_data.normals.astype(np.float32)))
    mesh.SetNormalsInterpolation(UsdGeom.Tokens.vertex)
    mesh.CreateSubdivisionSchemeAttr(UsdGeom.Tokens.none)
    colors = UsdGeom.PrimvarsAPI(mesh).CreatePrimvar("displayColor", Sdf.ValueTypeNames.Color3fArray,
                                                     UsdGeom.Tokens.vertex)
    colors.Set(Vt.Vec3fArray.FromNumpy(mesh_data.colors.astype(np.float32)))
    binding = UsdSkel.BindingAPI.Apply(mesh.GetPrim())
    binding.CreateSkeletonRel().SetTargets([skeleton.GetPath()])
    influences = mesh_data.joints.shape[1]
    binding.CreateJointIndicesPrimvar(False, influences).Set(
        Vt.IntArray.FromNumpy(mesh_data.joints.reshape(-1).astype(np.int32)))
    binding.CreateJointWeightsPrimvar(False, influences).Set(
        Vt.FloatArray.FromNumpy(mesh_data.weights.reshape(-1).astype(np.float32)))
    binding.CreateGeomBindTransformAttr(Gf.Matrix4d(1.0))


def usd_error_text(exc: BaseException) -> str:
    """What a pxr error says, without its C++ locations: each of its lines reads
    "Error in 'Function' at line N in file F.cpp : 'message'"; the first message is kept."""
    lines = [line.strip() for line in str(exc).splitlines() if line.strip()]
    if not lines:
        return type(exc).__name__
    first = lines[0]
    if " : " in first and first.startswith("Error in "):
        first = first.split(" : ", 1)[1].strip()
        if len(first) > 1 and first[0] == first[-1] == "'":  # the message is quoted once
            first = first[1:-1]
    return first[:200]
