"""Fast approximate antialiasing (FXAA) of part of a finished image: a renderable with a
create / apply / release lifecycle; the shader is ``shaders/fxaa.frag``.

On a software rasteriser, multisampling shades every sample (four times the creature's
fragment work); one FXAA pass over the rectangle the creature covers costs a fraction of
that and looks nearly the same. The ground, drawn without multisampling either way,
antialiases its own grid lines, so the rest of the picture is copied as it is.
"""

from __future__ import annotations

import moderngl
import numpy as np
from numpy.typing import NDArray

from .camera import Camera
from .scene import box_corners
from .shaders import ShaderLibrary

Region = tuple[int, int, int, int]  # x, y (from the bottom left), width, height in pixels

FXAA_REACH = 2  # pixels the pass reads around an edge pixel: pad regions by this much


class FxaaPass:
    """Antialias a region of a colour texture into a framebuffer of the same size."""

    def __init__(self, ctx: moderngl.Context, shaders: ShaderLibrary) -> None:
        self.ctx = ctx
        self.program = shaders.program("fxaa.vert", "fxaa.frag")
        self.vao = ctx.vertex_array(self.program, [])  # one screen triangle from gl_VertexID

    def apply(self, source: moderngl.Texture, target: moderngl.Framebuffer, region: Region) -> None:
        """Write ``source`` antialiased into ``target`` inside ``region`` (the rest of
        ``target`` is left alone)."""
        x, y, w, h = region
        if w <= 0 or h <= 0:
            return
        ctx = self.ctx
        target.use()
        target.viewport = (0, 0, *source.size)
        ctx.disable(moderngl.DEPTH_TEST | moderngl.BLEND | moderngl.CULL_FACE)
        target.scissor = (x, y, w, h)
        source.use(location=0)
        self.program["u_image"].value = 0
        self.program["u_texel"].value = (1.0 / source.size[0], 1.0 / source.size[1])
        self.vao.render(moderngl.TRIANGLES, vertices=3)
        target.scissor = None

    def release(self) -> None:
        self.vao.release()  # the program belongs to the shader library


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
