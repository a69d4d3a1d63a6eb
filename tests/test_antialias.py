"""Antialiasing of recorded frames: FXAA over the creature's screen region, against
multisampling and against none."""

from __future__ import annotations

import numpy as np
import pytest

from app import build_rig, load_creature
from app.kinematics.clip import clip_motion
from app.kinematics.world import IN_PLACE
from app.render.camera import Camera
from app.render.clip import ClipRenderer
from app.render.framing import clip_camera, loop_grid_spacing
from app.render.fxaa import TILE, screen_region, screen_tiles, sphere_boxes
from app.render.options import RenderOptions, ViewSettings
from app.render.scene import motion_instances

SIZE = (240, 180)


def test_screen_region_covers_the_projected_box() -> None:
    camera = Camera(target=(0.0, 0.0, 0.0), azimuth=0.0, elevation=0.0, distance=5.0)
    lo, hi = np.array([-0.5, -0.5, -0.5]), np.array([0.5, 0.5, 0.5])
    x, y, w, h = screen_region(lo, hi, camera, SIZE, pad=0)
    # Centred and symmetric, well inside the image, and larger for a larger box.
    assert abs((x + w / 2) - SIZE[0] / 2) <= 1 and abs((y + h / 2) - SIZE[1] / 2) <= 1
    assert 0 < w < SIZE[0] and 0 < h < SIZE[1]
    _x2, _y2, w2, h2 = screen_region(2 * lo, 2 * hi, camera, SIZE, pad=0)
    assert w2 > w and h2 > h
    assert screen_region(lo, hi, camera, SIZE, pad=3)[2] == w + 6


def test_screen_region_is_the_whole_image_when_the_box_reaches_behind_the_eye() -> None:
    camera = Camera(target=(0.0, 0.0, 0.0), azimuth=0.0, elevation=0.0, distance=1.0)
    assert screen_region(np.full(3, -5.0), np.full(3, 5.0), camera, SIZE) == (0, 0, *SIZE)


def _tile_mask(rects: np.ndarray, size: tuple[int, int]) -> np.ndarray:
    """Image-shaped (rows top down) mask of the pixels inside ``rects`` (bottom-left origin)."""
    mask = np.zeros(size[::-1], dtype=bool)
    for x, y, w, h in rects:
        mask[size[1] - (y + h):size[1] - y, x:x + w] = True
    return mask


def test_screen_tiles_cover_every_shape_and_little_else() -> None:
    motion, _ = clip_motion(build_rig(load_creature("dog")), 25.0, cycles=1.0, world=IN_PLACE)
    camera = clip_camera(motion, ViewSettings(size=SIZE))
    scene = motion_instances(motion).frame(3)
    rects = screen_tiles(scene, camera, SIZE)
    assert rects.shape[1] == 4 and len(rects) > 3
    # Whole tiles (clipped at the image's right and top edges), inside the image.
    assert np.all(rects[:, :2] % TILE == 0)
    assert np.all((rects[:, 2] % TILE == 0) | (rects[:, 0] + rects[:, 2] == SIZE[0]))
    assert np.all((rects[:, 3] == TILE) | (rects[:, 1] + rects[:, 3] == SIZE[1]))
    assert np.all(rects[:, 0] + rects[:, 2] <= SIZE[0]) and np.all(rects[:, 1] + rects[:, 3] <= SIZE[1])
    mask = _tile_mask(rects, SIZE)
    # Every shape's screen box (its bounding spheres, padded) lies within the tiles.
    caps, ells = scene.capsules.astype(float), scene.ellipsoids.astype(float)
    centres = np.concatenate([caps[:, 0:3], caps[:, 3:6], ells[:, 0:3]])
    radii = np.concatenate([caps[:, 6], caps[:, 7], ells[:, 12:15].max(axis=1)])
    boxes = sphere_boxes(centres, radii, camera, SIZE)
    assert boxes is not None
    for x0, y0, x1, y1 in np.clip(boxes, 0, [SIZE[0] - 1, SIZE[1] - 1] * 2).astype(int):
        assert mask[SIZE[1] - 1 - y1:SIZE[1] - y0, x0:x1 + 1].all()
    # Much less than the creature's whole screen rectangle.
    _x, _y, w, h = screen_region(*scene.box(), camera, SIZE)
    assert mask.sum() < 0.75 * w * h


