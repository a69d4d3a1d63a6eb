"""The viewer's panels, HUD and help overlay: imgui widgets that call :class:`ViewerState`.

Every value is shown in a slider (Ctrl+click to type a number) with a reset button that
gives it back its value from the loaded creature. No logic lives here beyond layout.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field, replace

import numpy as np
from imgui_bundle import imgui, implot

from ..gaits import GAIT_PRESETS, gaits_for
from ..export.formats import EXPORT_FORMATS
from ..output import GIF_QUALITIES, MAX_CRF
from ..render.camera import CAMERA_CHOICES, CAMERA_PRESETS
from ..choices import ANTIALIAS_MODES, ARC_JOINTS, KNEE_DIRECTIONS, LEG_TYPES, WAVE_SHAPES
from ..render.arcs import ARC_COLORS
from ..render.scene import KEY_POSE_COLORS
from ..styles import DEFAULT_TIMING_FPS, STYLES, WALK_STYLES
from ..spec import rule_for
from .state import ViewerState

ICON_RESET = "\uf2ea"
ICON_PLAY = "\uf04b"
ICON_PAUSE = "\uf04c"
ICON_STEP = "\uf051"
ICON_CAMERA = "\uf030"
ICON_RECORD = "\uf111"
ICON_SAVE = "\uf0c7"
ICON_OPEN = "\uf07c"

SIDEBAR_WIDTH = 380.0
SIDEBAR_COLOR = (0.094, 0.094, 0.102)  # display RGB of the sidebar's background
_ERROR = imgui.ImVec4(1.0, 0.45, 0.4, 1.0)
_OK = imgui.ImVec4(0.55, 0.85, 0.6, 1.0)
_ACCENT = imgui.ImVec4(0.26, 0.52, 0.85, 1.0)

SHORTCUTS: tuple[tuple[str, str], ...] = (
    ("Space", "play / pause"),
    ("Right", "step one frame (when not driving)"),
    ("W / Up", "drive: faster (the first press starts driving)"),
    ("S / Down", "drive: slower"),
    ("A / D, Left / Right", "drive: turn left / right"),
    ("Esc", "stop driving (the Gait panel's gait again)"),
    ("R", "reset the view"),
    ("F12", "screenshot of the 3-D view (PNG)"),
    ("Shift+F12", "screenshot of the whole window"),
    ("G", "record a GIF/MP4 (Record panel settings)"),
    ("Tab", "hide / show the UI"),
    ("F1", "this help"),
    ("Ctrl+Z / Ctrl+Y", "undo / redo an edit"),
    ("Ctrl+Q", "quit"),
    ("Left drag", "orbit"),
    ("Right / middle drag", "pan"),
    ("Wheel", "zoom"),
    ("Double-click", "focus on the point under the cursor"),
)


@dataclass
class FrameStats:
    """Smoothed timings (milliseconds) shown in the HUD."""

    fps: float = 0.0
    frame_ms: float = 0.0
    simulate_ms: float = 0.0
    scene_ms: float = 0.0
    ui_ms: float = 0.0


@dataclass
class PanelContext:
    """What the panels need besides the state."""

    presets: list[str]
    scale: float = 1.0
    icons: bool = True
    stats: FrameStats = field(default_factory=FrameStats)
    recording_progress: float | None = None  # 0..1 while a recording runs
    recording_label: str = ""
    monitor: object | None = None  # the live GaitMonitor (app/ui/monitor.py)
    file_dialog: object | None = None  # the File panel's native dialog (app/ui/file_dialog.py)
    dialogs_available: bool = False


# -- small helpers ------------------------------------------------------------------------


def _icon(pc: PanelContext, icon: str, text: str) -> str:
    return f"{icon}  {text}" if pc.icons else text


def _remember(state: ViewerState, key: str) -> None:
    lo, hi = imgui.get_item_rect_min(), imgui.get_item_rect_max()
    state.widget_rects[key] = (lo.x, lo.y, hi.x, hi.y)


def _doc(key: str) -> str:
    """A control's tooltip: what it means in plain words (its file key last, for the curious)."""
    rule = rule_for(key)
    if rule is None:
        return ""
    text = PLAIN_WORDS.get(key.rsplit(".", 1)[-1], rule.doc)
    return f"{text}\n(creature file: {key})"


