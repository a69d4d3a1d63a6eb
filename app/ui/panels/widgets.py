"""The panels' building blocks: icons and colours, the context every panel gets, and
the widgets (sliders with reset buttons, choices, rows) that call :class:`ViewerState`."""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

from imgui_bundle import imgui

from ...render.arcs import ARC_COLORS
from ...spec import rule_for
from ..state import ViewerState

if TYPE_CHECKING:
    from ..file_dialog import FileDialog
    from ..monitor import GaitMonitor

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
    monitor: GaitMonitor | None = None  # the live gait measurement
    file_dialog: FileDialog | None = None  # the File panel's native dialog
    dialogs_available: bool = False
    open_at_start: tuple[str, ...] = ()  # panel titles open on the first frame, the others closed (``--panels``)


# -- small helpers ------------------------------------------------------------------------


def _icon(pc: PanelContext, icon: str, text: str) -> str:
    return f"{icon}  {text}" if pc.icons else text


def _remember(state: ViewerState, key: str) -> None:
    """Note the control just drawn: where it is (for automation) and whether the mouse is
    still holding it from an earlier frame (its changes then continue one drag, one undo
    step, however slow the frames)."""
    lo, hi = imgui.get_item_rect_min(), imgui.get_item_rect_max()
    state.widget_rects[key] = (lo.x, lo.y, hi.x, hi.y)
    state.drag_held = imgui.is_item_active() and not imgui.is_item_activated()


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


def _wrapped_note(text: str, lines: int = 0) -> None:
    """Greyed text wrapped at the panel's edge (never cut), taking at least ``lines``
    lines' height: a text that changes (a description) then does not move what is below."""
    top = imgui.get_cursor_pos_y()
    imgui.push_text_wrap_pos(0.0)
    imgui.text_disabled(text)
    imgui.pop_text_wrap_pos()
    short = top + lines * imgui.get_text_line_height_with_spacing() - imgui.get_cursor_pos_y()
    if short > 0:
        imgui.dummy(imgui.ImVec2(1.0, short))


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
    if tooltip and imgui.is_item_hovered(imgui.HoveredFlags_.allow_when_disabled):
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
                               else "reset to people's value" if key == "poses.swing_knee"
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


def _hex_color(color: str) -> imgui.ImVec4:
    r, g, b = (int(color[i:i + 2], 16) / 255.0 for i in (1, 3, 5))
    return imgui.ImVec4(r, g, b, 1.0)


# Each arc joint's colour as the panels write it (sRGB hex).
_ARC_HEX = {joint: "#" + "".join(f"{int(round(255 * v ** 0.5)):02x}" for v in rgb) for joint, rgb in ARC_COLORS.items()}
