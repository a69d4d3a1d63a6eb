"""The Terrain panel's control: the ground regenerated under a walking creature."""

from __future__ import annotations

import numpy as np
import pytest
from PIL import Image

from app import load_creature
from app.kinematics.world import IN_PLACE, World
from app.ui.state import ViewerState

DT = 1.0 / 60.0


def walk(state: ViewerState, seconds: float) -> None:
    for _ in range(int(round(seconds / DT))):
        state.advance(DT)
        state.note_pose(state.pose())
        assert state.playing, state.error


@pytest.mark.parametrize("creature", ["dog", "horse"])
def test_dragging_a_terrain_slider_under_a_walking_creature_moves_no_planted_foot(creature: str) -> None:
    state = ViewerState(load_creature(creature), world=World())
    walk(state, 0.5)
    hills = dict(state.terrain_values["hills"])
    stairs = dict(state.terrain_values["stairs"])
    assert state.set_terrain("hills")
    walk(state, 0.5)
    # Drags: a new value every frame, as a slider sends them.
    for kind, key, start, end in (("hills", "amp", hills["amp"], 1.6 * hills["amp"]),
                                  ("hills", "wavelength", hills["wavelength"], 2.0 * hills["wavelength"]),
                                  ("slope", "angle", 2.0, 8.0),
                                  ("stairs", "rise", 0.5 * stairs["rise"], 1.3 * stairs["rise"])):
        for value in np.linspace(start, end, 30):
            assert state.set_terrain(kind, **{key: float(value)}), state.error
            walk(state, DT)
        assert state.world.terrain.describe().startswith(kind)
        assert state.live.world is state.world
        walk(state, 0.5)
    assert state.planted_jump_max < 1e-3  # largest frame-to-frame move of a planted foot (m)
    assert state.footprints.count > 10


def test_switching_the_kind_of_ground_keeps_walking() -> None:
    state = ViewerState(load_creature("dog"), world=World())
    walk(state, 0.5)
    for kind in ("hills", "slope", "stairs", "hills", "flat"):
        assert state.set_terrain(kind), state.error
        walk(state, 0.7)
    # A foot that lands on new ground while another still stands on the old may be pulled
    # onto it over a few frames when the two are further apart than the legs allow.
    assert state.planted_jump_max < 0.05


def test_new_footholds_are_on_the_new_ground() -> None:
    state = ViewerState(load_creature("dog"), world=World())
    walk(state, 0.5)
    assert state.set_terrain("hills", amp=0.05)
    walk(state, 2.0)  # every foot has stepped since
    pose = state.pose()
    ball = pose.joints[pose.contact, 3]
    ground = state.world.terrain.height(ball[:, [0, 2]])
    assert np.abs(ball[:, 1] - ground).max() < 1e-3
    assert np.abs(ground).max() > 1e-3  # and it is not flat there


def test_in_place_creature_starts_travelling_on_uneven_ground() -> None:
    state = ViewerState(load_creature("dog"), world=IN_PLACE)
    walk(state, 0.5)
    assert state.set_terrain("slope", angle=5.0)
    assert not state.world.in_place
    walk(state, 0.5)
    assert state.set_terrain("flat")
    assert state.planted_jump_max < 1e-3


@pytest.mark.parametrize("kind, change, words", [
    ("hills", {"amp": -1.0}, "amp=-1 must be >= 0"),
    ("slope", {"angle": 85.0}, "angle=85 must be <= 80"),
    ("heightmap", {"file": "missing.png"}, "no such file"),
    ("heightmap", {"file": ""}, "give the file"),
    ("mesh", {"file": "broken.obj"}, "mesh"),
])
def test_bad_terrain_input_shows_the_error_and_changes_nothing(tmp_path, monkeypatch, kind: str, change: dict,
                                                                words: str) -> None:
    monkeypatch.chdir(tmp_path)
    (tmp_path / "broken.obj").write_text("v 0 0 0\nf 1 2 3\n")
    state = ViewerState(load_creature("dog"), world=World())
    assert state.set_terrain("hills")
    world, values = state.world, {k: dict(v) for k, v in state.terrain_values.items()}
    assert not state.set_terrain(kind, **change)
    assert words in state.error
    assert state.world is world and state.live.world is world
    assert state.terrain_values == values and state.terrain_kind == "hills"
    walk(state, 0.2)


def test_a_heightmap_file_loads_as_ground(tmp_path) -> None:
    image = (np.add.outer(np.arange(64), np.arange(64)) * 2).astype(np.uint8)
    Image.fromarray(image).save(tmp_path / "ground.png")
    state = ViewerState(load_creature("dog"), world=World())
    assert state.set_terrain("heightmap", file=str(tmp_path / "ground.png"), size=40.0, height=0.2), state.error
    assert state.world.terrain.describe().startswith("heightmap:file=")
    walk(state, 1.0)
    assert state.planted_jump_max < 1e-3


@pytest.mark.parametrize("creature", ["spider", "dog"])
@pytest.mark.parametrize("kind, values", [("hills", {"amp": 0.12}), ("hills", {"amp": 0.25, "seed": 5}),
                                          ("stairs", {"rise": 0.15}), ("stairs", {"rise": 0.3})])
def test_a_terrain_edit_is_either_refused_at_once_or_walked(creature: str, kind: str, values: dict) -> None:
    """No dead ends: an edit the panel takes is walked on (20 s without a pause); one it
    refuses says why and changes nothing."""
    from app.worlds import make_world

    state = ViewerState(load_creature(creature), world=make_world("straight", "flat"))
    before = state.world.terrain.describe()
    if not state.set_terrain(kind, **values):
        assert state.error and state.world.terrain.describe() == before
        return
    for _ in range(600):
        state.advance(1.0 / 30.0)
        assert state.playing, state.error
