"""Foot events from heel and toe trajectories, after "Walk and Run Cycle Analysis".

For every ground contact of a foot:

- **stance**: where the foot stands most firmly — lowest and slowest;
- **lift** / **liftoff**: when the foot begins to lift / is fully off the ground;
- **strike** / **landing**: when it first touches / is fully down again.

Lift and landing points are found on the heel and the toe height curves separately, by
the seed's rules: starting at the stance time, follow the curve forwards (backwards) until
it reaches 10% of its maximum height; inside that span take the point of maximum
curvature (second derivative), ignoring points below the ground and points sloping the
wrong way. The earlier of heel and toe is *lift* (*strike*), the later *liftoff*
(*landing*). Then the forward-speed check: from the stance time, the first moment the
foot's speed along the direction of travel (relative to the body) differs from its speed
at the stance time by more than 50% — the foot no longer follows the ground — replaces
the lift (landing) time when it comes sooner. This keeps feet that drag along the ground
or sink into it from fooling the height rules.

The ground level of each curve is a rolling low percentile of the curve itself, so a
sloping floor or an ankle that never reaches y = 0 (a digitigrade heel) is handled.

Recorded motion (motion capture: feet that slide, dip near the ground in swing, jitter)
first finds each foot's contacts directly: a foot is down once one of its points is
within a few centimetres of its own local ground and one moves over the ground slower
than a share of the body's current speed (paws: a third; people, whose ankle and toe tip
roll with the sole: the whole, "falling behind the body"; each frame's speed its slower
side's), and stays down until it is clearly higher or faster
(hysteresis); lifts shorter than a tenth of a stride are closed and contacts shorter than
8 % of one dropped. A contact's first and last frames are the strike and the liftoff;
landing and lift follow the rules above inside it.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Literal

import numpy as np
from numpy.typing import NDArray

from ..errors import GaitlabError
from .filters import find_peaks, running_mean, running_percentile, savgol
from .tracks import FootTracks

EventKind = Literal["lift", "liftoff", "strike", "landing", "stance"]
EVENT_KINDS: tuple[str, ...] = ("strike", "landing", "stance", "lift", "liftoff")
LIFT_LEVEL = 0.10  # the search span ends at 10% of the curve's maximum height
SPEED_CHANGE = 0.50  # the forward-speed check: more than 50% away from the stance speed
CONTACT_SPEED = 0.5  # a contact point's foot moves at under half its typical speed when it is down
STATIC_SPEED = 0.25  # a foot slower than this fraction of the body's speed stands still
MIN_STANCE = 0.08  # of a stride: a shorter contact within the clip is a toe or heel dipping in swing, not a stance
PROVISIONAL_STRIDE = 0.5  # s: the stride recorded contacts are first found for, before the clip's own is known
MIN_SWING = 0.10  # of a stride: a shorter lift between two contacts is a stance split in two (marker noise)
PAW_LOW = 0.075  # of the hip height: a recorded foot this close to its own ground level may be down...
PAW_LOW_MAX = 0.045  # ...up to 4.5 cm (a tracked joint sits a few cm above the sole: a person's feet are no higher)
PAW_SLOW = 0.35  # of the body's current speed: a low paw slower than this over the ground is down
# Two feet (people): the tracked joint centres roll over the ground with the sole (the
# ankle through the heel rocker, the toe tip through push-off) at up to the body's own
# speed, so a foot is down while low and falling behind the body: the events this gives
# on CMU 12_01 are within two frames of Zeni et al. 2008's (heel most forward, toe most
# backward of the pelvis), the standard kinematic definition.
FOOT_SLOW = 1.0
# ... but never faster than this (hip heights a second; a person's 1.3 m/s): rolling over
# the sole, the slower of the two points moves no faster whatever the speed, while a
# runner's ankle coming down at 2 m/s, its toes still in the air, has not yet landed.
FOOT_SLOW_MAX = 1.5
RUNNER_DIP = 0.01  # of the hip height: a body this much below its stride's mean mid-contact runs (people jogging: 2-6 cm)
BELT_HEIGHTS = 30  # percentile: a foot walking in place is on the belt in its lowest frames
IN_PLACE = 0.1  # a body that travels less than this share of its feet's path walks in place
PAW_RELEASE = 1.2  # hysteresis: it stays down until it is this many times higher or faster


class AnalysisError(GaitlabError):
    """The trajectories cannot be analysed (too short, no steps found, ...)."""


@dataclass(frozen=True)
class Step:
    """One ground contact of a foot, as frame indices (strike <= landing <= stance <=
    lift <= liftoff). ``complete`` is False when the contact runs off either end of the
    clip (its strike or liftoff is then the clip's edge)."""

    strike: int
    landing: int
    stance: int
    lift: int
    liftoff: int
    complete: bool = True


@dataclass(frozen=True)
class FootEvents:
    """The steps of one foot, plus the curves they were found on (for plots)."""

    name: str
    steps: tuple[Step, ...]
    heel_height: NDArray[np.float64]  # (T,) above the curve's own ground level, metres
    toe_height: NDArray[np.float64]

    def times(self, kind: str, times: NDArray[np.float64], complete_only: bool = False) -> NDArray[np.float64]:
        steps = [s for s in self.steps if s.complete or not complete_only]
        return np.array([times[getattr(s, kind)] for s in steps])


def _odd(n: int) -> int:
    n = max(int(n), 5)
    return n if n % 2 else n + 1


def clip_period(tracks: FootTracks, min_seconds: float = 0.15) -> float:
    """The stride period (s): the first strong peak of the feet's height autocorrelation."""
    heights = 0.5 * (tracks.heel[..., 1] + tracks.toe[..., 1])  # (T, F)
    x = heights - heights.mean(axis=0)
    n = x.shape[0]
    if n < 8:
        raise AnalysisError(f"the clip has only {n} frames; at least one whole step is needed")
    spectrum = np.fft.rfft(x, n=2 * n, axis=0)
    acf = np.fft.irfft(np.abs(spectrum) ** 2, axis=0)[:n].sum(axis=1)
    if acf[0] <= 0:
        raise AnalysisError("the feet never move up and down: no steps to analyse")
    acf /= acf[0]
    acf /= (n - np.arange(n)) / n  # unbiased: long lags have fewer overlapping samples
    start = max(1, int(min_seconds * tracks.fps))
    peaks, props = find_peaks(acf[start: int(0.75 * n)], height=0.2)
    if len(peaks) == 0:
        raise AnalysisError(f"no repeating step found in {tracks.duration:.2f} s; the clip must hold at least "
                            "one full stride of every foot (about two steps)")
    heights = props["peak_heights"]
    best = int(peaks[np.nonzero(heights >= 0.8 * heights.max())[0][0]])  # the first strong peak, not a multiple
    return float((start + best) / tracks.fps)


def _crossings(a: NDArray, level: float) -> tuple[NDArray[np.intp], NDArray[np.intp]]:
    """For every index i: the first index >= i where ``a`` reaches ``level`` (len(a) if
    none), and the last index <= i where it does (-1 if none). O(T), for all steps at once."""
    n = len(a)
    at = np.arange(n)
    reached = a >= level
    after = np.minimum.accumulate(np.where(reached, at, n)[::-1])[::-1]
    before = np.maximum.accumulate(np.where(reached, at, -1))
    return after, before


def _curve_event(a: NDArray, d1: NDArray, d2: NDArray, start: int, crossings: tuple[NDArray, NDArray],
                 step: int) -> tuple[int, bool]:
    """The lift (step=+1) or touchdown (step=-1) point of one height curve: maximum
    curvature between the stance frame and where the curve reaches its search level
    (``crossings``, from :func:`_crossings`), skipping points below the ground and points
    sloping the wrong way. Returns (index, found)."""
    end = int(crossings[0][start] if step > 0 else crossings[1][start])
    if end >= len(a) or end < 0:
        return (len(a) - 1 if step > 0 else 0), False
    lo, hi = (start, end) if step > 0 else (end, start)
    seg = slice(lo, hi + 1)
    ok = (a[seg] >= 0.0) & ((d1[seg] >= 0.0) if step > 0 else (d1[seg] <= 0.0))
    if not ok.any():
        return end, True
    return lo + int(np.argmax(np.where(ok, d2[seg], -np.inf))), True


def _first_far(seg: NDArray, centre: float, threshold: float) -> int | None:
    hits = np.flatnonzero(np.abs(seg - centre) > threshold)
    return None if hits.size == 0 else int(hits[0])


def _speed_check(rel: NDArray, start: int, threshold: float, step: int, window: int) -> int | None:
    """First index from the stance frame where the forward speed relative to the body has
    moved more than ``threshold`` away from its value at the stance frame. Looks within
    ``window`` frames first (where it almost always is), then further."""
    centre = rel[start]
    if step > 0:
        near = _first_far(rel[start:start + window], centre, threshold)
        if near is None and start + window < len(rel):
            far = _first_far(rel[start + window:], centre, threshold)
            near = None if far is None else window + far
        return None if near is None else start + near
    lo = max(0, start - window + 1)
    near = _first_far(rel[lo:start + 1][::-1], centre, threshold)
    if near is None and lo > 0:
        far = _first_far(rel[:lo][::-1], centre, threshold)
        near = None if far is None else (start + 1 - lo) + far
    return None if near is None else start - near


def _plateau_centre(score: NDArray, peak: int, spread: float, tolerance: float = 0.02) -> int:
    """The middle of the stretch around ``peak`` where ``score`` stays within ``tolerance``
    (of its range, ``spread``) of the minimum: a flat stance's firmest frame is its
    centre, not an edge."""
    limit = score[peak] + tolerance * max(spread, 1e-12)
    above = score > limit
    window = 64
    hi = peak
    while True:  # forwards, a window at a time
        seg = above[hi + 1:hi + 1 + window]
        hits = np.flatnonzero(seg)
        if hits.size:
            hi += int(hits[0])
            break
        hi += seg.size
        if hi >= len(score) - 1:
            hi = len(score) - 1
            break
    lo = peak
    while True:  # backwards
        start = max(0, lo - window)
        seg = above[start:lo][::-1]
        hits = np.flatnonzero(seg)
        if hits.size:
            lo -= int(hits[0])
            break
        lo = start
        if lo <= 0:
            lo = 0
            break
    return (lo + hi) // 2


def _gather(a: NDArray, starts: NDArray[np.intp], width: int, step: int) -> tuple[NDArray, NDArray[np.bool_]]:
    """``a`` at ``starts + step * [0, width)`` for every start, (len(starts), width), and
    which of those indices lie inside ``a``."""
    grid = starts[:, None] + step * np.arange(width)[None, :]
    inside = (grid >= 0) & (grid < len(a))
    return a[np.clip(grid, 0, len(a) - 1)], inside


def _curve_events(a: NDArray, d1: NDArray, d2: NDArray, starts: NDArray[np.intp], crossings: tuple[NDArray, NDArray],
                  step: int, cap: int) -> tuple[NDArray[np.intp], NDArray[np.bool_]]:
    """:func:`_curve_event` for many stance frames at once: (indices, found)."""
    n = len(a)
    ends = (crossings[0] if step > 0 else crossings[1])[starts]
    found = (ends < n) & (ends >= 0)
    result = np.full(len(starts), n - 1 if step > 0 else 0, dtype=np.intp)
    lengths = np.abs(ends - starts) + 1
    rows = np.flatnonzero(found & (lengths <= cap))
    if rows.size:
        width = int(lengths[rows].max())
        lo = np.minimum(starts[rows], ends[rows])
        values, inside = _gather(a, lo, width, +1)
        slopes, _ = _gather(d1, lo, width, +1)
        bends, _ = _gather(d2, lo, width, +1)
        inside &= np.arange(width)[None, :] < lengths[rows][:, None]
        ok = inside & (values >= 0.0) & ((slopes >= 0.0) if step > 0 else (slopes <= 0.0))
        best = lo + np.argmax(np.where(ok, bends, -np.inf), axis=1)
        result[rows] = np.where(ok.any(axis=1), best, ends[rows])
    for r in np.flatnonzero(found & (lengths > cap)):  # rare very long searches: one at a time
        result[r] = _curve_event(a, d1, d2, int(starts[r]), crossings, step)[0]
    return result, found


def _speed_checks(rel: NDArray, starts: NDArray[np.intp], thresholds: NDArray, step: int,
                  window: int) -> NDArray[np.intp]:
    """:func:`_speed_check` for many stance frames at once (-1 where there is none)."""
    values, inside = _gather(rel, starts, window, step)
    hit = inside & (np.abs(values - rel[starts][:, None]) > thresholds[:, None])
    has = hit.any(axis=1)
    result = np.where(has, starts + step * np.argmax(hit, axis=1), -1)
    beyond = starts + step * window
    for r in np.flatnonzero(~has & (beyond >= 0) & (beyond < len(rel))):  # further than a stride
        found = _speed_check(rel, int(starts[r]), float(thresholds[r]), step, window)
        result[r] = -1 if found is None else found
    return result


def _plateau_centres(score: NDArray, peaks: NDArray[np.intp], spread: float, tolerance: float = 0.02,
                     window: int = 64) -> NDArray[np.intp]:
    """:func:`_plateau_centre` for many peaks at once."""
    n = len(score)
    limit = score[peaks] + tolerance * max(spread, 1e-12)
    ends = []
    for step in (+1, -1):
        values, inside = _gather(score, peaks + step, window, step)
        hit = inside & (values > limit[:, None])
        has = hit.any(axis=1)
        edge = np.where(has, peaks + step * np.argmax(hit, axis=1), n - 1 if step > 0 else 0)
        long_run = ~has & ((peaks + window < n - 1) if step > 0 else (peaks - window > 0))
        ends.append((edge, long_run))
    (hi, long_hi), (lo, long_lo) = ends
    centre = (lo + hi) // 2
    for r in np.flatnonzero(long_hi | long_lo):  # a plateau longer than the window
        centre[r] = _plateau_centre(score, int(peaks[r]), spread, tolerance)
    return centre


def _one_per_contact(steps: list[Step], score: NDArray) -> list[Step]:
    """A long flat stance can hold two score minima, found as two steps of one contact
    (the same strike and liftoff, or overlapping: a heel strike and a later flat-foot
    "strike" before one liftoff): keep one step per ground contact, from its first strike
    to its last liftoff, standing at its firmest frame."""
    merged: list[Step] = []
    for step in sorted(steps, key=lambda s: (s.strike, s.liftoff)):
        if merged and step.strike <= merged[-1].liftoff:
            last = merged[-1]
            late = step if step.liftoff > last.liftoff else last
            firm = step if score[step.stance] < score[last.stance] else last
            stance = min(max(firm.stance, last.landing), late.lift)
            merged[-1] = Step(strike=last.strike, landing=min(last.landing, stance), stance=stance,
                              lift=max(late.lift, stance), liftoff=late.liftoff,
                              complete=last.complete and step.complete)
        else:
            merged.append(step)
    return merged


def _long_enough(steps: list[Step], frames: int, count: int) -> list[Step]:
    """Drop contacts shorter than MIN_STANCE of a stride (``frames``) that lie wholly
    inside the clip (``count`` frames): a toe or heel dipping near the ground in mid-swing
    (they would halve the cycle). A contact cut by the clip's first or last frame keeps."""
    shortest = MIN_STANCE * frames
    return [s for s in steps
            if s.liftoff - s.strike >= shortest or s.strike <= 0 or s.liftoff >= count - 1]


def hysteresis(enter: NDArray[np.bool_], leave: NDArray[np.bool_]) -> NDArray[np.bool_]:
    """A state that turns on where ``enter`` holds and stays on until ``leave`` holds,
    for every frame at once ((T,) each; where both hold, ``leave`` wins). At the first
    frame it is on unless ``leave`` holds (what was under way before the clip began is
    not known: a foot already down must not seem to land on its second frame)."""
    at = np.arange(len(enter))
    switch_on = enter & ~leave
    switch_on[:1] = ~leave[:1]
    last_on = np.maximum.accumulate(np.where(switch_on, at, -1))
    last_off = np.maximum.accumulate(np.where(leave, at, -1))
    return last_on > last_off


def runs(mask: NDArray[np.bool_]) -> NDArray[np.intp]:
    """The stretches where ``mask`` (T,) holds, as (N, 2) [first, last] frame indices."""
    edges = np.diff(np.r_[0, mask.astype(np.int8), 0])
    return np.stack([np.flatnonzero(edges == 1), np.flatnonzero(edges == -1) - 1], axis=1)


def _clean_contacts(down: NDArray[np.bool_], frames: int) -> NDArray[np.bool_]:
    """``down`` (T,) with lifts shorter than MIN_SWING of a stride (``frames``) filled
    (a stance split in two by noise), then contacts shorter than MIN_STANCE dropped (a
    paw brushing the ground in swing); what touches the clip's ends is kept as it is."""
    down = down.copy()
    n = len(down)
    for value, shortest in ((False, MIN_SWING * frames), (True, MIN_STANCE * frames)):
        stretches = runs(down == value)
        for a, b in stretches[(stretches[:, 1] - stretches[:, 0] + 1 < shortest)
                              & (stretches[:, 0] > 0) & (stretches[:, 1] < n - 1)]:
            down[a:b + 1] = not value
    return down


def paw_contacts(height: NDArray[np.float64], speed: NDArray[np.float64], body_speed: NDArray[np.float64],
                 low: float, frames: int, slow_share: float = PAW_SLOW, slowest: float = np.inf
                 ) -> NDArray[np.bool_]:
    """Which frames a recorded paw is on the ground, (T,) bool: down once it is lower
    than ``low`` (m) above its own ground (``height``, (T,) m) and slower over the ground
    than ``slow_share`` of the body's current speed (``speed``, ``body_speed``, (T,) m/s) and
    than ``slowest`` (m/s), and
    up once it is PAW_RELEASE times higher or faster than that; each contact then runs
    from the first to the last frame it is truly low and slow (the hysteresis only keeps
    it whole between: it would otherwise end every contact late); then lifts and contacts
    too short for a stride of ``frames`` frames are taken out."""
    slow = np.minimum(slow_share * np.maximum(body_speed, 0.05), slowest)
    enter = (height < low) & (speed < slow)
    leave = (height > PAW_RELEASE * low) | (speed > PAW_RELEASE * slow)
    held = hysteresis(enter, leave)
    at = np.arange(len(enter))
    first_in = np.minimum.accumulate(np.where(enter, at, len(at))[::-1])[::-1]  # first enter frame at or after
    last_in = np.maximum.accumulate(np.where(enter, at, -1))  # last enter frame at or before
    down = np.zeros_like(held)
    for a, b in runs(held):
        lo, hi = first_in[a], last_in[b]
        if lo <= hi:
            down[lo:hi + 1] = True
    return _clean_contacts(down, frames)


@dataclass(frozen=True)
class _Signals:
    """What every foot's events are found from, smoothed over ``smooth`` frames: each
    point's height above its rolling ground with its first and second derivatives,
    its horizontal and vertical speed, (T, L) each by part ("heel", "toe"); the heel's
    forward speed relative to the body (T, L); the speed below which a point stands."""

    smooth: int
    above: dict[str, NDArray[np.float64]]
    slope: dict[str, NDArray[np.float64]]
    bend: dict[str, NDArray[np.float64]]
    speeds: dict[str, NDArray[np.float64]]
    rising: dict[str, NDArray[np.float64]]
    rel: NDArray[np.float64]
    static_speed: float
    body_speed: NDArray[np.float64]  # (T,) the body's horizontal speed, m/s, averaged over half a second
    # Memos of what the contacts of recorded feet are found from: each foot's inputs
    # (:func:`_recorded_inputs`), a walker's contacts by (stride frames, foot) and
    # :func:`runs_like_a_runner`'s answer by stride frames.
    inputs: dict[int, tuple] = field(default_factory=dict)
    walking: dict[tuple[int, int], NDArray[np.intp]] = field(default_factory=dict)
    runner: dict[int, bool] = field(default_factory=dict)


def _signals(tracks: FootTracks, frames: int) -> _Signals:
    smooth = _odd(int(min(frames * 0.06, frames // 3)))
    heights = {"heel": tracks.heel[..., 1], "toe": tracks.toe[..., 1]}
    ground_window = _odd(int(min(1.5 * frames, tracks.frame_count)))
    rel = tracks.forward_velocity(tracks.heel) - tracks.forward_velocity(tracks.body[:, None, :])[:, :1]
    rel = savgol(rel, smooth, 2)

    def horizontal_speed(points: NDArray) -> NDArray:
        velocity = np.gradient(points, tracks.times, axis=0)
        return savgol(np.hypot(velocity[..., 0], velocity[..., 2]), smooth, 2)

    speeds = {"heel": horizontal_speed(tracks.heel), "toe": horizontal_speed(tracks.toe)}
    # In exact motion rising counts as moving too (a heel turning up about the ball barely
    # moves forward); in recorded motion vertical jitter would hide the ground.
    rising = {part: np.abs(savgol(np.gradient(p[..., 1], tracks.times, axis=0), smooth, 2))
              for part, p in (("heel", tracks.heel), ("toe", tracks.toe))}
    body_velocity = np.gradient(tracks.body, tracks.times, axis=0)
    body_speed = np.hypot(body_velocity[:, 0], body_velocity[:, 2])
    static_speed = max(STATIC_SPEED * float(np.median(body_speed)), 0.02)
    body_speed = running_mean(body_speed, _odd(int(tracks.fps / 2)))  # over half a second
    above, slope, bend = {}, {}, {}
    for part, h in heights.items():
        hs = savgol(h, smooth, 3)
        above[part] = hs - running_percentile(hs, 10, ground_window)
        slope[part] = savgol(h, smooth, 3, deriv=1)
        bend[part] = savgol(h, smooth, 3, deriv=2)
    return _Signals(smooth, above, slope, bend, speeds, rising, rel, static_speed, body_speed)


def stride_period(tracks: FootTracks) -> float:
    """The stride period (s). Recorded motion: the median time between a foot's successive
    touchdowns, all feet pooled, from provisional contacts (:func:`recorded_contacts` as
    for a half-second stride), which a take that stands, shuffles or changes gait does
    not fool; exact motion, or a clip in which no foot lands twice: :func:`clip_period`."""
    if not tracks.exact and tracks.frame_count >= 8:
        guess = max(3, int(round(PROVISIONAL_STRIDE * tracks.fps)))
        sig = _signals(tracks, guess)
        gaps = [np.diff(spans[spans[:, 0] > 0, 0])
                for spans in (recorded_contacts(tracks, sig, f, guess) for f in range(len(tracks.names)))]
        pooled = np.concatenate(gaps)
        if pooled.size >= 2:
            return max(float(np.median(pooled)) / tracks.fps, 0.15)
    return clip_period(tracks)


def detect_events(tracks: FootTracks, period: float | None = None) -> list[FootEvents]:
    """Steps of every foot of ``tracks``; ``period`` (s) defaults to :func:`stride_period`."""
    period = stride_period(tracks) if period is None else period
    frames = max(3, int(round(period * tracks.fps)))
    if tracks.frame_count < 1.2 * frames:
        raise AnalysisError(f"the clip is {tracks.duration:.2f} s long but one stride takes {period:.2f} s; "
                            "give at least one full stride (about two steps)")
    signals = _signals(tracks, frames)
    result = [_foot_events(tracks, signals, f, frames) for f in range(len(tracks.names))]
    if not any(len(fe.steps) >= 2 for fe in result):
        raise AnalysisError(f"fewer than two steps found for every foot in {tracks.duration:.2f} s; "
                            "give a longer clip (at least one full stride)")
    return result


def _contact_curves(tracks: FootTracks, sig: _Signals, f: int) -> tuple[dict[str, tuple], dict[str, bool]]:
    """Foot ``f``'s heel and toe curves (height above the ground band, its derivatives,
    the curve's top and its crossings of the lift level), and which of them touch down."""
    curves = {}
    for part in ("heel", "toe"):
        # The ground band: the heights this point takes while it stands still (a rolling
        # paw's toe rises a little before the foot lifts).
        lifted = sig.above[part][:, f]
        static = np.hypot(sig.speeds[part][:, f], sig.rising[part][:, f] if tracks.exact else 0.0) < sig.static_speed
        band = float(np.percentile(lifted[static], 75)) if static.sum() > 3 else 0.0
        a = lifted - max(band, 0.0)
        top = max(float(np.percentile(a, 99)), 1e-9)
        curves[part] = (a, sig.slope[part][:, f], sig.bend[part][:, f], top, _crossings(a, LIFT_LEVEL * top))
    # A curve counts as a contact point only if that point is slow when the curve is
    # near its ground (a digitigrade "ankle" joint can be lowest in mid-swing).
    contact = {}
    for part, c in curves.items():
        down = c[0] < LIFT_LEVEL * c[3]
        speed_p = sig.speeds[part][:, f]
        contact[part] = bool(down.any()) and float(np.median(speed_p[down])) < \
            CONTACT_SPEED * max(float(np.median(speed_p)), 1e-9)
    if not any(contact.values()):
        contact = {"heel": True, "toe": True}
    if not contact["heel"]:
        curves["heel"] = curves["toe"]
    elif not contact["toe"]:
        curves["toe"] = curves["heel"]
    return curves, contact


def recorded_contacts(tracks: FootTracks, sig: _Signals, f: int, frames: int) -> NDArray[np.intp]:
    """A recorded foot's ground contacts, (N, 2) [first, last] frames (:func:`paw_contacts`):
    the foot is as low and as slow as the lower and the slower of its two tracked points,
    each above its own ground (either may be the one on the ground: a heel that rises
    while the toes push, a paw tip that slides). A person walking rolls over the sole
    (:data:`FOOT_SLOW`); a person running does not (:func:`runs_like_a_runner`) and is
    held to the paws' :data:`PAW_SLOW`."""
    if len(tracks.names) == 2 and not runs_like_a_runner(tracks, sig, frames):
        return _walker_contacts(tracks, sig, f, frames)
    height, speed, body_speed, low = _recorded_inputs(tracks, sig, f)
    return runs(paw_contacts(height, speed, body_speed, low, frames, PAW_SLOW))


def _walker_contacts(tracks: FootTracks, sig: _Signals, f: int, frames: int) -> NDArray[np.intp]:
    """Person ``f``'s contacts as a walker's (:data:`FOOT_SLOW`, at most
    :data:`FOOT_SLOW_MAX`), (N, 2) [first, last] frames; kept on ``sig``."""
    key = (frames, f)
    if key not in sig.walking:
        height, speed, body_speed, low = _recorded_inputs(tracks, sig, f)
        sig.walking[key] = runs(paw_contacts(height, speed, body_speed, low, frames, FOOT_SLOW,
                                             FOOT_SLOW_MAX * (tracks.hip_height or 0.9)))
    return sig.walking[key]


def runs_like_a_runner(tracks: FootTracks, sig: _Signals, frames: int) -> bool:
    """Whether a two-footed clip runs: its body is low through the middle third of a foot's
    contact (a runner lands on a spring), by more than :data:`RUNNER_DIP` below its mean
    over the stride; a walker vaults over its stance leg and is at or above its mean there
    (a person's pelvis rises twice a stride, over each stance leg). The contacts are a
    walker's (:data:`FOOT_SLOW`): long, for a runner, but centred. A clip of fewer than two
    whole contacts, or 1.2 strides, is no runner."""
    if len(tracks.names) != 2 or tracks.frame_count < 1.2 * frames:
        return False
    if frames in sig.runner:
        return sig.runner[frames]
    level = tracks.body[:, 1] - running_mean(tracks.body[:, 1], _odd(frames))  # (T,) m about its stride's mean
    middles: list[float] = []  # the body's mean level through each contact's middle third
    for f in range(2):
        spans = _walker_contacts(tracks, sig, f, frames)
        inside = spans[(spans[:, 0] > 0) & (spans[:, 1] < tracks.frame_count - 1)]  # whole contacts only
        for first, last in inside:
            third = (last - first) / 3.0
            middles.append(float(np.mean(level[int(round(first + third)):int(round(last - third)) + 1])))
    dip = -float(np.median(middles)) if len(middles) >= 2 else 0.0
    sig.runner[frames] = dip > RUNNER_DIP * (tracks.hip_height or 0.9)
    return sig.runner[frames]


def _recorded_inputs(tracks: FootTracks, sig: _Signals, f: int
                     ) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64], float]:
    """Foot ``f``'s height above its own ground and speed over it (T,) m, m/s (the lower
    and the slower of its two points), the body's speed (T,) m/s (the belt's, walking in
    place) and how low (m) a foot on the ground is; kept on ``sig``."""
    if f not in sig.inputs:
        sig.inputs[f] = _measure_inputs(tracks, sig, f)
    return sig.inputs[f]


def _measure_inputs(tracks: FootTracks, sig: _Signals, f: int
                    ) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64], float]:
    height = np.minimum(sig.above["heel"][:, f], sig.above["toe"][:, f])
    low = min(PAW_LOW * (tracks.hip_height or 0.5), PAW_LOW_MAX)
    k = max(1, int(round(tracks.fps / 60)))  # speeds over ~1/60 s: a gallop's stance may last six frames
    # Each point's velocity over the frame before and over the frame after (a planted
    # frame next to a swinging one is slow on its own side: a central difference would
    # take a frame off each end of every contact, 0.07 of the duty factor at 30 fps).
    dt = np.diff(tracks.times)[:, None]
    steps = [np.diff(points[:, f][:, [0, 2]], axis=0) / dt for points in (tracks.heel, tracks.toe)]  # (T-1, 2)
    sides = [(np.concatenate([v[:1], v]), np.concatenate([v, v[-1:]])) for v in steps]  # (before, after) (T, 2)
    body_speed = sig.body_speed
    swing = float(np.percentile(np.hypot(*sides[1][1].T), 90))
    body_path = float(np.sum(np.hypot(*np.diff(tracks.body[:, [0, 2]], axis=0).T)))
    foot_path = float(np.sum(np.hypot(*np.diff(tracks.toe[:, f][:, [0, 2]], axis=0).T)))
    belt = np.zeros(2)
    if body_path < IN_PLACE * foot_path:
        # A clip that walks in place (a treadmill, a game loop): the standing foot moves
        # with the belt, at the velocity the foot has at its lowest (a paw is "low" most of
        # the time, swinging too); slow means slow against that, and the belt's speed is
        # the body's.
        lowest = height <= np.percentile(height, BELT_HEIGHTS)
        belt = np.median(sides[1][1][lowest], axis=0)
        body_speed = np.full_like(body_speed, max(float(np.hypot(*belt)), IN_PLACE * swing))
    speed = np.full(tracks.frame_count, np.inf)
    for before, after in sides:
        one_sided = np.minimum(np.hypot(*(before - belt).T), np.hypot(*(after - belt).T))
        speed = np.minimum(speed, running_mean(one_sided, k))
    return height, speed, body_speed, low


