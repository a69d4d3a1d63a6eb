"""The skinned body: one closed surface per creature, weights that blend to one, and
vertices that follow their bones through a clip."""

from __future__ import annotations

import numpy as np
import pytest

from app import build_rig, load_creature
from app.kinematics.clip import clip_motion
from app.kinematics.skeleton import skeleton_clip
from app.resources import creatures_dir
from app.skin import build_body
from app.skin.body import _parts
from app.skin.sdf import capsule_distance, ellipsoid_distance, part_distances, smooth_union

PRESETS = sorted(p.stem for p in creatures_dir().glob("*.toml"))


@pytest.fixture(scope="module", params=PRESETS)
def built(request):
    rig = build_rig(load_creature(request.param))
    motion, _ = clip_motion(rig, 30.0, cycles=1.0)
    clip = skeleton_clip(motion)
    return request.param, motion, clip, build_body(motion, clip)


def test_the_body_is_one_closed_manifold_surface(built) -> None:
    import trimesh

    name, _, _, body = built
    mesh = trimesh.Trimesh(body.positions, body.faces, process=False)
    assert mesh.is_watertight and mesh.is_winding_consistent, name
    assert mesh.body_count == 1, name  # one piece, not a pile of parts
    assert mesh.volume > 0, name  # faces wound outwards
    assert np.allclose(np.linalg.norm(body.normals, axis=1), 1.0, atol=1e-4)


def test_skin_weights_are_non_negative_and_sum_to_one(built) -> None:
    name, _, clip, body = built
    assert body.weights.shape == body.joints.shape == (len(body.positions), 4)
    assert (body.weights >= 0).all(), name
    assert np.allclose(body.weights.sum(axis=1), 1.0, atol=1e-5), name
    assert body.joints.min() >= 0 and body.joints.max() < clip.world_position.shape[1]


