"""The viewer's panels, HUD and help overlay: imgui widgets that call :class:`ViewerState`.

Every value is shown in a slider (Ctrl+click to type a number) with a reset button that
gives it back its value from the loaded creature. No logic lives here beyond layout.

- :mod:`.widgets`: the building blocks and the context every panel gets;
- :mod:`.creature`, :mod:`.view`, :mod:`.world`, :mod:`.files`: the panels;
- here: the sidebar, the message bar, the signs, the HUD and the help overlay.
"""

from __future__ import annotations

from imgui_bundle import imgui

from ..state import ViewerState
from .creature import body_panel, creature_panel, gait_panel, poses_panel
from .files import file_panel, record_panel
from .view import playback_panel, plots_panel, view_panel
from .widgets import _ERROR, _OK, SHORTCUTS, SIDEBAR_COLOR, SIDEBAR_WIDTH, PanelContext, _remember
from .world import path_panel, terrain_panel

PANELS = (
    ("Creature", creature_panel, True),
    ("Gait", gait_panel, True),
    ("Key poses", poses_panel, False),
    ("Body", body_panel, False),
    ("View", view_panel, False),
    ("Terrain", terrain_panel, False),
    ("Path", path_panel, False),
    ("Playback", playback_panel, True),
    ("Plots", plots_panel, False),
    ("Record", record_panel, False),
    ("File", file_panel, False),
)



# Window flags, combined once (an enum's | is a Python call, and these windows are built every frame).
# The sidebar: the scrollbar's room is always kept, so panels opening never change the
# sliders' width; no ImGui background: the viewer clears the sidebar's rectangle to
# SIDEBAR_COLOR, much cheaper than a blended full-height quad on a software rasteriser.
_SIDEBAR_FLAGS = (imgui.WindowFlags_.no_move | imgui.WindowFlags_.no_resize | imgui.WindowFlags_.no_collapse
                  | imgui.WindowFlags_.no_title_bar | imgui.WindowFlags_.no_background
                  | imgui.WindowFlags_.always_vertical_scrollbar)
_MESSAGE_FLAGS = (imgui.WindowFlags_.no_decoration | imgui.WindowFlags_.no_saved_settings | imgui.WindowFlags_.no_nav
                  | imgui.WindowFlags_.no_focus_on_appearing | imgui.WindowFlags_.always_auto_resize)
_SIGN_FLAGS = _MESSAGE_FLAGS | imgui.WindowFlags_.no_inputs  # HUDs and signs over the 3-D view: no input

def sidebar(state: ViewerState, pc: PanelContext, extra_panels=()) -> None:
    io = imgui.get_io()
    width = SIDEBAR_WIDTH * pc.scale
    imgui.set_next_window_pos(imgui.ImVec2(0, 0))
    imgui.set_next_window_size(imgui.ImVec2(width, io.display_size.y))
    imgui.begin("Gaitlab", None, _SIDEBAR_FLAGS)
    gait = f"{state.driver.gait} (driving)" if state.driver is not None else state.spec.gait.preset
    imgui.text(f"Gaitlab  -  {state.spec.name}, {gait}")
    imgui.text_disabled("F1 help  -  Tab hide UI")
    for title, draw, default_open in (*PANELS, *extra_panels):
        flag = imgui.TreeNodeFlags_.default_open if default_open else 0
        if pc.open_at_start:  # --panels: these open at start, the others closed
            imgui.set_next_item_open(title in pc.open_at_start, imgui.Cond_.once)
        opened = imgui.collapsing_header(title, flag)
        _remember(state, f"panel.{title}")
        if opened:
            imgui.push_id(title)
            draw(state, pc)
            imgui.pop_id()
    imgui.end()


def message_bar(state: ViewerState, pc: PanelContext) -> None:
    """One fixed line along the bottom of the 3-D view: the newest message with its time
    (each replaces the last), and a recording's progress, whether or not a panel is open."""
    io = imgui.get_io()
    left = SIDEBAR_WIDTH * pc.scale if state.show_ui else 0.0
    imgui.set_next_window_pos(imgui.ImVec2(left, io.display_size.y), 0, imgui.ImVec2(0.0, 1.0))
    imgui.set_next_window_size(imgui.ImVec2(io.display_size.x - left, 0.0))
    imgui.set_next_window_bg_alpha(0.8)
    if state.message is None and pc.recording_progress is None:
        return
    imgui.begin("##messages", None, _MESSAGE_FLAGS)
    if pc.recording_progress is not None:
        imgui.progress_bar(pc.recording_progress, imgui.ImVec2(-1, 0), pc.recording_label)
    if state.message is not None:
        kind, text, stamp = state.message
        imgui.push_text_wrap_pos(0.0)
        imgui.text_colored(_ERROR if kind == "error" else _OK, f"{stamp}  {text}")
        imgui.pop_text_wrap_pos()
    _remember(state, "message")
    imgui.end()