LEG_LENGTHS = "x leg"  # step height, stride and bob are in units of the leg's rest length
PLAIN_WORDS = {
    "bias": "How long each foot stays down against how long it swings, as the source's wave skew b: "
            "more b, longer on the ground. It sets the duty factor (duty = 1/2 + asin(ln(cosh b)/b)/pi).",
    "duty_factor": "The share of each stride a foot spends on the ground: above 0.5 a walk, below a run.",
    "step_height": "How high a foot lifts in its swing, in leg lengths (x leg: the leg's length standing at rest).",
    "stride": "How far a planted foot travels back under its hip, in leg lengths (x leg: the leg's length "
              "standing at rest). Longer strides make the creature faster.",
    "bob": "How much the body rises and falls with the steps, in leg lengths (x leg: the leg's rest length).",
    "front_back": "How far (a share of the stride) each foot lands after the foot behind it on its side.",
    "left_right": "How far (a share of the stride) the right feet land after the left ones.",
    "frequency": "Strides per second. Left to the gait, it follows the hip height: longer legs step slower.",
}


def _combo(name: str, items: list[str], current: str, preview: str) -> str | None:
    """A drop-down showing ``preview`` (e.g. "dog*" once edited); returns the item chosen."""
    chosen = None
    if imgui.begin_combo(name, preview):
        for item in items:
            selected = item == current
            if imgui.selectable(item, selected)[0]:
                chosen = item
            if selected:
                imgui.set_item_default_focus()
        imgui.end_combo()
    return chosen


def _wrapped_note(text: str) -> None:
    """Greyed text wrapped at the panel's edge (never cut)."""
    imgui.push_text_wrap_pos(0.0)
    imgui.text_disabled(text)
    imgui.pop_text_wrap_pos()


def _begin_rows(name: str, pc: PanelContext) -> bool:
    flags = imgui.TableFlags_.sizing_fixed_fit
    if not imgui.begin_table(name, 3, flags):
        return False
    imgui.table_setup_column("label", imgui.TableColumnFlags_.width_fixed, 118 * pc.scale)
    imgui.table_setup_column("value", imgui.TableColumnFlags_.width_stretch)
    imgui.table_setup_column("reset", imgui.TableColumnFlags_.width_fixed, 26 * pc.scale)
    return True


def _checkbox(state: ViewerState, key: str, label: str, value: bool, tooltip: str = "") -> tuple[bool, bool]:
    """A check box remembered as widget ``key`` (its rectangle for the state dump), with a
    tooltip; returns (changed, value)."""
    changed, value = imgui.checkbox(label, value)
    _remember(state, key)
    if tooltip and imgui.is_item_hovered():
        imgui.set_tooltip(tooltip)
    return changed, value


def _label(text: str, tooltip: str) -> None:
    imgui.table_next_row()
    imgui.table_next_column()
    imgui.align_text_to_frame_padding()
    imgui.text(text)
    if tooltip:
        imgui.set_item_tooltip(tooltip)
    imgui.table_next_column()
    imgui.set_next_item_width(-1)


def _reset(state: ViewerState, key: str, pc: PanelContext) -> None:
    imgui.table_next_column()
    modified = state.is_modified(key)
    imgui.begin_disabled(not modified)
    if imgui.small_button(f"{ICON_RESET if pc.icons else 'R'}##reset-{key}"):
        state.reset(key)
    imgui.end_disabled()
    if modified:
        imgui.set_item_tooltip(f"reset to {state.base_value(key)!r}" if state.base_value(key) is not None
                               else "reset to the gait preset's value")


def shown(value: float, fmt: str) -> float:
    """``value`` rounded to the decimals a printf format such as ``"%.3f m"`` shows."""
    match = re.search(r"%\.(\d+)f", fmt)
    return round(value, int(match.group(1))) if match else float(value)


