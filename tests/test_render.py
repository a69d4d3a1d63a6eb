"""Headless rendering: golden images of the three leg types, every creature x gait,
determinism, framing. All at small sizes with MSAA off."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from app import build_rig, load_creature
from app.gaits import gaits_for
from app.kinematics.clip import clip_motion
from app.kinematics.motion import simulate
from app.kinematics.world import IN_PLACE
from app.render.camera import Camera, frame_points
from app.render.clip import ClipRenderer
from app.render.framing import clip_camera, loop_grid_spacing
from app.render.lighting import SKY_FADE, sky_band
from app.render.options import GroundView, RenderOptions, ViewSettings
from app.render.scene import motion_bounds, motion_instances, srgb_to_linear
from app.spec import SpecError

pytestmark = pytest.mark.gl
SIZE = (192, 144)


@pytest.fixture(scope="module")
def renderer(gl_ctx):
    r = ClipRenderer(SIZE, antialias="off", ctx=gl_ctx)
    yield r
    r.release()


def render(renderer, creature: str, gait: str | None = None, frame: int = 4, camera: str = "side",
           **options) -> np.ndarray:
    spec = load_creature(creature)
    if gait:
        spec = spec.with_overrides({"gait.preset": gait})
    motion, cycles = clip_motion(build_rig(spec), 25.0, cycles=1.0, world=IN_PLACE)
    view = ViewSettings(size=SIZE, camera=camera, antialias="off")
    settings = RenderOptions(grid_spacing=loop_grid_spacing(motion, cycles), **options)
    return renderer.frame(motion, frame % motion.frame_count, clip_camera(motion, view), settings)


@pytest.mark.parametrize("creature", ["bear", "dog", "horse", "bird"])  # plantigrade, digitigrade, unguligrade; a bird
def test_leg_types_golden_side_view(renderer, snapshot, creature: str) -> None:
    snapshot.check(f"{creature}_side", render(renderer, creature))


def test_three_quarter_golden(renderer, snapshot) -> None:
    snapshot.check("dog_three_quarter_trot", render(renderer, "dog", "trot", camera="three-quarter"))


def body_pixels(image: np.ndarray, hex_color: str, tolerance: int = 60) -> int:
    """Pixels whose hue is close to a creature colour (shading only scales brightness)."""
    rgb = np.sqrt(srgb_to_linear(hex_color)) * 255
    img = image.astype(np.float64)
    scale = (img @ rgb) / max(rgb @ rgb, 1e-9)
    return int((np.abs(img - scale[..., None] * rgb).max(axis=-1) < tolerance / 4).sum())


def nearest_colour_pixels(image: np.ndarray, colours: list[str]) -> np.ndarray:
    """How many pixels (one count per colour) are nearest in chromaticity (r, g, b shares,
    so shading aside) to each of ``colours``, among pixels within 0.06 of one of them."""
    img = image.reshape(-1, 3).astype(np.float64) + 1.0
    chroma = img / img.sum(axis=1, keepdims=True)
    refs = np.array([np.sqrt(srgb_to_linear(c)) + 1 / 255 for c in colours])
    refs = refs / refs.sum(axis=1, keepdims=True)
    distance = np.linalg.norm(chroma[:, None] - refs[None], axis=-1)
    near = distance.min(axis=1) < 0.06
    return np.bincount(distance.argmin(axis=1)[near], minlength=len(colours))


@pytest.mark.parametrize("gait", gaits_for(2))
@pytest.mark.parametrize("creature", ["bear", "cat", "deer", "dog", "horse"])
def test_every_creature_renders_every_gait(renderer, creature: str, gait: str) -> None:
    """In its coat, with no legs coloured by side by default; the side colours come back
    with the option (and the parts)."""
    image = render(renderer, creature, gait, frame=3, camera="three-quarter")
    assert image.shape == (SIZE[1], SIZE[0], 3) and image.dtype == np.uint8
    look = load_creature(creature).look
    colours = [look.body_color, look.left_color, look.right_color]
    coat, left, right = nearest_colour_pixels(image, colours)
    assert coat > 150 and left + right < 0.02 * coat
    sides = render(renderer, creature, gait, frame=3, camera="three-quarter", body="parts", side_colors=True)
    _, left, right = nearest_colour_pixels(sides, colours)
    assert left > 20 and right > 20  # both sides' legs are visible


def test_same_frame_twice_gives_identical_pixels(renderer) -> None:
    a = render(renderer, "dog", "gallop", frame=7, camera="three-quarter")
    b = render(renderer, "dog", "gallop", frame=7, camera="three-quarter")
    assert np.array_equal(a, b)


def test_a_shadow_cast_ahead_draws_the_same_frame(gl_ctx) -> None:
    """A viewer casts the next frame's shapes and shadow while the GL still draws this one:
    the frame drawn from that cast is the frame drawn in one go; the two shadow maps take
    turns; a cast overtaken by a later one (whose shapes are now the ones uploaded), or
    made for a camera that has moved since, is cast again rather than drawn with another
    frame's shapes or levels of detail."""
    from dataclasses import replace

    import moderngl

    from app.render.bodies import motion_body
    from app.render.options import GroundView
    from app.render.renderer import SceneRenderer
    from app.render.scene import motion_instances
    from app.render.target import OffscreenTarget

    motion, _ = clip_motion(build_rig(load_creature("dog")), 25.0, cycles=1.0, world=IN_PLACE)
    renderer, target = SceneRenderer(gl_ctx), OffscreenTarget(gl_ctx, SIZE)
    frames = replace(motion_instances(motion, parts=False), bodies=(motion_body(motion, renderer.body_cache),))
    first, later = frames.frame(0), frames.frame(9)
    camera = frame_points(motion_bounds(motion), "three-quarter", aspect=SIZE[0] / SIZE[1])
    options = RenderOptions()
    viewport = (0, 0, *SIZE)
    try:
        def draw(scene, cast=None, seen_by=camera) -> np.ndarray:
            renderer.draw_instances(scene, GroundView(), seen_by, target.fbo, options, cast=cast)
            return target.read().astype(int)

        renderer.draw_instances(first, GroundView(), camera, target.fbo, RenderOptions(shadow=False))
        unshadowed = target.read().astype(int)
        whole = draw(first)
        assert (np.abs(whole - unshadowed).max(axis=-1) > 20).sum() > 100  # (its shadow is in the picture)
        ahead = renderer.cast(first, GroundView().terrain, camera, viewport, options)
        gl_ctx.disable(moderngl.DEPTH_TEST | moderngl.CULL_FACE)  # a UI drawn in between, say
        gl_ctx.enable(moderngl.BLEND)
        assert np.array_equal(draw(first, ahead), whole)
        one = renderer.cast(first, GroundView().terrain, camera, viewport, options)
        two = renderer.cast(later, GroundView().terrain, camera, viewport, options)
        assert {one.shadow_map, two.shadow_map} == {0, 1}
        assert np.array_equal(draw(first, one), whole)  # overtaken: cast again
        assert not np.array_equal(draw(later, two), whole)
        # The camera moved away between the cast and the draw (a zoom, a key): the far
        # stand-in body is drawn, as a frame drawn in one go would.
        away = replace(camera, distance=camera.distance * 12.0)
        fresh = draw(first, seen_by=away)
        near = renderer.cast(first, GroundView().terrain, camera, viewport, options)
        assert np.array_equal(draw(first, near, seen_by=away), fresh)
    finally:
        target.release()
        renderer.release()


