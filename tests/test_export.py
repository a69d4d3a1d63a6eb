"""Export (issue 10): BVH read back by Gaitlab's reader and by an independent one (bvhio)
gives the clip's joints; analysing the export measures the same gait."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pytest
from cli_runner import gaitlab

from app import build_rig, load_creature
from app.analysis import analyze_tracks, tracks_from_motion
from app.analysis.bvh import read_bvh
from app.analysis.sources import load_tracks
from app.export import write_bvh
from app.kinematics.clip import clip_motion
from app.kinematics.skeleton import skeleton_clip
from app.worlds import make_world

PRESETS = ("ant", "bear", "cat", "centipede", "deer", "dog", "horse", "spider")


def motion_of(creature: str, gait: str | None = None, fps: float = 60.0, cycles: float = 2.0, world=None):
    spec = load_creature(creature)
    if gait:
        spec = spec.with_overrides({"gait.preset": gait})
    return clip_motion(build_rig(spec), fps, cycles=cycles, world=world or make_world())[0]


@pytest.mark.parametrize("creature", PRESETS)
def test_bvh_round_trip_with_both_readers(tmp_path: Path, creature: str) -> None:
    world = make_world("circle:r=3", "hills:amp=0.08") if creature == "dog" else None
    motion = motion_of(creature, world=world)
    clip = skeleton_clip(motion)
    path = write_bvh(tmp_path / f"{creature}.bvh", clip)
    names = list(clip.skeleton.names)
    ours = read_bvh(path).positions(names)
    assert np.abs(ours - clip.world_position).max() < 1e-4
    for leg, leg_name in enumerate(motion.leg_names):  # the clip's own joints, over the whole clip
        got = ours[:, [names.index(f"{leg_name}_{part}") for part in ("hip", "knee", "ankle", "ball", "toe")]]
        assert np.abs(got - motion.joints[:, leg]).max() < 1e-4
    channels = read_bvh(path).frames
    rotations = [k for j in read_bvh(path).joints for k, c in enumerate(j.channels, j.first_channel)
                 if c.lower().endswith("rotation")]
    assert np.abs(np.diff(channels[:, rotations], axis=0)).max() < 45.0  # continuous angles: no gimbal spins
    bvhio = pytest.importorskip("bvhio", reason="bvhio (the independent BVH reader) is a test dependency")
    root = bvhio.readAsHierarchy(str(path))
    joints = {joint.Name: joint for joint, _, _ in root.layout()}
    for t in range(motion.frame_count):  # the whole clip
        root.loadPose(t)
        theirs = np.array([list(joints[n].PositionWorld) for n in names])
        assert np.abs(theirs - clip.world_position[t]).max() < 1e-4


@pytest.mark.parametrize("creature, gait", [("dog", "walk"), ("horse", "gallop"), ("cat", "trot"), ("bear", "pace"),
                                            ("ant", None), ("spider", None)])
def test_analysing_the_export_measures_the_same_gait(tmp_path: Path, creature: str, gait: str | None) -> None:
    motion = motion_of(creature, gait, cycles=4.0)
    write_bvh(tmp_path / "x.bvh", skeleton_clip(motion))
    own = analyze_tracks(tracks_from_motion(motion))
    tracks, note = load_tracks(str(tmp_path / "x.bvh"))
    exported = analyze_tracks(tracks)
    assert note.startswith("Gaitlab export") and exported.gait_match == own.gait_match
    # Within a frame and a half of the cycle (the file's rounded positions may move an
    # event by a frame: 0.036 of a horse's 28-frame gallop) and never more than 0.05.
    frame = float(tracks.times[1] - tracks.times[0])
    tolerance = min(max(0.01, 1.5 * frame / own.cycle_seconds), 0.05)
    for a, b in zip(own.feet, exported.feet):
        assert a.name == b.name
        assert abs(a.duty_factor - b.duty_factor) <= tolerance
        assert min(abs(a.phase - b.phase), 1 - abs(a.phase - b.phase)) <= tolerance


def test_export_command_writes_a_bvh_that_analyze_reads(tmp_path: Path) -> None:
    def run(*a: str):
        return gaitlab(*a, cwd=tmp_path)

    out = run("export", "dog", "--gait", "trot", "--cycles", "6", "--fps", "60", "-o", "dog.bvh")
    assert out.returncode == 0, out.stderr
    assert "41 joints" in out.stdout and "metres, Y up" in out.stdout
    analysed = run("analyze", "dog.bvh")
    assert analysed.returncode == 0, analysed.stderr
    assert "trot" in analysed.stdout
    assert sorted(p.name for p in tmp_path.iterdir()) == ["dog.bvh"]


@pytest.mark.parametrize("args, message", [
    (["-o", "dog.fbx"], "export has '.fbx'; use .bvh, .glb, .usda, .usdc"),
    (["--ground", "-o", "dog.bvh"], "--ground adds the terrain as a mesh to glTF files"),
    (["--loop", "--seconds", "2", "-o", "dog.bvh"], "a looped export is whole cycles"),
    (["--speed", "1:4", "--cycles", "2", "-o", "dog.bvh"], "with a changing --speed give the length in --seconds"),
    (["-o", "missing/dog.bvh"], "output folder 'missing' does not exist"),
    (["--gait", "gallp", "-o", "dog.bvh"], "did you mean 'gallop'"),
    (["--fps", "0", "-o", "dog.bvh"], "frames per second"),
    (["--set", "legs.hind.femur=-1", "-o", "dog.bvh"], "legs.hind.femur"),
    (["--loop", "--cycles", "1.5", "-o", "dog.bvh"], "--cycles 1.5 with --loop: a loop is whole cycles"),
    (["--loop", "--cycles", "0.01", "-o", "dog.bvh"], "--cycles 0.01 with --loop"),
    (["-o", "z" * 300 + ".bvh"], "cannot write: File name too long"),
    (["-o", "/".join(["q" * 200] * 30) + "/dog.bvh"], "cannot write: File name too long"),
])
def test_export_bad_input_is_one_line_exit_2_and_writes_nothing(tmp_path: Path, args, message) -> None:
    out = gaitlab("export", "dog", *args, cwd=tmp_path)
    assert out.returncode == 2
    assert message in out.stderr and "Traceback" not in out.stderr
    assert len(out.stderr.strip().splitlines()) == 1
    assert list(tmp_path.iterdir()) == []


def test_a_scene_s_bvh_files_are_named_safely_and_written_all_or_none(tmp_path: Path) -> None:
    """Each creature's BVH is named after it: a name with a slash, a control character or
    300 letters is made safe (it was a traceback); when one file cannot be written (a folder
    has its name) none is, and an earlier file of another's name is left as it was."""
    cat = (Path(__file__).parents[1] / "creatures" / "cat.toml").read_text()
    for stem, name in (("slash", "a/b"), ("long", "x" * 300), ("tab", "one\ttwo")):
        (tmp_path / f"{stem}.toml").write_text(cat.replace('name = "cat"', f"name = {name!r}".replace("'", '"')))
        (tmp_path / f"{stem}_scene.toml").write_text(
            f'[[creatures]]\ncreature = "dog"\n[[creatures]]\ncreature = "{stem}.toml"\n')
        out = gaitlab("export", f"{stem}_scene.toml", "--seconds", "0.3", "-q", "-o", f"{stem}.bvh", cwd=tmp_path)
        assert out.returncode == 0, out.stderr
    names = sorted(p.name for p in tmp_path.glob("*-*.bvh"))
    assert names == ["long-dog.bvh", f"long-{'x' * 60}.bvh", "slash-a_b.bvh", "slash-dog.bvh", "tab-dog.bvh",
                     "tab-one_two.bvh"]
    (tmp_path / "dog2.toml").write_text(cat.replace('name = "cat"', 'name = "dog-2"'))
    (tmp_path / "dogs.toml").write_text('[[creatures]]\ncreature = "dog"\n[[creatures]]\ncreature = "dog"\n'
                                        '[[creatures]]\ncreature = "dog2.toml"\n')
    out = gaitlab("export", "dogs.toml", "--seconds", "0.3", "-q", "-o", "d.bvh", cwd=tmp_path)
    assert out.returncode == 0, out.stderr
    assert sorted(p.name for p in tmp_path.glob("d-*.bvh")) == ["d-dog-2-2.bvh", "d-dog-2.bvh", "d-dog.bvh"]
    (tmp_path / "pair.toml").write_text('[[creatures]]\ncreature = "dog"\n[[creatures]]\ncreature = "cat"\n')
    (tmp_path / "s-dog.bvh").write_text("yesterday's dog\n")
    (tmp_path / "s-cat.bvh").mkdir()
    out = gaitlab("export", "pair.toml", "--seconds", "0.3", "-q", "-o", "s.bvh", cwd=tmp_path)
    assert out.returncode == 2 and len(out.stderr.strip().splitlines()) == 1, out.stderr
    assert "s-cat.bvh: is a folder" in out.stderr
    assert (tmp_path / "s-dog.bvh").read_text() == "yesterday's dog\n"
    assert not list(tmp_path.glob(".*partial*"))


