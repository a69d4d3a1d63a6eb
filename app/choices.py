"""Typed user-facing choices shared by creature files, kinematics, the CLI and the UI.

A leaf module: it imports nothing from Gaitlab, so every layer may use it.
"""

from __future__ import annotations

from typing import Literal, get_args

WaveShape = Literal["planted", "skewed-sine"]
WAVE_SHAPES: tuple[str, ...] = get_args(WaveShape)

# Which way a leg's middle joint points: a knee forward, an elbow back, or (sprawled
# insect and spider legs) up and out, away from the body.
KneeDirection = Literal["forward", "back", "out"]
KNEE_DIRECTIONS: tuple[str, ...] = get_args(KneeDirection)

# How the trunk stands: from the hind to the fore legs, or rising from the hips (a human).
Posture = Literal["horizontal", "upright"]
POSTURES: tuple[str, ...] = get_args(Posture)

LegType = Literal["plantigrade", "digitigrade", "unguligrade"]
LEG_TYPES: tuple[str, ...] = get_args(LegType)


PLANTIGRADE_BELOW = 25.0  # degrees of ankle lift under which a foot stands on its sole (and its heel)
UNGULIGRADE_FROM = 75.0  # degrees of ankle lift from which it stands on a hoof


def leg_type(ankle_lift: float) -> LegType:
    """Which of the three leg types an ankle lift (degrees) reads as."""
    return "plantigrade" if ankle_lift < PLANTIGRADE_BELOW else "digitigrade" if ankle_lift < UNGULIGRADE_FROM \
        else "unguligrade"

# How recorded frames smooth their edges: FXAA over the creature (fast), multisampling
# (finest, costly on a software renderer) or nothing.
Antialias = Literal["fxaa", "msaa", "off"]
BodyStyle = Literal["skin", "parts"]  # one smooth skinned body, or the shapes it is made from
BODY_STYLES: tuple[BodyStyle, ...] = ("skin", "parts")
ANTIALIAS_MODES: tuple[str, ...] = get_args(Antialias)
DEFAULT_ANTIALIAS: Antialias = "fxaa"

# What the viewer can draw on the ground besides the creature (View panel, --overlays).
Overlay = Literal["footprints", "targets", "support"]
OVERLAYS: tuple[str, ...] = get_args(Overlay)
# The viewer's sidebar panels, top to bottom (``gaitlab view --panels`` opens them by these
# names, lower case with hyphens: key-poses).
PANEL_TITLES: tuple[str, ...] = ("Creature", "Gait", "Key poses", "Body", "View", "Terrain", "Path", "Playback",
                                 "Plots", "Record", "File")

# Joints whose paths over a cycle can be drawn as arcs (render --arcs, the viewer's View panel).
ArcJoint = Literal["toe", "heel", "knee", "hip", "hand", "head", "tail"]
ARC_JOINTS: tuple[str, ...] = get_args(ArcJoint)

# Camera presets. Recordings also take "follow": the default preset's angle, kept to the
# path's heading (as every preset is for a travelling creature).
CameraPreset = Literal["three-quarter", "side", "front", "top", "chase"]
CAMERA_PRESETS: tuple[str, ...] = get_args(CameraPreset)
DEFAULT_CAMERA: CameraPreset = "three-quarter"
CameraChoice = Literal["three-quarter", "side", "front", "top", "chase", "follow"]
CAMERA_CHOICES: tuple[str, ...] = get_args(CameraChoice)

# GIF size against fidelity (see app.output.gif): best (255 colours, lossless), good, small.
GifQuality = Literal["best", "good", "small"]
GIF_QUALITIES: tuple[str, ...] = get_args(GifQuality)
DEFAULT_GIF_QUALITY: GifQuality = "good"

# MP4 (H.264) constant rate factor: 0 lossless .. 51 smallest.
DEFAULT_CRF = 18  # visually lossless for these flat-shaded pictures
MAX_CRF = 51

# Skeleton files `gaitlab export` writes.
ExportFormat = Literal["bvh", "glb", "usda", "usdc"]
EXPORT_FORMATS: tuple[str, ...] = get_args(ExportFormat)

MAX_SIZE = 8192  # pixels: the widest or tallest image Gaitlab renders
MAX_HERD = 1000  # animals in one herd
