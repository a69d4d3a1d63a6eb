"""The view's panels: what is drawn, playback, the live plots."""

from __future__ import annotations

import numpy as np
from imgui_bundle import imgui, implot

from ...choices import ARC_JOINTS, CAMERA_PRESETS
from ..state import ViewerState
from .widgets import (
    _ARC_HEX,
    ICON_PAUSE,
    ICON_PLAY,
    ICON_RESET,
    ICON_STEP,
    PanelContext,
    _begin_rows,
    _checkbox,
    _hex_color,
    _icon,
    _label,
    _remember,
    _wrapped_note,
    shown,
)


def view_panel(state: ViewerState, pc: PanelContext) -> None:
    per_row = 3
    gap = imgui.get_style().item_spacing.x
    width = (imgui.get_content_region_avail().x - gap * (per_row - 1)) / per_row
    for i, preset in enumerate(CAMERA_PRESETS):
        if i % per_row:
            imgui.same_line()
        if imgui.button(preset, imgui.ImVec2(width, 0)):
            state.frame_view(preset)
        _remember(state, f"camera.{preset}")
    if imgui.button("side, orthographic (for animators)", imgui.ImVec2(-1, 0)):
        state.side_ortho()
    changed, ortho = imgui.checkbox("orthographic", state.camera.ortho)
    if changed:
        state.set_ortho(ortho)
    imgui.same_line()
    changed, state.follow = imgui.checkbox("follow", state.follow)
    from dataclasses import replace

    options = state.options
    imgui.same_line()
    changed_b, smooth = _checkbox(state, "view.smooth_body", "smooth body", options.body == "skin",
                                  "One smooth skinned body; off: the capsules and ellipsoids it is made from.")
    changed_g, grid = imgui.checkbox("grid", options.grid)
    imgui.same_line()
    changed_s, shadow = imgui.checkbox("shadow", options.shadow)
    imgui.same_line()
    changed_p, path = imgui.checkbox("path", options.path)
    imgui.same_line()
    imgui.begin_disabled(smooth)  # what the parts body alone shows (as ticked this frame)
    changed_j, joints = _checkbox(state, "view.joints", "joints", options.joints,
                                  "Markers at the knees, ankles and balls (with the smooth body off: it covers them).")
    imgui.same_line()
    changed_c, by_side = _checkbox(state, "view.side_colors", "sides", options.side_colors,
                                   "Colour legs and arms by side: left in the look's left colour, right in its\n"
                                   "right colour (with the smooth body off).")
    imgui.end_disabled()
    if changed_g or changed_s or changed_j or changed_p or changed_b or changed_c:
        state.options = replace(options, grid=grid, shadow=shadow, joints=joints, path=path,
                                body="skin" if smooth else "parts", side_colors=by_side)
    imgui.separator_text("overlays")
    options = state.options
    changed_f, footprints = _checkbox(state, "overlay.footprints", "footprints", options.footprints,
                                      "The last footprints on the ground, in each leg's side colour, fading with age.")
    imgui.same_line()
    changed_t, targets = _checkbox(state, "overlay.targets", "targets", options.targets,
                                   "Amber rings where the swinging feet will touch down.")
    imgui.same_line()
    changed_u, support = _checkbox(state, "overlay.support", "support", options.support,
                                   "The polygon of the planted feet and the trunk's centre dropped onto the ground:\n"
                                   "green inside (statically stable), red outside.")
    # Always there, greyed out while footprints are off: ticking them inserts no row.
    imgui.begin_disabled(not options.footprints)
    imgui.set_next_item_width(-1)
    _changed_n, count = imgui.slider_int("##footprint-count", options.footprint_count, 2, 200, "%d footprints")
    _remember(state, "overlay.footprint_count")
    imgui.end_disabled()
    if changed_f or changed_t or changed_u or count != options.footprint_count:
        state.options = replace(options, footprints=footprints, targets=targets, support=support,
                                footprint_count=int(count))
    imgui.separator_text("arcs (the last cycle; right limbs darker)")
    chosen = list(state.options.arcs)
    for i, joint in enumerate(ARC_JOINTS):
        if i % 4:
            imgui.same_line()
        imgui.push_style_color(imgui.Col_.check_mark, _hex_color(_ARC_HEX[joint]))
        changed, on = _checkbox(state, f"arc.{joint}", joint, joint in chosen)
        imgui.pop_style_color()
        if changed:
            chosen = [j for j in ARC_JOINTS if (on if j == joint else j in chosen)]
            state.options = replace(state.options, arcs=tuple(chosen))


