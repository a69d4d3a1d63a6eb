"""Gait analysis speed: 10 minutes of 60 fps motion of 4 feet (36,000 frames).

    python bench/bench_analysis.py

Prints the median wall time of the analysis (event detection and metrics) over repeats,
and the time to simulate the clip, on this machine.
"""

from __future__ import annotations

import os
import platform
import statistics
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from app import build_rig, load_creature  # noqa: E402
from app.analysis import analyze_tracks, tracks_from_motion  # noqa: E402
from app.recording import clip_motion  # noqa: E402


def main() -> None:
    repeats = 5
    rig = build_rig(load_creature("dog"))
    t0 = time.perf_counter()
    motion, _ = clip_motion(rig, 60.0, seconds=600.0)
    simulate = time.perf_counter() - t0
    tracks = tracks_from_motion(motion)
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        report = analyze_tracks(tracks)
        times.append(time.perf_counter() - t0)
    steps = sum(len(fe.steps) for fe in report.foot_events)
    print(f"# gait analysis benchmark - {platform.machine()}, {os.cpu_count()} cores, Python {platform.python_version()}")
    print(f"clip                      10 min at 60 fps, 4 feet ({motion.frame_count} frames, {steps} steps found)")
    print(f"simulate the clip         {simulate:.2f} s")
    print(f"analyze (median of {repeats})     {statistics.median(times):.2f} s  "
          f"({motion.frame_count / statistics.median(times):,.0f} frames/s; gait {report.gait_match})")


if __name__ == "__main__":
    main()
