"""Driving a creature: speed and turning from held keys, a path laid down as it goes.

:class:`DrivenPath` is a path whose future is not known in advance: from where driving
began it is a chain of constant-curvature arcs, one started each time the curvature
changes, the last one running on for ever (the creature's body, its feet's footholds and
the camera look a little ahead along it). What lies behind stays as it was, so a foot
planted on the path's past never moves.

:class:`Driver` turns the keys held into a speed (m/s) and a curvature (1/m) with limited
acceleration, turn rate and lateral acceleration, and each step gives the creature the
gait for its speed (walk -> trot -> gallop by Froude number with hysteresis, as
``--speed`` does) before stepping its :class:`~app.kinematics.live.LiveMotion`. The feet
land where the gait planned them and stand still there while the body turns over them.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .gait import G
from .live import LiveMotion
from .path import Path
from .rig import Rig
from .speed import froude, gait_at_speed

MAX_ARCS = 20000  # arcs kept; older ones are dropped (the path before them runs straight back)


def _arc(s0: NDArray[np.float64], x0: NDArray[np.float64], z0: NDArray[np.float64], heading: NDArray[np.float64],
         curvature: NDArray[np.float64], s: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Points and tangents (N, 2) at arc lengths ``s`` along arcs that start at (x0, z0)
    with ``heading`` (radians from +Z towards +X) at arc length s0 and turn left by
    ``curvature`` radians per metre (all (N,))."""
    ds = s - s0
    turn = curvature * ds
    # sin(t)/t and (1 - cos t)/t, exact and stable through t = 0.
    a = np.sinc(turn / np.pi)
    b = 0.5 * turn * np.sinc(turn / (2.0 * np.pi)) ** 2
    c, sn = np.cos(heading), np.sin(heading)
    x = x0 + ds * (sn * a + c * b)
    z = z0 + ds * (c * a - sn * b)
    end = heading + turn
    return np.stack([x, z], axis=-1), np.stack([np.sin(end), np.cos(end)], axis=-1)


class DrivenPath(Path):
    """``base`` up to arc length ``s0``; from there, arcs laid down by :meth:`steer`.
    ``min_radius`` (m) is the tightest turn the driver will ever ask for."""

    kind = "driven"

    def __init__(self, base: Path, s0: float, min_radius: float) -> None:
        super().__init__()
        self.base = base
        self.s0 = float(s0)
        self.min_radius = float(min_radius)
        (point,), (tangent,) = base.sample(np.array([self.s0]))
        # Arcs: start arc length, start point, heading, curvature (each (P,)).
        self._s = np.array([self.s0])
        self._x, self._z = np.array([point[0]]), np.array([point[1]])
        self._heading = np.array([math.atan2(tangent[0], tangent[1])])
        self._k = np.array([0.0])

    @property
    def arcs(self) -> int:
        return len(self._s)

    @property
    def curvature(self) -> float:
        """The curvature (1/m, > 0 turning left) the path runs on with now."""
        return float(self._k[-1])

    def steer(self, s: float, curvature: float) -> None:
        """From arc length ``s`` (not before the last change) on, turn with ``curvature``."""
        if curvature == self._k[-1]:
            return
        s = max(float(s), float(self._s[-1]))
        if s == self._s[-1]:
            self._k[-1] = curvature
            return
        (point,), (_tangent,) = _arc(self._s[-1:], self._x[-1:], self._z[-1:], self._heading[-1:], self._k[-1:],
                                    np.array([s]))
        heading = float(self._heading[-1] + self._k[-1] * (s - self._s[-1]))
        keep = slice(-(MAX_ARCS - 1), None) if len(self._s) >= MAX_ARCS else slice(None)
        self._s = np.append(self._s[keep], s)
        self._x, self._z = np.append(self._x[keep], point[0]), np.append(self._z[keep], point[1])
        self._heading = np.append(self._heading[keep], heading)
        self._k = np.append(self._k[keep], curvature)

    def sample(self, s: ArrayLike) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        s = np.asarray(s, dtype=np.float64)
        flat = s.reshape(-1)
        i = np.clip(np.searchsorted(self._s, flat, side="right") - 1, 0, len(self._s) - 1)
        before = flat < self._s[0]
        # Before the first kept arc: straight back along its start tangent.
        k = np.where(before, 0.0, self._k[i])
        points, tangents = _arc(self._s[i], self._x[i], self._z[i], self._heading[i], k, flat)
        if self._s[0] == self.s0:
            old = flat < self.s0
            if old.any():
                points[old], tangents[old] = self.base.sample(flat[old])
        return points.reshape(s.shape + (2,)), tangents.reshape(s.shape + (2,))

    def _local(self, s):  # sample() is overridden; the arcs are already in the world
        raise NotImplementedError

    def curvature_radius(self) -> float:
        """The tightest turn the driver asks for (the path before driving no longer matters)."""
        return self.min_radius

    def describe(self) -> str:
        return f"driven ({self.arcs} arcs from {self.base.describe()})"