@pytest.mark.parametrize("beyond", [1.2, 1.35])
def test_an_eye_just_below_the_floor_beyond_its_edge_sees_the_creature_and_the_sky(renderer, beyond) -> None:
    """Orbited down to -5 degrees and zoomed out, the eye sinks below the floor's level just
    beyond the floor's round edge (``beyond`` times its radius from the creatures' centre,
    at a diagonal): it sees the dog and the sky over the edge, with no floor overhead (a
    square floor's corner reached over such an eye at a diagonal and blanked the view; an
    eye below the floor's level no longer draws the floor at all, so this guards that rule
    at the floor's edge as well)."""
    from dataclasses import replace

    from app.render.options import GroundView
    from app.render.renderer import SceneRenderer, creature_bounds

    motion, _ = clip_motion(build_rig(load_creature("dog")), 25.0, cycles=1.0, world=IN_PLACE)
    scene = renderer._instances(motion, RenderOptions()).frame(4)
    centre, radius = creature_bounds(scene, GroundView().terrain)
    reach = radius * SceneRenderer.FOG_END * SceneRenderer.FLOOR_PAST_FOG  # the floor disc's radius
    base = frame_points(motion_bounds(motion), "three-quarter", aspect=SIZE[0] / SIZE[1])
    distances = np.linspace(1.0, 12.0, 2000)
    away = [np.hypot(*(np.asarray(replace(base, elevation=-5.0, azimuth=45.0, distance=d).eye)[[0, 2]]
                       - centre[[0, 2]])) for d in distances]
    assert np.max(away) > beyond * reach
    camera = replace(base, elevation=-5.0, azimuth=45.0,
                     distance=float(distances[np.argmax(np.array(away) > beyond * reach)]))
    assert camera.eye[1] < 0.0
    image = renderer.frame(motion, 4, camera, RenderOptions()).astype(int)
    dog = ((image[..., 0] - image[..., 2]) > 50).sum()  # orange-brown
    sky = ((image[..., 2] - image[..., 0]) > 8).sum()  # bluish
    assert dog > 100 and sky > 0.25 * image.shape[0] * image.shape[1], (dog, sky)


def test_the_creatures_bounds_count_a_skinned_body_drawn_without_joint_markers(renderer) -> None:
    """The fog and the floor are centred on the creatures' bounds: without joint markers (a
    skinned body draws none) a skinned dog's bounds came from its eyes and nose alone
    (centred near its head); now they match the bounds with the markers."""
    from app.render.renderer import creature_bounds

    motion, _ = clip_motion(build_rig(load_creature("dog")), 25.0, cycles=1.0, world=IN_PLACE)
    flat = GroundView().terrain
    bare_scene = renderer._instances(motion, RenderOptions()).frame(4)
    assert len(bare_scene.ellipsoids) == 0  # no markers over a skinned body
    markers = motion_instances(motion, show_joints=True, parts=False).frame(4)
    with_joints = creature_bounds(replace(markers, bodies=bare_scene.bodies), flat)
    bare = creature_bounds(bare_scene, flat)
    hip, shoulder = motion.joints[4, 2:, 0].mean(axis=0), motion.joints[4, :2, 0].mean(axis=0)
    assert abs(bare[0][2] - 0.5 * (hip + shoulder)[2]) < 0.15  # between the girdles, not at the head
    assert np.allclose(bare[0], with_joints[0], atol=0.05) and abs(bare[1] - with_joints[1]) < 0.05


def test_an_eye_below_the_floor_sees_through_it(renderer) -> None:
    """An eye orbited under the floor's level, inside the floor's disc, sees the dog from
    below against the sky, not the floor's underside painted as its top (which hid all
    but its feet)."""
    from dataclasses import replace

    motion, _ = clip_motion(build_rig(load_creature("dog")), 25.0, cycles=1.0, world=IN_PLACE)
    base = frame_points(motion_bounds(motion), "three-quarter", aspect=SIZE[0] / SIZE[1])
    camera = replace(base, elevation=-10.0, azimuth=45.0, distance=3.0)
    assert camera.eye[1] < 0.0
    image = renderer.frame(motion, 4, camera, RenderOptions()).astype(int)
    dog = ((image[..., 0] - image[..., 2]) > 50).sum()  # orange-brown (its hooves alone, under a drawn floor)
    sky = ((image[..., 2] - image[..., 0]) > 8).sum()  # bluish (none, under a drawn floor)
    assert dog > 400 and sky > 0.25 * image.shape[0] * image.shape[1], (dog, sky)
    # Nor is what lies on the floor drawn from below: a turning path's ribbon floated in the air.
    from app.worlds.text import make_world

    turning, _ = clip_motion(build_rig(load_creature("dog")), 25.0, cycles=1.0, world=make_world("circle:r=2"))
    base = frame_points(motion_bounds(turning), "three-quarter", aspect=SIZE[0] / SIZE[1])
    blue = []
    for elevation in (10.0, -10.0):
        image = renderer.frame(turning, 4, replace(base, elevation=elevation, azimuth=45.0, distance=3.0),
                               RenderOptions(path=True)).astype(int)
        blue.append(int(((image[..., 2] - image[..., 0]) > 40).sum()))
    assert blue[0] > 50 and blue[1] == 0, blue


def test_frames_differ_as_the_creature_walks(renderer) -> None:
    a = render(renderer, "dog", frame=0)
    b = render(renderer, "dog", frame=8)
    assert (np.abs(a.astype(int) - b.astype(int)).max(axis=-1) > 30).mean() > 0.01


def test_legs_of_the_two_sides_are_distinguishable() -> None:
    look = load_creature("dog").look
    left, right = srgb_to_linear(look.left_color), srgb_to_linear(look.right_color)
    assert np.abs(left - right).max() > 0.2


@pytest.mark.parametrize("camera", ["side", "front", "top", "three-quarter", "chase"])
def test_camera_presets_keep_the_creature_in_frame(camera: str) -> None:
    from app.render.scene import creature_points

    motion, _ = clip_motion(build_rig(load_creature("horse")), 25.0, cycles=1.0)
    cam = frame_points(motion_bounds(motion), camera, aspect=4 / 3)
    vp = np.array(cam.view_proj(4 / 3))
    points = creature_points(motion).reshape(-1, 3)  # joints, head, neck, tail, trunk
    pts = np.c_[points, np.ones(len(points))] @ vp.T
    ndc = pts[:, :3] / pts[:, 3:]
    assert np.all(np.abs(ndc[:, :2]) <= 1.0)
    assert np.abs(ndc[:, :2]).max() > 0.6  # and fills the frame reasonably


