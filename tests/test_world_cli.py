"""Paths, terrains and scenes from the command line and files: parsing, loading, every
bad input (one line, exit 2, nothing written), and the Python API."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from cli_runner import gaitlab
from PIL import Image

from app import simulate
from app.kinematics.path import CirclePath, FigureEightPath, StraightPath, WaypointPath
from app.kinematics.terrain import HeightGrid, HillsTerrain, SlopeTerrain, StairsTerrain
from app.kinematics.world import WorldError
from app.worlds import load_heightmap, load_mesh_terrain, load_scene, parse_path, parse_terrain

ROOT = Path(__file__).parents[1]


def test_path_text_forms() -> None:
    assert isinstance(parse_path("straight"), StraightPath)
    circle = parse_path("circle:r=3,dir=right")
    assert isinstance(circle, CirclePath) and circle.radius == 3 and circle.direction == "right"
    assert isinstance(parse_path("figure-eight:r=2"), FigureEightPath)
    waypoints = parse_path("waypoints:0,0,2,1,4,0")
    assert isinstance(waypoints, WaypointPath) and waypoints.points.shape == (3, 2)
    # Arc length really is arc length, and every path starts at the origin heading +Z.
    for path in (circle, parse_path("figure-eight:r=2"), waypoints):
        s = np.linspace(0.0, min(path.length, 6.0), 3001)
        points, tangents = path.sample(s)
        assert (np.allclose(points[0], 0.0, atol=1e-9) and np.allclose(tangents[0], [0, 1], atol=1e-6)) \
            or isinstance(path, WaypointPath)
        steps = np.linalg.norm(np.diff(points, axis=0), axis=1)
        assert np.allclose(steps, np.diff(s), rtol=1e-3)
        assert np.allclose(np.linalg.norm(tangents, axis=1), 1.0)


def test_terrain_queries_are_vectorised_with_the_documented_shapes() -> None:
    rng = np.random.default_rng(3)
    xz = rng.uniform(-5, 5, size=(1000, 2))
    for text in ("flat", "slope:angle=15,dir=30", "hills:amp=0.2,wavelength=3,seed=2", "stairs:rise=0.1,run=0.3"):
        terrain = parse_terrain(text)
        h, n = terrain.height(xz), terrain.normal(xz)
        assert h.shape == (1000,) and n.shape == (1000, 3)
        assert np.allclose(np.linalg.norm(n, axis=1), 1.0) and np.all(n[:, 1] > 0)
        assert terrain.height(xz.reshape(10, 100, 2)).shape == (10, 100)  # any leading shape
    slope = parse_terrain("slope:angle=15,dir=0")
    assert slope.height(np.array([[0.0, 1.0]]))[0] == pytest.approx(math.tan(math.radians(15)))
    # Hills: the analytic normal is the finite-difference one.
    hills = parse_terrain("hills:amp=0.3,wavelength=2")
    e = 1e-6
    gx = (hills.height(xz + [e, 0]) - hills.height(xz - [e, 0])) / (2 * e)
    gz = (hills.height(xz + [0, e]) - hills.height(xz - [0, e])) / (2 * e)
    expected = np.stack([-gx, np.ones_like(gx), -gz], axis=1)
    expected /= np.linalg.norm(expected, axis=1, keepdims=True)
    assert np.allclose(hills.normal(xz), expected, atol=1e-6)


def test_heightmap_image_becomes_ground(tmp_path: Path) -> None:
    ramp = (np.linspace(0, 65535, 64)[None, :] * np.ones((32, 1))).astype(np.uint16)
    Image.fromarray(ramp).save(tmp_path / "ramp.png")
    grid = load_heightmap(tmp_path / "ramp.png", size=6.3, height=2.0)
    assert isinstance(grid, HeightGrid)
    assert grid.height(np.array([[-3.15, 0.0], [3.15, 0.0], [0.0, 0.0]])) == pytest.approx([0.0, 2.0, 1.0], abs=1e-4)
    n = grid.normal(np.array([[0.0, 0.0]]))[0]
    assert n == pytest.approx(np.array([-2.0 / 6.3, 1.0, 0.0]) / np.linalg.norm([-2.0 / 6.3, 1.0, 0.0]), abs=1e-3)


def _png(width: int, height: int, rows: int) -> bytes:
    """A greyscale PNG that declares width x height pixels but holds only ``rows`` of them."""
    import struct
    import zlib

    def chunk(kind: bytes, data: bytes) -> bytes:
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)

    raw = zlib.compress(b"".join(b"\x00" + bytes(width) for _ in range(rows)), 9)
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 0, 0, 0, 0))
            + chunk(b"IDAT", raw) + chunk(b"IEND", b""))


@pytest.mark.parametrize("side", [30000, 10000, 9000])  # Pillow: refused, warned of, silent
def test_a_heightmap_that_declares_too_many_pixels_is_refused_before_decoding(tmp_path: Path, side: int) -> None:
    bomb = tmp_path / "bomb.png"
    bomb.write_bytes(_png(side, side, rows=50))  # a few KB that would decode to ~1 GB
    assert bomb.stat().st_size < 200_000
    result = gaitlab("render", "dog", "--terrain", f"heightmap:file={bomb}", "-o", tmp_path / "out.png")
    assert result.returncode == 2
    assert "heightmap may have at most" in result.stderr and len(result.stderr.strip().splitlines()) == 1
    assert not (tmp_path / "out.png").exists()


def test_a_height_grid_keeps_four_bytes_a_point_and_gradient_normals() -> None:
    rng = np.random.default_rng(3)
    heights = np.cumsum(rng.normal(0, 0.01, (60, 80)), axis=1)
    grid = HeightGrid(heights, (-2.0, -1.0), (4.0, 3.0))
    assert grid.heights.dtype == np.float32 and grid.heights.nbytes == 60 * 80 * 4
    assert not any(isinstance(v, np.ndarray) and v.size >= heights.size * 3 for v in vars(grid).values())
    # At grid points the normal is np.gradient's (central inside, one-sided at the edges).
    gz, gx = np.gradient(heights.astype(np.float32).astype(np.float64), 3.0 / 59, 4.0 / 79)
    iz, ix = np.meshgrid(np.arange(60), np.arange(80), indexing="ij")
    xz = np.stack([-2.0 + ix * 4.0 / 79, -1.0 + iz * 3.0 / 59], axis=-1).reshape(-1, 2)
    inside = (ix.reshape(-1) < 79) & (iz.reshape(-1) < 59)  # the last row and column sit on a cell's far side
    expected = np.stack([-gx, np.ones_like(gx), -gz], axis=-1).reshape(-1, 3)
    expected /= np.linalg.norm(expected, axis=-1, keepdims=True)
    assert np.allclose(grid.normal(xz)[inside], expected[inside], atol=1e-6)


def test_mesh_file_becomes_a_height_grid(tmp_path: Path) -> None:
    trimesh = pytest.importorskip("trimesh")
    stairs = StairsTerrain(0.1, 0.35, steps=4, start=0.5)
    positions, _, indices = stairs.surface((-1.0, -1.0), (1.0, 3.0), 0.1)
    trimesh.Trimesh(vertices=positions, faces=indices.reshape(-1, 3)).export(tmp_path / "stairs.obj")
    grid = load_mesh_terrain(tmp_path / "stairs.obj", cell=0.02)
    xz = np.random.default_rng(1).uniform([-0.9, -0.9], [0.9, 2.9], size=(2000, 2))
    near_riser = stairs.edge_distance(xz) < 0.03
    assert np.allclose(grid.height(xz)[~near_riser], stairs.height(xz)[~near_riser], atol=1e-6)
    # And a creature climbs it.
    motion = simulate("dog", seconds=4.0, fps=30.0, terrain=f"mesh:file={tmp_path / 'stairs.obj'},cell=0.02")
    assert motion.root[-1, 1, 3] - motion.root[0, 1, 3] > 0.3


def test_the_highest_surface_over_a_grid() -> None:
    """A bridge over a ramp, a wall and a triangle off the grid: each grid point gets the
    highest triangle over it, exactly; in chunks of any size (a triangle bigger than a
    chunk alone, or several together); and 3 km from the origin, where rounding once lost
    the grid's last row and column."""
    from app.worlds import files

    ramp = [[0, 0, 0], [4, 2, 0], [4, 2, 4], [0, 0, 4]]  # y = x / 2 over 0 <= x, z <= 4
    bridge = [[1, 3, 1], [3, 3, 1], [3, 3, 3]]  # y = 3 over the triangle z <= x between 1 and 3
    wall = [[2, 0, 0], [2, 9, 0], [2, 9, 4]]  # stands on edge: no extent seen from above
    far = [[10, 5, 10], [11, 5, 10], [11, 5, 11]]
    vertices = np.array(ramp + bridge + wall + far, dtype=np.float64)
    faces = np.array([[0, 1, 2], [0, 2, 3], [4, 5, 6], [7, 8, 9], [10, 11, 12]])
    xs = np.linspace(0.0, 4.0, 41)
    zs = np.linspace(0.0, 4.0, 33)
    gx, gz = np.meshgrid(xs, zs)
    expected = np.where((gx >= 1) & (gx <= 3) & (gz >= 1) & (gz <= gx + 1e-12), 3.0, gx / 2)
    got = files.highest_surface(vertices, faces, xs, zs, floor=-1.0)
    assert got.shape == (33, 41) and np.allclose(got, expected, atol=1e-12)
    # Beyond every triangle: the floor given. In chunks of a few points: the same heights.
    wide = np.linspace(-2.0, 6.0, 81)
    outside = files.highest_surface(vertices, faces, wide, zs, floor=-1.0)
    assert np.all(outside[:, wide < 0] == -1.0) and np.all(outside[:, wide > 4] == -1.0)
    chunk = files.SURFACE_CHUNK
    try:
        for files.SURFACE_CHUNK in (7, 50, 400):
            assert np.array_equal(files.highest_surface(vertices, faces, wide, zs, floor=-1.0), outside)
    finally:
        files.SURFACE_CHUNK = chunk
    # A square bowl (rim 5 m up) 2968 m from the origin on a 1024-point grid (its far edge was lost).
    off, w = -2968.408, 33.743
    corners = np.array([[off, 5, off], [off + w, 5, off], [off + w, 5, off + w], [off, 5, off + w],
                        [off + w / 2, 0, off + w / 2]])
    sides = np.array([[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]])
    grid = np.linspace(off, off + w, 1024)
    top = files.highest_surface(corners, sides, grid, grid, floor=-1.0)
    assert top.min() > -1.0 and np.allclose(top[[0, -1], :], 5.0) and np.allclose(top[:, [0, -1]], 5.0)