def test_screen_tiles_cover_a_skinned_body_drawn_alone() -> None:
    """A skinned body with no shapes beside it (no joint markers: the skin covers them)
    is covered by its joints' spheres: FXAA smoothed only the tiles of the shapes, so a
    smooth dog's outline was left jagged but for its knees and eyes."""
    from dataclasses import replace

    from app.render.bodies import motion_body, shared_body_cache

    motion, _ = clip_motion(build_rig(load_creature("dog")), 25.0, cycles=1.0, world=IN_PLACE)
    camera = clip_camera(motion, ViewSettings(size=SIZE))
    parts = motion_instances(motion).frame(3)
    skinned = replace(motion_instances(motion, show_joints=False, parts=False),
                      bodies=(motion_body(motion, shared_body_cache()),)).frame(3)
    assert len(skinned.capsules) == 0 and len(skinned.ellipsoids) == 0
    covered = _tile_mask(screen_tiles(skinned, camera, SIZE), SIZE)
    of_parts = _tile_mask(screen_tiles(parts, camera, SIZE), SIZE)
    # The body's tiles and the parts body's are nearly the same (the same creature, its
    # skin a little outside its bones; its joints' bounding spheres, each as far as its
    # farthest vertex every way, made twice as many).
    assert (covered & of_parts).sum() > 0.85 * of_parts.sum()
    assert covered.sum() < 1.25 * of_parts.sum()
    # Every vertex of the skin lies on a tile.
    body = skinned.bodies[0]
    boxes = sphere_boxes(body.surface_points(), np.zeros(len(body.body.positions)), camera, SIZE, 0.0)
    assert boxes is not None
    x, y = boxes[:, 0].astype(int), boxes[:, 1].astype(int)
    inside = (x >= 0) & (x < SIZE[0]) & (y >= 0) & (y < SIZE[1])
    assert inside.all() and covered[SIZE[1] - 1 - y, x].all()


def test_screen_tiles_are_the_whole_image_when_a_shape_is_behind_the_eye() -> None:
    motion, _ = clip_motion(build_rig(load_creature("dog")), 25.0, cycles=1.0, world=IN_PLACE)
    scene = motion_instances(motion).frame(0)
    centre = scene.capsules[0, 0:3].astype(float)
    camera = Camera(target=tuple(centre), azimuth=0.0, elevation=0.0, distance=0.01)
    assert screen_tiles(scene, camera, SIZE).tolist() == [[0, 0, *SIZE]]


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
            scene = renderer._instances(motion, options).frame(5)  # the skinned body and its features
        finally:
            renderer.release()
    outside = ~_tile_mask(screen_tiles(scene, camera, SIZE), SIZE)
    assert 0.3 * outside.size < outside.sum() < outside.size
    changed = np.abs(images["fxaa"] - images["off"]).max(axis=-1) > 0
    assert not changed[outside].any()
    assert changed.sum() > 100  # the silhouette's edge pixels were blended
    # Closer to multisampling than no antialiasing is, on the pixels where they differ.
    edges = np.abs(images["msaa"] - images["off"]).max(axis=-1) > 24
    assert edges.sum() > 100
    err_off = np.abs(images["off"] - images["msaa"])[edges].mean()
    err_fxaa = np.abs(images["fxaa"] - images["msaa"])[edges].mean()
    assert err_fxaa < 0.8 * err_off


def test_a_body_s_surface_points_are_its_vertices_skinned() -> None:
    """FXAA's tiles come from the skin's vertices skinned on the CPU: linear blend skinning,
    each vertex by its four joints' matrices, as skinned.vert does on the GL."""
    from app.render.bodies import motion_body, shared_body_cache

    motion, _ = clip_motion(build_rig(load_creature("dog")), 25.0, cycles=1.0, world=IN_PLACE)
    draw = motion_body(motion, shared_body_cache()).frame(5)
    points = draw.surface_points()
    body = draw.body
    assert points.shape == body.positions.shape
    for v in range(0, len(points), 97):
        matrix = sum(float(w) * draw.skin[j].astype(np.float64) for j, w in zip(body.joints[v], body.weights[v]))
        expected = (matrix @ np.append(body.positions[v], 1.0))[:3]
        assert np.allclose(points[v], expected, atol=1e-5), v
    # Away from the bind pose: the feet have moved from where they were bound.
    assert np.abs(points - body.positions).max() > 0.05