@pytest.mark.parametrize("camera", ["follow", "chase", "side"])
def test_travelling_cameras_keep_the_creature_in_frame_and_chase_stays_behind(camera: str) -> None:
    from app.kinematics.world import World
    from app.render.framing import clip_cameras
    from app.render.options import ViewSettings
    from app.render.scene import creature_points
    from app.worlds import parse_path

    rig = build_rig(load_creature("dog"))
    world = World(path=parse_path(f"figure-eight:r={2 * rig.body_length:.3f}"))
    motion, _ = clip_motion(rig, 25.0, seconds=8.0, world=world)
    cameras = clip_cameras(motion, ViewSettings(size=(480, 360), camera=camera))
    points = creature_points(motion)
    root = motion.root[:, :3, 3]
    _, tangents = motion.path.sample(motion.travel)
    for i, cam in enumerate(cameras):
        vp = np.array(cam.view_proj(480 / 360))
        clip = np.c_[points[i], np.ones(len(points[i]))] @ vp.T
        ndc = clip[:, :2] / clip[:, 3:]
        assert np.all(np.abs(ndc) <= 1.0), (camera, i)
        if camera == "chase":  # behind the body, looking the way it goes
            behind = (np.asarray(cam.eye) - root[i])[[0, 2]] @ tangents[i]
            assert behind < -0.5 * rig.body_length, i
    if camera == "chase":  # smooth: no jumps of the eye between frames
        eyes = np.array([c.eye for c in cameras])
        steps = np.linalg.norm(np.diff(eyes, axis=0), axis=1)
        assert steps.max() < 3.0 * np.median(steps) + 1e-3


def test_legs_have_volume_and_feet_by_leg_type() -> None:
    """Issue 8, looks: thighs thick at the top, paws, hooves and soles by leg type; sprawled
    legs (insects, spiders) stay plain."""
    from app.render.scene import HOOF_COLOR, pose_instances

    def shapes(name: str):
        rig = build_rig(load_creature(name))
        motion, _ = clip_motion(rig, 25.0, cycles=1.0, world=IN_PLACE)
        return rig, motion.pose(0), pose_instances(motion.pose(0), rig, show_joints=False)

    for name in ("dog", "horse", "bear", "ant"):
        rig, pose, scene = shapes(name)
        caps = scene.capsules.astype(float)
        hoofs = np.all(np.abs(caps[:, 8:11] - HOOF_COLOR) < 1e-6, axis=1)
        toes = pose.joints[:, 4]
        near_toe = lambda centres, toes=toes: np.linalg.norm(centres[:, None] - toes[None], axis=-1).min(axis=0)
        if name == "horse":  # a dark hoof at every toe
            assert hoofs.sum() == rig.leg_count
            assert near_toe(caps[hoofs, 3:6]).max() < 1e-6
        else:
            assert not hoofs.any()
        # Each mammal leg's thickest capsule is at its top, thicker than the bone.
        hips = pose.joints[:, 0]
        thick = caps[:, 6] > 1.4 * rig.bone_radius.max()
        if name == "ant":
            assert not np.any(np.linalg.norm(caps[thick, 0:3][:, None] - hips[None], axis=-1).min(axis=1)
                              < 0.2 * rig.femur.max())
        else:
            starts = caps[thick, 0:3]
            d_hip = np.linalg.norm(starts[:, None] - hips[None], axis=-1).min(axis=0)
            assert (d_hip < 0.2 * rig.femur.max()).sum() >= rig.leg_count  # one per leg, at its hip
        ells = scene.ellipsoids.astype(float)
        feet = near_toe(ells[:, 0:3]) < rig.toe + 0.6 * rig.metatarsus + 0.02  # (a sole spans the foot)
        if name in ("dog", "bear", "horse"):
            assert feet.all()  # a paw, sole or fetlock by every toe


def test_human_golden_side_view(renderer, snapshot) -> None:
    """The upright biped: heel strike of the left foot, the right arm forward."""
    snapshot.check("human_side", render(renderer, "human", frame=0))


def test_poses_sheet_golden(snapshot) -> None:
    from app.sheet import pose_sheet

    sheet = pose_sheet(load_creature("human"), size=(120, 150))
    assert sheet.names == ("contact", "down", "pass", "up", "contact")
    snapshot.check("human_poses_sheet", sheet.image)


def test_no_sky_band_when_the_top_of_the_view_looks_below_the_horizon() -> None:
    """Looking down by more than half the field of view, nothing above the horizon is in
    view: beyond the floor lies only the horizon colour the frame is cleared to, so no
    band is drawn (it cost ~0.7 ms a frame on llvmpipe for nothing). Looking down by less,
    the band rises from the floor's far edge to the top, bottom to top."""
    centre = np.array([0.0, 0.3, 0.0])
    for elevation in (16.0, 20.0, 45.0):  # the view's top looks 1, 5 and 30 degrees down
        assert sky_band(Camera(elevation=elevation, fov=30.0), 1.5, centre, 3.0) is None
    band = sky_band(Camera(elevation=10.0, fov=30.0), 1.5, centre, 3.0)  # the top looks 5 degrees up
    assert band is not None
    assert band[-1, 0] == pytest.approx(1.0) and np.all(np.diff(band[:, 0]) > 0)
    assert band[0, 1] == 0.0 and band[-1, 1] == pytest.approx(np.sin(np.radians(5.0)), abs=1e-3)
    assert band[-1, 1] < SKY_FADE


def test_offline_renders_soften_the_creature_s_shadow_on_itself() -> None:
    """The clip renderer compiles its shaders with SOFT_SELF_SHADOW (four taps, as the
    ground's shadow: one stepped the edge of a head's shadow on the shoulder into a comb);
    the window's renderer does not (each tap costs a software rasteriser)."""
    from app.render.shaders import shader_source, with_defines

    source = with_defines(shader_source("lit.frag"), ("SOFT_SELF_SHADOW",))
    assert source.splitlines()[:2] == ["#version 330 core", "#define SOFT_SELF_SHADOW"]
    assert "light_visibility_soft(v_shadow)" in source.split("#else")[0]
    clip = ClipRenderer((64, 48))
    assert clip.scene.shaders.defines == ("SOFT_SELF_SHADOW",)


