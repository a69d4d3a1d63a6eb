"""The ground: height and normal at many (x, z) points in one call, and a mesh to draw.

Every terrain answers :meth:`Terrain.height` ((N, 2) -> (N,)) and :meth:`Terrain.normal`
((N, 2) -> (N, 3), unit, pointing up) for arrays of any leading shape, vectorised. The
procedural kinds are exact functions (flat, slope, hills from a sum of smooth waves with
analytic normals, stairs with vertical risers); heightmap images and mesh files become a
:class:`HeightGrid` (bilinear heights, normals from central differences). Loading files
lives in :mod:`app.worlds`; this module only does numbers.

``max_slope`` (radians) is the steepest ground a foot may stand on (see
:mod:`app.kinematics.footholds`).
"""

from __future__ import annotations

import math
from abc import ABC, abstractmethod

import numpy as np
from numpy.typing import ArrayLike, NDArray

DEFAULT_MAX_SLOPE = math.radians(40.0)
Mesh = tuple[NDArray[np.float32], NDArray[np.float32], NDArray[np.uint32]]  # positions, normals, indices


def _xz(points: ArrayLike) -> NDArray[np.float64]:
    return np.asarray(points, dtype=np.float64)


def _unit(v: NDArray[np.float64]) -> NDArray[np.float64]:
    return v / np.maximum(np.linalg.norm(v, axis=-1, keepdims=True), 1e-300)


def _normal_from_gradient(gx: NDArray[np.float64], gz: NDArray[np.float64]) -> NDArray[np.float64]:
    """Unit normals of a height field with slopes dh/dx, dh/dz."""
    return _unit(np.stack([-gx, np.ones_like(gx), -gz], axis=-1))


class Terrain(ABC):
    """Ground as a height field y = h(x, z)."""

    kind: str = "terrain"

    def __init__(self, max_slope: float = DEFAULT_MAX_SLOPE) -> None:
        self.max_slope = float(max_slope)

    @property
    def flat(self) -> bool:
        """True for the plane y = 0 (drawn as the plain floor)."""
        return False

    @abstractmethod
    def height(self, xz: ArrayLike) -> NDArray[np.float64]:
        """Ground height (m) under points (..., 2) -> (...)."""

    @abstractmethod
    def normal(self, xz: ArrayLike) -> NDArray[np.float64]:
        """Unit upward ground normals under points (..., 2) -> (..., 3)."""

    @abstractmethod
    def describe(self) -> str:
        """The terrain as the text ``--terrain`` takes."""

    def surface(self, lo: tuple[float, float], hi: tuple[float, float], cell: float) -> Mesh:
        """A triangle mesh of the ground over the box lo..hi (x, z), vertices about
        ``cell`` m apart on a grid fixed in the world (so a moving box does not make the
        surface swim): positions (V, 3), normals (V, 3) float32, indices (3M,) uint32."""
        x = _grid_axis(lo[0], hi[0], cell)
        z = _grid_axis(lo[1], hi[1], cell)
        gx, gz = np.meshgrid(x, z, indexing="xy")
        xz = np.stack([gx, gz], axis=-1).reshape(-1, 2)
        y = self.height(xz)
        positions = np.column_stack([xz[:, 0], y, xz[:, 1]]).astype(np.float32)
        return positions, self.normal(xz).astype(np.float32), grid_triangles(len(z) - 1, len(x) - 1)

    def __repr__(self) -> str:
        return f"<{type(self).__name__} {self.describe()}>"


def _grid_axis(lo: float, hi: float, cell: float) -> NDArray[np.float64]:
    start = math.floor(lo / cell) * cell
    count = max(2, int(math.ceil((hi - start) / cell)) + 1)
    return start + cell * np.arange(count, dtype=np.float64)


def grid_triangles(rows: int, cols: int) -> NDArray[np.uint32]:
    """Counter-clockwise (seen from above) triangles of a (rows+1) x (cols+1) vertex grid
    laid out row by row with x along a row and z across rows."""
    r, c = np.meshgrid(np.arange(rows), np.arange(cols), indexing="ij")
    a = r * (cols + 1) + c
    b = a + cols + 1
    return np.stack([a, b, a + 1, a + 1, b, b + 1], axis=-1).reshape(-1).astype(np.uint32)


class FlatTerrain(Terrain):
    """The plane y = 0."""

    kind = "flat"

    @property
    def flat(self) -> bool:
        return True

    def height(self, xz):
        return np.zeros(_xz(xz).shape[:-1])

    def normal(self, xz):
        shape = _xz(xz).shape[:-1]
        return np.broadcast_to(np.array([0.0, 1.0, 0.0]), shape + (3,)).copy()

    def describe(self) -> str:
        return "flat"


