"""Mutated and generated inputs for Gaitlab's file loaders, and the check that each one
ends in a result or one clean error line: never a traceback, a hang or a memory blow-up.

Used by ``tests/test_fuzz.py`` (a few hundred inputs per loader) and by
``bench/fuzz_loaders.py`` (tens of thousands). Deterministic for a given seed.

Targets (what a user's file goes through on the command line):

- ``creature``: load_creature -> build_rig -> half a cycle of motion;
- ``scene``: load_scene -> every creature it names;
- ``bvh`` and ``csv``: load_tracks -> analyze_tracks (``gaitlab analyze FILE``).
"""

from __future__ import annotations

import contextlib
import os
import random
import re
import signal
import tempfile
import time
import traceback
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
DATA = ROOT / "tests" / "data"
TIME_LIMIT = 2.0  # seconds per input
TARGETS = ("creature", "scene", "bvh", "csv")

STRANGE_NUMBERS = ("0", "-0", "1", "-1", "0.5", "1e308", "-1e308", "1e-308", "nan", "-nan", "inf", "-inf",
                   "99999999999999999999", "10000000000", "-10000000000", "1e5", "0x10", "1_000", "", "abc",
                   "\uff11", "\u00b2", "3.", ".5", "+7", "1e", "--1", "1" * 5000)
STRANGE_BYTES = (b"\x00", b"\xff\xfe", b"\xef\xbb\xbf", b"\xc3\x28", b"\r", b"\r\n", b"\t", b"\x1b[2J", b"\\",
                 b"\"", b"'''", b"[", b"]", b"{", b"}", b"=", b"#", b",", b":", b"\n\n\n")
NUMBER = re.compile(rb"-?\d+(?:\.\d+)?(?:[eE][-+]?\d+)?")


class Hang(Exception):
    """An input took longer than the time limit."""


# -- seeds -----------------------------------------------------------------------------


def _trim_bvh(text: str, frames: int) -> str:
    """A BVH with only its first ``frames`` frames (a small seed that still has strides)."""
    head, motion = text.split("MOTION", 1)
    lines = motion.strip().splitlines()
    data = [line for line in lines[2:] if line.strip()][:frames]
    return f"{head}MOTION\nFrames: {len(data)}\n{lines[1].strip()}\n" + "\n".join(data) + "\n"


def _csv_seed() -> str:
    """A CSV of four feet trotting: what ``gaitlab analyze`` reads from other tools."""
    t = np.arange(0, 2.0, 1 / 60)
    rows = ["time,LH_x,LH_y,LH_z,RH_x,RH_y,RH_z,LF_x,LF_y,LF_z,RF_x,RF_y,RF_z,body_x,body_y,body_z"]
    for ti in t:
        values = [f"{ti:.4f}"]
        for x, z, phase in ((-0.3, 0.1, 0.0), (-0.3, -0.1, 0.5), (0.3, 0.1, 0.5), (0.3, -0.1, 0.0)):
            cycle, p = divmod(2.0 * ti + phase, 1.0)
            lift = max(0.0, np.sin(2 * np.pi * (p - 0.6) / 0.8)) * 0.06 if p > 0.6 else 0.0
            ahead = 0.5 * (cycle + max(0.0, p - 0.6) / 0.4)  # planted in stance, 0.5 m a stride in swing
            values += [f"{x + ahead:.4f}", f"{lift:.4f}", f"{z:.4f}"]
        values += [f"{1.0 * ti:.4f}", "0.45", "0"]
        rows.append(",".join(values))
    return "\n".join(rows) + "\n"


def seeds(target: str) -> list[bytes]:
    """The real files a target's inputs are mutated from."""
    if target == "creature":
        return [p.read_bytes() for p in sorted((ROOT / "creatures").glob("*.toml"))]
    if target == "scene":
        return [p.read_bytes() for p in sorted((ROOT / "scenes").glob("*.toml"))]
    if target == "bvh":
        texts = [p.read_text(encoding="utf-8") for p in sorted(DATA.glob("*.bvh"))]
        return [_trim_bvh(t, 150).encode() for t in texts]
    if target == "csv":
        return [_csv_seed().encode()]
    raise ValueError(target)


