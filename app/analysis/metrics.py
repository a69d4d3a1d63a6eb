"""From foot events to gait numbers: duty factor, phase, stride, slip, skating, limb phase,
and the named gait the pattern most resembles."""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING

import numpy as np

from ..gaits import GAIT_PRESETS, TETRAPOD_FEET, foot_names, phases_from_offsets, preset_phases
from .events import AnalysisError, FootEvents, Step, detect_events, stride_period
from .tracks import LOOP_PLAYS, FootTracks, played_round

if TYPE_CHECKING:
    from ..kinematics.motion import Motion

# Biped gaits, for two-footed clips: left/right phase and a typical duty factor.
BIPED_GAITS: dict[str, tuple[float, float]] = {"walk": (0.5, 0.62), "run": (0.5, 0.35), "hop": (0.0, 0.4)}
TRANSITION_DISTANCE = 0.12  # a cycle further than this from every gait is a change between gaits
SKATE_HEIGHT = 0.05  # m, for a 0.9 m hip height (scaled with the creature when known)
SKATE_SPEED = 0.5  # m/s, for a 0.9 m hip height (scaled with sqrt of the size: Froude)


def cyclic_distance(a: float, b: float) -> float:
    """Distance between two phases on the unit circle, in [0, 0.5]."""
    d = (a - b) % 1.0
    return min(d, 1.0 - d)


def circular_mean(phases) -> float:
    """Mean of phases (cycle fractions) on the circle, in [0, 1)."""
    angles = 2 * np.pi * np.asarray(phases, dtype=np.float64)
    if angles.size == 0:
        return math.nan
    return float(np.arctan2(np.sin(angles).mean(), np.cos(angles).mean()) / (2 * np.pi) % 1.0)


@dataclass
class FootReport:
    name: str
    duty_factor: float
    phase: float
    stride_length: float
    max_stance_slip: float
    skating_ratio: float
    events: list[tuple[str, float]] = field(default_factory=list)


@dataclass
class PathError:
    """How closely the trunk's centre followed its path: cross-track distance (m) RMS and
    maximum, the maximum in body lengths, and the heading error (degrees) RMS and maximum."""

    rms: float
    max: float
    max_body_lengths: float
    heading_rms_deg: float
    heading_max_deg: float


def path_error(motion: Motion) -> PathError | None:
    """The path error of a travelling motion (None in place): how far the body strays
    from its path beyond its own sideways sway (``motion.sway``, m either way)."""
    if motion.in_place:
        return None
    from ..kinematics.path import path_distance

    centre = motion.root[:, [0, 2], 3]
    distance, s = path_distance(motion.path, centre, motion.travel, 0.5 * motion.rig.body_length)
    distance = np.maximum(distance - motion.rig.motion.sway, 0.0)
    _, tangent = motion.path.sample(s)
    facing = motion.root[:, [0, 2], 2]
    facing /= np.maximum(np.linalg.norm(facing, axis=1, keepdims=True), 1e-12)
    angle = np.degrees(np.arccos(np.clip(np.sum(facing * tangent, axis=1), -1.0, 1.0)))
    return PathError(rms=float(np.sqrt(np.mean(distance ** 2))), max=float(distance.max()),
                     max_body_lengths=float(distance.max() / motion.rig.body_length),
                     heading_rms_deg=float(np.sqrt(np.mean(angle ** 2))), heading_max_deg=float(angle.max()))


@dataclass
class GaitSpan:
    start: float
    end: float
    gait: str


