"""Offscreen render targets: a framebuffer to draw into and read back as an RGB array."""

from __future__ import annotations

import moderngl
import numpy as np
from numpy.typing import NDArray

from .fxaa import FxaaPass, Region
from .shaders import ShaderLibrary


class OffscreenTarget:
    """A colour + depth framebuffer of ``size`` (width, height), antialiased by
    multisampling (``samples`` > 0), by FXAA (``fxaa``) or not at all.

    Draw into :attr:`fbo`; :meth:`read` resolves the samples (or runs FXAA over the given
    region) and returns (H, W, 3) uint8 with row 0 at the top of the image.
    """

    def __init__(self, ctx: moderngl.Context, size: tuple[int, int], samples: int = 0, fxaa: bool = False,
                 shaders: ShaderLibrary | None = None) -> None:
        self.ctx = ctx
        self.size = (int(size[0]), int(size[1]))
        self.samples = min(int(samples), ctx.max_samples) if samples and not fxaa else 0
        self._objects: list = []
        self._resolve = self._framebuffer(ctx.renderbuffer(self.size, 4), ctx.depth_renderbuffer(self.size))
        self._draw: moderngl.Framebuffer | None = None  # drawn into when not the resolve target itself
        self._image: moderngl.Texture | None = None
        self._fxaa: FxaaPass | None = None
        self._own_shaders = False
        if self.samples:
            self._draw = self._framebuffer(ctx.renderbuffer(self.size, 4, samples=self.samples),
                                           ctx.depth_renderbuffer(self.size, samples=self.samples))
        elif fxaa:
            self._image = ctx.texture(self.size, 4)
            self._image.filter = (moderngl.LINEAR, moderngl.LINEAR)
            self._image.repeat_x = self._image.repeat_y = False
            self._draw = self._framebuffer(self._image, ctx.depth_renderbuffer(self.size))
            self._own_shaders = shaders is None
            self._shaders = shaders or ShaderLibrary(ctx)
            self._fxaa = FxaaPass(ctx, self._shaders)

    def _framebuffer(self, color, depth) -> moderngl.Framebuffer:
        fbo = self.ctx.framebuffer(color_attachments=[color], depth_attachment=depth)
        self._objects += [fbo, color, depth]
        return fbo

    @property
    def fxaa(self) -> bool:
        return self._fxaa is not None

    @property
    def fbo(self) -> moderngl.Framebuffer:
        """The framebuffer to draw into."""
        return self._draw or self._resolve

    def read(self, region: Region | NDArray[np.integer] | None = None) -> NDArray[np.uint8]:
        """The drawn image, (H, W, 3) uint8, top row first. With FXAA, only ``region``
        (x, y from the bottom left, width, height, or (N, 4) such rectangles; default
        the whole image) is antialiased, the rest copied as drawn."""
        if self._draw is not None:
            self.ctx.copy_framebuffer(self._resolve, self._draw)
        if self._fxaa is not None and self._image is not None:
            self._fxaa.apply(self._image, self._resolve, (0, 0, *self.size) if region is None else region)
        data = self._resolve.read(components=3, alignment=1)
        w, h = self.size
        return np.frombuffer(data, dtype=np.uint8).reshape(h, w, 3)[::-1]

    def release(self) -> None:
        if self._fxaa is not None:
            self._fxaa.release()
            if self._own_shaders:
                self._shaders.release()
        for obj in self._objects:
            obj.release()
        self._objects.clear()
