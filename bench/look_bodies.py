"""Look at the bodies: every preset and a herd of eight dogs drawn by another checkout
(before) and by this one (after), side by side, in one sheet.

    python bench/look_bodies.py --old DIR [-o OUT.png]   # default: bodies_before_after.png

Each frame is ``gaitlab render NAME --time 0.3`` at 256x192 from the default
three-quarter camera, run in that tree (``PYTHONPATH``), so the sheet shows what a user
of each version sees. A check by eye (the tests check the numbers).
"""

from __future__ import annotations

import argparse
import subprocess
import sys
import tempfile
from pathlib import Path

from PIL import Image, ImageDraw

ROOT = Path(__file__).resolve().parents[1]
SIZE = (256, 192)
SUBJECTS = [(name, []) for name in ("ant", "bear", "bird", "cat", "centipede", "deer", "dog", "horse", "human",
                                    "spider", "theropod")] + [("dog", ["--herd", "8"])]


def frame(tree: Path, name: str, extra: list[str], out: Path) -> Image.Image:
    command = [sys.executable, "-m", "app", "render", name, *extra, "--time", "0.3", "--size",
               f"{SIZE[0]}x{SIZE[1]}", "-q", "-o", str(out)]
    done = subprocess.run(command, cwd=tree, env={"PYTHONPATH": str(tree), "PATH": "/usr/bin:/bin"},
                          capture_output=True, text=True, timeout=600)
    if done.returncode != 0:
        raise SystemExit(f"{tree}: {' '.join(command)} failed:\n{done.stderr}")
    return Image.open(out).convert("RGB")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--old", type=Path, required=True, help="the checkout to show as 'before'")
    parser.add_argument("-o", "--output", type=Path, default=Path("bodies_before_after.png"))
    ns = parser.parse_args()
    pairs = 2  # before/after pairs per row
    rows = -(-len(SUBJECTS) // pairs)
    label = 16
    sheet = Image.new("RGB", (SIZE[0] * 2 * pairs, (SIZE[1] + label) * rows), "white")
    draw = ImageDraw.Draw(sheet)
    with tempfile.TemporaryDirectory() as tmp:
        for i, (name, extra) in enumerate(SUBJECTS):
            title = name + (" herd of 8" if extra else "")
            x0 = (i % pairs) * 2 * SIZE[0]
            y0 = (i // pairs) * (SIZE[1] + label)
            for j, (tree, when) in enumerate(((ns.old, "before"), (ROOT, "after"))):
                image = frame(tree.resolve(), name, extra, Path(tmp) / f"{i}-{j}.png")
                sheet.paste(image, (x0 + j * SIZE[0], y0 + label))
                draw.text((x0 + j * SIZE[0] + 4, y0 + 2), f"{title}: {when}", fill=(20, 20, 20))
            print(f"  {title}", flush=True)
    sheet.save(ns.output, optimize=True)
    print(f"wrote {ns.output} ({ns.output.stat().st_size // 1024} KB)")


if __name__ == "__main__":
    main()