@dataclass
class GaitReport:
    """Everything ``gaitlab analyze`` prints (see :meth:`to_json`)."""

    source: str
    gait: str | None
    cycle_seconds: float
    speed: float
    limb_phase: float | None
    gait_match: str
    feet: list[FootReport]
    spans: list[GaitSpan]
    foot_events: list[FootEvents] = field(repr=False, default_factory=list)
    tracks: FootTracks | None = field(repr=False, default=None)
    path_error: PathError | None = None
    wave_lag: float | None = None  # many-legged creatures: a foot's lag behind the foot behind it
    notes: tuple[str, ...] = ()  # what the numbers rest on, when it is not the usual (e.g. a single stride)
    arm_phase: dict[str, float] | None = None  # bipeds: when (cycle phase) each hand is farthest forward

    def foot(self, name: str) -> FootReport:
        for f in self.feet:
            if f.name == name:
                return f
        raise KeyError(name)

    def to_json(self) -> dict:
        def num(x: float | None, digits: int = 4):
            return None if x is None or not math.isfinite(x) else round(float(x), digits)

        return {
            "source": self.source,
            "gait": self.gait,
            "cycle_seconds": num(self.cycle_seconds),
            "speed": num(self.speed),
            "limb_phase": num(self.limb_phase),
            "wave_lag": num(self.wave_lag),
            "gait_match": self.gait_match,
            "notes": list(self.notes),
            "arm_phase": None if self.arm_phase is None else {k: num(v) for k, v in self.arm_phase.items()},
            "feet": [{"name": f.name, "duty_factor": num(f.duty_factor), "phase": num(f.phase),
                      "stride_length": num(f.stride_length), "max_stance_slip": num(f.max_stance_slip, 5),
                      "skating_ratio": num(f.skating_ratio), "events": [{"kind": k, "time": num(t)} for k, t in f.events]}
                     for f in self.feet],
            "spans": [{"start": num(s.start), "end": num(s.end), "gait": s.gait} for s in self.spans],
            "path_error": None if self.path_error is None else {
                "rms": num(self.path_error.rms, 5), "max": num(self.path_error.max, 5),
                "max_body_lengths": num(self.path_error.max_body_lengths, 5),
                "heading_rms_deg": num(self.path_error.heading_rms_deg, 3),
                "heading_max_deg": num(self.path_error.heading_max_deg, 3)},
        }


def reference_foot(names: tuple[str, ...]) -> str:
    """The foot whose touchdown is phase 0: left hind (Hildebrand), left for bipeds, the
    rearmost left foot (Ln) of many-legged creatures."""
    for name in ("LH", "L"):
        if name in names:
            return name
    numbered = [n for n in names if n[:1] == "L" and n[1:].isdigit()]
    if numbered:
        return max(numbered, key=lambda n: int(n[1:]))
    return names[0]


@functools.lru_cache(maxsize=1)
def _preset_phases() -> dict[str, np.ndarray]:
    return {name: preset_phases(name, TETRAPOD_FEET) for name, p in GAIT_PRESETS.items() if p.fits(2)}


# The duty factors each two-pair gait is seen with in real animals (shared/reference:
# Hildebrand 1965, Cartmill et al. 2002; a walk is DF > 0.5, a run below it): a gait's
# duty factor falls with speed, so a cycle is scored by how far its duty factor lies
# outside its gait's range, not by the distance to one typical value.
DUTY_RANGES: dict[str, tuple[float, float]] = {
    "walk": (0.50, 0.85), "diagonal-walk": (0.50, 0.85), "amble": (0.35, 0.55), "trot": (0.30, 0.50),
    "pace": (0.30, 0.50), "canter": (0.35, 0.50), "gallop": (0.18, 0.29), "rotary-gallop": (0.20, 0.35),
    "half-bound": (0.30, 0.50), "bound": (0.30, 0.50), "pronk": (0.30, 0.40),
}


@functools.lru_cache(maxsize=1)
def _tetrapod_table() -> tuple[tuple[str, ...], np.ndarray, np.ndarray, np.ndarray]:
    """The two-pair gaits as arrays: names, phases (gaits, 4) and the low and high ends
    of their duty factors (gaits,) each (a preset's own value where no range is known)."""
    presets = _preset_phases()
    names = tuple(presets)
    ranges = [DUTY_RANGES.get(n, (GAIT_PRESETS[n].duty_factor,) * 2) for n in names]
    return (names, np.array([presets[n] for n in names], dtype=np.float64),
            np.array([r[0] for r in ranges], dtype=np.float64), np.array([r[1] for r in ranges], dtype=np.float64))


def wave_lag(phases: dict[str, float]) -> float | None:
    """The mean lag (cycle fraction) of a foot behind the one behind it on its side, for
    creatures with three or more pairs (L1 R1 ... Ln Rn): a metachronal wave's lag."""
    pairs = len([n for n in phases if n[:1] in "LR" and n[1:].isdigit()]) // 2
    if pairs < 3:
        return None
    lags = [(phases[f"{side}{i}"] - phases[f"{side}{i + 1}"]) % 1.0 for side in "LR" for i in range(1, pairs)]
    return circular_mean(lags)


