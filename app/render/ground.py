"""The ground pass: the flat floor (a disc fading into the horizon) with the creatures'
shadow on it, or a terrain patch; the path ribbon; overlays (footprints, targets, the
support polygon); and the sky band. Owns its GL objects (create, draw, release)."""

from __future__ import annotations

import math

import moderngl
import numpy as np

from ..kinematics.path import left_of
from ..kinematics.terrain import Terrain
from .camera import Camera
from .instanced import InstancedMesh
from .lighting import SHADOW_OUTLINE_SIDES, SKY_FADE, SKY_ROWS, floor_light, shadow_outline, sky_band
from .meshes import unit_sphere
from .options import GroundView, RenderOptions
from .overlays import SUPPORT_COLOR, Overlays
from .scene import ELLIPSOID_FLOATS, SceneInstances, srgb_to_linear
from .shaders import ShaderLibrary
from .uniforms import Uniforms

FLOOR_SIDES = 16  # corners of the floor's polygon (its edges stay past where the fog ends)
FOG_RINGS = 5  # rings of the floor through the fog (linear between them: within 4 % of its smoothstep)
TERRAIN_CELLS = 72  # the terrain patch around the creature is this many cells across
PATH_DEPTH_OFFSET = (-2.0, -8.0)  # the path ribbon pulled towards the eye (polygon offset factor, units)
ELLIPSOID_LAYOUT = ("3f", ("in_pos",), "3f 3f 3f 3f 3f 3f/i",
                    ("in_center", "in_axis_x", "in_axis_y", "in_axis_z", "in_radii", "in_color"), ELLIPSOID_FLOATS)


