"""The key-poses sheet: contact, down, pass, up and the next (mirrored) contact side by
side, as an animator lays out a walk (``gaitlab poses``).

Each pose is rendered headless from the side, orthographic, all with one camera framing
the whole cycle so heights compare across the sheet (a dashed line marks the hips' rest
height), and labelled with its name, the hips' height against rest and its frame at the
creature's timing frame rate (24 fps unless the file gives one: ``gait.timing_fps``).
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from .kinematics.clip import clip_motion, frame_at
from .kinematics.poses import key_pose_phases, reference_foot
from .kinematics.world import World
from .output import check_output_dir, write_png
from .render.clip import ClipRenderer
from .render.framing import clip_camera, loop_grid_spacing
from .render.options import RenderOptions, ViewSettings
from .rigging import build_rig
from .spec import CreatureSpec
from .styles import DEFAULT_TIMING_FPS

POSE_NAMES: tuple[str, ...] = ("contact", "down", "pass", "up", "contact")
LABEL_HEIGHT = 44  # pixels under each pose for its label


@dataclass(frozen=True)
class PoseSheet:
    """The sheet's image (H, W, 3) uint8, and each pose's name, cycle phase, time (s) and
    the rear hips' height against their rest height (m)."""

    image: NDArray[np.uint8]
    names: tuple[str, ...]
    phases: tuple[float, ...]
    times: tuple[float, ...]
    hip_heights: tuple[float, ...] = ()


def pose_sheet(spec: CreatureSpec, size: tuple[int, int] = (320, 360), second_step: bool = False) -> PoseSheet:
    """Render the five key poses of the first step (or the second, mirrored one), each
    ``size`` pixels (width, height) above its label."""
    from PIL import Image, ImageDraw, ImageFont

    rig = build_rig(spec)
    world = World(in_place=True)
    frequency = rig.gait.frequency
    timing = spec.gait.timing_fps or DEFAULT_TIMING_FPS
    phases = key_pose_phases(first_step=not second_step)
    times = phases / frequency
    cycle, _ = clip_motion(rig, 60.0, cycles=1.0, world=world)
    view = ViewSettings(size=size, camera="side", options=RenderOptions())
    # Orthographic, so one height is one pixel row across the sheet.
    camera = replace(clip_camera(cycle, view), ortho=True)
    options = RenderOptions(grid_spacing=loop_grid_spacing(cycle, None))
    w, h = size
    sheet = Image.new("RGB", (5 * w, h + LABEL_HEIGHT), (250, 248, 244))
    font = ImageFont.load_default(size=max(12, min(22, w // 14)))
    small = ImageFont.load_default(size=max(10, min(16, w // 20)))
    hips = slice(reference_foot(rig), reference_foot(rig) + 2)
    rest = float(rig.girdle_rest_height[-1])
    heights = []
    with ClipRenderer(size, view.antialias) as renderer:
        for i, (name, phase, t) in enumerate(zip(POSE_NAMES, phases, times)):
            motion = frame_at(rig, float(t), 60.0, world)
            pixels = renderer.frame(motion, 0, camera, options)
            sheet.paste(Image.fromarray(pixels), (i * w, 0))
            height = float(motion.joints[0, hips, 0, 1].mean()) - rest  # the rear hips against their rest
            heights.append(height)
            # The label on its own cell, so a long one is cut at the cell's edge.
            cell = Image.new("RGB", (max(w - 2, 1), LABEL_HEIGHT), (250, 248, 244))
            draw = ImageDraw.Draw(cell)
            side = "left" if (phase % 1.0) < 0.5 else "right"
            title = f"{i + 1} {name}" + (f" ({side})" if name == "contact" else "")
            draw.text((8, 4), title, fill=(30, 30, 34), font=font)
            frame = t * timing
            frame_text = f"{frame:.0f}" if abs(frame - round(frame)) < 0.05 else f"{frame:.1f}"
            draw.text((8, 26), f"frame {frame_text}  hips {height * 1000:+.0f} mm", fill=(90, 90, 96), font=small)
            sheet.paste(cell, (i * w + 1, h))
            if i:
                ImageDraw.Draw(sheet).line([(i * w, 0), (i * w, h + LABEL_HEIGHT)], fill=(200, 196, 188), width=1)
    # The hips' rest height, dashed across every pose: how far each one rides above or below it.
    row = _screen_row(camera, (w, h), np.array([0.0, rest, 0.0]) + np.asarray(motion.root[0, :3, 3]) * [1, 0, 1])
    if 0 <= row < h:
        draw = ImageDraw.Draw(sheet)
        for x in range(0, 5 * w, 12):
            draw.line([(x, row), (x + 6, row)], fill=(70, 110, 190), width=1)
        draw.text((4, row - 14), "hips at rest", fill=(70, 110, 190), font=small)
    return PoseSheet(image=np.asarray(sheet), names=POSE_NAMES, phases=tuple(float(p) for p in phases),
                     times=tuple(float(t) for t in times), hip_heights=tuple(heights))


def _screen_row(camera, size: tuple[int, int], point: NDArray[np.float64]) -> int:
    """The pixel row (from the top) where a world point (3,) appears."""
    w, h = size
    clip = np.asarray(camera.view_proj(w / h)) @ np.append(point, 1.0)
    return int(round((1.0 - (clip[1] / clip[3] + 1.0) / 2.0) * h))


def write_pose_sheet(spec: CreatureSpec, output: Path, size: tuple[int, int] = (320, 360),
                     second_step: bool = False) -> PoseSheet:
    """Render the sheet and write it as PNG (atomically; the folder is checked first)."""
    check_output_dir(output)
    sheet = pose_sheet(spec, size, second_step)
    write_png(output, sheet.image)
    return sheet