def slider(state: ViewerState, pc: PanelContext, key: str, label: str, lo: float, hi: float,
           fmt: str = "%.3f", setter=None) -> None:
    """A float row: label, slider (Ctrl+click to type), reset."""
    _label(label, _doc(key))
    value = float(state.get(key))
    changed, new = imgui.slider_float(f"##{key}", value, lo, hi, fmt)
    _remember(state, key)
    if changed:
        new = shown(float(new), fmt)  # the value as the slider shows it: no float32 noise in saved files
        if setter is None:
            state.set(key, new)
        else:
            setter(new)
    _reset(state, key, pc)


def int_slider(state: ViewerState, pc: PanelContext, key: str, label: str, lo: int, hi: int) -> None:
    _label(label, _doc(key))
    changed, new = imgui.slider_int(f"##{key}", int(state.get(key)), lo, hi)
    _remember(state, key)
    if changed:
        state.set(key, int(new))
    _reset(state, key, pc)


def choice(state: ViewerState, pc: PanelContext, key: str, label: str, options: tuple[str, ...] | list[str],
           setter=None) -> None:
    _label(label, _doc(key))
    current = str(state.get(key))
    items = list(options)
    changed, index = imgui.combo(f"##{key}", items.index(current) if current in items else 0, items)
    _remember(state, key)
    if changed:
        (setter or (lambda v: state.set(key, v)))(items[index])
    _reset(state, key, pc)


# -- panels -------------------------------------------------------------------------------


def creature_panel(state: ViewerState, pc: PanelContext) -> None:
    names = state.names
    if len(names) > 1:  # a scene: which creature the panels show (or click one in the view)
        labels = [f"{k + 1}. {name}" for k, name in enumerate(names)]
        imgui.set_next_item_width(-1)
        changed, index = imgui.combo("##scene-creature", state.selected, labels)
        _remember(state, "scene.creature")
        if imgui.is_item_hovered():
            imgui.set_tooltip("The scene's creatures: the one chosen here (or clicked in the view) is in the panels.")
        if changed:
            state.select(index)
    presets = pc.presets
    imgui.set_next_item_width(-1)
    choice_made = _combo("##creature", presets, state.spec.name, state.creature_label)
    _remember(state, "creature")
    if choice_made is not None:
        state.load_preset(choice_made)
    _wrapped_note(state.spec.description or state.spec.source)
    for pair in (leg.name for leg in state.spec.legs):
        imgui.separator_text("Legs" if pair == "legs" else f"{pair.capitalize()} legs")
        current = state.leg_type(pair)
        width = (imgui.get_content_region_avail().x - 8 * pc.scale) / 3
        for i, kind in enumerate(LEG_TYPES):
            if i:
                imgui.same_line()
            active = kind == current
            if active:
                imgui.push_style_color(imgui.Col_.button, imgui.get_color_u32(_ACCENT))
            if imgui.button(f"{kind}##{pair}", imgui.ImVec2(width, 0)):
                state.set_leg_type(pair, kind)  # type: ignore[arg-type]
            _remember(state, f"leg_type.{pair}.{kind}")
            if active:
                imgui.pop_style_color()
        if _begin_rows(f"legs-{pair}", pc):
            p = f"legs.{pair}"
            slider(state, pc, f"{p}.ankle_lift", "ankle lift", 0.0, 90.0, "%.1f deg")
            slider(state, pc, f"{p}.toe", "toe", 0.0, 0.3, "%.3f m")
            slider(state, pc, f"{p}.femur", "femur", 0.02, 1.0, "%.3f m")
            slider(state, pc, f"{p}.tibia", "tibia", 0.02, 1.0, "%.3f m")
            slider(state, pc, f"{p}.metatarsus", "metatarsus", 0.01, 0.6, "%.3f m")
            slider(state, pc, f"{p}.natural_bend", "natural bend", 0.0, 0.6, "%.2f")
            choice(state, pc, f"{p}.knee", "knee points", KNEE_DIRECTIONS)
            imgui.end_table()
    imgui.separator_text("Body")
    if _begin_rows("body-size", pc):
        slider(state, pc, "body.length", "length", 0.1, 2.5, "%.3f m")
        slider(state, pc, "body.width", "width", 0.03, 1.0, "%.3f m")
        int_slider(state, pc, "body.segments", "segments", 2, 24)
        imgui.end_table()


