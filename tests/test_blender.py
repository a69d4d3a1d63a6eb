"""Exports in a real client: Blender (``bpy``, Blender as a Python module) imports each
preset's glTF and its bones stand where Gaitlab's joints do, frame by frame.

``bpy`` is large and pins its own numpy, so it usually lives in a Python of its own: set
``GAITLAB_BLENDER_PYTHON`` to that interpreter (``python -m venv /opt/blender-py &&
/opt/blender-py/bin/pip install bpy``), or install ``bpy`` beside Gaitlab. Without either
the test is skipped, saying so."""

from __future__ import annotations

import importlib.util
import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from app import build_rig, load_creature
from app.export import write_glb
from app.export.mesh import export_layout
from app.kinematics.clip import clip_motion
from app.kinematics.skeleton import skeleton_clip
from app.resources import preset_creature_names

SCRIPT = Path(__file__).parent / "data" / "blender_bones.py"
FPS = 30


def _blender_python() -> str:
    given = os.environ.get("GAITLAB_BLENDER_PYTHON")
    if given:
        if not Path(given).exists():
            pytest.fail(f"GAITLAB_BLENDER_PYTHON={given}: no such interpreter")
        return given
    if importlib.util.find_spec("bpy") is not None:
        return sys.executable
    pytest.skip("bpy (Blender as a Python module) is not installed: set GAITLAB_BLENDER_PYTHON to a Python "
                "that has it to check the glTF exports in Blender")


def test_blender_imports_every_preset_with_its_bones_on_gaitlab_s_joints_and_its_skinned_body(tmp_path: Path) -> None:
    python = _blender_python()
    clips = {}
    for name in preset_creature_names():
        motion, _ = clip_motion(build_rig(load_creature(name)), float(FPS), cycles=1.0)
        clip = skeleton_clip(motion, export_layout(motion))  # as `gaitlab export` writes it
        path = write_glb(tmp_path / f"{name}.glb", motion, clip)
        clips[str(path)] = clip
    out = subprocess.run([python, str(SCRIPT), str(FPS), *clips], capture_output=True, text=True, timeout=600)
    assert out.returncode == 0, out.stderr[-2000:]
    line = next(text for text in out.stdout.splitlines() if text.startswith("BONES "))
    found = json.loads(line[len("BONES "):])
    for path, clip in clips.items():
        bones = found[path]
        names = list(clip.skeleton.names)
        assert sorted(bones["names"]) == sorted(names), Path(path).stem
        order = [bones["names"].index(n) for n in names]
        heads = np.asarray(bones["frames"])[:, order]  # (frames, joints, 3)
        assert heads.shape == clip.world_position.shape, Path(path).stem
        error = np.abs(heads - clip.world_position).max()
        assert error < 1e-3, f"{Path(path).stem}: bones {1000 * error:.2f} mm from Gaitlab's joints"
        body = [mesh for mesh in bones["meshes"] if mesh["skinned"]]  # the smooth body, on the armature
        assert len(body) == 1 and body[0]["vertices"] > 500 and body[0]["groups"] > 1, (Path(path).stem, bones["meshes"])


def test_blender_plays_a_rigged_model_s_export_with_its_feet_where_gaitlab_put_them(tmp_path: Path) -> None:
    """``gaitlab export Fox.glb``: Blender imports the model with the walk, and the foot
    bones stand where Gaitlab's solve put them (within 1 mm, in the model's units of 1 cm)."""
    python = _blender_python()
    from cli_runner import gaitlab

    from app.cast import Actor, cast_motions
    from app.rigged.creature import model_creature
    from app.rigged.drive import drive_joints
    from app.rigged.loaded import load_model
    from app.worlds import make_world

    model_path = Path(__file__).parent / "data" / "models" / "Fox.glb"
    out = tmp_path / "walked.glb"
    result = gaitlab("export", model_path, "--path", "circle:r=3", "--seconds", "1", "--fps", str(FPS), "-o", out)
    assert result.returncode == 0, result.stderr
    loaded = load_model(str(model_path))
    motions, _ = cast_motions((Actor(model_creature(str(model_path)), make_world("circle:r=3")),), float(FPS),
                              1.0, None, 0.0)
    solved = drive_joints(loaded.model, loaded.legs, loaded.scale, motions[0].joints, motions[0].root,
                          loaded.clearance, motions[0].rig.ankle_lift)
    feet = [loaded.model.names[chain.joints[-1]] for chain in loaded.legs.chains]
    blender = subprocess.run([python, str(SCRIPT), str(FPS), str(out)], capture_output=True, text=True, timeout=600)
    assert blender.returncode == 0, blender.stderr[-2000:]
    line = next(text for text in blender.stdout.splitlines() if text.startswith("BONES "))
    bones = json.loads(line[len("BONES "):])[str(out)]
    heads = np.asarray(bones["frames"])  # (frames, bones, 3) in the file's units
    frames = min(len(heads), len(solved))
    for foot in feet:
        k, j = bones["names"].index(foot), loaded.model.names.index(foot)
        error = np.abs(heads[:frames, k] * loaded.scale - solved[:frames, j, :3, 3]).max()
        assert error < 1e-3, f"{foot}: {1000 * error:.2f} mm from Gaitlab's"
