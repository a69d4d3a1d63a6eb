"""Comparing a gait's sagittal joint angles with a reference: a real clip or a normative
curve file. The mean curves over a normalised cycle (:mod:`.angles`), their RMS
difference per joint, and the events clinicians read off them.

A normative file is a CSV with a ``phase`` column (0-100, % of the cycle from a strike)
and, per joint (``hip``, ``knee``, ``ankle``), ``JOINT_mean`` and ``JOINT_sd`` in
degrees (the conventions of :mod:`.angles`).
"""

from __future__ import annotations

import csv
import io
import math
import os
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from .angles import JOINTS, SAMPLES, cycle_curves, rms
from .bvh import InputError
from .limbs import Legs
from .sources import check_columns_once

MAX_CSV_BYTES = 4 * 2**20
GRID = np.linspace(0.0, 100.0, SAMPLES)


@dataclass(frozen=True)
class Curves:
    """Mean curves (SAMPLES,) per joint over a cycle, their spread (SD per point) and
    where the foot leaves the ground (% of the cycle; None when unknown)."""

    name: str
    mean: dict[str, NDArray[np.float64]]
    sd: dict[str, NDArray[np.float64]]
    cycles: int = 0
    toe_off: float | None = None


@dataclass
class Comparison:
    """A gait against its reference: both curve sets, RMS per joint and event values."""

    gait: Curves
    reference: Curves
    rms: dict[str, float] = field(default_factory=dict)
    events: dict[str, tuple[float | None, float | None]] = field(default_factory=dict)

    def to_json(self) -> dict:
        def num(v: float | None) -> float | None:
            return None if v is None or not math.isfinite(v) else round(float(v), 3)

        return {"gait": self.gait.name, "reference": self.reference.name, "cycles": self.gait.cycles,
                "rms_deg": {k: num(v) for k, v in self.rms.items()},
                "events": {k: {"gait": num(a), "reference": num(b)} for k, (a, b) in self.events.items()},
                "curves": {"phase": GRID.tolist(),
                           **{f"{src}_{j}": [round(float(x), 3) for x in c.mean[j]]
                              for src, c in (("gait", self.gait), ("reference", self.reference)) for j in c.mean}}}


def leg_curves(legs: Legs, leg: str, contact_fraction: float | None = None) -> Curves:
    """One leg's mean curves over its whole cycles (strike to strike)."""
    strikes = legs.strikes.get(leg)
    if strikes is None or len(strikes) < 2:
        raise InputError(f"{legs.source}: fewer than two strikes of foot {leg}; give a clip of at least one full "
                         "stride")
    angles = legs.angles[leg]
    mean, sd = {}, {}
    cycles = 0
    for joint in JOINTS:
        curves = cycle_curves(angles.joint(joint), strikes)
        cycles = len(curves)
        mean[joint] = curves.mean(axis=0)
        sd[joint] = curves.std(axis=0)
    toe_off = None if contact_fraction is None else 100.0 * contact_fraction
    return Curves(name=f"{legs.source} {leg}", mean=mean, sd=sd, cycles=cycles, toe_off=toe_off)


def read_normative(path: str | os.PathLike[str]) -> Curves:
    """A normative curve file (see the module docstring); one-line :class:`InputError`
    for anything else."""
    path = os.fspath(path)
    try:
        with open(path, "rb") as fh:
            raw = fh.read(MAX_CSV_BYTES + 1)
    except OSError as exc:
        raise InputError(f"{path}: cannot read: {exc.strerror or exc}") from None
    if len(raw) > MAX_CSV_BYTES:
        raise InputError(f"{path}: over {MAX_CSV_BYTES // 2**20} MiB; a normative curve file is a few KiB")
    try:
        if b"\x00" in raw:
            raise ValueError("it holds NUL bytes")
        try:
            text = raw.decode("utf-8-sig")  # -sig: a spreadsheet's byte-order mark
        except UnicodeDecodeError:
            text = raw.decode("cp1252", errors="replace")  # as a spreadsheet on Windows saves it
        rows = [r for r in csv.reader(io.StringIO(text, newline="")) if r and not r[0].lstrip().startswith("#")]
    except (ValueError, csv.Error) as exc:
        raise InputError(f"{path}: not a CSV text file ({str(exc).split(' - ')[0][:80]}); a normative curve file is "
                         "text: phase,JOINT_mean,JOINT_sd,...") from None
    if len(rows) < 3:
        raise InputError(f"{path}: expected a header and rows: phase,JOINT_mean,JOINT_sd,... (JOINT: "
                         f"{', '.join(JOINTS)})")
    header = [h.strip() for h in rows[0]]
    check_columns_once(header, path)
    joints = [j for j in JOINTS if f"{j}_mean" in header and f"{j}_sd" in header]
    if "phase" not in header or not joints:
        shown = ", ".join(repr(h[:20]) for h in header[:8])
        raise InputError(f"{path}: columns {shown}: expected phase and, for at least one of {', '.join(JOINTS)}, "
                         "JOINT_mean and JOINT_sd (degrees)")
    try:
        table = np.array([[float(x) for x in r] for r in rows[1:]], dtype=np.float64)
    except ValueError:
        raise InputError(f"{path}: every value after the header must be a number") from None
    if table.shape[1] != len(header) or not np.all(np.isfinite(table)):
        raise InputError(f"{path}: every row needs {len(header)} finite numbers, as the header has columns")
    phase = table[:, header.index("phase")]
    if np.any(np.diff(phase) <= 0) or not (-5.0 <= phase[0] <= 5.0) or not (95.0 <= phase[-1] <= 105.0):
        raise InputError(f"{path}: phase must rise from about 0 to about 100 (% of the cycle)")
    for j in joints:
        for column in (f"{j}_mean", f"{j}_sd"):
            values = table[:, header.index(column)]
            if np.abs(values).max() > 360.0:
                row = int(np.argmax(np.abs(values)))
                raise InputError(f"{path}: {column} is {values[row]:g} at phase {phase[row]:g}; joint angles are "
                                 "degrees, within -360 to 360")
        sds = table[:, header.index(f"{j}_sd")]
        if np.any(sds < 0):
            row = int(np.argmax(sds < 0))
            raise InputError(f"{path}: {j}_sd is {sds[row]:g} at phase {phase[row]:g}; a standard deviation is "
                             "0 or more (degrees)")
    mean = {j: np.interp(GRID, phase, table[:, header.index(f"{j}_mean")]) for j in joints}
    sd = {j: np.interp(GRID, phase, table[:, header.index(f"{j}_sd")]) for j in joints}
    return Curves(name=Path(path).name, mean=mean, sd=sd, cycles=0)


