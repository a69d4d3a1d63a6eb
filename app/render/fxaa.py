"""Fast approximate antialiasing (FXAA) of part of a finished image: a renderable with a
create / apply / release lifecycle; the shader is ``shaders/fxaa.frag``.

On a software rasteriser, multisampling shades every sample (four times the creature's
fragment work); one FXAA pass over the pixels near the creature costs a fraction of
that and looks nearly the same. The ground, drawn without multisampling either way,
antialiases its own grid lines, so the rest of the picture is copied as it is.

A software rasteriser's cost is per pixel touched, whatever the shader does, so the pass
covers only screen tiles that some part of the creature reaches (:func:`screen_tiles`):
about half the pixels of the creature's whole bounding rectangle.
"""

from __future__ import annotations

from dataclasses import replace

import moderngl
import numpy as np
from numpy.typing import NDArray

from .camera import Camera
from .scene import SceneInstances, box_corners
from .shaders import ShaderLibrary
from .uniforms import uniform

Region = tuple[int, int, int, int]  # x, y (from the bottom left), width, height in pixels

FXAA_REACH = 2  # pixels the pass reads around an edge pixel: pad regions by this much
TILE = 16  # pixels per side of the tiles the pass is limited to


class FxaaPass:
    """Antialias rectangles of a colour texture into a framebuffer of the same size."""

    def __init__(self, ctx: moderngl.Context, shaders: ShaderLibrary) -> None:
        self.ctx = ctx
        self.program = shaders.program("fxaa.vert", "fxaa.frag")
        self._capacity = 64  # rectangles
        self.vbo = ctx.buffer(reserve=self._capacity * 6 * 2 * 4, dynamic=True)
        self.vao = ctx.vertex_array(self.program, [(self.vbo, "2f", "in_pixel")])

    def apply(self, source: moderngl.Texture, target: moderngl.Framebuffer,
              rects: Region | NDArray[np.integer]) -> None:
        """Write ``source`` antialiased into ``target`` inside ``rects`` (one region, or
        (N, 4) rectangles x, y, width, height from the bottom left); the rest of
        ``target`` is left alone."""
        boxes = np.asarray(rects, dtype=np.float32).reshape(-1, 4)
        boxes = boxes[(boxes[:, 2] > 0) & (boxes[:, 3] > 0)]
        if not len(boxes):
            return
        x0, y0 = boxes[:, 0], boxes[:, 1]
        x1, y1 = x0 + boxes[:, 2], y0 + boxes[:, 3]
        corners = np.stack([np.stack(c, axis=-1) for c in
                            ((x0, y0), (x1, y0), (x0, y1), (x0, y1), (x1, y0), (x1, y1))], axis=1)
        if len(boxes) > self._capacity:
            self._capacity = 2 * len(boxes)
            self.vbo.orphan(self._capacity * 6 * 2 * 4)
        self.vbo.write(np.ascontiguousarray(corners, dtype="f4").tobytes())
        ctx = self.ctx
        target.use()
        target.viewport = (0, 0, *source.size)
        ctx.disable(moderngl.DEPTH_TEST | moderngl.BLEND | moderngl.CULL_FACE)
        source.use(location=0)
        uniform(self.program, "u_image").value = 0
        uniform(self.program, "u_texel").value = (1.0 / source.size[0], 1.0 / source.size[1])
        self.vao.render(moderngl.TRIANGLES, vertices=6 * len(boxes))

    def release(self) -> None:
        self.vao.release()  # the program belongs to the shader library
        self.vbo.release()


def screen_region(lo: NDArray[np.float64], hi: NDArray[np.float64], camera: Camera, size: tuple[int, int],
                  pad: int = FXAA_REACH) -> Region:
    """The pixel rectangle (bottom-left origin) covering the world box ``lo``..``hi``
    (each (3,), metres) as ``camera`` sees it in an image of ``size``, padded by ``pad``
    pixels and clipped to the image; the whole image when the box reaches behind the eye."""
    w, h = size
    corners = np.column_stack([box_corners(lo, hi), np.ones(8)])
    clip = corners @ np.array(camera.view_proj(w / max(h, 1)), dtype=np.float64).T
    if np.any(clip[:, 3] <= 1e-6):
        return (0, 0, w, h)
    ndc = clip[:, :2] / clip[:, 3:4]
    x0 = max(0, int(np.floor((ndc[:, 0].min() + 1.0) * 0.5 * w)) - pad)
    x1 = min(w, int(np.ceil((ndc[:, 0].max() + 1.0) * 0.5 * w)) + pad)
    y0 = max(0, int(np.floor((ndc[:, 1].min() + 1.0) * 0.5 * h)) - pad)
    y1 = min(h, int(np.ceil((ndc[:, 1].max() + 1.0) * 0.5 * h)) + pad)
    return (x0, y0, max(0, x1 - x0), max(0, y1 - y0))