def glb_world_positions(path: Path, times: np.ndarray, rotations: bool = False):
    """Joint names and world positions (T, J, 3) at ``times`` (the animation's keys),
    computed from the .glb's node TRS and its animation alone; with ``rotations`` also the
    world rotations (T, J, 3, 3) and the skin's inverse bind matrices (J, 4, 4)."""
    import pygltflib
    from scipy.spatial.transform import Rotation

    doc = pygltflib.GLTF2().load(str(path))
    blob = doc.binary_blob()

    def read(index: int) -> np.ndarray:
        accessor = doc.accessors[index]
        view = doc.bufferViews[accessor.bufferView]
        width = {"SCALAR": 1, "VEC3": 3, "VEC4": 4, "MAT4": 16}[accessor.type]
        data = np.frombuffer(blob, dtype=np.float32, count=accessor.count * width,
                             offset=view.byteOffset + (accessor.byteOffset or 0))
        return data.reshape(accessor.count, width).astype(np.float64)

    skin = doc.skins[0]
    joints = skin.joints
    node_index = {n: k for k, n in enumerate(joints)}
    parents = {c: p for p in joints for c in (doc.nodes[p].children or [])}
    T, J = len(times), len(joints)
    translation = np.array([doc.nodes[n].translation for n in joints])[None].repeat(T, 0)
    rotation = np.array([doc.nodes[n].rotation for n in joints])[None].repeat(T, 0)
    animation = doc.animations[0]
    for channel in animation.channels:
        sampler = animation.samplers[channel.sampler]
        keys, values = read(sampler.input)[:, 0], read(sampler.output)
        k = node_index[channel.target.node]
        for t, time in enumerate(times):  # sampled at the keys themselves here
            i = int(np.argmin(np.abs(keys - time)))
            if channel.target.path == "translation":
                translation[t, k] = values[i]
            else:
                rotation[t, k] = values[i]
    names = [doc.nodes[n].name for n in joints]
    world_r = np.empty((T, J, 3, 3))
    world_p = np.empty((T, J, 3))
    for k, n in enumerate(joints):
        local = Rotation.from_quat(rotation[:, k]).as_matrix()
        if n in parents:
            p = node_index[parents[n]]
            world_r[:, k] = world_r[:, p] @ local
            world_p[:, k] = world_p[:, p] + np.einsum("tij,tj->ti", world_r[:, p], translation[:, k])
        else:
            world_r[:, k], world_p[:, k] = local, translation[:, k]
    if rotations:
        inverse_bind = read(skin.inverseBindMatrices).reshape(J, 4, 4).transpose(0, 2, 1)
        return names, world_p, world_r, inverse_bind
    return names, world_p


