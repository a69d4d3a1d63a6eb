"""The Path panel and waypoints: routes taken from where the creature is."""

from __future__ import annotations

import numpy as np
import pytest

from app import load_creature
from app.kinematics.path import SplicedPath, StraightPath
from app.kinematics.terrain import HillsTerrain
from app.kinematics.world import IN_PLACE, World
from app.render.camera import Camera, ground_point
from app.ui.state import ViewerState

DT = 1.0 / 60.0


def walk(state: ViewerState, seconds: float) -> list[np.ndarray]:
    roots = []
    for _ in range(int(round(seconds / DT))):
        state.advance(DT)
        pose = state.pose()
        state.note_pose(pose)
        roots.append(pose.root[:3, 3].copy())
        assert state.playing, state.error
    return roots


@pytest.mark.parametrize("creature", ["dog", "horse"])
@pytest.mark.parametrize("where", [(1.5, 1.0), (-1.5, 0.0), (0.5, -2.0), (-1.0, -6.0)])
def test_the_creature_goes_to_a_waypoint_anywhere_without_slipping(creature: str, where) -> None:
    state = ViewerState(load_creature(creature), world=World())
    walk(state, 0.5)
    length = state.live.rig.body_length
    target = np.array(where) * 2.0 * length
    assert state.add_waypoint(*target), state.error
    roots = np.array(walk(state, 20.0))
    assert np.linalg.norm(roots[:, [0, 2]] - target, axis=1).min() < 0.05 * length
    assert state.waypoints == []  # reached, so dropped
    assert state.planted_jump_max < 1e-6
    steps = np.linalg.norm(np.diff(roots[:, [0, 2]], axis=0), axis=1)
    assert steps.max() < 3.0 * np.median(steps)  # the body never jumps along the way


def test_waypoints_in_order_and_editing_them() -> None:
    state = ViewerState(load_creature("dog"), world=World())
    walk(state, 0.3)
    assert state.add_waypoint(1.0, 2.0) and state.add_waypoint(0.0, 4.0) and state.add_waypoint(1.0, 6.0)
    assert state.move_waypoint(1, -0.5, 4.0) and state.waypoints[1] == (-0.5, 4.0)
    assert state.delete_waypoint(2) and state.waypoints == [(1.0, 2.0), (-0.5, 4.0)]
    assert state.nearest_waypoint(0.9, 2.1, 0.2) == 0 and state.nearest_waypoint(5.0, 5.0, 0.2) is None
    roots = np.array(walk(state, 12.0))
    first = np.linalg.norm(roots[:, [0, 2]] - [1.0, 2.0], axis=1).argmin()
    second = np.linalg.norm(roots[:, [0, 2]] - [-0.5, 4.0], axis=1).argmin()
    assert first < second and state.waypoints == []
    assert isinstance(state.world.path, SplicedPath)


def test_a_path_kind_starts_where_the_body_is() -> None:
    state = ViewerState(load_creature("dog"), world=IN_PLACE)
    walk(state, 0.5)
    state.leave_in_place()
    before = state.pose().root[:3, 3]
    assert state.set_path("circle", r=1.5, dir="right"), state.error
    assert np.allclose(state.pose().root[:3, 3], before, atol=1e-3)  # nothing jumps at the switch
    roots = np.array(walk(state, 6.0))
    # A right-hand circle of radius 1.5 m: the body's distance from its centre stays 1.5.
    heading = 0.0
    centre = before[[0, 2]] + 1.5 * np.array([-np.cos(heading), np.sin(heading)])
    radius = np.linalg.norm(roots[:, [0, 2]] - centre, axis=1)
    assert np.abs(radius - 1.5).max() < 0.02
    assert state.planted_jump_max < 1e-6


@pytest.mark.parametrize("call, words", [
    (lambda s: s.set_path("circle", r=0.01), "too tight"),
    (lambda s: s.set_path("circle", r=-1.0), "r=-1"),
    (lambda s: s.set_path("spiral"), "unknown path"),
    (lambda s: s.add_waypoint(float("nan"), 1.0), "within 10 km"),
    (lambda s: s.add_waypoint(1e6, 0.0), "within 10 km"),
])
def test_bad_routes_show_the_error_and_change_nothing(call, words: str) -> None:
    state = ViewerState(load_creature("dog"), world=World())
    walk(state, 0.3)
    assert state.add_waypoint(1.0, 3.0)
    world, waypoints = state.world, list(state.waypoints)
    assert not call(state)
    assert words in state.error
    assert state.world is world and state.live.world is world and state.waypoints == waypoints
    walk(state, 0.3)