def test_vertices_follow_their_bones_through_the_clip(built) -> None:
    """Skinned to later frames, the surface stays as close to the posed parts as it was in
    the bind pose (within a quarter of a typical part's radius, plus half a per cent of
    the creature's size: the grid thickens the thinnest legs to two cells)."""
    name, motion, clip, body = built

    def error(frame: int) -> float:
        capsules, ellipsoids, _ = _parts(motion.frames(frame))
        d = smooth_union(part_distances(body.posed(clip, frame), capsules, ellipsoids), 0.01)
        return float(np.percentile(np.abs(d), 95))

    capsules, ellipsoids, _ = _parts(motion)
    typical = float(np.median(np.concatenate([capsules[:, 6:8].ravel(), ellipsoids[:, 12:15].ravel()])))
    size = float(np.ptp(body.positions, axis=0).max())
    bind = error(0)
    for frame in (motion.frame_count // 3, 2 * motion.frame_count // 3):
        assert error(frame) <= bind + 0.25 * typical + 0.005 * size, (name, frame)


def test_the_body_s_normals_are_its_smooth_surface_s(built) -> None:
    """The vertex normals are the smooth union's own (its gradient), not the simplified
    mesh's (as faceted as its triangles: they blotched a dog's flank and shoulder with
    streaks): against the exact field's gradient at each vertex (central differences),
    the typical error is well under the mesh normals' (0.16 to 0.43 of it over the
    presets, against the field the body was built from: its blend, its thin parts
    thickened to 1.1 cells) and the large ones are smaller too."""
    import trimesh

    from app.skin.body import LIMB_BLEND, bound_parts, grid_parts
    from app.skin.sdf import limb_union

    name, motion, clip, body = built
    capsules, ellipsoids, _, (legs, arms, tail) = bound_parts(motion, clip)
    # The field the body was built from: its blend and its parts at least 1.1 cells thick.
    _, _, _, blend, capsules, ellipsoids = grid_parts(capsules, ellipsoids, body.detail)
    points, h = body.positions.astype(np.float64), 1e-4

    def field(q: np.ndarray) -> np.ndarray:
        return limb_union(part_distances(q, capsules, ellipsoids), blend, legs, arms, tail, LIMB_BLEND * blend)

    gradient = np.stack([(field(points + h * e) - field(points - h * e)) / (2 * h) for e in np.eye(3)], axis=1)
    gradient /= np.maximum(np.linalg.norm(gradient, axis=1, keepdims=True), 1e-12)
    mesh = np.asarray(trimesh.Trimesh(points, body.faces, process=False).vertex_normals)

    def error(normals: np.ndarray) -> np.ndarray:
        return np.degrees(np.arccos(np.clip(np.sum(normals * gradient, axis=1), -1.0, 1.0)))

    ours, theirs = error(body.normals.astype(np.float64)), error(mesh)
    assert np.median(ours) < 0.6 * np.median(theirs), name
    assert np.percentile(ours, 90) < np.percentile(theirs, 90), name


def test_the_posed_body_at_the_bind_frame_is_the_bind_mesh(built) -> None:
    _, _, clip, body = built
    assert np.allclose(body.posed(clip, 0), body.positions, atol=1e-5)


def test_part_distances_are_signed_distances() -> None:
    points = np.array([[0.0, 0.0, 0.0], [0.0, 2.0, 0.0], [3.0, 0.5, 0.0], [0.0, -1.0, 0.0]])
    d = capsule_distance(points, np.zeros(3), np.array([0.0, 1.0, 0.0]), 0.5, 0.5)
    assert d == pytest.approx([-0.5, 0.5, 2.5, 0.5])
    e = ellipsoid_distance(np.array([[2.0, 0.0, 0.0], [0.0, 0.0, 0.0]]), np.zeros(3), np.eye(3),
                           np.array([1.0, 2.0, 3.0]))
    assert e[0] == pytest.approx(1.0) and e[1] < 0
    # The smooth union is never above the nearest part and meets it away from joins.
    both = np.stack([np.array([0.3, 5.0]), np.array([0.3, -1.0])])
    u = smooth_union(both, 0.05)
    assert u[0] <= 0.3 and u[0] == pytest.approx(0.3 - 0.05 * np.log(2.0))
    assert u[1] == pytest.approx(-1.0, abs=1e-12)


def test_coarse_bodies_are_quick_and_closed() -> None:
    import trimesh

    rig = build_rig(load_creature("dog"))
    motion, _ = clip_motion(rig, 30.0, cycles=0.2)
    clip = skeleton_clip(motion)
    coarse = build_body(motion, clip, detail="coarse")
    full = build_body(motion, clip)
    assert len(coarse.faces) < len(full.faces)
    assert trimesh.Trimesh(coarse.positions, coarse.faces, process=False).is_watertight


@pytest.mark.parametrize("creature", ["human", "dog", "horse", "spider"])
def test_a_single_pose_is_skinned_like_the_clip_it_comes_from(creature: str) -> None:
    """The viewer skins one pose at a time: its skeleton is laid out as the body's bind
    skeleton (the same joints in the same order, rolled the same way), so every key
    pose's surface stays on its parts."""
    from app.kinematics.clip import frame_at
    from app.kinematics.world import World
    from app.render.bodies import BodyCache, motion_body, pose_body

    rig = build_rig(load_creature(creature))
    cache = BodyCache()
    for phase in np.linspace(0.0, 1.0, 8, endpoint=False):
        motion = frame_at(rig, float(phase / rig.gait.frequency), 60.0, World(in_place=True))
        draw = motion_body(motion, cache).frame(0)
        assert np.allclose(pose_body(motion.pose(0), rig, cache).skin, draw.skin, atol=1e-5)
        body = draw.body
        p = np.concatenate([body.positions, np.ones((len(body.positions), 1), np.float32)], axis=1).astype(float)
        posed = np.einsum("vk,vkij,vj->vi", body.weights.astype(float), draw.skin.astype(float)[body.joints], p)[:, :3]
        capsules, ellipsoids, _ = _parts(motion)
        off = np.abs(smooth_union(part_distances(posed, capsules, ellipsoids), 0.01))
        size = float(np.ptp(body.positions, axis=0).max())
        assert np.percentile(off, 95) < 0.015 * size, (creature, phase)


def test_the_viewer_gets_a_coarse_body_at_once_and_the_full_one_soon() -> None:
    import time

    from app.render.bodies import BodyCache

    rig = build_rig(load_creature("cat"))
    cache = BodyCache()
    first = cache.live(rig)
    assert first.detail == "coarse"
    deadline = time.monotonic() + 30.0
    while cache.live(rig).detail != "full" and time.monotonic() < deadline:
        time.sleep(0.05)
    full = cache.live(rig)
    assert full.detail == "full" and len(full.faces) > len(first.faces)
    assert np.allclose(full.bind, first.bind) and full.layout == first.layout  # the same skeleton either way


def test_a_body_depends_on_its_shape_not_on_the_gait_it_walks() -> None:
    """The body cache keys bodies by shape: a trotting dog's body is the walking dog's
    (bound in one standing-apart pose), so what a render shows never depends on which gait
    happened to build the body first."""
    from app.render.bodies import _build

    walk = build_rig(load_creature("dog"))
    trot = build_rig(load_creature("dog").with_overrides({"gait.preset": "trot"}))
    a, b = _build(walk, "coarse"), _build(trot, "coarse")
    assert a.positions.shape == b.positions.shape
    assert np.array_equal(a.positions, b.positions) and np.array_equal(a.bind, b.bind)


def test_limbs_join_the_trunk_but_not_each_other() -> None:
    """Parts of one limb or of the trunk blend by the blend width, and so does a leg with
    the trunk (a hip's fillet); a leg meets another leg, and an arm anything, by a narrower
    one. A capsule 1.5 cm from another merges with it across the gap when both are the
    trunk's or a leg joins the trunk, and leaves the gap open between two legs or an arm
    and the trunk (a spider's neighbouring legs were joined by a web that stretched into
    an H as they moved apart; a hanging arm's web folded as it swung)."""
    from app.skin.sdf import union_on_grid

    trunk = np.array([[0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.1, 0.1]])
    limb = np.array([[0.135, 0.0, 0.0, 0.135, 1.0, 0.0, 0.02, 0.02]])  # 1.5 cm from the trunk's surface
    capsules = np.concatenate([trunk, limb])
    axes = (np.array([0.1075]), np.array([0.5]), np.array([0.0]))  # the gap's middle
    no_ellipsoids = np.zeros((0, 15))

    def gap(legs: list[int], arms: list[int]) -> float:
        return float(union_on_grid(axes, capsules, no_ellipsoids, 0.03, np.array(legs), np.array(arms), 0.009)[0, 0, 0])

    assert float(union_on_grid(axes, capsules, no_ellipsoids, 0.03)[0, 0, 0]) < 0.0  # one body
    assert gap([0, 1], [0, 0]) < 0.0  # a leg joins the trunk
    assert gap([1, 2], [0, 0]) > 0.0  # two legs stay apart
    assert gap([0, 0], [0, 1]) > 0.0  # an arm stays off the trunk
    assert gap([1, 1], [0, 0]) < 0.0  # a leg's own parts blend


def test_each_leg_and_arm_is_its_own_limb() -> None:
    """Each leg's and arm's parts are labelled with their limb; the tail's segments (not
    the rump's cap, which starts at the tail's base) with the tail; a person's shoulder
    line moves with the chest, not with one arm."""
    from app.skin.body import bound_parts

    for name, legs, arms in (("human", {0, 1, 2}, {0, 1, 2}), ("dog", {0, 1, 2, 3, 4}, {0}),
                             ("spider", set(range(9)), {0})):
        motion, _ = clip_motion(build_rig(load_creature(name)), 30.0, cycles=0.5)
        clip = skeleton_clip(motion)
        capsules, _, part_joint, (leg, arm, tail) = bound_parts(motion, clip)
        assert set(leg.tolist()) == legs and set(arm.tolist()) == arms
        assert not np.any((leg > 0) & (arm > 0))
        names = clip.skeleton.names
        for k in set(legs) - {0}:  # one leg's parts all move with one leg's joints
            assert len({names[j].split("_")[0] for j in part_joint[leg == k]}) == 1
        assert all(names[j].startswith("tail") for j in part_joint[tail])
        assert tail.sum() == motion.rig.body.tail_segments, name  # the dog's seven; not the rump's cap
        if name == "human":
            shoulders = motion.arms[0, :, 0]
            line = np.flatnonzero(np.linalg.norm(capsules[:, 0:3] - shoulders[0], axis=1)
                                  + np.linalg.norm(capsules[:, 3:6] - shoulders[1], axis=1) < 1e-6)
            assert len(line) == 1 and arm[line[0]] == 0 and names[part_joint[line[0]]].startswith("spine")


def _folds_near_hips(monkeypatch, root_spread: float) -> float:
    """Faces within 15 cm of a hip turned over (against the bind pose's normal carried by
    their joints) per frame, on average, as the dog climbs stairs."""
    from app import simulate
    from app.render.bodies import BodyCache, motion_body
    from app.skin import body as skin_body

    monkeypatch.setattr(skin_body, "ROOT_SPREAD", root_spread)
    motion = simulate("dog", seconds=4.0, fps=15, terrain="stairs")
    draw = motion_body(motion, BodyCache())
    body, skin = draw.body, draw.skin.astype(np.float64)
    faces = body.faces
    bind = body.positions.astype(np.float64)

    def normals(v: np.ndarray) -> np.ndarray:
        return np.cross(v[faces[:, 1]] - v[faces[:, 0]], v[faces[:, 2]] - v[faces[:, 0]])

    names = skeleton_clip(motion).skeleton.names
    hips = body.bind[[j for j, n in enumerate(names) if n.endswith("_hip")], :3, 3]
    near = np.linalg.norm(bind[faces].mean(axis=1)[:, None] - hips[None], axis=-1).min(axis=1) < 0.15
    points = np.concatenate([bind, np.ones((len(bind), 1))], axis=1)
    folds = []
    for frame in skin:
        blended = np.einsum("vk,vkij->vij", body.weights.astype(np.float64), frame[body.joints])
        moved = np.einsum("vij,vj->vi", blended, points)[:, :3]
        carried = np.einsum("fij,fj->fi", blended[faces[:, 0], :3, :3], normals(bind))
        folds.append(np.count_nonzero((np.einsum("fi,fi->f", normals(moved), carried) < 0.0) & near))
    return float(np.mean(folds))


def test_the_trunk_and_the_top_of_a_leg_share_their_vertices(monkeypatch) -> None:
    """About each hip and shoulder the weights are spread wider (ROOT_SPREAD): the thigh's
    vertices swung through the trunk's as a hind leg reached far back on stairs, a jagged
    crease on the rump. Fewer faces fold there (about a fifth fewer)."""
    from app.skin import body as skin_body

    shared = _folds_near_hips(monkeypatch, skin_body.ROOT_SPREAD)
    narrow = _folds_near_hips(monkeypatch, 1.0)
    assert shared < 0.9 * narrow, (shared, narrow)


def test_the_grid_union_is_the_limb_union_sampled() -> None:
    """:func:`union_on_grid` (accumulated part by part, each leg over its own box) agrees
    with :func:`limb_union` worked out at the points, near the surface (the tail's own
    union, by the narrow blend, once left out the tail 8 cm from the trunk)."""
    from app.skin.sdf import limb_union, union_on_grid

    capsules = np.array([
        [0.0, 0.3, -0.2, 0.0, 0.3, 0.2, 0.10, 0.12],  # trunk
        [0.06, 0.3, 0.15, 0.07, 0.0, 0.15, 0.03, 0.02],  # left leg
        [-0.06, 0.3, 0.15, -0.07, 0.0, 0.15, 0.03, 0.02],  # right leg, close beside it
        [0.0, 0.3, -0.2, 0.0, 0.32, -0.35, 0.03, 0.025],  # tail, two segments
        [0.0, 0.32, -0.35, 0.0, 0.34, -0.5, 0.025, 0.02],
        [0.14, 0.4, 0.0, 0.15, 0.2, 0.0, 0.02, 0.02],  # an arm hanging by the trunk
    ])
    ellipsoids = np.zeros((0, 15))
    legs, arms = np.array([0, 1, 2, 0, 0, 0]), np.array([0, 0, 0, 0, 0, 1])
    tail = np.array([False, False, False, True, True, False])
    axes = tuple(np.linspace(-0.3, 0.6, 31) for _ in range(3))
    blend, narrow = 0.03, 0.009
    grid = union_on_grid(axes, capsules, ellipsoids, blend, legs, arms, narrow, tail)  # type: ignore[arg-type]
    points = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, 3)
    exact = limb_union(part_distances(points, capsules, ellipsoids), blend, legs, arms, tail, narrow)
    near = np.abs(exact) < 0.5 * blend  # where the surface is (each part is left out beyond four blends of its box)
    assert near.sum() > 100
    assert np.abs(grid.ravel()[near] - exact[near]).max() < 0.05 * blend


