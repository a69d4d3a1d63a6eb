"""Turning motion files into :class:`FootTracks`: BVH (with a foot-joint mapping) and CSV
(per-foot positions over time), with units and the up axis given or detected."""

from __future__ import annotations

import csv
import io
import os
import re
from collections import Counter
from dataclasses import dataclass, replace
from typing import Literal

import numpy as np
from numpy.typing import NDArray

from ..errors import did_you_mean, not_a_file
from .bvh import MIN_FRAME_TIME, InputError, read_bvh
from .tracks import FootTracks

Units = Literal["auto", "m", "cm", "mm", "in", "ft", "cmu"]
UNIT_SCALE: dict[str, float] = {"m": 1.0, "cm": 0.01, "mm": 0.001, "in": 0.0254, "ft": 0.3048, "cmu": 0.056444}
UpAxis = Literal["auto", "y", "z"]

# Foot-joint names of common skeletons: foot name -> (ankle/heel joint, toe joint).
KNOWN_RIGS: tuple[tuple[str, dict[str, tuple[str, tuple[str, ...]]]], ...] = (
    ("quadruped (Tencent/3ds Max dog)", {
        "LF": ("b_LeftHand", ("b__LeftFinger", "b_LeftFinger")), "RF": ("b_RightHand", ("b_RightFinger",)),
        "LH": ("b_LeftAnkle", ("b_LeftToe",)), "RH": ("b_RightAnkle", ("b_RightToe",))}),
    ("biped (CMU)", {"L": ("LeftFoot", ("LeftToeBase", "LeftToe")), "R": ("RightFoot", ("RightToeBase", "RightToe"))}),
    ("biped (Mixamo)", {"L": ("mixamorig:LeftFoot", ("mixamorig:LeftToeBase",)),
                        "R": ("mixamorig:RightFoot", ("mixamorig:RightToeBase",))}),
    ("biped (generic)", {"L": ("LeftAnkle", ("LeftToe", "LeftToes")), "R": ("RightAnkle", ("RightToe", "RightToes"))}),
)


MAX_FEET = 64
MAX_CSV_BYTES = 512 * 2**20
MAX_COORDINATE = 1e7  # larger positions or times are not motion data (and overflow the analysis)


def _shown(text: str, limit: int = 40) -> str:
    return repr(text if len(text) <= limit else text[:limit] + "...")


def check_columns_once(header: list[str], where: str) -> None:
    """Refuse a CSV header naming a column twice (one of them would be silently
    ignored); unnamed columns are not read, so they may repeat. ``where``: the message's
    file (and line) prefix."""
    counts = Counter(h for h in header if h)  # linear: a header may name thousands of columns
    twice = next((h for h, n in counts.items() if n > 1), None)
    if twice is not None:
        raise InputError(f"{where}: column {_shown(twice)} appears {counts[twice]} times in the header; "
                         "give each column once")


@dataclass(frozen=True)
class FootMap:
    """Which joints stand for each foot: name -> (heel/ankle joint, toe joint or None)."""

    feet: dict[str, tuple[str, str | None]]
    rig: str


def parse_feet(text: str) -> dict[str, tuple[str, str | None]]:
    """``LH=ANKLE[:TOE],LF=...`` -> {"LH": ("ANKLE", "TOE"), ...}."""
    feet: dict[str, tuple[str, str | None]] = {}
    for part in filter(None, (p.strip() for p in text.split(","))):
        if "=" not in part:
            raise InputError(f"--feet {text!r}: expected NAME=ANKLE[:TOE] items separated by commas, "
                             f"e.g. L=LeftFoot:LeftToeBase,R=RightFoot:RightToeBase")
        name, joints = (s.strip() for s in part.split("=", 1))
        ankle, _, toe = joints.partition(":")
        if not name or not ankle:
            raise InputError(f"--feet: {part!r}: give a foot name and its ankle joint, e.g. LH=b_LeftAnkle:b_LeftToe")
        feet[name] = (ankle, toe or None)
    if not feet:
        raise InputError("--feet is empty; give NAME=ANKLE[:TOE] items, e.g. L=LeftFoot:LeftToeBase")
    return feet


# A biped's foot joints by their usual names, whatever the tool: the name without its
# namespace (mixamorig7:, Armature|) and separators, in lower case, is a side word (left,
# right, l, r) before or after a part word (Bip01 L Foot, L_Foot, lfoot, foot.L, foot_l).
_SIDES = (("left", "L"), ("right", "R"), ("l", "L"), ("r", "R"))
_ANKLE_WORDS = ("ankle", "foot")  # in order of preference (SMPL: L_Ankle, then L_Foot below it)
_TOE_WORDS = ("toebase", "toe", "toes", "toe0", "toe1", "ball", "toetip")
_PREFIXES = re.compile(r"^(bip0*1|biped|b)(?=l|r)")  # 3ds Max Biped, b_ rigs


