"""The scene renderer: creatures (instanced capsules and ellipsoids), their shadow and
the ground, into any framebuffer.

Lifecycle (the same for a window and for EGL): create with a context, call
:meth:`SceneRenderer.draw_instances` per frame with a target framebuffer,
:meth:`SceneRenderer.release` at the end. It owns its GL objects and knows nothing about
windows or files. A frame is three passes: the shadow map (:meth:`SceneRenderer.cast`),
the creatures (:class:`CreaturePass`) and the ground (:class:`~app.render.ground.GroundPass`,
with the sky).

The first can be issued ahead: a viewer casts the next frame's shadow while the GL still
rasterises this one (two shadow maps take turns), so the next frame's creatures, which
read the shadow map, do not wait for it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import moderngl
import numpy as np
from pyglm import glm

from ..kinematics.motion import Pose
from ..kinematics.rig import Rig
from ..kinematics.terrain import Terrain
from .bodies import body_levels, pose_body, shared_body_cache
from .camera import Camera
from .ground import ELLIPSOID_LAYOUT, GroundPass
from .instanced import InstancedMesh
from .lighting import LIGHT_DIR, SHADOW_MAP_SIZE, creature_bounds, light_view_proj
from .meshes import unit_capsule, unit_sphere
from .options import GroundView, RenderOptions
from .overlays import Overlays
from .scene import CAPSULE_FLOATS, Cap, Ell, SceneInstances, pose_instances, srgb_to_linear
from .shaders import ShaderLibrary
from .uniforms import Uniforms, uniform

GL_MULTISAMPLE = 0x809D  # glEnable/glDisable capability (moderngl's enable_direct)
TINY_PIXELS = 4.0  # small spheres fewer pixels across than this get the coarsest mesh
THIN_CAPSULE = 0.35  # capsules thinner than this fraction of the thickest use the coarse mesh
CAPSULE_LAYOUT = ("3f 1f", ("in_pos", "in_end"), "3f 3f 2f 3f/i", ("in_a", "in_b", "in_radius", "in_color"),
                  CAPSULE_FLOATS)


class CreaturePass:
    """The creatures' shapes: four instanced meshes, each in two levels of detail (thick
    capsules such as the trunk and the skull get finer meshes than thin ones such as leg
    bones, and small spheres such as joints and eyes; vertex shading runs on one CPU
    thread in a software rasteriser, so this matters)."""

    def __init__(self, ctx: moderngl.Context, shaders: ShaderLibrary) -> None:
        self.ctx = ctx
        lit_caps, depth_caps = shaders.program("capsule.vert", "lit.frag"), shaders.program("capsule.vert", "depth.frag")
        lit_ell, depth_ell = shaders.program("ellipsoid.vert", "lit.frag"), shaders.program("ellipsoid.vert", "depth.frag")
        self.lit_programs = (lit_caps, lit_ell)
        self.capsules = InstancedMesh(ctx, lit_caps, depth_caps, unit_capsule(8, 14), unit_capsule(4, 8),
                                      *CAPSULE_LAYOUT)
        self.thin_capsules = InstancedMesh(ctx, lit_caps, depth_caps, unit_capsule(6, 9), unit_capsule(2, 6),
                                           *CAPSULE_LAYOUT)
        self.ellipsoids = InstancedMesh(ctx, lit_ell, depth_ell, unit_sphere(10, 16), unit_sphere(6, 8),
                                        *ELLIPSOID_LAYOUT)
        self.small_ellipsoids = InstancedMesh(ctx, lit_ell, depth_ell, unit_sphere(6, 9), unit_sphere(3, 4),
                                              *ELLIPSOID_LAYOUT)
        # ... and those a few pixels across (a herd's far eyes): a handful of faces does
        self.tiny_ellipsoids = InstancedMesh(ctx, lit_ell, depth_ell, unit_sphere(3, 5), unit_sphere(3, 4),
                                             *ELLIPSOID_LAYOUT)

    def upload(self, scene: SceneInstances, eye: np.ndarray, pixel: float | None = None) -> None:
        """This frame's shapes, nearest first, so the depth test rejects hidden fragments
        before shading them. ``pixel``: the angle (radians) one pixel spans at the eye
        (perspective); small spheres (eyes, joints) narrower than half a pixel are left
        out, and those under TINY_PIXELS across get a coarse sphere (a herd's far eyes:
        every vertex is shaded on the drawing thread)."""
        caps = scene.capsules
        caps = caps[np.argsort(((0.5 * (caps[:, Cap.A] + caps[:, Cap.B]) - eye) ** 2).sum(axis=1))]
        thick = caps[:, Cap.RADII].max(axis=1) >= THIN_CAPSULE * (caps[:, Cap.RADII].max() if len(caps) else 0.0)
        self.capsules.upload(caps[thick])
        self.thin_capsules.upload(caps[~thick])
        small = scene.ellipsoids[scene.ellipsoid_casters:]
        self.ellipsoids.upload(scene.ellipsoids[:scene.ellipsoid_casters])
        small = small[np.argsort(((small[:, Ell.CENTRE] - eye) ** 2).sum(axis=1))]
        tiny = np.zeros(len(small), dtype=bool)
        if pixel is not None:
            across = 2.0 * small[:, Ell.RADII].max(axis=1) / (pixel * np.sqrt(((small[:, Ell.CENTRE] - eye) ** 2).sum(axis=1)))
            small, across = small[across >= 0.5], across[across >= 0.5]
            tiny = across < TINY_PIXELS
        self.small_ellipsoids.upload(small[~tiny])
        self.tiny_ellipsoids.upload(small[tiny])

    def draw_depth(self, light_vp: glm.mat4) -> None:
        """Into the shadow map (small spheres cast no shadow)."""
        for mesh in (self.capsules, self.thin_capsules, self.ellipsoids):
            uniform(mesh.vao_depth.program, "u_view_proj").write(light_vp)
            mesh.draw(depth_only=True)

    def draw(self) -> None:
        """Lit and shadowed."""
        self.ctx.enable(moderngl.CULL_FACE)
        self.ctx.disable(moderngl.BLEND)
        for mesh in (self.capsules, self.ellipsoids, self.thin_capsules, self.small_ellipsoids, self.tiny_ellipsoids):
            mesh.draw(depth_only=False)
        self.ctx.disable(moderngl.CULL_FACE)

    def release(self) -> None:
        for mesh in (self.capsules, self.thin_capsules, self.ellipsoids, self.small_ellipsoids, self.tiny_ellipsoids):
            mesh.release()


class BodyPass:
    """Skinned bodies: each body's mesh (with its features: eyes, nose, mane) uploaded once
    (kept while it is drawn), every
    frame's skinning matrices in one float texture (a row per joint: the matrix's top
    three rows, a texel each), one instanced draw call for each run of draws of the same
    body (a herd)."""

    FLOATS = 17  # position, normal, colour, four joints, four weights

    def __init__(self, ctx: moderngl.Context, shaders: ShaderLibrary) -> None:
        self.ctx = ctx
        self.lit = shaders.program("skinned.vert", "lit.frag")
        self.depth = shaders.program("skinned.vert", "depth.frag")
        self._meshes: dict[int, tuple[object, list, int]] = {}  # id(body) -> (body, GL objects, last frame used)
        self._bones: moderngl.Texture | None = None
        self._draws: list[tuple[moderngl.VertexArray, moderngl.VertexArray, int, int, int]] = []
        self._frame = 0

    def _mesh(self, body) -> tuple[moderngl.VertexArray, moderngl.VertexArray]:
        entry = self._meshes.get(id(body))
        if entry is None or entry[0] is not body:
            meshes = [body] if getattr(body, "features", None) is None else [body, body.features]  # eyes, nose, mane
            data = np.concatenate([np.concatenate([m.positions, m.normals, m.colors, m.joints.astype(np.float32),
                                                   m.weights], axis=1) for m in meshes]).astype("f4")
            starts = np.cumsum([0] + [len(m.positions) for m in meshes[:-1]])
            faces = np.concatenate([m.faces.astype(np.int64) + start for m, start in zip(meshes, starts)])
            vbo = self.ctx.buffer(data.tobytes())
            ibo = self.ctx.buffer(faces.astype("u4").tobytes())
            layout = (vbo, "3f 3f 3f 4f 4f", "in_pos", "in_normal", "in_color", "in_joints", "in_weights")
            lit = self.ctx.vertex_array(self.lit, [layout], index_buffer=ibo, index_element_size=4)
            depth = self.ctx.vertex_array(self.depth, [layout], index_buffer=ibo, index_element_size=4,
                                          skip_errors=True)
            entry = (body, [lit, depth, vbo, ibo], self._frame)
        self._meshes[id(body)] = (entry[0], entry[1], self._frame)
        return entry[1][0], entry[1][1]

    def upload(self, scene: SceneInstances, eye: np.ndarray, shadow_texel: float, pixel: float | None) -> None:
        """This frame's bodies and their joints, each drawn and casting its shadow at the
        level of detail :func:`~app.render.bodies.body_levels` chooses for the camera at
        ``eye`` (pixels ``pixel`` radians across, None: orthographic) and shadow-map
        texels ``shadow_texel`` m across; draws of the same meshes
        go together (one instanced call each)."""
        self._frame += 1
        self._draws = []
        if not scene.bodies:
            return
        levels = body_levels(scene.bodies, eye, shadow_texel, pixel)
        order = sorted(range(len(levels)), key=lambda k: (id(levels[k][0]), id(levels[k][1])))  # runs of one mesh
        rows = np.concatenate([scene.bodies[k].skin[:, :3, :].reshape(-1, 12) for k in order]).astype("f4")
        if self._bones is None or self._bones.height < len(rows):
            if self._bones is not None:
                self._bones.release()
            self._bones = self.ctx.texture((3, max(len(rows), 64)), 4, dtype="f4")
            self._bones.filter = (moderngl.NEAREST, moderngl.NEAREST)
        self._bones.write(rows.tobytes(), viewport=(0, 0, 3, len(rows)))
        offset = 0
        for k in order:
            shown, caster = levels[k]
            joints = scene.bodies[k].skin.shape[0]
            lit, depth = self._mesh(shown)[0], self._mesh(caster)[1]
            if self._draws and self._draws[-1][0] is lit and self._draws[-1][1] is depth:
                _, _, first, stride, count = self._draws[-1]
                self._draws[-1] = (lit, depth, first, stride, count + 1)  # one more of the herd
            else:
                self._draws.append((lit, depth, offset, joints, 1))
            offset += joints
        for key in [k for k, (_, _, used) in self._meshes.items() if used < self._frame - 120]:
            for obj in self._meshes.pop(key)[1]:
                obj.release()  # a body not drawn for a while (an edited shape, a creature gone)

    def _draw(self, depth_only: bool) -> None:
        if not self._draws or self._bones is None:
            return
        self._bones.use(location=1)
        program = self.depth if depth_only else self.lit
        uniform(program, "u_bones").value = 1
        for lit, depth, offset, stride, count in self._draws:
            uniform(program, "u_bone_offset").value = offset
            uniform(program, "u_bone_stride").value = stride
            (depth if depth_only else lit).render(moderngl.TRIANGLES, instances=count)

    def draw_depth(self, light_vp: glm.mat4) -> None:
        uniform(self.depth, "u_view_proj").write(light_vp)
        self._draw(depth_only=True)

    def draw(self) -> None:
        self.ctx.enable(moderngl.CULL_FACE)
        self._draw(depth_only=False)
        self.ctx.disable(moderngl.CULL_FACE)

    def release(self) -> None:
        for _, objects, _ in self._meshes.values():
            for obj in objects:
                obj.release()
        self._meshes.clear()
        if self._bones is not None:
            self._bones.release()


def _pixel_angle(camera: Camera, viewport: tuple[int, int, int, int]) -> float | None:
    """The angle (rad) one pixel of ``viewport`` spans at ``camera``'s eye (None: orthographic)."""
    return None if camera.ortho else math.radians(camera.fov) / max(viewport[3], 1)


