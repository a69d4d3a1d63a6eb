"""The viewer's Python per frame, without GL: the live motion moved on by one frame and
solved, the skinning matrices and the instances it draws (``Viewer._prepare``).

    python bench/bench_live.py                    # dog, human, horse
    python bench/bench_live.py --old DIR          # and another checkout's, in alternating runs
    python bench/bench_live.py spider --rounds 7

On software GL this Python is the viewer's critical path: the main thread solves the
next frame while the rasteriser's threads draw this one, so every millisecond here is
most of a millisecond of frame time. Each figure is the median of 600 frames in a fresh
process; with ``--old`` the two trees run in turn, ``--rounds`` times, and the ratio is
the median of the rounds' ratios (the machine is shared: read the ratio).
"""

from __future__ import annotations

import argparse
import os
import platform
import re
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

# Run in a child process with the tree to time on its path: prints the median (ms).
_CHILD = """
import statistics, sys, time
from app.spec import load_creature
from app.ui import viewer as V
from app.ui.monitor import GaitMonitor
from app.ui.state import ViewerState
from app.render.bodies import BodyCache
BodyCache.live = lambda self, rig: self.get(rig, "full")  # the full body from the first frame
v = object.__new__(V.Viewer)
v.state = ViewerState(load_creature(sys.argv[1]))
v.state.aspect = 1.5
v.state.frame_view()
v.monitor, v.options, v._press, v._herd_instances = GaitMonitor(), V.ViewerOptions(), None, {}
for _ in range(30):
    v._prepare(1 / 60)
times = []
for _ in range(600):
    t0 = time.perf_counter()
    v._prepare(1 / 60)
    times.append(time.perf_counter() - t0)
v.monitor.close()
print(statistics.median(times) * 1e3)
"""


def frame_ms(tree: Path, creature: str) -> float:
    """Median ms per frame of ``tree``'s viewer Python for ``creature`` (a fresh process)."""
    out = subprocess.run([sys.executable, "-c", _CHILD, creature], env={**os.environ, "PYTHONPATH": str(tree)},
                         cwd=tempfile.gettempdir(),  # not a checkout: "-c" puts the working directory first
                         capture_output=True, text=True, timeout=600)
    match = re.search(r"^([\d.]+)$", out.stdout, re.M)
    if out.returncode != 0 or match is None:
        raise SystemExit(f"{creature} ({tree}) failed (exit status {out.returncode}):\n{out.stderr[-2000:]}")
    return float(match.group(1))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("creatures", nargs="*", default=["dog", "human", "horse"])
    parser.add_argument("--old", type=Path, help="another Gaitlab checkout to time in alternating runs")
    parser.add_argument("--rounds", type=int, default=5)
    ns = parser.parse_args()
    print(f"# viewer Python per frame - {platform.machine()}, {os.cpu_count()} cores, Python {platform.python_version()}")
    for creature in ns.creatures:
        new, old = [], []
        for _ in range(ns.rounds if ns.old else 1):
            if ns.old:
                old.append(frame_ms(ns.old, creature))
            new.append(frame_ms(ROOT, creature))
        line = f"  {creature:10s} {statistics.median(new):6.3f} ms"
        if ns.old:
            ratio = statistics.median(n / o for n, o in zip(new, old))
            line += f"   {ns.old}: {statistics.median(old):6.3f} ms   this tree / that: {ratio:.3f}"
        print(line)


if __name__ == "__main__":
    main()