def test_an_arthropod_s_antennae_reach_forward_from_an_elbow() -> None:
    """An ant's antennae (``body.ear_length``) rise from the head, bend at an elbow and
    reach forward, as an insect's do (they stood straight up like a mammal's ears); a
    dog's ears still stand up."""
    from app.render.scene import ANTENNA_SCAPE, Cap, motion_instances

    for name, forward_at_least in (("ant", 0.6), ("dog", None)):
        rig = build_rig(load_creature(name))
        motion, _ = clip_motion(rig, 30.0, cycles=0.25)
        caps = np.asarray(motion_instances(motion, show_joints=False).frame(0).capsules, np.float64)
        head_dir = motion.head[0, 1] - motion.head[0, 0]
        head_dir /= np.linalg.norm(head_dir)
        length = rig.body.ear_length
        segment = np.linalg.norm(caps[:, Cap.B] - caps[:, Cap.A], axis=1)
        if forward_at_least is None:  # a mammal's ear: one piece, mostly up
            ears = caps[np.abs(segment - length) < 1e-6]
            assert len(ears) == 2 and np.all((ears[:, Cap.B] - ears[:, Cap.A])[:, 1] > 0.5 * length)
            continue
        flagella = caps[np.abs(segment - (1.0 - ANTENNA_SCAPE) * length) < 1e-6]
        assert len(flagella) == 2
        reach = (flagella[:, Cap.B] - flagella[:, Cap.A]) @ head_dir / ((1.0 - ANTENNA_SCAPE) * length)
        assert np.all(reach > forward_at_least)


def test_a_mammal_s_lower_leg_has_its_muscle() -> None:
    """Below the knee a forearm (gaskin, calf) muscle, thicker than the bone, tapering into
    the tendons over the first SHANK_MUSCLE of the lower leg (the bare bone was a stick);
    sprawled arthropod legs have none."""
    from app.render.scene import SHANK_MUSCLE, leg_instances

    for name, expected in (("horse", 4), ("human", 2), ("spider", 0)):
        rig = build_rig(load_creature(name))
        motion, _ = clip_motion(rig, 30.0, cycles=0.25)
        caps = np.asarray(leg_instances(motion.joints[:1], rig, show_joints=False).capsules[0], np.float64)
        knee, ankle = motion.joints[0, :, 1], motion.joints[0, :, 2]
        ends = knee + SHANK_MUSCLE * (ankle - knee)
        found = [np.flatnonzero(np.linalg.norm(caps[:, 3:6] - end, axis=1) < 1e-5) for end in ends]
        assert sum(len(f) for f in found) == expected, name
        for rows in found:
            for row in rows:
                assert caps[row, 6] > caps[row, 7] > 0.0  # thick at the top, tapering


def test_a_person_s_trunk_is_wider_than_deep_with_a_shoulder_line() -> None:
    """A person's trunk: ellipsoids along the spine, wider (across the hips, then the
    shoulders) than deep, and a line from shoulder to shoulder (a tube of round capsules
    read as a pill, as deep as wide, with domed shoulders); a dog keeps its round trunk."""
    from app.render.scene import TORSO_DEPTH, TORSO_WIDTH, Cap, Ell, motion_instances

    rig = build_rig(load_creature("human"))
    motion, _ = clip_motion(rig, 30.0, cycles=0.25)
    frame = motion_instances(motion, show_joints=False).frame(0)
    ells = np.asarray(frame.ellipsoids, np.float64)
    torso = ells[np.linalg.norm(ells[:, Ell.CENTRE][:, None] - motion.spine[0][None], axis=-1).min(axis=1) < 1e-6]
    assert len(torso) == rig.body.segments
    radii = torso[:, Ell.RADII]
    assert np.allclose(radii[:, 0] / radii[:, 1], TORSO_WIDTH / TORSO_DEPTH)
    across = torso[:, Ell.AXES[0]]
    hips = motion.joints[0, 0, 0] - motion.joints[0, 1, 0]
    assert abs(across[0] @ hips) / np.linalg.norm(hips) > 0.99  # the lowest turned with the hips
    caps = np.asarray(frame.capsules, np.float64)
    shoulders = motion.arms[0, :, 0]
    line = np.flatnonzero((np.linalg.norm(caps[:, Cap.A] - shoulders[0], axis=1) < 1e-6)
                          & (np.linalg.norm(caps[:, Cap.B] - shoulders[1], axis=1) < 1e-6))
    assert len(line) == 1
    dog = build_rig(load_creature("dog"))
    dog_motion, _ = clip_motion(dog, 30.0, cycles=0.25)
    dog_ells = np.asarray(motion_instances(dog_motion, show_joints=False).frame(0).ellipsoids, np.float64)
    assert not np.any(np.linalg.norm(dog_ells[:, Ell.CENTRE][:, None] - dog_motion.spine[0][None], axis=-1) < 1e-6)


def test_a_person_s_eyes_look_out_of_the_face() -> None:
    """A person's eyes sit at the front of the head near mid-height; an animal's high on
    the skull (the human's sat on top of its head)."""
    from app.render.scene import EYE_COLOR, Ell, motion_instances

    for name, lowest, highest in (("human", -0.1, 0.3), ("dog", 0.3, 0.6)):
        rig = build_rig(load_creature(name))
        motion, _ = clip_motion(rig, 30.0, cycles=0.25)
        ells = np.asarray(motion_instances(motion, show_joints=False).frame(0).ellipsoids, np.float64)
        eyes = ells[np.all(np.abs(ells[:, Ell.COLOR] - EYE_COLOR) < 1e-3, axis=1)]
        skulls = ells[np.isclose(ells[:, 12], 0.9 * rig.body.head_radius) & np.isclose(ells[:, 14], rig.body.head_radius)]
        assert len(eyes) == 2 and len(skulls) == 1
        up = skulls[0, Ell.AXES[1]]
        height = (eyes[:, Ell.CENTRE] - skulls[0, Ell.CENTRE]) @ up / rig.body.head_radius
        assert np.all((lowest < height) & (height < highest)), (name, height)


def _mane_above_skin(rig, motion, tufts: np.ndarray) -> np.ndarray:
    """How far each mane tuft (rows (K, 18), withers to poll) stands above the skinned
    body's crest: (K, 2) its place along the neck (0 base, 1 head) and the height (m) of
    its top over the highest skin vertex in a 6 cm slab across the neck under it."""
    from app.render.bodies import _build
    from app.render.scene import Ell, _frame_axes

    skin = _build(rig, "full").positions.astype(np.float64)
    base, head = motion.neck[0, 0], motion.neck[0, -1]
    length = np.linalg.norm(head - base)
    along = (head - base) / length
    _, up, _ = _frame_axes((head - base)[None])
    up = up[0]
    across = np.cross(up, along)
    rows = []
    for tuft in tufts:
        s = float(np.dot(tuft[Ell.CENTRE] - base, along))
        under = (np.abs((skin - base) @ along - s) < 0.03) & (np.abs((skin - base) @ across) < 0.03)
        crest = float(((skin[under] - base) @ up).max())
        rows.append((s / length, float(np.dot(tuft[Ell.CENTRE] - base, up)) + tuft[13] - crest))
    return np.array(rows)


