"""Herds: kinematics per frame for 1, 10 and 100 dogs, and the viewer's frame-time split.

    python bench/bench_herd.py              # kinematics, then the viewer (needs Xvfb) at 1280x720
    python bench/bench_herd.py --no-viewer  # kinematics only
    python bench/bench_herd.py --old DIR    # also one dog and 100 in another checkout's viewer, same run
    python bench/bench_herd.py --ui         # the viewer with its UI shown (the sidebar and panels)

Kinematics is one step of the herd's steering and clocks, every animal's leg joints and
every animal's instance rows (what the renderer draws), all vectorised across animals.
The viewer runs ``gaitlab view dog --herd N`` with the UI hidden (``--ui``: shown) and no vsync on a private
Xvfb display and prints its own split (simulate / draw scene / draw UI / swap). The same
run measures an EGL clear + readback of the same size, the floor any frame pays on this
machine's software renderer, and reports the viewer's frame rate as a fraction of it.
Medians of repeated runs; the machine is shared, so compare ratios.
"""

from __future__ import annotations

import argparse
import os
import platform
import re
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from app import build_rig, load_creature
from app.kinematics.herd import Herd
from app.render.herd import HerdInstances

SIZES = (1, 10, 100)


def kinematics(frames: int = 300) -> None:
    from app.worlds import make_world

    rig = build_rig(load_creature("dog"))
    hills = make_world("straight", "hills").terrain.height
    for ground, where in ((None, "flat ground"), (hills, "the default hills (legs set down on the ground)")):
        _kinematics(rig, frames, ground, where)


def _kinematics(rig, frames: int, ground, where: str) -> None:
    print(f"kinematics per frame on {where} (steering, clocks, joints, instance rows), median of", frames, "frames:")
    for n in SIZES:
        herd = Herd(rig, n)
        rows = HerdInstances(herd)
        leader = np.zeros(2)
        dt = 1.0 / 60.0
        times = {"step": [], "joints": [], "instances": []}
        for _ in range(frames):
            leader = leader + np.array([0.0, herd.cycle_speed * dt])
            t0 = time.perf_counter()
            herd.step(dt, leader, 0.0)
            t1 = time.perf_counter()
            herd.joints(ground)
            t2 = time.perf_counter()
            rows.frame(herd, ground)
            t3 = time.perf_counter()
            times["step"].append(t1 - t0)
            times["joints"].append(t2 - t1)
            times["instances"].append(t3 - t2)
        parts = {k: statistics.median(v) * 1e3 for k, v in times.items()}
        print(f"  {n:4d} dogs: total {sum(parts.values()):6.3f} ms  (step {parts['step']:.3f}, joints "
              f"{parts['joints']:.3f}, instances {parts['instances']:.3f})")


def clear_readback_fps(size: tuple[int, int], frames: int = 200) -> float:
    """Frames per second of an EGL clear + full readback at ``size``."""
    import moderngl

    ctx = moderngl.create_standalone_context(backend="egl")
    fbo = ctx.framebuffer([ctx.renderbuffer(size, 4)], ctx.depth_renderbuffer(size))
    fbo.use()
    t0 = time.perf_counter()
    for _ in range(frames):
        fbo.clear(0.8, 0.85, 0.9, 1.0, depth=1.0)
        fbo.read(components=3)
    fps = frames / (time.perf_counter() - t0)
    fbo.release()
    ctx.release()
    return fps