@pytest.mark.parametrize("creature", PRESETS)
def test_glb_joints_follow_the_clip(tmp_path: Path, creature: str) -> None:
    from app.export import write_glb

    world = make_world("circle:r=3", "hills:amp=0.08") if creature == "dog" else None
    motion = motion_of(creature, fps=60.0, world=world)  # at 30 fps a whipping swing turns ~45 degrees a frame
    clip = skeleton_clip(motion)
    path = write_glb(tmp_path / f"{creature}.glb", motion, clip)
    names, position, rotation, inverse_bind = glb_world_positions(path, motion.times - motion.times[0], True)
    assert names == list(clip.skeleton.names)
    assert np.abs(position - clip.world_position).max() < 1e-4
    assert np.abs(rotation - clip.world_rotation).max() < 1e-5  # the bones' frames: what the skin follows
    bind = np.tile(np.eye(4), (len(names), 1, 1))
    bind[:, :3, :3], bind[:, :3, 3] = rotation[0], position[0]
    assert np.abs(bind @ inverse_bind - np.eye(4)).max() < 1e-4  # the mesh sits on the bones at rest
    angles = np.degrees(np.arccos(np.clip((np.trace(np.einsum("tjki,tjkl->tjil", rotation[:-1], rotation[1:]),
                                                    axis1=2, axis2=3) - 1) / 2, -1, 1)))
    assert angles.max() < 30.0  # no bone flips from one 60 fps frame to the next


