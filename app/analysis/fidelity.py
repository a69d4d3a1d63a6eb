"""How close a gait is to the real thing: the measures of ``shared/reference/fidelity.md``
taken from a simulated motion's joints (never from the creature's own parameters).

:func:`walk_measures` for bipeds (speed, cadence, stride, duty, double support, knee,
hip and ankle events, pelvis motion, step width, arms, toe clearance), :func:`run_measures`
for a biped's run (flight acceleration, touchdown jolts, elbows), :func:`quadruped_measures`
for four-legged gaits (duty, stride, speed, head nod, back flexion). Each returns a dict
of named numbers; :data:`HUMAN_WALK`, :data:`HUMAN_RUN` give the published ranges.

Pure numpy, no GL.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from .angles import SAMPLES, cycle_curves, leg_angles, strikes_from_contact
from .filters import find_peaks

G = 9.81

# (low, high) typical adult values, fidelity.md.
HUMAN_WALK: dict[str, tuple[float, float]] = {
    "speed m/s": (1.2, 1.5),
    "cadence steps/min": (100.0, 120.0),
    "stride m": (1.3, 1.5),
    "stride / leg length": (1.4, 1.7),
    "duty factor": (0.58, 0.64),
    "double support %": (18.0, 26.0),
    "toe-off %": (58.0, 64.0),
    "knee at strike": (0.0, 10.0),
    "knee loading peak": (12.0, 24.0),
    "knee loading peak at %": (8.0, 18.0),
    "knee mid-stance": (0.0, 10.0),
    "knee at toe-off": (30.0, 45.0),
    "knee swing peak": (55.0, 70.0),
    "knee swing peak at %": (68.0, 76.0),
    "knee before strike": (0.0, 10.0),
    "hip at strike": (20.0, 32.0),
    "hip min": (-22.0, -8.0),
    "ankle at strike": (-5.0, 5.0),
    "ankle late stance max": (5.0, 16.0),
    "ankle at toe-off": (-25.0, -10.0),
    "ankle mid-swing": (-6.0, 6.0),
    "pelvis vertical cm": (3.0, 5.5),
    "pelvis peaks per cycle": (2.0, 2.0),
    "pelvis lateral cm": (3.0, 5.5),
    "pelvic obliquity deg": (2.0, 6.0),
    "pelvic rotation deg": (2.0, 6.0),
    "step width cm": (5.0, 12.0),
    "shoulder swing deg": (12.0, 28.0),
    "elbow deg": (12.0, 35.0),
    "toe clearance cm": (0.8, 3.0),
}

HUMAN_RUN: dict[str, tuple[float, float]] = {
    "flight acceleration g": (-1.1, -0.9),
    "largest vertical jolt g": (-3.0, 3.0),
    "elbow deg": (70.0, 110.0),
    "duty factor": (0.30, 0.40),
    "knee at toe-off": (0.0, 35.0),
    "cadence steps/min": (150.0, 190.0),
    "knee at strike": (15.0, 25.0),
    "knee stance peak": (40.0, 50.0),
    "knee swing peak": (90.0, 130.0),
    "hip at toe-off": (-20.0, -10.0),
    "ankle at toe-off": (-30.0, -20.0),
    "pelvis vertical cm": (6.0, 10.0),
}


def _cycles(motion) -> tuple[int, NDArray[np.intp], float]:
    """The reference foot (the rearmost left), its strikes and the median cycle (s)."""
    ref = motion.rig.leg_count - 2
    strikes = strikes_from_contact(motion.contact[:, ref])
    if len(strikes) < 3:
        raise ValueError("simulate at least three cycles to measure a gait")
    return ref, strikes, float(np.median(np.diff(strikes))) / motion.fps


def _mean_cycle(values: NDArray[np.float64], strikes: NDArray[np.intp]) -> NDArray[np.float64]:
    return cycle_curves(values, strikes).mean(axis=0)


def _horizontal(v: NDArray[np.float64]) -> NDArray[np.float64]:
    h = v.copy()
    h[..., 1] = 0.0
    return h / np.maximum(np.linalg.norm(h, axis=-1, keepdims=True), 1e-12)


def walk_measures(motion) -> dict[str, float]:
    """A biped's walk measured as fidelity.md's human-walk table is (see :data:`HUMAN_WALK`)."""
    rig = motion.rig
    ref, strikes, cycle = _cycles(motion)
    other = ref + 1
    span = slice(int(strikes[0]), int(strikes[-1]))
    fps = motion.fps
    out: dict[str, float] = {}
    root = motion.root[:, :3, 3]
    out["speed m/s"] = float(np.linalg.norm((root[strikes[-1]] - root[strikes[0]])[[0, 2]])
                             / ((strikes[-1] - strikes[0]) / fps))
    out["cadence steps/min"] = 120.0 / cycle
    out["stride m"] = out["speed m/s"] * cycle
    out["stride / leg length"] = out["stride m"] / rig.hip_height
    contact = motion.contact[span]
    out["duty factor"] = float(contact[:, ref].mean())
    out["double support %"] = 100.0 * float((contact[:, ref] & contact[:, other]).mean())
    out["toe-off %"] = 100.0 * out["duty factor"]
    forward = motion.root[:, :3, 2]
    j = motion.joints[:, ref]
    angles = leg_angles(j[:, 0], j[:, 1], j[:, 2], j[:, 3], forward, ankle_zero=-float(np.degrees(rig.ankle_lift[ref])))
    knee, hip, ankle = (_mean_cycle(a, strikes) for a in (angles.knee, angles.hip, angles.ankle))
    grid = np.linspace(0.0, 100.0, SAMPLES)
    toe_off = out["toe-off %"]
    out["knee at strike"] = float(knee[0])
    out["knee loading peak"] = float(knee[:26].max())
    out["knee loading peak at %"] = float(grid[int(np.argmax(knee[:26]))])
    out["knee mid-stance"] = float(knee[25:51].min())
    out["knee at toe-off"] = float(np.interp(toe_off, grid, knee))
    out["knee swing peak"] = float(knee[50:].max())
    out["knee swing peak at %"] = float(grid[50 + int(np.argmax(knee[50:]))])
    out["knee before strike"] = float(knee[95:].min())
    out["hip at strike"] = float(hip[0])
    out["hip min"] = float(hip.min())
    out["ankle at strike"] = float(ankle[0])
    out["ankle late stance max"] = float(ankle[30:int(toe_off)].max())
    out["ankle at toe-off"] = float(np.interp(toe_off, grid, ankle))
    out["ankle mid-swing"] = float(np.interp(0.5 * (toe_off + 100.0), grid, ankle))
    left = np.cross(np.array([0.0, 1.0, 0.0]), _horizontal(forward))
    out.update(_pelvis_measures(motion, ref, strikes, cycle, left))
    heel = motion.heel
    other_strikes = strikes_from_contact(motion.contact[:, other])
    widths = [abs(float(np.sum((heel[a, ref] - heel[b, other]) * left[a])))
              for a in strikes for b in other_strikes[(other_strikes > a)][:1]]
    out["step width cm"] = 100.0 * float(np.median(widths)) if widths else float("nan")
    out.update(_arm_measures(motion, strikes))
    out["toe clearance cm"] = _toe_clearance(motion, ref, strikes)
    return out


def _pelvis_measures(motion, ref: int, strikes: NDArray[np.int64], cycle: float,
                     left: NDArray[np.float64]) -> dict[str, float]:
    """The pelvis (the middle of the hips): its vertical and lateral excursion (cm), crests a
    cycle, obliquity and rotation (degrees, half the peak to peak). ``left`` (T, 3)."""
    out: dict[str, float] = {}
    other = ref + 1
    forward = motion.root[:, :3, 2]
    hips = motion.joints[:, [ref, other], 0]
    pelvis = hips.mean(axis=1)
    vertical = _mean_cycle(pelvis[:, 1], strikes)
    out["pelvis vertical cm"] = 100.0 * float(np.ptp(vertical))
    # Crests: maxima standing out by a tenth of the excursion (a millimetre's ripple is none),
    # counted once around the periodic cycle.
    periodic = np.concatenate([vertical[-SAMPLES // 4:-1], vertical, vertical[1:SAMPLES // 4]])
    crests, _ = find_peaks(periodic, prominence=0.1 * np.ptp(vertical))
    start = SAMPLES // 4 - 1
    out["pelvis peaks per cycle"] = float(np.count_nonzero((crests >= start) & (crests < start + SAMPLES - 1)))
    # Sideways: against the pelvis's own mean path (a cycle's running mean), towards the left.
    lateral = np.sum((pelvis - _running_mean(pelvis, int(round(cycle * motion.fps)))) * left, axis=-1)
    out["pelvis lateral cm"] = 100.0 * float(np.ptp(_mean_cycle(lateral, strikes)))
    across = hips[:, 0] - hips[:, 1]
    obliquity = np.degrees(np.arctan2(across[:, 1], np.linalg.norm(across[:, [0, 2]], axis=-1)))
    rotation = np.degrees(np.arctan2(np.sum(across * _horizontal(forward), axis=-1), np.sum(across * left, axis=-1)))
    out["pelvic obliquity deg"] = 0.5 * float(np.ptp(_mean_cycle(obliquity, strikes)))
    out["pelvic rotation deg"] = 0.5 * float(np.ptp(_mean_cycle(rotation, strikes)))
    return out


def _arm_measures(motion, strikes: NDArray[np.int64]) -> dict[str, float]:
    """The left arm's shoulder swing (degrees, half the peak to peak) and mean elbow angle;
    nothing for a creature without two arms."""
    out: dict[str, float] = {}
    forward = motion.root[:, :3, 2]
    if motion.arms.shape[1] == 2:
        arm = motion.arms[:, 0]  # the left arm: shoulder, elbow, wrist, hand
        upper, fore = arm[:, 1] - arm[:, 0], arm[:, 2] - arm[:, 1]
        fwd = _horizontal(forward)
        swing = np.degrees(np.arctan2(np.sum(upper * fwd, axis=-1), -upper[:, 1]))
        elbow = np.degrees(np.arccos(np.clip(np.sum(upper * fore, axis=-1) / (np.linalg.norm(upper, axis=-1)
                                                                          * np.linalg.norm(fore, axis=-1)), -1, 1)))
        out["shoulder swing deg"] = 0.5 * float(np.ptp(_mean_cycle(swing, strikes)))
        out["elbow deg"] = float(_mean_cycle(elbow, strikes).mean())
    return out


def _toe_clearance(motion, ref: int, strikes: NDArray[np.int64]) -> float:
    """The median over swings of the lowest the toe tip comes in the middle half of the
    swing, cm above the ground under it."""
    toe = motion.joints[:, ref, 4, 1] - _ground(motion, motion.joints[:, ref, 4])
    swing = ~motion.contact[:, ref]
    clear = []
    for a, b in zip(strikes[:-1], strikes[1:]):
        frames = np.arange(a, b)[swing[a:b]]
        if len(frames) > 4:
            middle = frames[len(frames) // 4: 3 * len(frames) // 4]
            clear.append(float(toe[middle].min()))
    return 100.0 * float(np.median(clear)) if clear else float("nan")


def _ground(motion, points: NDArray[np.float64]) -> NDArray[np.float64]:
    return motion.terrain.height(points[..., [0, 2]])


def _running_mean(points: NDArray[np.float64], window: int) -> NDArray[np.float64]:
    """Each frame's mean (T, 3) over ``window`` frames centred on it (the ends use what
    there is)."""
    window = max(1, window)
    kernel = np.ones(window)
    total = np.stack([np.convolve(points[:, k], kernel, mode="same") for k in range(points.shape[1])], axis=-1)
    count = np.convolve(np.ones(points.shape[0]), kernel, mode="same")
    return total / count[:, None]


def run_measures(motion) -> dict[str, float]:
    """A biped's run (see :data:`HUMAN_RUN`): the pelvis's vertical acceleration in flight
    (in g, mean over the middle of every flight) and its largest jolt in any frame, its
    vertical excursion, the elbow, duty factor, cadence and the sagittal angles at the
    strike and toe-off and their peaks (the hip is the thigh against the vertical)."""
    rig = motion.rig
    ref, strikes, cycle = _cycles(motion)
    other = ref + 1
    span = slice(int(strikes[0]), int(strikes[-1]))
    pelvis = motion.joints[:, [ref, other], 0].mean(axis=1)[:, 1]
    dt = 1.0 / motion.fps
    accel = np.gradient(np.gradient(pelvis, dt), dt) / G
    flight = ~(motion.contact[:, ref] | motion.contact[:, other])
    inner = flight & np.roll(flight, 2) & np.roll(flight, -2)  # away from the edges of each flight
    out: dict[str, float] = {}
    out["flight acceleration g"] = float(np.mean(accel[span][inner[span]])) if inner[span].any() else float("nan")
    out["largest vertical jolt g"] = float(accel[span][np.argmax(np.abs(accel[span]))])
    out["duty factor"] = float(motion.contact[span, ref].mean())
    out["cadence steps/min"] = 120.0 / cycle
    forward = motion.root[:, :3, 2]
    j = motion.joints[:, ref]
    angles = leg_angles(j[:, 0], j[:, 1], j[:, 2], j[:, 3], forward, ankle_zero=-float(np.degrees(rig.ankle_lift[ref])))
    knee, hip, ankle = (_mean_cycle(a, strikes) for a in (angles.knee, angles.hip, angles.ankle))
    grid = np.linspace(0.0, 100.0, SAMPLES)
    toe_off = 100.0 * out["duty factor"]
    stance = grid <= toe_off
    out["knee at toe-off"] = float(np.interp(toe_off, grid, knee))
    out["knee at strike"] = float(knee[0])
    out["knee stance peak"] = float(knee[stance].max())
    out["knee swing peak"] = float(knee[~stance].max())
    out["hip at toe-off"] = float(np.interp(toe_off, grid, hip))
    out["ankle at toe-off"] = float(np.interp(toe_off, grid, ankle))
    out["pelvis vertical cm"] = 100.0 * float(np.ptp(_mean_cycle(pelvis, strikes)))
    if motion.arms.shape[1] == 2:
        arm = motion.arms[:, 0]
        upper, fore = arm[:, 1] - arm[:, 0], arm[:, 2] - arm[:, 1]
        cos = np.sum(upper * fore, axis=-1) / (np.linalg.norm(upper, axis=-1) * np.linalg.norm(fore, axis=-1))
        out["elbow deg"] = float(np.degrees(np.arccos(np.clip(cos, -1, 1)))[span].mean())
    return out


def quadruped_measures(motion) -> dict[str, float]:
    """A four-legged gait: duty factor, speed, stride, cycle; the head's vertical motion
    (peak to peak, cm) and its main frequency against the stride's; the back's flexion
    (half its range, degrees: the trunk's rear against its front, in the sagittal plane)."""
    _, strikes, cycle = _cycles(motion)
    span = slice(int(strikes[0]), int(strikes[-1]))
    fps = motion.fps
    root = motion.root[:, :3, 3]
    out: dict[str, float] = {}
    out["duty factor"] = float(motion.contact[span].mean())
    out["speed m/s"] = float(np.linalg.norm((root[strikes[-1]] - root[strikes[0]])[[0, 2]])
                             / ((strikes[-1] - strikes[0]) / fps))
    out["stride m"] = out["speed m/s"] * cycle
    out["cycle s"] = cycle
    head = motion.head[span, 1, 1] - _ground(motion, motion.head[span, 1])  # the nose above the ground
    out["head vertical cm"] = 100.0 * float(np.ptp(_mean_cycle(motion.head[:, 1, 1], strikes)))
    spectrum = np.abs(np.fft.rfft(head - head.mean()))
    freqs = np.fft.rfftfreq(len(head), 1.0 / fps)
    out["head frequency / stride frequency"] = float(freqs[int(np.argmax(spectrum[1:])) + 1] * cycle)
    tangent = motion.spine_tangent
    forward = _horizontal(motion.root[:, :3, 2])
    left = np.cross(np.array([0.0, 1.0, 0.0]), forward)

    def pitch(t: NDArray[np.float64]) -> NDArray[np.float64]:
        t = t - np.sum(t * left, axis=-1, keepdims=True) * left
        return np.degrees(np.arctan2(t[..., 1], np.sum(t * forward, axis=-1)))

    flex = pitch(tangent[:, 0]) - pitch(tangent[:, -1])  # + arched (the rear tips down against the front)
    out["back flexion deg"] = 0.5 * float(np.ptp(_mean_cycle(flex, strikes)))
    return out
