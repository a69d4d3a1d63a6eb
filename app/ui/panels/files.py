"""The output panels: Record (GIF, MP4) and File (load, save, export)."""

from __future__ import annotations

from imgui_bundle import imgui

from ...choices import ANTIALIAS_MODES, CAMERA_CHOICES, EXPORT_FORMATS, GIF_QUALITIES, MAX_CRF
from ..state import ViewerState
from .widgets import (
    ICON_CAMERA,
    ICON_OPEN,
    ICON_RECORD,
    ICON_SAVE,
    PanelContext,
    _begin_rows,
    _combo,
    _icon,
    _label,
    _remember,
    _wrapped_note,
)


def record_panel(state: ViewerState, pc: PanelContext) -> None:
    r = state.record
    if imgui.button(_icon(pc, ICON_CAMERA, "screenshot (F12)"), imgui.ImVec2(-1, 0)):
        state.screenshot_requested = True
    imgui.separator_text("clip")
    if _begin_rows("record", pc):  # every field labelled
        _label("format", "GIF loops forever; MP4 is H.264 video")
        for fmt in ("gif", "mp4"):
            if imgui.radio_button(fmt, r.format == fmt):
                r.format = fmt
            imgui.same_line()
        imgui.table_next_column()
        if r.format == "gif":
            _label("quality", "GIF size against fidelity: good is half the size of best with no visible loss; "
                              "small is smaller still, with some grain")
            for i, quality in enumerate(GIF_QUALITIES):
                if i:
                    imgui.same_line()
                if imgui.radio_button(quality, r.gif_quality == quality):
                    r.gif_quality = quality  # type: ignore[assignment]
        else:
            _label("quality", "H.264 constant rate factor: lower is better and larger; 18 looks like the "
                              "original, each +6 roughly halves the file")
            imgui.set_next_item_width(-1)
            _, r.crf = imgui.slider_int("##crf", r.crf, 0, MAX_CRF, "crf %d")
        imgui.table_next_column()
        _label("edges", "antialiasing: fxaa is fast and nearly as smooth as msaa (multisampling), which "
                        "takes about twice as long without a GPU; off is raw pixels")
        for i, mode in enumerate(ANTIALIAS_MODES):
            if i:
                imgui.same_line()
            if imgui.radio_button(f"{mode}##aa", r.antialias == mode):
                r.antialias = mode  # type: ignore[assignment]
        imgui.table_next_column()
        _label("length", "how long the clip is, in gait cycles (which loop seamlessly) or seconds")
        _, r.length = imgui.input_float("##length", r.length, 0.0, 0.0, "%.2f")
        imgui.table_next_column()
        _label("in", "gait cycles (whole cycles loop seamlessly) or seconds")
        for i, unit in enumerate(("cycles", "seconds")):
            if i:
                imgui.same_line()
            if imgui.radio_button(unit, r.unit == unit):
                r.unit = unit  # type: ignore[assignment]
        imgui.table_next_column()
        _label("size", "width x height in pixels")
        imgui.set_next_item_width(70 * pc.scale)
        _, r.width = imgui.input_int("##w", r.width, 0, 0)
        imgui.same_line()
        imgui.text("x")
        imgui.same_line()
        imgui.set_next_item_width(70 * pc.scale)
        _, r.height = imgui.input_int("##h", r.height, 0, 0)
        imgui.table_next_column()
        _label("frame rate", "frames per second")
        _, r.fps = imgui.input_float("##fps", r.fps, 0.0, 0.0, "%.0f fps")
        imgui.table_next_column()
        _label("camera", "the camera preset, following the creature as it travels (chase: from behind, "
                         "looking ahead; follow: the default angle)")
        cams = list(CAMERA_CHOICES)
        changed, idx = imgui.combo("##rec-camera", cams.index(r.camera), cams)
        if changed:
            r.camera = cams[idx]
        imgui.table_next_column()
        _label("folder", "the folder to write into")
        _, r.folder = imgui.input_text("##folder", r.folder)
        imgui.table_next_column()
        _label("file name", "without extension (default: the creature's name)")
        _, r.name = imgui.input_text_with_hint("##name", state.spec.name, r.name)
        imgui.table_next_column()
        imgui.end_table()
    if pc.recording_progress is None:
        if imgui.button(_icon(pc, ICON_RECORD, f"record {r.path(state.spec.name)}  (G)"), imgui.ImVec2(-1, 0)):
            state.record_requested = True
        _remember(state, "record")
    else:
        imgui.progress_bar(pc.recording_progress, imgui.ImVec2(-1, 0), pc.recording_label)


