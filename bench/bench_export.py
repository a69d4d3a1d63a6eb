"""Export speed: a 10 s clip at 60 fps of each preset as BVH and as glTF (skeleton + file).

    python bench/bench_export.py

Prints, per creature, the median wall time (after a warm-up) of turning the solved clip
into a skeleton and writing the BVH, and the file size. The goal: under 2 s.
"""

from __future__ import annotations

import os
import platform
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from timing import median_time

from app import build_rig, load_creature
from app.export import write_bvh, write_glb
from app.kinematics.clip import clip_motion
from app.kinematics.skeleton import skeleton_clip


def main() -> None:
    print(f"# export benchmark - {platform.machine()}, {os.cpu_count()} cores, Python {platform.python_version()}")
    print("creature    joints  frames   BVH: time    size     glTF: time    size   (medians of 5, skeleton included)")
    with tempfile.TemporaryDirectory() as tmp:
        for creature in ("dog", "horse", "spider", "centipede"):
            motion, _ = clip_motion(build_rig(load_creature(creature)), 60.0, seconds=10.0)
            bvh, glb = Path(tmp) / f"{creature}.bvh", Path(tmp) / f"{creature}.glb"
            t_bvh = median_time(lambda b=bvh, m=motion: write_bvh(b, skeleton_clip(m)), repeats=5)
            t_glb = median_time(lambda g=glb, m=motion: write_glb(g, m, skeleton_clip(m)), repeats=5)
            joints = skeleton_clip(motion).skeleton.count
            print(f"{creature:10}  {joints:6}  {motion.frame_count:6}  {t_bvh:8.3f} s  {bvh.stat().st_size / 2**20:5.1f} MiB"
                  f"  {t_glb:8.3f} s  {glb.stat().st_size / 2**20:5.1f} MiB")


if __name__ == "__main__":
    main()
