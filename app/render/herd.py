"""A herd's instances: every animal's shapes from one solved cycle, in one batch.

:class:`HerdInstances` keeps the instance rows of every frame of the herd's cycle
(:func:`app.render.scene.motion_instances`); per frame it blends each animal's two cycle
frames and moves the rows to the animal's place, size and heading, for all animals at
once. The renderer then draws the whole herd with the same four instanced draw calls as
one creature.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from ..kinematics.herd import Herd
from ..kinematics.motion import Motion
from .scene import SceneInstances, motion_instances


class HerdInstances:
    """Instance rows for a herd; rebuilt from the herd's cycle when its rig changes."""

    def __init__(self, herd: Herd, show_joints: bool = True) -> None:
        self.show_joints = show_joints
        self._cycle: Motion | None = None
        self._rows: SceneInstances | None = None
        self._update(herd)

    def _update(self, herd: Herd) -> None:
        if herd.cycle is not self._cycle:
            self._cycle = herd.cycle
            self._rows = motion_instances(herd.cycle, show_joints=self.show_joints)

    def frame(self, herd: Herd, ground_height=None) -> SceneInstances:
        """Every animal's capsules (N * C, 11) and ellipsoids (N * E, 18), the shadow
        casters (each animal's skull) first."""
        self._update(herd)
        assert self._rows is not None
        f0, f1, w = herd.blend()
        scale, rot, move = herd.transforms(ground_height)
        caps = _blend(self._rows.capsules, f0, f1, w)  # (N, C, 11)
        ells = _blend(self._rows.ellipsoids, f0, f1, w)  # (N, E, 18)
        out_c = caps.copy()
        for k in (0, 3):  # the two end points
            out_c[..., k:k + 3] = _place(caps[..., k:k + 3], scale, rot, move)
        out_c[..., 6:8] = caps[..., 6:8] * scale[:, None, None]
        out_e = ells.copy()
        out_e[..., 0:3] = _place(ells[..., 0:3], scale, rot, move)
        for k in (3, 6, 9):  # the axes turn with the animal
            out_e[..., k:k + 3] = np.einsum("nij,nsj->nsi", rot, ells[..., k:k + 3])
        out_e[..., 12:15] = ells[..., 12:15] * scale[:, None, None]
        casters = self._rows.ellipsoid_casters
        n = herd.count
        ellipsoids = np.concatenate([out_e[:, :casters].reshape(n * casters, -1),
                                     out_e[:, casters:].reshape(-1, out_e.shape[-1])])
        return SceneInstances(out_c.reshape(-1, out_c.shape[-1]).astype(np.float32),
                              ellipsoids.astype(np.float32), n * casters)


def _blend(rows: NDArray[np.float32], f0: NDArray[np.int64], f1: NDArray[np.int64],
           w: NDArray[np.float64]) -> NDArray[np.float64]:
    """Rows (F, S, K) blended between frames f0 and f1 with weight w (each (N,)): (N, S, K)."""
    a, b = rows[f0].astype(np.float64), rows[f1].astype(np.float64)
    return a + (b - a) * w[:, None, None]


def _place(points: NDArray[np.float64], scale: NDArray[np.float64], rot: NDArray[np.float64],
           move: NDArray[np.float64]) -> NDArray[np.float64]:
    """Points (N, S, 3) in each animal's frame, scaled, turned and moved into the world."""
    return np.einsum("nij,nsj->nsi", rot, points * scale[:, None, None]) + move[:, None, :]
