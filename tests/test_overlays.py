"""Viewer overlays: support polygon, footprints, touchdown targets (geometry and pixels)."""

from __future__ import annotations

import numpy as np
import pytest

from app import build_rig, load_creature
from app.kinematics.clip import clip_motion
from app.kinematics.live import LiveMotion
from app.kinematics.overlays import (
    FootprintTrail,
    inside_polygon,
    planted_points,
    support_polygon,
    touchdown_targets,
    trunk_centre,
)
from app.kinematics.world import IN_PLACE
from app.render.camera import frame_points
from app.render.options import GroundView, RenderOptions
from app.render.overlays import TARGET_COLOR, Overlays
from app.render.renderer import SceneRenderer
from app.render.scene import motion_bounds, motion_instances
from app.render.target import OffscreenTarget


def test_support_polygon_is_the_convex_hull_in_order() -> None:
    points = np.array([[0, 0], [2, 0], [2, 1], [0, 1], [1, 0.5], [1, 0], [0.3, 0.9]], dtype=float)
    hull = support_polygon(points)
    corners = {tuple(p) for p in hull}
    assert {(0, 0), (2, 0), (2, 1), (0, 1)} <= corners
    assert (1, 0.5) not in corners and (0.3, 0.9) not in corners
    x, z = hull[:, 0], hull[:, 1]
    area = 0.5 * np.sum(x * np.roll(z, -1) - np.roll(x, -1) * z)
    assert area == pytest.approx(2.0)  # ordered (positive area), nothing crossed
    assert inside_polygon(np.array([1.0, 0.5]), hull) and inside_polygon(np.array([2.0, 0.5]), hull)
    assert not inside_polygon(np.array([2.1, 0.5]), hull) and not inside_polygon(np.array([1.0, -0.01]), hull)


def test_support_polygon_of_two_feet_or_a_line_is_a_segment_with_no_inside() -> None:
    assert support_polygon(np.array([[0.0, 0.0], [1.0, 1.0]])).shape == (2, 2)
    line = support_polygon(np.array([[0.0, 0.0], [2.0, 2.0], [1.0, 1.0]]))
    assert sorted(map(tuple, line)) == [(0.0, 0.0), (2.0, 2.0)]
    assert not inside_polygon(np.array([1.0, 1.0]), line)


def stable_fraction(gait: str) -> float:
    rig = build_rig(load_creature("dog").with_overrides({"gait.preset": gait}))
    motion, _ = clip_motion(rig, 60.0, cycles=2.0)
    stable = []
    for i in range(motion.frame_count):
        pose = motion.pose(i)
        hull = support_polygon(planted_points(pose)[:, [0, 2]])
        stable.append(inside_polygon(trunk_centre(pose)[[0, 2]], hull))
    return float(np.mean(stable))


def test_a_walk_is_statically_stable_more_often_than_a_trot() -> None:
    walk, trot = stable_fraction("walk"), stable_fraction("trot")
    assert walk > 0.3  # three feet down around the centre for much of a walk
    assert trot < 0.1  # a trot stands on diagonal pairs: a segment, no inside
    assert walk > trot + 0.25


@pytest.mark.parametrize("world", [None, IN_PLACE])
def test_footprints_are_one_per_landing_and_stay_on_the_ground(world) -> None:
    rig = build_rig(load_creature("dog"))
    motion, _ = clip_motion(rig, 60.0, cycles=3.0, world=world)
    trail = FootprintTrail(capacity=64)
    landings = 0
    for i in range(motion.frame_count):
        pose = motion.pose(i)
        trail.record(pose, float(motion.times[i]))
        if i:
            landings += int(np.sum(motion.contact[i] & ~motion.contact[i - 1]))
        else:
            landings += int(motion.contact[0].sum())
    assert trail.count == landings
    assert 3 * rig.leg_count - rig.leg_count <= landings <= 3 * rig.leg_count + rig.leg_count
    # The newest footprint of each planted foot is under that foot now.
    last = motion.pose(motion.frame_count - 1)
    points, legs, age = trail.recent(8, last.ground_offset)
    assert age[0] == 1.0 and age[-1] == 0.0 and np.all(np.diff(age) < 0)
    for leg in np.nonzero(last.contact)[0]:
        newest = points[legs == leg][-1]
        assert np.allclose(newest, last.joints[leg, 3], atol=1e-9)