def _validator() -> list[str] | None:
    """The command that runs the Khronos glTF validator, or None (with the reason) if unavailable."""
    import shutil
    import subprocess

    node = shutil.which("node")
    if node is None:
        pytest.skip("node is not installed: the Khronos glTF validator (npm gltf-validator) cannot run")
    home = Path(os.environ.get("GAITLAB_NODE_CACHE", Path.home() / ".cache" / "gaitlab-node"))
    if not (home / "node_modules" / "gltf-validator").exists():
        npm = shutil.which("npm")
        home.mkdir(parents=True, exist_ok=True)
        done = subprocess.run([npm, "install", "--silent", "--no-audit", "--no-fund", "--prefix", str(home),
                               "gltf-validator@2.0.0-dev.3.10"], capture_output=True, text=True, timeout=300) \
            if npm else None
        if done is None or done.returncode != 0:
            pytest.skip("could not install the npm package gltf-validator (offline?)")
    script = Path(__file__).parent / "data" / "validate_gltf.js"
    return [node, str(script), str(home)]


@pytest.mark.parametrize("creature", PRESETS)
def test_every_preset_passes_the_khronos_validator(tmp_path: Path, creature: str) -> None:
    import json
    import subprocess

    from app.export import write_glb

    command = _validator()
    world = make_world("circle:r=2", "stairs:rise=0.05,run=0.3") if creature == "dog" else None
    motion = motion_of(creature, fps=30.0, world=world)
    from app.export.mesh import export_layout

    path = write_glb(tmp_path / f"{creature}.glb", motion, skeleton_clip(motion, export_layout(motion)),
                     ground=creature in ("dog", "ant"))
    out = subprocess.run([*command, str(path)], capture_output=True, text=True, timeout=120)
    report = json.loads(out.stdout)
    assert report.get("errors") == 0, report


@pytest.mark.parametrize("in_place", [True, False])
def test_a_looped_export_ends_where_it_began(tmp_path: Path, in_place: bool) -> None:
    from app.export import export_clip

    world = make_world(in_place=in_place)
    result = export_clip(load_creature("cat"), tmp_path / "cat.bvh", fps=30.0, cycles=2.0, world=world, loop=True)
    clip = read_bvh(result.path)
    names = [j.name for j in clip.joints]
    position = clip.positions(names)
    shift = position[-1, 0] - position[0, 0]  # the root's travel over the clip
    if in_place:
        assert np.abs(shift).max() < 1e-5
    assert np.abs((position[-1] - shift) - position[0]).max() < 1e-5  # the same pose again
    with pytest.raises(Exception, match="a looped export is whole cycles"):
        export_clip(load_creature("cat"), tmp_path / "x.bvh", seconds=2.0, loop=True)


