"""Unit meshes for instancing (numpy only): a UV sphere and a two-ended capsule."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray


def _grid_indices(rows: int, cols: int) -> NDArray[np.uint32]:
    """Triangles of a (rows+1) x (cols+1) vertex grid, wrapping nothing.

    Rows run from the +Y pole downwards and columns with increasing longitude, so this
    winding is counter-clockwise seen from outside (front faces for back-face culling).
    """
    r, c = np.meshgrid(np.arange(rows), np.arange(cols), indexing="ij")
    a = r * (cols + 1) + c
    b = a + cols + 1
    quads = np.stack([a, a + 1, b, a + 1, b + 1, b], axis=-1)
    return quads.reshape(-1).astype(np.uint32)


def unit_sphere(rings: int = 14, segments: int = 24) -> tuple[NDArray[np.float32], NDArray[np.uint32]]:
    """Unit sphere: vertices (N, 3) float32 (positions = normals), triangle indices (M,)."""
    theta = np.linspace(0.0, np.pi, rings + 1)[:, None]
    phi = np.linspace(0.0, 2.0 * np.pi, segments + 1)[None, :]
    pos = np.stack([np.sin(theta) * np.cos(phi), np.cos(theta) * np.ones_like(phi),
                    np.sin(theta) * np.sin(phi)], axis=-1).reshape(-1, 3)
    return pos.astype(np.float32), _grid_indices(rings, segments)


def unit_capsule(rings: int = 12, segments: int = 16) -> tuple[NDArray[np.float32], NDArray[np.uint32]]:
    """Capsule along +Y: vertices (N, 4) float32 = unit direction xyz and end (0 or 1).

    The lower hemisphere belongs to end 0 and the upper to end 1; the equator ring is
    duplicated so the cylinder between the ends is one band of triangles.
    """
    half = rings // 2
    theta_top = np.linspace(0.0, 0.5 * np.pi, half + 1)  # pole -> equator, end 1
    theta_bottom = np.linspace(0.5 * np.pi, np.pi, half + 1)  # equator -> pole, end 0
    theta = np.concatenate([theta_top, theta_bottom])[:, None]
    end = np.concatenate([np.ones(half + 1), np.zeros(half + 1)])[:, None]
    phi = np.linspace(0.0, 2.0 * np.pi, segments + 1)[None, :]
    pos = np.stack([np.sin(theta) * np.cos(phi), np.cos(theta) * np.ones_like(phi),
                    np.sin(theta) * np.sin(phi), end * np.ones_like(phi)], axis=-1).reshape(-1, 4)
    return pos.astype(np.float32), _grid_indices(2 * half + 1, segments)
