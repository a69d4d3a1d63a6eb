"""A scene with several creatures in the viewer: all walk, one at a time in the panels."""

from __future__ import annotations

import numpy as np

from app.cli import build_parser
from app.resources import scenes_dir
from app.ui.state import ViewerState

DT = 1.0 / 60.0


def scene_state() -> ViewerState:
    from app.cli.inputs import load_cast

    args = build_parser().parse_args(["view", str(scenes_dir() / "garden.toml")])
    lead, *others = load_cast(args)
    state = ViewerState(lead.spec, world=lead.world)
    for actor in others:
        assert state.add_creature(actor.spec, actor.world), state.error
    return state


def test_every_scene_creature_walks_and_selection_swaps_the_panels() -> None:
    state = scene_state()
    assert state.names == ["ant", "centipede"] and state.selected == 0 and state.spec.name == "ant"
    start = [state.live.travel, state.others[0].live.travel]
    for _ in range(60):
        state.advance(DT)
    assert state.live.travel > start[0] and state.others[0].live.travel > start[1]  # both walk
    assert state.set("gait.step_height", 0.3) and state.spec.gait.step_height == 0.3  # edits the ant
    assert state.select(1) and state.spec.name == "centipede" and state.names == ["ant", "centipede"]
    assert state.others[0].spec.gait.step_height == 0.3  # the ant keeps its edit
    assert state.set("gait.step_height", 0.2) and state.spec.gait.step_height == 0.2
    assert state.undo() and state.spec.gait.step_height != 0.2  # the centipede's own history
    assert state.select(0) and state.spec.name == "ant" and state.spec.gait.step_height == 0.3
    assert not state.select(5) and "no creature 6" in state.error


def test_a_ray_picks_the_creature_it_meets() -> None:
    state = scene_state()
    for _ in range(30):
        state.advance(DT)
    centipede = state.others[0].live.pose().root[:3, 3]
    eye = centipede + np.array([0.0, 2.0, -3.0])
    direction = (centipede - eye) / np.linalg.norm(centipede - eye)
    assert state.pick_creature(eye, direction) == 1
    assert state.pick_creature(eye, -direction) is None  # looking away


def test_terrain_changes_reach_every_scene_creature() -> None:
    state = scene_state()
    assert state.set_terrain("hills", amp=0.01)
    assert all(m.live.world.terrain is state.world.terrain for m in state.others)
    for _ in range(60):
        state.advance(DT)
    assert state.playing, state.error
