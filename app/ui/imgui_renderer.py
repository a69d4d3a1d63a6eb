"""Drawing Dear ImGui (imgui-bundle >= 1.92) with moderngl, into any framebuffer.

imgui-bundle's own backends need PyOpenGL; this one uses the project's single GL
wrapper, so the same code draws the UI into a glfw window or an EGL framebuffer. It
implements ImGui's texture protocol (``ImTextureStatus`` create / update / destroy
requests in ``platform_io.textures``): fonts are rasterised on demand and uploaded here.
"""

from __future__ import annotations

import ctypes

import moderngl
import numpy as np
from imgui_bundle import imgui

from ..render.shaders import ShaderLibrary
from ..render.uniforms import uniform

_VERTEX_FORMAT = "2f 2f 4f1"  # ImDrawVert: pos, uv, col (RGBA8, normalised)


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
        elif status == imgui.ImTextureStatus.want_updates:
            texture = self._textures[tex.tex_id]
            pixels = np.asarray(tex.get_pixels_array(), dtype=np.uint8).reshape(tex.height, tex.width, 4)
            for r in tex.updates:
                block = np.ascontiguousarray(pixels[r.y:r.y + r.h, r.x:r.x + r.w])
                texture.write(block.tobytes(), viewport=(r.x, r.y, r.w, r.h))
            tex.status = imgui.ImTextureStatus.ok
        elif status == imgui.ImTextureStatus.want_destroy:
            gone = self._textures.pop(tex.tex_id, None)
            if gone is not None:
                gone.release()
            tex.set_tex_id(0)
            tex.status = imgui.ImTextureStatus.destroyed

    # -- drawing ------------------------------------------------------------------------

    def render(self, draw_data: imgui.ImDrawData, target: moderngl.Framebuffer) -> None:
        """Draw ``draw_data`` over whatever ``target`` holds (alpha-blended, no depth)."""
        self._update_textures()
        scale_x, scale_y = draw_data.framebuffer_scale
        fb_w = int(draw_data.display_size.x * scale_x)
        fb_h = int(draw_data.display_size.y * scale_y)
        if fb_w <= 0 or fb_h <= 0:
            return
        ctx = self.ctx
        target.use()
        target.viewport = (0, 0, fb_w, fb_h)
        ctx.enable(moderngl.BLEND)
        ctx.blend_func = (moderngl.SRC_ALPHA, moderngl.ONE_MINUS_SRC_ALPHA,  # type: ignore[assignment]  # (moderngl's
                          moderngl.ONE, moderngl.ONE_MINUS_SRC_ALPHA)  # stub knows only the two-factor form)
        ctx.disable(moderngl.DEPTH_TEST | moderngl.CULL_FACE)
        x0, y0 = draw_data.display_pos.x, draw_data.display_pos.y
        w, h = draw_data.display_size.x, draw_data.display_size.y
        proj = np.array([[2.0 / w, 0, 0, 0], [0, -2.0 / h, 0, 0], [0, 0, -1, 0],
                         [-(2 * x0 + w) / w, (2 * y0 + h) / h, 0, 1]], dtype="f4")
        uniform(self.program, "u_proj").write(proj.tobytes())
        uniform(self.program, "u_texture").value = 0
        for commands in draw_data.cmd_lists:
            vtx_bytes = commands.vtx_buffer.size() * imgui.VERTEX_SIZE
            idx_bytes = commands.idx_buffer.size() * imgui.INDEX_SIZE
            self._upload(self._vbo, ctypes.string_at(commands.vtx_buffer.data_address(), vtx_bytes))
            self._upload(self._ibo, ctypes.string_at(commands.idx_buffer.data_address(), idx_bytes))
            for cmd in commands.cmd_buffer:
                cx0, cy0, cx1, cy1 = cmd.clip_rect
                left, top = (cx0 - x0) * scale_x, (cy0 - y0) * scale_y
                right, bottom = (cx1 - x0) * scale_x, (cy1 - y0) * scale_y
                if right <= left or bottom <= top:
                    continue
                texture = self._textures.get(cmd.tex_ref.get_tex_id())
                if texture is not None:
                    texture.use(0)
                target.scissor = (int(left), int(fb_h - bottom), int(right - left), int(bottom - top))
                self._vao.render(moderngl.TRIANGLES, vertices=cmd.elem_count, first=cmd.idx_offset)
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