def _mirror(phases: dict[str, float]) -> dict[str, float]:
    """The same gait on the other lead: every left foot swapped with its right partner
    (``LF``/``RF``, ``L3``/``R3``), the reference foot back at phase 0."""
    partner = {"L": "R", "R": "L"}
    swapped = {name: phases[partner[name[0]] + name[1:]] for name in phases}
    zero = swapped[reference_foot(tuple(phases))]
    return {k: (v - zero) % 1.0 for k, v in swapped.items()}


def match_gait(phases: dict[str, float], duty: float) -> str:
    """The named gait closest to measured phases (relative to the reference foot) and a
    duty factor: mean cyclic phase error plus the duty-factor difference; asymmetric
    gaits are tried on both leads."""
    return gait_distance(phases, duty)[0]


def gait_distance(phases: dict[str, float], duty: float) -> tuple[str, float]:
    """(closest gait, its distance) — see :func:`match_gait`."""
    feet = set(phases)
    if feet >= set(TETRAPOD_FEET):
        first = {k: phases[k] for k in TETRAPOD_FEET}
        measured = np.array([[m[k] for k in TETRAPOD_FEET] for m in (first, _mirror(first))])  # (2, 4)
        names, expected, low, high = _tetrapod_table()
        d = (measured[None, :, :] - expected[:, None, :]) % 1.0  # (gaits, leads, feet)
        outside = np.maximum(0.0, np.maximum(low - duty, duty - high))
        score = np.minimum(d, 1.0 - d).mean(axis=2) + outside[:, None]
        best = int(np.argmin(score.min(axis=1)))  # the first gait, on its better lead, at a tie
        return names[best], float(score[best].min())
    if {"L", "R"} <= feet:
        lr = phases["R"] - phases["L"]
        scores = {g: cyclic_distance(lr, p) + abs(duty - d) for g, (p, d) in BIPED_GAITS.items()}
        biped = min(scores, key=lambda g: scores[g])
        return biped, scores[biped]
    pairs = len(feet) // 2
    names = foot_names(pairs)
    if pairs >= 3 and feet >= set(names):
        chosen, best_d = "", math.inf
        lag = wave_lag(phases)
        for name, preset in GAIT_PRESETS.items():
            if not preset.fits(pairs):
                continue
            fb = lag if name == "metachronal" and lag is not None else float(preset.front_back or 0.0)
            expected = phases_from_offsets(fb, float(preset.left_right or 0.0), names)
            d = float(np.mean([cyclic_distance(phases[n], e) for n, e in zip(names, expected)]))
            d += abs(duty - preset.duty_factor) * (0.25 if name == "metachronal" else 1.0)
            if d < best_d:
                chosen, best_d = name, d
        return chosen, best_d
    return "unknown", math.inf


def _step_phases(times: np.ndarray, strikes: dict[str, np.ndarray], ref: str) -> dict[str, list[float]]:
    """Per foot, the phase of each touchdown within the reference foot's cycle around it;
    a touchdown before the reference's first or after its last (a short clip's edges)
    within the nearest of its cycles."""
    ref_strikes = strikes[ref]
    out: dict[str, list[float]] = {}
    if len(ref_strikes) < 2:
        return {name: [] for name in strikes}
    for name, ts in strikes.items():
        values = []
        for t in ts:
            j = min(max(int(np.searchsorted(ref_strikes, t, side="right")) - 1, 0), len(ref_strikes) - 2)
            values.append(float((t - ref_strikes[j]) / (ref_strikes[j + 1] - ref_strikes[j])) % 1.0)
        out[name] = values
    return out


def skating_ratio(fe: FootEvents, point: np.ndarray, times: np.ndarray, scale: float) -> float:
    """Share of frames in which the foot is down — between strike and liftoff and within
    5 cm of the ground, in this and the next frame — and slides faster than 0.5 m/s
    (both thresholds scaled to the creature: height with its size, speed with the square
    root of its size). A planted-foot animation scores 0."""
    down = np.zeros(len(times), dtype=bool)
    for s in fe.steps:
        down[s.strike + 1:s.liftoff] = True  # strictly inside: event frames are known to a frame
    low = np.minimum(fe.heel_height, fe.toe_height) < SKATE_HEIGHT * scale
    velocity = np.gradient(point, times, axis=0)
    fast = np.hypot(velocity[:, 0], velocity[:, 2]) > SKATE_SPEED * math.sqrt(scale)
    both = down[:-1] & down[1:] & low[:-1] & low[1:] & fast[:-1]
    return float(both.mean())