def test_a_mammal_s_neck_is_deeper_than_wide_and_a_horse_s_is_maned() -> None:
    """A four-legged mammal's neck has flattened sections, deep as the chest at the base
    and as the head at the throat (a round tube read as a hose into the chest); the
    horse's crest carries a dark mane (``body.mane``), drawn on the skinned body as the
    eyes are and left out of the skin's surface, low over the withers and the poll."""
    from app.render.bodies import _build
    from app.render.scene import NECK_SECTIONS, NECK_WIDTH, Ell, mane_color, motion_instances, skin_features
    from app.skin.body import _parts

    def rows(name: str, **keys: float):
        rig = build_rig(load_creature(name).with_overrides({f"body.{k}": v for k, v in keys.items()}))
        motion, _ = clip_motion(rig, 30.0, cycles=0.25)
        ells = np.asarray(motion_instances(motion, show_joints=False).frame(0).ellipsoids, np.float64)
        skin = skin_features(motion)  # what the skinned body carries on its surface
        maned = np.all(np.abs(ells[:, Ell.COLOR] - mane_color(rig)) < 1e-3, axis=1)
        return rig, motion, ells, skin, maned

    rig, motion, ells, skin, maned = rows("horse")
    assert rig.body.mane > 0 and maned.sum() > 4
    assert np.all(np.abs(skin[:, Ell.COLOR] - mane_color(rig)) < 1e-3, axis=1).sum() == maned.sum()
    features = _build(rig, "coarse").features  # skinned with the body, not drawn over it
    assert features is not None
    assert np.all(np.abs(features.colors - mane_color(rig)) < 1e-3, axis=1).sum() == maned.sum() * 42
    overlays = np.asarray(motion_instances(motion, show_joints=False, parts=False).frame(0).ellipsoids)
    assert len(overlays) == 0
    _, skin_parts, _ = _parts(motion)
    assert len(skin_parts) == len(ells) - maned.sum() - 2  # neither the mane nor the eyes
    base, top = motion.neck[0, 0], motion.neck[0, -1]
    along = base + NECK_SECTIONS[:, None] * (top - base)
    sections = ells[np.linalg.norm(ells[:, Ell.CENTRE][:, None] - along[None], axis=-1).min(axis=1) < 0.25 * rig.body.radius[-1]]
    sections = sections[~np.all(np.abs(sections[:, Ell.COLOR] - mane_color(rig)) < 1e-3, axis=1)]
    assert len(sections) == len(NECK_SECTIONS)
    radii = sections[:, Ell.RADII]
    assert np.allclose(radii[:, 0], NECK_WIDTH * radii[:, 1])
    assert radii[0, 1] > 1.5 * rig.body.head_radius > radii[-1, 1]  # deep at the base, as the head at the throat
    # The mane grows out of the withers and falls to a tuft at the poll: tallest along the
    # middle of the neck (it stood full height at both ends, a plank ending in a knob above
    # the ears).
    above = _mane_above_skin(rig, motion, ells[maned])  # (s along the neck, tuft's top above the skin (m))
    middle = above[(above[:, 0] > 0.5) & (above[:, 0] < 0.8), 1]
    assert 0.3 * rig.body.mane < np.median(middle) < 0.7 * rig.body.mane, above
    assert above[-1, 1] < 0.5 * np.median(middle), above  # at the poll: 6.1 cm, as high as mid-neck
    _, _, _, _, unmaned = rows("horse", mane=0.0)
    assert not unmaned.any()
    for name in ("human", "spider", "bird"):  # no mammal's neck
        _, motion, ells, _, _ = rows(name)
        base, top = motion.neck[0, 0], motion.neck[0, -1]
        along = base + NECK_SECTIONS[:, None] * (top - base)
        assert np.linalg.norm(ells[:, Ell.CENTRE][:, None] - along[None], axis=-1).min() > 1e-3


def test_a_mammal_s_tail_leaves_the_top_of_the_croup_and_a_horse_s_is_hair() -> None:
    """A four-legged mammal's tail is set high on the rump (the horse's had come out of the
    middle of the buttock); a maned animal's tail is dark hair, full to its end, in the
    parts and on the skinned body (the tail's own vertices take the mane's colour)."""
    from app.render.bodies import _build
    from app.render.scene import Cap, mane_color, motion_instances

    for name, high in (("dog", True), ("horse", True), ("theropod", False)):
        rig = build_rig(load_creature(name))
        motion, _ = clip_motion(rig, 30.0, cycles=0.25)
        above = motion.tail[0, 0, 1] - motion.spine[0, 0, 1]
        assert (above > 0.3 * rig.body.radius[0]) == high, (name, above)
        caps = np.asarray(motion_instances(motion, show_joints=False).frame(0).capsules, np.float64)
        tail = caps[np.linalg.norm(caps[:, Cap.A] - motion.tail[0, 0], axis=1) < 1e-6]
        hair = np.all(np.abs(tail[:, Cap.COLOR] - mane_color(rig)) < 1e-3, axis=1)
        assert len(tail) == 1 and hair.all() == (rig.body.mane > 0), name
    horse = build_rig(load_creature("horse"))
    body = _build(horse, "coarse")
    dark = np.all(np.abs(body.colors - mane_color(horse)) < 0.02, axis=1)
    assert 0.02 < dark.mean() < 0.2  # the tail's vertices, not the coat


def test_hooves_are_dark_horn_on_the_skinned_body_too() -> None:
    """An unguligrade foot's hoof was dark only in the parts; on the skinned body it took
    the coat's colour (a slipper of hide). Vertices on a hoof are horn (within the soft
    edge where colours meet), and the hoof at the ground is mostly horn."""
    from app.render.bodies import _build
    from app.render.scene import HOOF_COLOR

    for name, hooved in (("horse", True), ("deer", True), ("dog", False)):
        body = _build(build_rig(load_creature(name)), "coarse")
        horn = np.all(np.abs(body.colors - HOOF_COLOR) < 1e-4, axis=1)
        assert horn.any() == hooved, name
        if hooved:
            assert body.positions[horn, 1].max() < 0.15 and horn.mean() < 0.1, name  # at the ground, not the coat
            # The hoof's lowest 4 cm reads as horn: its vertices' colours were 70 % of the way to the
            # coat's (the fetlock's coat bulge covered the hoof and the hoof's few vertices blended away).
            low = body.positions[:, 1] < 0.04
            coat = srgb_to_linear(build_rig(load_creature(name)).look.body_color)
            toward_coat = np.sum((body.colors[low] - HOOF_COLOR) * (coat - HOOF_COLOR), axis=1) \
                / np.sum((coat - HOOF_COLOR) ** 2)
            assert toward_coat.mean() < 0.4, (name, toward_coat.mean())


