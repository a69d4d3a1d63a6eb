"""Herds: many animals of one kind, vectorised across animals, drawn with instancing."""

from __future__ import annotations

import moderngl
import numpy as np
import pytest
from cli_runner import gaitlab

from app import build_rig, load_creature
from app.errors import GaitlabError
from app.kinematics.herd import MAX_HERD, Herd, check_herd_size, follow_leader
from app.kinematics.world import World
from app.recording import RecordRequest
from app.render.camera import frame_points
from app.render.clip import ClipRenderer
from app.render.herd import HerdInstances
from app.render.options import GroundView, RenderOptions, ViewSettings
from app.worlds import make_world

DT = 1.0 / 60.0


def straight_leader(herd: Herd, seconds: float) -> tuple[np.ndarray, np.ndarray]:
    frames = int(round(seconds / DT))
    z = herd.cycle_speed * DT * np.arange(frames)
    return np.column_stack([np.zeros(frames), z]), np.zeros(frames)


def test_herd_sizes_are_checked() -> None:
    assert check_herd_size(1) == 1 and check_herd_size(MAX_HERD) == MAX_HERD
    for bad in (0, -3, MAX_HERD + 1, 100_000, 2.5, True):
        with pytest.raises(GaitlabError, match="give 1 to"):
            check_herd_size(bad)  # type: ignore[arg-type]


