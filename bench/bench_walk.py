"""The cost of the animator's walk (issue 9) in the frame path: one live pose per frame
(what the viewer pays) and a whole clip (what render and analyze pay), for creatures
without the new features (dog, horse: the foot roll, arms and key poses are off) and with
them (human, bird, theropod).

    python bench/bench_walk.py                   # this tree
    python bench/bench_walk.py --old DIR         # also another checkout, runs alternated

Prints medians; these machines are shared and noisy: read the ratios, not single runs.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
from pathlib import Path

CHILD = r"""
import json, sys, time
import numpy as np
from app import build_rig, load_creature
from app.kinematics.live import LiveMotion
from app.kinematics.motion import simulate
names = sys.argv[1].split(",")
out = {}
for name in names:
    try:
        rig = build_rig(load_creature(name))
    except Exception:
        continue
    live = LiveMotion(rig)
    for _ in range(30):
        live.step(1 / 60)
        live.pose()
    frames = []
    for _ in range(300):
        t0 = time.perf_counter()
        live.step(1 / 60)
        live.pose()
        frames.append(time.perf_counter() - t0)
    simulate(rig, 1.0, 60.0)
    clips = []
    for _ in range(5):
        t0 = time.perf_counter()
        simulate(rig, 10.0, 60.0)
        clips.append(time.perf_counter() - t0)
    out[name] = (float(np.median(frames)) * 1e3, float(np.median(clips)))
print(json.dumps(out))
"""


def run(tree: Path, names: list[str]) -> dict:
    env = {**os.environ, "PYTHONPATH": str(tree)}
    result = subprocess.run([sys.executable, "-c", CHILD, ",".join(names)], capture_output=True, text=True, env=env,
                            cwd=tree, timeout=600, check=True)
    return json.loads(result.stdout)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--old", type=Path, help="another Gaitlab checkout to compare with (runs alternated)")
    parser.add_argument("--repeats", type=int, default=3)
    ns = parser.parse_args()
    here = Path(__file__).resolve().parents[1]
    names = ["dog", "horse", "human", "bird", "theropod"]
    new_runs, old_runs = [], []
    for _ in range(ns.repeats):
        new_runs.append(run(here, names))
        if ns.old is not None:
            old_runs.append(run(ns.old, names))

    def med(runs, name, k):
        values = [r[name][k] for r in runs if name in r]
        return statistics.median(values) if values else None

    print(f"{'creature':10} {'live pose (ms)':>15} {'10 s clip at 60 fps (s)':>24}" +
          (f" {'old pose':>9} {'old clip':>9} {'pose x':>7} {'clip x':>7}" if old_runs else ""))
    for name in names:
        pose, clip = med(new_runs, name, 0), med(new_runs, name, 1)
        line = f"{name:10} {pose:15.3f} {clip:24.3f}"
        if old_runs:
            old_pose, old_clip = med(old_runs, name, 0), med(old_runs, name, 1)
            if old_pose is None:
                line += f" {'-':>9} {'-':>9}"
            else:
                line += f" {old_pose:9.3f} {old_clip:9.3f} {pose / old_pose:7.2f} {clip / old_clip:7.2f}"
        print(line)


if __name__ == "__main__":
    main()
