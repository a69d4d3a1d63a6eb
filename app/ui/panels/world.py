"""Where the creature walks: the Terrain and Path panels."""

from __future__ import annotations

from dataclasses import replace

from imgui_bundle import imgui

from ...worlds.kinds import TERRAIN_KINDS
from ..state import ViewerState
from .widgets import PanelContext, _begin_rows, _checkbox, _label, _remember, shown


def terrain_panel(state: ViewerState, pc: PanelContext) -> None:
    """The ground under the creature, regenerated live as values change. The kinds, keys,
    ranges and help are the command line's (:data:`app.worlds.kinds.TERRAIN_KINDS`)."""
    kinds = list(TERRAIN_KINDS)
    imgui.set_next_item_width(-1)
    changed, index = imgui.combo("##terrain-kind", kinds.index(state.terrain_kind), kinds)
    _remember(state, "terrain.kind")
    from_file = ("heightmap", "mesh")
    if changed and kinds[index] not in from_file:
        state.set_terrain(kinds[index])
    elif changed:
        state.terrain_kind = kinds[index]  # pick the file first, then load
    kind = TERRAIN_KINDS[state.terrain_kind]
    values = state.terrain_values[kind.name]
    top = imgui.get_cursor_pos_y()
    if kind.name in from_file:
        imgui.set_next_item_width(-70 * pc.scale)
        _, values["file"] = imgui.input_text_with_hint("##terrain-file", "image or mesh file path", values["file"])
        _remember(state, "terrain.file")
        imgui.same_line()
        if imgui.button("load##terrain", imgui.ImVec2(-1, 0)):
            state.set_terrain(kind.name)
        _remember(state, "terrain.load")
    sliders = [key for key in kind.keys if key.slider is not None]
    if sliders and _begin_rows(f"terrain-{kind.name}", pc):
        for key in sliders:
            assert key.slider is not None
            lo, hi = key.slider
            _label(key.name, f"{key.help} ({key.unit})" if key.unit else key.help)
            fmt = key.fmt if key.integer or not key.unit or key.fmt.endswith(key.unit) else f"{key.fmt} {key.unit}"
            value: float
            if key.integer:
                changed, value = imgui.slider_int(f"##terrain-{key.name}", int(values[key.name]), int(lo), int(hi), fmt)
            else:
                changed, number = imgui.slider_float(f"##terrain-{key.name}", float(values[key.name]), lo, hi, fmt)
                value = shown(float(number), fmt.split()[0])
            _remember(state, f"terrain.{key.name}")
            imgui.table_next_column()
            if changed and value != values[key.name] and (kind.name not in from_file or values["file"]):
                state.set_terrain(kind.name, **{key.name: value})
            elif changed:
                values[key.name] = value
        imgui.end_table()
    # Room for the kind with the most rows: picking another kind moves nothing below.
    style = imgui.get_style()
    row = imgui.get_frame_height() + 2.0 * style.cell_padding.y
    most = max(len([k for k in other.keys if k.slider is not None]) + (other.name in from_file)
               for other in TERRAIN_KINDS.values())
    short = top + most * row - imgui.get_cursor_pos_y()
    if short > 0:
        imgui.dummy(imgui.ImVec2(1.0, short))
    imgui.text_disabled(f"now: {state.world.terrain.describe()}"[:60])


def path_panel(state: ViewerState, pc: PanelContext) -> None:
    """The route from here on: a kind with its values, or waypoints edited on the ground."""
    kinds = list(state.path_values)
    imgui.set_next_item_width(-1)
    changed, index = imgui.combo("##path-kind", kinds.index(state.path_kind), kinds)
    _remember(state, "path.kind")
    if changed:
        state.set_path(kinds[index])
    kind = state.path_kind
    values = state.path_values[kind]
    if kind in ("circle", "figure-eight") and _begin_rows(f"path-{kind}", pc):
        _label("radius", "the turning circle's radius, from where the creature is now")
        changed, radius = imgui.slider_float("##path-r", float(values["r"]), 0.1, 20.0, "%.2f m")
        _remember(state, "path.r")
        imgui.table_next_column()
        if changed:  # live: each value re-routes from where the creature is
            state.set_path(kind, r=shown(float(radius), "%.2f"))
        if kind == "circle":
            _label("turning", "which way the circle turns")
            sides = ["left", "right"]
            changed, side = imgui.combo("##path-dir", sides.index(values["dir"]), sides)
            imgui.table_next_column()
            if changed:
                state.set_path(kind, dir=sides[side])
        imgui.end_table()
    changed, edit = _checkbox(state, "path.edit", "edit waypoints on the ground", state.waypoint_edit,
                              "Click on the ground to add a waypoint (the creature goes there next), drag one to "
                              "move it, right-click one to delete it. Reached waypoints are dropped.")
    if changed:
        state.waypoint_edit = edit
        if edit:
            state.leave_in_place()
        if edit and not state.options.path:
            state.options = replace(state.options, path=True)
    imgui.text_disabled(f"{len(state.waypoints)} waypoint(s) ahead")
    if state.waypoints:
        imgui.same_line()
        if imgui.small_button("clear##waypoints"):
            state.set_waypoints([])
        _remember(state, "path.clear")
