"""Damaged and hostile files a user may give end in one line and exit 2 (or load), with no
warning printed, no hang and nothing left behind (found by an audit with real processes)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from cli_runner import gaitlab
from PIL import Image

from app.rigged.gltf import RigError, load_rigged_model

FOX = Path(__file__).parent / "data" / "models" / "Fox.glb"
RENDER = ("--size", "160x120", "-q")


def _one_line(result, *words: str) -> None:
    assert result.returncode == 2, result.stderr
    assert len(result.stderr.strip().splitlines()) == 1, result.stderr
    for word in words:
        assert word in result.stderr


def _fox_with(tmp_path: Path, change) -> Path:
    import pygltflib

    gltf = pygltflib.GLTF2().load(str(FOX))
    change(gltf)
    out = tmp_path / "fox.glb"
    gltf.save(str(out))
    return out


def test_a_model_whose_nodes_loop_is_refused_not_walked_forever(tmp_path: Path) -> None:
    def loop(gltf) -> None:
        root = gltf.skins[0].joints[0]
        gltf.nodes[root].children = [*(gltf.nodes[root].children or []), root]  # its own child

    with pytest.raises(RigError, match="its own ancestor"):
        load_rigged_model(_fox_with(tmp_path, loop))


@pytest.mark.parametrize("damage", ["vertex index", "accessor count", "nan translation"])
def test_a_damaged_model_is_one_line(tmp_path: Path, damage: str) -> None:
    def change(gltf) -> None:
        prim = next(p for m in gltf.meshes for p in m.primitives)
        if damage == "vertex index":  # a triangle naming a vertex the mesh does not have
            gltf.accessors[prim.indices].max = None
            gltf.buffers[0].uri = None
            data = bytearray(gltf.binary_blob())
            view = gltf.bufferViews[gltf.accessors[prim.indices].bufferView]
            start = (view.byteOffset or 0) + (gltf.accessors[prim.indices].byteOffset or 0)
            data[start:start + 2] = (60000).to_bytes(2, "little")
            gltf.set_binary_blob(bytes(data))
        elif damage == "accessor count":  # more rows than its buffer holds
            gltf.accessors[prim.attributes.POSITION].count = 10**9
        else:  # written as 123456.5, then made NaN in the file's text (JSON has no NaN; Python's reader takes it)
            gltf.nodes[gltf.skins[0].joints[1]].translation = [123456.5, 0.0, 0.0]

    model = _fox_with(tmp_path, change)
    if damage == "nan translation":
        import pygltflib

        gltf = pygltflib.GLTF2().load(str(model))
        gltf.convert_buffers(pygltflib.BufferFormat.DATAURI)
        model = tmp_path / "fox.gltf"
        gltf.save(str(model))
        model.write_text(model.read_text().replace("123456.5", "NaN"))
    with pytest.raises(RigError):
        load_rigged_model(model)
    _one_line(gaitlab("render", model, *RENDER, "-o", tmp_path / "o.png"), str(model))
    assert not (tmp_path / "o.png").exists()


def test_a_float_heightmap_loads_and_palette_pngs_print_no_warning(tmp_path: Path) -> None:
    ramp = np.tile(np.linspace(0.0, 1.0, 64, dtype=np.float32), (48, 1))
    Image.fromarray(ramp, mode="F").save(tmp_path / "float.tiff")
    result = gaitlab("render", "dog", "--terrain", f"heightmap:file={tmp_path / 'float.tiff'},height=0.05",
                     *RENDER, "-o", tmp_path / "a.png")
    assert result.returncode == 0 and not result.stderr, result.stderr
    palette = Image.fromarray(np.arange(64 * 48, dtype=np.uint8).reshape(48, 64) % 4, mode="P")
    palette.putpalette([0, 0, 0, 60, 60, 60, 120, 120, 120, 180, 180, 180])
    palette.info["transparency"] = b"\x00\xff\xff\xff"  # transparency as bytes: Pillow warns on converting it
    palette.save(tmp_path / "pal.png", transparency=b"\x00\xff\xff\xff")
    result = gaitlab("render", "dog", "--terrain", f"heightmap:file={tmp_path / 'pal.png'},height=0.02",
                     *RENDER, "-o", tmp_path / "b.png")
    assert result.returncode == 0 and not result.stderr, result.stderr


def test_a_wall_and_a_far_away_mesh_are_refused_as_terrain(tmp_path: Path) -> None:
    (tmp_path / "wall.obj").write_text("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3\nf 1 3 4\n")
    _one_line(gaitlab("render", "dog", "--terrain", f"mesh:file={tmp_path / 'wall.obj'}", *RENDER, "-o",
                      tmp_path / "o.png"), "spread both ways")
    (tmp_path / "far.obj").write_text("v -1e300 0 -1e300\nv 1e300 0 -1e300\nv 1e300 0 1e300\nf 1 2 3\n")
    _one_line(gaitlab("render", "dog", "--terrain", f"mesh:file={tmp_path / 'far.obj'}", *RENDER, "-o",
                      tmp_path / "o.png"), "must lie within")
    (tmp_path / "ok.obj").write_text("v -3 0 -3\nv 3 0 -3\nv 3 0 3\nv -3 0 3\nf 1 2 3\nf 1 3 4\n")
    result = gaitlab("render", "dog", "--terrain", f"mesh:file={tmp_path / 'ok.obj'},cell=1e-320", *RENDER, "-o",
                     tmp_path / "o.png")
    assert result.returncode == 0 and not result.stderr, result.stderr  # the finest grid it allows


def test_a_mesh_of_large_triangles_stacked_deep_is_refused_before_the_work(tmp_path: Path) -> None:
    """6,000 triangles each over the whole ground: ~390 million point tests (half an hour);
    refused at once, naming the count and the limit. Two layers (a bridge) are fine."""
    layers = 6000
    lines = [f"v {x} {h} {z}" for h in range(layers) for x, z in ((0, 0), (20, 0), (0, 20))]
    lines += [f"f {3 * k + 1} {3 * k + 2} {3 * k + 3}" for k in range(layers)]
    (tmp_path / "deep.obj").write_text("\n".join(lines) + "\n")
    _one_line(gaitlab("render", "dog", "--terrain", f"mesh:file={tmp_path / 'deep.obj'}", *RENDER, "-o",
                      tmp_path / "o.png"), "deep.obj: laying its triangles on the grid takes",
              "at most 268,435,456", "give a coarser cell=")
    assert not (tmp_path / "o.png").exists()


@pytest.mark.parametrize("text", ["ply\nend_header\n", "ply\nformat binary_little_endian 1.0\nelement vertex 3\n"
                                  "property float x\nend_header\n"])
def test_a_damaged_mesh_says_so_in_words_not_an_exception_name(tmp_path: Path, text: str) -> None:
    (tmp_path / "ground.ply").write_text(text)
    result = gaitlab("render", "dog", "--terrain", f"mesh:file={tmp_path / 'ground.ply'}", *RENDER, "-o",
                     tmp_path / "o.png")
    _one_line(result, "ground.ply", "cannot read the mesh: damaged, or not an OBJ, PLY, STL or glTF/GLB file")
    assert "Error" not in result.stderr.split("error:", 1)[1] and "index out of range" not in result.stderr
    assert sorted(p.name for p in tmp_path.iterdir()) == ["ground.ply"]


def test_clips_sampled_impossibly_fast_and_tiny_values_are_one_line(tmp_path: Path) -> None:
    from app.analysis.bvh import MIN_FRAME_TIME

    bvh = tmp_path / "fast.bvh"
    bvh.write_text("HIERARCHY\nROOT hips\n{\n OFFSET 0 0 0\n CHANNELS 3 Xposition Yposition Zposition\n"
                   " End Site\n {\n  OFFSET 0 -1 0\n }\n}\nMOTION\nFrames: 2\nFrame Time: 1e-300\n0 1 0\n0 1 0\n")
    _one_line(gaitlab("analyze", bvh), f"at least {MIN_FRAME_TIME:g}")
    _one_line(gaitlab("render", "dog", "--fps", "1e-300", "-o", tmp_path / "o.gif"), "at least 1")
    _one_line(gaitlab("render", "dog", "--set", "gait.frequency=1e-300", "-o", tmp_path / "o.gif"), "0.05")
    _one_line(gaitlab("render", "dog", "--time", "1e300", "-o", tmp_path / "o.png"), "86400")
    assert not list(tmp_path.glob("o.*"))


def test_a_folder_or_a_device_given_as_a_file_says_what_it_is(tmp_path: Path) -> None:
    (tmp_path / "dir.toml").mkdir()
    _one_line(gaitlab("render", tmp_path / "dir.toml", *RENDER, "-o", tmp_path / "o.png"), "dir.toml: is a folder")
    _one_line(gaitlab("render", "dog", "--terrain", "mesh:file=/dev/zero", *RENDER, "-o", tmp_path / "o.png"),
              "/dev/zero: is not a regular file")
    _one_line(gaitlab("render", "dog", "--terrain", f"heightmap:file={tmp_path}", *RENDER, "-o", tmp_path / "o.png"),
              "is a folder")
    keys = gaitlab("creatures", "--keys", tmp_path / "dir.toml")
    _one_line(keys, "dir.toml: is a folder")
    assert keys.stdout == ""  # the error alone, not the whole listing before it
    assert sorted(p.name for p in tmp_path.iterdir()) == ["dir.toml"]


def test_a_creature_file_saved_with_a_byte_order_mark_loads(tmp_path: Path) -> None:
    dog = (Path(__file__).parents[1] / "creatures" / "dog.toml").read_bytes()
    (tmp_path / "bom.toml").write_bytes(b"\xef\xbb\xbf" + dog)
    result = gaitlab("render", tmp_path / "bom.toml", *RENDER, "-o", tmp_path / "o.png")
    assert result.returncode == 0 and not result.stderr, result.stderr


def test_a_scene_with_a_misspelt_creatures_table_is_read_as_a_scene(tmp_path: Path) -> None:
    """It was read as a creature file: "unknown key 'terrain'; allowed here: ... body"."""
    (tmp_path / "typo.toml").write_text('terrain = "hills"\n[[creature]]\ncreature = "dog"\n')
    _one_line(gaitlab("render", tmp_path / "typo.toml", *RENDER, "-o", tmp_path / "o.png"),
              "unknown key 'creature' (did you mean 'creatures'?)")


def test_a_gait_that_does_not_fit_names_the_option_and_the_scene_s_creature(tmp_path: Path) -> None:
    """It said "--set: gait.preset = 'tripod' ..." though no --set was given, and not which creature."""
    garden = Path(__file__).parents[1] / "scenes" / "garden.toml"
    _one_line(gaitlab("render", garden, "--gait", "tripod", *RENDER, "-o", tmp_path / "o.png"),
              "--gait tripod (centipede): gait.preset = 'tripod' is a gait for 3 pairs")
    _one_line(gaitlab("render", "dog", "--gait", "tripod", *RENDER, "-o", tmp_path / "o.png"),
              "--gait tripod: gait.preset = 'tripod' is a gait for 3 pairs; this creature has 2 leg pairs")
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("table, expected", [
    ('kind = "waypoints"\npoints = [[true, false], [0, 5]]', "expected [[x, z], [x, z], ...], pairs of numbers"),
    ('kind = "waypoints"\npoints = [[0, 0, 5], [3, 4, 7]]', "expected [[x, z], [x, z], ...], pairs of numbers"),
    ('kind = "circle"\nr = "2,dir=right"', "paths.p.r = '2,dir=right': expected a number, or a word or file name without commas"),
    ('kind = "circle:r=2"', "paths.p.kind = 'circle:r=2': expected a name alone"),
])
def test_a_scene_path_table_takes_numbers_and_words_not_spliced_text(tmp_path: Path, table: str,
                                                                      expected: str) -> None:
    """Booleans were read as 1 and 0, three-number points regrouped into other waypoints,
    and text values spliced into the path's own text."""
    (tmp_path / "scene.toml").write_text(f'[paths.p]\n{table}\n[[creatures]]\ncreature = "dog"\npath = "p"\n')
    _one_line(gaitlab("render", tmp_path / "scene.toml", *RENDER, "-o", tmp_path / "o.png"), expected)