PAUSE = 2.0  # a foot's "stride" longer than this many cycles is a pause (standing, shuffling): no stride


def _landed(fe: FootEvents, frame_count: int) -> list[Step]:
    """The steps of ``fe`` whose touchdown was seen: the complete ones and a last one that
    lands inside the clip and is still down at its end."""
    return [s for i, s in enumerate(fe.steps)
            if s.complete or (i == len(fe.steps) - 1 and s.strike > 0 and s.liftoff >= frame_count - 1)]


def analyze_tracks(tracks: FootTracks, requested_gait: str | None = None) -> GaitReport:
    """Events and gait numbers for foot trajectories. Raises :class:`AnalysisError`. A
    clip too short to analyse that is one loop (:func:`played_round`) is analysed as
    played round three times, and says so."""
    try:
        return _analyze(tracks, requested_gait)
    except AnalysisError as exc:
        looped = played_round(tracks)
        if looped is None:
            raise AnalysisError(f"{exc} (or, for a one-cycle loop, end on the pose it starts with)") from None
        try:
            report = _analyze(looped, requested_gait)
        except AnalysisError:
            raise exc from None  # (a clip that stands still "closes" too: say what is wrong with it)
    note = (f"the clip is one loop (its last pose is its first): analysed as played round {LOOP_PLAYS} times "
            f"({looped.duration:.2f} s)")
    return replace(report, notes=report.notes + (note,))