def outline_spheres(scene: SceneInstances) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """What covers a frame's creatures on screen: the shapes' bounding spheres (centres
    (N, 3), radii (N,), m) and every skinned body's vertices (radius 0). (A joint's
    sphere holds all of its skin: the tiles came to twice the body's own.)"""
    centres, radii = replace(scene, bodies=()).spheres()
    points = [body.surface_points() for body in scene.bodies]
    return (np.concatenate([centres, *points]),
            np.concatenate([radii, *(np.zeros(len(p)) for p in points)]))


def sphere_boxes(centres: NDArray[np.float64], radii: NDArray[np.float64], camera: Camera,
                 size: tuple[int, int], pad: float = FXAA_REACH) -> NDArray[np.float64] | None:
    """Screen boxes (N, 4: x0, y0, x1, y1 in pixels from the bottom left) holding each
    sphere as ``camera`` sees it, padded by ``pad`` pixels; None when a sphere reaches
    behind the eye (its box would be unbounded)."""
    w, h = size
    aspect = w / max(h, 1)
    view = np.array(camera.view(), dtype=np.float64)
    proj = np.array(camera.projection(aspect), dtype=np.float64)
    eye_space = centres @ view[:3, :3].T + view[:3, 3]
    clip = np.column_stack([eye_space, np.ones(len(centres))]) @ proj.T
    depth = clip[:, 3] if not camera.ortho else np.ones(len(centres))
    if not camera.ortho and np.any(-eye_space[:, 2] - radii <= 1e-6):
        return None
    ndc = clip[:, :2] / clip[:, 3:4]
    # A sphere's outline is an ellipse a little wider than r / depth off the axis; the
    # factor covers that for fields of view up to about 90 degrees.
    half = 1.25 * radii[:, None] * np.abs(np.diag(proj)[None, :2]) / depth[:, None]
    lo = (ndc - half + 1.0) * 0.5 * np.array([w, h]) - pad
    hi = (ndc + half + 1.0) * 0.5 * np.array([w, h]) + pad
    return np.column_stack([lo, hi])


def screen_tiles(scene: SceneInstances, camera: Camera, size: tuple[int, int], tile: int = TILE,
                 pad: int = FXAA_REACH) -> NDArray[np.int64]:
    """Rectangles (N, 4: x, y, width, height in pixels from the bottom left, clipped to
    the image) made of ``tile``-pixel tiles that together cover every shape of ``scene``
    on screen, padded by ``pad`` pixels; the whole image when a shape reaches behind the
    eye. Each row of tiles gives one rectangle per run of covered tiles."""
    w, h = size
    boxes = sphere_boxes(*outline_spheres(scene), camera, size, pad)
    if boxes is None:
        return np.array([[0, 0, w, h]], dtype=np.int64)
    cols, rows = -(-w // tile), -(-h // tile)
    boxes = boxes[(boxes[:, 2] > 0) & (boxes[:, 3] > 0) & (boxes[:, 0] < w) & (boxes[:, 1] < h)]
    if not len(boxes):
        return np.zeros((0, 4), dtype=np.int64)
    tx0 = np.clip(np.floor(boxes[:, 0] / tile), 0, cols - 1).astype(np.int64)
    ty0 = np.clip(np.floor(boxes[:, 1] / tile), 0, rows - 1).astype(np.int64)
    tx1 = np.clip(np.floor(boxes[:, 2] / tile), 0, cols - 1).astype(np.int64) + 1
    ty1 = np.clip(np.floor(boxes[:, 3] / tile), 0, rows - 1).astype(np.int64) + 1
    # Mark every box's tiles at once: a 2-D difference array, summed along both axes.
    marks = np.zeros((rows + 1, cols + 1), dtype=np.int64)
    np.add.at(marks, (ty0, tx0), 1)
    np.add.at(marks, (ty0, tx1), -1)
    np.add.at(marks, (ty1, tx0), -1)
    np.add.at(marks, (ty1, tx1), 1)
    covered = marks.cumsum(axis=0).cumsum(axis=1)[:rows, :cols] > 0
    # Runs of covered tiles along each row.
    edges = np.diff(np.pad(covered.astype(np.int8), ((0, 0), (1, 1))), axis=1)
    run_rows, starts = np.nonzero(edges == 1)
    _, ends = np.nonzero(edges == -1)
    x0, y0 = starts * tile, run_rows * tile
    x1, y1 = np.minimum(ends * tile, w), np.minimum((run_rows + 1) * tile, h)
    return np.column_stack([x0, y0, x1 - x0, y1 - y0]).astype(np.int64)