def test_a_herd_keeps_apart_and_keeps_up_with_its_leader() -> None:
    rig = build_rig(load_creature("dog"))
    herd = Herd(rig, 40, seed=3)
    assert herd.size.min() >= 0.89 and herd.size.max() <= 1.11 and np.ptp(herd.size) > 0.1  # +-10% sizes
    leader, heading = straight_leader(herd, 12.0)
    track = follow_leader(herd, leader, heading, 1.0 / DT)
    for i in range(len(leader) // 2, len(leader), 30):  # once settled
        p = track.position[i]
        d = np.linalg.norm(p[:, None] - p[None], axis=-1)
        np.fill_diagonal(d, np.inf)
        assert d.min() > 0.7 * rig.body_length, i  # nobody walks through anybody
        centre = p.mean(axis=0)
        assert np.linalg.norm(centre - leader[i]) < 3.5 * herd.spacing  # the group keeps up (40 in loose rows)
    assert np.abs(track.heading[-1]).max() < 0.3  # all facing the way the leader goes


def test_herd_animals_keep_nose_to_rump_room() -> None:
    """An animal keeps its neighbours ahead at least its own nose-to-rump length away
    (centre to centre, in line): a head never sits in the rump ahead (the old separation,
    a body length hip to shoulder, let a dog's head into the next dog's rump)."""
    rig = build_rig(load_creature("dog"))
    herd = Herd(rig, 8, seed=1)
    front, back, half_width = herd.extent
    closest = np.inf
    for k in range(600):
        herd.step(1 / 30, np.array([0.0, rig.ground_speed * k / 30]), 0.0)
        if k < 150:
            continue
        forward = np.column_stack([np.sin(herd.heading), np.cos(herd.heading)])
        delta = herd.position[None] - herd.position[:, None]
        along = np.sum(delta * forward[:, None], axis=-1)
        side = delta[..., 0] * forward[:, None, 1] - delta[..., 1] * forward[:, None, 0]
        in_line = (np.abs(side) < 2.0 * half_width) & (along > 0)
        if in_line.any():
            closest = min(closest, float(along[in_line].min()))
    assert closest > 1.1 * (front + back)


def test_herd_feet_stay_planted_while_walking_straight() -> None:
    rig = build_rig(load_creature("dog"))
    herd = Herd(rig, 12, seed=2)
    leader, heading = straight_leader(herd, 8.0)
    track = follow_leader(herd, leader, heading, 1.0 / DT)
    joints = []
    contact = []
    for i in range(len(leader) - 120, len(leader)):
        track.apply(herd, i)
        joints.append(herd.joints()[:, :, 3])
        f0, f1, _ = herd.blend()
        contact.append(herd.cycle.contact[f0] & herd.cycle.contact[f1])
    ball, planted = np.array(joints), np.array(contact)
    still = planted[1:] & planted[:-1]
    slip = np.linalg.norm(ball[1:] - ball[:-1], axis=-1)[still]
    assert still.sum() > 500
    # Straight and steady, a planted foot holds; so does one of an animal turning to keep
    # its place (each foot is locked where it lands).
    assert slip.max() < 1e-6


@pytest.mark.parametrize("ground", ["flat", "hills:amp=0.15,wavelength=3"])
def test_herd_feet_stay_planted_while_turning(ground: str) -> None:
    """Round a circle of 3 m, each standing foot stays where it landed (the rigid cycle
    swung them about the body: up to 4.5 mm a frame), on the ground, within its leg's
    reach; in the swing after, the foot eases back onto the cycle's path without a jump."""
    rig = build_rig(load_creature("dog"))
    world = make_world("circle:r=3", ground)
    height = None if world.terrain.flat else world.terrain.height
    herd = Herd(rig, 8, seed=3)
    frames = 480
    points, tangents = world.path.sample(np.arange(frames) * DT * herd.cycle_speed)
    heading = np.unwrap(np.arctan2(tangents[:, 0], tangents[:, 1]))
    track = follow_leader(herd, points, heading, 1.0 / DT, height)
    balls, standing, short = [], [], []
    for i in range(frames):
        track.apply(herd, i)
        joints, legs = herd.legs(height)  # None: every foot where the cycle puts it
        balls.append(joints[:, :, 3])
        standing.append(~herd._swinging()[0])
        short.append(np.zeros(joints.shape[:2]) if legs is None else legs.short)
    ball, planted = np.array(balls), np.array(standing)
    still = planted[1:] & planted[:-1]
    step = np.linalg.norm(ball[1:] - ball[:-1], axis=-1)
    assert still.sum() > 5000 and np.abs(track.foot_shift).max() > 0.02  # the locks did something
    assert step[still].max() < 1e-6
    assert np.array(short)[planted].max() < 1e-6
    ground_y = 0.0 if height is None else height(ball[..., [0, 2]].reshape(-1, 2)).reshape(ball.shape[:3])
    assert np.abs(ball[..., 1] - ground_y)[planted].max() < 1e-6
    assert step[~planted[1:]].max() < 0.1  # a swinging foot moves smoothly (the cycle's own: 78 mm a frame)


def test_herd_kinematics_are_vectorised_across_animals() -> None:
    rig = build_rig(load_creature("dog"))
    herd = Herd(rig, 100)
    joints = herd.joints()
    assert joints.shape == (100, rig.leg_count, 5, 3)
    herd.step(DT, np.array([0.0, 0.1]), 0.0)
    # Each animal's pose is the cycle's, scaled, turned and moved: bone lengths scale with size.
    femur = np.linalg.norm(joints[:, 0, 1] - joints[:, 0, 0], axis=-1)
    assert np.allclose(femur / herd.size, rig.femur[0], rtol=2e-3)  # (blending two frames shortens a hair)


@pytest.mark.gl
def test_a_herd_is_drawn_with_the_same_draw_calls_as_one_animal(gl_ctx, monkeypatch) -> None:
    rig = build_rig(load_creature("dog"))
    calls: list[int] = []
    original = moderngl.VertexArray.render

    def counting(self, *args, **kwargs):
        calls.append(1)
        return original(self, *args, **kwargs)

    monkeypatch.setattr(moderngl.VertexArray, "render", counting)
    renderer = ClipRenderer((160, 120), "off", ctx=gl_ctx)
    counts, pixels = [], []
    try:
        for n in (2, 60):
            herd = Herd(rig, n)
            scene = HerdInstances(herd).frame(herd)
            assert len(scene.bodies) == n and all(b.body is scene.bodies[0].body for b in scene.bodies)
            parts = HerdInstances(herd, body="parts").frame(herd)
            assert parts.capsules.shape[0] % n == 0 and parts.ellipsoid_casters == n
            points = scene.spheres()[0]
            camera = frame_points(points, "three-quarter", aspect=4 / 3)
            calls.clear()
            renderer.scene.draw_instances(scene, GroundView(), camera, renderer.target.fbo, RenderOptions())
            counts.append(len(calls))
            pixels.append(renderer.target.read())
    finally:
        renderer.release()
    # The same draw calls whatever the herd's size; a herd framed from afar may add one, its
    # eyes a few pixels across drawn with the coarsest sphere (and a near one the finer).
    assert abs(counts[1] - counts[0]) <= 1
    body = np.sqrt(np.array([0.78, 0.58, 0.38]) ** 2) * 255  # roughly the dog's tan
    assert all((np.abs(p.astype(float) - body).max(axis=-1) < 60).sum() > 50 for p in pixels)


def test_a_herd_draws_and_shadows_small_animals_with_coarser_meshes() -> None:
    """Levels of detail by size on screen and in the shadow map: a lone dog near the
    camera shows its full body and casts its shadow stand-in; a herd of 100 framed from
    afar draws the coarsest meshes (a few hundred faces) and casts them into its shadow
    map (each dog a few dozen texels long)."""
    from app.render.bodies import body_levels
    from app.render.lighting import light_view_proj

    rig = build_rig(load_creature("dog"))
    pixel = np.radians(40.0) / 720
    herd = Herd(rig, 1)
    scene = HerdInstances(herd).frame(herd)
    body = scene.bodies[0].body
    assert body.far is not None and body.far.shadow is not None and body.shadow is not None
    assert len(body.faces) > len(body.shadow.faces) > len(body.far.faces) > len(body.far.shadow.faces)
    eye = np.array([0.0, 1.0, 2.5])
    (shown, caster), = body_levels(scene.bodies, eye, light_view_proj(scene)[1], pixel)
    assert shown is body and caster is body.shadow
    herd = Herd(rig, 100)
    scene = HerdInstances(herd).frame(herd)
    points = scene.spheres()[0]
    camera = frame_points(points, "three-quarter", aspect=16 / 9)
    levels = body_levels(scene.bodies, np.asarray(camera.eye), light_view_proj(scene)[1], pixel)
    assert sum(shown is body.far.shadow for shown, _ in levels) > 80
    assert all(caster is body.far.shadow for _, caster in levels)
    # An orthographic view has no size in pixels: its far animals keep the far mesh.
    levels = body_levels(scene.bodies, np.asarray(camera.eye), light_view_proj(scene)[1], None)
    assert all(shown is body or shown is body.far for shown, _ in levels)


def test_render_refuses_bad_herds_in_one_line(tmp_path) -> None:
    for args, words in ((["--herd", "0"], "give 1 to 1000"), (["--herd", "100000"], "give 1 to 1000"),
                        (["--herd", "5", "--in-place"], "drop --in-place")):
        out = gaitlab("render", "dog", *args, "-o", "x.png", cwd=tmp_path)
        assert out.returncode == 2, out.stderr
        assert words in out.stderr and "Traceback" not in out.stderr and len(out.stderr.strip().splitlines()) == 1
        assert not (tmp_path / "x.png").exists()
    with pytest.raises(GaitlabError):
        RecordRequest.of(load_creature("dog"), output=tmp_path / "x.png", herd=0)
    with pytest.raises(GaitlabError, match="in-place"):
        RecordRequest.of(load_creature("dog"), output=tmp_path / "x.png", herd=3, world=World(in_place=True))


def first_frame(gl_ctx, tmp_path, **request) -> np.ndarray:
    """The first frame a PNG recording of the dog would write (small, no antialiasing)."""
    from app.recording import Recording

    job = Recording(RecordRequest.of(load_creature("dog"), output=tmp_path / "frame.png",
                                  view=ViewSettings(size=(192, 144), antialias="off"), **request), ctx=gl_ctx)
    try:
        return job._render(0)
    finally:
        job.cancel()


@pytest.mark.gl
def test_herd_golden(gl_ctx, snapshot, tmp_path) -> None:
    snapshot.check("herd_of_eight_dogs", first_frame(gl_ctx, tmp_path, herd=8, start=2.0))


@pytest.mark.gl
def test_travelling_on_hills_golden(gl_ctx, snapshot, tmp_path) -> None:
    rig = build_rig(load_creature("dog"))
    world = make_world("circle:r=2.5", f"hills:amp={0.12 * rig.hip_height:.4f},wavelength={3 * rig.body_length:.3f}")
    snapshot.check("dog_travelling_on_hills", first_frame(gl_ctx, tmp_path, start=3.0, world=world))


def test_scene_files_take_a_herd_and_refuse_bad_ones(tmp_path) -> None:
    from app.kinematics.world import WorldError
    from app.resources import scenes_dir
    from app.worlds import load_scene

    scene = load_scene(scenes_dir() / "herd.toml")
    assert scene.creatures[0].herd == 20
    for value, words in (("0", "herd = 0"), ("100000", "herd = 100000"), ('"many"', "herd = 'many'"),
                         ("true", "herd = True")):
        bad = tmp_path / "bad.toml"
        bad.write_text(f'[[creatures]]\ncreature = "dog"\nherd = {value}\n')
        with pytest.raises(WorldError, match="give 1 to 1000") as info:
            load_scene(bad)
        assert words in str(info.value) and str(bad) in str(info.value)


def test_the_viewer_steps_its_herd_and_still_samples_the_creature() -> None:
    from app.ui.state import ViewerState

    state = ViewerState(load_creature("dog"))
    assert not state.set_herd(0) and "give 1 to" in state.error
    assert state.set_herd(6) and state.herd is not None and state.herd.count == 5
    start = state.herd.position.copy()
    for _ in range(30):
        state.advance(1.0 / 30.0)
        assert state.take_samples()  # the live measurement keeps its sub-steps
    assert np.all(np.linalg.norm(state.herd.position - start, axis=1) > 0.2)  # they walk along
    assert state.set_herd(1) and state.herd is None


def test_a_herd_keeps_up_with_a_driven_leader() -> None:
    from app.ui.state import ViewerState

    state = ViewerState(load_creature("dog"))
    assert state.set_herd(8) and state.start_driving()
    state.drive_input = (1.0, 0.0)
    for _ in range(int(6 / DT)):  # 6 s of W: up to a gallop
        state.advance(DT)
    assert state.driver is not None and state.driver.gait == "gallop"
    point, _ = state._here()
    gap = np.linalg.norm(state.herd.position.mean(axis=0) - point)
    assert gap < 8.0 * state.live.rig.body_length
    assert state.herd.rig.gait.preset == "gallop"  # the herd's cycle follows the leader's gait


def test_a_herd_is_a_loose_group_not_a_parade() -> None:
    """Places scattered over the group (no rows or columns: most lateral quarter-spacings
    are taken), room between neighbours, headings that differ at the start, and places
    that drift as the group goes (it mills)."""
    herd = Herd(build_rig(load_creature("dog")), 30)
    home, spacing = herd.home, herd.spacing
    lateral = home[:, 0]
    columns = np.floor((lateral - lateral.min()) / (0.25 * spacing)).astype(int)
    assert len(set(columns)) >= 0.6 * (columns.max() + 1)
    gaps = np.linalg.norm(home[:, None] - home[None], axis=-1) + np.diag(np.full(len(home), np.inf))
    assert gaps.min() >= 0.5 * spacing
    assert np.degrees(np.std(herd.heading)) > 5.0
    start = herd.slot.copy()
    for _ in range(60):
        herd.step(1 / 30, np.zeros(2), 0.0)
    drift = np.linalg.norm(herd.slot - start, axis=-1)
    assert 0.02 * spacing < np.median(drift) < 0.7 * spacing


def test_the_viewer_marks_the_herd_s_leader() -> None:
    """With a herd, the creature the panels edit stands in a gold ring on the ground."""
    from app.render.overlays import LEADER_COLOR
    from app.ui.state import ViewerState

    state = ViewerState(load_creature("dog"))
    assert state.overlays(state.pose()) is None
    state.set_herd(8)
    overlays = state.overlays(state.pose())
    assert overlays is not None and overlays.leader is not None
    centre = state.pose().root[:3, 3]
    assert np.linalg.norm(overlays.leader[[0, 2]] - centre[[0, 2]]) < 1e-9
    rows = overlays.markers(np.ones(3))
    gold = np.all(np.abs(rows[:, 15:18] - LEADER_COLOR) < 1e-6, axis=1)
    assert gold.sum() >= 12
    ring = np.linalg.norm(rows[gold][:, [0, 2]] - centre[[0, 2]], axis=1)
    assert np.allclose(ring, overlays.leader_radius)


def test_herd_animals_set_their_feet_on_the_hill_under_them() -> None:
    """On hills each animal stands on the plane of the ground under it, then each leg
    reaches down or folds up to the ground under its own foot (settling lower for a foot
    in a hollow): planted feet stand on the ground (they stood up to 13 cm off it with the
    plane alone), and every leg bone keeps its length."""
    rig = build_rig(load_creature("dog"))
    terrain = make_world("straight", "hills:amp=0.15,wavelength=3").terrain
    herd = Herd(rig, 30, seed=2)
    errors, stretch = [], []
    for k in range(200):
        herd.step(1 / 30, np.array([0.0, 0.05 * k]), 0.0)
        joints = herd.joints(terrain.height)
        ball = joints[:, :, 3]
        f0, f1, _ = herd.blend()
        planted = herd.cycle.contact[f0] & herd.cycle.contact[f1]
        off = ball[..., 1] - terrain.height(ball[..., [0, 2]].reshape(-1, 2)).reshape(ball.shape[:2])
        errors.append(np.abs(off[planted]))
        bones = np.linalg.norm(np.diff(joints, axis=2), axis=-1)
        upright = np.linalg.norm(np.diff(herd.joints(), axis=2), axis=-1)  # the same pose on flat ground
        stretch.append(np.abs(bones / upright - 1.0).max())
    assert np.concatenate(errors).max() < 1e-3
    assert max(stretch) < 1e-9
    flat = herd.transforms()[1]
    assert np.allclose(flat[:, 1], [0.0, 1.0, 0.0])  # on flat ground, upright


def test_a_herds_skinned_legs_follow_the_feet_set_down() -> None:
    """The skinned body's leg bones turn and move with the legs set down on the hill:
    each leg joint's posed matrix puts the joint where the solve put it."""
    from app.render.herd import HerdInstances

    rig = build_rig(load_creature("dog"))
    terrain = make_world("straight", "hills:amp=0.15,wavelength=3").terrain
    herd = Herd(rig, 6, seed=3)
    herd.phase = np.round(herd.phase * herd.cycle.frame_count) / herd.cycle.frame_count  # on cycle frames
    rows = HerdInstances(herd, body="skin")
    drawn = rows.frame(herd, terrain.height)
    joints, legs = herd.legs(terrain.height)
    assert legs is not None and np.abs(legs.foot_move).max() > 0.01  # the hills move some feet
    bind = drawn.bodies[0].body.bind
    for n, body in enumerate(drawn.bodies):
        world = body.skin.astype(np.float64) @ bind  # each joint's world matrix
        placed = world[rows._leg_bones, :3, 3]  # (L, 5, 3)
        assert np.abs(placed - joints[n]).max() < 2e-4, n  # (float32 matrices)


def test_a_herds_leg_shapes_follow_the_feet_set_down() -> None:
    """Drawn as parts, each animal's leg capsules run between the joints set down."""
    from app.render.herd import HerdInstances

    rig = build_rig(load_creature("dog"))
    terrain = make_world("straight", "hills:amp=0.15,wavelength=3").terrain
    herd = Herd(rig, 5, seed=4)
    drawn = HerdInstances(herd, body="parts", show_joints=False).frame(herd, terrain.height)
    joints = herd.joints(terrain.height)
    ends = drawn.capsules[:, 0:3].astype(np.float64)
    balls = joints[:, :, 3].reshape(-1, 3)
    nearest = np.linalg.norm(ends[:, None] - balls[None], axis=-1).min(axis=0)
    assert nearest.max() < 1e-4  # a bone starts at every ball


@pytest.mark.parametrize("count", [2, 3, 14])
def test_no_follower_walks_into_its_leader(count: int) -> None:
    """Every follower keeps at least a body length from the leader (its places start a
    spacing behind it), however few the herd."""
    rig = build_rig(load_creature("horse"))
    herd = Herd(rig, count)
    for k in range(600):
        herd.step(1 / 30, np.array([0.0, rig.ground_speed * k / 30]), 0.0)
        if k > 120:
            leader = np.array([0.0, rig.ground_speed * k / 30])
            assert np.linalg.norm(herd.position - leader, axis=1).min() > rig.body_length, k


def test_a_herds_legs_set_down_are_as_thick_as_on_flat_ground() -> None:
    """Set down on the ground, each animal's leg shapes keep its own size (a small dog's
    legs are thinner): on ground that is flat everywhere they equal the flat path's."""
    from app.render.herd import HerdInstances

    rig = build_rig(load_creature("dog"))
    herd = Herd(rig, 5, seed=6)
    rows = HerdInstances(herd, body="parts", show_joints=True)
    flat = rows.frame(herd, None)
    level = rows.frame(herd, lambda xz: np.zeros(len(xz)))
    assert flat.capsules.shape == level.capsules.shape and flat.ellipsoids.shape == level.ellipsoids.shape
    key = lambda a: a[np.lexsort(np.round(a, 4).T[::-1])]  # (rows in another order)
    assert np.allclose(key(flat.capsules), key(level.capsules), atol=1e-4)
    # (centres, radii, colours: a joint marker is a sphere, whose axes may point anywhere)
    columns = np.r_[0:3, 12:18]
    assert np.allclose(key(flat.ellipsoids[:, columns]), key(level.ellipsoids[:, columns]), atol=1e-4)


def test_setting_legs_down_keeps_bones_even_for_straight_and_reversed_legs() -> None:
    """Edge cases of the leg solve: a leg straight along the hip-ankle line still bends
    with its bones' lengths; opposite bone directions give a real rotation."""
    from app.kinematics.herd import legs_to_ground, rotation_between

    joints = np.array([[[[0, 1.0, 0], [0, 0.5, 0], [0, 0.0, 0], [0, -0.05, 0.05], [0, -0.05, 0.1]]]])
    raised = legs_to_ground(joints, lambda xz: np.full(len(xz), 0.1), np.zeros((1, 1)))
    bones = np.linalg.norm(np.diff(raised.joints[0, 0], axis=0), axis=-1)
    assert np.allclose(bones, np.linalg.norm(np.diff(joints[0, 0], axis=0), axis=-1))
    assert raised.joints[0, 0, 3, 1] == pytest.approx(0.1)  # the ball on the raised ground
    a = np.array([[0.0, 1.0, 0.0], [1.0, 0.0, 0.0]])
    turn = rotation_between(a, -a)
    assert np.allclose(np.einsum("nij,nj->ni", turn, a), -a)
    assert np.allclose(turn @ np.swapaxes(turn, -1, -2), np.eye(3)) and np.allclose(np.linalg.det(turn), 1.0)


def test_a_step_that_passes_a_whole_swing_lifts_and_lands_the_foot() -> None:
    """At a low frame rate a foot with a short swing can lift and land between two steps;
    it must re-lock where it lands, not stay locked a stride behind (it was 1.3 m off at a
    duty factor of 0.94 and 24 frames a second)."""
    rig = build_rig(load_creature("dog").with_overrides({"gait.duty_factor": 0.94}))
    herd = Herd(rig, 6, seed=4)
    fps = 24.0
    frames = 240
    leader = np.column_stack([np.zeros(frames), herd.cycle_speed / fps * np.arange(frames)])
    track = follow_leader(herd, leader, np.zeros(frames), fps)
    assert np.abs(track.foot_shift).max() < 0.5 * rig.hip_height