def gait_panel(state: ViewerState, pc: PanelContext) -> None:
    names = gaits_for(state.spec.pair_count)  # only the gaits that fit this body
    imgui.set_next_item_width(-1)
    chosen = _combo("##gait", names, state.spec.gait.preset, state.gait_label)
    _remember(state, "gait")
    if chosen is not None:
        state.set_gait(chosen)
    _wrapped_note(GAIT_PRESETS[state.spec.gait.preset].describe(state.spec.pair_count))
    if _begin_rows("gait", pc):
        slider(state, pc, "gait.frequency", "frequency", 0.1, 6.0, "%.2f Hz")
        # Rows that do not apply stay, disabled, so the layout never moves under the cursor.
        imgui.begin_disabled(not state.gait_is_symmetric or state.spec.pair_count == 1)
        slider(state, pc, "gait.front_back", "front / back", 0.0, 1.0, "%.3f")
        imgui.end_disabled()
        imgui.begin_disabled(not state.gait_is_symmetric)
        slider(state, pc, "gait.left_right", "left / right", 0.0, 1.0, "%.3f")
        imgui.end_disabled()
        bias = float(state.get("gait.bias"))
        slider(state, pc, "gait.duty_factor", "duty factor", 0.06, 0.94, "%.3f", setter=state.set_duty)
        slider(state, pc, "gait.bias", "swing bias", -6.0, 6.0, f"%.2f  (b = {bias:.2f})", setter=state.set_bias)
        slider(state, pc, "gait.step_height", "step height", 0.0, 0.6, f"%.3f {LEG_LENGTHS}")
        slider(state, pc, "gait.stride", "stride", 0.0, 1.5, f"%.3f {LEG_LENGTHS}")
        choice(state, pc, "gait.wave", "wave shape", WAVE_SHAPES)
        imgui.end_table()
    if state.spec.gait.frequency is None:
        _wrapped_note("frequency: from the gait and the hip height (it changes with the legs' lengths)")
    else:
        _wrapped_note("frequency: set by hand")
    imgui.text(f"touchdown phase per foot ({state.live.rig.leg_names[-2]} = 0)")
    feet = state.live.rig.leg_names
    if imgui.begin_table("phases", min(4, len(feet))):
        for foot in feet:
            imgui.table_next_column()
            key = f"gait.phases.{foot}"
            imgui.set_next_item_width(-1)
            changed, value = imgui.drag_float(f"##{key}", float(state.get(key)), 0.002, 0.0, 1.0, f"{foot} %.3f")
            _remember(state, key)
            if changed:
                state.set(key, shown(float(value) % 1.0, "%.3f"))
        imgui.end_table()
    imgui.begin_disabled(state.spec.gait.phases is None)
    if imgui.small_button("back to the preset's phases"):
        state.reset(f"gait.phases.{feet[0]}")
    imgui.end_disabled()
    if state.live.blending:  # always one line, so nothing below moves
        imgui.text_colored(_ACCENT, "blending into the new gait...")
    else:
        imgui.text_disabled("every foot in the gait")


