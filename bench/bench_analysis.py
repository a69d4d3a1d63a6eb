"""Gait analysis speed: 10 minutes of 60 fps motion of 4 feet (36,000 frames).

    python bench/bench_analysis.py                 # this tree
    python bench/bench_analysis.py --old DIR       # this tree against another checkout, in one run

Prints the median wall time of the analysis (event detection and metrics) over repeats,
and the time to simulate the clip, on this machine. With ``--old``, both trees analyse
the same clip (simulated by each) in alternating child processes, and the speed-up is
the ratio of the medians.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import statistics
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def measure(repeats: int) -> dict:
    from app import build_rig, load_creature
    from app.analysis import analyze_tracks, tracks_from_motion
    from app.kinematics.clip import clip_motion

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
    return {"frames": motion.frame_count, "steps": sum(len(fe.steps) for fe in report.foot_events),
            "simulate": simulate, "times": times, "gait": report.gait_match}


def live_measurement() -> None:
    """The viewer's gait monitor: what one frame pays for measuring, in line or in the worker."""
    from app import load_creature
    from app.ui.monitor import GaitMonitor
    from app.ui.state import ViewerState

    for creature in ("dog", "spider", "centipede"):
        state = ViewerState(load_creature(creature))
        state.fine_sampling = True
        monitor = GaitMonitor()
        for _ in range(6 * 60):
            state.advance(1 / 60)
            monitor.record_samples(state.live.rig, state.world, state.take_samples(), state.live.frequency)
        inline = []
        for _ in range(5):
            t0 = time.perf_counter()
            monitor.measure(state.live.time, force=True)
            inline.append(time.perf_counter() - t0)
        sample_costs, measure_costs, reports = [], [], 0
        start = time.perf_counter()
        for frame in range(8 * 60):  # 8 s of 60 fps frames in real time, measuring every 0.5 s in the worker
            state.advance(1 / 60)
            t0 = time.perf_counter()
            monitor.record_samples(state.live.rig, state.world, state.take_samples(), state.live.frequency)
            t1 = time.perf_counter()
            before = monitor.report
            monitor.update(state.live.time)
            t2 = time.perf_counter()
            reports += monitor.report is not before
            if frame >= 180:  # after the worker process has started (about 2 s)
                sample_costs.append(t1 - t0)
                measure_costs.append(t2 - t1)
            time.sleep(max(0.0, start + (frame + 1) / 60 - time.perf_counter()))
        monitor.close()
        print(f"live measurement, {creature:9}  in line {statistics.median(inline) * 1e3:5.1f} ms per measurement; "
              f"in the worker, per frame: hand-over/pick-up max {max(measure_costs) * 1e3:.2f} ms, "
              f"fine sampling median {statistics.median(sample_costs) * 1e3:.2f} ms, max "
              f"{max(sample_costs) * 1e3:.2f} ms ({reports} reports in 8 s)")


def plots_cost() -> None:
    """What the Plots panel adds to a viewer frame's simulation: stepping at 240 Hz and
    solving the samples in one call (the frame's pose is the last sample) against one
    step and one pose a frame, at 60 fps."""
    from app import load_creature
    from app.ui.monitor import GaitMonitor
    from app.ui.state import ViewerState

    for creature in ("dog", "human", "centipede"):
        cost = {}
        for fine in (False, True):
            state = ViewerState(load_creature(creature))
            state.fine_sampling = fine
            monitor = GaitMonitor()
            times = []
            for _ in range(600):
                t0 = time.perf_counter()
                state.advance(1 / 60)
                sampled = monitor.record_samples(state.live.rig, state.world, state.take_samples(),
                                                 state.live.frequency) if fine else None
                _ = sampled.pose(sampled.frame_count - 1) if sampled is not None else state.pose()
                times.append(time.perf_counter() - t0)
            monitor.close()
            cost[fine] = statistics.median(times[60:]) * 1e3
        print(f"simulate per frame, {creature:9}  Plots closed {cost[False]:5.2f} ms, open {cost[True]:5.2f} ms "
              f"(+{cost[True] - cost[False]:.2f} ms)")


def child(tree: Path, repeats: int) -> dict:
    out = subprocess.run([sys.executable, __file__, "--child", "--repeats", str(repeats)], capture_output=True,
                         text=True, env={**os.environ, "PYTHONPATH": str(tree)}, check=True)
    return json.loads(out.stdout)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--old", type=Path, help="another Gaitlab checkout to compare with")
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--child", action="store_true", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.child:
        print(json.dumps(measure(args.repeats)))
        return
    print(f"# gait analysis benchmark - {platform.machine()}, {os.cpu_count()} cores, Python {platform.python_version()}")
    if args.old is None:
        sys.path.insert(0, str(ROOT))
        r = measure(args.repeats)
        median = statistics.median(r["times"])
        print(f"clip                      10 min at 60 fps, 4 feet ({r['frames']} frames, {r['steps']} steps found)")
        print(f"simulate the clip         {r['simulate']:.2f} s")
        print(f"analyze (median of {args.repeats})     {median:.2f} s  ({r['frames'] / median:,.0f} frames/s; "
              f"gait {r['gait']})")
        live_measurement()
        plots_cost()
        return
    old_times, new_times = [], []
    for _ in range(2):  # alternate, so load on the machine drifts over both
        old = child(args.old, args.repeats)
        new = child(ROOT, args.repeats)
        old_times += old["times"]
        new_times += new["times"]
    o, n = statistics.median(old_times), statistics.median(new_times)
    print(f"clip      10 min at 60 fps, 4 feet ({new['frames']} frames; steps found old {old['steps']}, "
          f"new {new['steps']})")
    print(f"old       median {o:.2f} s over {len(old_times)} runs (gait {old['gait']})")
    print(f"new       median {n:.2f} s over {len(new_times)} runs (gait {new['gait']})")
    print(f"speed-up  {o / n:.1f}x")


if __name__ == "__main__":
    main()
