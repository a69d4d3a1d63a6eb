"""The creature's panels: legs and body, gait, key poses, body motion."""

from __future__ import annotations

from imgui_bundle import imgui

from ...choices import KNEE_DIRECTIONS, LEG_TYPES, WAVE_SHAPES
from ...gaits import GAIT_PRESETS, gaits_for
from ...kinematics.gait import WALK_DUTY
from ...kinematics.walker import SWING_KNEE_RANGE, heel_to_toe
from ...render.scene import KEY_POSE_COLORS
from ...styles import DEFAULT_TIMING_FPS, STYLES, WALK_STYLES
from ..state import ViewerState
from .widgets import (
    _ACCENT,
    LEG_LENGTHS,
    PanelContext,
    _begin_rows,
    _checkbox,
    _combo,
    _hex_color,
    _remember,
    _wrapped_note,
    choice,
    int_slider,
    shown,
    slider,
)

DESCRIPTION_LINES = 3  # a creature's or gait's description keeps this much room, however long it is now


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
    _wrapped_note(state.creature_description, lines=DESCRIPTION_LINES)
    model = state.bones_from_model
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
            imgui.begin_disabled(model)  # a rigged model's bones are its own
            slider(state, pc, f"{p}.toe", "toe", 0.0, 0.3, "%.3f m")
            imgui.begin_disabled(state.get(f"{p}.knee") == "out")  # a sprawled leg's foot is its last segment
            int_slider(state, pc, f"{p}.toes", "splayed toes", 0, 4)
            imgui.end_disabled()
            slider(state, pc, f"{p}.femur", "femur", 0.02, 1.0, "%.3f m")
            slider(state, pc, f"{p}.tibia", "tibia", 0.02, 1.0, "%.3f m")
            slider(state, pc, f"{p}.metatarsus", "metatarsus", 0.01, 0.6, "%.3f m")
            imgui.end_disabled()
            slider(state, pc, f"{p}.natural_bend", "natural bend", 0.0, 0.6, "%.2f")
            choice(state, pc, f"{p}.knee", "knee points", KNEE_DIRECTIONS)
            imgui.end_table()
    imgui.separator_text("Body")
    if _begin_rows("body-size", pc):
        imgui.begin_disabled(model)
        slider(state, pc, "body.length", "length", 0.1, 2.5, "%.3f m")
        slider(state, pc, "body.width", "width", 0.03, 1.0, "%.3f m")
        imgui.end_disabled()
        int_slider(state, pc, "body.segments", "segments", 2, 64)  # the schema's range: a centipede has 30
        imgui.begin_disabled(model)
        slider(state, pc, "body.wings", "wings", 0.0, 1.0, "%.3f m")
        slider(state, pc, "body.beak", "beak", 0.0, state.spec.body.head_length, "%.3f m")  # at most the head
        imgui.begin_disabled(state.spec.body.posture == "upright")  # a person has no hump
        slider(state, pc, "body.hump", "hump", 0.0, 0.5, "%.3f m")
        imgui.end_disabled()
        imgui.end_disabled()
        imgui.end_table()


def gait_panel(state: ViewerState, pc: PanelContext) -> None:
    names = gaits_for(state.spec.pair_count)  # only the gaits that fit this body
    imgui.set_next_item_width(-1)
    chosen = _combo("##gait", names, state.spec.gait.preset, state.gait_label)
    _remember(state, "gait")
    if chosen is not None:
        state.set_gait(chosen)
    _wrapped_note(GAIT_PRESETS[state.spec.gait.preset].describe(state.spec.pair_count), lines=DESCRIPTION_LINES)
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
        slider(state, pc, "body.tail_curl", "tail curl", -180.0, 180.0, "%.0f deg")
        slider(state, pc, "motion.pelvis_tilt", "pelvis tilt", 0.0, 20.0, "%.1f deg")
        slider(state, pc, "motion.spine_flex", "spine flex", 0.0, 3.0, "%.2f x")
        imgui.end_table()
    imgui.separator_text("overlap (follow-through delay)")
    if _begin_rows("overlap", pc):
        for part in ("head", "neck", "arms", "tail", "ears"):
            slider(state, pc, f"overlap.{part}", part, 0.0, 0.5, "%.3f cycle")
        imgui.end_table()




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
        rig = state.live.rig  # a walker's knee: feet that roll heel to toe, walking
        imgui.begin_disabled(not heel_to_toe(rig).any() or rig.gait.duty_factor < WALK_DUTY[0])
        slider(state, pc, "poses.swing_knee", "swing knee", *SWING_KNEE_RANGE, "%.1f deg")
        imgui.end_disabled()
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