def _analyze(tracks: FootTracks, requested_gait: str | None) -> GaitReport:
    period = stride_period(tracks)
    events = detect_events(tracks, period)
    times = tracks.times
    ref = reference_foot(tracks.names)
    # Touchdowns seen: every complete step's, and that of a last contact still down when
    # the clip ends (it was seen landing; only its liftoff is unknown).
    landed = {fe.name: _landed(fe, tracks.frame_count) for fe in events}
    strikes = {name: np.array([times[s.strike] for s in steps]) for name, steps in landed.items()}
    notes: list[str] = []
    if tracks.compromised:
        notes.append(f"{tracks.compromised} stance(s) stood on compromised footholds: uneven ground with no "
                     "acceptable spot in reach, so the least-bad one")
    if tracks.cut_short:
        notes.append(f"{tracks.cut_short} stance end(s) cut short where the leg could not reach its foothold: "
                     "the foot lifted early or landed late")
    if not tracks.exact and len(tracks.names) == 2 and np.allclose(tracks.toe, tracks.heel):
        notes.append("no toe joints: a stance reads as ending when the heel rises, so a walk's duty factors read "
                     "low (about 0.15 on CMU 12_01); name toes with --feet L=ANKLE:TOE,R=ANKLE:TOE")
    single = len(strikes.get(ref, [])) < 2
    if single:
        # A single stride (a short mocap take): each foot's one contact, the cycle from a
        # foot seen touching down twice or from the alternating feet.
        cycle, how = _single_stride_cycle(events, times, ref, period)
        phases = _single_stride_phases(events, times, ref, cycle)
        notes.append(f"the clip holds a single stride: the cycle ({cycle:.3f} s, {how}) and so the duty factors "
                     "and phases are estimates")
    else:
        # Every foot's strike-to-strike intervals, pooled: a short or speeding-up clip's
        # cycle is not one foot's two or three strides.
        cycle = float(np.median(np.concatenate([np.diff(s) for s in strikes.values() if len(s) > 1])))
        phases = {k: circular_mean(v) for k, v in _step_phases(times, strikes, ref).items()}
    scale = (tracks.hip_height / 0.9) if tracks.hip_height else 1.0

    feet = []
    for f, fe in enumerate(events):
        complete = [s for s in fe.steps if s.complete]
        duties = []
        for a, b in zip(landed[fe.name], landed[fe.name][1:]):
            if a.complete and times[b.strike] - times[a.strike] <= PAUSE * cycle:  # (not a pause: see gait_spans)
                duties.append((times[a.liftoff] - times[a.strike]) / max(times[b.strike] - times[a.strike], 1e-9))
        if single:
            duties = [(times[a.liftoff] - times[a.strike]) / cycle for a in complete]
        heel = tracks.heel[:, f]
        stance_points = np.array([heel[s.stance][[0, 2]] for s in complete])
        strides = np.linalg.norm(np.diff(stance_points, axis=0), axis=1) if len(stance_points) > 1 else np.array([])
        # Slip while planted: strictly inside [landing, lift] (the event frames themselves
        # are only known to within a frame).
        slips = [float(np.max(np.linalg.norm(heel[s.landing + 1:s.lift][:, [0, 2]] - heel[s.landing + 1][[0, 2]],
                                                   axis=1))) for s in complete if s.lift - s.landing >= 3]
        skating = skating_ratio(fe, heel, times, scale)
        evts = sorted(((kind, float(times[getattr(s, kind)])) for s in fe.steps for kind in
                       ("strike", "landing", "stance", "lift", "liftoff")), key=lambda e: e[1])
        feet.append(FootReport(name=fe.name, duty_factor=float(np.median(duties)) if duties else math.nan,
                               phase=phases.get(fe.name, math.nan),
                               stride_length=float(np.median(strides)) if len(strides) else math.nan,
                               max_stance_slip=max(slips) if slips else math.nan, skating_ratio=skating,
                               events=evts))

    duty = float(np.nanmean([f.duty_factor for f in feet]))
    limb_phase = None
    if set(TETRAPOD_FEET) <= set(phases):
        limb_phase = circular_mean([(phases["LF"] - phases["LH"]) % 1.0, (phases["RF"] - phases["RH"]) % 1.0])
    gait_match = match_gait(phases, duty)
    spans = gait_spans(times, events, strikes, ref, cycle)
    arms = arm_phases(tracks, strikes.get(ref, np.array([])), cycle)
    return GaitReport(source=tracks.source, gait=requested_gait, cycle_seconds=cycle, speed=tracks.speed(),
                      limb_phase=limb_phase, gait_match=gait_match, feet=feet, spans=spans, foot_events=events,
                      tracks=tracks, wave_lag=wave_lag(phases), notes=tuple(notes), arm_phase=arms)


def arm_phases(tracks: FootTracks, strikes: np.ndarray, cycle: float) -> dict[str, float] | None:
    """When each hand is farthest forward of the body along the travel, as a cycle phase
    after the reference foot's touchdowns (the left foot of a biped): about 0.5 for the
    left hand (forward with the right foot) in a walk whose arms swing against the legs.
    None without hands or touchdowns."""
    if tracks.hands is None or len(strikes) == 0 or not math.isfinite(cycle) or cycle <= 0:
        return None
    direction = tracks.travel_direction()[:, [0, 2]]  # (T, 2)
    ahead = np.sum((tracks.hands[..., [0, 2]] - tracks.body[:, None, [0, 2]]) * direction[:, None, :], axis=-1)
    out = {}
    for i, name in enumerate(("L", "R")):
        # The fundamental of the hand's fore-aft swing over the cycle: its phase of maximum.
        angle = 2.0 * np.pi * (tracks.times - strikes[0]) / cycle
        centred = ahead[:, i] - ahead[:, i].mean()
        out[name] = float(np.mod(np.arctan2(np.sum(centred * np.sin(angle)), np.sum(centred * np.cos(angle)))
                                 / (2.0 * np.pi), 1.0))
    return out


def _touchdowns(fe: FootEvents, times: np.ndarray) -> np.ndarray:
    """A foot's touchdown times seen inside the clip (a contact already under way at the
    first frame has none)."""
    return np.array([times[s.strike] for s in fe.steps if s.strike > 0])


