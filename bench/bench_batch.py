"""A folder of clips analysed with one process and with two (``gaitlab analyze DIR --jobs N``).

    python bench/bench_batch.py            # 20 clips: the longest of the real BVH clips of tests/data and its corpus

Prints the wall time of the whole command (start-up and imports included: about 0.35 s;
it was 1.4 s while the analysis imported scipy.signal and scipy.ndimage) and of the
analysis alone, in this process (``analyse_folder``), for --jobs 1 and 2; medians of
three runs.
"""

from __future__ import annotations

import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from app.analysis.batch import analyse_folder, clips_under


def main() -> None:
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        data = ROOT / "tests" / "data"
        sources = sorted(data.glob("*.bvh")) + sorted((data / "corpus").glob("*.bvh"))
        # A folder of takes: the longest clips (a user's takes run seconds to minutes; the
        # corpus's shortest excerpts, 1.6 s jogs, would time little but the start-up).
        frames = {s: int(next(line for line in s.read_text().splitlines() if line.startswith("Frames:")).split()[1])
                  for s in sources}
        sources = sorted(sources, key=lambda s: -frames[s])
        for k in range(20):
            source = sources[k % len(sources)]
            shutil.copy(source, folder / f"{k:02d}_{source.name}")
        clips = clips_under(folder)
        print(f"# {len(clips)} clips: the longest of the {len(sources)} real clips of tests/data and "
              f"tests/data/corpus, {sum(frames[s] for s in sources[:20])} frames in all")
        analyse_folder(clips[:1], 1)  # imports loaded, caches warm
        whole: dict[int, float] = {}
        alone: dict[int, float] = {}
        for jobs in (1, 2):
            runs = []
            for _ in range(3):
                start = time.perf_counter()
                subprocess.run([sys.executable, "-m", "app", "analyze", str(folder), "--jobs", str(jobs)],
                               cwd=ROOT, capture_output=True, check=False)
                runs.append(time.perf_counter() - start)
            whole[jobs] = statistics.median(runs)
            runs = []
            for _ in range(3):
                start = time.perf_counter()
                analyse_folder(clips, jobs)
                runs.append(time.perf_counter() - start)
            alone[jobs] = statistics.median(runs)
        for jobs in (1, 2):
            print(f"--jobs {jobs}: whole command {whole[jobs]:.2f} s, analysis alone {alone[jobs]:.2f} s")
        print(f"ratio --jobs 2 / --jobs 1: whole command {whole[2] / whole[1]:.2f}, "
              f"analysis alone {alone[2] / alone[1]:.2f}")


if __name__ == "__main__":
    main()
