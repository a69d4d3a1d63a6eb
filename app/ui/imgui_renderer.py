"""Drawing Dear ImGui (imgui-bundle >= 1.92) with moderngl, into any framebuffer.

imgui-bundle's own backends need PyOpenGL; this one uses the project's single GL
wrapper, so the same code draws the UI into a glfw window or an EGL framebuffer. It
implements ImGui's texture protocol (``ImTextureStatus`` create / update / destroy
requests in ``platform_io.textures``): fonts are rasterised on demand and uploaded here.

A software rasteriser pays per pixel touched, and small blended, textured glyph quads are
its dearest pixels: the sidebar's thousands of them cost about 2 ms a frame at 1280x720.
While the sidebar's draw lists are unchanged (the user is watching, not editing), its
pixels are kept in a layer of their own and copied into the frame (:class:`Backdrop`).
"""

from __future__ import annotations

import ctypes
from dataclasses import dataclass

import moderngl
import numpy as np
from imgui_bundle import imgui

from ..render.shaders import ShaderLibrary
from ..render.uniforms import uniform

_VERTEX_FORMAT = "2f 2f 4f1"  # ImDrawVert: pos, uv, col (RGBA8, normalised)


@dataclass(frozen=True)
class Backdrop:
    """A strip along the left edge of the framebuffer, ``width`` pixels wide and as high
    as the frame, filled with ``color`` (display RGB, 0-1) under the UI drawn in it (the
    sidebar). The draw lists that lie wholly inside it, first in ImGui's order, are drawn
    once into a layer and copied into every frame until they change."""

    width: int
    color: tuple[float, float, float]


def _command(cmd: imgui.ImDrawCmd) -> tuple[tuple[float, float, float, float], int, int, int]:
    """A draw command as plain values: clip rectangle, index count, first index, texture id."""
    clip = cmd.clip_rect
    return (clip.x, clip.y, clip.z, clip.w), cmd.elem_count, cmd.idx_offset, cmd.tex_ref.get_tex_id()