class SlopeTerrain(Terrain):
    """A plane rising at ``angle`` (radians) towards ``direction`` (radians from +Z
    towards +X), through y = 0 at the origin."""

    kind = "slope"

    def __init__(self, angle: float, direction: float = 0.0, max_slope: float = DEFAULT_MAX_SLOPE) -> None:
        super().__init__(max_slope)
        self.angle = float(angle)
        self.direction = float(direction)
        t = math.tan(self.angle)
        self._gradient = np.array([t * math.sin(self.direction), t * math.cos(self.direction)])

    def height(self, xz):
        return _xz(xz) @ self._gradient

    def normal(self, xz):
        shape = _xz(xz).shape[:-1]
        n = _normal_from_gradient(np.array(self._gradient[0]), np.array(self._gradient[1]))
        return np.broadcast_to(n, shape + (3,)).copy()

    def describe(self) -> str:
        return f"slope:angle={math.degrees(self.angle):g},dir={math.degrees(self.direction):g}"


class HillsTerrain(Terrain):
    """Rolling hills: a sum of smooth waves in random directions (seeded), with wavelengths
    spread around ``wavelength`` m, scaled so the heights span about +-``amplitude`` m.
    Heights and normals are exact (analytic derivatives)."""

    kind = "hills"
    WAVES = 7

    def __init__(self, amplitude: float, wavelength: float, seed: int = 1,
                 max_slope: float = DEFAULT_MAX_SLOPE) -> None:
        super().__init__(max_slope)
        self.amplitude = float(amplitude)
        self.wavelength = float(wavelength)
        self.seed = int(seed)
        rng = np.random.default_rng(self.seed)
        angles = rng.uniform(0.0, 2.0 * np.pi, self.WAVES)
        lengths = self.wavelength * np.geomspace(1.0, 0.35, self.WAVES) * rng.uniform(0.85, 1.15, self.WAVES)
        weights = (lengths / self.wavelength) ** 1.2
        k = 2.0 * np.pi / lengths
        self._k = np.stack([np.sin(angles) * k, np.cos(angles) * k], axis=-1)  # (W, 2) wave vectors
        self._phase = rng.uniform(0.0, 2.0 * np.pi, self.WAVES)
        # Normalise so that +-amplitude holds the heights (sum of |weights| bounds them;
        # the typical range is about half of that, so scale by it).
        self._a = self.amplitude * weights / (0.5 * weights.sum())

    def _arg(self, xz):
        return _xz(xz) @ self._k.T + self._phase  # (..., W)

    def height(self, xz):
        return np.sin(self._arg(xz)) @ self._a

    def normal(self, xz):
        c = np.cos(self._arg(xz)) * self._a  # (..., W)
        return _normal_from_gradient(c @ self._k[:, 0], c @ self._k[:, 1])

    def describe(self) -> str:
        return f"hills:amp={self.amplitude:g},wavelength={self.wavelength:g},seed={self.seed}"


class StairsTerrain(Terrain):
    """A flight of ``steps`` steps, each ``rise`` m up and ``run`` m deep, climbing towards
    ``direction`` (radians from +Z towards +X); the first riser is ``start`` m from the
    origin, flat ground before it and a landing after the last step. Risers are vertical."""

    kind = "stairs"

    def __init__(self, rise: float, run: float, steps: int = 12, start: float = 1.0, direction: float = 0.0,
                 max_slope: float = DEFAULT_MAX_SLOPE) -> None:
        super().__init__(max_slope)
        self.rise, self.run, self.steps = float(rise), float(run), int(steps)
        self.start, self.direction = float(start), float(direction)
        self._axis = np.array([math.sin(self.direction), math.cos(self.direction)])

    def _along(self, xz) -> NDArray[np.float64]:
        return _xz(xz) @ self._axis - self.start

    def step_index(self, xz) -> NDArray[np.float64]:
        """How many risers lie behind each point (0 before the flight, ``steps`` after it)."""
        u = self._along(xz)
        return np.clip(np.floor(u / self.run) + 1.0, 0.0, self.steps) * (u >= 0)

    def height(self, xz):
        return self.rise * self.step_index(xz)

    def normal(self, xz):
        shape = _xz(xz).shape[:-1]
        return np.broadcast_to(np.array([0.0, 1.0, 0.0]), shape + (3,)).copy()

    def edge_distance(self, xz) -> NDArray[np.float64]:
        """Distance (m) along the flight from each point to the nearest riser."""
        u = self._along(xz)
        edges = np.clip(np.round(u / self.run), 0, self.steps - 1) * self.run
        return np.abs(u - edges)

    def surface(self, lo, hi, cell) -> Mesh:
        # A height grid would slope the risers over a cell: build treads and risers exactly,
        # in the flight's frame (u along the climb, w across), then turn into the world.
        corners = np.array([[lo[0], lo[1]], [hi[0], lo[1]], [lo[0], hi[1]], [hi[0], hi[1]]])
        across = np.array([self._axis[1], -self._axis[0]])
        u_all, w_all = corners @ self._axis - self.start, corners @ across
        u0, u1, w0, w1 = u_all.min(), u_all.max(), w_all.min(), w_all.max()
        cuts = self.run * np.arange(self.steps)  # risers at u = k * run
        inside = cuts[(cuts > u0) & (cuts < u1)]
        bounds = np.concatenate([[u0], inside, [u1]])
        positions: list[NDArray[np.float64]] = []
        normals: list[NDArray[np.float64]] = []
        indices: list[NDArray[np.int64]] = []

        def quad(p: NDArray[np.float64], n: NDArray[np.float64]) -> None:
            base = sum(len(q) for q in positions)
            positions.append(p)
            normals.append(np.broadcast_to(n, (4, 3)))
            indices.append(base + np.array([0, 2, 1, 1, 2, 3]))

        def world(u, w, y):
            xz = np.outer(u + self.start, self._axis) + np.outer(w, across)
            return np.column_stack([xz[:, 0], y, xz[:, 1]])

        wq = np.array([w0, w1, w0, w1])
        for a, b in zip(bounds[:-1], bounds[1:]):
            y = self.height(((0.5 * (a + b) + self.start) * self._axis)[None])[0]
            quad(world(np.array([a, a, b, b]), wq, np.full(4, y)), np.array([0.0, 1.0, 0.0]))
        up = np.array([self._axis[0], 0.0, self._axis[1]])
        for u in inside:
            y_lo = self.height((((u - 1e-6) + self.start) * self._axis)[None])[0]
            y_hi = y_lo + self.rise
            quad(world(np.full(4, u), np.array([w1, w0, w1, w0]), np.array([y_lo, y_lo, y_hi, y_hi])), -up)
        positions_a = np.concatenate(positions).astype(np.float32)
        return positions_a, np.concatenate(normals).astype(np.float32), np.concatenate(indices).astype(np.uint32)

    def describe(self) -> str:
        return (f"stairs:rise={self.rise:g},run={self.run:g},steps={self.steps},start={self.start:g},"
                f"dir={math.degrees(self.direction):g}")


