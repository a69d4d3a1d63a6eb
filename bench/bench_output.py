"""Recording: peak memory of long takes, MP4 speed and GIF size, old against new.

    python bench/bench_output.py memory             # 600 s GIF and MP4: peak memory (GNU time -v) and wall time
    python bench/bench_output.py speed --old DIR    # 60 s 480x360 MP4: this tree against another checkout
    python bench/bench_output.py size --old DIR     # the README GIF and a 60 s GIF: sizes, old against new

``--old DIR`` is another checkout of Gaitlab (e.g. ``git worktree add /tmp/old <commit>``);
both run as ``python -m app render`` with the same interpreter. Runs alternate old/new so
the machine's load drifts over both equally; medians are printed.
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
import threading
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def tree_rss_mb(pid: int) -> float:
    """Resident memory (MB) of a process and all its descendants, from /proc."""
    children: dict[int, list[int]] = {}
    rss: dict[int, int] = {}
    for entry in os.listdir("/proc"):
        if not entry.isdigit():
            continue
        try:
            fields = Path(f"/proc/{entry}/stat").read_text().rsplit(")", 1)[1].split()
            children.setdefault(int(fields[1]), []).append(int(entry))
            rss[int(entry)] = int(fields[21]) * os.sysconf("SC_PAGE_SIZE")
        except (OSError, IndexError, ValueError):
            continue
    total, todo = 0, [pid]
    while todo:
        p = todo.pop()
        total += rss.get(p, 0)
        todo.extend(children.get(p, []))
    return total / 2**20


def run(args: list[str], tree: Path, cwd: Path) -> dict[str, float]:
    """Run ``gaitlab`` from ``tree`` under GNU time; wall s, its peak RSS and the process tree's."""
    env = {**os.environ, "PYTHONPATH": str(tree)}
    command = ["/usr/bin/time", "-v", sys.executable, "-m", "app", *args]
    t0 = time.perf_counter()
    process = subprocess.Popen(command, cwd=cwd, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                               text=True)
    peak = 0.0
    done = threading.Event()

    def sample() -> None:
        nonlocal peak
        while not done.is_set():
            peak = max(peak, tree_rss_mb(process.pid))
            time.sleep(0.1)

    sampler = threading.Thread(target=sample, daemon=True)
    sampler.start()
    _, err = process.communicate()
    wall = time.perf_counter() - t0
    done.set()
    sampler.join()
    if process.returncode != 0:
        raise SystemExit(f"failed: {' '.join(args)}\n{err}")
    max_rss = float(re.search(r"Maximum resident set size \(kbytes\): (\d+)", err).group(1)) / 1024
    return {"wall": wall, "max_rss": max_rss, "tree_peak": peak}


def header(title: str) -> None:
    print(f"# {title} - {platform.machine()}, {os.cpu_count()} cores, Python {platform.python_version()}")


def memory(_: argparse.Namespace) -> None:
    header("600 s recordings: peak memory (GNU time -v, and the whole process tree sampled every 0.1 s)")
    with tempfile.TemporaryDirectory() as tmp:
        for out in ("x.gif", "x.mp4"):
            r = run(["render", "dog", "--seconds", "600", "-q", "-o", out], ROOT, Path(tmp))
            size = (Path(tmp) / out).stat().st_size / 2**20
            print(f"render dog --seconds 600 -o {out:6}  {r['wall']:6.0f} s  max RSS {r['max_rss']:5.0f} MB  "
                  f"process tree peak {r['tree_peak']:5.0f} MB  file {size:6.1f} MiB")


def alternate(args_list: list[list[str]], old: Path, repeats: int, cwd: Path) -> tuple[list[float], list[float]]:
    old_t, new_t = [], []
    for _ in range(repeats):
        for args in args_list:
            old_t.append(run(args, old, cwd)["wall"])
            new_t.append(run(args, ROOT, cwd)["wall"])
    return old_t, new_t


def speed(ns: argparse.Namespace) -> None:
    header("60 s 480x360 MP4 of the walking dog: wall time, old against new (alternating runs)")
    with tempfile.TemporaryDirectory() as tmp:
        old_t, new_t = alternate([["render", "dog", "--seconds", "60", "-q", "-o", "x.mp4"]], ns.old, ns.repeats,
                                 Path(tmp))
    o, n = statistics.median(old_t), statistics.median(new_t)
    print(f"old  median {o:5.1f} s  runs {', '.join(f'{t:.1f}' for t in old_t)}")
    print(f"new  median {n:5.1f} s  runs {', '.join(f'{t:.1f}' for t in new_t)}")
    print(f"speed-up  {o / n:.2f}x")


def size(ns: argparse.Namespace) -> None:
    header("GIF sizes, old against new")
    with tempfile.TemporaryDirectory() as tmp:
        cwd = Path(tmp)
        for label, args in (("README dog (2 cycles)", ["render", "dog", "-q", "-o", "x.gif"]),
                            ("60 s dog", ["render", "dog", "--seconds", "60", "-q", "-o", "x.gif"])):
            row = []
            for tree in (ns.old, ROOT):
                r = run(args, tree, cwd)
                row.append(((cwd / "x.gif").stat().st_size, r["wall"], r["max_rss"]))
            (so, to, mo), (sn, tn, mn) = row
            print(f"{label:22} old {so / 2**20:6.2f} MiB ({to:5.1f} s, {mo:5.0f} MB)   new {sn / 2**20:6.2f} MiB "
                  f"({tn:5.1f} s, {mn:5.0f} MB)   new/old {sn / so:.2f}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("what", choices=("memory", "speed", "size"))
    parser.add_argument("--old", type=Path, help="another Gaitlab checkout to compare with (speed, size)")
    parser.add_argument("--repeats", type=int, default=3)
    ns = parser.parse_args()
    if ns.what in ("speed", "size") and ns.old is None:
        parser.error(f"{ns.what} compares against --old DIR (another checkout)")
    {"memory": memory, "speed": speed, "size": size}[ns.what](ns)


if __name__ == "__main__":
    main()
