"""Many clips at once: every motion file under a folder analysed in parallel processes,
one row per clip (``gaitlab analyze DIR/ --csv table.csv --jobs N``).

A clip that cannot be analysed is a row with its error and the batch goes on. Rows keep
the folder's sorted order whatever order the workers finish in.
"""

from __future__ import annotations

import csv
import io
import math
import os
from collections.abc import Callable, Iterable
from concurrent.futures import ProcessPoolExecutor, as_completed
from dataclasses import dataclass, field
from pathlib import Path

from ..errors import GaitlabError
from .sources import Units, UpAxis

CLIP_SUFFIXES = (".bvh", ".csv")


@dataclass(frozen=True)
class ClipRow:
    """One clip's result: its gait, cycle (s), speed (m/s), each foot's duty factor and
    phase (name -> value), notes; or the error that stopped it (the rest empty)."""

    source: str
    gait: str = ""
    cycle: float | None = None
    speed: float | None = None
    duty: dict[str, float | None] = field(default_factory=dict)
    phase: dict[str, float | None] = field(default_factory=dict)
    notes: tuple[str, ...] = ()
    error: str = ""

    @property
    def ok(self) -> bool:
        return not self.error


OWN_TABLES = ("source,gait,cycle_s", "foot,kind,time")  # headers of analyze's own CSVs: no clips


def _is_clip(path: Path, skip: Path | None) -> bool:
    if not path.is_file() or path.suffix.lower() not in CLIP_SUFFIXES:
        return False
    if skip is not None and path.resolve() == skip.resolve():
        return False
    if path.suffix.lower() == ".csv":
        try:
            with path.open("rb") as fh:
                head = fh.read(64).decode("utf-8", errors="replace")
        except OSError:
            return True  # a row saying it cannot be read
        return not head.lstrip("\ufeff").startswith(OWN_TABLES)
    return True


def clips_under(folder: Path, skip: Path | None = None) -> list[Path]:
    """Every motion file (.bvh, .csv) under ``folder``, sorted by path, but for ``skip``
    (the table being written) and analyze's own tables and events CSVs; one line when
    there is none."""
    if not folder.is_dir():
        raise GaitlabError(f"{folder}: not a folder")
    found = sorted(p for p in folder.rglob("*") if _is_clip(p, skip))
    if not found:
        raise GaitlabError(f"{folder}: no .bvh or .csv clips under it")
    return found


def _finite(value: float | None) -> float | None:
    return None if value is None or not math.isfinite(value) else float(value)


def analyse_clip(path: str, feet: str | None = None, units: Units = "auto", up: UpAxis = "auto") -> ClipRow:
    """One clip's row (never raises: an error is the row's ``error``). Runs in a worker."""
    from . import analyze_tracks
    from .sources import load_tracks

    try:
        tracks, _ = load_tracks(path, feet=feet, units=units, up=up)
        report = analyze_tracks(tracks, requested_gait=None)
    except GaitlabError as exc:
        return ClipRow(source=path, error=str(exc).splitlines()[0])
    except Exception as exc:  # a clip that breaks the analysis is a row, not the end of the batch
        return ClipRow(source=path, error=f"{type(exc).__name__}: {exc}".splitlines()[0])
    return ClipRow(source=path, gait=report.gait_match, cycle=_finite(report.cycle_seconds),
                   speed=_finite(report.speed),
                   duty={f.name: _finite(f.duty_factor) for f in report.feet},
                   phase={f.name: _finite(f.phase) for f in report.feet}, notes=tuple(report.notes))


def analyse_folder(clips: Iterable[Path], jobs: int, feet: str | None = None, units: Units = "auto",
                   up: UpAxis = "auto", progress: Callable[[ClipRow], None] | None = None) -> list[ClipRow]:
    """Rows for ``clips`` in their order, analysed by ``jobs`` processes (1: in this one);
    ``progress`` is called with each row as it finishes."""
    paths = [str(p) for p in clips]
    rows: dict[str, ClipRow] = {}
    if jobs <= 1 or len(paths) <= 1:
        for path in paths:
            rows[path] = analyse_clip(path, feet, units, up)
            if progress:
                progress(rows[path])
    else:
        # Loaded here, before the workers fork, so that no worker pays for the imports.
        from . import analyze_tracks  # noqa: F401
        from .sources import load_tracks  # noqa: F401

        with ProcessPoolExecutor(max_workers=min(jobs, len(paths))) as pool:
            futures = {pool.submit(analyse_clip, path, feet, units, up): path for path in paths}
            for future in as_completed(futures):
                try:
                    row = future.result()
                except Exception as exc:  # a worker that died (killed, out of memory): that clip's row says so
                    row = ClipRow(source=futures[future], error=f"the worker analysing it stopped: {exc}"[:300])
                rows[futures[future]] = row
                if progress:
                    progress(row)
    return [rows[path] for path in paths]


def default_jobs() -> int:
    """As many processes as this machine has cores for us."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # not on Linux
        return max(1, os.cpu_count() or 1)


def table_csv(rows: list[ClipRow]) -> str:
    """The rows as CSV text: source, gait, cycle_s, speed_m_s, duty_FOOT and phase_FOOT for
    every foot any clip has (in the order first met), notes, error."""
    feet: list[str] = []
    for row in rows:
        feet += [name for name in row.duty if name not in feet]
    out = io.StringIO()
    writer = csv.writer(out, lineterminator="\n")
    writer.writerow(["source", "gait", "cycle_s", "speed_m_s", *(f"duty_{f}" for f in feet),
                     *(f"phase_{f}" for f in feet), "notes", "error"])

    def cell(value: float | None, digits: int = 4) -> str:
        return "" if value is None else f"{value:.{digits}f}"

    for row in rows:
        writer.writerow([row.source, row.gait, cell(row.cycle), cell(row.speed),
                         *(cell(row.duty.get(f)) for f in feet), *(cell(row.phase.get(f)) for f in feet),
                         "; ".join(row.notes), row.error])
    return out.getvalue()


def table_text(rows: list[ClipRow], root: Path) -> str:
    """A short table for the terminal: one line per clip."""
    width = max(len(_short(row.source, root)) for row in rows)
    lines = [f"{'clip':{width}}  {'gait':14} {'cycle s':>8} {'speed':>7}  duty factors"]
    for row in rows:
        name = _short(row.source, root)
        if not row.ok:
            lines.append(f"{name:{width}}  error: {row.error}")
            continue
        duty = " ".join(f"{k} {v:.2f}" if v is not None else f"{k} -" for k, v in row.duty.items())
        cycle = "-" if row.cycle is None else f"{row.cycle:.3f}"
        speed = "-" if row.speed is None else f"{row.speed:.2f}"
        lines.append(f"{name:{width}}  {row.gait[:14]:14} {cycle:>8} {speed:>7}  {duty}")
    return "\n".join(lines)


def _short(source: str, root: Path) -> str:
    try:
        return str(Path(source).relative_to(root))
    except ValueError:
        return source
