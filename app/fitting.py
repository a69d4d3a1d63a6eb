"""``gaitlab fit``: a creature made to move like a motion-capture clip.

1. **Analyse the clip** as ``gaitlab analyze`` does: cycle, speed, each foot's duty
   factor and phase, the gait's name.
2. **Body from the skeleton** (BVH): each leg's segment lengths (hip to knee, knee to
   ankle, ankle to toe joint; medians over the clip, in metres by the clip's detected
   units), the hips' width, a quadruped's trunk between its girdles, a biped's arms. A
   biped starts from the ``human`` preset, a quadruped from the ``dog``; what the clip
   does not show (head, tail, toes beyond the toe joint) is the preset's, scaled by leg
   length.
3. **Gait from the analysis**: frequency 1 / cycle, one duty factor midway between the feet's, each
   foot's phase, the stride that gives the clip's speed at that frequency and duty
   (speed = stride x frequency / duty), the step height from how high the toes rise.
4. **Refined** (bipeds): a small optimisation (scipy's Nelder-Mead, a wide search then a
   restart round the best point) of what shapes the joint angles against the clip's own
   sagittal hip and knee curves (``gaitlab compare``'s): the four key-pose heights (the
   body low or high at contact, down, pass, up: how bent the knee stands), the foot angle
   at strike, the leg's natural bend, its roll and the step height. A quadruped's joints
   above its foot differ from rig to rig (the Tencent dog's foot joint is the ball), so
   its angle curves are not compared. Then, for both, the gait is calibrated against
   Gaitlab's own measurement of the creature (``gaitlab analyze``'s: its duty, cycle and
   speed brought onto the clip's in a few corrections). Gaitlab gives every foot one duty
   factor: the fit takes the one midway between the clip's feet's.

Everything here is plain numpy and scipy on top of the spec, the rig and the analysis.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from .analysis import GaitReport, analyze_tracks, tracks_from_motion
from .analysis.bvh import read_bvh
from .analysis.compare import compare_curves, leg_curves
from .analysis.limbs import Legs, bvh_legs, leg_chains, motion_legs
from .analysis.sources import load_tracks
from .errors import GaitlabError
from .gaits import GAIT_PRESETS
from .kinematics.clip import clip_motion
from .kinematics.gait import WALK_DUTY
from .kinematics.walker import SWING_KNEE, SWING_KNEE_RANGE
from .rigging import build_rig
from .spec import SCALED_BODY_KEYS, CreatureSpec, creature_from_dict, load_creature

BASE = {2: "human", 4: "dog"}  # the preset a clip with this many feet starts from
FEET = {2: ("L", "R"), 4: ("LF", "RF", "LH", "RH")}
MIN_SPEED = 1e-3  # m/s: a clip slower than this walks in place
LEG_RANGE = (0.05, 5.0)  # m: legs outside this are the wrong units
MAX_RETIME = 1.5  # a calibration round changes the frequency by at most this factor either way
FIT_FPS = 120.0  # frames per second of the creature's motion while fitting
FIT_CYCLES = 4.0  # cycles of it measured per evaluation
REFINE_EVALUATIONS = 300  # Nelder-Mead's budget of motions solved
CALIBRATIONS = 5  # rounds (at most) of bringing the measured duty, cycle and speed onto the clip's
CALIBRATED = (0.002, 0.003, 0.005)  # close enough: duty, and cycle and speed as fractions
TIMING_KEPT = 0.03  # a refined fit whose duty (or cycle, as a fraction) misses by more falls back to unrefined poses
JOINTS = ("hip", "knee")  # the curves the refinement matches

Progress = Callable[[str], None]


@dataclass(frozen=True)
class FitResult:
    """The fitted creature, the clip's analysis and the creature's own, and how close its
    joint angles came to the clip's (joint -> RMS degrees over a cycle, per compared leg)."""

    spec: CreatureSpec
    clip: GaitReport
    fitted: GaitReport
    rms: dict[str, dict[str, float]]
    measured: dict[str, Any] = field(default_factory=dict)  # what was read off the skeleton
    note: str = ""  # why the joint angles were not compared, or were not refined

    def summary(self) -> str:
        """What was fitted and how close it came, for the terminal."""
        g = self.spec.gait
        lines = [f"fitted     {self.spec.name} from {self.clip.source}",
                 "body       " + ", ".join(f"{k} {v:.3f} m" for k, v in self.measured.items()),
                 f"gait       {g.preset}: frequency {g.frequency:.3f} Hz, duty {g.duty_factor:.3f}, stride "
                 f"{g.stride:.3f} leg lengths, step height {g.step_height:.3f}"]
        if self.spec.poses.contact_height is not None:
            p = self.spec.poses
            angle = "" if p.foot_angle is None else f"; foot angle {p.foot_angle:.1f} deg"
            angle += "" if p.swing_knee is None else f", swing knee {p.swing_knee:.1f} deg"
            lines.append(f"poses      heights contact {p.contact_height:+.3f}, down {p.down_height:+.3f}, pass "
                         f"{p.pass_height:+.3f}, up {p.up_height:+.3f} m{angle}")
        lines.append("")
        lines.append(f"{'':12}{'clip':>10}{'creature':>10}")
        lines.append(f"{'cycle (s)':12}{self.clip.cycle_seconds:10.3f}{self.fitted.cycle_seconds:10.3f}")
        lines.append(f"{'speed (m/s)':12}{self.clip.speed:10.3f}{self.fitted.speed:10.3f}")
        for foot in self.clip.feet:
            mine = self.fitted.foot(foot.name)
            lines.append(f"{'duty ' + foot.name:12}{_num(foot.duty_factor):>10}{_num(mine.duty_factor):>10}")
        lines.append(f"{'duty (one)':12}{mean_duty(self.clip):10.3f}{mean_duty(self.fitted):10.3f}")
        for leg, joints in self.rms.items():
            lines.append(f"RMS {leg:8}" + "  ".join(f"{j} {v:.1f} deg" for j, v in joints.items())
                         + "  (joint angles against the clip's, over a cycle)")
        if not self.rms:
            lines.append(f"joint angles not compared: {self.note}")
        elif self.note:
            lines.append(f"note: {self.note}")
        return "\n".join(lines)