def test_python_api_keeps_the_world() -> None:
    motion = simulate("cat", seconds=1.0, fps=30.0, path="circle:r=1", terrain="hills:amp=0.05")
    assert isinstance(motion.path, CirclePath) and isinstance(motion.terrain, HillsTerrain)
    assert motion.terrain.height(np.zeros((5, 2))).shape == (5,)
    assert motion.terrain.normal(np.zeros((5, 2))).shape == (5, 3)
    assert isinstance(simulate("ant", 0.5, 30.0, terrain=SlopeTerrain(0.1)).terrain, SlopeTerrain)


def test_scene_files_load() -> None:
    for path in sorted((ROOT / "scenes").glob("*.toml")):
        scene = load_scene(path)
        assert scene.creatures, path
    garden = load_scene(ROOT / "scenes" / "garden.toml")
    assert len(garden.creatures) == 2 and isinstance(garden.creatures[0].world.path, WaypointPath)


@pytest.mark.gl
def test_render_travels_and_follows(tmp_path: Path) -> None:
    out = gaitlab("render", "spider", "--path", "circle:r=1.5", "--terrain", "hills:amp=0.05", "-o", "s.gif",
                  "--seconds", "0.8", "--fps", "10", "--size", "96x72", "--msaa", "0", cwd=tmp_path)
    assert out.returncode == 0, out.stderr
    with Image.open(tmp_path / "s.gif") as gif:
        assert gif.n_frames == 8
    out = gaitlab("render", str(ROOT / "scenes" / "hillside.toml"), "-o", "h.png", "--size", "96x72", "-q",
                  cwd=tmp_path)
    assert out.returncode == 0, out.stderr
    image = np.asarray(Image.open(tmp_path / "h.png").convert("RGB"))
    assert image.std() > 10  # a creature and the ground, not an empty frame