def generated(target: str) -> list[bytes]:
    """Hand-made hostile inputs: huge counts in small files, deep nesting, empty files."""
    common = [b"", b"\n", b"\x00" * 64, "\u00e9\u00e8".encode("latin-1"), b"\xff" * 10]
    if target == "bvh":
        deep = "HIERARCHY\nROOT r\n{ OFFSET 0 0 0 CHANNELS 3 Xposition Yposition Zposition\n" + \
            "JOINT j { OFFSET 0 1 0 CHANNELS 0\n" * 20000 + "}\n" * 20001 + "MOTION\nFrames: 1\nFrame Time: 0.1\n0 0 0\n"
        return common + [s.encode() for s in (
            "HIERARCHY\nROOT r\n{ OFFSET 0 0 0 CHANNELS 1 Xposition\n}\nMOTION\nFrames: 10000000000\nFrame Time: 0.1\n1\n",
            "HIERARCHY\nROOT r\n{ OFFSET 0 0 0 CHANNELS 100000000 Xposition\n}\nMOTION\nFrames: 1\nFrame Time: 1\n1\n",
            "HIERARCHY\nROOT r\n{ OFFSET 0 0 0 CHANNELS 0\n}\nMOTION\nFrames: 3\nFrame Time: 0.1\n\n\n\n",
            "HIERARCHY\nROOT r\n{ OFFSET 0 0 0 CHANNELS 1 Xposition\n}\nMOTION\nFrames: 2\nFrame Time: 1e-300\n1\n2\n",
            "HIERARCHY\nROOT r\n{ OFFSET nan 0 0 CHANNELS 1 Xposition\n}\nMOTION\nFrames: 1\nFrame Time: 0.1\n1\n",
            deep, "MOTION\n", "HIERARCHY\n" * 1000)]
    if target == "csv":
        wide = ",".join(["time"] + [f"F{i}_{a}" for i in range(3000) for a in "xyz"]) + "\n"
        return common + [s.encode() for s in (
            "time\n", "time,L_x,L_y,L_z\n0,0,0,0\n", "time,L_x,L_y,L_z\n" + "0,0,0,0\n" * 3000,
            "time,L_x,L_y,L_z\n" + "".join(f"{i / 60},{i},{i},{i}\n" for i in range(500)),
            wide, "time,L_x,L_y,L_z\n0,1e308,1e308,1e308\n1,-1e308,-1e308,-1e308\n",
            "\"time\n" + "x" * 200_000 + "\n")]
    if target in ("creature", "scene"):
        return common + [s.encode() for s in (
            "a = " + "[" * 5000 + "]" * 5000 + "\n", "a = " + "{b = " * 2000 + "1" + "}" * 2000 + "\n",
            "[" + "a." * 3000 + "b]\n", "x = " + "9" * 5000 + "\n", "name = \"" + "n" * 1_000_000 + "\"\n",
            "[legs.a]\ncount = 1000000\nspan = [0.1, 0.9]\n", "[[creatures]]\ncreature = \"dog\"\n" * 2000,
            "[body]\nlength = 1e308\n", "[gait]\nfrequency = 1e-308\n")]
    raise ValueError(target)


# -- mutations -------------------------------------------------------------------------


def _span(rng: random.Random, n: int) -> tuple[int, int]:
    a = rng.randrange(n + 1)
    return a, min(n, a + rng.choice((1, 2, 4, 16, 64, 512)))


def mutate(data: bytes, rng: random.Random) -> bytes:
    """One to three random edits of ``data``: bytes flipped, spans cut or repeated, numbers
    replaced by strange ones, lines swapped, stray bytes inserted, the file truncated."""
    for _ in range(rng.choice((1, 1, 2, 3))):
        n = len(data)
        kind = rng.randrange(9)
        if n == 0:
            data = rng.choice(STRANGE_BYTES)
            continue
        if kind == 0:  # flip bytes
            buf = bytearray(data)
            for _ in range(rng.randint(1, 8)):
                buf[rng.randrange(n)] = rng.randrange(256)
            data = bytes(buf)
        elif kind == 1:  # cut a span
            a, b = _span(rng, n)
            data = data[:a] + data[b:]
        elif kind == 2:  # repeat a span
            a, b = _span(rng, n)
            data = data[:b] + data[a:b] * rng.choice((1, 2, 10)) + data[b:]
        elif kind == 3:  # truncate
            data = data[:rng.randrange(n)]
        elif kind in (4, 5):  # a strange number
            numbers = list(NUMBER.finditer(data))
            if numbers:
                m = rng.choice(numbers)
                data = data[:m.start()] + rng.choice(STRANGE_NUMBERS).encode() + data[m.end():]
        elif kind == 6:  # swap two lines
            lines = data.split(b"\n")
            i, j = rng.randrange(len(lines)), rng.randrange(len(lines))
            lines[i], lines[j] = lines[j], lines[i]
            data = b"\n".join(lines)
        elif kind == 7:  # a stray byte sequence
            a = rng.randrange(n + 1)
            data = data[:a] + rng.choice(STRANGE_BYTES) + data[a:]
        else:  # a line copied elsewhere
            lines = data.split(b"\n")
            lines.insert(rng.randrange(len(lines) + 1), rng.choice(lines))
            data = b"\n".join(lines)
    return data