def test_two_settings_of_one_thing_on_a_command_line_are_refused(tmp_path: Path) -> None:
    """The later one silently won."""
    _one_line(gaitlab("render", "dog", "--set", "gait.bias=1", "--set", "gait.duty_factor=0.5", *RENDER, "-o",
                      tmp_path / "o.png"), "gait.duty_factor and gait.bias both given: give one")
    _one_line(gaitlab("render", "dog", "--set", "gait.frequency=2", "--frames-per-cycle", "30", *RENDER, "-o",
                      tmp_path / "o.png"), "gait.frequency and --frames-per-cycle both given")
    (tmp_path / "scene.toml").write_text('[[creatures]]\ncreature = "dog"\nset = { "gait.duty_factor" = 0.6, '
                                         '"gait.bias" = 0.3 }\n')
    _one_line(gaitlab("render", tmp_path / "scene.toml", *RENDER, "-o", tmp_path / "o.png"),
              "scene.toml (dog): gait.duty_factor and gait.bias both given")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["scene.toml"]


def test_headings_and_directions_are_bounded(tmp_path: Path) -> None:
    """1e300 degrees was taken (a direction float rounding cannot tell apart)."""
    _one_line(gaitlab("render", "dog", "--path", "straight:heading=1e300", *RENDER, "-o", tmp_path / "o.png"),
              "heading=1e+300 must be <= 3600 deg")
    _one_line(gaitlab("render", "dog", "--terrain", "stairs:dir=-1e300", *RENDER, "-o", tmp_path / "o.png"),
              "dir=-1e+300 must be >= -3600 deg")