def test_ground_point_under_a_screen_position() -> None:
    camera = Camera(target=(0.0, 0.0, 0.0), azimuth=30.0, elevation=35.0, distance=6.0)
    flat = ground_point(camera, 1.5, (0.0, 0.0), lambda xz: np.zeros(len(xz)))
    assert flat is not None and np.allclose(flat, 0.0, atol=1e-3)  # the view's centre is the target
    assert ground_point(camera, 1.5, (0.0, 0.99), lambda xz: np.zeros(len(xz))) is not None
    sky = Camera(target=(0.0, 1.0, 0.0), azimuth=0.0, elevation=5.0, distance=6.0)
    assert ground_point(sky, 1.5, (0.0, 0.9), lambda xz: np.zeros(len(xz))) is None  # above the horizon
    hills = HillsTerrain(0.3, 2.0)
    hit = ground_point(camera, 1.5, (0.3, -0.2), hills.height)
    assert hit is not None and abs(hit[1] - hills.height(hit[None, [0, 2]])[0]) < 2e-3


def test_spliced_path_keeps_the_past() -> None:
    base = StraightPath()
    path = SplicedPath(base, 2.0, StraightPath(start=(0.0, 2.0), heading=0.5))
    s = np.linspace(-1.0, 2.0, 31)
    assert np.allclose(path.sample(s)[0], base.sample(s)[0])
    assert np.allclose(path.sample([2.0])[0], [[0.0, 2.0]])


def test_review_findings_stay_fixed() -> None:
    """Edits while driving, drags past the list, long editing sessions, close waypoints."""
    state = ViewerState(load_creature("dog"), world=World())
    walk(state, 0.3)
    # Editing the creature while cruising in drive mode (same speed, new rig).
    assert state.start_driving()
    walk(state, 0.5)
    assert state.set("gait.step_height", 0.2), state.error
    # A rejected route while driving keeps driving.
    assert not state.set_path("circle", r=0.01) and state.driver is not None
    # A waypoint just ahead (within a lead distance) is taken, and ends the drive.
    point, heading = state._here()
    ahead = point + 0.7 * state.live.rig.body_length * np.array([np.sin(heading), np.cos(heading)])
    assert state.add_waypoint(*ahead), state.error
    assert state.driver is None
    # Moving or deleting a waypoint that is gone changes nothing.
    assert not state.move_waypoint(5, 1.0, 1.0) and not state.delete_waypoint(-1)
    # Hundreds of edits (a drag) keep the path one flat list, quick to sample.
    for k in range(600):
        point, heading = state._here()
        target = point + 2.0 * np.array([np.sin(heading), np.cos(heading)]) + [0.001 * (k % 50), 0.0]
        assert state.set_waypoints([tuple(target)]), state.error
        state.advance(1.0 / 60.0)
    path = state.world.path
    assert isinstance(path, SplicedPath) and len(path.routes) <= SplicedPath.MAX_ROUTES
    import time

    t0 = time.perf_counter()
    path.sample(np.linspace(state.live.travel - 10.0, state.live.travel + 10.0, 2000))
    assert time.perf_counter() - t0 < 0.5


def test_targets_overlay_is_under_the_feet_in_place() -> None:
    state = ViewerState(load_creature("dog"), world=IN_PLACE)
    state.options = state.options.__class__(targets=True)
    walk(state, 2.0)
    overlays = state.overlays(state.pose())
    assert overlays is not None and len(overlays.targets)
    feet = state.pose().joints[:, 3]
    assert np.abs(overlays.targets[:, 2]).max() < np.abs(feet[:, 2]).max() + state.live.rig.body_length


@pytest.mark.parametrize("creature", ["centipede", "dog", "horse"])
@pytest.mark.parametrize("angle", [90.0, 180.0, 250.0])
def test_a_waypoint_close_beside_or_behind_is_looped_to_not_refused(creature: str, angle: float) -> None:
    """A click near the creature, beside or behind it, gets a loop it can walk (no tighter
    than its turn), reached without a planted foot moving."""
    state = ViewerState(load_creature(creature), world=World())
    walk(state, 0.3)
    length = state.live.rig.body_length
    a = np.radians(angle)
    target = np.array([np.sin(a), np.cos(a)]) * 0.7 * length + state.pose().root[[0, 2], 3]
    assert state.add_waypoint(*target), state.error
    roots = np.array(walk(state, 25.0))
    assert np.linalg.norm(roots[:, [0, 2]] - target, axis=1).min() < 0.1 * length
    assert state.planted_jump_max < 1e-6


def test_turn_towards_keeps_its_radius_and_ends_at_the_target() -> None:
    from app.kinematics.path import WaypointPath, turn_towards

    rng = np.random.default_rng(4)
    for target in rng.uniform(-3.0, 3.0, size=(30, 2)):
        if np.linalg.norm(target) < 0.2:
            continue
        way = turn_towards(np.zeros(2), 0.3, target, 0.5)
        assert np.allclose(way[0], 0.0) and np.allclose(way[-1], target)
        assert WaypointPath(way, start_direction=(np.sin(0.3), np.cos(0.3))).curvature_radius() >= 0.25