def body_panel(state: ViewerState, pc: PanelContext) -> None:
    if _begin_rows("body-motion", pc):
        slider(state, pc, "motion.bob", "bob", 0.0, 0.2, f"%.3f {LEG_LENGTHS}")
        slider(state, pc, "motion.bob_phase", "bob timing", -0.5, 0.5, "%.3f")
        slider(state, pc, "motion.yaw", "yaw", 0.0, 30.0, "%.1f deg")
        slider(state, pc, "motion.tail_sway", "tail sway", 0.0, 60.0, "%.1f deg")
        slider(state, pc, "body.neck_angle", "neck angle", -60.0, 90.0, "%.0f deg")
        slider(state, pc, "body.tail_angle", "tail angle", -90.0, 90.0, "%.0f deg")
        slider(state, pc, "motion.pelvis_tilt", "pelvis tilt", 0.0, 20.0, "%.1f deg")
        slider(state, pc, "motion.spine_flex", "spine flex", 0.0, 3.0, "%.2f x")
        imgui.end_table()
    imgui.separator_text("overlap (follow-through delay)")
    if _begin_rows("overlap", pc):
        for part in ("head", "neck", "arms", "tail", "ears"):
            slider(state, pc, f"overlap.{part}", part, 0.0, 0.5, "%.3f cycle")
        imgui.end_table()


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
    changed_g, grid = imgui.checkbox("grid", options.grid)
    imgui.same_line()
    changed_s, shadow = imgui.checkbox("shadow", options.shadow)
    imgui.same_line()
    changed_j, joints = imgui.checkbox("joints", options.joints)
    imgui.same_line()
    changed_p, path = imgui.checkbox("path", options.path)
    if changed_g or changed_s or changed_j or changed_p:
        state.options = replace(options, grid=grid, shadow=shadow, joints=joints, path=path)
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
    count = options.footprint_count
    if options.footprints:
        imgui.set_next_item_width(-1)
        changed_n, count = imgui.slider_int("##footprint-count", options.footprint_count, 2, 200,
                                            "%d footprints")
        _remember(state, "overlay.footprint_count")
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


def record_panel(state: ViewerState, pc: PanelContext) -> None:
    r = state.record
    if imgui.button(_icon(pc, ICON_CAMERA, "screenshot (F12)"), imgui.ImVec2(-1, 0)):
        state.screenshot_requested = True
    imgui.separator_text("clip")
    if _begin_rows("record", pc):  # every field labelled
        _label("format", "GIF loops forever; MP4 is H.264 video")
        for fmt in ("gif", "mp4"):
            if imgui.radio_button(fmt, r.format == fmt):
                r.format = fmt  # type: ignore[assignment]
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
    if state.recent:
        imgui.set_next_item_width(-1)
        chosen = _combo("##recent", state.recent, "", "recent files")
        if chosen is not None:
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
        if implot.begin_plot("foot heights (cm)", imgui.ImVec2(width, 150 * pc.scale)):
            implot.setup_axes("seconds", "", implot.AxisFlags_.no_label, 0)
            implot.setup_axis_limits(implot.ImAxis_.x1, -monitor.seconds, 0.0, implot.Cond_.always)
            # The height axis fits the data (a gallop or a high step is never clipped).
            low, high = float(np.nanmin(heights)), float(np.nanmax(heights))
            pad = max(0.08 * (high - low), 0.5)
            implot.setup_axis_limits(implot.ImAxis_.y1, min(low, 0.0) - pad, high + pad, implot.Cond_.always)
            for i, name in enumerate(names):
                implot.plot_line(name, t, np.ascontiguousarray(heights[:, i]))
            implot.end_plot()
        contact = monitor.contact()
        if implot.begin_plot("gait diagram (stance)", imgui.ImVec2(width, 110 * pc.scale),
                             implot.Flags_.no_legend | implot.Flags_.no_mouse_text):
            implot.setup_axes("", "", implot.AxisFlags_.no_label, implot.AxisFlags_.invert)
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


