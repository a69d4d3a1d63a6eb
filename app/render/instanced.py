"""A unit mesh (capsule, sphere) drawn once per instance row, in two levels of detail."""

from __future__ import annotations

import moderngl
import numpy as np


class InstancedMesh:
    """A unit mesh drawn once per instance: a detailed version lit in the main pass and a
    coarse one for the (soft, low-resolution) shadow pass, sharing one instance buffer."""

    def __init__(self, ctx: moderngl.Context, lit: moderngl.Program, depth: moderngl.Program,
                 detailed: tuple[np.ndarray, np.ndarray], coarse: tuple[np.ndarray, np.ndarray],
                 vertex_format: str, vertex_attrs: tuple[str, ...],
                 instance_format: str, instance_attrs: tuple[str, ...], instance_floats: int) -> None:
        self.instance_floats = instance_floats
        self.capacity = 64
        self.instances = ctx.buffer(reserve=self.capacity * instance_floats * 4, dynamic=True)
        self.count = 0
        self._objects: list = [self.instances]

        def vao(program: moderngl.Program, mesh: tuple[np.ndarray, np.ndarray]) -> moderngl.VertexArray:
            vbo = ctx.buffer(mesh[0].astype("f4").tobytes())
            ibo = ctx.buffer(mesh[1].astype("u4").tobytes())
            layout = [(vbo, vertex_format, *vertex_attrs), (self.instances, instance_format, *instance_attrs)]
            array = ctx.vertex_array(program, layout, index_buffer=ibo, index_element_size=4,
                                     skip_errors=True)  # the depth pass ignores colours
            self._objects += [array, vbo, ibo]
            return array

        self.vao_lit = vao(lit, detailed)
        self.vao_depth = vao(depth, coarse)

    def upload(self, data: np.ndarray) -> None:
        self.count = int(data.shape[0])
        if self.count > self.capacity:
            self.capacity = max(self.count, self.capacity * 2)
            self.instances.orphan(self.capacity * self.instance_floats * 4)
        if self.count:
            self.instances.write(np.ascontiguousarray(data, dtype="f4").tobytes())

    def draw(self, depth_only: bool, count: int | None = None) -> None:
        """Draw the first ``count`` instances (default all)."""
        n = self.count if count is None else min(count, self.count)
        if n:
            (self.vao_depth if depth_only else self.vao_lit).render(moderngl.TRIANGLES, instances=n)

    def release(self) -> None:
        for obj in self._objects:
            obj.release()