def _view_key(camera: Camera, viewport: tuple[int, int, int, int]) -> tuple[float | None, ...]:
    """What the levels of detail are chosen from: the eye (m) and the pixel's angle."""
    return (*(float(c) for c in camera.eye), _pixel_angle(camera, viewport))


@dataclass(frozen=True)
class ShadowCast:
    """One frame's shapes uploaded and its shadow map drawn (:meth:`SceneRenderer.cast`):
    the light's view-projection, the world size (m) of a shadow-map texel, which of the
    renderer's shadow maps holds it, and the creatures' bounds (``centre`` (3,), m, and
    ``radius``, m) and the ground's height under them (m)."""

    scene: SceneInstances
    light_vp: glm.mat4
    texel: float
    shadow_map: int
    centre: np.ndarray
    radius: float
    ground_level: float
    shadow: bool  # whether the creatures cast a shadow (options.shadow)
    view: tuple[float | None, ...]  # the view the levels of detail were chosen for (_view_key)

    def fits(self, scene: SceneInstances, camera: Camera, viewport: tuple[int, int, int, int],
             options: RenderOptions) -> bool:
        """Whether this cast holds ``scene`` as ``camera`` sees it in ``viewport``, with ``options``' shadow."""
        return self.scene is scene and self.shadow == options.shadow and self.view == _view_key(camera, viewport)