def _side_and_part(name: str) -> tuple[str, str] | None:
    bare = re.split(r"[:|]", name)[-1]
    key = _PREFIXES.sub("", re.sub(r"[^a-z0-9]", "", bare.lower()))
    for word, side in _SIDES:
        for part in (*_ANKLE_WORDS, *_TOE_WORDS):
            if key in (word + part, part + word):
                return side, part
    return None


def _named_biped(names: list[str]) -> FootMap | None:
    """Left and right ankle and toe joints found by :func:`_side_and_part` (a toe that is
    not named: the ankle's End Site, when it has one)."""
    found: dict[tuple[str, str], str] = {}
    for name in names:
        hit = _side_and_part(name)
        if hit is not None and hit not in found:
            found[hit] = name
    feet: dict[str, tuple[str, str | None]] = {}
    for side in ("L", "R"):
        ankle = next((found[(side, w)] for w in _ANKLE_WORDS if (side, w) in found), None)
        if ankle is None:
            return None
        toe = next((found[(side, w)] for w in _TOE_WORDS if (side, w) in found), None)
        if toe is None and (side, "ankle") in found and (side, "foot") in found:
            toe = found[(side, "foot")]  # an ankle with a foot joint below it (SMPL)
        if toe is None and f"{ankle}/End" in names:
            toe = f"{ankle}/End"
        feet[side] = (ankle, toe)
    return FootMap(feet, "biped (by joint names)")


def resolve_feet(feet: dict[str, tuple[str, str | None]], names: list[str]) -> dict[str, tuple[str, str | None]]:
    """``--feet`` items whose names hold colons themselves (namespaces: mixamorig7:LeftFoot)
    split where both halves are joints of the clip; the rest as given."""
    present = set(names)
    out: dict[str, tuple[str, str | None]] = {}
    for foot, (ankle, toe) in feet.items():
        text = ankle if toe is None else f"{ankle}:{toe}"
        if ankle in present and (toe is None or toe in present):
            out[foot] = (ankle, toe)
            continue
        if text in present:
            out[foot] = (text, None)
            continue
        splits = [(text[:i], text[i + 1:]) for i, c in enumerate(text) if c == ":"]
        out[foot] = next(((a, t) for a, t in splits if a in present and t in present), (ankle, toe))
    return out


def find_feet(names: list[str], path: str) -> FootMap:
    """The feet of a skeleton with one of the known naming schemes (see KNOWN_RIGS); a
    toe joint that ends in an End Site stands for that tip (the tips of the toes stay
    down through push-off while the toe joint rolls forward)."""
    found = _find_feet(names, path)
    present = set(names)
    return FootMap({foot: (ankle, f"{toe}/End" if toe and toe != ankle and f"{toe}/End" in present else toe)
                    for foot, (ankle, toe) in found.feet.items()}, found.rig)


def _find_feet(names: list[str], path: str) -> FootMap:
    present = set(names)
    for rig, mapping in KNOWN_RIGS:
        feet = {}
        for foot, (ankle, toes) in mapping.items():
            if ankle not in present:
                break
            feet[foot] = (ankle, next((t for t in toes if t in present), None))
        else:
            return FootMap(feet, rig)
    # Gaitlab's own exports: NAME_ball and NAME_toe for every foot (the same points that
    # Gaitlab's analysis of its own motion uses).
    exported = [n[:-5] for n in names if n.endswith("_ball") and f"{n[:-5]}_toe" in present]
    if exported:
        return FootMap({foot: (f"{foot}_ball", f"{foot}_toe") for foot in exported}, "Gaitlab export")
    biped = _named_biped(names)
    if biped is not None:
        return biped
    names = [n for n in names if not n.endswith("/End")]  # End Sites are no joints to name here
    ankles = [n for n in names if re.search(r"(foot|ankle|toe|hand|paw|hoof)", n, re.IGNORECASE)]
    shown = ", ".join(ankles[:12] or names[:12]) + (" ..." if len(ankles or names) > 12 else "")
    raise InputError(f"{path}: no feet recognised among the joints ({shown}); map them with "
                     "--feet LH=ANKLE[:TOE],RH=...,LF=...,RF=... (quadruped) or --feet L=LeftFoot:LeftToeBase,"
                     "R=RightFoot:RightToeBase (biped)")