def test_a_bird_has_a_beak_folded_wings_plumes_and_splayed_toes() -> None:
    """The bird was an egg on stilts: one dark coat from beak to toes, no wings, a paw for
    a foot and its head pitched 68 degrees down. Its parts now: a flat beak at the head's
    tip, a folded wing on each flank (out of the trunk, in the plumes' colour), a tail of
    plumes, two toes a foot (an ostrich's), the neck and lower legs in their own colours."""
    from app.render.scene import Ell, palette, pose_instances, srgb_to_linear

    rig = build_rig(load_creature("bird"))
    motion = simulate(rig, 0.5, 30.0, world=IN_PLACE)
    shapes = motion_instances(motion, show_joints=False, by_side=False).frame(0)
    colors = palette(rig)
    ells = shapes.ellipsoids.astype(np.float64)
    plumes = np.all(np.abs(ells[:, Ell.COLOR] - colors.plume) < 1e-5, axis=1)
    assert plumes.sum() == 2  # two wings
    wings = ells[plumes]
    assert np.allclose(wings[:, 14], 0.5 * rig.body.wings, atol=1e-6)  # half their length along
    spine = motion.spine[0]
    assert np.all(np.abs(wings[:, 0] - spine[:, 0].mean()) > 0.8 * rig.body.radius.max())  # out on the flanks
    assert wings[0, 0] * wings[1, 0] < 0  # one each side
    beak = ells[np.all(np.abs(ells[:, Ell.COLOR] - srgb_to_linear(rig.look.beak_color)) < 1e-5, axis=1)]
    assert len(beak) == 1
    nose = motion.head[0, 1]
    assert np.linalg.norm(beak[0, 0:3] + beak[0, 9:12] * beak[0, 14] - nose) < 1e-6  # its tip is the head's
    assert 2 * beak[0, 14] == pytest.approx(rig.body.beak)
    head_dir = motion.head[0, 1] - motion.head[0, 0]
    assert abs(np.degrees(np.arcsin(head_dir[1] / np.linalg.norm(head_dir)))) < 25  # held about level
    caps = shapes.capsules.astype(np.float64)
    feet = np.all(np.abs(caps[:, 8:11] - colors.legs) < 1e-5, axis=1)
    toe_caps = caps[feet & (np.linalg.norm(caps[:, 0:3][:, None] - motion.joints[0, :, 3][None], axis=-1).min(axis=1)
                            < 1e-5)]
    assert len(toe_caps) == 2 * (1 + 2)  # each foot: its toe bone and two splayed toes
    neck = np.all(np.abs(caps[:, 8:11] - colors.neck) < 1e-5, axis=1)
    assert neck.any() and not np.allclose(colors.neck, colors.coat)
    tail = np.all(np.abs(caps[:, 8:11] - colors.plume) < 1e-5, axis=1)
    assert tail.sum() == rig.body.tail_segments
    # Side colours still colour every leg part by side (a debugging view).
    by_side = pose_instances(motion.pose(0), rig, show_joints=False)
    assert not np.any(np.all(np.abs(by_side.capsules[..., 8:11] - colors.legs) < 1e-5, axis=-1))


def test_the_skin_takes_each_parts_colour_with_soft_edges() -> None:
    """On the skinned bird the feet are the legs' colour, the neck the neck's, the wings
    and tail plumes, the rest the coat; where two colours meet they blend over a few
    triangles (each vertex's colour averaged with its neighbours'), not a saw-tooth."""
    from app.render.bodies import _build
    from app.render.scene import palette

    rig = build_rig(load_creature("bird").with_overrides({"look.countershade": 0.0}))  # every coat vertex the coat's
    body = _build(rig, "coarse")
    colors = palette(rig)

    def share(color: np.ndarray) -> float:
        return float(np.mean(np.all(np.abs(body.colors - color) < 1e-3, axis=1)))

    low = body.positions[:, 1] < 0.3  # the lower legs and feet
    assert np.mean(np.all(np.abs(body.colors[low] - colors.legs) < 1e-3, axis=1)) > 0.8
    assert share(colors.plume) > 0.03 and share(colors.neck) > 0.05
    edges = np.concatenate([body.faces[:, [0, 1]], body.faces[:, [1, 2]], body.faces[:, [2, 0]]])
    jump = np.linalg.norm(body.colors[edges[:, 0]] - body.colors[edges[:, 1]], axis=1).max()
    assert jump < 0.7 * np.linalg.norm(colors.plume - colors.coat)  # no edge jumps from one part's colour to the next
    pure = np.any([np.all(np.abs(body.colors - c) < 1e-3, axis=1)
                   for c in (colors.coat, colors.legs, colors.plume, colors.neck, colors.beak)], axis=0)
    assert 0.5 < pure.mean() < 1.0  # a soft band where colours meet, not a smear over the body


def test_bird_keys_are_checked() -> None:
    """The new keys refuse what they cannot draw, in one line naming the key."""
    spec = load_creature("bird")
    for key, value, words in (("body.beak", 0.5, "longer than the head"), ("legs.legs.toes", 5, "toes"),
                              ("body.wings", -0.1, "wings"), ("look.plume_color", "white", "plume_color")):
        with pytest.raises(SpecError, match=words):
            spec.with_overrides({key: value})
    assert spec.with_overrides({"legs.legs.toes": 4, "body.wings": 0.0}).legs[0].toes == 4


def test_a_centipede_is_a_row_of_plates_and_a_spider_is_not() -> None:
    """The centipede was an unsegmented sausage on pegs: its trunk is now a flattened plate
    a leg pair, wider than tall, over a thinner, darker tube (the membranes between them);
    its lower legs are yellow. A spider's two-part body has no plates."""
    from app.render.scene import MEMBRANE_SHADE, Ell, palette

    rig = build_rig(load_creature("centipede"))
    motion = simulate(rig, 0.5, 30.0, world=IN_PLACE)
    shapes = motion_instances(motion, show_joints=False, by_side=False).frame(0)
    colors = palette(rig)
    ells = shapes.ellipsoids.astype(np.float64)
    plates = ells[np.all(np.abs(ells[:, Ell.COLOR] - colors.coat) < 1e-5, axis=1) & (ells[:, 12] > 1.5 * ells[:, 13])]
    assert len(plates) == rig.leg_count // 2
    t = np.linspace(0.0, 1.0, 20)[:, None, None]
    spine = ((1.0 - t) * motion.spine[0, :-1] + t * motion.spine[0, 1:]).reshape(-1, 3)  # the polyline, finely
    gaps = np.linalg.norm(spine[:, None] - plates[None, :, 0:3], axis=-1).min(axis=0)
    assert gaps.max() < 0.01 * rig.body.length  # on the spine
    along = np.sort(plates[:, 2])
    assert np.all(2 * plates[:, 14].max() < np.diff(along).min() * 1.01)  # apart: the membranes show between them
    caps = shapes.capsules.astype(np.float64)
    tube = np.all(np.abs(caps[:, 8:11] - MEMBRANE_SHADE * colors.coat) < 1e-5, axis=1)
    assert tube.sum() >= rig.body.segments
    assert not np.allclose(colors.legs, colors.coat)
    spider = build_rig(load_creature("spider"))
    flat = motion_instances(simulate(spider, 0.5, 30.0, world=IN_PLACE), show_joints=False, by_side=False).frame(0)
    body = srgb_to_linear(spider.look.body_color)
    assert not np.any(np.all(np.abs(flat.capsules[:, 8:11] - MEMBRANE_SHADE * body) < 1e-5, axis=1))


