"""Rigged models users bring (glTF with a skin): reading their skeleton, rest pose and
skinned mesh (:mod:`.gltf`), finding their legs (:mod:`.legs`), the model ready to drive
(:mod:`.loaded`: read once, its scale and its mesh in metres), the creature with their
proportions (:mod:`.creature`) and that creature's motion on their own skeleton
(:mod:`.drive`). No GL."""

from __future__ import annotations

MODEL_SUFFIXES = (".glb", ".gltf")


def is_model_path(text: str) -> bool:
    """Whether ``text`` names a rigged model file (by its suffix)."""
    return text.lower().endswith(MODEL_SUFFIXES)


# What a rigged model's creature takes from the model itself and its skeleton cannot
# stretch to follow: table -> keys (legs.PAIR.KEY, body.KEY, arms.KEY).
MODEL_OWN = {"legs": ("femur", "tibia", "metatarsus", "toe", "hip_offset"), "body": ("length", "width"),
             "arms": ("upper", "fore", "shoulder_width")}


def model_owns(key: str) -> bool:
    """Whether the creature key ``key`` (``legs.hind.femur``) is a rigged model's own."""
    parts = key.split(".")
    return parts[-1] in MODEL_OWN.get(parts[0], ())