def test_a_black_coat_keeps_every_part_of_its_skin() -> None:
    """The parts drawn on the skin rather than in it (eyes, mane) and the hooves are found by
    where they are, not by their colour: a black dog lost its skull and neck from its skin,
    their colour matching a mane's (a third of the coat's)."""
    from app.kinematics.clip import clip_motion
    from app.skin.body import _parts

    for name in ("dog", "horse"):
        counts = []
        for coat in ("#b38b5d", "#000000"):
            rig = build_rig(load_creature(name).with_overrides({"look.body_color": coat}))
            motion, _ = clip_motion(rig, 30.0, cycles=0.25)
            capsules, ellipsoids, _ = _parts(motion)
            counts.append((len(capsules), len(ellipsoids)))
        assert counts[0] == counts[1], (name, counts)


@pytest.mark.parametrize("name", ["horse", "deer", "dog", "human", "theropod"])
def test_the_eyes_stand_half_out_of_the_skin(name: str) -> None:
    """The eyes sit on the skinned body, not in it: along the line from the skull's centre
    through each eye, at least half the eye's reach lies outside the skin. They were set
    on the skull, and the skin blended over skull, jowl and neck buried a horse's to a
    dot a few pixels across."""
    from app.render.bodies import _build, bind_motion
    from app.render.scene import EYE_COLOR, feature_anchors
    from app.skin.features import _first_hit

    rig = build_rig(load_creature(name))
    body = _build(rig, "full")
    features = body.features
    assert features is not None
    skull = feature_anchors(bind_motion(rig))  # the motion the body is bound in
    skull = skull[np.all(np.isfinite(skull), axis=1)][0]
    eye = np.all(np.abs(features.colors - EYE_COLOR) < 1e-5, axis=1)
    per = eye.sum() // 2
    assert eye.sum() == 2 * per
    positions = features.positions[eye].astype(np.float64).reshape(2, per, 3)
    centres = positions.mean(axis=1)
    direction = (centres - skull) / np.linalg.norm(centres - skull, axis=1, keepdims=True)
    outermost = np.max(np.einsum("kvi,ki->kv", positions - skull, direction), axis=1)
    reach = outermost - np.einsum("ki,ki->k", centres - skull, direction)
    skin = _first_hit(np.tile(skull, (2, 1)), direction, body.positions.astype(np.float64)[body.faces])
    assert np.all(np.isfinite(skin))
    assert np.all(outermost - skin >= 0.45 * reach), (name, outermost - skin, reach)
