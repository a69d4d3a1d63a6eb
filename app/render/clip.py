"""Rendering a clip frame by frame, headless: the one path every recording takes.

``gaitlab render`` and the viewer's Record panel both go through :class:`ClipRenderer`,
so the same settings give the same pixels.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import replace

import moderngl
import numpy as np
from numpy.typing import NDArray

from ..choices import ANTIALIAS_MODES, DEFAULT_ANTIALIAS, Antialias
from ..kinematics.motion import Motion
from .bodies import motion_body
from .camera import Camera
from .context import shared_headless_context
from .fxaa import screen_tiles
from .options import GroundView, RenderOptions, path_half_width
from .renderer import SceneRenderer
from .scene import SceneInstances, frame_instances, motion_instances
from .target import OffscreenTarget


class ClipRenderer:
    """Headless renderer of clips, in the given context or the process's shared EGL one
    (never released here). ``antialias`` and ``samples`` as in :class:`~app.render.options.ViewSettings`."""

    def __init__(self, size: tuple[int, int], antialias: Antialias = DEFAULT_ANTIALIAS, samples: int = 4,
                 ctx: moderngl.Context | None = None) -> None:
        if antialias not in ANTIALIAS_MODES:
            raise ValueError(f"antialias {antialias!r}: choose one of {', '.join(ANTIALIAS_MODES)}")
        self.ctx = ctx or shared_headless_context()
        self.scene = SceneRenderer(self.ctx, soft_self_shadow=True)
        self.target = OffscreenTarget(self.ctx, size, samples=samples if antialias == "msaa" else 0,
                                      fxaa=antialias == "fxaa", shaders=self.scene.shaders)
        self._cache: dict[int, tuple[Motion, tuple, SceneInstances]] = {}

    def _instances(self, motion: Motion, options: RenderOptions) -> SceneInstances:
        """Every frame's instances of a clip (and its skinned body through every frame),
        built in one vectorised pass and kept."""
        key = (options.joints, options.body, options.side_colors)
        cached = self._cache.get(id(motion))
        if cached is None or cached[0] is not motion or cached[1] != key:
            skin = options.body == "skin"
            shapes = motion_instances(motion, show_joints=options.joint_markers, parts=not skin, by_side=options.side_colors)
            if skin:
                shapes = replace(shapes, bodies=(motion_body(motion, self.scene.body_cache),))
            cached = self._cache[id(motion)] = (motion, key, shapes)
        return cached[2]

    def frame(self, motions: Motion | Sequence[Motion], index: int, camera: Camera, options: RenderOptions,
              extra: SceneInstances | Sequence[SceneInstances] | None = None) -> NDArray[np.uint8]:
        """Frame ``index`` of one clip or of several (a scene's creatures, over the first
        one's ground) and ``extra`` shapes (herds, arcs), as (H, W, 3) uint8."""
        motions = [motions] if isinstance(motions, Motion) else list(motions)
        extras = [] if extra is None else [extra] if isinstance(extra, SceneInstances) else list(extra)
        if len(self._cache) > 4 * len(motions):  # a new clip: forget the old ones
            self._cache = {k: v for k, v in self._cache.items() if any(v[0] is m for m in motions)}
        scene = frame_instances([self._instances(m, options).frame(index) for m in motions] + extras)
        lead = motions[0]
        ground = GroundView(terrain=lead.terrain, offset=float(lead.ground_offset[index]),
                            path=None if lead.in_place else lead.path, travel=float(lead.travel[index]),
                            path_width=path_half_width(lead.rig.hip_height, lead.rig.body_length))
        self.scene.draw_instances(scene, ground, camera, self.target.fbo, options)
        tiles = screen_tiles(scene, camera, self.target.size) if self.target.fxaa else None
        return self.target.read(tiles)

    def release(self) -> None:
        self.target.release()
        self.scene.release()

    def __enter__(self) -> ClipRenderer:
        return self

    def __exit__(self, *exc: object) -> None:
        self.release()