def _to_y_up(points: np.ndarray, up: str) -> np.ndarray:
    """Re-express (..., 3) points so that ``up`` becomes +Y (right-handed)."""
    if up == "z":
        return np.stack([points[..., 0], points[..., 2], -points[..., 1]], axis=-1)
    return points


def detect_up(body: np.ndarray, feet: np.ndarray) -> str:
    """The axis along which the body is highest above the feet: 'y' or 'z'."""
    lift = np.median(body[:, None, :] - feet, axis=(0, 1))
    return "z" if lift[2] > lift[1] else "y"


def detect_units(height: float) -> tuple[str, str]:
    """Units from a hip height in file units: (units, reason)."""
    if 0.1 <= height <= 3.0:
        return "m", f"hip height {height:.2f} units reads as metres"
    if 3.0 < height < 25.0:
        return "cmu", f"hip height {height:.1f} units reads as CMU mocap units (0.056444 m)"
    if 25.0 <= height <= 300.0:
        return "cm", f"hip height {height:.0f} units reads as centimetres"
    if 300.0 < height <= 3000.0:
        return "mm", f"hip height {height:.0f} units reads as millimetres"
    raise InputError(f"cannot tell the units from a hip height of {height:g}; give --units m, cm, mm, in, ft or cmu")


def _leading_jumps(points: np.ndarray, limit: int = 5) -> int:
    """How many leading frames jump to the motion (e.g. a T-pose at frame 0 of a mocap
    take): frames whose step to the next is far larger than the clip's typical step."""
    step = np.linalg.norm(np.diff(points, axis=0), axis=-1).max(axis=-1)  # (T-1,)
    typical = float(np.median(step)) + 1e-12
    skip = 0
    while skip < min(limit, len(step) - 2) and step[skip] > 8.0 * typical:
        skip += 1
    return skip


INCH_HIPS = (25.0, 60.0)  # hip heights (file units) that read as a small animal in cm or a person in inches
STRIDE_TIME = {"walk": 3.4, "run": 2.6}  # a stride's period in units of sqrt(hip height / g)


def _centimetres_or_inches(times, names, heel, toe, body, hip: float, reason: str) -> tuple[str, str]:
    """Centimetres or inches for a hip height both could be (a 36 cm dog, a 36 in person),
    by dynamic similarity: the one that makes the stride's period nearer to an animal's of
    that size walking or running as the clip does (:data:`STRIDE_TIME` times sqrt(h / g);
    a walk when the feet are down more than half the time); centimetres when the clip has
    no clear stride."""
    from . import analyze_tracks
    from .events import AnalysisError

    provisional = FootTracks(times=np.asarray(times, dtype=np.float64), names=tuple(names), heel=heel * 0.01,
                             toe=toe * 0.01, body=body * 0.01, source="", hip_height=hip * 0.01)
    try:
        report = analyze_tracks(provisional)
    except AnalysisError:
        return "cm", reason
    period = float(report.cycle_seconds)
    duties = [f.duty_factor for f in report.feet if f.duty_factor is not None and np.isfinite(f.duty_factor)]
    if not (np.isfinite(period) and period > 0 and duties):
        return "cm", reason
    expected = STRIDE_TIME["walk" if float(np.mean(duties)) > 0.5 else "run"]
    misfit = {unit: abs(np.log(period * np.sqrt(9.81 / (hip * UNIT_SCALE[unit])) / expected))
              for unit in ("cm", "in")}
    if misfit["in"] < misfit["cm"]:
        return "in", (f"hip height {hip:.0f} units with a {period:.2f} s stride reads as inches (in centimetres the "
                      "stride would be too slow for so small an animal)")
    return "cm", reason


