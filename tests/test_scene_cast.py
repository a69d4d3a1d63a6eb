"""A scene of several creatures filmed and exported together (issue 13): ``render``
films every creature, ``export`` writes one skeleton per creature (glTF, USD) or one
BVH file each, and the viewer's Record and File panels do the same for what it shows."""

from __future__ import annotations

import json
import subprocess
from pathlib import Path

import numpy as np
import pytest
from cli_runner import gaitlab
from PIL import Image

from app import load_creature
from app.cast import Actor, cast_motions
from app.resources import scenes_dir
from app.worlds import make_world

PADDOCK = scenes_dir() / "paddock.toml"


def test_render_of_a_scene_films_every_creature(tmp_path: Path) -> None:
    out = gaitlab("render", str(PADDOCK), "--time", "2", "-o", "paddock.png", "--size", "320x240", cwd=tmp_path)
    assert out.returncode == 0, out.stderr
    assert "horse, dog and cat" in out.stdout and "note:" not in out.stderr
    image = np.asarray(Image.open(tmp_path / "paddock.png").convert("RGB")).astype(np.float64)
    from app.cast import cast_frames_at
    from app.cli import build_parser
    from app.cli.inputs import load_cast
    from app.recording import Recording, RecordRequest
    from app.render.options import RenderOptions, ViewSettings

    cast = load_cast(build_parser().parse_args(["render", str(PADDOCK)]))
    assert [a.spec.name for a in cast] == ["horse", "dog", "cat"]
    view = ViewSettings(size=(320, 240), options=RenderOptions(path=True))  # as render draws a turning path
    job = Recording(RecordRequest(cast=cast, output=tmp_path / "all.png", start=2.0, view=view))
    camera = job.cameras[0]
    full = job._render(0).astype(np.float64)
    assert np.abs(full - image).max() <= 1  # the command's picture is this one
    motions = cast_frames_at(cast, 2.0, 25.0)
    # Drawn without each creature in turn, with the same camera: every one of them has
    # pixels of its own in the picture.
    alone = {}
    for index, name in enumerate(("horse", "dog", "cat")):
        others = [m for i, m in enumerate(motions) if i != index]
        without = job._renderer.frame(others, 0, camera, job.options).astype(np.float64)
        alone[name] = int((np.abs(full - without).max(axis=-1) > 40).sum())
    job.cancel()
    assert all(count > 30 for count in alone.values()), alone


def test_a_scene_clip_moves_every_creature_over_the_same_frames() -> None:
    cast = (Actor(load_creature("dog"), make_world("circle:r=3")), Actor(load_creature("cat"), make_world()),
            Actor(load_creature("ant"), make_world("straight:heading=40")))
    motions, cycles = cast_motions(cast, 30.0, cycles=2.0)
    assert cycles == 2.0 and len({m.frame_count for m in motions}) == 1
    for m in motions:
        assert np.allclose(m.times, motions[0].times)
        assert m.travel[-1] > m.travel[0] + 0.1  # each walks its own way


def test_export_of_a_scene_holds_a_skeleton_per_creature(tmp_path: Path) -> None:
    import pygltflib

    out = gaitlab("export", str(PADDOCK), "--cycles", "1", "-o", "paddock.glb", cwd=tmp_path)
    assert out.returncode == 0, out.stderr
    assert "3 skeletons (horse, dog, cat)" in out.stdout
    doc = pygltflib.GLTF2().load(str(tmp_path / "paddock.glb"))
    assert len(doc.skins) == 3 and len(doc.meshes) == 3
    prefixes = {doc.nodes[skin.joints[0]].name.split(":")[0] for skin in doc.skins}
    assert prefixes == {"horse", "dog", "cat"}
    joint_nodes = [j for skin in doc.skins for j in skin.joints]
    assert len(joint_nodes) == len(set(joint_nodes))  # no joint shared between skeletons
    animated = {c.target.node for c in doc.animations[0].channels}
    assert set(joint_nodes) <= animated
    from test_export import _validator

    command = _validator()
    report = json.loads(subprocess.run([*command, str(tmp_path / "paddock.glb")], capture_output=True, text=True,
                                       timeout=120).stdout)
    assert report.get("errors") == 0, report


def test_export_of_a_scene_as_bvh_writes_one_file_per_creature(tmp_path: Path) -> None:
    from app.analysis.bvh import read_bvh

    out = gaitlab("export", str(scenes_dir() / "garden.toml"), "--cycles", "1", "-o", "garden.bvh", cwd=tmp_path)
    assert out.returncode == 0, out.stderr
    assert "one file per creature" in out.stdout
    assert sorted(p.name for p in tmp_path.iterdir()) == ["garden-ant.bvh", "garden-centipede.bvh"]
    ant, centipede = (read_bvh(tmp_path / f"garden-{name}.bvh") for name in ("ant", "centipede"))
    assert ant.frames.shape[0] == centipede.frames.shape[0] > 5  # the same frames, the ant's cycle long
    assert len(centipede.joints) > len(ant.joints)  # each its own skeleton


def test_export_of_a_scene_as_usd_has_a_skel_root_each(tmp_path: Path) -> None:
    pxr = pytest.importorskip("pxr")
    out = gaitlab("export", str(PADDOCK), "--cycles", "1", "-o", "paddock.usda", cwd=tmp_path)
    assert out.returncode == 0, out.stderr
    stage = pxr.Usd.Stage.Open(str(tmp_path / "paddock.usda"))
    roots = [p for p in stage.Traverse() if p.IsA(pxr.UsdSkel.Root)]
    assert sorted(p.GetName() for p in roots) == ["cat", "dog", "horse"]


def test_the_record_panel_records_every_creature_the_view_shows(tmp_path: Path) -> None:
    from app.cli import build_parser
    from app.cli.inputs import load_cast
    from app.ui.state import ViewerState

    lead, *others = load_cast(build_parser().parse_args(["view", str(PADDOCK)]))
    state = ViewerState(lead.spec, world=lead.world)
    for actor in others:
        assert state.add_creature(actor.spec, actor.world)
    assert state.select(1)  # the dog in the panels: it leads the recording
    request = state.record_request()
    assert [a.spec.name for a in request.cast] == ["dog", "horse", "cat"]
    state.record.folder, state.record.unit, state.record.length = str(tmp_path), "cycles", 0.5
    state.record.export_format = "glb"
    assert state.export(), state.error
    import pygltflib

    assert len(pygltflib.GLTF2().load(str(tmp_path / "dog.glb")).skins) == 3
