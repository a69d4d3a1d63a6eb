"""Antialiasing of recorded frames: FXAA over the creature's screen region, against
multisampling and against none."""

from __future__ import annotations

import numpy as np
import pytest

from app import build_rig, load_creature
from app.kinematics.clip import clip_motion
from app.kinematics.world import IN_PLACE
from app.render.camera import Camera
from app.render.clip import ClipRenderer, ViewSettings, clip_camera, loop_grid_spacing
from app.render.fxaa import screen_region
from app.render.renderer import RenderOptions
from app.render.scene import motion_instances

SIZE = (240, 180)


def test_screen_region_covers_the_projected_box() -> None:
    camera = Camera(target=(0.0, 0.0, 0.0), azimuth=0.0, elevation=0.0, distance=5.0)
    lo, hi = np.array([-0.5, -0.5, -0.5]), np.array([0.5, 0.5, 0.5])
    x, y, w, h = screen_region(lo, hi, camera, SIZE, pad=0)
    # Centred and symmetric, well inside the image, and larger for a larger box.
    assert abs((x + w / 2) - SIZE[0] / 2) <= 1 and abs((y + h / 2) - SIZE[1] / 2) <= 1
    assert 0 < w < SIZE[0] and 0 < h < SIZE[1]
    x2, y2, w2, h2 = screen_region(2 * lo, 2 * hi, camera, SIZE, pad=0)
    assert w2 > w and h2 > h
    assert screen_region(lo, hi, camera, SIZE, pad=3)[2] == w + 6


def test_screen_region_is_the_whole_image_when_the_box_reaches_behind_the_eye() -> None:
    camera = Camera(target=(0.0, 0.0, 0.0), azimuth=0.0, elevation=0.0, distance=1.0)
    assert screen_region(np.full(3, -5.0), np.full(3, 5.0), camera, SIZE) == (0, 0, *SIZE)


@pytest.mark.gl
def test_fxaa_smooths_the_creature_and_leaves_the_rest_alone(gl_ctx) -> None:
    motion, cycles = clip_motion(build_rig(load_creature("dog")), 25.0, cycles=1.0, world=IN_PLACE)
    options = RenderOptions(grid_spacing=loop_grid_spacing(motion, cycles))
    camera = clip_camera(motion, ViewSettings(size=SIZE))
    images = {}
    for mode in ("off", "fxaa", "msaa"):
        renderer = ClipRenderer(SIZE, mode, ctx=gl_ctx)
        try:
            images[mode] = renderer.frame(motion, 5, camera, options).astype(np.int16)
        finally:
            renderer.release()
    scene = motion_instances(motion).frame(5)
    x, y, w, h = screen_region(*scene.box(), camera, SIZE)
    assert 0 < w * h < 0.8 * SIZE[0] * SIZE[1]
    outside = np.ones(SIZE[::-1], dtype=bool)
    outside[SIZE[1] - (y + h):SIZE[1] - y, x:x + w] = False  # image rows run top down
    changed = np.abs(images["fxaa"] - images["off"]).max(axis=-1) > 0
    assert not changed[outside].any()
    assert changed.sum() > 100  # the silhouette's edge pixels were blended
    # Closer to multisampling than no antialiasing is, on the pixels where they differ.
    edges = np.abs(images["msaa"] - images["off"]).max(axis=-1) > 24
    assert edges.sum() > 100
    err_off = np.abs(images["off"] - images["msaa"])[edges].mean()
    err_fxaa = np.abs(images["fxaa"] - images["msaa"])[edges].mean()
    assert err_fxaa < 0.8 * err_off