def _value_at(curve: NDArray[np.float64], percent: float) -> float:
    return float(np.interp(percent, GRID, curve))


def _events(c: Curves) -> dict[str, float | None]:
    """The clinical events of a curve set (degrees; ``*_at`` in % of the cycle)."""
    out: dict[str, float | None] = {}
    if "knee" in c.mean:
        k = c.mean["knee"]
        out["knee at strike"] = float(k[0])
        out["knee loading peak"] = float(k[:26].max())
        out["knee mid-stance"] = float(k[25:51].min())
        out["knee swing peak"] = float(k[50:].max())
        out["knee swing peak at %"] = float(GRID[50 + int(np.argmax(k[50:]))])
        out["knee at toe-off"] = None if c.toe_off is None else _value_at(k, c.toe_off)
    if "hip" in c.mean:
        out["hip max"] = float(c.mean["hip"].max())
        out["hip min"] = float(c.mean["hip"].min())
    if "ankle" in c.mean:
        a = c.mean["ankle"]
        out["ankle at strike"] = float(a[0])
        out["ankle min (push-off)"] = float(a.min())
        out["ankle at toe-off"] = None if c.toe_off is None else _value_at(a, c.toe_off)
        out["ankle mid-swing"] = None if c.toe_off is None else _value_at(a, 0.5 * (c.toe_off + 100.0))
    return out


def compare_curves(gait: Curves, reference: Curves) -> Comparison:
    """RMS difference per joint both sides give, and the events of each."""
    result = Comparison(gait, reference)
    for joint in JOINTS:
        if joint in gait.mean and joint in reference.mean:
            result.rms[joint] = rms(gait.mean[joint], reference.mean[joint])
    ours, theirs = _events(gait), _events(reference)
    result.events = {k: (ours.get(k), theirs.get(k)) for k in ours}
    return result


def format_comparison(c: Comparison) -> str:
    def show(v: float | None) -> str:
        return "-" if v is None else f"{v:7.1f}"

    def count(n: int) -> str:
        return f" ({n} cycle{'' if n == 1 else 's'})"

    lines = [f"gait       {c.gait.name}{count(c.gait.cycles)}",
             f"reference  {c.reference.name}" + (count(c.reference.cycles) if c.reference.cycles else ""),
             "",
             "joint     RMS difference (deg)"]
    lines += [f"{joint:<9} {value:6.1f}" for joint, value in c.rms.items()]
    lines += ["", f"{'event':<24} {'gait':>7} {'reference':>10}"]
    lines += [f"{name:<24} {show(a)} {show(b):>10}" for name, (a, b) in c.events.items()]
    return "\n".join(lines)


def write_comparison_plot(c: Comparison, path: str | os.PathLike[str]) -> Path:
    """The curves side by side, one panel per joint, the reference's band (mean +- SD)
    shaded; written atomically."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from ..output import AtomicPath

    joints = [j for j in JOINTS if j in c.gait.mean and j in c.reference.mean]
    fig, axes = plt.subplots(1, len(joints), figsize=(4.2 * len(joints), 3.6), dpi=110, constrained_layout=True,
                             squeeze=False)
    for ax, joint in zip(axes[0], joints):
        ref, sd = c.reference.mean[joint], c.reference.sd[joint]
        ax.fill_between(GRID, ref - sd, ref + sd, color="#bbbbbb", alpha=0.5, lw=0, label="reference +- SD")
        ax.plot(GRID, ref, color="#555555", lw=1.6, label="reference")
        ax.plot(GRID, c.gait.mean[joint], color="#d62728", lw=1.8, label="Gaitlab")
        if c.gait.toe_off is not None:
            ax.axvline(c.gait.toe_off, color="#d62728", lw=0.8, ls=":")
        ax.set_title(f"{joint}  (RMS {c.rms.get(joint, float('nan')):.1f} deg)")
        ax.set_xlabel("% of the cycle (strike to strike)")
        ax.set_ylabel({"hip": "thigh vs vertical, + flexion (deg)", "knee": "flexion (deg)",
                       "ankle": "dorsiflexion, + toes up (deg)"}[joint])
        ax.set_xlim(0, 100)
        ax.grid(alpha=0.3)
    axes[0][0].legend(loc="upper left", fontsize=8, frameon=False)
    fig.suptitle(f"{c.gait.name}  vs  {c.reference.name}", fontsize=10)
    with AtomicPath(path) as out:
        fig.savefig(out.tmp, format="png")
    plt.close(fig)
    return Path(path)
