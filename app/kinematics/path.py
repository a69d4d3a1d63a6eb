"""Paths on the ground that a creature's body follows, parameterised by arc length.

A path lives in the ground plane (x, z); heights come from the terrain. Every path starts
at its ``start`` point heading ``heading`` (radians from +Z towards +X: 0 is straight
ahead, +pi/2 turns to the creature's left) and answers :meth:`Path.sample` for arrays of
arc lengths: points (N, 2) and unit tangents (N, 2) as (x, z). Arc lengths before the
start or past the end of an open path continue straight along the end tangent, so a
body whose rear is still behind the start, or a clip longer than the path, is defined.
Closed paths (circle, figure-eight) wrap around.

Kinds: :class:`StraightPath`, :class:`CirclePath`, :class:`FigureEightPath` and
:class:`WaypointPath` (centripetal Catmull-Rom through points: no cusps or loops within
a segment, Yuksel et al. 2011).
"""

from __future__ import annotations

import math
from abc import ABC, abstractmethod
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike, NDArray


def left_of(tangent: NDArray[np.float64]) -> NDArray[np.float64]:
    """The unit (x, z) direction to the left of tangents (..., 2): +X for a +Z heading."""
    return np.stack([tangent[..., 1], -tangent[..., 0]], axis=-1)


def _rotate(xz: NDArray[np.float64], heading: float) -> NDArray[np.float64]:
    """Rotate (x, z) vectors from the frame that faces +Z to one that faces ``heading``."""
    c, s = math.cos(heading), math.sin(heading)
    x, z = xz[..., 0], xz[..., 1]
    return np.stack([c * x + s * z, -s * x + c * z], axis=-1)


