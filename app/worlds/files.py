"""Ground from files: greyscale heightmap images and meshes, as height grids."""

from __future__ import annotations

import math
import warnings
from pathlib import Path as FilePath

import numpy as np
from numpy.typing import NDArray

from ..errors import not_a_file
from ..kinematics.terrain import DEFAULT_MAX_SLOPE, HeightGrid
from ..kinematics.world import WorldError


def _check_file(file: FilePath) -> None:
    if not file.is_file():
        raise WorldError(f"{file}: {not_a_file(file)}")


MAX_HEIGHTMAP_SIDE = 8192
MAX_HEIGHTMAP_PIXELS = MAX_HEIGHTMAP_SIDE * MAX_HEIGHTMAP_SIDE  # 256 MB of float32 heights at most


def load_heightmap(file: FilePath, size: float, height: float, max_slope: float = DEFAULT_MAX_SLOPE) -> HeightGrid:
    """A greyscale image as ground: its width spans ``size`` m (centred on the origin, rows
    along +Z), black at 0 and white at ``height`` m. 8- and 16-bit images keep their depth."""
    from PIL import Image, UnidentifiedImageError

    from ..images import opened_image

    _check_file(file)
    try:
        with opened_image(file) as image:
            # The size an image declares is checked before a byte of it is decoded.
            cols, rows = image.size
            if cols * rows > MAX_HEIGHTMAP_PIXELS:
                raise WorldError(f"{file}: the image declares {cols}x{rows} pixels; a heightmap may have at most "
                                 f"{MAX_HEIGHTMAP_PIXELS:,} pixels ({MAX_HEIGHTMAP_SIDE}x{MAX_HEIGHTMAP_SIDE}); "
                                 "scale it down")
            image.load()
            mode = image.mode
            if mode in ("I;16", "I;16B", "I;16L", "I"):
                data = np.asarray(image, dtype=np.float32)
                top = 65535.0 if mode.startswith("I;16") else max(float(data.max()), 1.0)
            elif mode == "F":
                data = np.array(image, dtype=np.float32)  # a copy: Pillow's own buffer is read-only
                top = max(float(data.max()), 1e-12)
            else:
                data = np.asarray(image.convert("L"), dtype=np.float32)
                top = 255.0
    except Image.DecompressionBombError:
        raise WorldError(f"{file}: the image declares more pixels than Pillow will decode; a heightmap may have at "
                         f"most {MAX_HEIGHTMAP_PIXELS:,} pixels ({MAX_HEIGHTMAP_SIDE}x{MAX_HEIGHTMAP_SIDE}); "
                         "scale it down") from None
    except (UnidentifiedImageError, OSError, SyntaxError, ValueError) as exc:
        raise WorldError(f"{file}: not an image Gaitlab can read as a heightmap ({type(exc).__name__}); "
                         "give a PNG (8- or 16-bit greyscale)") from None
    if data.ndim != 2 or min(data.shape) < 2:
        raise WorldError(f"{file}: a heightmap needs at least 2x2 pixels, got {data.shape[::-1]}")
    if not np.all(np.isfinite(data)):
        raise WorldError(f"{file}: the image holds values that are not finite numbers")
    rows, cols = data.shape
    depth = size * (rows - 1) / (cols - 1)
    data *= np.float32(height / top)  # in place: one float32 copy of the image in all
    return HeightGrid(data, (-0.5 * size, -0.5 * depth), (size, depth),
                      label=f"heightmap:file={file},size={size:g},height={height:g}", max_slope=max_slope)


MAX_GRID = 1024
MAX_MESH_BYTES = 256 * 2**20  # checked before the file is parsed
MAX_MESH_FACES = 4_000_000
MAX_MESH_REACH = 1e5  # m from the origin (farther, the grid's numbers lose their centimetres)


SURFACE_CHUNK = 1 << 20  # grid points tested against triangles at a time (memory: ~130 bytes each)
MAX_SURFACE_TESTS = 1 << 28  # point-in-triangle tests a mesh may ask for (~20 s here; an honest terrain: a few per point)