def _vertex_bounds(vertices: bytes) -> tuple[float, float, float, float]:
    """x0, y0, x1, y1 (ImGui's display units) of the positions in ``vertices`` (ImDrawVert)."""
    positions = np.frombuffer(vertices, dtype=np.float32).reshape(-1, imgui.VERTEX_SIZE // 4)[:, :2]
    if not len(positions):
        return (0.0, 0.0, 0.0, 0.0)
    lo, hi = positions.min(axis=0), positions.max(axis=0)
    return (float(lo[0]), float(lo[1]), float(hi[0]), float(hi[1]))


class ImguiRenderer:
    """Renders ImGui draw data with moderngl. One per GL context and ImGui context."""

    def __init__(self, ctx: moderngl.Context, shaders: ShaderLibrary | None = None) -> None:
        if imgui.get_current_context() is None:
            raise RuntimeError("create an ImGui context (imgui.create_context()) before ImguiRenderer")
        self.ctx = ctx
        self.shaders = shaders or ShaderLibrary(ctx)
        self.program = self.shaders.program("imgui.vert", "imgui.frag")
        self._vbo = ctx.buffer(reserve=1 << 16, dynamic=True)
        self._ibo = ctx.buffer(reserve=1 << 16, dynamic=True)
        self._vao = ctx.vertex_array(self.program, [(self._vbo, _VERTEX_FORMAT, "in_pos", "in_uv", "in_color")],
                                     index_buffer=self._ibo, index_element_size=imgui.INDEX_SIZE)
        self._textures: dict[int, moderngl.Texture] = {}
        self._texture_updates = 0  # counts uploads: a cached layer drawn with older glyphs is stale
        self._layer: moderngl.Framebuffer | None = None
        self._layer_key: object = None
        self._layer_lists: list = []  # the draw lists the layer holds
        io = imgui.get_io()
        io.backend_flags |= imgui.BackendFlags_.renderer_has_textures
        max_size = int(ctx.info["GL_MAX_TEXTURE_SIZE"])
        platform = imgui.get_platform_io()
        platform.renderer_texture_max_width = max_size
        platform.renderer_texture_max_height = max_size

    # -- textures (ImGui's requests) ----------------------------------------------------

    def _update_textures(self) -> None:
        for tex in imgui.get_platform_io().textures:
            if tex.status != imgui.ImTextureStatus.ok:
                self._update_texture(tex)

    def _update_texture(self, tex: imgui.ImTextureData) -> None:
        status = tex.status
        if status == imgui.ImTextureStatus.want_create:
            pixels = np.asarray(tex.get_pixels_array(), dtype=np.uint8).reshape(tex.height, tex.width, 4)
            texture = self.ctx.texture((tex.width, tex.height), 4, data=pixels.tobytes())
            texture.filter = (moderngl.LINEAR, moderngl.LINEAR)
            texture.repeat_x = texture.repeat_y = False
            self._textures[texture.glo] = texture
            tex.set_tex_id(texture.glo)
            tex.status = imgui.ImTextureStatus.ok
            self._texture_updates += 1
        elif status == imgui.ImTextureStatus.want_updates:
            texture = self._textures[tex.tex_id]
            pixels = np.asarray(tex.get_pixels_array(), dtype=np.uint8).reshape(tex.height, tex.width, 4)
            for r in tex.updates:
                block = np.ascontiguousarray(pixels[r.y:r.y + r.h, r.x:r.x + r.w])
                texture.write(block.tobytes(), viewport=(r.x, r.y, r.w, r.h))
            tex.status = imgui.ImTextureStatus.ok
            self._texture_updates += 1
        elif status == imgui.ImTextureStatus.want_destroy:
            gone = self._textures.pop(tex.tex_id, None)
            if gone is not None:
                gone.release()
            tex.set_tex_id(0)
            tex.status = imgui.ImTextureStatus.destroyed

    # -- drawing ------------------------------------------------------------------------

    def render(self, draw_data: imgui.ImDrawData, target: moderngl.Framebuffer,
               backdrop: Backdrop | None = None) -> None:
        """Draw ``draw_data`` over whatever ``target`` holds (alpha-blended, no depth),
        over ``backdrop`` (filled first, its draw lists kept while unchanged). A
        multisampled ``target`` cannot take the layer's copy: give no backdrop."""
        self._update_textures()
        scale_x, scale_y = draw_data.framebuffer_scale
        fb_w = int(draw_data.display_size.x * scale_x)
        fb_h = int(draw_data.display_size.y * scale_y)
        if fb_w <= 0 or fb_h <= 0:
            return
        lists = [(ctypes.string_at(c.vtx_buffer.data_address(), c.vtx_buffer.size() * imgui.VERTEX_SIZE),
                  ctypes.string_at(c.idx_buffer.data_address(), c.idx_buffer.size() * imgui.INDEX_SIZE),
                  [_command(cmd) for cmd in c.cmd_buffer]) for c in draw_data.cmd_lists]
        origin = (draw_data.display_pos.x, draw_data.display_pos.y)
        size = (draw_data.display_size.x, draw_data.display_size.y)
        scale = (scale_x, scale_y)
        if backdrop is not None and 0 < backdrop.width <= fb_w:
            inside = 0  # the leading lists wholly inside the strip (those the layer holds already are)
            right = origin[0] + backdrop.width / scale_x
            kept = self._layer_lists if isinstance(self._layer_key, tuple) and self._layer_key[0] == backdrop else []
            while inside < len(lists) and ((inside < len(kept) and lists[inside] == kept[inside])
                                           or _vertex_bounds(lists[inside][0])[2] <= right + 0.5):
                inside += 1
            self._draw_layer(backdrop, lists[:inside], origin, size, scale, fb_h)
            assert self._layer is not None
            self.ctx.copy_framebuffer(target, self._layer)
            lists = lists[inside:]
        self._draw_lists(lists, target, origin, size, scale, (0, 0, fb_w, fb_h))

    def _draw_layer(self, backdrop: Backdrop, lists: list, origin: tuple[float, float],
                    size: tuple[float, float], scale: tuple[float, float], fb_h: int) -> None:
        """The backdrop and ``lists`` into the layer, unless it already holds them."""
        key = (backdrop, fb_h, origin, size, scale, self._texture_updates, lists)
        if self._layer is not None and self._layer_key == key:
            return
        if self._layer is None or self._layer.size != (backdrop.width, fb_h):
            self._release_layer()
            self._layer = self.ctx.framebuffer([self.ctx.renderbuffer((backdrop.width, fb_h), 4)])
        self._layer.use()
        self._layer.clear(*backdrop.color, 1.0)
        self._draw_lists(lists, self._layer, origin, size, scale, (0, 0, backdrop.width, fb_h))
        self._layer_key, self._layer_lists = key, lists

    def _draw_lists(self, lists: list, target: moderngl.Framebuffer, origin: tuple[float, float],
                    size: tuple[float, float], scale: tuple[float, float], viewport: tuple[int, int, int, int]) -> None:
        """Draw ImGui draw lists (vertex bytes, index bytes, commands) into ``target``,
        whose ``viewport`` is the display's lower-left part (the whole of it, or a layer)."""
        if not lists:
            return
        ctx = self.ctx
        target.use()
        fb_w, fb_h = int(size[0] * scale[0]), int(size[1] * scale[1])
        target.viewport = (0, 0, fb_w, fb_h)
        ctx.enable(moderngl.BLEND)
        ctx.blend_func = (moderngl.SRC_ALPHA, moderngl.ONE_MINUS_SRC_ALPHA,  # type: ignore[assignment]  # (moderngl's
                          moderngl.ONE, moderngl.ONE_MINUS_SRC_ALPHA)  # stub knows only the two-factor form)
        ctx.disable(moderngl.DEPTH_TEST | moderngl.CULL_FACE)
        (x0, y0), (w, h) = origin, size
        proj = np.array([[2.0 / w, 0, 0, 0], [0, -2.0 / h, 0, 0], [0, 0, -1, 0],
                         [-(2 * x0 + w) / w, (2 * y0 + h) / h, 0, 1]], dtype="f4")
        uniform(self.program, "u_proj").write(proj.tobytes())
        uniform(self.program, "u_texture").value = 0
        vx, vy, vw, vh = viewport
        for vertices, indices, commands in lists:
            self._upload(self._vbo, vertices)
            self._upload(self._ibo, indices)
            for (cx0, cy0, cx1, cy1), count, first, tex_id in commands:
                left, top = max((cx0 - x0) * scale[0], vx), max((cy0 - y0) * scale[1], fb_h - vy - vh)
                right, bottom = min((cx1 - x0) * scale[0], vx + vw), min((cy1 - y0) * scale[1], fb_h - vy)
                if right <= left or bottom <= top:
                    continue
                texture = self._textures.get(tex_id)
                if texture is not None:
                    texture.use(0)
                target.scissor = (int(left), int(fb_h - bottom), int(right - left), int(bottom - top))
                self._vao.render(moderngl.TRIANGLES, vertices=count, first=first)
        target.scissor = None  # type: ignore[assignment]  # (None turns the scissor off; the stub omits it)
        ctx.disable(moderngl.BLEND)
        ctx.blend_func = moderngl.DEFAULT_BLENDING  # type: ignore[assignment]  # (a pair of factors in the stub)

    @staticmethod
    def _upload(buffer: moderngl.Buffer, data: bytes) -> None:
        if len(data) > buffer.size:
            buffer.orphan(max(len(data), buffer.size * 2))
        buffer.write(data)

    def release(self) -> None:
        """Free the GL objects and tell ImGui its textures are gone."""
        for tex in imgui.get_platform_io().textures:
            if tex.status != imgui.ImTextureStatus.destroyed and tex.tex_id in self._textures:
                tex.set_tex_id(0)
                tex.status = imgui.ImTextureStatus.destroyed
        for texture in self._textures.values():
            texture.release()
        self._textures.clear()
        for obj in (self._vao, self._vbo, self._ibo):
            obj.release()
        self._release_layer()

    def _release_layer(self) -> None:
        if self._layer is not None:
            attachments = self._layer.color_attachments
            self._layer.release()
            for attachment in attachments:
                attachment.release()
        self._layer, self._layer_key, self._layer_lists = None, None, []