def _foot_events(tracks: FootTracks, sig: _Signals, f: int, frames: int) -> FootEvents:
    """One foot's steps, then each stance's lift, liftoff, strike and landing on both
    curves, checked by speed. Exact motion: stance centres where heel and toe are low
    and slow, each step from the curves. Recorded motion (feet that slide, dip in swing
    and jitter): the contacts of :func:`recorded_contacts` give strike and liftoff, and
    each contact's firmest frame is its stance."""
    curves, contact = _contact_curves(tracks, sig, f)
    smooth = sig.smooth
    foot_speed = np.minimum(sig.speeds["heel"][:, f] if contact["heel"] else np.inf,
                            sig.speeds["toe"][:, f] if contact["toe"] else np.inf)
    a_heel, a_toe = curves["heel"][0], curves["toe"][0]
    speed_n = foot_speed / max(float(np.percentile(foot_speed, 95)), 1e-9)
    score = a_heel / curves["heel"][3] + a_toe / curves["toe"][3] + speed_n
    score = savgol(score, smooth, 2)
    recorded = not tracks.exact
    if not recorded:
        low = np.minimum(a_heel / curves["heel"][3], a_toe / curves["toe"][3])
        # Candidate stance frames at least a third of a stride apart (cadence may change
        # over the clip); two minima in one long stance are merged below.
        peaks, _ = find_peaks(-score, distance=max(1, int(0.3 * frames)))
        spread = float(np.ptp(score))
        peaks = np.asarray([p for p in peaks if low[p] < 0.25], dtype=np.intp)
        stances = _plateau_centres(score, peaks, spread) if peaks.size else peaks
    else:
        spans = recorded_contacts(tracks, sig, f, frames)
        firmest = np.array([a + int(np.argmin(score[a:b + 1])) for a, b in spans], dtype=np.intp)
        centres = _plateau_centres(score, firmest, float(np.ptp(score))) if len(spans) else firmest
        stances = np.clip(centres, spans[:, 0], spans[:, 1]) if len(spans) else firmest
    rel_f = np.ascontiguousarray(sig.rel[:, f])
    floor = 0.1 * float(np.percentile(np.abs(rel_f), 95))
    thresholds = SPEED_CHANGE * np.maximum(np.abs(rel_f[stances]), floor)
    # Every stance's events at once: lift and touchdown on both curves, speed checks.
    ups, downs, found = [], [], np.ones(len(stances), dtype=bool)
    for part in ("heel", "toe"):
        a, d1, d2, _, crossings = curves[part]
        up, ok_up = _curve_events(a, d1, d2, stances, crossings, +1, 4 * frames)
        down, ok_down = _curve_events(a, d1, d2, stances, crossings, -1, 4 * frames)
        ups.append(up)
        downs.append(down)
        found &= ok_up & ok_down
    lift, liftoff = np.minimum(*ups), np.maximum(*ups)
    strike, landing = np.minimum(*downs), np.maximum(*downs)
    z_up = _speed_checks(rel_f, stances, thresholds, +1, frames)
    z_down = _speed_checks(rel_f, stances, thresholds, -1, frames)
    lift = np.where((z_up >= 0) & (z_up < lift), np.maximum(z_up, stances), lift)
    landing = np.where((z_down >= 0) & (z_down > landing), np.minimum(z_down, stances), landing)
    if recorded:  # the contact decides where the step begins and ends
        strike, liftoff = spans[:, 0], spans[:, 1]
        landing, lift = np.clip(landing, strike, stances), np.clip(lift, stances, liftoff)
        found = (strike > 0) & (liftoff < tracks.frame_count - 1)
    steps = [Step(strike=int(strike[i]), landing=int(landing[i]), stance=int(stances[i]), lift=int(lift[i]),
                  liftoff=int(liftoff[i]), complete=bool(found[i])) for i in range(len(stances))]
    if not recorded:
        steps = _long_enough(_one_per_contact(steps, score), frames, tracks.frame_count)
    return FootEvents(name=tracks.names[f], steps=tuple(steps), heel_height=a_heel, toe_height=a_toe)