def test_a_list_value_is_bounded(tmp_path: Path) -> None:
    """A radius profile of a million numbers was taken (10 s)."""
    profile = "[" + ",".join(["0.1"] * 1000) + "]"
    _one_line(gaitlab("render", "dog", "--set", f"body.radius={profile}", *RENDER, "-o", tmp_path / "o.png"),
              "body.radius: a list of 1,000 numbers; at most 256 are read")


def test_a_scene_s_name_and_description_are_text(tmp_path: Path) -> None:
    (tmp_path / "scene.toml").write_text('name = {a = 1}\n[[creatures]]\ncreature = "dog"\n')
    _one_line(gaitlab("render", tmp_path / "scene.toml", *RENDER, "-o", tmp_path / "o.png"),
              "name = {'a': 1}: expected a text in quotes")
    (tmp_path / "scene.toml").write_text('description = [1, 2]\n[[creatures]]\ncreature = "dog"\n')
    _one_line(gaitlab("render", tmp_path / "scene.toml", *RENDER, "-o", tmp_path / "o.png"),
              "description = [1, 2]: expected a text in quotes")


def test_exporting_a_scene_s_herd_says_only_its_lead_is_written(tmp_path: Path) -> None:
    herd = Path(__file__).parents[1] / "scenes" / "herd.toml"
    result = gaitlab("export", herd, "--seconds", "0.3", "-o", tmp_path / "h.bvh")
    assert result.returncode == 0, result.stderr
    assert "note: the herd of 20 dogs is exported as its lead animal" in result.stderr