def test_a_short_beak_still_meets_the_face() -> None:
    """A beak shorter than the head's front (``body.beak`` 0.03 on the bird, or its head made
    longer) floated ahead of the face: a muzzle now bridges it to the skull, and the beak
    keeps its own length (a longer one, from the skull on, takes the muzzle's place)."""
    from app.render.scene import Ell, palette

    for overrides, bridged in (({"body.beak": 0.03}, True), ({"body.head_length": 0.25}, True), ({}, False)):
        rig = build_rig(load_creature("bird").with_overrides(overrides))
        motion = simulate(rig, 0.2, 30.0, world=IN_PLACE)
        shapes = motion_instances(motion, show_joints=False, by_side=False).frame(0)
        ells, caps = shapes.ellipsoids.astype(np.float64), shapes.capsules.astype(np.float64)
        beak = ells[np.all(np.abs(ells[:, Ell.COLOR] - palette(rig).beak) < 1e-5, axis=1)][0]
        assert 2 * beak[14] == pytest.approx(rig.body.beak)  # its own length
        back = beak[0:3] - beak[9:12] * beak[14]
        skull = ells[0]  # the skull: the first ellipsoid (it casts the head's shadow)
        muzzle = caps[np.linalg.norm(caps[:, 0:3] - skull[0:3], axis=1) < 1e-5]
        assert len(muzzle) == (1 if bridged else 0), overrides
        if bridged:
            # From the skull to the beak: its round end (as deep as the beak) reaches into the
            # beak's back, not over the beak itself.
            gap = np.linalg.norm(muzzle[0, 3:6] - back)
            assert muzzle[0, 7] <= beak[13] + 1e-6 and 0.0 < gap < muzzle[0, 7]
        else:
            inside = np.sum(((back - skull[0:3]) @ np.stack([skull[3:6], skull[6:9], skull[9:12]]).T
                             / skull[12:15]) ** 2)
            assert inside < 1.0  # the beak's back end lies in the skull


def test_a_birds_wings_move_with_its_trunk_not_its_thighs() -> None:
    """A wing's ellipsoid lies nearer the hip joint than the spine, and was bound to the
    hip: on the skinned bird it swung 34 degrees with each thigh. Its vertices now follow
    the trunk."""
    from app.kinematics.skeleton import skeleton_clip
    from app.render.bodies import _build
    from app.render.scene import palette

    rig = build_rig(load_creature("bird"))
    body = _build(rig, "coarse")
    names = skeleton_clip(simulate(rig, 0.2, 30.0, world=IN_PLACE), body.layout).skeleton.names
    tail = np.array([n.startswith("tail") for n in names])
    plume = np.all(np.abs(body.colors - palette(rig).plume) < 1e-3, axis=1)
    on_wing = plume & ~tail[body.joints[:, 0]]  # feathers not bound first to the tail: the wings'
    assert on_wing.sum() > 20
    leg = np.array([n.split("_", 1)[0] in ("L", "R") for n in names])  # the legs' joints: L_hip, R_knee, ...
    on_legs = np.sum(np.where(leg[body.joints[on_wing]], body.weights[on_wing], 0.0), axis=1)
    assert on_legs.mean() < 0.1


def test_a_person_has_buttocks_that_move_with_the_pelvis() -> None:
    """A person's side view ran flat from the back into the thighs: two ellipsoids now sit
    behind the hip joints, and on the skinned body they follow the pelvis, not a thigh."""
    from app.kinematics.skeleton import skeleton_clip
    from app.render.bodies import _build
    from app.render.scene import trunk_parts

    rig = build_rig(load_creature("human"))
    motion = simulate(rig, 0.2, 30.0, world=IN_PLACE)
    glutes = trunk_parts(motion)
    assert len(glutes) == 2
    hips = motion.joints[0, 0:2, 0]
    forward = (motion.head[0, 1] - motion.head[0, 0]) * np.array([1.0, 0.0, 1.0])  # where the face looks
    forward /= np.linalg.norm(forward)
    assert np.all((glutes - hips) @ forward < -0.03)  # behind the hips
    assert glutes[0, 0] * glutes[1, 0] < 0 or abs(glutes[0, 0] - glutes[1, 0]) > 0.05  # one each side
    body = _build(rig, "coarse")
    names = skeleton_clip(motion, body.layout).skeleton.names
    leg = np.array([n.split("_", 1)[0] in ("L", "R") and "shoulder" not in n and "elbow" not in n
                    and "wrist" not in n and "hand" not in n for n in names])
    behind = ((body.positions - hips.mean(axis=0)) @ forward < -0.1) & (
        np.abs(body.positions[:, 1] - hips[:, 1].mean()) < 0.08)
    assert behind.sum() > 5
    on_legs = np.sum(np.where(leg[body.joints[behind]], body.weights[behind], 0.0), axis=1)
    assert on_legs.mean() < 0.5


def test_a_bear_has_a_shoulder_hump_that_moves_with_its_trunk() -> None:
    """``body.hump`` stands an ellipsoid over the back just behind the fore legs, its top the
    hump's height above the trunk there (the grizzly's); bound to the spine, not a fore leg."""
    from app.render.scene import trunk_parts

    rig = build_rig(load_creature("bear"))
    motion = simulate(rig, 0.2, 30.0, world=IN_PLACE)
    (hump,) = trunk_parts(motion)
    flat = build_rig(load_creature("bear").with_overrides({"body.hump": 0.0}))
    assert len(trunk_parts(simulate(flat, 0.2, 30.0, world=IN_PLACE))) == 0
    ells = motion_instances(motion, show_joints=False, by_side=False).frame(0).ellipsoids.astype(np.float64)
    row = ells[np.linalg.norm(ells[:, 0:3] - hump, axis=1) < 1e-5][0]
    top = row[0:3] + row[6:9] * row[13]  # up its y axis
    spine = motion.spine[0]
    nearest = np.argmin(np.linalg.norm(spine - hump, axis=1))
    back = spine[nearest, 1] + motion.spine_radius[nearest]
    assert top[1] - back == pytest.approx(rig.body.hump, abs=0.03)
    along = (hump - spine[0]) @ (spine[-1] - spine[0]) / np.linalg.norm(spine[-1] - spine[0]) ** 2
    assert 0.75 < along < 1.0  # over the shoulders, at the front of the trunk