# Terrain panel: (key, label, tooltip, low, high, format) per kind; whole numbers for "%d".
TERRAIN_CONTROLS: dict[str, tuple[tuple[str, str, str, float, float, str], ...]] = {
    "flat": (),
    "slope": (("angle", "angle", "rise of the plane (negative: downhill ahead)", -35.0, 35.0, "%.1f deg"),
              ("dir", "uphill towards", "direction the slope rises, degrees from straight ahead (+Z)", -180.0,
               180.0, "%.0f deg")),
    "hills": (("amp", "height", "about how high and low the hills go", 0.0, 1.0, "%.3f m"),
              ("wavelength", "wavelength", "typical distance between hilltops", 0.2, 20.0, "%.2f m"),
              ("seed", "seed", "which random hills", 0, 99, "%d")),
    "stairs": (("rise", "rise", "each step's height (negative: down)", -0.5, 0.5, "%.3f m"),
               ("run", "run", "each step's depth", 0.02, 2.0, "%.3f m"),
               ("steps", "steps", "how many steps", 1, 60, "%d"),
               ("start", "first riser", "distance from the start to the first step", -10.0, 20.0, "%.2f m"),
               ("dir", "climbing towards", "direction of the flight, degrees from +Z", -180.0, 180.0, "%.0f deg")),
    "heightmap": (("size", "width", "the image's width on the ground", 1.0, 200.0, "%.1f m"),
                  ("height", "white height", "height of white pixels (black is 0)", 0.0, 10.0, "%.2f m")),
    "mesh": (("cell", "grid spacing", "sampling of the mesh (0: its size / 256)", 0.0, 2.0, "%.3f m"),),
}


def terrain_panel(state: ViewerState, pc: PanelContext) -> None:
    """The ground under the creature, regenerated live as values change."""
    kinds = list(TERRAIN_CONTROLS)
    imgui.set_next_item_width(-1)
    changed, index = imgui.combo("##terrain-kind", kinds.index(state.terrain_kind), kinds)
    _remember(state, "terrain.kind")
    if changed and kinds[index] not in ("heightmap", "mesh"):
        state.set_terrain(kinds[index])
    elif changed:
        state.terrain_kind = kinds[index]  # pick the file first, then load
    kind = state.terrain_kind
    values = state.terrain_values[kind]
    if kind in ("heightmap", "mesh"):
        imgui.set_next_item_width(-70 * pc.scale)
        _, values["file"] = imgui.input_text_with_hint("##terrain-file", "image or mesh file path", values["file"])
        _remember(state, "terrain.file")
        imgui.same_line()
        if imgui.button("load##terrain", imgui.ImVec2(-1, 0)):
            state.set_terrain(kind)
        _remember(state, "terrain.load")
    if TERRAIN_CONTROLS[kind] and _begin_rows(f"terrain-{kind}", pc):
        for key, label, tip, lo, hi, fmt in TERRAIN_CONTROLS[kind]:
            _label(label, tip)
            if fmt == "%d":
                changed, value = imgui.slider_int(f"##terrain-{key}", int(values[key]), int(lo), int(hi), fmt)
            else:
                changed, value = imgui.slider_float(f"##terrain-{key}", float(values[key]), lo, hi, fmt)
                value = shown(float(value), fmt.split()[0])
            _remember(state, f"terrain.{key}")
            imgui.table_next_column()
            if changed and value != values[key] and (kind not in ("heightmap", "mesh") or values["file"]):
                state.set_terrain(kind, **{key: value})
            elif changed:
                values[key] = value
        imgui.end_table()
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


def _hex_color(color: str) -> imgui.ImVec4:
    return imgui.ImVec4(*(int(color[i:i + 2], 16) / 255.0 for i in (1, 3, 5)), 1.0)


_ARC_HEX = {joint: "#" + "".join(f"{int(round(255 * v ** 0.5)):02x}" for v in rgb) for joint, rgb in ARC_COLORS.items()}


