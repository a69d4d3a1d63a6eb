"""Fuzz Gaitlab's file loaders: mutated real files and hand-made hostile ones.

    python bench/fuzz_loaders.py                 # 10,000 inputs per loader
    python bench/fuzz_loaders.py --count 500 --target bvh --seed 3

Each input goes through what ``gaitlab`` does with a user's file (see tests/fuzz_inputs.py)
and must end in a result or one clean error line within 2 s. Prints, per loader: inputs
that loaded, clean errors, crashes (with the first traceback), hangs, the slowest input,
and the process's peak memory. Exit status 1 if anything crashed or hung.
"""

from __future__ import annotations

import argparse
import os
import platform
import resource
import sys
import time
import warnings
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(ROOT), str(ROOT / "tests")]

from fuzz_inputs import TARGETS, run


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--count", type=int, default=10_000, help="inputs per loader (default 10000)")
    parser.add_argument("--target", choices=TARGETS, action="append", help="loader(s) to fuzz (default: all)")
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args()
    from tqdm import tqdm

    warnings.simplefilter("ignore", RuntimeWarning)
    print(f"# loader fuzzing - {platform.machine()}, {os.cpu_count()} cores, Python {platform.python_version()}")
    failed = False
    for target in args.target or TARGETS:
        bar = tqdm(total=args.count, desc=target, leave=False, disable=not sys.stderr.isatty())
        t0 = time.perf_counter()
        result = run(target, args.count, args.seed, progress=lambda n, b=bar: b.update(n - b.n))
        bar.close()
        peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
        print(f"{target:9} {result.total:6} inputs in {time.perf_counter() - t0:6.1f} s: {result.loaded:5} loaded, "
              f"{result.clean_errors:5} clean errors, {len(result.crashes)} crashes, {len(result.hangs)} hangs, "
              f"{len(result.bad_messages)} messy messages; slowest {result.slowest:.2f} s; peak memory so far "
              f"{peak:.0f} MB")
        for data, tb in result.crashes[:1]:
            print(f"  first crash, input starts {data[:120]!r}\n{tb}")
        for data, seconds in result.hangs[:1]:
            print(f"  first hang ({seconds:.1f} s), input starts {data[:120]!r}")
        for _data, message in result.bad_messages[:1]:
            print(f"  first messy message: {message[:300]}")
        failed |= bool(result.crashes or result.hangs)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
