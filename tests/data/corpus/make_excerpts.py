"""How the corpus's excerpts were cut (kept for the record; the tests read the .bvh files).

    python tests/data/corpus/make_excerpts.py SOURCE_DIR

SOURCE_DIR holds the original takes (Tencent-RoboticsX/lifelike-agility-and-play,
data/raw_mocap_data/*.bvh at commit cc9eaa9). Each excerpt keeps the take's hierarchy
and the frames [first, last) of its motion, every ``step``-th (120 fps -> 60 fps with
step 2), numbers rounded to three decimals (centimetres and degrees: 0.01 mm, 0.001 deg).
"""

from __future__ import annotations

import sys
from pathlib import Path

# name: (source take, first frame, last frame, step)
EXCERPTS = {
    "dog_walk_tencent_walkrun007_f120-300": ("dog_quad_walkrun_007", 120, 300, 2),
    "dog_trot_tencent_walkrun007_f240-480": ("dog_quad_walkrun_007", 240, 480, 2),
    "dog_gallop_tencent_walkrun007_f600-800": ("dog_quad_walkrun_007", 600, 800, 2),
    "dog_trot_tencent_walkrun006_f480-600": ("dog_quad_walkrun_006", 480, 600, 2),
    "dog_gallop_tencent_walkrun006_f720-840": ("dog_quad_walkrun_006", 720, 840, 2),
    "dog_walk_tencent_walkrun001_f120-360": ("dog_quad_walkrun_001", 120, 360, 2),
    "dog_gallop_tencent_walkrun001_f600-840": ("dog_quad_walkrun_001", 600, 840, 2),
    "dog_gallop_tencent_walkrun005_f600-720": ("dog_quad_walkrun_005", 600, 720, 2),
    "dog_backwards_tencent_back001_f300-700": ("dog_back_001", 300, 700, 2),
}


def excerpt(source: Path, first: int, last: int, step: int) -> str:
    lines = source.read_text().splitlines()
    motion = next(i for i, line in enumerate(lines) if line.strip() == "MOTION")
    frame_time = float(lines[motion + 2].split(":")[1])
    frames = lines[motion + 3:][first:last:step]
    rounded = [" ".join(f"{float(v):.3f}" for v in line.split()) for line in frames]
    head = lines[:motion + 1] + [f"Frames: {len(rounded)}", f"Frame Time: {frame_time * step:.6f}"]
    return "\n".join(head + rounded) + "\n"


if __name__ == "__main__":
    source_dir, out = Path(sys.argv[1]), Path(__file__).parent
    for name, (take, first, last, step) in EXCERPTS.items():
        (out / f"{name}.bvh").write_text(excerpt(source_dir / f"{take}.bvh", first, last, step))
        print(name)