def _begin_sign(name: str) -> None:
    """Begin a small window over the 3-D view that takes no input (HUDs, the PAUSED sign);
    place it and set its background first, end it with ``imgui.end()``."""
    imgui.begin(name, None, _SIGN_FLAGS)


def paused_marker(state: ViewerState, pc: PanelContext) -> None:
    """A PAUSED sign over the 3-D view while the animation is stopped (issue 12, item 5)."""
    io = imgui.get_io()
    left = SIDEBAR_WIDTH * pc.scale if state.show_ui else 0.0
    imgui.set_next_window_pos(imgui.ImVec2(left + 0.5 * (io.display_size.x - left), 14 * pc.scale), 0,
                              imgui.ImVec2(0.5, 0.0))
    imgui.set_next_window_bg_alpha(0.75)
    _begin_sign("##paused")
    imgui.text_colored(imgui.ImVec4(1.0, 0.8, 0.35, 1.0), "PAUSED")
    imgui.same_line()
    imgui.text_disabled("Space to play, Right to step")
    imgui.end()


def hud(pc: PanelContext) -> None:
    io = imgui.get_io()
    s = pc.stats
    pad = 10 * pc.scale
    imgui.set_next_window_pos(imgui.ImVec2(io.display_size.x - pad, pad), 0, imgui.ImVec2(1.0, 0.0))
    imgui.set_next_window_bg_alpha(0.72)
    _begin_sign("##hud")
    imgui.text(f"{s.fps:5.1f} fps   {s.frame_ms:5.1f} ms")
    imgui.text(f"simulate {s.simulate_ms:4.1f}  scene {s.scene_ms:4.1f}  ui {s.ui_ms:4.1f} ms")
    imgui.end()


def drive_hud(state: ViewerState, pc: PanelContext) -> None:
    """Speed, Froude number and gait over the 3-D view while driving."""
    driver = state.driver
    if driver is None:
        return
    left = SIDEBAR_WIDTH * pc.scale if state.show_ui else 0.0
    pad = 10 * pc.scale
    imgui.set_next_window_pos(imgui.ImVec2(left + pad, pad), 0, imgui.ImVec2(0.0, 0.0))
    imgui.set_next_window_bg_alpha(0.72)
    _begin_sign("##drive-hud")
    imgui.text_colored(imgui.ImVec4(0.55, 0.85, 1.0, 1.0), "DRIVING")
    imgui.same_line()
    imgui.text(f"{driver.ground_speed:5.2f} m/s   Froude {driver.ground_froude:5.2f}   {driver.gait}")
    turn = "left" if driver.curvature > 1e-6 else "right" if driver.curvature < -1e-6 else "straight"
    imgui.text_disabled(f"asked {driver.target_speed:.2f} m/s, turning {turn}   W/S speed  A/D turn  Esc stop")
    imgui.end()


def help_overlay(state: ViewerState, pc: PanelContext) -> None:
    io = imgui.get_io()
    imgui.set_next_window_pos(imgui.ImVec2(io.display_size.x * 0.5, io.display_size.y * 0.5), 0,
                              imgui.ImVec2(0.5, 0.5))
    imgui.set_next_window_bg_alpha(0.92)
    flags = imgui.WindowFlags_.always_auto_resize | imgui.WindowFlags_.no_collapse
    _, still_open = imgui.begin("Keyboard and mouse (F1)", True, flags)
    if imgui.begin_table("keys", 2, imgui.TableFlags_.row_bg | imgui.TableFlags_.borders_inner_v):
        for key, what in SHORTCUTS:
            imgui.table_next_column()
            imgui.text(key)
            imgui.table_next_column()
            imgui.text(what)
        imgui.end_table()
    imgui.text_disabled("Sliders: Ctrl+click to type a value; the arrow button resets it.")
    imgui.end()
    if not still_open:
        state.show_help = False


def draw_ui(state: ViewerState, pc: PanelContext, extra_panels=()) -> None:
    """All of the viewer's UI for one frame."""
    if state.show_ui:
        sidebar(state, pc, extra_panels)
        hud(pc)
    drive_hud(state, pc)
    if not state.playing:
        paused_marker(state, pc)
    message_bar(state, pc)
    if state.show_help:
        help_overlay(state, pc)


__all__ = ["PANELS", "SIDEBAR_COLOR", "SIDEBAR_WIDTH", "PanelContext", "draw_ui"]
