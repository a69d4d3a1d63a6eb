"""Arcs drawn as thin tubes through a joint's positions over the last cycle, with a bead
at each key pose (numpy only; the renderer draws them with the creature's shapes). Each
joint has its colour; a right-side limb's arc is a darker shade of it."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from ..kinematics.arcs import ARC_JOINTS
from .scene import SceneInstances, _capsules, _ellipsoids

# One colour per joint kind (linear), bright enough to read against the creature and ground.
ARC_COLORS: dict[str, NDArray[np.float64]] = {name: np.array(rgb) ** 2 for name, rgb in zip(ARC_JOINTS, (
    (0.95, 0.75, 0.10), (0.85, 0.35, 0.85), (0.20, 0.75, 0.95), (0.30, 0.85, 0.40), (0.98, 0.45, 0.20),
    (0.55, 0.45, 0.95), (0.90, 0.25, 0.40)))}


RIGHT_SHADE = 0.35  # a right limb's arc: its joint's colour this bright (left limbs come first, then right)


def arc_instances(trails: dict[str, NDArray[np.float64]], markers: dict[str, NDArray[np.float64]],
                  size: float) -> SceneInstances:
    """Tubes through each trail (joint -> (N, K, 3)) and beads at its key poses (joint ->
    (M, K, 3)); ``size`` (m) is the tube's radius, beads three times it."""
    capsules, beads = [np.zeros((0, 11))], [np.zeros((0, 18))]
    for joint, points in trails.items():
        k = points.shape[1]
        shade = np.where((np.arange(k) % 2 == 1) & (k > 1), RIGHT_SHADE, 1.0)[:, None]
        color = ARC_COLORS[joint][None, :] * shade  # (K, 3)
        if len(points) >= 2:
            capsules.append(_capsules(points[:-1], points[1:], size, size, color[None]).reshape(-1, 11))
        bead = markers.get(joint)
        if bead is not None and len(bead):
            beads.append(_ellipsoids(bead, np.array([0.0, 0.0, 1.0]), np.full(3, 3.0 * size),
                                     np.broadcast_to(color, bead.shape)).reshape(-1, 18))
    return SceneInstances(capsules=np.concatenate(capsules).astype(np.float32),
                          ellipsoids=np.concatenate(beads).astype(np.float32), ellipsoid_casters=0)