def poses_panel(state: ViewerState, pc: PanelContext) -> None:
    """Key poses, walk style and timing, as an animator shapes a walk."""
    imgui.text("style")
    for i, name in enumerate(WALK_STYLES):
        if i % 3:
            imgui.same_line()
        current = state.spec.poses.style == name
        label = f"{name}*" if current and state.style_edited else name
        if current:
            imgui.push_style_color(imgui.Col_.button, imgui.get_style_color_vec4(imgui.Col_.button_active))
        if imgui.button(f"{label}###{name}"):
            state.set_style(name)
        if current:
            imgui.pop_style_color()
        _remember(state, f"style.{name}")
        if imgui.is_item_hovered():
            imgui.set_tooltip(STYLES[name].description)
    hip = state.live.rig.hip_height
    if _begin_rows("poses", pc):
        for pose in ("contact", "down", "pass", "up"):
            slider(state, pc, f"poses.{pose}_height", f"{pose} height", -0.35 * hip, 0.1 * hip, "%.3f m")
        slider(state, pc, "poses.foot_angle", "foot angle", -30.0, 60.0, "%.1f deg")
        slider(state, pc, "poses.arm_swing", "arm swing", 0.0, 80.0, "%.1f deg")
        slider(state, pc, "poses.torso_lean", "torso lean", -30.0, 45.0, "%.1f deg")
        slider(state, pc, "gait.stride", "stride", 0.0, 1.5, f"%.3f {LEG_LENGTHS}")
        slider(state, pc, "gait.frames_per_cycle", "frames / cycle", 6.0, 96.0, "%.1f frames")
        imgui.end_table()
    fps = state.spec.gait.timing_fps or DEFAULT_TIMING_FPS
    frames = float(state.get("gait.frames_per_cycle"))
    step = frames / 2.0
    step_text = f"{step:.0f}" if abs(step - round(step)) < 0.05 else f"{step:.1f}"
    imgui.text_disabled(f"a step every {step_text} frames (on {step_text}s) at {fps:g} fps; "
                        f"{state.live.rig.gait.frequency:.2f} strides a second")
    _, state.show_ghosts = _checkbox(state, "poses.ghosts", "ghosts: this step's key poses along the path",
                                     state.show_ghosts)
    if state.show_ghosts:
        for i, (name, color) in enumerate(zip(("contact", "down", "pass", "up"), KEY_POSE_COLORS)):
            if i:
                imgui.same_line()
            imgui.text_colored(_hex_color(color), name)
    if state.live.rig.poses.heights is None:
        _wrapped_note("the body bobs with the gait; set a height or a style to key it")


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


def sidebar(state: ViewerState, pc: PanelContext, extra_panels=()) -> None:
    io = imgui.get_io()
    width = SIDEBAR_WIDTH * pc.scale
    imgui.set_next_window_pos(imgui.ImVec2(0, 0))
    imgui.set_next_window_size(imgui.ImVec2(width, io.display_size.y))
    flags = (imgui.WindowFlags_.no_move | imgui.WindowFlags_.no_resize | imgui.WindowFlags_.no_collapse
             | imgui.WindowFlags_.no_title_bar | imgui.WindowFlags_.no_background)
    # No ImGui background: the viewer clears the sidebar's rectangle to SIDEBAR_COLOR, which
    # is much cheaper than a blended full-height quad on a software rasteriser.
    imgui.begin("Gaitlab", None, flags)
    gait = f"{state.driver.gait} (driving)" if state.driver is not None else state.spec.gait.preset
    imgui.text(f"Gaitlab  -  {state.spec.name}, {gait}")
    imgui.text_disabled("F1 help  -  Tab hide UI")
    for title, draw, default_open in (*PANELS, *extra_panels):
        flag = imgui.TreeNodeFlags_.default_open if default_open else 0
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
    flags = (imgui.WindowFlags_.no_decoration | imgui.WindowFlags_.no_saved_settings | imgui.WindowFlags_.no_nav
             | imgui.WindowFlags_.no_focus_on_appearing | imgui.WindowFlags_.always_auto_resize)
    if state.message is None and pc.recording_progress is None:
        return
    imgui.begin("##messages", None, flags)
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
    imgui.begin(name, None, imgui.WindowFlags_.no_decoration | imgui.WindowFlags_.always_auto_resize
                | imgui.WindowFlags_.no_saved_settings | imgui.WindowFlags_.no_focus_on_appearing
                | imgui.WindowFlags_.no_nav | imgui.WindowFlags_.no_inputs)


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