def inputs(target: str, count: int, seed: int = 0):
    """``count`` inputs for ``target``: the hand-made ones first, then mutations of the seeds."""
    rng = random.Random(f"{target}-{seed}")
    made = generated(target)
    originals = seeds(target)
    for i in range(count):
        yield made[i] if i < len(made) else mutate(rng.choice(originals), rng)


# -- running a loader ------------------------------------------------------------------


def _load_creature(path: str) -> None:
    from app import build_rig, load_creature
    from app.kinematics.clip import clip_motion

    rig = build_rig(load_creature(path))
    clip_motion(rig, 20.0, cycles=0.5)


def _load_scene(path: str) -> None:
    from app import load_creature
    from app.worlds import load_scene

    scene = load_scene(path)
    for entry in scene.creatures:
        spec = load_creature(entry.creature)
        if entry.overrides:
            spec.with_overrides(dict(entry.overrides), origin=path)


def _load_motion(path: str) -> None:
    from app.analysis import analyze_tracks
    from app.analysis.sources import load_tracks

    tracks, _ = load_tracks(path)
    analyze_tracks(tracks)


RUNNERS: dict[str, tuple[str, Callable[[str], None]]] = {
    "creature": (".toml", _load_creature), "scene": (".toml", _load_scene),
    "bvh": (".bvh", _load_motion), "csv": (".csv", _load_motion),
}


@dataclass
class FuzzResult:
    """What a target's inputs led to."""

    target: str
    loaded: int = 0
    clean_errors: int = 0
    crashes: list[tuple[bytes, str]] = field(default_factory=list)  # (input, traceback)
    hangs: list[tuple[bytes, float]] = field(default_factory=list)
    bad_messages: list[tuple[bytes, str]] = field(default_factory=list)  # not one short line
    slowest: float = 0.0

    @property
    def total(self) -> int:
        return self.loaded + self.clean_errors + len(self.crashes) + len(self.hangs)


def _alarm(signum, frame) -> None:
    raise Hang()


def run(target: str, count: int, seed: int = 0, progress: Callable[[int], None] | None = None) -> FuzzResult:
    """Feed ``count`` inputs to ``target``'s loader; collect crashes, hangs and messy errors."""
    from app.errors import GaitlabError

    suffix, loader = RUNNERS[target]
    result = FuzzResult(target)
    old = signal.signal(signal.SIGALRM, _alarm)
    try:
        with tempfile.TemporaryDirectory() as folder:
            path = os.path.join(folder, f"input{suffix}")
            # A first load pays the imports and the caches' first fill (half a second for a
            # creature, more on a loaded machine): not a hang, so it is not timed.
            with open(path, "wb") as fh:
                fh.write(seeds(target)[0])
            with contextlib.suppress(Exception):
                loader(path)
            for i, data in enumerate(inputs(target, count, seed)):
                with open(path, "wb") as fh:
                    fh.write(data)
                t0 = time.perf_counter()
                signal.setitimer(signal.ITIMER_REAL, TIME_LIMIT)
                try:
                    loader(path)
                    result.loaded += 1
                except Hang:
                    result.hangs.append((data, time.perf_counter() - t0))
                except GaitlabError as exc:
                    result.clean_errors += 1
                    message = str(exc)
                    if "\n" in message or len(message) > 600 or not message.strip():
                        result.bad_messages.append((data, message[:2000]))
                except BaseException as exc:
                    if isinstance(exc, KeyboardInterrupt):
                        raise
                    result.crashes.append((data, traceback.format_exc(limit=6)))
                finally:
                    signal.setitimer(signal.ITIMER_REAL, 0)
                result.slowest = max(result.slowest, time.perf_counter() - t0)
                if progress:
                    progress(i + 1)
    finally:
        signal.signal(signal.SIGALRM, old)
    return result
