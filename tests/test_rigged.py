"""Reading a user's rigged glTF and finding its legs (app/rigged)."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from app.rigged.gltf import RigError, RiggedModel, load_rigged_model
from app.rigged.legs import chain_lengths, find_legs

MODELS = Path(__file__).parent / "data" / "models"


def _skinned_rest(model: RiggedModel) -> np.ndarray:
    """The mesh skinned by the rest pose (V, 3)."""
    skin = model.rest @ model.inverse_bind
    v = np.concatenate([model.positions, np.ones((len(model.positions), 1))], axis=1)
    return np.einsum("vk,vkab,vb->va", model.weights, skin[model.joints], v)[:, :3]


def test_the_fox_is_read_with_its_skeleton_weights_and_texture() -> None:
    fox = load_rigged_model(MODELS / "Fox.glb")
    assert len(fox.names) == 24 and fox.faces.shape == (576, 3)
    assert np.allclose(fox.weights.sum(axis=1), 1.0)
    assert fox.parents[fox.names.index("b_LeftLeg02_016")] == fox.names.index("b_LeftLeg01_015")
    # The rest pose skins the mesh onto itself (the file's bind pose).
    assert np.abs(_skinned_rest(fox) - fox.positions).max() < 1e-3
    # Colours from its texture: a fox's orange, not a flat grey.
    r, g, b = fox.colors.mean(axis=0)
    assert r > g > b and r - b > 0.3


def test_cesium_man_stands_up_through_his_z_up_node() -> None:
    man = load_rigged_model(MODELS / "CesiumMan.glb")
    mesh = _skinned_rest(man)
    assert abs(mesh[:, 1].min()) < 0.01 and 1.4 < np.ptp(mesh[:, 1]) < 1.6  # feet on y = 0, 1.5 m tall, y up
    assert man.rest_points[:, 1].max() < 1.3  # the head joint is high up, not lying along z


def test_legs_are_found_front_first_and_a_fox_walks_on_its_arms() -> None:
    fox = load_rigged_model(MODELS / "Fox.glb")
    legs = find_legs(fox)
    assert legs.arms_as_legs and len(legs.pairs) == 2
    names = [[fox.names[j] for j in chain.joints] for chain in legs.chains]
    assert names[0] == ["b_LeftUpperArm_09", "b_LeftForeArm_010", "b_LeftHand_011"]
    assert names[3] == ["b_RightLeg01_019", "b_RightLeg02_020", "b_RightFoot01_021", "b_RightFoot02_022"]
    assert [c.side for c in legs.chains] == ["L", "R", "L", "R"]
    assert np.allclose(chain_lengths(fox, legs.chains[2]), chain_lengths(fox, legs.chains[3]), rtol=1e-3)
    man = find_legs(load_rigged_model(MODELS / "CesiumMan.glb"))
    assert not man.arms_as_legs and len(man.pairs) == 1
    assert len(man.pairs[0][0].joints) == 4


@pytest.mark.parametrize("names", [
    ("mixamorig:Hips", "mixamorig:LeftUpLeg", "mixamorig:LeftLeg", "mixamorig:LeftFoot", "mixamorig:LeftToeBase",
     "mixamorig:RightUpLeg", "mixamorig:RightLeg", "mixamorig:RightFoot", "mixamorig:RightToeBase"),
    ("mixamorig7:Hips", "mixamorig7:LeftUpLeg", "mixamorig7:LeftLeg", "mixamorig7:LeftFoot", "mixamorig7:LeftToeBase",
     "mixamorig7:RightUpLeg", "mixamorig7:RightLeg", "mixamorig7:RightFoot", "mixamorig7:RightToeBase"),
    ("pelvis", "thigh.L", "shin.L", "foot.L", "toe.L", "thigh.R", "shin.R", "foot.R", "toe.R"),
    ("Hips", "L_Thigh", "L_Calf", "L_Foot", "L_Toe", "R_Thigh", "R_Calf", "R_Foot", "R_Toe"),
    ("Bip01 Pelvis", "Bip01 L Thigh", "Bip01 L Calf", "Bip01 L Foot", "Bip01 L Toe0",
     "Bip01 R Thigh", "Bip01 R Calf", "Bip01 R Foot", "Bip01 R Toe0"),
    ("root", "lfemur", "ltibia", "lfoot", "ltoes", "rfemur", "rtibia", "rfoot", "rtoes"),
])
def test_legs_are_found_by_common_naming_conventions(names: tuple[str, ...]) -> None:
    model = _biped(names)
    legs = find_legs(model)
    assert len(legs.pairs) == 1 and not legs.arms_as_legs
    left, right = legs.pairs[0]
    assert left.joints == (1, 2, 3, 4) and right.joints == (5, 6, 7, 8)


def test_legs_whose_names_say_nothing_are_found_by_the_skeleton_s_shape() -> None:
    """Joints named j0, j1, ...: the legs are the mirrored chains that branch off the trunk
    and run down to the ground, the same chains the names give (the fox's arms, its front
    legs, included)."""
    for name in ("Fox.glb", "CesiumMan.glb"):
        model = load_rigged_model(MODELS / name)
        anonymous = dataclasses.replace(model, names=tuple(f"j{k}" for k in range(len(model.names))))
        by_shape, by_name = find_legs(anonymous), find_legs(model)
        assert [(c.side, c.joints) for c in by_shape.chains] == [(c.side, c.joints) for c in by_name.chains]
    legs = find_legs(_biped(("root", "a", "b", "c", "d", "e", "f", "g", "h")))
    assert [c.joints for c in legs.chains] == [(1, 2, 3, 4), (5, 6, 7, 8)]


def test_a_model_without_legs_or_skin_is_one_clear_line(tmp_path) -> None:
    biped = _biped(("root", "a", "b", "c", "d", "e", "f", "g", "h"))
    one_legged = dataclasses.replace(biped, names=biped.names[:5], parents=biped.parents[:5], rest=biped.rest[:5],
                                     inverse_bind=biped.inverse_bind[:5])
    with pytest.raises(RigError) as err:
        find_legs(one_legged)
    message = str(err.value)
    assert "\n" not in message and "root, a, b" in message and "LeftUpLeg" in message and "--rig" in message
    import trimesh

    plain = tmp_path / "box.glb"
    trimesh.creation.box().export(plain)
    with pytest.raises(RigError, match="no skinned mesh"):
        load_rigged_model(plain)
    broken = tmp_path / "broken.glb"
    broken.write_bytes(b"glTF\x02\x00\x00\x00garbage")
    with pytest.raises(RigError, match="broken.glb: not a readable glTF"):
        load_rigged_model(broken)
    with pytest.raises(RigError, match="no such file"):
        load_rigged_model(tmp_path / "missing.glb")


def _biped(names: tuple[str, ...]) -> RiggedModel:
    """A skeleton of a pelvis and two four-joint legs (pelvis 1 m up), named ``names``."""
    points = np.array([[0, 1.0, 0], [0.1, 0.95, 0], [0.1, 0.5, 0.02], [0.1, 0.08, 0], [0.1, 0.0, 0.12],
                       [-0.1, 0.95, 0], [-0.1, 0.5, 0.02], [-0.1, 0.08, 0], [-0.1, 0.0, 0.12]])
    rest = np.tile(np.eye(4), (len(points), 1, 1))
    rest[:, :3, 3] = points
    none = np.zeros((0, 3))
    return RiggedModel(path=Path("model.glb"), names=names, parents=np.array([-1, 0, 1, 2, 3, 0, 5, 6, 7]),
                       rest=rest, inverse_bind=np.linalg.inv(rest), positions=none, normals=none, colors=none,
                       faces=np.zeros((0, 3), dtype=np.int64), joints=np.zeros((0, 4), dtype=np.int64),
                       weights=np.zeros((0, 4)))


def test_model_dataclass_is_frozen() -> None:
    model = _biped(tuple("abcdefghi"))
    with pytest.raises(dataclasses.FrozenInstanceError):
        model.names = ()  # type: ignore[misc]


def _driven(name: str, world: str, terrain: str = "flat", seconds: float = 3.0):
    from app import build_rig
    from app.kinematics import simulate
    from app.rigged.creature import creature_from_model
    from app.rigged.drive import drive_model, rest_in_metres
    from app.worlds import make_world

    model = load_rigged_model(MODELS / name)
    legs = find_legs(model)
    spec, scale = creature_from_model(model, legs)
    motion = simulate(build_rig(spec), seconds, 60.0, world=make_world(world, terrain))
    return model, legs, scale, motion, drive_model(model, legs, scale, motion), rest_in_metres(model, scale)


def test_a_creature_is_made_with_the_model_s_own_proportions() -> None:
    from app import build_rig
    from app.rigged.creature import creature_from_model

    fox = load_rigged_model(MODELS / "Fox.glb")
    spec, scale = creature_from_model(fox, find_legs(fox))
    assert scale == 0.01  # the fox is modelled in centimetres
    rig = build_rig(spec)
    assert rig.leg_names == ("LF", "RF", "LH", "RH")
    hind = chain_lengths(fox, find_legs(fox).chains[2]) * scale
    assert np.allclose([spec.legs[-1].femur, spec.legs[-1].tibia, spec.legs[-1].metatarsus], hind[:3], atol=1e-4)
    assert abs(spec.body.length - 0.479) < 0.002 and abs(spec.legs[-1].hip_offset - 0.0697) < 0.001
    man = load_rigged_model(MODELS / "CesiumMan.glb")
    spec, scale = creature_from_model(man, find_legs(man))
    assert scale == 1.0 and build_rig(spec).leg_names == ("L", "R")


@pytest.mark.parametrize("name", ["Fox.glb", "CesiumMan.glb"])
def test_the_model_s_skeleton_walks_a_circle_over_hills_with_every_bone_its_length(name: str) -> None:
    """The creature's motion on the model's own skeleton, round a circle over the default
    hills: every bone keeps its rest length, and every planted foot stays put: a leg that
    ends at its ball (the fox's hind legs, the man's) keeps that joint where the
    creature's ball stands; one that ends at its wrist (the fox's fore legs) turns its paw
    about it. They slipped up to 7 mm (the fox's fore paws missed by 2.4 cm: its rigid
    spine cannot stretch as the creature's hips part on a hill)."""
    model, legs, _, motion, world, rest = _driven(name, "circle:r=3", "hills")
    assert world.shape == (motion.frame_count, len(model.names), 4, 4)
    pos = world[:, :, :3, 3]
    for j, p in enumerate(model.parents):
        if p >= 0:
            length = np.linalg.norm(rest[j, :3, 3] - rest[p, :3, 3])
            assert np.abs(np.linalg.norm(pos[:, j] - pos[:, p], axis=-1) - length).max() <= 1e-6 * max(length, 1.0)
    rotations = world[:, :, :3, :3]
    assert np.allclose(rotations @ np.swapaxes(rotations, -1, -2), np.eye(3), atol=1e-9)
    rig = motion.rig
    for leg, chain in enumerate(legs.chains):
        last = chain.joints[-1]
        planted = np.linalg.norm(np.diff(motion.joints[:, leg, 3], axis=0), axis=-1) < 1e-6  # the creature's ball
        assert planted.sum() > 0.2 * motion.frame_count
        if len(chain.joints) >= 4:  # the ball, a joint of the model's
            point = pos[:, last]
        else:  # the paw under the wrist: the creature's ball, carried by the wrist
            lift, length = rig.ankle_lift[leg], rig.metatarsus[leg]
            ball = rest[last, :3, 3] + length * np.array([0.0, -np.sin(lift), np.cos(lift)])
            point = np.einsum("tab,b->ta", world[:, last] @ np.linalg.inv(rest[last]), np.append(ball, 1.0))[:, :3]
        assert np.linalg.norm(point - motion.joints[:, leg, 3], axis=-1)[1:][planted].max() < 1e-6
        assert np.linalg.norm(np.diff(point, axis=0), axis=-1)[planted].max() < 1e-3
    # A biped's arms swing as the creature's: each wrist where the creature's is from its
    # shoulder, seen from the model's own shoulder and turned 8 degrees out from the side
    # (they hung at rest, held out from the body).
    assert len(legs.arms) == (2 if name == "CesiumMan.glb" else 0)
    for a, chain in enumerate(legs.arms):
        shoulder, wrist = pos[:, chain.joints[0]], pos[:, chain.joints[2]]
        have, want = wrist - shoulder, motion.arms[:, a, 2] - motion.arms[:, a, 0]
        assert np.abs(np.linalg.norm(have, axis=-1) - np.linalg.norm(want, axis=-1)).max() < 1e-9
        cos = np.sum(have * want, axis=-1) / np.linalg.norm(have, axis=-1) / np.linalg.norm(want, axis=-1)
        turned = np.degrees(np.arccos(np.clip(cos, -1, 1)))  # 8 about the body's forward axis: less as it swings
        assert (turned > 5.0).all() and (turned < 8.0 + 1e-6).all()
        assert np.ptp(wrist[:, 2] - shoulder[:, 2]) > 0.2  # swung back and forth
        assert (wrist[:, 1] < shoulder[:, 1] - 0.3).all()  # hanging, not held out


def test_a_model_s_feet_keep_their_own_shape_on_the_ground() -> None:
    """A foot turns as the creature's foot turns from standing flat, so the model's own
    foot stays flat on the floor at mid-stance and its toes stay on it as the heel rises:
    over a walk on flat ground the man's lowest vertex stays within a few millimetres of
    the floor (his heels went 5-7 cm into it when his steep foot bone was laid along the
    creature's flatter foot, and his toes 11 cm at toe-off)."""
    from app import build_rig
    from app.kinematics import simulate
    from app.rigged.creature import creature_from_model
    from app.rigged.loaded import load_model

    loaded = load_model(str(MODELS / "CesiumMan.glb"))
    spec, _ = creature_from_model(loaded.model, loaded.legs)
    assert abs(spec.legs[0].toe - 0.151) < 0.002  # the toes the model's ball joint carries
    motion = simulate(build_rig(spec), 2.0, 30.0)
    skin = loaded.skin(motion.joints, motion.root, motion.rig.ankle_lift).astype(np.float64)
    vertices = np.concatenate([loaded.mesh, np.ones((len(loaded.mesh), 1))], axis=1)
    weights, joints = loaded.model.weights, loaded.model.joints
    lowest = [np.einsum("vk,vkab,vb->va", weights, skin[t][joints], vertices)[:, 1].min() for t in range(60)]
    assert min(lowest) > -0.004 and max(lowest) < 0.01


@pytest.mark.gl
def test_render_walks_a_rigged_fox_round_a_circle_over_hills(tmp_path) -> None:
    """``gaitlab render Fox.glb``: the model's own mesh, skinned by its own weights, walks
    the path; its orange fur is in the frames (no preset body drawn instead)."""
    from cli_runner import gaitlab
    from PIL import Image

    out = tmp_path / "fox.png"
    result = gaitlab("render", MODELS / "Fox.glb", "--path", "circle:r=3", "--terrain", "hills", "--time", "1.5",
                     "-o", out, "--size", "320x240")
    assert result.returncode == 0, result.stderr
    image = np.asarray(Image.open(out).convert("RGB")).astype(int)
    orange = (image[..., 0] > 150) & (image[..., 0] - image[..., 2] > 80)
    assert orange.mean() > 0.02


def test_render_refuses_a_model_it_cannot_drive_in_one_line(tmp_path) -> None:
    import trimesh
    from cli_runner import gaitlab

    plain = tmp_path / "box.glb"
    trimesh.creation.box().export(plain)
    result = gaitlab("render", plain, "-o", tmp_path / "box.gif")
    assert result.returncode == 2 and "no skinned mesh" in result.stderr and len(result.stderr.strip().splitlines()) == 1
    assert not (tmp_path / "box.gif").exists()
    # A model's bones and body size are its own: --set on them is refused; its gait is not.
    for key in ("legs.hind.femur=0.3", "body.length=0.8", "legs.fore.hip_offset=0.1"):
        result = gaitlab("render", MODELS / "Fox.glb", "--set", key, "-o", tmp_path / "fox.png", "--size", "160x120")
        assert result.returncode == 2 and "its own" in result.stderr and len(result.stderr.strip().splitlines()) == 1
    assert not (tmp_path / "fox.png").exists()
    assert gaitlab("render", MODELS / "Fox.glb", "--set", "gait.duty_factor=0.7", "-o", tmp_path / "fox.png",
                   "--size", "160x120").returncode == 0


def _animated_world(path: Path, names: tuple[str, ...]) -> np.ndarray:
    """The first animation of the glTF at ``path`` played on its joints: world transforms
    (T, J, 4, 4) in the file's units, joints in the order of ``names``."""
    import pygltflib as gl
    from scipy.spatial.transform import Rotation

    from app.rigged.gltf import _Reader, node_matrix, world_matrices

    gltf = gl.GLTF2().load(str(path))
    reader = _Reader(gltf, path)
    animation = gltf.animations[0]
    tracks: dict[tuple[int, str], np.ndarray] = {}
    for channel in animation.channels:
        sampler = animation.samplers[channel.sampler]
        tracks[(channel.target.node, channel.target.path)] = reader.accessor(sampler.output).astype(np.float64)
    frames = len(next(iter(tracks.values())))
    static = world_matrices(gltf)
    parent = {c: p for p, n in enumerate(gltf.nodes) for c in (n.children or [])}
    by_name = {n.name: i for i, n in enumerate(gltf.nodes)}
    world: dict[int, np.ndarray] = {}

    def of(i: int) -> np.ndarray:
        if i in world:
            return world[i]
        node = gltf.nodes[i]
        local = np.tile(node_matrix(node), (frames, 1, 1))
        if (i, "rotation") in tracks:
            scale = np.array(node.scale or [1.0, 1.0, 1.0])
            local[:, :3, :3] = Rotation.from_quat(tracks[(i, "rotation")]).as_matrix() * scale
            local[:, :3, 3] = tracks[(i, "translation")]
        p = parent.get(i, -1)
        if p >= 0 and (p, "rotation") in tracks:
            above = of(p)  # an animated parent
        else:
            above = np.broadcast_to(static[p] if p >= 0 else np.eye(4), (frames, 4, 4))
        world[i] = above @ local
        return world[i]

    return np.stack([of(by_name[name]) for name in names], axis=1)


def test_export_writes_the_walk_on_the_model_s_own_skeleton(tmp_path) -> None:
    """``gaitlab export Fox.glb -o walked.glb``: the model's own file with the walk as its
    first animation; the same joints, hierarchy and rest pose; played back, its foot bones
    stand where Gaitlab put them (within 1 mm); the Khronos validator finds no error."""
    import json
    import subprocess

    from cli_runner import gaitlab
    from test_export import _validator

    from app.rigged.drive import drive_joints
    from app.rigged.loaded import load_model

    out = tmp_path / "walked.glb"
    result = gaitlab("export", MODELS / "Fox.glb", "--path", "circle:r=3", "--terrain", "hills", "--seconds", "1",
                     "-o", out)
    assert result.returncode == 0, result.stderr
    original, walked = load_rigged_model(MODELS / "Fox.glb"), load_rigged_model(out)
    assert walked.names == original.names and np.array_equal(walked.parents, original.parents)
    assert np.allclose(walked.rest, original.rest, atol=1e-5)
    assert np.allclose(walked.inverse_bind, original.inverse_bind)
    import pygltflib as gl

    animations = gl.GLTF2().load(str(out)).animations
    assert animations[0].name == "gaitlab walk" and len(animations) == 4  # the fox's own three kept after
    # Played back, the foot bones are where Gaitlab's solve put them.
    from app import build_rig
    from app.cast import Actor, cast_motions
    from app.rigged.creature import model_creature
    from app.worlds import make_world

    loaded = load_model(str(MODELS / "Fox.glb"))
    played = _animated_world(out, original.names)[:, :, :3, 3] * loaded.scale

    spec = model_creature(str(MODELS / "Fox.glb"))
    motions, _ = cast_motions((Actor(spec, make_world("circle:r=3", "hills")),), 30.0, 1.0, None, 0.0)
    solved = drive_joints(loaded.model, loaded.legs, loaded.scale, motions[0].joints, motions[0].root,
                          loaded.clearance, motions[0].rig.ankle_lift)[:, :, :3, 3]
    feet = [chain.joints[-1] for chain in loaded.legs.chains]
    assert played.shape == solved.shape
    assert np.abs(played[:, feet] - solved[:, feet]).max() < 1e-3
    assert build_rig(spec).model.endswith("Fox.glb")
    command = _validator()
    report = json.loads(subprocess.run([*command, str(out)], capture_output=True, text=True, timeout=120).stdout)
    assert report.get("errors") == 0, report


def test_a_rig_map_names_the_legs_of_a_model_whose_names_do_not_say(tmp_path) -> None:
    """``--rig map.toml`` for joints named anything: the legs it lists are driven; a map that
    names a joint the model has not, lists a leg out of order or unpaired, or is given for
    a creature that is not a model, is one line and exit status 2 (nothing written)."""
    from cli_runner import gaitlab

    from app.rigged.legs import legs_from_map

    fox = load_rigged_model(MODELS / "Fox.glb")
    mapping = {"legs": {"LF": ["b_LeftUpperArm_09", "b_LeftForeArm_010", "b_LeftHand_011"],
                        "RF": ["b_RightUpperArm_06", "b_RightForeArm_07", "b_RightHand_08"],
                        "LH": ["b_LeftLeg01_015", "b_LeftLeg02_016", "b_LeftFoot01_017", "b_LeftFoot02_018"],
                        "RH": ["b_RightLeg01_019", "b_RightLeg02_020", "b_RightFoot01_021", "b_RightFoot02_022"]}}
    assert legs_from_map(fox, mapping, "map.toml").chains == find_legs(fox).chains
    good = tmp_path / "map.toml"
    lines = ["[legs]"] + [f"{k} = {v!r}".replace("'", '"') for k, v in mapping["legs"].items()]
    good.write_text("\n".join(lines) + "\n")
    result = gaitlab("render", MODELS / "Fox.glb", "--rig", good, "--time", "0.5", "-o", tmp_path / "fox.png",
                     "--size", "160x120")
    assert result.returncode == 0, result.stderr
    cases = {
        '[legs]\nLF = ["b_LeftUpperArm_09", "b_Elbow", "b_LeftHand_011"]\nRF = ["a", "b", "c"]\n': "names 'b_Elbow'",
        '[legs]\nLH = ["b_LeftFoot02_018", "b_LeftFoot01_017", "b_LeftLeg02_016"]\n'
        'RH = ["b_RightLeg01_019", "b_RightLeg02_020", "b_RightFoot01_021"]\n': "does not hang below",
        '[legs]\nLH = ["b_LeftLeg01_015", "b_LeftLeg02_016", "b_LeftFoot01_017"]\n': "in pairs",
        '[legz]\nLH = []\n': "give a [legs] table",
        '[legs]\nLF = ["b_LeftUpperArm_09", "b_LeftForeArm_010", "b_LeftHand_011"]\n'
        'RF = ["b_RightUpperArm_06", "b_RightForeArm_07", "b_RightHand_08"]\n'
        'LH = ["b_LeftLeg01_015", "b_LeftLeg02_016", "b_LeftFoot01_017"]\n'
        'RH = ["b_RightLeg01_019", "b_RightLeg02_020", "b_RightFoot01_021"]\n'
        '[arms]\nL = ["b_LeftUpperArm_09", "b_LeftForeArm_010", "b_LeftHand_011"]\n': "is for a biped",
        # left and right swapped: driven, the legs crossed under the body
        '[legs]\nLF = ["b_RightUpperArm_06", "b_RightForeArm_07", "b_RightHand_08"]\n'
        'RF = ["b_LeftUpperArm_09", "b_LeftForeArm_010", "b_LeftHand_011"]\n'
        'LH = ["b_LeftLeg01_015", "b_LeftLeg02_016", "b_LeftFoot01_017"]\n'
        'RH = ["b_RightLeg01_019", "b_RightLeg02_020", "b_RightFoot01_021"]\n':
            "legs.LF ('b_RightUpperArm_06') is on the model's right and legs.RF ('b_LeftUpperArm_09') on its left",
    }
    for text, expected in cases.items():
        bad = tmp_path / "bad.toml"
        bad.write_text(text)
        result = gaitlab("render", MODELS / "Fox.glb", "--rig", bad, "-o", tmp_path / "bad.gif")
        assert result.returncode == 2 and expected in result.stderr, (text, result.stderr)
        assert len(result.stderr.strip().splitlines()) == 1 and "bad.toml" in result.stderr
        assert not (tmp_path / "bad.gif").exists()
    result = gaitlab("render", "dog", "--rig", good, "-o", tmp_path / "dog.gif")
    assert result.returncode == 2 and "--rig" in result.stderr
    # A biped's map may name its arms too: they swing.
    man = load_rigged_model(MODELS / "CesiumMan.glb")
    named = find_legs(man)
    arms = {"L": [man.names[j] for j in named.arms[0].joints], "R": [man.names[j] for j in named.arms[1].joints]}
    legs = {side: [man.names[j] for j in chain.joints] for side, chain in zip(("L", "R"), named.chains)}
    mapped = legs_from_map(man, {"legs": legs, "arms": arms}, "man.toml")
    assert mapped.arms == named.arms and mapped.chains == named.chains
    with pytest.raises(RigError, match="man.toml: arms.L: give 3 joint names"):
        legs_from_map(man, {"legs": legs, "arms": {"L": arms["L"][:2], "R": arms["R"]}}, "man.toml")
    with pytest.raises(RigError, match="man.toml: arms.L .* is on the model's right .* swap their joint lists"):
        legs_from_map(man, {"legs": legs, "arms": {"L": arms["R"], "R": arms["L"]}}, "man.toml")
    # A later command without --rig goes by the joint names again.
    assert gaitlab("render", MODELS / "Fox.glb", "--time", "0.5", "-o", tmp_path / "again.png",
                   "--size", "160x120").returncode == 0


def test_a_driven_fox_s_paws_rest_on_the_ground_not_in_it() -> None:
    """The model's feet stand on their soles: its last foot joints sit above the sole (a
    fox's hind toes 1.1 cm, its fore legs end at the wrist with the paw below), so over a
    walk the lowest vertex of the mesh stays within a few millimetres of the ground (it
    sank 2.5 cm when the joints were set on the ground)."""
    from app import build_rig
    from app.kinematics import simulate
    from app.rigged.creature import creature_from_model
    from app.rigged.loaded import load_model

    loaded = load_model(str(MODELS / "Fox.glb"))
    spec, _ = creature_from_model(loaded.model, loaded.legs)
    motion = simulate(build_rig(spec), 2.0, 30.0)
    skin = loaded.skin(motion.joints, motion.root, motion.rig.ankle_lift).astype(np.float64)
    vertices = np.concatenate([loaded.mesh, np.ones((len(loaded.mesh), 1))], axis=1)
    weights, joints = loaded.model.weights, loaded.model.joints
    lowest = [np.einsum("vk,vkab,vb->va", weights, skin[t][joints], vertices)[:, 1].min() for t in range(0, 60, 5)]
    assert min(lowest) > -0.006 and max(lowest) < 0.01


@pytest.mark.parametrize("name", ["Fox.glb", "CesiumMan.glb"])
def test_a_herd_of_a_model_walks_each_on_its_own_skeleton(name: str) -> None:
    """A herd of a rigged model (it was refused): every animal the model's own size, its
    skeleton driven from its legs as the herd sets them down on the hills and locks them,
    all animals in one call; every bone keeps its length and every foot's ball stands
    where the herd put it."""
    from app import build_rig
    from app.kinematics.herd import Herd
    from app.render.herd import HerdInstances
    from app.rigged.creature import model_creature
    from app.rigged.loaded import load_model
    from app.worlds import make_world

    loaded = load_model(str(MODELS / name))
    rig = build_rig(model_creature(str(MODELS / name)))
    herd = Herd(rig, 5)
    assert np.all(herd.size == 1.0)
    rows = HerdInstances(herd)
    hills = make_world("straight", "hills").terrain.height
    bind = np.concatenate([loaded.bind[:, :, 3][:, :3], np.ones((len(loaded.bind), 1))], axis=1)
    rest = np.linalg.norm(loaded.bind[1:, :3, 3] - loaded.bind[loaded.model.parents[1:], :3, 3], axis=-1)
    leader = np.zeros(2)
    balls = [c for c in range(len(loaded.legs.chains)) if len(loaded.legs.chains[c].joints) >= 4]
    for _ in range(30):
        leader = leader + np.array([0.0, herd.cycle_speed / 30.0])
        herd.step(1.0 / 30.0, leader, 0.0, ground_height=hills)
        scene = rows.frame(herd, hills)
        assert len(scene.bodies) == 5 and all(b.body is scene.bodies[0].body for b in scene.bodies)
        legs = herd.legs(hills)[0]  # (N, L, 5, 3)
        for k, body in enumerate(scene.bodies):
            pos = np.einsum("jab,jb->ja", body.skin.astype(np.float64), bind)[:, :3]
            bones = np.linalg.norm(pos[1:] - pos[loaded.model.parents[1:]], axis=-1)
            parented = loaded.model.parents[1:] >= 0
            assert np.abs(bones - rest)[parented].max() < 1e-5  # float32 skinning matrices
            for leg in balls:
                ball = legs[k, leg, 3] + np.array([0.0, loaded.clearance[leg], 0.0])
                assert np.linalg.norm(pos[loaded.legs.chains[leg].joints[-1]] - ball) < 1e-4


def test_front_legs_under_shoulders_are_one_pair_not_two() -> None:
    """``Shoulder_L -> FrontLeg_L -> ...``: the shoulder chain holds the front leg; the legs
    are two pairs, not three."""
    names = ("Hips", "Shoulder_L", "FrontLeg_L", "FrontShin_L", "FrontFoot_L", "Shoulder_R", "FrontLeg_R",
             "FrontShin_R", "FrontFoot_R", "BackLeg_L", "BackShin_L", "BackFoot_L", "BackToe_L", "BackLeg_R",
             "BackShin_R", "BackFoot_R", "BackToe_R")
    parents = np.array([-1, 0, 1, 2, 3, 0, 5, 6, 7, 0, 9, 10, 11, 0, 13, 14, 15])
    points = np.array([[0, 0.5, 0], [0.05, 0.5, 0.3], [0.08, 0.45, 0.3], [0.08, 0.25, 0.3], [0.08, 0.02, 0.3],
                       [-0.05, 0.5, 0.3], [-0.08, 0.45, 0.3], [-0.08, 0.25, 0.3], [-0.08, 0.02, 0.3],
                       [0.08, 0.45, -0.3], [0.08, 0.25, -0.28], [0.08, 0.08, -0.32], [0.08, 0.0, -0.28],
                       [-0.08, 0.45, -0.3], [-0.08, 0.25, -0.28], [-0.08, 0.08, -0.32], [-0.08, 0.0, -0.28]])
    rest = np.tile(np.eye(4), (len(points), 1, 1))
    rest[:, :3, 3] = points
    none = np.zeros((0, 3))
    model = RiggedModel(path=Path("quad.glb"), names=names, parents=parents, rest=rest,
                        inverse_bind=np.linalg.inv(rest), positions=none, normals=none, colors=none,
                        faces=np.zeros((0, 3), dtype=np.int64), joints=np.zeros((0, 4), dtype=np.int64),
                        weights=np.zeros((0, 4)))
    legs = find_legs(model)
    assert len(legs.pairs) == 2
    assert [model.names[c.joints[0]] for c in legs.chains] == ["FrontLeg_L", "FrontLeg_R", "BackLeg_L", "BackLeg_R"]


def test_the_viewer_opens_a_model_from_its_file_field_and_greys_its_bones(tmp_path) -> None:
    """The File panel loads a .glb as it loads a creature file: the model's creature, its
    bone lengths marked as the model's own (the panel greys their sliders); a model that
    cannot be driven is one error line and the creature shown stays."""
    from app.spec import load_creature
    from app.ui.state import ViewerState

    state = ViewerState(load_creature("dog"))
    assert not state.bones_from_model
    assert state.load(str(MODELS / "Fox.glb"))
    assert state.spec.name == "Fox" and state.bones_from_model and state.error is None
    toe = state.spec.leg("hind").toe
    assert state.set_leg_type("hind", "plantigrade")  # the ankle lift changes; the model's toes stay
    assert state.spec.leg("hind").toe == toe and state.spec.leg("hind").ankle_lift < 20
    assert state.recent and str(MODELS / "Fox.glb") in state.recent[0]
    broken = tmp_path / "broken.glb"
    broken.write_bytes(b"not a glTF at all")
    assert not state.load(str(broken))
    assert state.spec.name == "Fox" and state.error is not None and "broken.glb" in state.error
    assert len(state.error.splitlines()) == 1


def test_a_scene_file_walks_rigged_models_beside_each_other(tmp_path) -> None:
    """Models go in scene files as presets do: the fox and the man, each on its own line."""
    from cli_runner import gaitlab

    for name in ("Fox.glb", "CesiumMan.glb"):
        (tmp_path / name).write_bytes((MODELS / name).read_bytes())
    (tmp_path / "models.toml").write_text(
        'name = "models"\n'
        '[paths.a]\nkind = "waypoints"\npoints = [[0, 0], [0, 40]]\n'
        '[paths.b]\nkind = "waypoints"\npoints = [[1.2, 0], [1.2, 40]]\n'
        '[[creatures]]\ncreature = "Fox.glb"\npath = "a"\n'
        '[[creatures]]\ncreature = "CesiumMan.glb"\npath = "b"\nherd = 2\n')
    result = gaitlab("render", tmp_path / "models.toml", "--time", "1", "-o", tmp_path / "models.png",
                     "--size", "320x240", cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    # A scene's own settings cannot stretch a model's bones either.
    (tmp_path / "stretched.toml").write_text('name = "stretched"\n[[creatures]]\ncreature = "Fox.glb"\n'
                                             '[creatures.set]\n"legs.hind.femur" = 0.3\n')
    bad = gaitlab("render", tmp_path / "stretched.toml", "-o", tmp_path / "bad.png", cwd=tmp_path)
    assert bad.returncode == 2 and "its own" in bad.stderr and len(bad.stderr.strip().splitlines()) == 1
    assert "Fox" in result.stdout and "CesiumMan" in result.stdout
    image = np.asarray(Image.open(tmp_path / "models.png").convert("RGB")).astype(int)
    orange = (image[..., 0] > 150) & (image[..., 2] < 0.5 * image[..., 0]) & (image[..., 1] < 0.75 * image[..., 0])
    assert orange.sum() > 200  # the fox's coat


def test_a_leg_s_type_comes_from_its_foot() -> None:
    """A heel on the ground makes a plantigrade leg (the man's ankle moves the vertices of
    his heel, down to the sole); an ankle high above the sole a digitigrade one (the fox's
    hock, 6.6 cm up)."""
    from app.rigged.creature import creature_from_model, foot_kind
    from app.rigged.loaded import load_model
    from app.spec import leg_type

    kinds = {}
    for name in ("Fox.glb", "CesiumMan.glb"):
        loaded = load_model(str(MODELS / name))
        chain = loaded.legs.chains[-1]
        length = float(np.linalg.norm(loaded.bind[chain.joints[3], :3, 3] - loaded.bind[chain.joints[2], :3, 3]))
        kinds[name] = foot_kind(loaded.model, loaded.mesh, loaded.bind[:, :3, 3], chain.joints[2],
                                float(loaded.mesh[:, 1].min()), length)
        spec, _ = creature_from_model(loaded.model, loaded.legs)
        assert leg_type(spec.legs[-1].ankle_lift) == kinds[name]
    assert kinds == {"Fox.glb": "digitigrade", "CesiumMan.glb": "plantigrade"}
    # A hock that owns the whole metatarsus down to the pads is still digitigrade: the pads
    # lie ahead of it, and a heel behind.
    fox = load_model(str(MODELS / "Fox.glb"))
    hock, paw = fox.legs.chains[-1].joints[2:4]
    joints = fox.model.joints.copy()
    joints[joints == paw] = hock
    moved = dataclasses.replace(fox.model, joints=joints)
    length = float(np.linalg.norm(fox.bind[paw, :3, 3] - fox.bind[hock, :3, 3]))
    assert foot_kind(moved, fox.mesh, fox.bind[:, :3, 3], hock, float(fox.mesh[:, 1].min()), length) == "digitigrade"


def test_a_model_s_neck_and_tail_turn_as_the_creature_s() -> None:
    """The fox's neck (b_Neck_04 to its head) and tail (b_Tail01..03) are found by their
    names; driven, each tail and neck bone points where its rest direction, carried by
    the body, turns by the creature's own nod, follow-through and sway (the head turns
    whole as the creature's head does), so the model keeps its own neck and tail shape and
    moves them as the creature moves its own: the tail tip swings by centimetres against
    the hips (it was rigid)."""
    from app.kinematics.appendages import heading_frames
    from app.rigged.drive import motion_turns

    model, legs, _, motion, world, rest = _driven("Fox.glb", "circle:r=3", "hills")
    assert [model.names[j] for j in legs.neck] == ["b_Neck_04", "b_Head_05"]
    assert [model.names[j] for j in legs.tail] == ["b_Tail01_012", "b_Tail02_013", "b_Tail03_014"]
    turns, heading = motion_turns(motion), heading_frames(motion.root)

    def in_world(turn: np.ndarray) -> np.ndarray:
        return heading @ turn @ np.swapaxes(heading, -1, -2)

    hip = int(model.parents[legs.tail[0]])
    carried = world[:, hip, :3, :3] @ rest[hip, :3, :3].T
    k_of = {0: 1, 1: 4}  # the creature's tail segment at each bone's middle (7 segments, by rest length)
    for i, k in k_of.items():
        j, child = legs.tail[i], legs.tail[i + 1]
        have = world[:, child, :3, 3] - world[:, j, :3, 3]
        want = in_world(turns.tail[:, k]) @ carried @ (rest[child, :3, 3] - rest[j, :3, 3])
        assert np.abs(have - want).max() < 1e-9
    neck, head = legs.neck
    spine = int(model.parents[neck])
    carried = world[:, spine, :3, :3] @ rest[spine, :3, :3].T
    assert np.abs(world[:, head, :3, :3] - in_world(turns.head) @ carried @ rest[head, :3, :3]).max() < 1e-9
    tip = np.einsum("tji,tj->ti", world[:, hip, :3, :3], world[:, legs.tail[-1], :3, 3] - world[:, hip, :3, 3])
    assert np.ptp(tip, axis=0).max() > 0.02


def test_creatures_keys_reads_a_model_through_its_rig_map(tmp_path) -> None:
    """``creatures --keys MODEL.glb --rig MAP.toml`` reads the legs as render would (the map
    was not an option there, so a model whose names do not say could not be listed)."""
    from cli_runner import gaitlab

    bad = tmp_path / "bad.toml"
    bad.write_text('[legs]\nLH = ["b_LeftLeg01_015", "b_LeftLeg02_016", "b_LeftFoot01_017"]\n')
    result = gaitlab("creatures", "--keys", MODELS / "Fox.glb", "--rig", bad)
    assert result.returncode == 2 and "bad.toml" in result.stderr and "in pairs" in result.stderr, result.stderr
    assert result.stdout == ""  # nothing listed before the error
    result = gaitlab("creatures", "--keys", MODELS / "Fox.glb")
    assert result.returncode == 0 and "gait.phases.RH" in result.stdout, result.stderr
    result = gaitlab("creatures", "--rig", bad)
    assert result.returncode == 2 and "give --keys" in result.stderr


def test_a_rig_map_may_name_the_neck_and_tail() -> None:
    """``[neck] joints = [...]`` and ``[tail] joints = [...]`` name them (a model whose
    names do not say); a map that names a joint the model has not, or gives them another
    shape, is one line."""
    from app.rigged.legs import legs_from_map

    fox = load_rigged_model(MODELS / "Fox.glb")
    found = find_legs(fox)
    legs = {"LF": ["b_LeftUpperArm_09", "b_LeftForeArm_010", "b_LeftHand_011"],
            "RF": ["b_RightUpperArm_06", "b_RightForeArm_07", "b_RightHand_08"],
            "LH": ["b_LeftLeg01_015", "b_LeftLeg02_016", "b_LeftFoot01_017", "b_LeftFoot02_018"],
            "RH": ["b_RightLeg01_019", "b_RightLeg02_020", "b_RightFoot01_021", "b_RightFoot02_022"]}
    mapped = legs_from_map(fox, {"legs": legs, "neck": {"joints": ["b_Neck_04", "b_Head_05"]},
                                 "tail": {"joints": ["b_Tail01_012", "b_Tail02_013", "b_Tail03_014"]}}, "fox.toml")
    assert (mapped.neck, mapped.tail) == (found.neck, found.tail)
    assert legs_from_map(fox, {"legs": legs}, "fox.toml").tail == ()  # a map without them leaves them carried
    for table, expected in (({"neck": {"joints": ["b_Neck_04", "b_Snout"]}}, "neck.joints names 'b_Snout'"),
                            ({"tail": {"joints": ["b_Tail03_014", "b_Tail01_012"]}}, "does not hang below"),
                            ({"tail": ["b_Tail01_012"]}, "[tail] has one key, joints"),
                            ({"tail": {"joints": ["b_Tail01_012"]}}, "tail.joints: give 2 or more joint names"),
                            ({"tail": {"joints": ["b_LeftLeg02_016", "b_LeftFoot01_017"]}},
                             "joint 'b_LeftLeg02_016' is in both legs.LH and tail.joints"),
                            ({"legs": {**legs, "RF": legs["LF"]}}, "is in both legs.LF and legs.RF")):
        with pytest.raises(RigError) as caught:
            legs_from_map(fox, {"legs": legs, **table}, "fox.toml")
        assert expected in str(caught.value) and str(caught.value).startswith("fox.toml: ")


@pytest.mark.parametrize("texture", ["30000", "10000", "garbage"])
def test_a_model_whose_texture_is_a_bomb_or_no_image_is_one_clear_line(tmp_path: Path, texture: str) -> None:
    """The base colour texture's declared size is checked before it is decoded (Pillow's
    own refusal and its warning never show), and bytes that are no image say so."""
    import base64

    import pygltflib
    from cli_runner import gaitlab
    from test_world_cli import _png

    side = int(texture) if texture.isdigit() else 0
    data = _png(side, side, rows=20) if side else b"not an image at all"
    gltf = pygltflib.GLTF2().load(str(MODELS / "Fox.glb"))
    (image,) = gltf.images
    image.bufferView, image.mimeType = None, None
    image.uri = "data:image/png;base64," + base64.b64encode(data).decode()
    model = tmp_path / "fox.gltf"
    gltf.convert_buffers(pygltflib.BufferFormat.DATAURI)
    gltf.save(str(model))
    with pytest.raises(RigError) as refused:
        load_rigged_model(model)
    assert ("may have at most 67,108,864 pixels" if side else "not an image Gaitlab can read") in str(refused.value)
    result = gaitlab("render", model, "-o", tmp_path / "fox.png", "--size", "160x120")
    assert result.returncode == 2 and len(result.stderr.strip().splitlines()) == 1, result.stderr
    assert not (tmp_path / "fox.png").exists()


def test_a_model_whose_texture_file_is_missing_loads_plain_and_says_so(tmp_path: Path) -> None:
    """A texture named by file that is not there: the model loads in its material's
    colour, and the command and the viewer's message line say which file was missing."""
    import pygltflib
    from cli_runner import gaitlab

    from app.spec import load_creature
    from app.ui.state import ViewerState

    gltf = pygltflib.GLTF2().load(str(MODELS / "Fox.glb"))
    (image,) = gltf.images
    image.bufferView, image.mimeType, image.uri = None, None, "fur.png"
    model = tmp_path / "fox.gltf"
    gltf.convert_buffers(pygltflib.BufferFormat.DATAURI)
    gltf.save(str(model))
    loaded = load_rigged_model(model)
    assert np.ptp(loaded.colors, axis=0).max() == 0.0  # one plain colour (the fox's texture has many)
    (note,) = loaded.notes
    assert "its texture fur.png is missing" in note and str(tmp_path / "fur.png") in note
    result = gaitlab("render", model, "-o", tmp_path / "fox.png", "--size", "160x120")
    assert result.returncode == 0, result.stderr
    assert f"note: {model}: its texture fur.png is missing" in result.stderr
    quiet = gaitlab("render", model, "-o", tmp_path / "fox.png", "--size", "160x120", "-q")
    assert quiet.returncode == 0 and quiet.stderr == "", quiet.stderr
    state = ViewerState(load_creature("dog"))
    assert state.load(str(model)) and "note: its texture fur.png is missing" in state.status


def test_export_of_a_model_writes_a_glb_by_default(tmp_path: Path) -> None:
    """With no -o, a rigged model's walk goes onto the model (MODEL.glb): a BVH default was refused."""
    from cli_runner import gaitlab

    result = gaitlab("export", MODELS / "Fox.glb", "--cycles", "1", "-q", cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    assert [p.name for p in tmp_path.iterdir()] == ["Fox.glb"]