def _finish(path: str, times, names, heel, toe, body, units: Units, up: UpAxis,
            hands=None) -> tuple[FootTracks, str]:
    if len(times) < 2:
        raise InputError(f"{path}: the clip holds {len(times)} frame{'' if len(times) == 1 else 's'}; analysing a "
                         "gait needs at least one full stride")
    for what, values in (("foot", heel), ("toe", toe), ("body", body)):
        if not np.all(np.abs(values) < MAX_COORDINATE):
            raise InputError(f"{path}: {what} positions reach {float(np.nanmax(np.abs(values))):.3g} (or are not "
                             f"finite); positions must be under {MAX_COORDINATE:g} in file units")
    skip = _leading_jumps(np.concatenate([heel, toe, body[:, None]], axis=1))
    times, heel, toe, body = times[skip:] - times[skip], heel[skip:], toe[skip:], body[skip:]
    up_axis = detect_up(body, heel) if up == "auto" else up
    heel, toe, body = (_to_y_up(a, up_axis) for a in (heel, toe, body))
    if hands is not None:
        hands = _to_y_up(hands[skip:], up_axis)
    hip = float(np.median(body[:, 1] - heel[..., 1].min(axis=1)))
    notes = []
    if units == "auto":
        detected, reason = detect_units(abs(hip))
        if detected == "cm" and INCH_HIPS[0] <= abs(hip) <= INCH_HIPS[1]:
            detected, reason = _centimetres_or_inches(times, names, heel, toe, body, abs(hip), reason)
        notes.append(f"units {detected} ({reason}; --units to override)")
        scale = UNIT_SCALE[detected]
    else:
        scale = UNIT_SCALE[units]
    if up == "auto":
        notes.append(f"up axis {up_axis.upper()}")
    if skip:
        notes.append(f"skipped {skip} leading frame{'s' if skip > 1 else ''} that jump into the motion (a rest pose)")
    tracks = FootTracks(times=np.asarray(times, dtype=np.float64), names=tuple(names), heel=heel * scale,
                        toe=toe * scale, body=body * scale, source=path, hip_height=hip * scale,
                        hands=None if hands is None else hands * scale, unit_scale=scale)
    return tracks, "; ".join(notes)


def tracks_from_bvh(path: str, feet: dict[str, tuple[str, str | None]] | None = None, units: Units = "auto",
                    up: UpAxis = "auto") -> tuple[FootTracks, str]:
    """Foot tracks of a BVH clip and a note on what was detected. The ankle joint is the
    heel proxy; without a toe joint the ankle stands for both."""
    clip = read_bvh(path)
    mapping = FootMap(resolve_feet(feet, clip.names), "given with --feet") if feet else find_feet(clip.names, path)
    for foot, (ankle, toe_joint) in mapping.feet.items():
        for joint in (ankle, toe_joint):
            if joint is not None and joint not in clip.names:
                raise InputError(f"{path}: --feet {foot}: no joint {joint!r}{did_you_mean(joint, clip.names)}; "
                                 f"joints are {', '.join(clip.names[:20])}{' ...' if len(clip.names) > 20 else ''}")
    names = list(mapping.feet)
    ankles = [mapping.feet[n][0] for n in names]
    toes = [mapping.feet[n][1] or mapping.feet[n][0] for n in names]
    pos = clip.positions(ankles + toes + [clip.joints[0].name])
    heel, toe, body = pos[:, :len(names)], pos[:, len(names):2 * len(names)], pos[:, -1]
    hands: NDArray[np.float64] | None = None
    if names == ["L", "R"]:  # a biped's hands, when the skeleton names them: the arms' phase
        for prefix in ("", "mixamorig:"):
            if f"{prefix}LeftHand" in clip.names and f"{prefix}RightHand" in clip.names:
                hands = clip.positions([f"{prefix}LeftHand", f"{prefix}RightHand"])
                break
    times = np.arange(clip.frames.shape[0]) * clip.frame_time
    tracks, note = _finish(path, times, names, heel, toe, body, units, up, hands)
    if mapping.rig == "Gaitlab export":  # Gaitlab's own motion, noise-free: read as exactly as it was made
        tracks = replace(tracks, exact=True)
    return tracks, f"{mapping.rig}: " + ", ".join(f"{n}={a}:{t}" for n, (a, t) in mapping.feet.items()) + (
        f"; {note}" if note else "")


