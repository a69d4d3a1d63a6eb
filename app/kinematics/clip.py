"""Clip timing: how many frames a clip has and the gait clock at each (no rendering here).

Shared by ``gaitlab render``, ``gaitlab analyze``, the viewer's recordings and tests, so
all of them see the same frames.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from .motion import Motion, check_reach, check_world, constant_gait_inputs, frame_count, solve_motion
from .rig import Rig
from .world import World

DEFAULT_CYCLES = 2.0
DEFAULT_SPEED_SECONDS = 4.0


def clip_motion(rig: Rig, fps: float, seconds: float | None = None, cycles: float | None = None,
                start: float = 0.0, speed: tuple[float, float] | None = None,
                world: World | None = None, closed: bool = False) -> tuple[Motion, float | None]:
    """The motion of a clip and, for whole-cycle clips, its cycle count.

    With ``cycles`` the frame count is ``round(cycles * fps / frequency)`` and the clock
    steps by exactly ``cycles / frames`` per frame (the frequency nudged by under half a
    frame per clip) so the last frame leads seamlessly into the first. With ``speed``
    (m/s at the first and last frame, linear in between) the gait follows the speed
    (:mod:`app.kinematics.speed`). ``world``: where to walk (default straight ahead on
    flat ground, travelling). ``closed`` (whole cycles only) adds the frame that closes
    the loop: the last frame then equals the first (shifted by the travel, if any), as
    animation packages expect of a cycle.
    """
    world = world or World()
    check_world(rig, world)
    if closed and (seconds is not None or speed is not None):
        raise ValueError("a closed loop needs whole cycles (not seconds or a speed ramp)")
    if speed is not None:
        motion, cycles = _speed_clip(rig, fps, seconds, cycles, speed, world, start)
        if not world.terrain.flat:
            check_reach(motion)
        return motion, cycles
    f = rig.gait.frequency
    start_clock = f * start
    if seconds is None:
        cycles = DEFAULT_CYCLES if cycles is None else cycles
        frames = max(1, int(round(cycles * fps / f)))
        clock = start_clock + cycles * np.arange(frames + int(closed), dtype=np.float64) / frames
    else:
        frames = frame_count(seconds, fps)
        clock = start_clock + f * np.arange(frames, dtype=np.float64) / fps
        cycles = None
    times = start + np.arange(len(clock)) / fps
    motion = solve_motion(rig, world, constant_gait_inputs(rig, world, clock, times), fps=fps)
    if not world.terrain.flat:
        check_reach(motion)
    return motion, cycles


def frame_at(rig: Rig, time: float, fps: float, world: World | None = None) -> Motion:
    """A one-frame motion at ``time`` seconds."""
    world = world or World()
    clock = np.array([rig.gait.frequency * time])
    return solve_motion(rig, world, constant_gait_inputs(rig, world, clock, np.array([time])), fps=fps)


def _speed_clip(rig: Rig, fps: float, seconds: float | None, cycles: float | None,
                speed: tuple[float, float], world: World, start: float = 0.0) -> tuple[Motion, float | None]:
    from .speed import gait_at_speed, simulate_speed

    if seconds is None:
        if cycles is not None:  # cycles need a constant speed (checked by the caller): its frequency
            seconds = cycles / gait_at_speed(rig, speed[0]).gait.frequency
        else:
            seconds = DEFAULT_SPEED_SECONDS
    frames = frame_count(seconds, fps)
    # A clip that starts at ``start`` s: the creature has walked at the first speed until
    # then (and is that far along its path); the ramp runs over the clip itself.
    before = int(round(start * fps))
    speeds = np.concatenate([np.full(before, speed[0]), np.linspace(speed[0], speed[1], frames)])
    motion, gaits = simulate_speed(rig, speeds, fps, world=world)
    return replace(motion, gaits=tuple(gaits)).frames(before), None