class Path(ABC):
    """A ground path parameterised by arc length (m). Subclasses give the local shape
    (starting at the origin, facing +Z); the base class places it at ``start``/``heading``."""

    kind: str = "path"

    def __init__(self, start: tuple[float, float] = (0.0, 0.0), heading: float = 0.0) -> None:
        self.start = (float(start[0]), float(start[1]))
        self.heading = float(heading)

    @property
    def closed(self) -> bool:
        return False

    @property
    def length(self) -> float:
        """Arc length (m) of the path's own shape (``inf`` for a straight line)."""
        return math.inf

    @abstractmethod
    def _local(self, s: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Points and unit tangents (N, 2) at arc lengths s within [0, length]."""

    @abstractmethod
    def describe(self) -> str:
        """The path as the text ``--path`` takes."""

    def sample(self, s: ArrayLike) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Points and unit tangents (x, z) at arc lengths ``s`` (any shape): (..., 2) each."""
        s = np.asarray(s, dtype=np.float64)
        flat = s.reshape(-1)
        if self.closed:
            local_s = np.mod(flat, self.length)
            points, tangents = self._local(local_s)
        else:
            end = self.length
            inside = np.clip(flat, 0.0, end)
            points, tangents = self._local(inside)
            beyond = flat - inside  # < 0 before the start, > 0 past the end: go straight on
            points = points + beyond[:, None] * tangents
        points = _rotate(points, self.heading) + np.asarray(self.start)
        tangents = _rotate(tangents, self.heading)
        return points.reshape(s.shape + (2,)), tangents.reshape(s.shape + (2,))

    def curvature_radius(self) -> float:
        """The smallest turning radius along the path (m); ``inf`` for a straight line."""
        return math.inf

    def __repr__(self) -> str:
        return f"<{type(self).__name__} {self.describe()}>"


class StraightPath(Path):
    """Straight ahead from ``start`` along ``heading``."""

    kind = "straight"

    def _local(self, s):
        points = np.stack([np.zeros_like(s), s], axis=-1)
        return points, np.broadcast_to(np.array([0.0, 1.0]), points.shape).copy()

    def sample(self, s: ArrayLike) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """As :meth:`Path.sample`, the same numbers in a few operations (the live motion
        samples its path several times per step)."""
        s = np.asarray(s, dtype=np.float64)
        direction = np.array([math.sin(self.heading), math.cos(self.heading)])
        points = np.multiply.outer(s, direction) + np.asarray(self.start)
        return points, np.broadcast_to(direction, points.shape).copy()

    def describe(self) -> str:
        return "straight" + (f":heading={math.degrees(self.heading):g}" if self.heading else "")


class CirclePath(Path):
    """A circle of ``radius`` m turning ``direction`` ("left" or "right") from the start."""

    kind = "circle"

    def __init__(self, radius: float, direction: str = "left", start=(0.0, 0.0), heading: float = 0.0) -> None:
        super().__init__(start, heading)
        self.radius = float(radius)
        self.direction = direction
        self.sign = 1.0 if direction == "left" else -1.0

    @property
    def closed(self) -> bool:
        return True

    @property
    def length(self) -> float:
        return 2.0 * math.pi * self.radius

    def _local(self, s):
        a = s / self.radius
        points = np.stack([self.sign * self.radius * (1.0 - np.cos(a)), self.radius * np.sin(a)], axis=-1)
        tangents = np.stack([self.sign * np.sin(a), np.cos(a)], axis=-1)
        return points, tangents

    def curvature_radius(self) -> float:
        return self.radius

    def describe(self) -> str:
        return f"circle:r={self.radius:g},dir={self.direction}"


class FigureEightPath(Path):
    """Two circles of ``radius`` m that touch at the start: a left loop, then a right loop."""

    kind = "figure-eight"

    def __init__(self, radius: float, start=(0.0, 0.0), heading: float = 0.0) -> None:
        super().__init__(start, heading)
        self.radius = float(radius)

    @property
    def closed(self) -> bool:
        return True

    @property
    def length(self) -> float:
        return 4.0 * math.pi * self.radius

    def _local(self, s):
        r = self.radius
        loop = 2.0 * math.pi * r
        sign = np.where(s < loop, 1.0, -1.0)
        a = np.where(s < loop, s, s - loop) / r
        points = np.stack([sign * r * (1.0 - np.cos(a)), r * np.sin(a)], axis=-1)
        tangents = np.stack([sign * np.sin(a), np.cos(a)], axis=-1)
        return points, tangents

    def curvature_radius(self) -> float:
        return self.radius

    def describe(self) -> str:
        return f"figure-eight:r={self.radius:g}"


@dataclass
class _Table:
    """A dense arc-length table of a curve: cumulative length (M,), points and tangents (M, 2)."""

    s: NDArray[np.float64]
    points: NDArray[np.float64]
    tangents: NDArray[np.float64] = field(repr=False)


class WaypointPath(Path):
    """A centripetal Catmull-Rom spline through ``points`` (N, 2) given in world (x, z),
    leaving its first point along ``start_direction`` (x, z) when given.

    The spline is sampled densely once and inverted for arc length by interpolation (a
    lookup table); ``start`` and ``heading`` are the first point and the first tangent.
    """

    kind = "waypoints"
    SAMPLES_PER_SEGMENT = 400

    def __init__(self, points: ArrayLike, closed: bool = False, start_direction: ArrayLike | None = None) -> None:
        pts = np.asarray(points, dtype=np.float64).reshape(-1, 2)
        self.points = pts
        self._closed = bool(closed)
        direction = None if start_direction is None else np.asarray(start_direction, dtype=np.float64).reshape(2)
        self._table = self._build(pts, self._closed, direction)
        super().__init__((0.0, 0.0), 0.0)  # the points are already in the world

    @property
    def closed(self) -> bool:
        return self._closed

    @property
    def length(self) -> float:
        return float(self._table.s[-1])

    def point_arc_lengths(self, first: int, count: int) -> NDArray[np.float64]:
        """Arc lengths (m, (count,)) at which the path passes its points ``first`` to
        ``first + count - 1``."""
        knots = np.arange(first, first + count) * self.SAMPLES_PER_SEGMENT
        return self._table.s[knots]

    @staticmethod
    def _build(pts: NDArray[np.float64], closed: bool, start_direction: NDArray[np.float64] | None = None) -> _Table:
        if closed:
            ctrl = np.concatenate([pts[-1:], pts, pts[:2]])
        else:  # mirror the end points so the spline starts and ends along its end segments
            before = 2 * pts[:1] - pts[1:2]
            if start_direction is not None:  # ... or leaves its start along a given direction
                unit = start_direction / max(float(np.linalg.norm(start_direction)), 1e-12)
                before = pts[:1] - unit * np.linalg.norm(pts[1] - pts[0])
            ctrl = np.concatenate([before, pts, 2 * pts[-1:] - pts[-2:-1]])
        p0, p1, p2, p3 = ctrl[:-3], ctrl[1:-2], ctrl[2:-1], ctrl[3:]

        def knot(a, b):
            return np.sqrt(np.maximum(np.linalg.norm(b - a, axis=-1), 1e-12))[:, None]  # alpha = 0.5

        t01, t12, t23 = knot(p0, p1), knot(p1, p2), knot(p2, p3)
        # Tangents at p1 and p2 of the centripetal spline, scaled to the segment [0, 1].
        m1 = (p1 - p0) / t01 - (p2 - p0) / (t01 + t12) + (p2 - p1) / t12
        m2 = (p2 - p1) / t12 - (p3 - p1) / (t12 + t23) + (p3 - p2) / t23
        m1, m2 = m1 * t12, m2 * t12
        u = np.linspace(0.0, 1.0, WaypointPath.SAMPLES_PER_SEGMENT + 1)[:-1]
        u = u[None, :, None]
        h00, h10 = 2 * u ** 3 - 3 * u ** 2 + 1, u ** 3 - 2 * u ** 2 + u
        h01, h11 = -2 * u ** 3 + 3 * u ** 2, u ** 3 - u ** 2
        pts_dense = h00 * p1[:, None] + h10 * m1[:, None] + h01 * p2[:, None] + h11 * m2[:, None]
        d00, d10, d01, d11 = 6 * u ** 2 - 6 * u, 3 * u ** 2 - 4 * u + 1, -6 * u ** 2 + 6 * u, 3 * u ** 2 - 2 * u
        tan_dense = d00 * p1[:, None] + d10 * m1[:, None] + d01 * p2[:, None] + d11 * m2[:, None]
        points = np.concatenate([pts_dense.reshape(-1, 2), p2[-1:]])
        tangents = np.concatenate([tan_dense.reshape(-1, 2), m2[-1:]])
        tangents /= np.maximum(np.linalg.norm(tangents, axis=-1, keepdims=True), 1e-12)
        s = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(points, axis=0), axis=-1))])
        return _Table(s=s, points=points, tangents=tangents)

    def _local(self, s):
        t = self._table
        points = np.stack([np.interp(s, t.s, t.points[:, 0]), np.interp(s, t.s, t.points[:, 1])], axis=-1)
        tangents = np.stack([np.interp(s, t.s, t.tangents[:, 0]), np.interp(s, t.s, t.tangents[:, 1])], axis=-1)
        tangents /= np.maximum(np.linalg.norm(tangents, axis=-1, keepdims=True), 1e-12)
        return points, tangents

    def curvature_radius(self) -> float:
        t = self._table
        turn = np.abs(np.diff(np.unwrap(np.arctan2(t.tangents[:, 0], t.tangents[:, 1]))))
        ds = np.diff(t.s)
        curvature = turn / np.maximum(ds, 1e-12)
        return float(1.0 / max(curvature.max(), 1e-12))

    def describe(self) -> str:
        coords = ",".join(f"{v:g}" for v in self.points.reshape(-1))
        return f"waypoints:{coords}" + (",closed" if self._closed else "")