def file_panel(state: ViewerState, pc: PanelContext) -> None:
    dialog = pc.file_dialog
    if dialog is not None:
        chosen = dialog.poll()
        if chosen is not None:
            state.file_path = chosen
            (state.load if dialog.kind == "open" else state.save)(chosen)
    imgui.text_disabled("file")
    imgui.same_line()
    imgui.set_next_item_width(-1)
    _, state.file_path = imgui.input_text("##file", state.file_path)
    _remember(state, "file")
    width = (imgui.get_content_region_avail().x - 8 * pc.scale) / 3
    can_browse = dialog is not None and pc.dialogs_available and not dialog.open
    imgui.begin_disabled(not can_browse)
    if imgui.button("browse...##open", imgui.ImVec2(width, 0)) and dialog is not None:
        dialog.start("open", state.file_path)
    imgui.end_disabled()
    if not pc.dialogs_available:
        imgui.set_item_tooltip("no file dialog on this system (install zenity or kdialog): type the path above")
    imgui.same_line()
    pending = state.overwrite_pending  # read once: the click below may change it
    if pending:
        imgui.push_style_color(imgui.Col_.button, imgui.get_color_u32(imgui.ImVec4(0.7, 0.3, 0.2, 1.0)))
    if imgui.button(_icon(pc, ICON_SAVE, "overwrite" if pending else "save") + "##save", imgui.ImVec2(width, 0)):
        state.save()
    _remember(state, "save")
    if pending:
        imgui.pop_style_color()
    imgui.same_line()
    if imgui.button(_icon(pc, ICON_OPEN, "load") + "##load", imgui.ImVec2(width, 0)):
        state.load(state.file_path)
    _remember(state, "load")
    if not pc.dialogs_available:
        _wrapped_note("no file dialog here (install zenity or kdialog); type a path in the field")
    # The row is always there (greyed while empty): a first save must not push the
    # buttons below it away from under the cursor.
    imgui.begin_disabled(not state.recent)
    imgui.set_next_item_width(-1)
    chosen = _combo("##recent", state.recent or [""], "", "recent files" if state.recent else "no recent files yet")
    imgui.end_disabled()
    if chosen is not None and state.recent:
        state.file_path = chosen
    imgui.separator_text("export the motion")
    r = state.record
    for i, fmt in enumerate(EXPORT_FORMATS[:3]):
        if i:
            imgui.same_line()
        if imgui.radio_button(fmt + "##export", r.export_format == fmt):
            r.export_format = fmt  # type: ignore[assignment]
    imgui.set_item_tooltip("BVH: the skeleton; glTF: skeleton, skinned mesh and animation (Blender, Godot, web); "
                           "USD: UsdSkel (needs usd-core)")
    name = f"{r.name or state.spec.name}.{r.export_format}"
    if imgui.button(f"export {name}##export", imgui.ImVec2(-1, 0)):
        state.export()
    imgui.set_item_tooltip("what is on screen, from now on, for the Record panel's length and frame rate, into its "
                           "folder; whole cycles end on the frame that closes the loop")
    label = "really reset every change? (press again)" if state.reset_pending else \
        "reset everything to the loaded creature"
    if imgui.button(label + "##reset-all", imgui.ImVec2(-1, 0)):
        state.reset_all()
    _remember(state, "reset_all")
