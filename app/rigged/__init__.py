"""Rigged models users bring (glTF with a skin): reading their skeleton, rest pose and
skinned mesh (:mod:`.gltf`), and finding their legs (:mod:`.legs`). No GL."""