def path_distance(path: Path, points: NDArray[np.float64], s_hint: NDArray[np.float64],
                  window: float) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Distance (m) of ground points (N, 2) from the path, searched within ``window`` m of
    arc length around ``s_hint`` (N,); also the arc length of the nearest path point."""
    offsets = np.linspace(-window, window, 161)
    s = s_hint[:, None] + offsets[None, :]
    pts, _ = path.sample(s)
    d = np.linalg.norm(pts - points[:, None, :], axis=-1)
    best = d.argmin(axis=1)
    return d[np.arange(len(points)), best], s[np.arange(len(points)), best]


class SplicedPath(Path):
    """``base`` up to arc length ``s0``, then ``then`` (whose own arc length 0 is at
    ``s0``): a new route taken from where the body is, the way it came kept behind it.
    ``then`` should start where ``base`` is at ``s0``, along its tangent there.

    Splicing onto a spliced path does not nest: the routes are kept as one flat list of
    (start, route) after the first path (``root``), a later splice replacing every route
    that started at or after it, and the oldest dropped beyond MAX_ROUTES (the path that
    far behind then follows ``root``), so sampling stays one pass whatever the number of
    edits."""

    kind = "spliced"
    MAX_ROUTES = 200

    def __init__(self, base: Path, s0: float, then: Path) -> None:
        super().__init__()
        s0 = float(s0)
        self.root: Path
        if isinstance(base, SplicedPath):
            self.root = base.root
            kept = [(s, route) for s, route in base.routes if s < s0]
        else:
            self.root = base
            kept = []
        self.routes: list[tuple[float, Path]] = (kept + [(s0, then)])[-self.MAX_ROUTES:]
        self.s0 = s0
        self.then = then

    @property
    def base(self) -> Path:
        return self.root

    @property
    def closed(self) -> bool:
        return False

    def sample(self, s: ArrayLike) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        s = np.asarray(s, dtype=np.float64)
        flat = s.reshape(-1)
        starts = np.array([start for start, _ in self.routes])
        which = np.searchsorted(starts, flat, side="right") - 1  # -1: before every route, the root
        points = np.empty((len(flat), 2))
        tangents = np.empty((len(flat), 2))
        for k in np.unique(which):
            pick = which == k
            if k < 0:
                points[pick], tangents[pick] = self.root.sample(flat[pick])
            else:
                start, route = self.routes[k]
                points[pick], tangents[pick] = route.sample(flat[pick] - start)
        return points.reshape(s.shape + (2,)), tangents.reshape(s.shape + (2,))

    def _local(self, s):  # sample() is overridden
        raise NotImplementedError

    def curvature_radius(self) -> float:
        """The route being taken now: past routes no longer limit the body."""
        return self.then.curvature_radius()

    def describe(self) -> str:
        return self.then.describe()


def turn_towards(start: NDArray[np.float64], heading: float, target: NDArray[np.float64], radius: float
                 ) -> NDArray[np.float64]:
    """Points (N, 2) of a way from ``start`` (x, z), facing ``heading`` (rad, from +Z
    towards +X), to ``target`` (x, z) that never turns tighter than ``radius`` (m): an arc
    on the target's side until the target lies straight ahead, then a straight line
    (Dubins' turn-and-go). A target inside that turning circle is reached by the loop
    the other way round. The first point is ``start``, the last ``target``; the points
    lie a quarter radius apart, for a spline through them to keep the radius."""
    start = np.asarray(start, dtype=np.float64)
    target = np.asarray(target, dtype=np.float64)
    forward = np.array([np.sin(heading), np.cos(heading)])
    to_target = target - start
    cross = forward[0] * to_target[1] - forward[1] * to_target[0]
    side = 1.0 if cross >= 0.0 else -1.0  # +1: the target is on the side of +90 degrees turned from forward
    normal = side * np.array([-forward[1], forward[0]])
    centre = start + radius * normal
    if np.linalg.norm(target - centre) < radius * 1.05:  # inside the turn: loop round the other way
        side, normal = -side, -normal
        centre = start + radius * normal
    # Along the arc, the heading turns by theta; the target is straight ahead where the
    # line from the arc point to the target is the arc's tangent there.
    theta = np.linspace(0.0, 2.0 * np.pi, 721)
    radial0 = start - centre
    rot = side * theta
    cos_t, sin_t = np.cos(rot), np.sin(rot)
    radial = np.stack([radial0[0] * cos_t - radial0[1] * sin_t, radial0[0] * sin_t + radial0[1] * cos_t], axis=-1)
    on_arc = centre + radial
    ahead = np.stack([forward[0] * cos_t - forward[1] * sin_t, forward[0] * sin_t + forward[1] * cos_t], axis=-1)
    towards = target - on_arc
    misalign = ahead[:, 0] * towards[:, 1] - ahead[:, 1] * towards[:, 0]  # cross(ahead, towards)
    facing = np.sum(ahead * towards, axis=-1) > 0.0
    crossing = np.nonzero(facing[1:] & (np.sign(misalign[1:]) != np.sign(misalign[:-1])))[0]
    aligned = facing & (np.abs(misalign) <= 1e-9)
    if aligned[0] or (not crossing.size and not aligned.any()):
        return np.stack([start, target])  # already facing it
    stop = int(crossing[0]) + 1 if crossing.size else int(np.argmax(aligned))
    # Evenly spaced along the whole way (arc, then line), a quarter radius apart.
    arc_length = radius * theta[stop]
    line = np.linalg.norm(target - on_arc[stop])
    count = max(2, int(np.ceil((arc_length + line) / (0.25 * radius))) + 1)
    s_at = np.linspace(0.0, arc_length + line, count)
    on_turn = s_at <= arc_length
    angle = side * s_at / radius
    c, s_ = np.cos(angle), np.sin(angle)
    turning = centre + np.stack([radial0[0] * c - radial0[1] * s_, radial0[0] * s_ + radial0[1] * c], axis=-1)
    going = on_arc[stop] + (target - on_arc[stop]) * (np.clip(s_at - arc_length, 0.0, None) / max(line, 1e-12))[:, None]
    return np.where(on_turn[:, None], turning, going)