def _num(x: float | None) -> str:
    return "-" if x is None or not math.isfinite(x) else f"{x:.3f}"


def mean_duty(report: GaitReport) -> float:
    """The duty factor one number gives the feet best: midway between the lowest and the
    highest foot's (the mean, for two feet), nearest to every foot's at once."""
    values = [f.duty_factor for f in report.feet if f.duty_factor is not None and math.isfinite(f.duty_factor)]
    if not values:
        raise GaitlabError(f"{report.source}: no foot's duty factor could be measured; fit needs whole steps")
    return float(0.5 * (min(values) + max(values)))


def _median_length(points: NDArray[np.float64], a: int, b: int) -> float:
    return float(np.median(np.linalg.norm(points[:, b] - points[:, a], axis=-1)))


_NOT_LIMB = ("clav", "collar", "shoulder", "scap", "pelvis", "hip", "spine", "root", "body", "chest", "neck")


def _whole_limb(clip, chain: tuple[str, str, str, str]) -> tuple[str, str, str, str]:
    """A limb chain (hip, knee, ankle, toe) moved up one joint where the "hip" still has a
    limb bone of the same side above it (the Tencent dog's hind leg: LegUpper, Leg, Leg1,
    Ankle, Toe, whose foot joint is the ball): then hip, knee, ankle and ball."""
    hip = clip.joints[clip.index(chain[0])]
    if hip.parent < 0:
        return chain
    parent = clip.joints[hip.parent].name
    low = parent.lower()
    side = next((w for w in ("left", "right") if w in chain[2].lower()), None)
    if side is None or side not in low or any(word in low for word in _NOT_LIMB):
        return chain
    return (parent, chain[0], chain[1], chain[2])