@pytest.mark.parametrize("args, expected", [
    (["--crf", "10", "-o", "o.png"], "--crf 10 sets a .mp4's quality, and o.png is a .png"),
    (["--gif-quality", "small", "-o", "o.mp4"], "--gif-quality small sets a .gif's quality, and o.mp4 is a .mp4"),
    (["--side-colors", "-o", "o.png"], "--side-colors colours the parts' legs and arms by side: give it with --body"),
    (["--seconds", "2", "-o", "o.png"], "--seconds 2 sets a clip's length, and o.png is one frame: drop it (--time T"),
    (["--cycles", "3", "-o", "o.png"], "--cycles 3 sets a clip's length, and o.png is one frame"),
    (["--fps", "30", "-o", "o.png"], "--fps 30 sets a clip's frame rate, and o.png is one frame"),
])
def test_an_option_that_would_do_nothing_is_refused(tmp_path: Path, args: list[str], expected: str) -> None:
    """They were ignored, while other conflicts (--msaa with --antialias off) are refused."""
    _one_line(gaitlab("render", "dog", "--size", "160x120", *args, cwd=tmp_path), expected)
    assert list(tmp_path.iterdir()) == []


def test_compare_refuses_a_scene_as_poses_does() -> None:
    """It measured the scene's first creature off the scene's path and ground, unsaid."""
    hillside = Path(__file__).parents[1] / "scenes" / "hillside.toml"
    _one_line(gaitlab("compare", hillside), "hillside.toml: a scene file; compare measures one creature")


def test_empty_names_are_names_not_absent_options() -> None:
    """``--leg ''`` and ``--keys ''`` were taken as not given."""
    _one_line(gaitlab("compare", "human", "--leg", ""), "--leg '': the human has feet L, R")
    _one_line(gaitlab("creatures", "--keys", ""), "unknown creature ''")


def test_numbers_in_a_scene_table_are_read_exactly(tmp_path: Path) -> None:
    """They were written into the terrain's text with six digits: seed 1234567 became 1234570."""
    from app.worlds import load_scene

    (tmp_path / "scene.toml").write_text('terrain = {kind = "hills", amp = 0.123456789, seed = 1234567}\n'
                                         '[[creatures]]\ncreature = "dog"\n')
    hills = load_scene(tmp_path / "scene.toml").terrain
    assert (hills.amplitude, hills.seed) == (0.123456789, 1234567)


def test_a_reference_csv_in_a_windows_code_page_loads_and_binary_is_refused(tmp_path: Path) -> None:
    (tmp_path / "latin.csv").write_bytes(b"# Donn\xe9es (\xb0)\nphase,knee_mean,knee_sd\n0,5,2\n50,10,3\n100,5,2\n")
    result = gaitlab("compare", "human", "--reference", tmp_path / "latin.csv")
    assert result.returncode == 0, result.stderr
    (tmp_path / "bin.csv").write_bytes(bytes(range(256)) * 4)
    _one_line(gaitlab("compare", "human", "--reference", tmp_path / "bin.csv"),
              "bin.csv: not a CSV text file (it holds NUL bytes)")


def test_keys_of_a_scene_file_say_it_is_a_scene() -> None:
    garden = Path(__file__).parents[1] / "scenes" / "garden.toml"
    _one_line(gaitlab("creatures", "--keys", garden), "garden.toml: a scene file; give a creature")