@pytest.mark.gl
def test_analyze_reports_speed_slip_and_path_error() -> None:
    out = gaitlab("analyze", "dog", "--path", "circle:r=1.5", "--terrain", "slope:angle=8", "--json")
    assert out.returncode == 0, out.stderr
    import json

    report = json.loads(out.stdout)
    assert report["speed"] > 0.3
    assert all(foot["max_stance_slip"] < 1e-6 for foot in report["feet"])
    assert report["path_error"]["max_body_lengths"] < 0.02
    table = gaitlab("analyze", "ant", "--path", "figure-eight:r=1")
    assert table.returncode == 0 and "path         off by" in table.stdout and "tripod" in table.stdout


BAD_WORLD = {
    "unknown path kind": (["--path", "spiral:r=2"], "unknown kind 'spiral'"),
    "unknown terrain kind": (["--terrain", "lava"], "unknown kind 'lava'"),
    "malformed path": (["--path", "circle:r"], "is not KEY=VALUE"),
    "unknown path key": (["--path", "circle:radious=3"], "unknown key 'radious'"),
    "malformed terrain": (["--terrain", "hills:amp=high"], "amp='high' is not a number"),
    "one waypoint": (["--path", "waypoints:1,2"], "at least two points"),
    "odd waypoints": (["--path", "waypoints:1,2,3"], "x,z pairs"),
    "zero radius": (["--path", "circle:r=0"], "r=0 must be > 0"),
    "negative radius": (["--path", "figure-eight:r=-1"], "must be > 0"),
    "nan radius": (["--path", "circle:r=nan"], "not a finite number"),
    "nan terrain": (["--terrain", "slope:angle=nan"], "not a finite number"),
    "no foothold": (["--terrain", "slope:angle=60"], "steeper than max_slope"),
    "in place on hills": (["--terrain", "hills", "--in-place"], "in place needs flat ground"),
    "missing heightmap": (["--terrain", "heightmap:file=nowhere.png"], "no such file"),
    "huge radius": (["--path", "figure-eight:r=1e300"], "must be <= 10000 m"),
    "path too tight": (["--path", "circle:r=0.01"], "too tight for the dog"),
    "steps out of reach": (["--terrain", "stairs:rise=1,start=0"], "cannot reach its foothold"),
}