def measure_skeleton(path: str, feet: dict[str, tuple[str, str | None]] | None, scale: float) -> dict[str, Any]:
    """Lengths (m) read off a BVH skeleton: per foot (femur, tibia, metatarsus); the hips'
    width (biped) or each girdle's (quadruped); a quadruped's girdle-to-girdle length; a
    biped's arm segments when the skeleton names them (CMU, Mixamo)."""
    clip = read_bvh(path)
    _, found = leg_chains(clip, path, feet)
    chains = {foot: _whole_limb(clip, chain) for foot, chain in found.items()}
    names = [n for chain in chains.values() for n in chain]
    points = clip.positions(names) * scale  # (T, 4F, 3)
    legs = {}
    for i, foot in enumerate(chains):
        k = 4 * i
        legs[foot] = (_median_length(points, k, k + 1), _median_length(points, k + 1, k + 2),
                      _median_length(points, k + 2, k + 3))
    hip = {foot: points[:, 4 * i] for i, foot in enumerate(chains)}
    out: dict[str, Any] = {"legs": legs}
    if set(chains) == {"L", "R"}:
        out["width"] = float(np.median(np.linalg.norm(hip["L"] - hip["R"], axis=-1)))
        for prefix in ("", "mixamorig:"):
            arm = [f"{prefix}LeftArm", f"{prefix}LeftForeArm", f"{prefix}LeftHand"]
            if all(n in clip.names for n in arm):
                a = clip.positions(arm) * scale
                out["arms"] = (_median_length(a, 0, 1), _median_length(a, 1, 2))
                break
    elif set(chains) == {"LF", "RF", "LH", "RH"}:
        fore = 0.5 * (hip["LF"] + hip["RF"])
        hind = 0.5 * (hip["LH"] + hip["RH"])
        out["length"] = float(np.median(np.linalg.norm(fore - hind, axis=-1)))
        out["fore_width"] = float(np.median(np.linalg.norm(hip["LF"] - hip["RF"], axis=-1)))
        out["hind_width"] = float(np.median(np.linalg.norm(hip["LH"] - hip["RH"], axis=-1)))
    return out


def _leg_of(doc: dict[str, Any], foot: str) -> str:
    """The creature file's leg table a foot belongs to (``legs`` for a biped's one pair,
    ``fore``/``hind`` for a quadruped's)."""
    names = list(doc["legs"])
    if len(names) == 1:
        return names[0]
    return names[0] if foot.endswith("F") else names[-1]


def _body_from_skeleton(doc: dict[str, Any], skeleton: dict[str, Any]) -> float:
    """Write the skeleton's lengths into the creature document; returns how much longer
    (a ratio) its legs are than the preset's (the scale of what the clip does not show)."""
    ratios = []
    for table_name in doc["legs"]:
        table = doc["legs"][table_name]
        lengths = [v for foot, v in skeleton["legs"].items() if _leg_of(doc, foot) == table_name]
        if not lengths:
            continue
        femur, tibia, metatarsus = (float(np.mean([leg[k] for leg in lengths])) for k in range(3))
        old = table["femur"] + table["tibia"] + table["metatarsus"]
        ratios.append((femur + tibia + metatarsus) / old)
        table["femur"], table["tibia"], table["metatarsus"] = round(femur, 4), round(tibia, 4), round(metatarsus, 4)
    ratio = float(np.mean(ratios)) if ratios else 1.0
    body = doc["body"]
    for key in SCALED_BODY_KEYS:
        if key in body and isinstance(body[key], (int, float)):
            body[key] = round(body[key] * ratio, 4)
    body["radius"] = [round(r * ratio, 4) for r in body["radius"]]
    for table in doc["legs"].values():
        for key in ("toe", "heel", "radius", "hip_offset"):
            if key in table:
                table[key] = round(table[key] * ratio, 4)
    if "width" in skeleton:
        body["width"] = round(skeleton["width"], 4)
    if "length" in skeleton:
        body["length"] = round(skeleton["length"], 4)
        body["width"] = round(0.5 * (skeleton["fore_width"] + skeleton["hind_width"]), 4)
    if "arms" in skeleton and "arms" in doc:
        doc["arms"]["upper"], doc["arms"]["fore"] = (round(v, 4) for v in skeleton["arms"])
        for key in ("hand", "shoulder_width", "radius"):
            doc["arms"][key] = round(doc["arms"][key] * ratio, 4)
    return ratio


def _step_height(report: GaitReport, leg_rest: float) -> float:
    """How high (leg rest lengths) the toes rise in swing: the median over feet of the
    95th percentile of toe height above the 5th."""
    tracks = report.tracks
    if tracks is None:
        return 0.05
    toe = tracks.toe[..., 1]
    rise = np.percentile(toe, 95, axis=0) - np.percentile(toe, 5, axis=0)
    return float(np.clip(np.median(rise) / max(leg_rest, 1e-6), 0.0, 0.5))


def _simulate(spec: CreatureSpec):
    rig = build_rig(spec)
    fps = float(max(FIT_FPS, math.ceil(200 * rig.gait.frequency)))
    motion, _ = clip_motion(rig, fps, cycles=FIT_CYCLES + 1.0)
    return rig, motion