def viewer(size: tuple[int, int], repeats: int, old: Path | None = None, ui: bool = False) -> None:
    if shutil.which("Xvfb") is None:
        print("viewer: skipped (Xvfb is not installed; bash .ci/setup --test installs it)")
        return
    read_fd, write_fd = os.pipe()
    xvfb = subprocess.Popen(["Xvfb", "-displayfd", str(write_fd), "-screen", "0", f"{size[0] + 64}x{size[1] + 64}x24",
                             "-nolisten", "tcp"], pass_fds=(write_fd,), stdout=subprocess.DEVNULL,
                            stderr=subprocess.DEVNULL)
    os.close(write_fd)
    with os.fdopen(read_fd) as pipe:
        display = ":" + pipe.readline().strip()
    env = {**os.environ, "DISPLAY": display, "PYTHONPATH": str(ROOT)}
    pattern = re.compile(r"([\d.]+) fps .*simulate ([\d.]+), draw scene ([\d.]+), draw UI ([\d.]+), "
                         r"swap and rest (-?[\d.]+)")
    try:
        shown = "UI shown" if ui else "UI hidden"
        print(f"viewer at {size[0]}x{size[1]}, {shown}, no vsync (median of {repeats} runs of 240 frames):")
        floor = []
        results: dict[int, list[tuple[float, ...]]] = {n: [] for n in SIZES}
        before: dict[str, list[float]] = {"one": [], "herd": []}
        after: dict[str, list[float]] = {"one": [], "herd": []}  # this tree, the same commands as the other's

        def run(tree: Path, herd: list[str]) -> tuple[float, ...]:
            out = subprocess.run([sys.executable, "-m", "app", "view", "dog", *herd, "--frames", "240", "--no-vsync",
                                  "--report-fps", *([] if ui else ["--hide-ui"]), "--size", f"{size[0]}x{size[1]}"],
                                 env={**env, "PYTHONPATH": str(tree)}, cwd=tmp, capture_output=True, text=True,
                                 timeout=600)
            match = pattern.search(out.stdout + out.stderr)
            if out.returncode != 0 or match is None:
                raise SystemExit(f"viewer {' '.join(herd)} ({tree}) failed (exit status {out.returncode}):\n"
                                 f"{out.stderr[-2000:]}\n{out.stdout[-2000:]}")
            return tuple(float(v) for v in match.groups())

        with tempfile.TemporaryDirectory() as tmp:
            for _ in range(repeats):
                floor.append(clear_readback_fps(size))
                for n in SIZES:
                    results[n].append(run(ROOT, ["--herd", str(n)]))
                if old is not None:
                    for key, herd in (("one", []), ("herd", ["--herd", "100"])):
                        before[key].append(run(old, herd)[0])
                        after[key].append(run(ROOT, herd)[0])
        base = statistics.median(floor)
        for n in SIZES:
            fps, sim, scene, ui_ms, rest = (statistics.median(r[k] for r in results[n]) for k in range(5))
            print(f"  {n:4d} dogs: {fps:6.1f} fps   simulate {sim:6.2f}  draw scene {scene:6.2f}  draw UI {ui_ms:5.2f}  "
                  f"swap and rest {rest:5.2f} ms")
        one = statistics.median(r[0] for r in results[1])
        print(f"EGL clear + readback at {size[0]}x{size[1]}: {base:.1f} fps; one dog in the viewer runs at "
              f"{one / base:.3f} of it")
        if before["one"]:
            fps = {(tree, key): statistics.median(runs[key]) for tree, runs in (("old", before), ("new", after))
                   for key in runs}
            for tree, name in (("old", str(old)), ("new", "this tree")):
                print(f"{name}: gaitlab view dog {fps[tree, 'one']:.1f} fps, --herd 100 {fps[tree, 'herd']:.1f} fps "
                      f"({fps[tree, 'herd'] / fps[tree, 'one']:.3f} of one dog)")
            print(f"one dog: this tree runs {fps['new', 'one'] / fps['old', 'one']:.2f}x the other's frame rate; "
                  f"100 dogs: {fps['new', 'herd'] / fps['old', 'herd']:.2f}x")
    finally:
        xvfb.terminate()
        xvfb.wait(timeout=10)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--no-viewer", action="store_true", help="kinematics only")
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--old", type=Path, help="another Gaitlab checkout: its viewer's frame rates for one dog and 100")
    parser.add_argument("--ui", action="store_true", help="run the viewer with its UI shown")
    ns = parser.parse_args()
    print(f"# herds - {platform.machine()}, {os.cpu_count()} cores, Python {platform.python_version()}")
    kinematics()
    if not ns.no_viewer:
        viewer((1280, 720), ns.repeats, ns.old, ns.ui)


if __name__ == "__main__":
    main()
