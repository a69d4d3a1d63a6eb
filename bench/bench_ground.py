"""Every preset over the ground the README offers: which are walked, which refused.

    .venv/bin/python bench/bench_ground.py [--seconds 20]

Each creature x {flat, slope 15, default hills, default stairs} x {straight, circle r=3,
figure-eight r=3}: simulated at 30 fps; prints per combination ok / compromised stances /
the refusal, and the totals with the wall time.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from app import build_rig, load_creature
from app.errors import GaitlabError
from app.kinematics.motion import simulate
from app.resources import creatures_dir
from app.worlds import make_world

TERRAINS = ("flat", "slope:angle=15", "hills", "stairs")
PATHS = ("straight", "circle:r=3", "figure-eight:r=3")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seconds", type=float, default=20.0)
    args = parser.parse_args()
    names = sorted(p.stem for p in creatures_dir().glob("*.toml"))
    refused, compromised_runs, runs = [], 0, 0
    start = time.perf_counter()
    for name in names:
        rig = build_rig(load_creature(name))
        for terrain in TERRAINS:
            for path in PATHS:
                runs += 1
                try:
                    motion = simulate(rig, args.seconds, 30.0, world=make_world(path, terrain))
                except GaitlabError as exc:
                    refused.append((name, terrain, path, str(exc)))
                    print(f"  {name:10} {terrain:16} {path:18} REFUSED  {str(exc)[:110]}")
                    continue
                bad = int(motion.compromised.sum()) if motion.compromised is not None else 0
                compromised_runs += bad > 0
                print(f"  {name:10} {terrain:16} {path:18} ok" + (f"  ({bad} compromised foot-frames)" if bad else ""))
    wall = time.perf_counter() - start
    print(f"\n{runs - len(refused)} of {runs} walked ({compromised_runs} with compromised footholds), "
          f"{len(refused)} refused; {args.seconds:g} s each, {wall:.0f} s wall")


if __name__ == "__main__":
    main()