def _own_report(spec: CreatureSpec) -> GaitReport:
    """Gaitlab's analysis of the creature, as ``gaitlab analyze`` makes it (four cycles at
    about 200 frames a cycle)."""
    rig = build_rig(spec)
    motion, _ = clip_motion(rig, float(max(FIT_FPS, math.ceil(200 * rig.gait.frequency))), cycles=4.0)
    return analyze_tracks(tracks_from_motion(motion))


def _rms(spec: CreatureSpec, reference: dict[str, Any], joints: tuple[str, ...] = JOINTS) -> dict[str, dict[str, float]]:
    """RMS degrees per compared leg and joint of ``spec``'s motion against the clip's curves."""
    rig, motion = _simulate(spec)
    legs = motion_legs(motion)
    out = {}
    for leg, curves in reference.items():
        mine = leg_curves(legs, leg, contact_fraction=rig.gait.duty_factor)
        comparison = compare_curves(mine, curves)
        out[leg] = {j: float(comparison.rms[j]) for j in joints if j in comparison.rms}
    return out


def _compared_legs(clip_legs: Legs) -> dict[str, Any]:
    """The clip's legs to match: a biped's left. (A quadruped's joints above its foot
    joint differ from rig to rig: the Tencent dog's hind "ankle" is the ball, so its chain
    reads the knee as a hip, and fore-limb angle conventions differ; quadrupeds are fitted
    by their gait and skeleton, not refined against angle curves.)"""
    return {"L": leg_curves(clip_legs, "L")} if "L" in clip_legs.angles else {}


def _refine(doc: dict[str, Any], keys: list[str], start: list[float], bounds: list[tuple[float, float]],
            reference: dict[str, Any], name: str, progress: Progress | None) -> dict[str, Any]:
    """Nelder-Mead over ``keys`` (dotted paths into the document) against the clip's hip
    and knee curves; returns the best document."""
    from scipy.optimize import minimize

    lo, hi = np.array([b[0] for b in bounds]), np.array([b[1] for b in bounds])
    span = hi - lo
    best: dict[str, Any] = {"cost": np.inf, "doc": doc}
    count = [0]

    def build(x: NDArray[np.float64]) -> dict[str, Any]:
        trial = _copy(doc)
        for key, value in zip(keys, np.clip(lo + x * span, lo, hi)):
            _set(trial, key, round(float(value), 4))
        return trial

    def cost(x: NDArray[np.float64]) -> float:
        count[0] += 1
        trial = build(x)
        try:
            rms = _rms(creature_from_dict(trial, source=name), reference)
        except GaitlabError:
            return 1e6
        values = [v for joints in rms.values() for v in joints.values()]
        value = float(0.5 * (np.mean(values) + np.max(values)))  # close on every joint, not one at another's cost
        if value < best["cost"]:
            best.update(cost=value, doc=trial)
        if progress is not None:
            progress(f"refining: {count[0]}/{REFINE_EVALUATIONS} motions, best mean RMS {best['cost']:.1f} deg")
        return value

    x = (np.array(start) - lo) / span
    for step, share in ((0.25, 0.6), (0.08, 0.4)):  # a wide search, then a restart round the best point
        simplex = np.vstack([x] + [np.clip(x + step * np.eye(len(keys))[i], 0.0, 1.0) for i in range(len(keys))])
        result = minimize(cost, x, method="Nelder-Mead", options={
            "maxfev": int(share * REFINE_EVALUATIONS), "initial_simplex": simplex, "xatol": 1e-3, "fatol": 0.02})
        x = np.clip(result.x, 0.0, 1.0)
    return best["doc"]


def _copy(doc: dict[str, Any]) -> dict[str, Any]:
    import copy

    return copy.deepcopy(doc)


def _set(doc: dict[str, Any], key: str, value: Any) -> None:
    *path, last = key.split(".")
    table = doc
    for part in path:
        table = table.setdefault(part, {})
    table[last] = value


def _timing_miss(doc: dict[str, Any], clip: GaitReport) -> float:
    """How far Gaitlab's own analysis of ``doc`` misses the clip's timing: the larger of
    the duty factor's miss and the cycle's relative miss (inf when unreadable)."""
    try:
        own = _own_report(creature_from_dict(doc, source=clip.source))
    except GaitlabError:
        return math.inf
    return max(abs(mean_duty(own) - mean_duty(clip)), abs(own.cycle_seconds / clip.cycle_seconds - 1.0))


