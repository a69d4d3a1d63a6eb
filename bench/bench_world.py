"""Gaitlab world benchmarks: travelling over terrain, terrain queries, heightmap loading.

    python bench/bench_world.py            # full run (about half a minute)
    python bench/bench_world.py --quick    # fewer repeats

Prints medians over repeats (these machines are shared and noisy: read the medians and
the ratios, not single runs). Goals (2-core machine, no GPU): 60 s of a dog on hills along
a figure-eight at 60 fps simulates >= 300x faster than real time and costs < 2x the same
gait in place; terrain height + normal queries >= 1,000,000 points/s; a 1024x1024
heightmap loads in < 1 s; a terrain mesh samples onto the finest grid in about a second.
"""

from __future__ import annotations

import argparse
import platform
import sys
import tempfile
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from timing import median_time

from app import build_rig, load_creature
from app.kinematics.motion import simulate
from app.worlds import load_heightmap, make_world, parse_terrain
from app.worlds.files import load_mesh_terrain


def bench_travel(repeats: int) -> list[tuple[str, str]]:
    rows = []
    seconds, fps = 60.0, 60.0
    dog = build_rig(load_creature("dog"))
    in_place = median_time(lambda: simulate(dog, seconds, fps, world=make_world(in_place=True)), repeats)
    world = make_world("figure-eight:r=1.5", "hills:amp=0.1,wavelength=2")
    hills = median_time(lambda: simulate(dog, seconds, fps, world=world), repeats)
    rows.append(("dog walk in place, 60 s at 60 fps", f"{in_place * 1000:.0f} ms ({seconds / in_place:,.0f}x real time)"))
    rows.append(("dog walk on hills along a figure-eight, 60 s at 60 fps",
                 f"{hills * 1000:.0f} ms ({seconds / hills:,.0f}x real time; {hills / in_place:.2f}x in place)"))
    stairs = make_world("straight", "stairs:rise=0.08,run=0.35,steps=40")
    t = median_time(lambda: simulate(dog, seconds, fps, world=stairs), repeats)
    rows.append(("dog walk up 40 stairs, 60 s at 60 fps", f"{t * 1000:.0f} ms ({seconds / t:,.0f}x real time)"))
    centipede = build_rig(load_creature("centipede"))
    small_hills = make_world("figure-eight:r=1.5", "hills:amp=0.015,wavelength=1")  # hills its size
    t = median_time(lambda: simulate(centipede, seconds, fps, world=small_hills), repeats)
    rows.append(("centipede (30 legs) on hills along a figure-eight, 60 s at 60 fps",
                 f"{t * 1000:.0f} ms ({seconds / t:,.0f}x real time)"))
    return rows


def bench_queries(repeats: int) -> list[tuple[str, str]]:
    rows = []
    points = np.random.default_rng(0).uniform(-20, 20, size=(1_000_000, 2))
    with tempfile.TemporaryDirectory() as folder:
        heightmap = Path(folder) / "map.png"
        _write_heightmap(heightmap, 1024)
        load = median_time(lambda: load_heightmap(heightmap, 40.0, 3.0), repeats)
        rows.append(("load a 1024x1024 16-bit heightmap (heights + normals)", f"{load * 1000:.0f} ms"))
        grid = load_heightmap(heightmap, 40.0, 3.0)
        mesh = Path(folder) / "hills.obj"
        faces = _write_mesh(mesh, 120)
        for cell, what in ((0.0, "default grid, 256 across"), (0.019, "finest grid, 1024x1024")):
            t = median_time(lambda cell=cell: load_mesh_terrain(mesh, cell), repeats)
            rows.append((f"load a {faces:,}-face terrain mesh ({what})", f"{t * 1000:.0f} ms"))
    for name, terrain in (("hills", parse_terrain("hills:amp=0.2,wavelength=3")),
                          ("slope", parse_terrain("slope:angle=15")),
                          ("stairs", parse_terrain("stairs:rise=0.1,run=0.3")), ("1024^2 heightmap", grid)):
        t = median_time(lambda terrain=terrain: (terrain.height(points), terrain.normal(points)), repeats)
        rows.append((f"terrain height + normal, 1M points: {name}", f"{points.shape[0] / t / 1e6:.1f} M points/s"))
    return rows


def _write_heightmap(path: Path, size: int) -> None:
    from PIL import Image

    y, x = np.mgrid[0:size, 0:size] / size
    heights = 0.5 + 0.25 * np.sin(6 * x) * np.cos(4 * y) + 0.2 * np.sin(17 * x + 5 * y)
    Image.fromarray((np.clip(heights, 0, 1) * 65535).astype(np.uint16)).save(path)


def _write_mesh(path: Path, n: int) -> int:
    """An n x n grid of hills 20 m across as an OBJ; returns its number of faces."""
    x, z = np.meshgrid(np.linspace(-10, 10, n), np.linspace(-10, 10, n))
    y = 0.3 * np.sin(x) * np.cos(0.7 * z)
    corner = (np.arange(n - 1)[:, None] * n + np.arange(n - 1)[None, :]).ravel() + 1  # OBJ counts from 1
    faces = np.concatenate([np.column_stack([corner, corner + n, corner + 1]),
                            np.column_stack([corner + 1, corner + n, corner + n + 1])])
    lines = [f"v {a:.6f} {b:.6f} {c:.6f}" for a, b, c in zip(x.ravel(), y.ravel(), z.ravel())]
    lines += [f"f {a} {b} {c}" for a, b, c in faces]
    path.write_text("\n".join(lines) + "\n")
    return len(faces)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--quick", action="store_true", help="fewer repeats")
    args = parser.parse_args()
    repeats = 3 if args.quick else 7
    print(f"machine: {platform.machine()}, {platform.python_implementation()} {platform.python_version()}, "
          f"numpy {np.__version__}; median of {repeats} runs")
    rows = bench_travel(repeats) + bench_queries(repeats)
    width = max(len(name) for name, _ in rows)
    for name, value in rows:
        print(f"  {name:<{width}}  {value}")


if __name__ == "__main__":
    main()
