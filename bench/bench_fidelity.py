"""The fidelity table: Gaitlab's motion measured from its joints against published
biomechanics (../shared/reference/fidelity.md) and real clips.

    .venv/bin/python bench/bench_fidelity.py [--cmu PATH]

Prints, for the human walk (default creature, default speed) every row of the human-walk
table with its typical range, the RMS difference of the hip, knee and ankle curves from
the bundled normative mean (Schwartz et al. 2008) and of the knee from the CMU walk
12_01; for the human run, every row of fidelity.md's run table (knee at strike, stance
and swing peaks, hip and ankle at toe-off, vertical excursion) with the flight's
acceleration, the largest jolt, elbows, duty and cadence; for the horse's walk and trot
and the dog's rotary gallop and bound, duty, stride, speed, head nod and back flexion.
"""

from __future__ import annotations

import argparse
import math
import os
import platform
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from app import build_rig, load_creature
from app.analysis.compare import compare_curves, leg_curves, read_normative
from app.analysis.fidelity import HUMAN_RUN, HUMAN_WALK, quadruped_measures, run_measures, walk_measures
from app.analysis.limbs import bvh_legs, motion_legs
from app.kinematics.clip import clip_motion
from app.resources import reference_dir

CMU_WALK = ROOT.parent / "shared" / "reference" / "motion" / "human_walk_cmu_12_01.bvh"
QUADRUPED_RANGES = {
    ("horse", "walk"): {"duty factor": (0.60, 0.67), "stride m": (1.5, 2.0), "speed m/s": (1.5, 1.8),
                        "head vertical cm": (3.0, 12.0), "head frequency / stride frequency": (1.8, 2.2)},
    ("horse", "trot"): {"duty factor": (0.38, 0.47), "stride m": (2.3, 3.0), "cycle s": (0.65, 0.8),
                        "head vertical cm": (3.0, 12.0)},
    ("horse", "gallop"): {"duty factor": (0.20, 0.30), "head frequency / stride frequency": (0.8, 1.2)},
    ("dog", "rotary-gallop"): {"back flexion deg": (8.0, 20.0)},
    ("dog", "bound"): {"back flexion deg": (8.0, 20.0)},
}


def row(name: str, value: float, low: float | None = None, high: float | None = None) -> str:
    if low is None or high is None:
        return f"  {name:34} {value:8.2f}"
    ok = math.isfinite(value) and low - 1e-9 <= value <= high + 1e-9
    return f"  {name:34} {value:8.2f}   typical {low:g} to {high:g}   {'ok' if ok else 'OUT'}"


def human(cmu: Path) -> None:
    spec = load_creature("human")
    rig = build_rig(spec)
    motion, _ = clip_motion(rig, 240.0, cycles=8.0)
    print("\nhuman walk (default creature, default speed), 8 cycles at 240 fps")
    for name, value in walk_measures(motion).items():
        print(row(name, value, *HUMAN_WALK.get(name, (None, None))))
    gait = leg_curves(motion_legs(motion), "L", contact_fraction=rig.gait.duty_factor)
    normative = compare_curves(gait, read_normative(reference_dir() / "human_walk_schwartz2008.csv"))
    for joint, value in normative.rms.items():
        print(row(f"{joint} RMS vs Schwartz 2008 (deg)", value, 0.0, 8.0))
    if cmu.is_file():
        clip = compare_curves(gait, leg_curves(bvh_legs(str(cmu)), "L"))
        print(row("knee RMS vs CMU 12_01 (deg)", clip.rms["knee"], 0.0, 10.0))
    else:
        print(f"  (no {cmu}: the CMU comparison is skipped)")
    run = spec.with_overrides({"gait.preset": "run"})
    run_rig = build_rig(run)
    motion, _ = clip_motion(run_rig, 240.0, cycles=8.0)
    print("\nhuman run (--gait run), 8 cycles at 240 fps")
    for name, value in run_measures(motion).items():
        print(row(name, value, *HUMAN_RUN.get(name, (None, None))))


def quadrupeds() -> None:
    for (creature, gait), ranges in QUADRUPED_RANGES.items():
        spec = load_creature(creature)
        if spec.gait.preset != gait:  # its own gait as its file tunes it; another one as the preset has it
            spec = spec.with_overrides({"gait.preset": gait})
        rig = build_rig(spec)
        motion, _ = clip_motion(rig, 240.0, cycles=6.0)
        print(f"\n{creature} {gait} (default speed), 6 cycles at 240 fps")
        for name, value in quadruped_measures(motion).items():
            print(row(name, value, *ranges.get(name, (None, None))))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--cmu", type=Path, default=CMU_WALK, help="the CMU walk 12_01 BVH")
    args = parser.parse_args()
    print(f"# fidelity - {platform.machine()}, {os.cpu_count()} cores, Python {platform.python_version()}")
    human(args.cmu)
    quadrupeds()


if __name__ == "__main__":
    main()