class TooManySurfaceTests(ValueError):
    """A mesh whose triangles' boxes hold more grid points than :func:`highest_surface` was
    allowed to test."""


def highest_surface(vertices: NDArray[np.float64], faces: NDArray[np.int64], xs: NDArray[np.float64],
                    zs: NDArray[np.float64], floor: float, max_tests: int | None = None) -> NDArray[np.float64]:
    """The height (m) of the highest triangle over each point of a grid: (len(zs), len(xs)),
    ``floor`` where no triangle lies over a point. ``vertices`` (V, 3) finite, with +Y up,
    ``faces`` (F, 3); ``xs`` and ``zs`` evenly spaced and rising, at least two points each.
    Each triangle is laid on the grid points within its own x-z box, widened by a point
    each way (the barycentric test decides, so rounding far from the origin loses no
    edge), vectorised over triangles in chunks; triangles standing on edge (no extent seen
    from above) are skipped. More than ``max_tests`` grid points in the triangles' boxes
    (large triangles stacked deep) raise :class:`TooManySurfaceTests` before any is tested."""
    tri = vertices[faces]  # (F, 3, 3)
    x, y, z = tri[..., 0], tri[..., 1], tri[..., 2]
    det = (z[:, 1] - z[:, 2]) * (x[:, 0] - x[:, 2]) + (x[:, 2] - x[:, 1]) * (z[:, 0] - z[:, 2])
    dx, dz = (xs[-1] - xs[0]) / (len(xs) - 1), (zs[-1] - zs[0]) / (len(zs) - 1)
    i0 = np.clip(np.ceil((x.min(axis=1) - xs[0]) / dx) - 1, 0, len(xs)).astype(np.int64)
    i1 = np.clip(np.floor((x.max(axis=1) - xs[0]) / dx) + 1, -1, len(xs) - 1).astype(np.int64)
    j0 = np.clip(np.ceil((z.min(axis=1) - zs[0]) / dz) - 1, 0, len(zs)).astype(np.int64)
    j1 = np.clip(np.floor((z.max(axis=1) - zs[0]) / dz) + 1, -1, len(zs) - 1).astype(np.int64)
    across, down = np.maximum(i1 - i0 + 1, 0), np.maximum(j1 - j0 + 1, 0)
    keep = np.flatnonzero((across * down > 0) & (np.abs(det) > 1e-300))
    counts = (across * down)[keep]
    if max_tests is not None and int(counts.sum()) > max_tests:
        raise TooManySurfaceTests(f"laying its triangles on the grid takes {int(counts.sum()):,} point tests, at most "
                         f"{max_tests:,}")
    best = np.full(len(zs) * len(xs), -np.inf)
    ends = np.cumsum(counts)
    start = 0
    while start < len(keep):  # chunks of about SURFACE_CHUNK points (a huge triangle alone)
        stop = max(int(np.searchsorted(ends, (ends[start - 1] if start else 0) + SURFACE_CHUNK, side="right")),
                   start + 1)
        t = keep[start:stop]
        n = counts[start:stop]
        owner = np.repeat(np.arange(len(t)), n)
        k = np.arange(int(n.sum())) - np.repeat(np.cumsum(n) - n, n)  # index within its triangle's box
        f = t[owner]
        ii = i0[f] + k % across[f]
        jj = j0[f] + k // across[f]
        px, pz = xs[ii], zs[jj]
        a = ((z[f, 1] - z[f, 2]) * (px - x[f, 2]) + (x[f, 2] - x[f, 1]) * (pz - z[f, 2])) / det[f]
        b = ((z[f, 2] - z[f, 0]) * (px - x[f, 2]) + (x[f, 0] - x[f, 2]) * (pz - z[f, 2])) / det[f]
        c = 1.0 - a - b
        inside = (a >= -1e-9) & (b >= -1e-9) & (c >= -1e-9)
        height = a * y[f, 0] + b * y[f, 1] + c * y[f, 2]
        np.maximum.at(best, (jj * len(xs) + ii)[inside], height[inside])
        start = stop
    return np.where(np.isfinite(best), best, floor).reshape(len(zs), len(xs))