class HeightGrid(Terrain):
    """Heights sampled on a regular grid: ``heights`` (rows along z, columns along x)
    covering ``origin`` (x0, z0) to origin + ``size`` (m). Bilinear heights; normals from
    central differences (one-sided at the edges), interpolated bilinearly. Outside the
    grid the edge continues. The heights are kept as float32 and the normals worked out
    at the four grid points around each query, so a large grid costs 4 bytes a point."""

    kind = "grid"

    def __init__(self, heights: ArrayLike, origin: tuple[float, float], size: tuple[float, float],
                 label: str = "grid", max_slope: float = DEFAULT_MAX_SLOPE) -> None:
        super().__init__(max_slope)
        self.heights = np.ascontiguousarray(heights, dtype=np.float32)
        rows, cols = self.heights.shape
        self.origin = (float(origin[0]), float(origin[1]))
        self.size = (float(size[0]), float(size[1]))
        self.cell = (self.size[0] / (cols - 1), self.size[1] / (rows - 1))
        self.label = label

    def _grid_normals(self, iz: NDArray[np.int64], ix: NDArray[np.int64]) -> NDArray[np.float64]:
        """Normals (..., 3) at grid points (iz, ix), as ``np.gradient`` gives the slopes."""
        rows, cols = self.heights.shape
        h = self.heights
        x0, x1 = np.maximum(ix - 1, 0), np.minimum(ix + 1, cols - 1)
        z0, z1 = np.maximum(iz - 1, 0), np.minimum(iz + 1, rows - 1)
        gx = (h[iz, x1].astype(np.float64) - h[iz, x0]) / ((x1 - x0) * self.cell[0])
        gz = (h[z1, ix].astype(np.float64) - h[z0, ix]) / ((z1 - z0) * self.cell[1])
        return _normal_from_gradient(gx, gz)

    def _locate(self, xz):
        p = _xz(xz)
        rows, cols = self.heights.shape
        fx = np.clip((p[..., 0] - self.origin[0]) / self.cell[0], 0.0, cols - 1.000001)
        fz = np.clip((p[..., 1] - self.origin[1]) / self.cell[1], 0.0, rows - 1.000001)
        ix, iz = fx.astype(np.int64), fz.astype(np.int64)
        return ix, iz, (fx - ix)[..., None], (fz - iz)[..., None]

    def height(self, xz):
        ix, iz, tx, tz = self._locate(xz)
        h = self.heights
        tx, tz = tx[..., 0], tz[..., 0]
        g00, g01 = h[iz, ix].astype(np.float64), h[iz, ix + 1].astype(np.float64)
        g10, g11 = h[iz + 1, ix].astype(np.float64), h[iz + 1, ix + 1].astype(np.float64)
        return (g00 * (1 - tx) + g01 * tx) * (1 - tz) + (g10 * (1 - tx) + g11 * tx) * tz

    def normal(self, xz):
        ix, iz, tx, tz = self._locate(xz)
        n00, n01 = self._grid_normals(iz, ix), self._grid_normals(iz, ix + 1)
        n10, n11 = self._grid_normals(iz + 1, ix), self._grid_normals(iz + 1, ix + 1)
        return _unit((n00 * (1 - tx) + n01 * tx) * (1 - tz) + (n10 * (1 - tx) + n11 * tx) * tz)

    def describe(self) -> str:
        return self.label