def test_a_usd_that_cannot_be_written_is_one_line_without_cpp_locations(tmp_path: Path,
                                                                         monkeypatch: pytest.MonkeyPatch) -> None:
    pxr = pytest.importorskip("pxr", reason="usd-core (Pixar's USD) is optional")

    from types import SimpleNamespace

    from app.export import usd

    def refuse(path: str):
        # What pxr raises when it cannot write (here, a folder it may not create files in).
        return pxr.Usd.Stage.CreateNew("/proc/no-such-dir/x.usda")

    modules = list(usd._pxr())
    modules[2] = SimpleNamespace(Stage=SimpleNamespace(CreateNew=refuse))  # Usd, with a stage that cannot be made
    monkeypatch.setattr(usd, "_pxr", lambda: tuple(modules))
    out = gaitlab("export", "dog", "-o", "dog.usda", "--seconds", "0.2", cwd=tmp_path)
    assert out.returncode == 2 and len(out.stderr.strip().splitlines()) == 1, out.stderr
    assert "dog.usda: cannot write USD: Could not create directory '/proc/no-such-dir/'" in out.stderr
    assert out.stderr.rstrip().endswith("x.usda'")
    assert ".cpp" not in out.stderr and "pxrInternal" not in out.stderr and "line " not in out.stderr
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("creature, suffix", [("dog", "usda"), ("spider", "usdc")])
def test_usd_skeleton_animation_reads_back(tmp_path: Path, creature: str, suffix: str) -> None:
    pytest.importorskip("pxr", reason="usd-core (Pixar's USD) is optional")
    from pxr import Usd, UsdGeom, UsdSkel

    from app.export import write_usd

    world = make_world("circle:r=3", "hills:amp=0.08") if creature == "dog" else None
    motion = motion_of(creature, fps=30.0, world=world)
    clip = skeleton_clip(motion)
    path = write_usd(tmp_path / f"{creature}.{suffix}", motion, clip)
    stage = Usd.Stage.Open(str(path))
    assert UsdGeom.GetStageUpAxis(stage) == "Y" and UsdGeom.GetStageMetersPerUnit(stage) == 1.0
    cache = UsdSkel.Cache()
    cache.Populate(UsdSkel.Root(stage.GetPrimAtPath("/Creature")), Usd.PrimDefaultPredicate)
    query = cache.GetSkelQuery(UsdSkel.Skeleton(stage.GetPrimAtPath("/Creature/Skeleton")))
    assert query.GetAnimQuery()
    for t in range(motion.frame_count):
        world_xf = query.ComputeJointWorldTransforms(UsdGeom.XformCache(t))
        position = np.array([[m[3][0], m[3][1], m[3][2]] for m in world_xf])
        assert np.abs(position - clip.world_position[t]).max() < 1e-4
    assert sorted(p.name for p in tmp_path.iterdir()) == [path.name]
    features = UsdGeom.Mesh(stage.GetPrimAtPath("/Creature/Features"))  # the eyes (and a dog's nose)
    assert len(features.GetPointsAttr().Get()) >= 2 * 42
    assert UsdSkel.BindingAPI(features.GetPrim()).GetSkeletonRel().GetTargets() == ["/Creature/Skeleton"]


def test_a_clip_of_no_frames_is_refused_and_nothing_written(tmp_path: Path, monkeypatch) -> None:
    import app.cast as cast_module
    import app.export.clip as export_module
    from app.errors import GaitlabError

    real = cast_module.clip_motion  # every clip is simulated there (a creature's, or a scene's)
    monkeypatch.setattr(cast_module, "clip_motion", lambda *a, **k: (lambda m: (m[0].frames(m[0].frame_count),
                                                                                  m[1]))(real(*a, **k)))
    with pytest.raises(GaitlabError, match="the clip has no frames"):
        export_module.export_clip(load_creature("dog"), tmp_path / "dog.glb")
    assert list(tmp_path.iterdir()) == []