def _calibrate(doc: dict[str, Any], clip: GaitReport, name: str, progress: Progress | None) -> dict[str, Any]:
    """Bring Gaitlab's own measured duty, cycle and speed onto the clip's: each round
    simulates the creature, analyses it and corrects the asked-for values by the misses."""
    target_duty, target_cycle, target_speed = mean_duty(clip), clip.cycle_seconds, clip.speed
    for round_ in range(CALIBRATIONS):
        if progress is not None:
            progress(f"calibrating the gait: round {round_ + 1}/{CALIBRATIONS}")
        try:
            own = _own_report(creature_from_dict(doc, source=name))
            duty_now = mean_duty(own)
        except GaitlabError:
            break  # (a motion the analysis cannot read: keep the values asked for)
        if not all(math.isfinite(v) and v > 0 for v in (own.cycle_seconds, own.speed, duty_now)):
            break
        misses = (abs(target_duty - duty_now), abs(own.cycle_seconds / target_cycle - 1.0),
                  abs(own.speed / target_speed - 1.0))
        if all(m <= limit for m, limit in zip(misses, CALIBRATED)):
            break
        gait = doc["gait"]
        duty = float(np.clip(gait["duty_factor"] + np.clip(target_duty - duty_now, -0.1, 0.1), 0.1, 0.9))
        retime = float(np.clip(own.cycle_seconds / target_cycle, 1.0 / MAX_RETIME, MAX_RETIME))
        frequency = float(np.clip(gait["frequency"] * retime, 0.05, 19.0))
        # speed = stride x frequency / duty: the stride makes up for the speed missed and
        # for the new frequency and duty.
        stride = gait["stride"] * (target_speed / own.speed) * (duty / gait["duty_factor"]) \
            * (gait["frequency"] / frequency)
        gait.update(duty_factor=round(duty, 4), frequency=round(frequency, 4),
                    stride=round(float(np.clip(stride, 0.05, 2.0)), 4))
    return doc


