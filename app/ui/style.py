"""The viewer's look: fonts (Roboto with Font Awesome icons merged in) and a calm dark style."""

from __future__ import annotations

from pathlib import Path

import imgui_bundle
from imgui_bundle import imgui

_ASSETS = Path(imgui_bundle.__file__).resolve().parent / "assets" / "fonts"


def setup_style(scale: float) -> bool:
    """Fonts (Roboto with Font Awesome icons merged in) and a calm dark style. Returns
    whether the icon font is available."""
    io = imgui.get_io()
    icons = False
    regular = _ASSETS / "Roboto" / "Roboto-Regular.ttf"
    awesome = _ASSETS / "Font_Awesome_6_Free-Solid-900.otf"
    if regular.exists():
        font = io.fonts.add_font_from_file_ttf(str(regular), 15.0 * scale)
        if awesome.exists():
            config = imgui.ImFontConfig()
            config.merge_mode = True
            io.fonts.add_font_from_file_ttf(str(awesome), 12.0 * scale, config)
            icons = True
        io.font_default = font
    imgui.style_colors_dark()
    style = imgui.get_style()
    style.window_rounding = 0.0
    style.frame_rounding = 3.0
    style.grab_rounding = 3.0
    style.window_border_size = 0.0
    style.item_spacing = imgui.ImVec2(6, 5)
    # Every input visible when it is off: framed boxes, checkboxes and radio buttons, a
    # slider track that shows, a thin see-through knob that never hides the value, and
    # opaque pop-ups (issue 12, item 3).
    style.frame_border_size = 1.0
    style.grab_min_size = 6.0
    colors = {
        imgui.Col_.border: (0.50, 0.52, 0.58, 0.80),
        imgui.Col_.frame_bg: (0.20, 0.22, 0.27, 1.00),
        imgui.Col_.frame_bg_hovered: (0.26, 0.30, 0.38, 1.00),
        imgui.Col_.frame_bg_active: (0.30, 0.36, 0.46, 1.00),
        imgui.Col_.slider_grab: (0.45, 0.65, 0.95, 0.55),
        imgui.Col_.slider_grab_active: (0.55, 0.75, 1.00, 0.75),
        imgui.Col_.check_mark: (0.55, 0.78, 1.00, 1.00),
        imgui.Col_.popup_bg: (0.11, 0.11, 0.13, 1.00),
    }
    for index, rgba in colors.items():
        style.set_color_(index, imgui.ImVec4(*rgba))
    style.scale_all_sizes(scale)
    return icons