def load_mesh_terrain(file: FilePath, cell: float = 0.0, max_slope: float = DEFAULT_MAX_SLOPE) -> HeightGrid:
    """A mesh file (anything trimesh reads: OBJ, PLY, STL, glTF/GLB) as a height grid: the
    highest surface above each grid point, found by laying each triangle on the grid (up is +Y).
    ``cell`` is the grid spacing in metres (default: the mesh's size / 256)."""
    import trimesh

    _check_file(file)
    size = file.stat().st_size
    if size > MAX_MESH_BYTES:
        raise WorldError(f"{file}: {size / 2**20:.0f} MB; a terrain mesh may be at most {MAX_MESH_BYTES // 2**20} MB "
                         "(simplify it first)")
    try:
        with warnings.catch_warnings(), np.errstate(all="ignore"):  # what it reads is checked below, not warned of
            warnings.simplefilter("ignore")
            loaded: trimesh.Trimesh = trimesh.load(str(file), force="mesh")  # type: ignore[assignment]  # force="mesh"
    except Exception as exc:  # trimesh raises many kinds for broken files (ImportError: an optional reader)
        unreadable = f"{file}: cannot read the mesh: damaged, or not an OBJ, PLY, STL or glTF/GLB file"
        said = " ".join(str(exc).split())
        if isinstance(exc, (ValueError, OSError)) and " " in said:  # the reader's own sentence, not a bare key or index
            unreadable += f" (the reader says: {said[:80]})"
        raise WorldError(unreadable) from None
    faces = getattr(loaded, "faces", None)
    if faces is None or len(faces) == 0:
        raise WorldError(f"{file}: the mesh has no faces; a terrain mesh needs triangles")
    if len(faces) > MAX_MESH_FACES:
        raise WorldError(f"{file}: {len(faces):,} faces; a terrain mesh may have at most {MAX_MESH_FACES:,} "
                         "(simplify it first)")
    vertices = np.asarray(loaded.vertices, dtype=np.float64)
    if not np.all(np.isfinite(vertices)):
        raise WorldError(f"{file}: the mesh has vertices that are not finite numbers")
    if np.abs(vertices).max() > MAX_MESH_REACH:
        raise WorldError(f"{file}: the mesh reaches {np.abs(vertices).max():.3g} m from the origin; a terrain mesh "
                         f"must lie within {MAX_MESH_REACH:g} m of it (metres, up is +Y)")
    lo, hi = vertices.min(axis=0), vertices.max(axis=0)
    width, depth = float(hi[0] - lo[0]), float(hi[2] - lo[2])
    if min(width, depth) <= 0:
        raise WorldError(f"{file}: the mesh spreads {width:g} m along x and {depth:g} m along z; a terrain must "
                         "spread both ways over the ground (up is +Y)")
    cell = cell or max(width, depth) / 256.0

    def points(span: float) -> int:  # grid points across a span, at most MAX_GRID (a tiny cell asks for more)
        return MAX_GRID if span >= cell * (MAX_GRID - 1) else math.ceil(span / cell) + 1

    cols, rows = points(width), points(depth)
    xs = np.linspace(lo[0], hi[0], max(cols, 2))
    zs = np.linspace(lo[2], hi[2], max(rows, 2))
    try:  # no surface above a point: the lowest
        heights = highest_surface(vertices, faces, xs, zs, floor=float(lo[1]), max_tests=MAX_SURFACE_TESTS)
    except TooManySurfaceTests as exc:
        raise WorldError(f"{file}: {exc}: its triangles are large and lie many deep (layers hidden under the "
                         "surface?); simplify the mesh or give a coarser cell=") from None
    return HeightGrid(heights, (float(lo[0]), float(lo[2])), (width, depth), label=f"mesh:file={file}", max_slope=max_slope)