def fit_clip(path: str, feet: dict[str, tuple[str, str | None]] | None = None, units: str = "auto",
             up: str = "auto", name: str | None = None, refine: bool = True,
             progress: Progress | None = None) -> FitResult:
    """A creature that moves like the BVH clip at ``path`` (see the module docstring).
    Raises :class:`GaitlabError` (one line) for a clip it cannot fit."""
    source = Path(path)
    if source.suffix.lower() != ".bvh":
        raise GaitlabError(f"{path}: fit reads BVH clips (it needs the skeleton's bones)")
    feet_text = None if feet is None else ",".join(f"{k}={a}" + (f":{t}" if t else "") for k, (a, t) in feet.items())
    tracks, _ = load_tracks(path, feet_text, units, up)  # type: ignore[arg-type]
    clip = analyze_tracks(tracks)
    count = len(tracks.names)
    if count not in BASE or set(tracks.names) != set(FEET[count]):
        raise GaitlabError(f"{path}: feet {', '.join(tracks.names)}; fit makes bipeds (feet L, R) and quadrupeds "
                           "(LF, RF, LH, RH): name the feet so with --feet")
    if not math.isfinite(clip.cycle_seconds) or clip.cycle_seconds <= 0:
        raise GaitlabError(f"{path}: no repeating step found; fit needs at least one whole stride")
    if not (math.isfinite(clip.speed) and clip.speed > MIN_SPEED):
        raise GaitlabError(f"{path}: the clip walks in place (speed {clip.speed:.2f} m/s); fit needs a clip that "
                           "travels (its stride is the distance covered)")
    clip_duty = mean_duty(clip)
    skeleton = measure_skeleton(path, feet, tracks.unit_scale)
    longest = max(sum(leg) for leg in skeleton["legs"].values())
    if not LEG_RANGE[0] <= longest <= LEG_RANGE[1]:
        raise GaitlabError(f"{path}: its legs read {longest:.3g} m long (units {tracks.unit_scale:g} m each); "
                           f"expected {LEG_RANGE[0]:g} to {LEG_RANGE[1]:g} m: check --units")
    base = load_creature(BASE[count])
    doc = base.to_dict()
    doc["name"] = name or source.stem
    doc["description"] = (f"fitted to {source.name} by gaitlab fit ({clip.gait_match}, {clip.cycle_seconds:.3f} s "
                          "cycle)")
    _body_from_skeleton(doc, skeleton)

    gait = doc["gait"]
    named = clip.gait_match.split()[0] if clip.gait_match else ""
    preset = named if named in GAIT_PRESETS else ("run" if count == 2 and clip_duty < 0.5 else "walk")
    for key in ("frames_per_cycle", "timing_fps", "bias", "front_back", "left_right"):
        gait.pop(key, None)
    gait["preset"] = preset
    gait["frequency"] = round(1.0 / clip.cycle_seconds, 4)
    gait["duty_factor"] = round(float(np.clip(clip_duty, 0.05, 0.95)), 4)
    phases = {f.name: f.phase for f in clip.feet}
    if all(p is not None and math.isfinite(p) for p in phases.values()):
        gait["phases"] = {k: round(float(v) % 1.0, 4) for k, v in phases.items()}
    spec = creature_from_dict(doc, source=str(path))
    rig = build_rig(spec)
    stride_m = clip.speed * gait["duty_factor"] / gait["frequency"]  # ground_speed: stride / duty x frequency
    gait["stride"] = round(float(np.clip(stride_m / rig.leg_scale, 0.05, 2.0)), 4)
    gait["step_height"] = round(_step_height(clip, rig.leg_scale), 4)
    if count == 2:  # the key poses: a walk's or a run's own heights and foot angle, refined below
        poses = doc.setdefault("poses", {})
        from .styles import style_heights

        heights = style_heights(poses.get("style", "normal"), rig.hip_height)
        for key, h in zip(("contact_height", "down_height", "pass_height", "up_height"), heights):
            poses.setdefault(key, round(h, 4))
    doc = _calibrate(doc, clip, str(path), progress)

    note = "a quadruped's joints above its foot differ from rig to rig" if count == 4 else ""
    reference: dict[str, Any] = {}
    if count == 2:
        try:
            reference = _compared_legs(bvh_legs(path, feet))
        except GaitlabError as exc:  # (one stride: no whole cycle of angles to compare)
            note = str(exc).replace(f"{path}: ", "")
    if refine and reference:  # (bipeds)
        hip_height = build_rig(creature_from_dict(doc, source=str(path))).hip_height
        leg = next(iter(doc["legs"]))
        keys = ["poses.contact_height", "poses.down_height", "poses.pass_height", "poses.up_height",
                "poses.foot_angle", f"legs.{leg}.natural_bend", "gait.step_height", f"legs.{leg}.roll"]
        low = -0.2 * hip_height
        bounds = [(low, 0.02 * hip_height)] * 4 + [(0.0, 30.0), (0.0, 0.2), (0.01, 0.3), (0.2, 1.0)]
        start = [doc["poses"][k.split(".")[1]] for k in keys[:4]] + [doc["poses"].get("foot_angle", 16.0),
                                                                      doc["legs"][leg].get("natural_bend", 0.01),
                                                                      doc["gait"]["step_height"],
                                                                      doc["legs"][leg].get("roll", 1.0)]
        if clip_duty >= WALK_DUTY[0]:  # a walker's knee (a runner's swing does not use it)
            keys.append("poses.swing_knee")
            bounds.append(SWING_KNEE_RANGE)
            start.append(doc["poses"].get("swing_knee", SWING_KNEE))
        start = [float(np.clip(v, lo, hi)) for v, (lo, hi) in zip(start, bounds)]
        unrefined = _copy(doc)
        doc = _calibrate(_refine(doc, keys, start, bounds, reference, str(path), progress), clip, str(path), progress)
        if _timing_miss(doc, clip) > TIMING_KEPT and _timing_miss(unrefined, clip) <= TIMING_KEPT:
            # Poses that bend the angles closer but change the gait's timing past what
            # calibration brings back (a runner's feet skimming the ground read as down):
            # the gait comes first.
            doc = unrefined
            note = "the refined poses changed the gait's timing beyond calibration: the poses are the unrefined ones"
    spec = creature_from_dict(doc, source=str(path))
    fitted = _own_report(spec)
    rms = _rms(spec, reference) if reference else {}
    measured = {f"{leg} leg": sum(v) for leg, v in skeleton["legs"].items() if leg in ("L", "LF", "LH")}
    for key in ("width", "length"):
        if key in skeleton:
            measured[f"hip {key}" if key == "width" else "trunk"] = skeleton[key]
    return FitResult(spec=spec, clip=clip, fitted=fitted, rms=rms, measured=measured, note=note)
