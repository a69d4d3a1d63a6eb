"""The ImGui renderer's sidebar layer and the floor shadow's outline: speed-ups that
must not change a pixel."""

from __future__ import annotations

import numpy as np
import pytest
from imgui_bundle import imgui

from app import build_rig, load_creature
from app.kinematics import simulate
from app.render.lighting import LIGHT_DIR, light_view_proj, shadow_outline
from app.render.scene import pose_instances
from app.ui.imgui_renderer import Backdrop, ImguiRenderer

SIZE = (480, 320)
STRIP = 200
COLOR = (0.094, 0.094, 0.102)


@pytest.fixture
def ui(gl_ctx):
    context = imgui.create_context()
    imgui.get_io().set_ini_filename("")
    renderer = ImguiRenderer(gl_ctx)
    yield renderer
    renderer.release()
    imgui.destroy_context(context)


def _frame(label: str, tooltip_x: float | None = None) -> imgui.ImDrawData:
    """A sidebar window in the strip and a second window out in the view."""
    io = imgui.get_io()
    io.display_size = imgui.ImVec2(*SIZE)
    io.delta_time = 1.0 / 60.0
    imgui.new_frame()
    imgui.set_next_window_pos(imgui.ImVec2(0, 0))
    imgui.set_next_window_size(imgui.ImVec2(STRIP, SIZE[1]))
    imgui.begin("side", None, imgui.WindowFlags_.no_title_bar | imgui.WindowFlags_.no_background)
    imgui.text(label)
    imgui.slider_float("speed", 0.5, 0.0, 1.0)
    imgui.button("Record")
    imgui.end()
    if tooltip_x is not None:
        imgui.set_next_window_pos(imgui.ImVec2(tooltip_x, 20))
        imgui.begin("hud", None, imgui.WindowFlags_.no_title_bar | imgui.WindowFlags_.always_auto_resize)
        imgui.text("60 fps")
        imgui.end()
    imgui.render()
    return imgui.get_draw_data()


def _draw(gl_ctx, renderer: ImguiRenderer, data: imgui.ImDrawData, backdrop: Backdrop | None) -> np.ndarray:
    fbo = gl_ctx.simple_framebuffer(SIZE, components=4)
    fbo.use()
    fbo.clear(0.5, 0.6, 0.7, 1.0)
    if backdrop is None:
        fbo.clear(*COLOR, 1.0, viewport=(0, 0, STRIP, SIZE[1]))
    renderer.render(data, fbo, backdrop)
    image = np.frombuffer(fbo.read(components=3), dtype=np.uint8).reshape(SIZE[1], SIZE[0], 3).copy()
    for attachment in fbo.color_attachments:
        attachment.release()
    fbo.release()
    return image


def test_the_sidebar_layer_gives_the_same_pixels_and_is_kept_while_unchanged(gl_ctx, ui, monkeypatch) -> None:
    for _ in range(3):  # windows settle (sizes, fonts) over their first frames
        _draw(gl_ctx, ui, _frame("Gaitlab - dog", tooltip_x=300), None)
    data = _frame("Gaitlab - dog", tooltip_x=300)
    direct = _draw(gl_ctx, ui, data, None)
    layered = _draw(gl_ctx, ui, data, Backdrop(STRIP, COLOR))
    assert np.array_equal(direct, layered)
    assert (direct[:, :STRIP] != direct[0, 0]).any(axis=-1).mean() > 0.01  # the sidebar drew something
    drawn = []
    real = ui._draw_lists
    monkeypatch.setattr(ui, "_draw_lists", lambda lists, target, *a: (drawn.append(len(lists)), real(lists, target, *a)))
    again = _draw(gl_ctx, ui, _frame("Gaitlab - dog", tooltip_x=310), Backdrop(STRIP, COLOR))
    assert drawn == [1]  # only the window out in the view: the sidebar's pixels came from the layer
    assert np.array_equal(again[:, :STRIP], layered[:, :STRIP])
    changed = _draw(gl_ctx, ui, _frame("Gaitlab - horse", tooltip_x=310), Backdrop(STRIP, COLOR))
    assert drawn[1:] == [1, 1]  # the sidebar changed: drawn into the layer again, then the rest
    assert not np.array_equal(changed[:, :STRIP], layered[:, :STRIP])


def test_the_floor_shadow_outline_holds_the_shadow_and_little_else() -> None:
    rig = build_rig(load_creature("dog"))
    pose = simulate(rig, 1.0, 30.0).pose(7)
    scene = pose_instances(pose, rig, show_joints=False, parts=True, by_side=False)
    texel = light_view_proj(scene)[1]
    outline = shadow_outline(scene, texel)
    # Every caster sphere's shadow (its centre projected along the light, with the radius
    # it can reach on the floor) lies inside the polygon.
    points, radii = scene.spheres(casters_only=True)
    on_ground = (points - LIGHT_DIR * (points[:, 1:2] / LIGHT_DIR[1]))[:, [0, 2]]
    angles = np.linspace(0.0, 2.0 * np.pi, 16, endpoint=False)
    rim = on_ground[:, None, :] + (radii / abs(LIGHT_DIR[1]))[:, None, None] * np.stack(
        [np.cos(angles), np.sin(angles)], axis=-1)
    edges = np.roll(outline, -1, axis=0) - outline
    to_points = rim.reshape(-1, 1, 2) - outline[None]
    cross = edges[None, :, 0] * to_points[..., 1] - edges[None, :, 1] * to_points[..., 0]
    assert np.all(cross >= -1e-9) or np.all(cross <= 1e-9)  # on one side of every edge: inside
    # ... and it is tighter than the box the shadow was drawn over before (every point
    # padded by the largest radius).
    x, z = outline[:, 0], outline[:, 1]
    area = 0.5 * abs(np.dot(x, np.roll(z, 1)) - np.dot(z, np.roll(x, 1)))
    pad = radii.max() / abs(LIGHT_DIR[1]) + 4.0 * texel
    box = np.prod(np.ptp(on_ground, axis=0) + 2.0 * pad)
    assert area < 0.8 * box
