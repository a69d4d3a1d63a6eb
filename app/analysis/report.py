"""Presenting a gait report: a readable table, JSON, and a CSV of the events."""

from __future__ import annotations

import csv
import io
import math

from .metrics import GaitReport


def _fmt(x: float | None, digits: int = 3, unit: str = "") -> str:
    if x is None or (isinstance(x, float) and not math.isfinite(x)):
        return "-"
    return f"{x:.{digits}f}{unit}"


def format_table(report: GaitReport, requested: dict[str, tuple[float, float]] | None = None,
                 notes: str = "") -> str:
    """The human-readable report. ``requested`` maps a foot to its (duty, phase) as asked for."""
    lines = [f"source       {report.source}"]
    if notes:
        lines.append(f"read as      {notes}")
    for note in report.notes:
        lines.append(f"note         {note}")
    if report.gait:
        verdict = "matches" if report.gait_match == report.gait else f"requested {report.gait}"
        lines.append(f"gait         {report.gait_match} ({verdict})")
    else:
        lines.append(f"gait         {report.gait_match}")
    lines.append(f"cycle        {_fmt(report.cycle_seconds, 3, ' s')}   speed {_fmt(report.speed, 2, ' m/s')}"
                 + (f"   limb phase {_fmt(report.limb_phase, 3)}" if report.limb_phase is not None else "")
                 + (f"   wave lag {_fmt(report.wave_lag, 3)} per pair" if report.wave_lag is not None else ""))
    if report.arm_phase is not None:
        a = report.arm_phase
        lines.append(f"arms         hands farthest forward at phase L {_fmt(a['L'], 3)}, R {_fmt(a['R'], 3)} "
                     "(0 = left foot down; an arm swinging against the legs peaks with the other foot)")
    if report.path_error is not None:
        e = report.path_error
        lines.append(f"path         off by {_fmt(e.rms * 1000, 1)} mm RMS, {_fmt(e.max * 1000, 1)} mm at most "
                     f"({_fmt(e.max_body_lengths * 100, 2)}% of the body length); heading off by "
                     f"{_fmt(e.heading_rms_deg, 2)} deg RMS, {_fmt(e.heading_max_deg, 2)} deg at most")
    if len(report.spans) > 1:
        spans = ", ".join(f"{s.gait} {s.start:.2f}-{s.end:.2f} s" for s in report.spans)
        lines.append(f"gaits        {spans}")
    header = f"{'foot':<5} {'duty':>6} {'phase':>6} {'stride':>9} {'max slip':>9} {'skating':>8}"
    if requested:
        header += f"   {'asked duty':>10} {'phase':>6}"
    lines += ["", header]
    for f in report.feet:
        row = (f"{f.name:<5} {_fmt(f.duty_factor):>6} {_fmt(f.phase):>6} {_fmt(f.stride_length, 3, ' m'):>9} "
               f"{_fmt(f.max_stance_slip, 3, ' m'):>9} {_fmt(f.skating_ratio):>8}")
        if requested and f.name in requested:
            duty, phase = requested[f.name]
            row += f"   {duty:>10.3f} {phase:>6.3f}"
        lines.append(row)
    return "\n".join(lines)


def events_csv(report: GaitReport) -> str:
    """One row per event: foot, kind, time (s)."""
    out = io.StringIO()
    writer = csv.writer(out, lineterminator="\n")
    writer.writerow(["foot", "kind", "time"])
    for f in report.feet:
        for kind, time in f.events:
            writer.writerow([f.name, kind, f"{time:.5f}"])
    return out.getvalue()