def _single_stride_cycle(events: list[FootEvents], times: np.ndarray, ref: str, period: float) -> tuple[float, str]:
    """The cycle (s) of a clip too short for the reference foot to land twice, and how it
    was found: a foot seen touching down twice, else the alternating left and right feet
    (a symmetric gait's are half a cycle apart), else the clip's repetition."""
    twice = {fe.name: np.diff(t) for fe in events if len(t := _touchdowns(fe, times)) >= 2}
    if twice:
        name = min(twice, key=lambda n: (n != ref, n))
        return float(np.median(twice[name])), f"from {name}'s two touchdowns"
    once = {fe.name: t[0] for fe in events if len(t := _touchdowns(fe, times)) == 1}
    if {"L", "R"} <= set(once):
        return 2.0 * abs(float(once["R"] - once["L"])), "twice the time from one foot's touchdown to the other's"
    if not any(s.complete for fe in events for s in fe.steps):
        raise AnalysisError("no foot has a whole ground contact in the clip; give a longer clip (at least one stride)")
    return float(period), "from the clip's repetition"


def _single_stride_phases(events: list[FootEvents], times: np.ndarray, ref: str, cycle: float) -> dict[str, float]:
    """Each foot's touchdown phase after the reference foot's first touchdown."""
    downs = {fe.name: _touchdowns(fe, times) for fe in events}
    if len(downs.get(ref, [])) == 0:
        raise AnalysisError(f"the reference foot {ref} never touches down in the clip; give a longer clip "
                            "(at least one full stride)")
    t0 = float(downs[ref][0])
    return {name: circular_mean(((t - t0) / cycle) % 1.0) for name, t in downs.items() if len(t)}


def gait_spans(times: np.ndarray, events: list[FootEvents], strikes: dict[str, np.ndarray], ref: str,
               cycle: float = math.inf) -> list[GaitSpan]:
    """The gait over time, as spans of one gait.

    Every foot's cycles (touchdown to touchdown) are classified, with the phases taken
    relative to the reference foot as everywhere else, so the stretch before the
    reference foot's first touchdown, and a cycle in which the reference foot's
    neighbours miss a step, are still named. Each moment takes the gait most of the
    cycles around it agree on ("transition" where none is near a named gait). A foot's
    "cycle" over twice the clip's ``cycle`` (s) is a pause, a shuffle while standing, and
    names nothing: a take that begins or ends standing has no gait there."""
    # Each foot's complete steps as sorted strike and liftoff times: one binary search per cycle.
    contacts = []
    for fe in events:
        complete = [s for s in fe.steps if s.complete]
        on = np.array([times[s.strike] for s in complete])
        off = np.array([times[s.liftoff] for s in complete])
        order = np.argsort(on, kind="stable")
        contacts.append((fe.name, on[order], off[order]))
    windows: list[tuple[float, float, str]] = []
    for _, cycle_on, _ in contacts:
        for t0, t1 in zip(cycle_on, cycle_on[1:]):
            if t1 - t0 > PAUSE * cycle:
                continue
            phases, duties = {}, []
            for name, on, off in contacts:
                i = int(np.searchsorted(on, t0, side="left"))
                if i >= len(on) or not on[i] < t1:
                    break
                phases[name] = (on[i] - t0) / (t1 - t0)
                duties.append((off[i] - on[i]) / (t1 - t0))
            else:
                base = phases[ref]
                phases = {k: (v - base) % 1.0 for k, v in phases.items()}
                name, distance = gait_distance(phases, float(np.mean(duties)))
                windows.append((float(t0), float(t1), "transition" if distance > TRANSITION_DISTANCE else name))
    if not windows:
        return []
    starts = np.array([w[0] for w in windows])
    ends = np.array([w[1] for w in windows])
    bounds = np.unique(np.concatenate([starts, ends]))
    spans: list[GaitSpan] = []
    for a, b in zip(bounds, bounds[1:]):
        around = [windows[k][2] for k in np.nonzero((starts <= a) & (ends >= b))[0]]
        if not around:
            continue
        named = [g for g in around if g != "transition"]
        if not named and len(around) < 2:
            continue  # one foot's odd cycle at the clip's edge says too little
        votes = {g: named.count(g) for g in named}
        name = max(votes, key=lambda g: (votes[g], -named.index(g))) if votes and max(votes.values()) * 2 >= len(
            around) else "transition"
        if spans and spans[-1].gait == name and abs(spans[-1].end - a) < 1e-9:
            spans[-1].end = float(b)
        else:
            spans.append(GaitSpan(float(a), float(b), name))
    return spans
