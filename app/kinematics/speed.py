"""Speed-driven gaits: from a speed (m/s) to the gait and its numbers, by dynamic similarity.

With hip height h, the Froude number is ``Fr = v^2 / (g h)``; stride length follows
``lambda / h = 2.3 Fr^0.3`` and the stride frequency is ``v / lambda`` (Alexander 1976;
Alexander & Jayes 1983). The gait changes walk -> trot -> gallop at Froude thresholds
(0.5 and 2.5 by default, per creature in its ``[speed]`` table), up a little above a
threshold and down a little below it (hysteresis), and within each gait the duty factor
falls as speed rises (walks near 0.7 fall towards 0.55, trots from 0.45 to 0.33, gallops
to 0.2 at top speed). A creature whose speed changes over a clip is simulated by
:class:`~app.kinematics.live.LiveMotion`, so every gait change reaches the feet without a
jump; the poses are then solved for all frames at once.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike

from ..spec import CreatureSpec
from .live import LiveMotion
from .motion import Motion, solve_motion
from .rig import G, build_rig

# Duty factor against sqrt(Froude) within each gait: (intercept, slope, low, high).
_DUTY = {"walk": (0.75, 0.28, 0.52, 0.80), "trot": (0.50, 0.11, 0.30, 0.48), "gallop": (0.38, 0.065, 0.18, 0.33)}


def froude(speed: float, hip_height: float) -> float:
    """Froude number v^2 / (g h)."""
    return speed * speed / (G * hip_height)


def stride_length(speed: float, hip_height: float) -> float:
    """Distance per stride (m): 2.3 Fr^0.3 h."""
    return 2.3 * froude(speed, hip_height) ** 0.3 * hip_height


def choose_gait(fr: float, current: str | None, spec: CreatureSpec) -> str:
    """walk, trot or the creature's gallop for Froude number ``fr``; ``current`` (the gait
    in use) makes the thresholds sticky by the hysteresis fraction."""
    up, down = 1.0 + spec.speed.hysteresis, 1.0 - spec.speed.hysteresis
    gallop = spec.speed.gallop
    level = {"walk": 0, "trot": 1, gallop: 2}.get(current or "", None)
    wt, tg = spec.speed.walk_trot, spec.speed.trot_gallop
    if level is None:
        return "walk" if fr < wt else "trot" if fr < tg else gallop
    if level == 0:
        return gallop if fr >= tg * up else "trot" if fr >= wt * up else "walk"
    if level == 1:
        return gallop if fr >= tg * up else "walk" if fr < wt * down else "trot"
    return gallop if fr >= tg * down else "walk" if fr < wt * down else "trot"


def gait_at_speed(spec: CreatureSpec, speed: float, current: str | None = None) -> CreatureSpec:
    """``spec`` with the gait for ``speed`` (m/s): preset, frequency, duty factor and stride."""
    if not math.isfinite(speed) or speed <= 0:
        raise ValueError(f"speed must be a positive number of m/s, got {speed}")
    gait = choose_gait(froude(speed, build_rig(spec).hip_height), current, spec)
    return gait_with_speed(spec, speed, gait)


def gait_with_speed(spec: CreatureSpec, speed: float, gait: str) -> CreatureSpec:
    """``spec`` doing ``gait`` at ``speed`` (m/s), whatever the thresholds say."""
    rig = build_rig(spec)
    h = rig.hip_height
    fr = froude(speed, h)
    intercept, slope, lo, hi = _DUTY["gallop" if "gallop" in gait else gait]
    duty = float(np.clip(intercept - slope * math.sqrt(fr), lo, hi))
    length = stride_length(speed, h)
    stride = length * duty / float(rig.l_rest.mean())  # the planted foot's travel, in leg rest lengths
    return spec.with_overrides({"gait.preset": gait, "gait.frequency": speed / length, "gait.duty_factor": duty,
                                "gait.stride": min(stride, 2.0)})


def simulate_speed(spec: CreatureSpec, speeds: ArrayLike, fps: float) -> tuple[Motion, list[str]]:
    """A clip whose speed follows ``speeds`` (m/s, one per frame): its motion and the gait
    chosen at each frame. Gait changes blend seamlessly (see LiveMotion)."""
    speeds = np.asarray(speeds, dtype=np.float64)
    gait = None
    current = gait_at_speed(spec, float(speeds[0]))
    gait = current.gait.preset
    live = LiveMotion(current)
    dt = 1.0 / fps
    frames: list[dict] = []
    gaits: list[str] = []
    for i, v in enumerate(speeds):
        if i:
            target = gait_at_speed(spec, float(v), gait)
            gait = target.gait.preset
            live.set_spec(target)
            live.step(dt)
        frames.append(live.frame_inputs())
        gaits.append(gait)
    rig = live.rig
    stack = lambda key: np.array([f[key] for f in frames])  # noqa: E731
    forward = None if any(f["forward_m"] is None for f in frames) else stack("forward_m")
    motion = solve_motion(rig, stack("clock"), offsets=stack("offsets"), duty=stack("duty"), stride=stack("stride"),
                          step_height=stack("step_height"), bob=stack("bob"), ground_offset=stack("ground"),
                          times=stack("time"), fps=fps, forward_m=forward)
    return motion, gaits