@dataclass(frozen=True)
class DriveLimits:
    """How fast a driven creature may change what it does. Speeds are given as Froude
    numbers (v^2 / (g h)) so one set of limits suits a mouse and a horse."""

    min_froude: float = 0.02  # the slowest stroll (the creature never stands quite still)
    max_froude: float = 9.0  # a fast gallop (a dog at about 6 m/s, a horse at 12)
    accel_g: float = 0.2  # acceleration and braking, in g
    lateral_g: float = 0.5  # sideways acceleration in a turn, in g: faster means wider turns
    min_radius: float = 1.0  # body lengths: the tightest turn at a walk
    turn_time: float = 0.4  # s to go from straight to the tightest turn (and back)
    throttle_time: float = 3.0  # s of holding W to go from the slowest to the fastest speed


class Driver:
    """Drives ``live`` (whose rig's speed table picks the gaits) from held keys.

    Each :meth:`step`: ``throttle`` (-1, 0 or 1: S, nothing, W) moves the asked-for
    speed, ``steer`` (-1 right, 0, 1 left) the asked-for turn; the speed follows the
    asked-for one at the acceleration limit, the curvature at the turn-rate limit, the
    gait follows the speed, and the motion steps.
    """

    def __init__(self, live: LiveMotion, rig: Rig, limits: DriveLimits = DriveLimits()) -> None:
        self.live = live
        self.limits = limits
        self.base_rig = rig
        h = rig.hip_height
        self.min_speed = math.sqrt(limits.min_froude * G * h)
        self.max_speed = math.sqrt(limits.max_froude * G * h)
        self.speed = float(np.clip(live.travel_per_cycle() * live.frequency, self.min_speed, self.max_speed))
        self.target_speed = self.speed
        self.curvature = 0.0
        self.gait = ""
        self._applied: tuple[float, Rig] | None = None
        self.path = DrivenPath(live.world.path, live.travel, limits.min_radius * rig.body_length)
        before = live.world
        live.world = replace(live.world, path=self.path)
        try:
            self._apply_speed()
        except BaseException:
            live.world = before  # nothing changes when the creature cannot be driven
            raise

    @property
    def froude(self) -> float:
        return froude(self.speed, self.base_rig.hip_height)

    @property
    def ground_speed(self) -> float:
        """The speed (m/s) the body is moving along its path now (the gait's, as blended)."""
        return float(self.live.travel_per_cycle() * self.live.frequency)

    @property
    def ground_froude(self) -> float:
        """The Froude number of :attr:`ground_speed`."""
        return froude(self.ground_speed, self.base_rig.hip_height)

    def set_rig(self, rig: Rig) -> None:
        """A new creature (edited in the panels): keep driving it at the same speed. On a
        :class:`~app.kinematics.world.WorldError` (a body the world cannot take) nothing
        changes."""
        saved = dict(self.__dict__)
        radius = self.path.min_radius
        try:
            self.base_rig = rig
            h = rig.hip_height
            self.min_speed = math.sqrt(self.limits.min_froude * G * h)
            self.max_speed = math.sqrt(self.limits.max_froude * G * h)
            self.path.min_radius = self.limits.min_radius * rig.body_length
            self.speed = float(np.clip(self.speed, self.min_speed, self.max_speed))
            self.target_speed = float(np.clip(self.target_speed, self.min_speed, self.max_speed))
            self._apply_speed()
        except BaseException:
            self.__dict__.update(saved)
            self.path.min_radius = radius
            raise

    def set_target_speed(self, speed: float) -> None:
        """Ask for ``speed`` (m/s, clamped to the creature's range); reached at the
        acceleration limit."""
        self.target_speed = float(np.clip(speed, self.min_speed, self.max_speed))

    def release(self) -> None:
        """Stop steering: the path runs straight on from here."""
        self.curvature = 0.0
        self.path.steer(self.live.travel, 0.0)

    def max_curvature(self, speed: float | None = None) -> float:
        """The tightest curvature (1/m) allowed at ``speed`` (default now)."""
        v = self.speed if speed is None else speed
        lateral = self.limits.lateral_g * G / max(v * v, 1e-9)
        return min(1.0 / self.path.min_radius, lateral)

    def step(self, dt: float, throttle: float = 0.0, steer: float = 0.0) -> None:
        if dt <= 0:
            return
        lim = self.limits
        span = self.max_speed - self.min_speed
        self.target_speed = float(np.clip(self.target_speed + throttle * span * dt / lim.throttle_time,
                                          self.min_speed, self.max_speed))
        accel = lim.accel_g * G * dt
        self.speed += float(np.clip(self.target_speed - self.speed, -accel, accel))
        k_max = self.max_curvature()
        wanted = float(np.clip(steer, -1.0, 1.0)) * k_max
        rate = (1.0 / self.path.min_radius) * dt / lim.turn_time
        self.curvature = float(np.clip(self.curvature + np.clip(wanted - self.curvature, -rate, rate), -k_max, k_max))
        self._apply_speed()
        self.path.steer(self.live.travel, self.curvature)
        self.live.step(dt)

    def _apply_speed(self) -> None:
        if self._applied is not None and self._applied[0] == self.speed and self._applied[1] is self.base_rig:
            return
        self._applied = (self.speed, self.base_rig)
        rig = gait_at_speed(self.base_rig, self.speed, self.gait or None)
        self.gait = rig.gait.preset
        self.live.set_rig(rig)
