"""The scene renderer: a creature pose, a ground with a grid and a shadow, into any framebuffer.

Lifecycle (the same for a window and for EGL): create with a context, call
:meth:`SceneRenderer.render` per frame with a target framebuffer, :meth:`release` at the
end. The renderer owns its GL objects and knows nothing about windows or files.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from pyglm import glm
import moderngl
import numpy as np

from ..kinematics.motion import Pose
from ..kinematics.path import Path, left_of
from ..kinematics.rig import Rig
from ..kinematics.terrain import FlatTerrain, Terrain
from .camera import Camera
from .meshes import unit_capsule, unit_sphere
from .overlays import SUPPORT_COLOR, Overlays
from .scene import CAPSULE_FLOATS, ELLIPSOID_FLOATS, SceneInstances, pose_instances, srgb_to_linear
from .shaders import ShaderLibrary

GL_MULTISAMPLE = 0x809D  # glEnable/glDisable capability (moderngl's enable_direct)
SHADOW_MAP_SIZE = 256
FLOOR_SEGMENTS = 64
THIN_CAPSULE = 0.35  # capsules thinner than this fraction of the thickest use the coarse mesh
SUN_COLOR = np.array([0.95, 0.90, 0.84])  # as in shaders/lighting.glsl
LIGHT_DIR = np.array([-0.45, -1.0, -0.35]) / np.linalg.norm([-0.45, -1.0, -0.35])


@dataclass(frozen=True)
class RenderOptions:
    """What to draw. Colours are ``#rrggbb`` (sRGB)."""

    grid: bool = True
    shadow: bool = True
    joints: bool = True
    grid_spacing: float = 0.25  # metres between minor grid lines
    sky_color: str = "#cfd9e6"
    horizon_color: str = "#eef0ee"
    ground_color: str = "#e3ddd2"
    line_color: str = "#a89f91"
    path: bool = False  # draw the body's path on the ground
    path_color: str = "#3b7dd8"
    footprints: bool = False  # the last footprint_count footprints, fading (viewer overlays)
    footprint_count: int = 24
    targets: bool = False  # where the swinging feet will land
    support: bool = False  # the planted feet's support polygon and the trunk's centre in it
    arcs: tuple[str, ...] = ()  # joints whose paths over the last cycle are drawn (viewer; see kinematics.arcs)


@dataclass(frozen=True)
class GroundView:
    """The ground under a frame: the terrain, how far the ground has moved back (in place),
    and the path to draw around the body's arc length ``travel`` (m) along it."""

    terrain: Terrain = FlatTerrain()
    offset: float = 0.0
    path: Path | None = None
    travel: float = 0.0


TERRAIN_CELLS = 72  # the terrain patch around the creature is this many cells across


def nice_grid_spacing(scale: float) -> float:
    """A round grid spacing (1, 2.5 or 5 x 10^k m) near a quarter of ``scale`` (m)."""
    raw = max(scale / 4.0, 1e-3)
    exponent = math.floor(math.log10(raw))
    for step in (1.0, 2.5, 5.0, 10.0):
        if raw <= step * 10 ** exponent * 1.5:
            return step * 10 ** exponent
    return 10.0 ** (exponent + 1)


class _InstancedMesh:
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


