"""The analysis plot: each foot's heel and toe height with its events marked, and a
Hildebrand gait diagram (stance bars per foot) over two cycles. Matplotlib, headless."""

from __future__ import annotations

from pathlib import Path

from .metrics import GaitReport

_EVENT_STYLE = {"strike": ("v", "#d62728"), "landing": ("s", "#ff7f0e"), "stance": ("o", "#2ca02c"),
                "lift": ("^", "#1f77b4"), "liftoff": ("D", "#9467bd")}


def save_plot(report: GaitReport, path: Path) -> None:
    """Draw the plot into the PNG file ``path``, in place (callers give a temporary file:
    :func:`app.output.write_together`)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    tracks = report.tracks
    assert tracks is not None
    times = tracks.times
    feet = report.foot_events
    fig = plt.figure(figsize=(10, 2.0 * len(feet) + 2.6), dpi=110, constrained_layout=True)
    grid = fig.add_gridspec(len(feet) + 1, 1, height_ratios=[1.0] * len(feet) + [1.1])
    for i, fe in enumerate(feet):
        ax = fig.add_subplot(grid[i])
        ax.plot(times, fe.heel_height * 100, color="#444444", lw=1.2, label="heel")
        ax.plot(times, fe.toe_height * 100, color="#999999", lw=1.0, ls="--", label="toe")
        for kind, (marker, color) in _EVENT_STYLE.items():
            idx = [getattr(s, kind) for s in fe.steps]
            curve = fe.toe_height if kind in ("strike", "liftoff") else fe.heel_height
            ax.scatter(times[idx], curve[idx] * 100, marker=marker, color=color, s=22, zorder=3,
                       label=kind if i == 0 else None)
        report_foot = report.foot(fe.name)
        ax.set_ylabel(f"{fe.name}\nheight (cm)")
        ax.set_title(f"{fe.name}: duty factor {report_foot.duty_factor:.3f}, phase {report_foot.phase:.3f}",
                     fontsize=9, loc="left")
        ax.grid(alpha=0.3)
        ax.set_xlim(times[0], times[-1])
        if i == 0:
            ax.legend(ncol=7, fontsize=7, loc="upper right")
    # Gait diagram: stance bars over two cycles from the first complete reference strike.
    ax = fig.add_subplot(grid[-1])
    start = times[0]
    from .metrics import reference_foot

    ref_name = reference_foot(tuple(fe.name for fe in feet))
    ref = next(fe for fe in feet if fe.name == ref_name)
    complete = [s for s in ref.steps if s.complete]
    if complete:
        start = times[complete[0].strike]
    end = min(start + 2 * report.cycle_seconds, times[-1])
    for row, fe in enumerate(feet):
        for s in fe.steps:
            t0, t1 = times[s.strike], times[s.liftoff]
            if t1 < start or t0 > end:
                continue
            ax.barh(row, min(t1, end) - max(t0, start), left=max(t0, start), height=0.6, color="#3a6ea5")
    ax.set_yticks(range(len(feet)), [fe.name for fe in feet])
    ax.invert_yaxis()
    ax.set_xlim(start, end)
    ax.set_xlabel("time (s)")
    limb = "" if report.limb_phase is None else f", limb phase {report.limb_phase:.2f}"
    ax.set_title(f"gait diagram (stance): {report.gait_match}{limb}, cycle {report.cycle_seconds:.3f} s",
                 fontsize=9, loc="left")
    ax.grid(axis="x", alpha=0.3)
    fig.suptitle(str(report.source), fontsize=10)
    try:
        fig.savefig(path, format="png")
    finally:
        plt.close(fig)
