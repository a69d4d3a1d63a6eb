"""Rendering a motion clip frame by frame, headless: the one path every recording takes.

``gaitlab render`` and the viewer's Record panel both go through :class:`ClipRenderer`,
so the same settings give the same pixels.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Iterator

import moderngl
import numpy as np
from numpy.typing import NDArray

from ..kinematics.motion import Motion
from .camera import DEFAULT_CAMERA, Camera, CameraPreset, frame_points
from .context import create_headless_context
from .renderer import RenderOptions, SceneRenderer, nice_grid_spacing
from .scene import SceneInstances, motion_bounds, motion_instances
from .target import OffscreenTarget


@dataclass(frozen=True)
class ViewSettings:
    """How a clip is filmed: image size (pixels), camera preset, multisampling, options."""

    size: tuple[int, int] = (480, 360)
    camera: CameraPreset = DEFAULT_CAMERA
    samples: int = 4
    options: RenderOptions = field(default_factory=RenderOptions)


def clip_camera(motion: Motion, view: ViewSettings) -> Camera:
    """The preset camera framing the creature over the whole clip (no jitter)."""
    w, h = view.size
    return frame_points(motion_bounds(motion), view.camera, aspect=w / h)


def loop_grid_spacing(motion: Motion, cycles: float | None) -> float:
    """A round grid spacing for the creature's size; for a clip of whole cycles it is
    nudged so the ground has moved a whole number of major squares (5 lines) by the end,
    which makes the loop seamless."""
    spacing = nice_grid_spacing(motion.rig.hip_height * 1.6)
    travel = float(motion.ground_offset[-1] - motion.ground_offset[0]) + (
        float(motion.ground_offset[1] - motion.ground_offset[0]) if motion.frame_count > 1 else 0.0)
    if cycles and travel > 0:
        majors = max(1, round(travel / (5.0 * spacing)))
        spacing = travel / (5.0 * majors)
    return spacing


class ClipRenderer:
    """Headless renderer of clips; owns an EGL context unless given one."""

    def __init__(self, size: tuple[int, int], samples: int = 4, ctx: moderngl.Context | None = None) -> None:
        self._owns_ctx = ctx is None
        self.ctx = ctx or create_headless_context()
        self.scene = SceneRenderer(self.ctx)
        self.target = OffscreenTarget(self.ctx, size, samples)
        self._cache: tuple[Motion, bool, SceneInstances] | None = None

    def _instances(self, motion: Motion, joints: bool) -> SceneInstances:
        """Every frame's instances, built in one vectorised pass and kept for the clip."""
        if self._cache is None or self._cache[0] is not motion or self._cache[1] != joints:
            self._cache = (motion, joints, motion_instances(motion, show_joints=joints))
        return self._cache[2]

    def frame(self, motion: Motion, index: int, camera: Camera, options: RenderOptions) -> NDArray[np.uint8]:
        """Frame ``index`` of ``motion`` as (H, W, 3) uint8."""
        scene = self._instances(motion, options.joints).frame(index)
        self.scene.draw_instances(scene, float(motion.ground_offset[index]), camera, self.target.fbo, options)
        return self.target.read()

    def frames(self, motion: Motion, camera: Camera, options: RenderOptions) -> Iterator[NDArray[np.uint8]]:
        for index in range(motion.frame_count):
            yield self.frame(motion, index, camera, options)

    def release(self) -> None:
        self.target.release()
        self.scene.release()
        if self._owns_ctx:
            self.ctx.release()

    def __enter__(self) -> "ClipRenderer":
        return self

    def __exit__(self, *exc) -> None:
        self.release()
