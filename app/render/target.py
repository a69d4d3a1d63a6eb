"""Offscreen render targets: a framebuffer to draw into and read back as an RGB array."""

from __future__ import annotations

import moderngl
import numpy as np
from numpy.typing import NDArray


class OffscreenTarget:
    """A colour + depth framebuffer of ``size`` (width, height), optionally multisampled.

    Draw into :attr:`fbo`; :meth:`read` resolves the samples and returns (H, W, 3) uint8
    with row 0 at the top of the image.
    """

    def __init__(self, ctx: moderngl.Context, size: tuple[int, int], samples: int = 0) -> None:
        self.ctx = ctx
        self.size = (int(size[0]), int(size[1]))
        self.samples = min(int(samples), ctx.max_samples) if samples else 0
        self._resolve = ctx.framebuffer(color_attachments=[ctx.renderbuffer(self.size, 4)],
                                        depth_attachment=ctx.depth_renderbuffer(self.size))
        self._msaa = None
        if self.samples:
            self._msaa = ctx.framebuffer(
                color_attachments=[ctx.renderbuffer(self.size, 4, samples=self.samples)],
                depth_attachment=ctx.depth_renderbuffer(self.size, samples=self.samples))

    @property
    def fbo(self) -> moderngl.Framebuffer:
        """The framebuffer to draw into."""
        return self._msaa or self._resolve

    def read(self) -> NDArray[np.uint8]:
        """The drawn image, (H, W, 3) uint8, top row first."""
        if self._msaa is not None:
            self.ctx.copy_framebuffer(self._resolve, self._msaa)
        data = self._resolve.read(components=3, alignment=1)
        w, h = self.size
        return np.frombuffer(data, dtype=np.uint8).reshape(h, w, 3)[::-1]

    def release(self) -> None:
        for fbo in (self._msaa, self._resolve):
            if fbo is None:
                continue
            for attachment in (*fbo.color_attachments, fbo.depth_attachment):
                attachment.release()
            fbo.release()