def _accessor(doc, index: int, dtype, width: int) -> np.ndarray:
    """A glb's accessor ``index`` as a (count, width) array of ``dtype``."""
    view = doc.bufferViews[doc.accessors[index].bufferView]
    count = doc.accessors[index].count
    start = view.byteOffset + (doc.accessors[index].byteOffset or 0)
    return np.frombuffer(doc.binary_blob(), dtype=dtype, count=count * width, offset=start).reshape(count, width)


def _skinned(vertices, matrices, vertex_joints, vertex_weights) -> np.ndarray:
    """Linear blend skinning: vertices (V, 3) by joint matrices (J, 4, 4), joints and weights (V, 4)."""
    blended = np.einsum("vk,vkij->vij", vertex_weights, matrices[vertex_joints])
    return np.einsum("vij,vj->vi", blended[:, :3, :3], vertices) + blended[:, :3, 3]


@pytest.mark.parametrize("creature", ["dog", "human", "spider"])
def test_the_glb_carries_the_skinned_body_the_viewer_draws(tmp_path: Path, creature: str) -> None:
    """The file's mesh, skinned by the file's own joints, weights and inverse binds, stands
    where the viewer draws its body (the shared cache's body, skinned per pose), vertex for
    vertex, at the first frame and mid-clip."""
    import pygltflib

    from app.export import write_glb
    from app.export.mesh import export_layout
    from app.render.bodies import pose_body, shared_body_cache

    motion = motion_of(creature, fps=30.0)
    clip = skeleton_clip(motion, export_layout(motion))  # as `gaitlab export` lays it out
    path = write_glb(tmp_path / f"{creature}.glb", motion, clip)
    doc = pygltflib.GLTF2().load(str(path))
    attributes = doc.meshes[0].primitives[0].attributes

    positions = _accessor(doc, attributes.POSITION, np.float32, 3).astype(np.float64)
    weights = _accessor(doc, attributes.WEIGHTS_0, np.float32, 4).astype(np.float64)
    joints = _accessor(doc, attributes.JOINTS_0, np.uint16, 4).astype(np.int64)
    assert np.allclose(weights.sum(axis=1), 1.0, atol=1e-5) and (weights >= 0).all()
    _, world_p, world_r, inverse_bind = glb_world_positions(path, motion.times - motion.times[0], True)
    body = shared_body_cache().get(motion.rig)
    assert np.array_equal(joints, body.joints) and len(positions) == len(body.positions)

    for frame in (0, motion.frame_count // 2):
        world = np.tile(np.eye(4), (len(world_p[frame]), 1, 1))
        world[:, :3, :3], world[:, :3, 3] = world_r[frame], world_p[frame]
        in_file = _skinned(positions, world @ inverse_bind, joints, weights)
        drawn = pose_body(motion.pose(frame), motion.rig, shared_body_cache())
        in_viewer = _skinned(body.positions.astype(np.float64), drawn.skin.astype(np.float64), body.joints,
                            body.weights.astype(np.float64))
        assert np.abs(in_file - in_viewer).max() < 1e-4, (creature, frame)


@pytest.mark.parametrize("creature", ["horse", "dog", "bird"])
def test_the_glb_carries_the_eyes_nose_and_mane_where_the_viewer_draws_them(tmp_path: Path, creature: str) -> None:
    """The features on the skin (eyes, a mammal's nose, a mane) were missing from exports:
    an eyeless horse with a bare neck in Blender. They are the mesh's second primitive,
    the body's own features mesh, skinned by the file's joints exactly where the viewer
    skins them, at the first frame and mid-clip; each eye stays on the head (within 1 cm
    of the skull's eye as the parts place it, every frame)."""
    import pygltflib

    from app.export import write_glb
    from app.export.mesh import export_layout
    from app.render.bodies import pose_body, shared_body_cache
    from app.render.scene import EYE_COLOR, Ell, mane_color, motion_instances

    motion = motion_of(creature, fps=30.0)
    clip = skeleton_clip(motion, export_layout(motion))
    path = write_glb(tmp_path / f"{creature}.glb", motion, clip)
    doc = pygltflib.GLTF2().load(str(path))
    assert len(doc.meshes) == 1 and len(doc.meshes[0].primitives) == 2
    attributes = doc.meshes[0].primitives[1].attributes

    positions = _accessor(doc, attributes.POSITION, np.float32, 3).astype(np.float64)
    colors = _accessor(doc, attributes.COLOR_0, np.float32, 3).astype(np.float64)
    weights = _accessor(doc, attributes.WEIGHTS_0, np.float32, 4).astype(np.float64)
    joints = _accessor(doc, attributes.JOINTS_0, np.uint16, 4).astype(np.int64)
    features = shared_body_cache().get(motion.rig).features
    assert features is not None and len(positions) == len(features.positions)
    count = {"horse": 2 + 14, "dog": 3, "bird": 2}[creature]  # eyes, a nose (not the horse's), the mane
    per = len(positions) // count
    assert per * count == len(positions)
    eye = np.all(np.abs(colors - EYE_COLOR) < 1e-5, axis=1)
    assert eye.sum() == 2 * per and eye[:2 * per].all()
    assert (np.all(np.abs(colors - mane_color(motion.rig)) < 1e-5, axis=1).sum() == 14 * per) == (creature == "horse")
    _, world_p, world_r, inverse_bind = glb_world_positions(path, motion.times - motion.times[0], True)

    parts = motion_instances(motion, show_joints=False)
    for frame in (0, motion.frame_count // 2):
        world = np.tile(np.eye(4), (len(world_p[frame]), 1, 1))
        world[:, :3, :3], world[:, :3, 3] = world_r[frame], world_p[frame]
        in_file = _skinned(positions, world @ inverse_bind, joints, weights)
        drawn = pose_body(motion.pose(frame), motion.rig, shared_body_cache())
        in_viewer = _skinned(features.positions.astype(np.float64), drawn.skin.astype(np.float64), features.joints,
                            features.weights.astype(np.float64))
        assert np.abs(in_file - in_viewer).max() < 1e-4, (creature, frame)
        rows = np.asarray(parts.frame(frame).ellipsoids, np.float64)
        skull_eyes = rows[np.all(np.abs(rows[:, Ell.COLOR] - EYE_COLOR) < 1e-5, axis=1), 0:3]
        eyes = in_file[:2 * per].reshape(2, per, 3).mean(axis=1)
        # Where the parts draw them, or out along the line from the skull onto the skin
        # (the horse's skin, blended over skull, jowl and neck, lies 1 cm out there).
        assert np.linalg.norm(eyes - skull_eyes, axis=1).max() < 0.02, (creature, frame)


def test_a_glb_export_reads_back_in_its_own_colours(tmp_path: Path) -> None:
    """Gaitlab read its own export white: the loader took the material's colour and not the
    vertex colours (COLOR_0) that carry the coat, the hooves and the features. Read back,
    the horse is chestnut with dark hooves, eyes and mane."""
    from app.export import write_glb
    from app.export.mesh import export_layout
    from app.render.scene import EYE_COLOR, HOOF_COLOR, mane_color, srgb_to_linear
    from app.rigged.gltf import load_rigged_model

    motion = motion_of("horse", fps=30.0, cycles=0.5)
    path = write_glb(tmp_path / "horse.glb", motion, skeleton_clip(motion, export_layout(motion)))
    model = load_rigged_model(path)
    display = model.colors  # display RGB: the square roots of the linear colours written
    coat = np.sqrt(srgb_to_linear(motion.rig.look.body_color))
    for color in (coat, np.sqrt(HOOF_COLOR), np.sqrt(EYE_COLOR), np.sqrt(mane_color(motion.rig))):
        assert (np.abs(display - color).max(axis=1) < 0.02).sum() > 20, color
    assert np.median(np.abs(display - coat).max(axis=1)) < 0.15  # mostly coat (lighter below: countershaded)