def _zigzag_order(sides: int) -> list[int]:
    """A polygon's corners in the order a strip zig-zagging across it takes them."""
    order = [0]
    for k in range(1, sides // 2 + 1):
        order.append(k)
        if sides - k > k:
            order.append(sides - k)
    return order


def floor_mesh(sides: int, fog_from: float, fog_to: float, rings: int) -> tuple[np.ndarray, np.ndarray]:
    """The floor's disc (unit radius) as a mesh the fog can be computed on per vertex:
    a polygon of ``sides`` corners on the circle of radius ``fog_from`` (where the fog
    starts: none inside it), zig-zagged across (a fan of thin wedges meeting under the
    creature costs a software rasteriser more: it shades the blocks along every edge once
    for each triangle on it), then ``rings`` rings out to ``fog_to`` (where the fog is
    whole) and one more to the rim, each of ``sides`` quads. Returns xz corners (V, 2) and
    triangles (F, 3) of vertex indices."""
    radii = np.append(np.linspace(fog_from, fog_to, rings + 1), 1.0)  # (C,) circles
    angles = np.arange(sides) * (2.0 * np.pi / sides)
    corners = (radii[:, None, None] * np.stack([np.cos(angles), np.sin(angles)], axis=-1)[None]).reshape(-1, 2)
    order = _zigzag_order(sides)
    inner = [(order[i], order[i + 1], order[i + 2]) if i % 2 == 0 else (order[i + 1], order[i], order[i + 2])
             for i in range(len(order) - 2)]
    circle, j = np.meshgrid(np.arange(len(radii) - 1), np.arange(sides), indexing="ij")
    a = circle * sides + j  # each quad's corners: this circle's j and j + 1, the next circle's likewise
    b = circle * sides + (j + 1) % sides
    quads = np.stack([a, a + sides, b, b, a + sides, b + sides], axis=-1).reshape(-1, 3)  # counter-clockwise
    return corners, np.concatenate([np.array(inner, dtype=np.int64).reshape(-1, 3), quads])


class StreamBuffer:
    """A vertex buffer rewritten every frame, grown (never shrunk) as needed."""

    def __init__(self, ctx: moderngl.Context, program: moderngl.Program) -> None:
        self.capacity = 64
        self.vbo = ctx.buffer(reserve=self.capacity, dynamic=True)
        self.vao = ctx.vertex_array(program, [(self.vbo, "3f", "in_position")])

    def draw(self, strip: np.ndarray) -> None:
        data = strip.tobytes()
        if len(data) > self.capacity:
            self.capacity = len(data) * 2
            self.vbo.orphan(self.capacity)
        self.vbo.write(data)
        self.vao.render(moderngl.TRIANGLE_STRIP, vertices=len(strip))

    def release(self) -> None:
        self.vao.release()
        self.vbo.release()


class GroundPass:
    """Everything under and around the creatures."""

    def __init__(self, ctx: moderngl.Context, shaders: ShaderLibrary, uniforms: Uniforms,
                 fog: tuple[float, float]) -> None:
        """``fog``: where the fog starts and where it is whole, as fractions of the floor's
        radius."""
        self.ctx = ctx
        self.uniforms = uniforms
        self.floor_prog = shaders.program("ground.vert", "ground.frag")
        # The floor is a disc out to where the fog has reached the horizon colour (no farther:
        # an eye just beyond it, below the floor's level, must not find the floor overhead),
        # with rings through the fog, which is computed at its corners (floor_mesh): a
        # software rasteriser's floor costs per pixel, and it is most of the picture.
        corners, triangles = floor_mesh(FLOOR_SIDES, *fog, FOG_RINGS)
        self.floor_vbo = ctx.buffer(corners.astype("f4").tobytes())
        self.floor_ibo = ctx.buffer(triangles.astype("u4").tobytes())
        self.floor_vao = ctx.vertex_array(self.floor_prog, [(self.floor_vbo, "2f", "in_xz")],
                                          index_buffer=self.floor_ibo, index_element_size=4)
        self.shadow_prog = shaders.program("ground.vert", "ground_shadow.frag")
        # The shadow's outline on the floor (world xz corners; ground.vert's rectangle set to
        # the identity), rewritten every frame.
        self.shadow_vbo = ctx.buffer(reserve=2 * 4 * SHADOW_OUTLINE_SIDES, dynamic=True)
        self.shadow_vao = ctx.vertex_array(self.shadow_prog, [(self.shadow_vbo, "2f", "in_xz")])
        self.sky_prog = shaders.program("background.vert", "background.frag")
        self.sky_vbo = ctx.buffer(reserve=2 * (SKY_ROWS + 2) * 5 * 4, dynamic=True)
        self.sky_vao = ctx.vertex_array(self.sky_prog, [(self.sky_vbo, "2f 3f", "in_ndc", "in_color")])
        self.terrain_prog = shaders.program("terrain.vert", "terrain.frag")
        self.overlay_prog = shaders.program("overlay.vert", "overlay.frag")
        self._terrain_key: tuple | None = None
        self._terrain_objects: list = []
        self._terrain_vao: moderngl.VertexArray | None = None
        self.path = StreamBuffer(ctx, self.overlay_prog)
        self.outline = StreamBuffer(ctx, self.overlay_prog)
        lit, depth = shaders.program("ellipsoid.vert", "lit.frag"), shaders.program("ellipsoid.vert", "depth.frag")
        # Overlay markers on the ground (footprints, targets): flat discs, no shadow.
        self.markers = InstancedMesh(ctx, lit, depth, unit_sphere(4, 12), unit_sphere(2, 4), *ELLIPSOID_LAYOUT)

    @property
    def lit_programs(self) -> tuple[moderngl.Program, ...]:
        """The programs that take the light's and camera's uniforms."""
        return (self.floor_prog, self.shadow_prog, self.terrain_prog, self.overlay_prog)

    def set_fog_and_grid(self, centre: np.ndarray, radius: float, fog: tuple[float, float], ground: GroundView,
                         options: RenderOptions) -> None:
        """The fog around the creatures and the grid's look, for every ground program."""
        set_ = self.uniforms.set
        horizon = tuple(srgb_to_linear(options.horizon_color))
        start, end = radius * fog[0], radius * fog[1]
        for prog in (self.floor_prog, self.terrain_prog, self.overlay_prog):
            set_(prog, "u_horizon_color", horizon)
            set_(prog, "u_focus", (float(centre[0]), float(centre[2])))
        for prog in (self.terrain_prog, self.overlay_prog):
            set_(prog, "u_fog_range", (start, end))
        set_(self.floor_prog, "u_fog_ramp", (1.0 / (end - start), -start / (end - start)))
        set_(self.terrain_prog, "u_ground_color", tuple(srgb_to_linear(options.ground_color)))
        set_(self.terrain_prog, "u_line_color", tuple(srgb_to_linear(options.line_color)))
        light = sum(floor_light(options))
        set_(self.floor_prog, "u_ground_lit", tuple(srgb_to_linear(options.ground_color) * light))
        set_(self.floor_prog, "u_line_lit", tuple(srgb_to_linear(options.line_color) * light))
        for prog in (self.floor_prog, self.terrain_prog):
            set_(prog, "u_grid_offset", (0.0, float(ground.offset)))
            set_(prog, "u_grid_spacing", float(options.grid_spacing))
            set_(prog, "u_grid_on", 1.0 if options.grid else 0.0)

    def draw_floor(self, scene: SceneInstances, centre: np.ndarray, reach: float, shadow_texel: float,
                   radius: float, options: RenderOptions) -> None:
        """The flat floor (a disc fading into the horizon) and the creatures' shadow on it."""
        ctx, set_ = self.ctx, self.uniforms.set
        g = self.floor_prog
        set_(g, "u_center", (float(centre[0]), float(centre[2])))
        set_(g, "u_half_size", (reach, reach))
        set_(g, "u_lift", 0.0)
        self.floor_vao.render(moderngl.TRIANGLES)
        if options.shadow:
            floor_ambient, floor_sun = floor_light(options)
            # The shadow on the floor, over the polygon holding it only, lifted a hair above the floor.
            self.shadow_vbo.write(shadow_outline(scene, shadow_texel).astype("f4").tobytes())
            gs = self.shadow_prog
            set_(gs, "u_center", (0.0, 0.0))
            set_(gs, "u_half_size", (1.0, 1.0))
            set_(gs, "u_lift", 1e-3 * radius)
            set_(gs, "u_shadowed_ratio", tuple(floor_ambient / (floor_ambient + floor_sun)))
            ctx.enable(moderngl.BLEND)
            ctx.blend_func = moderngl.DST_COLOR, moderngl.ZERO
            self.shadow_vao.render(moderngl.TRIANGLE_FAN)
            ctx.disable(moderngl.BLEND)
            ctx.blend_func = moderngl.DEFAULT_BLENDING  # type: ignore[assignment]  # (a pair of factors in the stub)

    def draw_terrain(self, terrain: Terrain, centre: np.ndarray, reach: float, options: RenderOptions) -> None:
        """The terrain as a lit mesh over a patch around the creatures. The patch snaps to
        whole cells of a grid fixed in the world, and is rebuilt only when it moves."""
        self.uniforms.set(self.terrain_prog, "u_contour", 0.5 * float(options.grid_spacing) if options.grid else 0.0)
        cell = 2.0 * reach / TERRAIN_CELLS
        decade = 10.0 ** math.floor(math.log10(cell))
        cell = float(decade * min((1.0, 2.0, 2.5, 5.0, 10.0), key=lambda m: abs(m - cell / decade)))
        lo = (math.floor((centre[0] - reach) / cell) * cell, math.floor((centre[2] - reach) / cell) * cell)
        size = (TERRAIN_CELLS + 2) * cell
        key = (id(terrain), lo, cell)
        if key != self._terrain_key:
            for obj in self._terrain_objects:
                obj.release()
            positions, normals, indices = terrain.surface(lo, (lo[0] + size, lo[1] + size), cell)
            vbo = self.ctx.buffer(np.concatenate([positions, normals], axis=1).astype("f4").tobytes())
            ibo = self.ctx.buffer(indices.astype("u4").tobytes())
            self._terrain_vao = self.ctx.vertex_array(self.terrain_prog, [(vbo, "3f 3f", "in_position", "in_normal")],
                                                      index_buffer=ibo, index_element_size=4)
            self._terrain_objects = [self._terrain_vao, vbo, ibo]
            self._terrain_key = key
        assert self._terrain_vao is not None
        self._terrain_vao.render(moderngl.TRIANGLES)

    def draw_path(self, ground: GroundView, reach: float, radius: float, options: RenderOptions) -> None:
        """The body's path as a thin ribbon draped over the ground, around the body, as
        wide as ``ground.path_width`` (else scaled to the scene's ``radius``) and lifted
        a fifth of that off the ground: under the creature's feet, never over it."""
        assert ground.path is not None
        terrain = ground.terrain
        width = 0.012 * radius + 0.004 if ground.path_width is None else ground.path_width
        pts, tangents = ground.path.sample(np.arange(ground.travel - reach, ground.travel + reach, reach / 120.0))
        side = left_of(tangents) * width
        # Draped over the ground: each point as high as the ground around it, so the ribbon
        # never dips under a step between two points.
        step = tangents * (reach / 120.0)
        lift = 0.004 * radius + 0.002 if ground.path_width is None else 0.1 * width
        y = np.maximum.reduce([terrain.height(pts + k * step) for k in (-1.0, 0.0, 1.0)]) + lift
        left, right = pts + side, pts - side
        strip = np.empty((2 * len(pts), 3), dtype="f4")
        strip[0::2] = np.column_stack([left[:, 0], y, left[:, 1]])
        strip[1::2] = np.column_stack([right[:, 0], y, right[:, 1]])
        if ground.offset:
            strip[:, 2] -= ground.offset
        self.uniforms.set(self.overlay_prog, "u_color", tuple(srgb_to_linear(options.path_color)))
        # Nearly on the ground (under the feet), drawn over it by a depth offset rather than a
        # lift that would have to grow with the depth range of the whole scene.
        self.ctx.polygon_offset = PATH_DEPTH_OFFSET
        self.path.draw(strip)
        self.ctx.polygon_offset = (0.0, 0.0)

    def draw_overlays(self, overlays: Overlays, terrain: Terrain, options: RenderOptions) -> None:
        """Footprints, touchdown targets and the support polygon, on the ground."""
        markers = overlays.markers(srgb_to_linear(options.ground_color), terrain)
        strip = overlays.outline(terrain)
        if strip is not None:
            self.uniforms.set(self.overlay_prog, "u_color", tuple(SUPPORT_COLOR))
            self.outline.draw(strip)
        if len(markers):
            self.markers.upload(markers)
            self.ctx.enable(moderngl.CULL_FACE)
            self.markers.draw(depth_only=False)
            self.ctx.disable(moderngl.CULL_FACE)

    def draw_sky(self, camera: Camera, aspect: float, centre: np.ndarray, reach: float, ground_level: float,
                 options: RenderOptions) -> None:
        """The sky band above the floor's far edge (nothing when no sky is in view)."""
        band = sky_band(camera, aspect, centre, reach, ground_level)
        if band is None:
            return
        # The gradient's colours per row, in display values (linear mix, then the display
        # transform): the fragment shader only passes them on (its cost is per pixel).
        top, horizon = srgb_to_linear(options.sky_color), srgb_to_linear(options.horizon_color)
        t = np.clip(band[:, 1] / SKY_FADE, 0.0, 1.0)
        fade = t * t * (3.0 - 2.0 * t)
        colors = np.sqrt(np.clip(horizon + (top - horizon) * fade[:, None], 0.0, 1.0))
        strip = np.empty((2 * len(band), 5), dtype="f4")
        strip[0::2, 0], strip[1::2, 0] = -1.0, 1.0
        strip[:, 1] = np.repeat(band[:, 0], 2)
        strip[:, 2:] = np.repeat(colors, 2, axis=0)
        self.ctx.depth_func = "<="  # the sky sits exactly on the far plane
        self.sky_vbo.write(strip.tobytes())
        self.sky_vao.render(moderngl.TRIANGLE_STRIP, vertices=len(strip))
        self.ctx.depth_func = "<"

    def release(self) -> None:
        for obj in (*self._terrain_objects, self.floor_vao, self.shadow_vao, self.shadow_vbo, self.floor_vbo, self.floor_ibo,
                    self.sky_vao, self.sky_vbo):
            obj.release()
        self.path.release()
        self.outline.release()
        self.markers.release()