def tracks_from_csv(path: str, units: Units = "m", up: UpAxis = "y") -> tuple[FootTracks, str]:
    """Foot tracks from a CSV with a ``time`` column (s) and, per foot, ``NAME_x``,
    ``NAME_y``, ``NAME_z`` (heel / ankle) and optionally ``NAME_toe_x`` .. ``NAME_toe_z``;
    optionally ``body_x`` .. ``body_z`` (default: the mean of the feet)."""
    try:
        with open(path, "rb") as fh:
            raw = fh.read(MAX_CSV_BYTES + 1)
        if len(raw) > MAX_CSV_BYTES:
            raise InputError(f"{path}: the file is over {MAX_CSV_BYTES // 2**20} MiB; CSV files up to that size "
                             "are read")
        rows = list(csv.reader(io.StringIO(raw.decode("utf-8-sig"), newline="")))  # -sig: a spreadsheet's BOM
    except OSError as exc:
        raise InputError(f"{path}: cannot read: {exc.strerror or exc}") from None
    except (csv.Error, UnicodeDecodeError) as exc:
        raise InputError(f"{path}: malformed CSV: {exc}") from None
    if not rows:
        raise InputError(f"{path}:1: empty CSV; expected a header like time,LH_x,LH_y,LH_z,...")
    header = [h.strip() for h in rows[0]]
    if "time" not in header:
        raise InputError(f"{path}:1: missing column 'time' (seconds); the header is {','.join(header)}")
    check_columns_once(header, f"{path}:1")
    feet = list(dict.fromkeys(h[:-2] for h in header if h.endswith(("_x", "_y", "_z"))
                              and not h[:-2].endswith("_toe") and h[:-2] != "body"))
    if not feet:
        raise InputError(f"{path}:1: no foot columns; expected NAME_x,NAME_y,NAME_z for each foot (e.g. LH_x)")
    if len(feet) > MAX_FEET:
        raise InputError(f"{path}:1: {len(feet)} feet in the header; at most {MAX_FEET} are analysed")
    columns = set(header)
    missing = [f"{f}_{a}" for f in feet for a in "xyz" if f"{f}_{a}" not in columns]
    missing += [f"{f}_toe_{a}" for f in feet for a in "xyz"
                if any(f"{f}_toe_{b}" in columns for b in "xyz") and f"{f}_toe_{a}" not in columns]
    if any(f"body_{a}" in columns for a in "xyz"):
        missing += [f"body_{a}" for a in "xyz" if f"body_{a}" not in columns]
    if missing:
        raise InputError(f"{path}:1: missing columns {', '.join(missing)}; each foot needs NAME_x, NAME_y, NAME_z "
                         "(and NAME_toe_x/y/z if any toe column is given)")
    data = np.empty((len(rows) - 1, len(header)))
    for r, row in enumerate(rows[1:]):
        line = r + 2
        if len(row) != len(header):
            raise InputError(f"{path}:{line}: malformed CSV: {len(row)} values, the header has {len(header)}")
        for c, value in enumerate(row):
            try:
                data[r, c] = float(value)
            except ValueError:
                raise InputError(f"{path}:{line}: malformed CSV: column {_shown(header[c])} value {_shown(value)} "
                                 "is not a number") from None
            if not abs(data[r, c]) < MAX_COORDINATE:
                raise InputError(f"{path}:{line}: column {_shown(header[c])} is {_shown(value)}; values must be "
                                 f"finite and under {MAX_COORDINATE:g} in size")
    if data.shape[0] < 2:
        raise InputError(f"{path}: the CSV holds {data.shape[0]} rows; a clip needs at least one full stride")
    col = {h: i for i, h in enumerate(header)}
    times = data[:, col["time"]]
    too_soon = np.nonzero(np.diff(times) < MIN_FRAME_TIME)[0]
    if len(too_soon):
        bad = int(too_soon[0]) + 3
        raise InputError(f"{path}:{bad}: time must increase from row to row, by at least {MIN_FRAME_TIME:g} s "
                         f"(a {1 / MIN_FRAME_TIME:,.0f} Hz capture)")
    heel = np.stack([data[:, [col[f"{f}_x"], col[f"{f}_y"], col[f"{f}_z"]]] for f in feet], axis=1)
    has_toe = all(f"{f}_toe_x" in col for f in feet)
    toe = np.stack([data[:, [col[f"{f}_toe_x"], col[f"{f}_toe_y"], col[f"{f}_toe_z"]]] for f in feet], axis=1) \
        if has_toe else heel.copy()
    body = data[:, [col["body_x"], col["body_y"], col["body_z"]]] if "body_x" in col else heel.mean(axis=1)
    return _finish(path, times - times[0], feet, heel, toe, body, units, up)


def load_tracks(source: str, feet: str | None = None, units: Units = "auto", up: UpAxis = "auto") \
        -> tuple[FootTracks, str]:
    """Tracks from a .bvh or .csv file (by suffix)."""
    suffix = os.path.splitext(source)[1].lower()
    if not os.path.isfile(source):
        raise InputError(f"{source}: {not_a_file(source)}")
    if suffix == ".bvh":
        return tracks_from_bvh(source, parse_feet(feet) if feet else None, units, up)
    if suffix == ".csv":
        if feet:
            raise InputError("--feet applies to BVH files; a CSV names its feet in the header (NAME_x, NAME_y, NAME_z)")
        return tracks_from_csv(source, "m" if units == "auto" else units, "y" if up == "auto" else up)
    raise InputError(f"{source}: unknown motion file type {suffix!r}; analyze reads .bvh and .csv files, or a "
                     "creature (preset name or .toml)")