class SceneRenderer:
    """Draws poses. One instance per GL context; reuse it for every frame."""

    def __init__(self, ctx: moderngl.Context, shaders: ShaderLibrary | None = None) -> None:
        self.ctx = ctx
        self.shaders = shaders or ShaderLibrary(ctx)
        lit_caps = self.shaders.program("capsule.vert", "lit.frag")
        depth_caps = self.shaders.program("capsule.vert", "depth.frag")
        lit_ell = self.shaders.program("ellipsoid.vert", "lit.frag")
        depth_ell = self.shaders.program("ellipsoid.vert", "depth.frag")
        # Two levels of detail each: thick capsules (trunk, neck, head) and the skull get
        # finer meshes than thin ones (leg bones, tail, ears) and small spheres (joints,
        # eyes), whose facets a few pixels wide do not show. Vertex shading runs on one
        # CPU thread in a software rasteriser, so this matters.
        capsule_layout = ("3f 1f", ("in_pos", "in_end"), "3f 3f 2f 3f/i",
                          ("in_a", "in_b", "in_radius", "in_color"), CAPSULE_FLOATS)
        ellipsoid_layout = ("3f", ("in_pos",), "3f 3f 3f 3f 3f 3f/i",
                            ("in_center", "in_axis_x", "in_axis_y", "in_axis_z", "in_radii", "in_color"),
                            ELLIPSOID_FLOATS)
        self.capsules = _InstancedMesh(ctx, lit_caps, depth_caps, unit_capsule(8, 14), unit_capsule(4, 8),
                                       *capsule_layout)
        self.thin_capsules = _InstancedMesh(ctx, lit_caps, depth_caps, unit_capsule(6, 9), unit_capsule(2, 6),
                                            *capsule_layout)
        self.ellipsoids = _InstancedMesh(ctx, lit_ell, depth_ell, unit_sphere(10, 16), unit_sphere(6, 8),
                                         *ellipsoid_layout)
        self.small_ellipsoids = _InstancedMesh(ctx, lit_ell, depth_ell, unit_sphere(6, 9), unit_sphere(3, 4),
                                               *ellipsoid_layout)
        # Overlay markers on the ground (footprints, targets): flat discs, no shadow.
        self.markers = _InstancedMesh(ctx, lit_ell, depth_ell, unit_sphere(4, 12), unit_sphere(2, 4),
                                      *ellipsoid_layout)
        self.ground_prog = self.shaders.program("ground.vert", "ground.frag")
        # The floor is a disc (a fan) out to where the fog has reached the horizon colour.
        angles = np.linspace(0.0, 2.0 * np.pi, FLOOR_SEGMENTS + 1)
        disc = np.concatenate([[[0.0, 0.0]], np.stack([np.cos(angles), np.sin(angles)], axis=1)]).astype("f4")
        self.ground_vbo = ctx.buffer(disc.tobytes())
        self.ground_vao = ctx.vertex_array(self.ground_prog, [(self.ground_vbo, "2f", "in_xz")])
        quad = np.array([-1, -1, 1, -1, -1, 1, 1, 1], dtype="f4")
        self.quad_vbo = ctx.buffer(quad.tobytes())
        self.ground_shadow_prog = self.shaders.program("ground.vert", "ground_shadow.frag")
        self.ground_shadow_vao = ctx.vertex_array(self.ground_shadow_prog, [(self.quad_vbo, "2f", "in_xz")])
        self.background_prog = self.shaders.program("background.vert", "background.frag")
        self.sky_vbo = ctx.buffer(reserve=4 * 3 * 4, dynamic=True)
        self.background_vao = ctx.vertex_array(self.background_prog, [(self.sky_vbo, "2f 1f", "in_ndc", "in_height")])

        self.shadow_map = ctx.depth_texture((SHADOW_MAP_SIZE, SHADOW_MAP_SIZE))
        self.shadow_map.compare_func = "<="
        self.shadow_map.filter = (moderngl.LINEAR, moderngl.LINEAR)
        self.shadow_map.repeat_x = False
        self.shadow_map.repeat_y = False
        self.shadow_fbo = ctx.framebuffer(depth_attachment=self.shadow_map)
        self.terrain_prog = self.shaders.program("terrain.vert", "terrain.frag")
        self.overlay_prog = self.shaders.program("overlay.vert", "overlay.frag")
        self._terrain_key: tuple | None = None
        self._terrain_objects: list = []
        self._terrain_vao: moderngl.VertexArray | None = None
        self.path_vbo = ctx.buffer(reserve=64, dynamic=True)
        self._path_capacity = 64
        self.path_vao = ctx.vertex_array(self.overlay_prog, [(self.path_vbo, "3f", "in_position")])
        self.outline_vbo = ctx.buffer(reserve=64, dynamic=True)
        self._outline_capacity = 64
        self.outline_vao = ctx.vertex_array(self.overlay_prog, [(self.outline_vbo, "3f", "in_position")])
        self._lit_programs = (lit_caps, lit_ell, self.ground_prog, self.ground_shadow_prog, self.terrain_prog,
                              self.overlay_prog)
        self._members: dict[int, set[str]] = {}
        self._uniforms: dict[tuple[int, str], object] = {}

    # -- per frame ------------------------------------------------------------------

    def render(self, pose: Pose, rig: Rig, camera: Camera, target: moderngl.Framebuffer,
               options: RenderOptions = RenderOptions(), viewport: tuple[int, int, int, int] | None = None) -> None:
        """Draw ``pose`` of creature ``rig`` seen by ``camera`` into ``target`` (cleared first)."""
        scene = pose_instances(pose, rig, show_joints=options.joints)
        self.draw_instances(scene, GroundView(offset=pose.ground_offset), camera, target, options, viewport)

    # The floor is drawn out to where the fog has turned it into the horizon colour; the
    # sky shader gives the same colour below the horizon beyond it.
    FOG_START = 2.2  # x the creature's bounding radius
    FOG_END = 5.0

    def draw_instances(self, scene: SceneInstances, ground: GroundView | float, camera: Camera,
                       target: moderngl.Framebuffer, options: RenderOptions,
                       viewport: tuple[int, int, int, int] | None = None, multisampled: bool | None = None,
                       overlays: Overlays | None = None) -> None:
        """Draw creature instances over ``ground`` (a GroundView, or the in-place ground
        offset in metres) seen by ``camera`` into ``target`` (cleared first), with
        ``overlays`` (footprints, targets, support polygon) on the ground.
        ``multisampled``: whether ``target`` has several samples per pixel (default: from
        its colour attachments; give it for a window's framebuffer)."""
        if not isinstance(ground, GroundView):
            ground = GroundView(offset=float(ground))
        terrain = ground.terrain
        ctx = self.ctx
        # Nearest first, so the depth test rejects hidden fragments before shading them.
        eye = np.asarray(camera.eye, dtype=np.float32)
        caps = scene.capsules
        caps = caps[np.argsort(((0.5 * (caps[:, 0:3] + caps[:, 3:6]) - eye) ** 2).sum(axis=1))]
        thick = caps[:, 6:8].max(axis=1) >= THIN_CAPSULE * caps[:, 6:8].max()
        self.capsules.upload(caps[thick])
        self.thin_capsules.upload(caps[~thick])
        small = scene.ellipsoids[scene.ellipsoid_casters:]
        self.ellipsoids.upload(scene.ellipsoids[:scene.ellipsoid_casters])
        self.small_ellipsoids.upload(small[np.argsort(((small[:, 0:3] - eye) ** 2).sum(axis=1))])
        viewport = viewport or (0, 0, *target.size)
        aspect = viewport[2] / max(viewport[3], 1)

        centre, radius = self._bounds(scene, terrain)
        ground_level = 0.0 if terrain.flat else float(terrain.height(centre[[0, 2]]))
        light_vp, shadow_texel = self._light_view_proj(scene, None if terrain.flat else ground_level)
        ctx.enable(moderngl.DEPTH_TEST | moderngl.CULL_FACE)
        ctx.disable(moderngl.BLEND)
        ctx.depth_func = "<"

        # 1. Shadow pass (depth from the key light).
        self.shadow_fbo.use()
        self.shadow_fbo.clear(depth=1.0)
        if options.shadow:
            for mesh in (self.capsules, self.thin_capsules, self.ellipsoids):  # small spheres cast no shadow
                mesh.vao_depth.program["u_view_proj"].write(light_vp)
                mesh.draw(depth_only=True)

        # 2. Main pass. Without multisampling the creature goes first, nearest shapes
        #    first, so the depth test rejects the ground hidden behind it before shading
        #    it (a software rasteriser's cost is per pixel shaded). With multisampling the
        #    ground and the sky go first with it off, then the creature with it on: a
        #    software rasteriser (llvmpipe) shades every sample of a multisampled target,
        #    so the ground, most of the picture, would cost four times over for nothing
        #    (its grid lines antialias themselves and its far edge fades into the fog);
        #    drawn first, it sits under the creature's antialiased edges.
        target.use()
        target.viewport = viewport
        sky, horizon = srgb_to_linear(options.sky_color), srgb_to_linear(options.horizon_color)
        target.clear(*np.sqrt(horizon), 1.0, depth=1.0, viewport=viewport)  # beyond the floor: horizon
        view_proj = camera.view_proj(aspect)
        self.shadow_map.use(location=0)
        for prog in self._lit_programs:
            self._set(prog, "u_view_proj", view_proj)
            self._set(prog, "u_light_view_proj", light_vp)
            self._set(prog, "u_light_dir", tuple(LIGHT_DIR))
            self._set(prog, "u_camera_pos", tuple(camera.eye))
            self._set(prog, "u_sky_color", tuple(sky))
            self._set(prog, "u_bounce_color", tuple(srgb_to_linear(options.ground_color) * 0.8))
            self._set(prog, "u_shadow_map", 0)
            self._set(prog, "u_shadow_strength", 0.7 if options.shadow else 0.0)
            self._set(prog, "u_shadow_texel", shadow_texel)
        if multisampled is None:
            multisampled = any(getattr(a, "samples", 0) > 0 for a in target.color_attachments)
        if not multisampled:
            self._draw_creature()
        ctx.disable_direct(GL_MULTISAMPLE)
        ctx.disable(moderngl.CULL_FACE)
        reach = radius * self.FOG_END * 1.05
        horizon_t = tuple(horizon)
        for prog in (self.ground_prog, self.terrain_prog, self.overlay_prog):
            self._set(prog, "u_horizon_color", horizon_t)
            self._set(prog, "u_focus", (float(centre[0]), float(centre[2])))
            self._set(prog, "u_fog_range", (radius * self.FOG_START, radius * self.FOG_END))
        for prog in (self.ground_prog, self.terrain_prog):
            self._set(prog, "u_ground_color", tuple(srgb_to_linear(options.ground_color)))
            self._set(prog, "u_line_color", tuple(srgb_to_linear(options.line_color)))
            self._set(prog, "u_grid_offset", (0.0, float(ground.offset)))
            self._set(prog, "u_grid_spacing", float(options.grid_spacing))
            self._set(prog, "u_grid_on", 1.0 if options.grid else 0.0)
        if terrain.flat:
            self._draw_floor(scene, centre, reach, shadow_texel, radius, options)
        else:
            self._set(self.terrain_prog, "u_contour", 0.5 * float(options.grid_spacing) if options.grid else 0.0)
            self._draw_terrain(terrain, centre, reach)
        if options.path and ground.path is not None:
            self._draw_path(ground, terrain, reach, radius, options)
        if overlays is not None:
            self._draw_overlays(overlays, terrain, options)

        band = self._sky_band(camera, aspect, centre, reach, ground_level)
        if band is not None:
            ctx.depth_func = "<="  # the sky sits exactly on the far plane
            self.sky_vbo.write(band.tobytes())
            self._set(self.background_prog, "u_top_color", tuple(sky))
            self._set(self.background_prog, "u_horizon_color", tuple(horizon))
            self.background_vao.render(moderngl.TRIANGLE_STRIP)
            ctx.depth_func = "<"
        ctx.enable_direct(GL_MULTISAMPLE)
        if multisampled:
            self._draw_creature()

    def _draw_creature(self) -> None:
        """The creature's shapes as uploaded for this frame, lit and shadowed."""
        ctx = self.ctx
        ctx.enable(moderngl.CULL_FACE)
        ctx.disable(moderngl.BLEND)
        for mesh in (self.capsules, self.ellipsoids, self.thin_capsules, self.small_ellipsoids):
            mesh.draw(depth_only=False)
        ctx.disable(moderngl.CULL_FACE)

    def _draw_floor(self, scene: SceneInstances, centre: np.ndarray, reach: float, shadow_texel: float,
                    radius: float, options: RenderOptions) -> None:
        """The flat floor (a disc fading into the horizon) and the creature's shadow on it."""
        ctx = self.ctx
        g = self.ground_prog
        self._set(g, "u_center", (float(centre[0]), float(centre[2])))
        self._set(g, "u_half_size", (reach, reach))
        self._set(g, "u_lift", 0.0)
        floor_ambient, floor_sun = self._floor_light(options)
        self._set(g, "u_floor_light", tuple(floor_ambient + floor_sun))
        self.ground_vao.render(moderngl.TRIANGLE_FAN)
        if options.shadow:
            # The shadow on the floor, over its footprint only, lifted a hair above the floor.
            lo, hi = self._shadow_footprint(scene, shadow_texel)
            gs = self.ground_shadow_prog
            self._set(gs, "u_center", tuple(0.5 * (lo + hi)))
            self._set(gs, "u_half_size", tuple(0.5 * (hi - lo)))
            self._set(gs, "u_lift", 1e-3 * radius)
            self._set(gs, "u_shadowed_ratio", tuple(floor_ambient / (floor_ambient + floor_sun)))
            ctx.enable(moderngl.BLEND)
            ctx.blend_func = moderngl.DST_COLOR, moderngl.ZERO
            self.ground_shadow_vao.render(moderngl.TRIANGLE_STRIP)
            ctx.disable(moderngl.BLEND)
            ctx.blend_func = moderngl.DEFAULT_BLENDING

    def _draw_terrain(self, terrain: Terrain, centre: np.ndarray, reach: float) -> None:
        """The terrain as a lit mesh over a patch around the creature. The patch snaps to
        whole cells of a grid fixed in the world, and is rebuilt only when it moves."""
        cell = 2.0 * reach / TERRAIN_CELLS
        cell = float(10.0 ** math.floor(math.log10(cell)) * min((1.0, 2.0, 2.5, 5.0, 10.0),
                                                              key=lambda m: abs(m - cell / 10.0 ** math.floor(
                                                                  math.log10(cell)))))
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

    def _draw_path(self, ground: GroundView, terrain: Terrain, reach: float, radius: float,
                   options: RenderOptions) -> None:
        """The body's path as a thin ribbon draped over the ground, around the body."""
        assert ground.path is not None
        width = 0.012 * radius + 0.004
        pts, tangents = ground.path.sample(np.arange(ground.travel - reach, ground.travel + reach, reach / 120.0))
        side = left_of(tangents) * width
        # Draped over the ground: each point as high as the ground around it, so the ribbon
        # never dips under a step between two points.
        step = tangents * (reach / 120.0)
        y = np.maximum.reduce([terrain.height(pts + k * step) for k in (-1.0, 0.0, 1.0)]) + 0.004 * radius + 0.002
        left, right = pts + side, pts - side
        strip = np.empty((2 * len(pts), 3), dtype="f4")
        strip[0::2] = np.column_stack([left[:, 0], y, left[:, 1]])
        strip[1::2] = np.column_stack([right[:, 0], y, right[:, 1]])
        if ground.offset:
            strip[:, 2] -= ground.offset
        data = strip.tobytes()
        if len(data) > self._path_capacity:
            self._path_capacity = len(data) * 2
            self.path_vbo.orphan(self._path_capacity)
        self.path_vbo.write(data)
        self._set(self.overlay_prog, "u_color", tuple(srgb_to_linear(options.path_color)))
        self.path_vao.render(moderngl.TRIANGLE_STRIP, vertices=len(strip))

    def _draw_overlays(self, overlays: Overlays, terrain: Terrain, options: RenderOptions) -> None:
        """Footprints, touchdown targets and the support polygon, on the ground."""
        markers = overlays.markers(srgb_to_linear(options.ground_color), terrain)
        strip = overlays.outline(terrain)
        if strip is not None:
            data = strip.tobytes()
            if len(data) > self._outline_capacity:
                self._outline_capacity = len(data) * 2
                self.outline_vbo.orphan(self._outline_capacity)
            self.outline_vbo.write(data)
            self._set(self.overlay_prog, "u_color", tuple(SUPPORT_COLOR))
            self.outline_vao.render(moderngl.TRIANGLE_STRIP, vertices=len(strip))
        if len(markers):
            self.markers.upload(markers)
            self.ctx.enable(moderngl.CULL_FACE)
            self.markers.draw(depth_only=False)
            self.ctx.disable(moderngl.CULL_FACE)

    def _set(self, prog: moderngl.Program, name: str, value) -> None:
        """Set a uniform if the program has it and its value changed since the last frame."""
        members = self._members.get(prog.glo)
        if members is None:
            members = self._members[prog.glo] = {m for m in prog if isinstance(prog[m], moderngl.Uniform)}
        if name not in members:
            return
        key = (prog.glo, name)
        if self._uniforms.get(key) == value:
            return
        self._uniforms[key] = value
        uniform = prog[name]
        if isinstance(value, glm.mat4):
            uniform.write(value)
        else:
            uniform.value = value

    @staticmethod
    def _floor_light(options: RenderOptions) -> tuple[np.ndarray, np.ndarray]:
        """Ambient and sun light reaching the flat floor: lighting.glsl's model for an
        upward normal (``ambient_light(up)`` and the wrapped key light)."""
        sky = srgb_to_linear(options.sky_color)
        ambient = sky * 0.55  # mix(bounce, sky, 0.5 + 0.5 * n.y) with n = up
        wrapped = max((-LIGHT_DIR[1] + 0.35) / 1.35, 0.0)
        return ambient, SUN_COLOR * wrapped

    @staticmethod
    def _bounds(scene: SceneInstances, terrain: Terrain) -> tuple[np.ndarray, float]:
        """The creature's box down to the ground: its centre and half diagonal (m)."""
        pts = np.concatenate([scene.capsules[:, 0:3], scene.capsules[:, 3:6], scene.ellipsoids[:, 0:3]])
        lo, hi = pts.min(axis=0), pts.max(axis=0)
        lo[1] = 0.0 if terrain.flat else min(float(lo[1]), float(terrain.height(0.5 * (lo + hi)[[0, 2]])))
        centre = 0.5 * (lo + hi)
        return centre, float(np.linalg.norm(hi - lo) * 0.5 + 0.05)

    @staticmethod
    def _light_view_proj(scene: SceneInstances, ground: float | None = None) -> tuple[glm.mat4, float]:
        """Orthographic key-light matrix fitted tightly around the shadow casters, and the
        world size (m) of one shadow-map texel.

        Seen from a directional light, a shadow lies exactly within its casters' xy
        footprint, so any receiver outside this box is lit and costs no shadow lookups.
        The depth range reaches past the casters down to the ground under them.
        """
        caps, ells = scene.capsules, scene.ellipsoids
        points = np.concatenate([caps[:, 0:3], caps[:, 3:6], ells[:, 0:3]]).astype(np.float64)
        pads = np.concatenate([caps[:, 6], caps[:, 7], ells[:, 12:15].max(axis=1)]).astype(np.float64)
        centre = 0.5 * (points.min(axis=0) + points.max(axis=0))
        height = float(points[:, 1].max() + pads.max())
        view = glm.lookAt(glm.vec3(*(centre - LIGHT_DIR * (height + 1.0) * 4.0)), glm.vec3(*centre),
                          glm.vec3(0.0, 0.0, 1.0))
        m = np.array(view, dtype=np.float64)  # numpy sees glm matrices row-major (as written in maths)
        local = points @ m[:3, :3].T + m[:3, 3]
        lo = local.min(axis=0) - pads.max()
        hi = local.max(axis=0) + pads.max()
        # From the highest caster down to the flat floor (y = 0), or on terrain (``ground``:
        # its height under the creature) as far again below it, for slopes falling away.
        drop = height if ground is None else 2.0 * (height - ground) + 0.5 * float(np.ptp(points[:, 0]))
        reach = drop / max(-LIGHT_DIR[1], 1e-3) + 0.01
        near, far = -hi[2] - 0.01, -lo[2] + reach
        proj = glm.ortho(float(lo[0]), float(hi[0]), float(lo[1]), float(hi[1]), float(near), float(far))
        return proj * view, float(max(hi[0] - lo[0], hi[1] - lo[1]) / SHADOW_MAP_SIZE)

    @staticmethod
    def _shadow_footprint(scene: SceneInstances, texel: float) -> tuple[np.ndarray, np.ndarray]:
        """World xz bounds (lo, hi) of the creature's shadow on the plane y = 0: every
        caster point projected along the light, padded by its radius."""
        caps, ells = scene.capsules, scene.ellipsoids[:scene.ellipsoid_casters]
        points = np.concatenate([caps[:, 0:3], caps[:, 3:6], ells[:, 0:3]]).astype(np.float64)
        pad = float(max(caps[:, 6:8].max(), ells[:, 12:15].max() if len(ells) else 0.0))
        on_ground = points - LIGHT_DIR * (points[:, 1:2] / LIGHT_DIR[1])
        pad = pad / abs(LIGHT_DIR[1]) + 4.0 * texel
        return on_ground[:, [0, 2]].min(axis=0) - pad, on_ground[:, [0, 2]].max(axis=0) + pad

    @staticmethod
    def _sky_band(camera: Camera, aspect: float, centre: np.ndarray, reach: float,
                  ground_level: float = 0.0) -> np.ndarray | None:
        """The sky's screen band: from the floor's far edge straight ahead up to the top
        of the view, as 4 vertices (ndc x, ndc y, height); None when no sky is in view."""
        forward = np.asarray(camera.target, dtype=np.float64) - camera.eye
        flat = np.array([forward[0], 0.0, forward[2]])
        if camera.top_down or np.linalg.norm(flat) < 1e-6:
            return None
        flat /= np.linalg.norm(flat)
        edge = np.array([centre[0], ground_level, centre[2]]) + flat * reach
        vp = np.array(camera.view_proj(aspect), dtype=np.float64)
        clip = vp @ np.append(edge, 1.0)
        y0 = float(np.clip(clip[1] / clip[3], -1.0, 1.0)) if clip[3] > 0 else -1.0
        if y0 >= 1.0:
            return None
        if camera.ortho:
            h1 = 0.6
        else:
            far = np.linalg.inv(vp) @ np.array([0.0, 1.0, 1.0, 1.0])
            ray = far[:3] / far[3] - camera.eye
            h1 = max(float(ray[1] / np.linalg.norm(ray)), 0.0)
        return np.array([[-1, y0, 0.0], [1, y0, 0.0], [-1, 1, h1], [1, 1, h1]], dtype="f4")

    def release(self) -> None:
        """Free every GL object this renderer made."""
        for mesh in (self.capsules, self.thin_capsules, self.ellipsoids, self.small_ellipsoids, self.markers):
            mesh.release()
        for obj in (*self._terrain_objects, self.path_vao, self.path_vbo, self.outline_vao, self.outline_vbo):
            obj.release()
        for obj in (self.ground_vao, self.ground_shadow_vao, self.ground_vbo, self.quad_vbo, self.background_vao,
                    self.sky_vbo, self.shadow_fbo, self.shadow_map):
            obj.release()
        self.shaders.release()