@pytest.mark.parametrize("case", list(BAD_WORLD))
def test_bad_world_input_is_one_line_exit_2_nothing_written(tmp_path: Path, case: str) -> None:
    args, expected = BAD_WORLD[case]
    out = gaitlab("render", "dog", *args, "-o", "x.gif", "--seconds", "0.2", cwd=tmp_path)
    assert out.returncode == 2, (case, out.stderr)
    lines = out.stderr.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in out.stderr, out.stderr
    assert expected in lines[0], lines[0]
    assert list(tmp_path.iterdir()) == []


def test_bad_files(tmp_path: Path) -> None:
    (tmp_path / "notimage.png").write_text("this is not a PNG")
    (tmp_path / "empty.obj").write_text("# no faces\nv 0 0 0\nv 1 0 0\n")
    (tmp_path / "scene.toml").write_text('terain = "flat"\n[[creatures]]\ncreature = "dog"\n')
    (tmp_path / "noncreature.toml").write_text('[[creatures]]\ncreature = "dog"\nspeed = -1\n')
    cases = {
        ("--terrain", f"heightmap:file={tmp_path / 'notimage.png'}"): "not an image",
        ("--terrain", f"mesh:file={tmp_path / 'empty.obj'}"): "no faces",
    }
    for args, expected in cases.items():
        out = gaitlab("render", "dog", *args, "-o", "x.gif", cwd=tmp_path)
        assert out.returncode == 2 and expected in out.stderr and len(out.stderr.strip().splitlines()) == 1, \
            out.stderr
    out = gaitlab("render", str(tmp_path / "scene.toml"), "-o", "x.gif", cwd=tmp_path)
    assert out.returncode == 2 and "unknown key 'terain'" in out.stderr and "did you mean 'terrain'" in out.stderr
    out = gaitlab("render", str(tmp_path / "noncreature.toml"), "-o", "x.gif", cwd=tmp_path)
    assert out.returncode == 2 and "speed = -1" in out.stderr
    assert not (tmp_path / "x.gif").exists()
    with pytest.raises(WorldError, match="no faces"):
        load_mesh_terrain(tmp_path / "empty.obj")


