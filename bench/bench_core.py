"""Gaitlab core benchmarks: pose solving, headless rendering, GIF recording.

    python bench/bench_core.py            # full run (about a minute)
    python bench/bench_core.py --quick    # fewer repeats

Prints a table of medians over repeats (these machines are shared and noisy: read the
medians and the ratios, not single runs). Goals (2-core llvmpipe machine):
batch pose solving >= 30x a per-leg Python loop and >= 1,000,000 leg-solves/s;
640x480 render + readback >= 150 frames/s; the 4 s 480x360 dog GIF under 5 s wall.
"""

from __future__ import annotations

import argparse
import os
import platform
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from timing import median_time

from app import (
    build_rig,
    load_creature,
    simulate,
)
from app.kinematics.leg import solve_legs
from app.kinematics.leg_scalar import solve_leg

UP = np.array([0.0, 1.0, 0.0])
FWD = np.array([0.0, 0.0, 1.0])


def leg_inputs(frames: int):
    """Hips and targets of the dog walking: (frames, 4, 3) each, plus toe curl (frames, 4)."""
    motion = simulate(load_creature("dog"), seconds=frames / 60.0, fps=60.0)
    return motion.joints[:, :, 0], motion.joints[:, :, 3], np.zeros(motion.contact.shape), motion.rig


def bench_pose(repeats: int) -> list[tuple[str, str]]:
    rows = []
    frames = 25_000
    hips, targets, curl, rig = leg_inputs(frames)
    kw = dict(femur=rig.femur, tibia=rig.tibia, metatarsus=rig.metatarsus, toe=rig.toe, ankle_lift=rig.ankle_lift,
              l_max=rig.l_max, l_rest=rig.l_rest, l_min=rig.l_min, knee_sign=rig.knee_sign)
    batch = median_time(lambda: solve_legs(hips, targets, FWD, UP, curl, **kw), repeats)
    batch_rate = frames * 4 / batch

    loop_frames = 1_000
    h_list, t_list = hips[:loop_frames].tolist(), targets[:loop_frames].tolist()
    params = [(rig.femur[i], rig.tibia[i], rig.metatarsus[i], rig.toe[i], rig.ankle_lift[i], rig.l_max[i],
               rig.l_rest[i], rig.l_min[i], rig.knee_sign[i]) for i in range(4)]

    def loop() -> None:
        for f in range(loop_frames):
            for leg in range(4):
                solve_leg(tuple(h_list[f][leg]), tuple(t_list[f][leg]), (0.0, 0.0, 1.0), (0.0, 1.0, 0.0), 0.0,
                          *params[leg])

    scalar = median_time(loop, max(3, repeats // 2))
    loop_rate = loop_frames * 4 / scalar
    rows.append(("leg IK, batch over frames (numpy)", f"{batch_rate:,.0f} leg-solves/s"))
    rows.append(("leg IK, per-leg Python loop", f"{loop_rate:,.0f} leg-solves/s"))
    rows.append(("  batch / loop", f"{batch_rate / loop_rate:.0f}x  (goal >= 30x, >= 1,000,000/s)"))

    seconds = 60.0
    sim = median_time(lambda: simulate(load_creature("dog"), seconds=seconds, fps=60.0), max(3, repeats // 2))
    rows.append(("simulate() whole creature, 60 s at 60 fps", f"{seconds * 60 / sim:,.0f} frames/s"))
    return rows


def bench_render(repeats: int) -> list[tuple[str, str]]:
    from app.kinematics.clip import clip_motion
    from app.render.clip import ClipRenderer
    from app.render.framing import clip_camera
    from app.render.options import RenderOptions, ViewSettings

    rows = []
    size = (640, 480)
    motion, _ = clip_motion(build_rig(load_creature("dog")), 60.0, seconds=2.0)
    n = 60
    for antialias in ("off", "fxaa", "msaa"):
        view = ViewSettings(size=size, antialias=antialias)
        camera = clip_camera(motion, view)
        with ClipRenderer(size, antialias) as renderer:
            options = RenderOptions()
            t = median_time(lambda r=renderer, c=camera, o=options: [r.frame(motion, i, c, o) for i in range(n)], repeats)
            label = {"off": "no antialiasing", "fxaa": "FXAA", "msaa": "MSAA 4x"}[antialias]
            rows.append((f"render + readback 640x480, {label}", f"{n / t:,.0f} frames/s "
                         f"({t / n * 1000:.2f} ms)"))
            if antialias == "off":
                target = renderer.target

                def clear_read(target=target) -> None:
                    for _ in range(n):
                        target.fbo.use()
                        target.fbo.clear(0.5, 0.5, 0.5, 1.0)
                        target.read()

                floor = median_time(clear_read, repeats)
                rows.append(("  floor: clear + readback only", f"{n / floor:,.0f} frames/s ({floor / n * 1000:.2f} ms)"))
    return rows


def bench_gif(repeats: int) -> list[tuple[str, str]]:
    exe = Path(sys.executable).with_name("gaitlab")
    cmd = [str(exe) if exe.exists() else "gaitlab", "render", "dog", "-o", "x.gif", "--seconds", "4", "--fps", "25",
           "--size", "480x360"]
    with tempfile.TemporaryDirectory() as tmp:
        def run() -> None:
            subprocess.run(cmd, cwd=tmp, check=True, capture_output=True)

        t = median_time(run, max(3, repeats // 2))
        size = (Path(tmp) / "x.gif").stat().st_size
    return [("gaitlab render dog -o x.gif --seconds 4 --fps 25 --size 480x360",
             f"{t:.2f} s wall, {size / 1024:.0f} KiB (goal < 5 s)")]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--quick", action="store_true", help="fewer repeats")
    parser.add_argument("--only", choices=("pose", "render", "gif"), help="run one group")
    args = parser.parse_args()
    repeats = 3 if args.quick else 7
    print(f"# Gaitlab benchmarks — {platform.processor() or platform.machine()}, {os.cpu_count()} cores, "
          f"Python {platform.python_version()}, numpy {np.__version__}; medians of {repeats} runs")
    groups = {"pose": bench_pose, "render": bench_render, "gif": bench_gif}
    rows = []
    for name, fn in groups.items():
        if args.only in (None, name):
            rows += fn(repeats)
    width = max(len(r[0]) for r in rows)
    for label, value in rows:
        print(f"{label:<{width}}  {value}")


if __name__ == "__main__":
    main()
