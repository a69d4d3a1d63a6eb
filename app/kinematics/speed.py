"""Speed-driven gaits: from a speed (m/s) to the gait and its numbers, by dynamic similarity.

With hip height h, the Froude number is ``Fr = v^2 / (g h)``; stride length follows
``lambda / h = 2.3 Fr^0.3`` and the stride frequency is ``v / lambda`` (Alexander 1976;
Alexander & Jayes 1983). A tetrapod changes walk -> trot -> gallop at Froude thresholds
(0.5 and 2.5 by default, per creature in its ``[speed]`` table), up a little above a
threshold and down a little below it (hysteresis), and within each gait the duty factor
falls as speed rises (walks near 0.7 fall towards 0.55, trots from 0.45 to 0.33, gallops
to 0.2 at top speed). Other body plans keep their own gait, its frequency and stride
scaled by the same law. A creature whose speed changes over a clip is simulated by
:class:`~app.kinematics.live.LiveMotion`, so every gait change reaches the feet without a
jump; the poses are then solved for all frames at once.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
from numpy.typing import ArrayLike

from .gait import G
from .live import LiveMotion, stack_inputs
from .motion import Motion, solve_motion
from .rig import Rig, SpeedGaits
from .world import World

# Duty factor against sqrt(Froude) within each gait: (intercept, slope, low, high).
_DUTY = {"walk": (0.75, 0.28, 0.52, 0.80), "run": (0.45, 0.08, 0.22, 0.42), "trot": (0.50, 0.11, 0.30, 0.48),
         "gallop": (0.38, 0.065, 0.18, 0.33)}


def froude(speed: float, hip_height: float) -> float:
    """Froude number v^2 / (g h)."""
    return speed * speed / (G * hip_height)


def stride_length(speed: float, hip_height: float) -> float:
    """Distance per stride (m): 2.3 Fr^0.3 h."""
    return 2.3 * froude(speed, hip_height) ** 0.3 * hip_height


def choose_gait(fr: float, current: str | None, table: SpeedGaits) -> str:
    """The gait for Froude number ``fr``: the fastest of the table's ladder whose
    threshold ``fr`` reaches. ``current`` (the gait in use) makes the thresholds sticky:
    a faster gait needs its threshold times (1 + hysteresis), a slower one is kept down
    to its threshold times (1 - hysteresis)."""
    names = table.order
    level = names.index(current) if current in names else None
    chosen = 0
    for index, (_, threshold) in enumerate(table.ladder[1:], start=1):
        scale = 1.0 if level is None else 1.0 + table.hysteresis if index > level else 1.0 - table.hysteresis
        if fr >= threshold * scale:
            chosen = index
    return names[chosen]


def _table(rig: Rig) -> SpeedGaits:
    if rig.speed is None:
        return SpeedGaits(ladder=((rig.gait.preset, 0.0),), hysteresis=0.15, gaits={rig.gait.preset: rig.gait})
    return rig.speed


def gait_with_speed(rig: Rig, speed: float, gait: str) -> Rig:
    """``rig`` doing ``gait`` (one of its speed table's) at ``speed`` (m/s)."""
    table = _table(rig)
    template = table.gaits[gait]
    h = rig.hip_height
    fr = froude(speed, h)
    family = "gallop" if "gallop" in gait else gait
    if family in _DUTY:
        intercept, slope, lo, hi = _DUTY[family]
        duty = float(np.clip(intercept - slope * math.sqrt(fr), lo, hi))
    else:
        duty = template.duty_factor
    length = stride_length(speed, h)
    stride = min(length * duty / rig.leg_scale, 2.0)  # the planted foot's travel, in leg rest lengths
    return rig.with_gait(replace(template, frequency=speed / length, duty_factor=duty, stride=stride))


def gait_at_speed(rig: Rig, speed: float, current: str | None = None) -> Rig:
    """``rig`` with the gait for ``speed`` (m/s): preset, frequency, duty factor and stride."""
    if not math.isfinite(speed) or speed <= 0:
        raise ValueError(f"speed must be a positive number of m/s, got {speed}")
    gait = choose_gait(froude(speed, rig.hip_height), current, _table(rig))
    return gait_with_speed(rig, speed, gait)


def simulate_speed(rig: Rig, speeds: ArrayLike, fps: float, world: World | None = None) -> tuple[Motion, list[str]]:
    """A clip whose speed follows ``speeds`` (m/s, one per frame): its motion and the gait
    chosen at each frame. Gait changes blend seamlessly (see LiveMotion)."""
    speeds = np.asarray(speeds, dtype=np.float64)
    current = gait_at_speed(rig, float(speeds[0]))
    gait = current.gait.preset
    live = LiveMotion(current, world)
    dt = 1.0 / fps
    frames: list[dict] = []
    gaits: list[str] = []
    for i, v in enumerate(speeds):
        if i:
            target = gait_at_speed(rig, float(v), gait)
            gait = target.gait.preset
            live.set_rig(target)
            live.step(dt)
        frames.append(live.frame_inputs())
        gaits.append(gait)
    motion = solve_motion(live.rig, live.world, stack_inputs(frames), fps=fps)
    return motion, gaits