def test_a_mammal_has_a_dark_nose_drawn_on_its_skin() -> None:
    """A dog's, cat's or bear's muzzle ended in its coat: a dark nose now sits over the
    tip, carried on the skinned body as the eyes are (not in its surface), smaller on a
    deer's longer head; a horse's long head (a soft muzzle) and a bird have none, and a
    head lengthened towards a horse's shrinks the nose away rather than dropping it."""
    from app.render.bodies import _build
    from app.render.scene import NOSE_COLOR, Ell, skin_overlays

    for name, has in (("dog", True), ("bear", True), ("deer", True), ("horse", False), ("bird", False),
                      ("human", False)):
        rig = build_rig(load_creature(name))
        motion = simulate(rig, 0.2, 30.0, world=IN_PLACE)
        ells = motion_instances(motion, show_joints=False, by_side=False).frame(0).ellipsoids.astype(np.float64)
        noses = ells[np.all(np.abs(ells[:, Ell.COLOR] - NOSE_COLOR) < 1e-6, axis=1)]
        assert len(noses) == (1 if has else 0), name
        if has:
            assert np.linalg.norm(noses[0, 0:3] - motion.head[0, 1]) < 0.3 * rig.body.head_radius  # at the tip
            on_skin = skin_overlays(motion)
            assert np.min(np.linalg.norm(on_skin - noses[0, 0:3], axis=1)) < 1e-6  # left out of the surface
            features = _build(rig, "coarse").features  # and carried on it, skinned with it
            assert features is not None and np.all(np.abs(features.colors - NOSE_COLOR) < 1e-6, axis=1).sum() == 42
    sizes = []
    for length in np.linspace(0.2, 0.4, 41):  # the dog's head lengthened step by step
        rig = build_rig(load_creature("dog").with_overrides({"body.head_length": float(length)}))
        ells = motion_instances(simulate(rig, 0.1, 30.0, world=IN_PLACE), show_joints=False).frame(0).ellipsoids
        noses = ells[np.all(np.abs(ells[:, Ell.COLOR] - NOSE_COLOR) < 1e-6, axis=1)]
        sizes.append(float(noses[0, 12] / rig.body.head_radius) if len(noses) else 0.0)
    assert sizes[0] > 0.2 and sizes[-1] == 0.0 and np.abs(np.diff(sizes)).max() < 0.02  # shrinks, never drops


def test_the_floor_mesh_covers_its_disc_once_with_rings_through_the_fog() -> None:
    """The floor's fog is worked out at its corners (a software rasteriser's floor costs per
    pixel): its mesh must cover the polygon once (no gaps, no overlaps, one winding) and
    have its rings from the fog's start to its end, so the fog is linear enough between."""
    from app.render.ground import FLOOR_SIDES, FOG_RINGS, floor_mesh
    from app.render.renderer import SceneRenderer

    # Where the renderer's fog starts and ends, of the floor's radius (the rings must fall there).
    start = SceneRenderer.FOG_START / (SceneRenderer.FOG_END * SceneRenderer.FLOOR_PAST_FOG)
    end = 1.0 / SceneRenderer.FLOOR_PAST_FOG
    sides, rings = FLOOR_SIDES, FOG_RINGS
    corners, triangles = floor_mesh(sides, start, end, rings)
    assert corners.shape == ((rings + 2) * sides, 2) and triangles.shape == (sides - 2 + 2 * (rings + 1) * sides, 3)
    a, b, c = (corners[triangles[:, k]] for k in range(3))
    signed = 0.5 * ((b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0]))
    assert np.all(signed > 0) or np.all(signed < 0)  # one winding
    polygon = 0.5 * sides * np.sin(2.0 * np.pi / sides)  # the unit 16-gon's area
    assert abs(np.abs(signed).sum() - polygon) < 1e-9  # covered exactly once
    radii = np.unique(np.round(np.linalg.norm(corners, axis=1), 9))
    assert np.allclose(radii, [*np.linspace(start, end, rings + 1), 1.0])
    # The smoothstep fog, linear between the rings (and exact at them), is within 3 % along
    # a ray (4 % between a ring's corners, its sides being chords).
    t = np.linspace(0.0, 1.0, 1001)
    ring_t = np.linspace(0.0, 1.0, rings + 1)
    smooth = t * t * (3.0 - 2.0 * t)
    assert np.abs(np.interp(t, ring_t, ring_t * ring_t * (3.0 - 2.0 * ring_t)) - smooth).max() < 0.03


def test_a_bird_s_drumsticks_are_bare_below_its_feathered_thighs() -> None:
    """An ostrich's legs are bare from the plumage down: its drumstick (the tibiotarsus,
    knee to ankle) was drawn in the black plumage to the ankle, as if feathered. On the
    skinned body the middle of the drumstick is the legs' colour, as the shank below it."""
    from app.render.bodies import _build, bind_motion
    from app.render.scene import palette

    rig = build_rig(load_creature("bird"))
    body = _build(rig, "coarse")
    joints = bind_motion(rig).joints[0]  # (L, 5, 3): hip, knee, ankle, ball, toe in the bind pose
    colors = palette(rig)

    def colour_near(point: np.ndarray) -> np.ndarray:
        return body.colors[np.argmin(np.linalg.norm(body.positions - point, axis=1))]

    for leg in range(rig.leg_count):
        knee, ankle, ball = joints[leg, 1], joints[leg, 2], joints[leg, 3]
        assert np.allclose(colour_near(knee + 0.5 * (ankle - knee)), colors.legs, atol=0.02), leg
        assert np.allclose(colour_near(ankle + 0.5 * (ball - ankle)), colors.legs, atol=0.02), leg


def test_a_horse_s_face_is_a_deep_wedge_to_the_chin() -> None:
    """A horse's head was a round skull with a thin snout off it (an anteater's): the jaw
    now runs on from the jowl to the chin. Through the lower half of the face the skinned
    head is as deep as a horse's (~0.17 m; it was ~0.10) and no wider than deep."""
    from app.render.bodies import _build, bind_motion
    from app.render.scene import _frame_axes, _skull

    rig = build_rig(load_creature("horse"))
    body = _build(rig, "full")
    head = bind_motion(rig).head[:1]
    skull, along = (v[0] for v in _skull(head, rig))
    face = float(np.linalg.norm(head[0, 1] - skull))
    across, up, _ = (v[0] for v in _frame_axes(along[None]))
    rel = body.positions - skull
    a, x, y = rel @ along, rel @ across, rel @ up
    on_head = (np.abs(x) < 0.12) & (np.abs(y) < 0.2)
    depths, widths = [], []
    for f in (0.6, 0.7, 0.8):
        ring = on_head & (np.abs(a - f * face) < 0.015)
        assert ring.sum() >= 3, f
        depths.append(float(np.ptp(y[ring])))
        widths.append(float(2.0 * np.abs(x[ring]).max()))
    assert np.mean(depths) > 0.15, depths
    assert np.all(np.array(widths) < np.array(depths) + 0.01), (widths, depths)