def test_every_scene_creature_is_checked(tmp_path: Path) -> None:
    scene = tmp_path / "two.toml"
    scene.write_text('[[creatures]]\ncreature = "dog"\n[[creatures]]\ncreature = "cat"\n'
                     'set = { "legs.hind.femr" = 1 }\n')
    out = gaitlab("render", str(scene), "-o", "x.gif", cwd=tmp_path)
    assert out.returncode == 2 and len(out.stderr.strip().splitlines()) == 1
    assert "did you mean 'legs.hind.femur'" in out.stderr and not (tmp_path / "x.gif").exists()
    (tmp_path / "closed.toml").write_text('[paths.p]\nkind = "waypoints"\npoints = [[0, 0], [1, 1], [2, 0]]\n'
                                          'closed = "yes"\n[[creatures]]\ncreature = "dog"\npath = "p"\n')
    with pytest.raises(WorldError, match="closed = 'yes': expected true or false"):
        load_scene(tmp_path / "closed.toml")


def test_the_viewer_pauses_where_the_ground_offers_no_foothold() -> None:
    from app import load_creature
    from app.ui.state import ViewerState
    from app.worlds import make_world

    state = ViewerState(load_creature("dog"), world=make_world("straight", "hills:amp=0.28,seed=6,max_slope=22"))
    for _ in range(600):
        state.advance(1.0 / 60.0)
        if not state.playing:
            break
    assert not state.playing and state.error is not None and "steeper than max_slope" in state.error
    before = state.live.clock
    state.step_frame()  # still there, still paused, no traceback
    assert state.live.clock == before and not state.playing
    # A path too tight for a newly chosen creature keeps the old one.
    tight = ViewerState(load_creature("cat"), world=make_world("circle:r=0.1"))
    assert tight.load_preset("horse") is False and tight.spec.name == "cat" and "too tight" in tight.error


def test_the_viewer_walks_on_over_uneven_ground_and_says_so() -> None:
    from app import load_creature
    from app.ui.state import ViewerState
    from app.worlds import make_world

    state = ViewerState(load_creature("dog"), world=make_world("straight", "hills:amp=0.02,wavelength=0.3"))
    for _ in range(240):
        state.advance(1.0 / 60.0)
        state.note_pose(state.pose())
    assert state.playing and state.error is None
    assert state.live.compromised_count > 0 and "uneven ground" in (state.status or "")
    assert state.planted_jump_max < 1e-6


def test_gaits_that_do_not_fit_are_refused() -> None:
    out = gaitlab("render", "ant", "--gait", "gallop", "-o", "x.gif")
    assert out.returncode == 2
    assert "is a gait for 2 pairs; this creature has 3 leg pairs: use one of tripod, tetrapod, metachronal" \
        in out.stderr
    listing = gaitlab("creatures")
    assert listing.returncode == 0
    for word in ("ant", "spider", "centipede", "15 leg pairs", "tripod", "metachronal", "for 3 pairs"):
        assert word in listing.stdout


def test_the_kinds_registry_is_what_the_parser_help_and_readme_offer() -> None:
    """One registry of path and terrain kinds (issue 13): every kind and key it declares is
    accepted by the parser, listed by ``render --help`` and in the README's tables; the
    viewer's Terrain panel reads the same table."""
    from app.worlds.kinds import PATH_KINDS, TERRAIN_KINDS

    readme = (ROOT / "README.md").read_text()
    help_text = gaitlab("render", "--help").stdout
    for kind in PATH_KINDS.values():
        assert f"| `{kind.name}` |" in readme and kind.name in help_text
        for key in kind.keys:
            assert f"`{key.name}`" in readme.split(f"| `{kind.name}` |")[1].split("\n")[0], (kind.name, key.name)
    for kind in TERRAIN_KINDS.values():
        row = readme.split(f"| `{kind.name}` |")[1].split("\n")[0]
        assert kind.name in help_text
        for key in kind.keys:
            assert f"`{key.name}`" in row and f"{key.name}=" in help_text, (kind.name, key.name)
        if "file" not in kind.required:
            text = kind.example or kind.name
            assert parse_terrain(text).describe().startswith(kind.name), text
