"""How fast ``gaitlab`` starts: ``--version`` and ``--help`` against a bare ``python -c pass``,
median wall time over repeated runs (issue 13's goal: --version well under 0.4 s).

    .venv/bin/python bench/bench_startup.py [--runs 20] [--old DIR]

``--old DIR`` also times another checkout's ``python -m app --version`` (run from DIR),
in the same sitting.
"""

from __future__ import annotations

import argparse
import os
import platform
import statistics
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def median_seconds(command: list[str], runs: int, cwd: Path) -> float:
    times = []
    for _ in range(runs):
        start = time.perf_counter()
        subprocess.run(command, cwd=cwd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, check=True,
                       env={**os.environ, "PYTHONPATH": str(cwd)})
        times.append(time.perf_counter() - start)
    return statistics.median(times)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--runs", type=int, default=20)
    parser.add_argument("--old", type=Path, help="another checkout to time as well")
    args = parser.parse_args()
    print(f"# start-up, median of {args.runs} runs - {platform.machine()}, {os.cpu_count()} cores, "
          f"Python {platform.python_version()}")
    rows = [("python -c pass", [sys.executable, "-c", "pass"], ROOT),
            ("gaitlab --version", [sys.executable, "-m", "app", "--version"], ROOT),
            ("gaitlab --help", [sys.executable, "-m", "app", "--help"], ROOT),
            ("gaitlab render --help", [sys.executable, "-m", "app", "render", "--help"], ROOT)]
    if args.old is not None:
        rows.append((f"old: gaitlab --version ({args.old})", [sys.executable, "-m", "app", "--version"], args.old))
    base = None
    for name, command, cwd in rows:
        seconds = median_seconds(command, args.runs, cwd)
        base = base or seconds
        print(f"{name:45}  {seconds * 1000:7.1f} ms  ({seconds / base:4.1f}x python -c pass)")


if __name__ == "__main__":
    main()