def playback_panel(state: ViewerState, pc: PanelContext) -> None:
    label = _icon(pc, ICON_PAUSE, "pause") if state.playing else _icon(pc, ICON_PLAY, "play")
    if imgui.button(f"{label}##play", imgui.ImVec2(110 * pc.scale, 0)):
        state.toggle_play()
    _remember(state, "play")
    imgui.same_line()
    if imgui.button(_icon(pc, ICON_STEP, "step"), imgui.ImVec2(90 * pc.scale, 0)):
        state.step_frame()
    imgui.same_line()
    imgui.text(f"t = {state.live.time:.2f} s")
    if _begin_rows("playback", pc):
        _label("time scale", "How fast the animation runs against the clock (1 = real time).")
        changed, scale = imgui.slider_float("##time-scale", state.time_scale, 0.0, 3.0, "%.2fx")
        if changed:
            state.time_scale = shown(float(scale), "%.2f")
        imgui.table_next_column()
        imgui.begin_disabled(state.time_scale == 1.0)
        if imgui.small_button(f"{ICON_RESET if pc.icons else 'R'}##reset-time-scale"):
            state.time_scale = 1.0
        imgui.end_disabled()
        _label("cycle phase", "Where the gait is within its cycle; dragging pauses the animation.")
        changed, phase = imgui.slider_float("##phase", state.live.phase, 0.0, 0.999, "%.3f")
        _remember(state, "phase")
        if changed:
            state.scrub(float(phase))
        imgui.table_next_column()
        if imgui.small_button(f"{ICON_RESET if pc.icons else 'R'}##reset-phase"):
            state.scrub(0.0)
        _label("drive", "Steer the creature with the keyboard: W/S or Up/Down set the speed, A/D or "
                        "Left/Right turn, Esc stops. The gait follows the speed (walk, trot, gallop by "
                        "Froude number).")
        changed, on = imgui.checkbox("W A S D##drive", state.driver is not None)
        _remember(state, "drive")
        if changed:
            state.start_driving() if on else state.stop_driving()
        imgui.table_next_column()
        driver = state.driver
        if driver is not None:
            _label("asked speed", "The speed W and S move; the creature reaches it at its acceleration limit.")
            changed, speed = imgui.slider_float("##drive-speed", driver.target_speed, driver.min_speed,
                                                driver.max_speed, "%.2f m/s")
            _remember(state, "drive-speed")
            if changed:
                driver.set_target_speed(float(speed))
            imgui.table_next_column()
        imgui.end_table()


def plots_panel(state: ViewerState, pc: PanelContext) -> None:
    """Live foot heights, the gait diagram, and measured vs requested duty and phase."""
    monitor = pc.monitor
    if monitor is None:
        return
    monitor.wanted = True  # measure only while someone is looking
    times = monitor.times
    names = monitor.names
    width = -1
    if len(times) > 1:
        t = (times - times[-1]).astype(np.float64)
        heights = monitor.heights() * 100.0
        if implot.begin_plot("foot heights", imgui.ImVec2(width, 170 * pc.scale)):
            implot.setup_axes("time (s)", "height (cm)")
            # The legend beside the curves, never over them.
            implot.setup_legend(implot.Location_.east, implot.LegendFlags_.outside)
            implot.setup_axis_limits(implot.ImAxis_.x1, -monitor.seconds, 0.0, implot.Cond_.always)
            # The height axis fits the data (a gallop or a high step is never clipped).
            low, high = float(np.nanmin(heights)), float(np.nanmax(heights))
            pad = max(0.08 * (high - low), 0.5)
            implot.setup_axis_limits(implot.ImAxis_.y1, min(low, 0.0) - pad, high + pad, implot.Cond_.always)
            for i, name in enumerate(names):
                implot.plot_line(name, t, np.ascontiguousarray(heights[:, i]))
            implot.end_plot()
        contact = monitor.contact()
        if implot.begin_plot("gait diagram (stance)", imgui.ImVec2(width, 130 * pc.scale),
                             implot.Flags_.no_legend | implot.Flags_.no_mouse_text):
            implot.setup_axes("time (s)", "", 0, implot.AxisFlags_.invert)
            implot.setup_axis_limits(implot.ImAxis_.x1, -monitor.seconds, 0.0, implot.Cond_.always)
            implot.setup_axis_limits(implot.ImAxis_.y1, -0.6, len(names) - 0.4, implot.Cond_.always)
            implot.setup_axis_ticks(implot.ImAxis_.y1, 0.0, len(names) - 1.0, len(names), list(names))
            spec = implot.Spec()
            spec.line_weight = 7.0 * pc.scale
            for i, name in enumerate(names):
                rows = np.where(contact[:, i], float(i), np.nan)
                implot.plot_line(name, t, rows, spec)
            implot.end_plot()
    report = monitor.report
    gait = state.live.rig.gait
    requested = dict(zip(state.live.rig.leg_names, gait.offsets))
    if report is not None:
        imgui.text(f"measured: {report.gait_match}   cycle {report.cycle_seconds:.3f} s")
    elif monitor.error:
        _wrapped_note(monitor.error)
    flags = imgui.TableFlags_.row_bg | imgui.TableFlags_.borders_inner_v | imgui.TableFlags_.sizing_stretch_same
    if imgui.begin_table("measured", 5, flags):
        for title in ("foot", "duty", "measured", "phase", "measured"):
            imgui.table_setup_column(title)
        imgui.table_headers_row()
        for name in names:
            measured = None
            if report is not None:
                measured = next((f for f in report.feet if f.name == name), None)
            imgui.table_next_row()
            cells = [name, f"{gait.duty_factor:.3f}",
                     "-" if measured is None else f"{measured.duty_factor:.3f}",
                     f"{requested.get(name, 0.0):.3f}", "-" if measured is None else f"{measured.phase:.3f}"]
            for cell in cells:
                imgui.table_next_column()
                imgui.text(cell)
        imgui.end_table()