class SceneRenderer:
    """Draws creatures over the ground. One per GL context; reuse it for every frame."""

    # The floor is drawn out to where the fog has turned it into the horizon colour; the
    # sky shader gives the same colour below the horizon beyond it.
    FOG_START = 2.2  # x the creatures' bounding radius
    FOG_END = 5.0
    FLOOR_PAST_FOG = 1.05  # the floor's radius: a little past the fog's end

    def __init__(self, ctx: moderngl.Context, shaders: ShaderLibrary | None = None,
                 soft_self_shadow: bool = False) -> None:
        """``soft_self_shadow``: the creatures' shadows on themselves from four taps of the
        shadow map, as the ground's (offline rendering), not one (the window: a stepped
        edge where the head's shadow crosses the shoulder, but each tap costs a software
        rasteriser)."""
        self.ctx = ctx
        defines = ("SOFT_SELF_SHADOW",) if soft_self_shadow else ()
        if shaders is not None and set(defines) - set(shaders.defines):
            raise ValueError("soft_self_shadow needs a ShaderLibrary compiled with SOFT_SELF_SHADOW")
        self.shaders = shaders or ShaderLibrary(ctx, defines)
        self.uniforms = Uniforms()
        self.creatures = CreaturePass(ctx, self.shaders)
        self.bodies = BodyPass(ctx, self.shaders)
        self.body_cache = shared_body_cache()
        self.ground = GroundPass(ctx, self.shaders, self.uniforms,
                                 (self.FOG_START / (self.FOG_END * self.FLOOR_PAST_FOG), 1.0 / self.FLOOR_PAST_FOG))
        self.shadow_maps = tuple(self._shadow_map() for _ in range(2))  # (texture, framebuffer): they take turns
        self._next_map = 0
        self._latest: ShadowCast | None = None  # the last cast: its shapes are the ones uploaded

    def _shadow_map(self) -> tuple[moderngl.Texture, moderngl.Framebuffer]:
        texture = self.ctx.depth_texture((SHADOW_MAP_SIZE, SHADOW_MAP_SIZE))
        texture.compare_func = "<="
        texture.filter = (moderngl.LINEAR, moderngl.LINEAR)
        texture.repeat_x = False
        texture.repeat_y = False
        return texture, self.ctx.framebuffer(depth_attachment=texture)

    def render(self, pose: Pose, rig: Rig, camera: Camera, target: moderngl.Framebuffer,
               options: RenderOptions | None = None, viewport: tuple[int, int, int, int] | None = None) -> None:
        """Draw ``pose`` of creature ``rig`` seen by ``camera`` into ``target`` (cleared first)."""
        options = options or RenderOptions()
        skin = options.body == "skin"
        scene = pose_instances(pose, rig, show_joints=options.joint_markers, parts=not skin, by_side=options.side_colors)
        if skin:
            scene = replace(scene, bodies=(pose_body(pose, rig, self.body_cache),))
        self.draw_instances(scene, GroundView(offset=pose.ground_offset), camera, target, options, viewport)

    def cast(self, scene: SceneInstances, terrain: Terrain, camera: Camera, viewport: tuple[int, int, int, int],
             options: RenderOptions) -> ShadowCast:
        """Upload ``scene``'s shapes (nearest first, at the levels of detail ``camera``
        calls for in a view of ``viewport``'s size) and draw their shadow map, into the
        shadow map the last cast did not use (a frame drawn from it may still be in the
        GL's hands). Give the result to the next :meth:`draw_instances`; a cast that is not
        the latest is cast again there."""
        pixel = _pixel_angle(camera, viewport)
        self.creatures.upload(scene, np.asarray(camera.eye, dtype=np.float32), pixel)
        centre, radius = creature_bounds(scene, terrain)
        ground_level = 0.0 if terrain.flat else float(terrain.height(centre[[0, 2]]))
        light_vp, shadow_texel = light_view_proj(scene, None if terrain.flat else ground_level)
        self.bodies.upload(scene, np.asarray(camera.eye, dtype=np.float64), shadow_texel, pixel)
        index, self._next_map = self._next_map, 1 - self._next_map
        self._shadow_pass(self.shadow_maps[index][1], light_vp, options)
        self._latest = ShadowCast(scene, light_vp, shadow_texel, index, centre, radius, ground_level, options.shadow,
                                  _view_key(camera, viewport))
        return self._latest

    def draw_instances(self, scene: SceneInstances, ground: GroundView | float, camera: Camera,
                       target: moderngl.Framebuffer, options: RenderOptions,
                       viewport: tuple[int, int, int, int] | None = None, multisampled: bool | None = None,
                       overlays: Overlays | None = None, clear_target: bool = False,
                       cast: ShadowCast | None = None) -> None:
        """Draw creature instances over ``ground`` (a GroundView, or the in-place ground
        offset in metres) seen by ``camera`` into ``target`` (cleared first), with
        ``overlays`` (footprints, targets, support polygon) on the ground.
        ``multisampled``: whether ``target`` has several samples per pixel (default: from
        its colour attachments; give it for a window's framebuffer). ``clear_target``:
        clear all of ``target``, not just ``viewport`` (cheaper on a software rasteriser
        than a clear cut to a rectangle, for callers that draw over the rest anyway).
        ``cast``: this scene's shapes and shadow, issued ahead by :meth:`cast` (else, or
        if the camera or the viewport's height has changed since, they are cast here).

        Without multisampling the creatures go first, nearest shapes first, so the depth
        test rejects the ground hidden behind them before shading it (a software
        rasteriser's cost is per pixel shaded). With multisampling the ground and the sky
        go first with it off, then the creatures with it on: a software rasteriser
        (llvmpipe) shades every sample of a multisampled target, so the ground, most of
        the picture, would cost four times over for nothing (its grid lines antialias
        themselves and its far edge fades into the fog)."""
        if not isinstance(ground, GroundView):
            ground = GroundView(offset=float(ground))
        terrain = ground.terrain
        viewport = viewport or (0, 0, *target.size)
        if cast is None or cast is not self._latest or not cast.fits(scene, camera, viewport, options):
            cast = self.cast(scene, terrain, camera, viewport, options)
        aspect = viewport[2] / max(viewport[3], 1)
        centre, radius = cast.centre, cast.radius
        self._begin_main_pass(target, viewport, camera, aspect, cast, options, clear_target)
        if multisampled is None:
            multisampled = any(getattr(a, "samples", 0) > 0 for a in target.color_attachments)
        if not multisampled:
            self.bodies.draw()
            self.creatures.draw()
        self.ctx.disable_direct(GL_MULTISAMPLE)
        self.ctx.disable(moderngl.CULL_FACE)
        reach = radius * self.FOG_END * self.FLOOR_PAST_FOG
        self.ground.set_fog_and_grid(centre, radius, (self.FOG_START, self.FOG_END), ground, options)
        # An eye under a flat floor's level sees through it: the floor, its shadow and what
        # lies on it (the path, footprints) are not drawn from below.
        on_floor = not terrain.flat or camera.eye[1] > 0.0
        if terrain.flat:
            if on_floor:
                self.ground.draw_floor(scene, centre, reach, cast.texel, radius, options)
        else:
            self.ground.draw_terrain(terrain, centre, reach, options)
        if options.path and ground.path is not None and on_floor:
            self.ground.draw_path(ground, reach, radius, options)
        if overlays is not None and on_floor:
            self.ground.draw_overlays(overlays, terrain, options)
        self.ground.draw_sky(camera, aspect, centre, reach, cast.ground_level, options)
        self.ctx.enable_direct(GL_MULTISAMPLE)
        if multisampled:
            self.bodies.draw()
            self.creatures.draw()

    def _shadow_pass(self, fbo: moderngl.Framebuffer, light_vp: glm.mat4, options: RenderOptions) -> None:
        """Depth from the key light into a shadow map's ``fbo`` (cleared: no shadow when off)."""
        ctx = self.ctx
        ctx.enable(moderngl.DEPTH_TEST | moderngl.CULL_FACE)
        ctx.disable(moderngl.BLEND)
        ctx.depth_func = "<"
        fbo.use()
        fbo.clear(depth=1.0)
        if options.shadow:
            self.creatures.draw_depth(light_vp)
            self.bodies.draw_depth(light_vp)

    def _begin_main_pass(self, target: moderngl.Framebuffer, viewport: tuple[int, int, int, int], camera: Camera,
                         aspect: float, cast: ShadowCast, options: RenderOptions, clear_target: bool = False) -> None:
        """Clear ``target`` (its ``viewport``, or all of it) to the horizon colour and give
        every lit program the camera, the light and the shadow map."""
        target.use()
        target.viewport = viewport
        self.ctx.enable(moderngl.DEPTH_TEST)  # (whatever was drawn since the cast, a UI say, may have turned it off)
        self.ctx.disable(moderngl.BLEND)
        self.ctx.depth_func = "<"
        sky, horizon = srgb_to_linear(options.sky_color), srgb_to_linear(options.horizon_color)
        r, g, b = (float(c) for c in np.sqrt(horizon))
        target.clear(r, g, b, 1.0, depth=1.0, viewport=None if clear_target else viewport)  # beyond the floor: horizon
        view_proj = camera.view_proj(aspect)
        self.shadow_maps[cast.shadow_map][0].use(location=0)
        light_vp, shadow_texel = cast.light_vp, cast.texel
        set_ = self.uniforms.set
        for prog in (*self.creatures.lit_programs, self.bodies.lit, *self.ground.lit_programs):
            set_(prog, "u_view_proj", view_proj)
            set_(prog, "u_light_view_proj", light_vp)
            set_(prog, "u_light_dir", tuple(LIGHT_DIR))
            set_(prog, "u_camera_pos", tuple(camera.eye))
            set_(prog, "u_sky_color", tuple(sky))
            set_(prog, "u_bounce_color", tuple(srgb_to_linear(options.ground_color) * 0.8))
            set_(prog, "u_shadow_map", 0)
            set_(prog, "u_shadow_strength", 0.7 if options.shadow else 0.0)
            set_(prog, "u_shadow_texel", shadow_texel)

    def release(self) -> None:
        """Free every GL object this renderer made."""
        self.creatures.release()
        self.bodies.release()
        self.ground.release()
        for texture, fbo in self.shadow_maps:
            fbo.release()
            texture.release()
        self.shaders.release()
