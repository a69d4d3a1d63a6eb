"""What the viewer's overlays show, computed from poses (no drawing here).

- :func:`support_polygon`: the convex hull of the planted feet on the ground, the
  classic picture of static stability, and :func:`inside_polygon` for whether the
  trunk's centre projected to the ground lies inside it;
- :class:`FootprintTrail`: where feet landed, newest last, kept in a fixed-size ring;
- :func:`touchdown_targets`: where the swinging feet will land.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from .live import LiveMotion
from .motion import Pose

BALL = 3  # joint index of the foot's ball: what stands on the ground


def support_polygon(points: NDArray[np.float64]) -> NDArray[np.float64]:
    """The convex hull of ground points (N, 2, as (x, z)) as (K, 2) vertices ordered
    counter-clockwise in the (x, z) plane (positive signed area); fewer than three
    points give the points, collinear ones the segment's two ends (scipy's Qhull)."""
    from scipy.spatial import ConvexHull, QhullError

    pts = np.unique(np.asarray(points, dtype=np.float64).reshape(-1, 2), axis=0)
    if len(pts) < 3:
        return pts
    try:
        return pts[ConvexHull(pts).vertices]  # counter-clockwise for 2-D input
    except QhullError:  # all on one line: the segment's two ends
        order = np.argsort((pts - pts[0]) @ (pts[-1] - pts[0]))
        return pts[order[[0, -1]]]


def inside_polygon(point: NDArray[np.float64], hull: NDArray[np.float64]) -> bool:
    """Whether ground point ``point`` (2,) lies inside the convex polygon ``hull`` (K, 2)
    in counter-clockwise order (on an edge counts as inside; a segment or point has no
    inside)."""
    if len(hull) < 3:
        return False
    edge = np.roll(hull, -1, axis=0) - hull
    rel = np.asarray(point, dtype=np.float64) - hull
    return bool(np.all(edge[:, 0] * rel[:, 1] - edge[:, 1] * rel[:, 0] >= -1e-12))


def planted_points(pose: Pose) -> NDArray[np.float64]:
    """World positions (P, 3) of the planted feet's balls."""
    return pose.joints[pose.contact, BALL]


def trunk_centre(pose: Pose) -> NDArray[np.float64]:
    """The trunk's centre (3,): the body's root (the middle of the spine)."""
    return pose.root[:3, 3].copy()


def touchdown_targets(live: LiveMotion) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
    """Where each swinging foot will land (S, 3) and which legs swing (S,)."""
    plan = live.frame_plan()
    swinging = np.nonzero(~plan.contact[0])[0]
    return plan.end[0, swinging].copy(), swinging


@dataclass
class FootprintTrail:
    """The last ``capacity`` footprints: where and when feet landed, and which leg.

    :meth:`record` takes each frame's pose; a foot that is planted now at a spot it was
    not planted on last time (a new landing) adds one footprint. Vectorised over legs.
    Points are kept on the ground as it lies at time 0: in place (the ground moving
    back under the creature) a footprint is its foot's position plus the ground's
    offset then; :meth:`recent` gives them where the ground is now."""

    capacity: int = 256

    def __post_init__(self) -> None:
        self.points = np.zeros((self.capacity, 3))
        self.legs = np.zeros(self.capacity, dtype=np.int64)
        self.times = np.full(self.capacity, -np.inf)
        self.count = 0  # footprints recorded in all (the ring holds the last ``capacity``)
        self._last: NDArray[np.float64] | None = None  # (L, 3) where each foot last stood

    def clear(self) -> None:
        self.__post_init__()

    def record(self, pose: Pose, time: float) -> int:
        """Add this frame's new landings; returns how many."""
        balls = pose.joints[:, BALL] + np.array([0.0, 0.0, pose.ground_offset])
        if self._last is None or len(self._last) != len(balls):
            self._last = np.full((len(balls), 3), np.nan)
        moved = ~np.all(np.abs(balls - self._last) <= 1e-6, axis=1)
        new = np.nonzero(pose.contact & moved)[0]
        self._last[pose.contact] = balls[pose.contact]
        if len(new):
            slots = (self.count + np.arange(len(new))) % self.capacity
            self.points[slots] = balls[new]
            self.legs[slots] = new
            self.times[slots] = time
            self.count += len(new)
        return len(new)

    def recent(self, n: int, ground_offset: float = 0.0
               ) -> tuple[NDArray[np.float64], NDArray[np.int64], NDArray[np.float64]]:
        """The last ``n`` footprints, oldest first, on the ground moved back by
        ``ground_offset`` (m, in place): points (n, 3), legs (n,) and age (n,) from 1 (the
        oldest shown) to 0 (the newest)."""
        n = int(min(n, self.count, self.capacity))
        if n <= 0:
            return np.zeros((0, 3)), np.zeros(0, dtype=np.int64), np.zeros(0)
        slots = (self.count - n + np.arange(n)) % self.capacity
        age = np.linspace(1.0, 0.0, n) if n > 1 else np.zeros(1)
        points = self.points[slots] - np.array([0.0, 0.0, ground_offset])
        return points, self.legs[slots].copy(), age