def test_touchdown_targets_are_where_swinging_feet_land() -> None:
    rig = build_rig(load_creature("dog"))
    live = LiveMotion(rig)
    for _ in range(20):
        live.step(1 / 60)
    targets, legs = touchdown_targets(live)
    assert len(legs) > 0 and not live.frame_plan().contact[0][legs].any()
    # Step until each of those legs lands: it lands on its target.
    landed = {}
    for _ in range(200):
        live.step(1 / 60)
        pose = live.pose()
        for k, leg in enumerate(legs):
            if leg not in landed and pose.contact[leg]:
                landed[leg] = (pose.joints[leg, 3], targets[k])
    assert set(landed) == set(legs.tolist())
    for ball, target in landed.values():
        assert np.allclose(ball[[0, 2]], target[[0, 2]], atol=1e-6)


@pytest.mark.gl
def test_overlays_draw_on_the_ground(gl_ctx) -> None:
    rig = build_rig(load_creature("dog"))
    motion, _ = clip_motion(rig, 30.0, cycles=1.0, world=IN_PLACE)
    scene = motion_instances(motion).frame(0)
    camera = frame_points(motion_bounds(motion), "top", aspect=1.0)
    renderer = SceneRenderer(gl_ctx)
    target = OffscreenTarget(gl_ctx, (160, 160))
    try:
        def draw(overlays):
            renderer.draw_instances(scene, GroundView(), camera, target.fbo, RenderOptions(shadow=False),
                                    overlays=overlays)
            return target.read().astype(float)

        plain = draw(None)
        pose = motion.pose(0)
        targets = np.array([[0.0, 0.0, 0.9], [0.2, 0.0, -0.9]])  # in front of and behind the dog
        hull = support_polygon(planted_points(pose)[:, [0, 2]])
        marked = draw(Overlays(size=0.06, targets=targets, support=hull, centre=trunk_centre(pose)[[0, 2]]))
        changed = np.abs(marked - plain).max(axis=-1) > 30
        assert changed.sum() > 20
        amber = np.sqrt(TARGET_COLOR) * 255
        close = np.abs(marked - amber).max(axis=-1) < 60
        assert close.sum() >= 4  # the targets' rings
    finally:
        target.release()
        renderer.release()


@pytest.mark.gl
@pytest.mark.parametrize("creature", ["centipede", "ant", "dog"])
def test_the_path_ribbon_lies_under_the_creature_and_is_its_size(gl_ctx, creature: str) -> None:
    """The path drawn on a circle never covers the creature (every pixel of it that shows
    without the path shows with it) and is a line of the walker's own size, however big
    the scene around it: a horse far off in the same frame leaves it as it was (the
    ribbon once grew with the scene's bounds and, near a small creature, filled the view)."""
    from app.kinematics.path import StraightPath
    from app.kinematics.world import World
    from app.render.clip import ClipRenderer
    from app.render.framing import clip_camera
    from app.render.options import ViewSettings
    from app.worlds import make_world

    rig = build_rig(load_creature(creature))
    motion, _ = clip_motion(rig, 25.0, cycles=1.0, world=make_world(f"circle:r={2 * rig.body_length:.3f}", "flat"))
    horse, _ = clip_motion(build_rig(load_creature("horse")), 25.0, cycles=1.0,
                           world=World(path=StraightPath(start=(6.0, 0.0))))
    camera = clip_camera(motion, ViewSettings(size=(320, 240), camera="three-quarter"))
    renderer = ClipRenderer((320, 240), "off", ctx=gl_ctx)
    frame = motion.frame_count // 2
    changed = {}
    try:
        for name, motions in (("alone", [motion]), ("scene", [motion, horse])):
            without = renderer.frame(motions, frame, camera, RenderOptions(path=False)).astype(np.int16)
            with_path = renderer.frame(motions, frame, camera, RenderOptions(path=True)).astype(np.int16)
            changed[name] = np.abs(with_path - without).max(axis=-1) > 24
            if name == "alone":
                bare = without
    finally:
        renderer.release()
    alone, scene = int(changed["alone"].sum()), int(changed["scene"].sum())
    assert alone > 50  # the path is drawn
    assert abs(scene - alone) < 0.3 * alone, (alone, scene)  # the walker's size, not the scene's
    # Where the creature is (shades of its colours: coat, feet, a centipede's membranes),
    # the path changes nothing.
    from app.render.scene import MEMBRANE_SHADE, palette

    colors = palette(rig)
    creature_pixels = np.zeros(bare.shape[:2], dtype=bool)
    for linear in (colors.coat, colors.legs, MEMBRANE_SHADE * colors.coat):
        shade = np.sqrt(linear) * 255
        scale = (bare @ shade) / (shade @ shade)
        creature_pixels |= np.abs(bare - scale[..., None] * shade).max(axis=-1) < 14
    assert creature_pixels.sum() > 200
    assert (changed["alone"] & creature_pixels).sum() <= 0.002 * creature_pixels.sum() + 2
    assert alone < 0.12 * creature_pixels.sum()  # a line beside the creature, not a band
