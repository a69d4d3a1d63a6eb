"""A herd's instances: every animal's shapes from one solved cycle, in one batch.

:class:`HerdInstances` keeps the instance rows of every frame of the herd's cycle
(:func:`app.render.scene.motion_instances`); per frame it blends each animal's two cycle
frames and moves the rows to the animal's place, size and heading, for all animals at
once. The renderer then draws the whole herd with the same four instanced draw calls as
one creature. Each animal's legs are set down on the ground under its feet and reach to
where its feet are locked (:func:`app.kinematics.herd.legs_to_ground`): the leg shapes
are built from those joints, and a skinned body's thigh, shin and foot bones turn and
move with them.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from ..choices import BodyStyle
from ..kinematics.appendages import Appendages
from ..kinematics.herd import Herd, LegAdjustment
from ..kinematics.motion import Motion
from ..kinematics.skeleton import LEG_JOINTS, skeleton_points
from ..rigged.drive import motion_turns
from ..rigged.loaded import LoadedModel, load_model
from .bodies import BodyDraw, motion_body, shared_body_cache
from .scene import Cap, Ell, SceneInstances, leg_instances, motion_instances


class HerdInstances:
    """Instance rows for a herd (and its animals' skinned bodies, with ``body`` "skin");
    rebuilt from the herd's cycle when its rig changes."""

    def __init__(self, herd: Herd, show_joints: bool = True, body: BodyStyle = "skin", by_side: bool = False) -> None:
        self.show_joints = show_joints
        self.body = body
        self.by_side = by_side
        self._cycle: Motion | None = None
        self._rows: SceneInstances | None = None  # with the legs (flat ground)
        self._body_rows: SceneInstances | None = None  # without them (legs set down on uneven ground)
        self._skins: BodyDraw | None = None
        self._leg_bones: NDArray[np.int64] | None = None  # (L, 5) skeleton joint of each leg joint
        self._model: LoadedModel | None = None  # a rigged model's herd: each animal's skeleton driven
        self._turns: Appendages | None = None  # (its cycle's neck, head and tail turns)
        self._update(herd)

    def matches(self, show_joints: bool, body: BodyStyle, by_side: bool) -> bool:
        """Whether these instances draw as asked."""
        return (self.show_joints, self.body, self.by_side) == (show_joints, body, by_side)

    def _update(self, herd: Herd) -> None:
        if herd.cycle is not self._cycle:
            self._cycle = herd.cycle
            skin = self.body == "skin"
            # On skinned bodies a herd shows no joint markers (inside the skin, and many).
            self._rows = motion_instances(herd.cycle, show_joints=self.show_joints and not skin, parts=not skin,
                                          by_side=self.by_side)
            self._body_rows = motion_instances(herd.cycle, show_joints=False, parts=not skin, by_side=self.by_side,
                                               legs=False)
            self._skins = motion_body(herd.cycle, shared_body_cache()) if skin else None
            self._model = load_model(herd.cycle.rig.model) if skin and herd.cycle.rig.model else None
            self._turns = motion_turns(herd.cycle) if self._model is not None else None
            if skin and self._model is None:
                assert self._skins is not None
                names = skeleton_points(herd.cycle.frames(0), self._skins.body.layout)[0].names
                self._leg_bones = np.array([[names.index(f"{leg}_{part}") for part in LEG_JOINTS]
                                            for leg in herd.cycle.leg_names])

    def frame(self, herd: Herd, ground_height=None) -> SceneInstances:
        """Every animal's capsules (N * C, 11) and ellipsoids (N * E, 18), the shadow
        casters (each animal's skull) first."""
        self._update(herd)
        assert self._rows is not None and self._body_rows is not None
        f0, f1, w = herd.blend()
        scale, rot, move = herd.transforms(ground_height)
        rows = self._rows
        leg_joints, legs = herd.legs(ground_height, (scale, rot, move))  # legs None: the cycle's as they are
        if legs is not None:
            move = move.copy()
            move[:, 1] -= legs.lowered
            rows = self._body_rows
        caps = _blend(rows.capsules, f0, f1, w)  # (N, C, 11), each animal's at size 1 in its own frame
        ells = _blend(rows.ellipsoids, f0, f1, w)  # (N, E, 18)
        if legs is not None and self._skins is None:  # the legs' shapes from the joints set down
            # (built in each animal's own frame at size 1, then placed like the rest)
            local = np.einsum("nji,nlkj->nlki", rot, legs.joints - move[:, None, None, :]) / scale[:, None, None, None]
            leg_rows = leg_instances(local, herd.rig, show_joints=self.show_joints, by_side=self.by_side)
            caps = np.concatenate([caps, leg_rows.capsules.astype(np.float64)], axis=1)
            ells = np.concatenate([ells, leg_rows.ellipsoids.astype(np.float64)], axis=1)
        out_c = caps.copy()
        for k in (0, 3):  # the two end points
            out_c[..., k:k + 3] = _place(caps[..., k:k + 3], scale, rot, move)
        out_c[..., Cap.RADII] = caps[..., Cap.RADII] * scale[:, None, None]
        out_e = ells.copy()
        out_e[..., 0:3] = _place(ells[..., 0:3], scale, rot, move)
        axes = ells[..., 3:12].reshape(len(ells), -1, 3)  # the three axes turn with the animal
        out_e[..., 3:12] = (axes @ np.swapaxes(rot, 1, 2)).reshape(ells.shape[0], ells.shape[1], 9)
        out_e[..., Ell.RADII] = ells[..., Ell.RADII] * scale[:, None, None]
        casters = self._rows.ellipsoid_casters
        n = herd.count
        width = out_e.shape[-1]
        parts = [out_e[:, :casters].reshape(n * casters, width), out_e[:, casters:].reshape(-1, width)]
        out_caps = out_c.reshape(-1, caps.shape[-1])
        ellipsoids = np.concatenate(parts)
        bodies: tuple[BodyDraw, ...] = ()
        if self._model is not None and self._skins is not None:  # each animal's own skeleton, driven at once
            nearest = np.where(w < 0.5, f0, f1)
            turns = None if self._turns is None else self._turns.at(nearest)
            driven = _drive_models(self._model, herd.cycle, f0, f1, w, leg_joints, scale, rot, move, turns)
            bodies = tuple(BodyDraw(self._skins.body, driven[k]) for k in range(n))
        elif self._skins is not None:  # each animal's body: its blended skin, placed
            skins = self._skins.skin.astype(np.float64)
            skin = skins[f0] + (skins[f1] - skins[f0]) * w[:, None, None, None]  # (N, J, 4, 4)
            posed = _placement(scale, rot, move)[:, None] @ skin
            if legs is not None:
                assert self._leg_bones is not None
                posed = _set_down(posed, self._leg_bones, legs)
            posed = posed.astype(np.float32)
            bodies = tuple(BodyDraw(self._skins.body, posed[k]) for k in range(n))
        return SceneInstances(out_caps.astype(np.float32), ellipsoids.astype(np.float32), n * casters, bodies)


def _placement(scale: NDArray[np.float64], rot: NDArray[np.float64], move: NDArray[np.float64]) -> NDArray[np.float64]:
    """Each animal's placing in the world (N, 4, 4): scaled, turned, moved."""
    place = np.tile(np.eye(4), (len(scale), 1, 1))
    place[:, :3, :3] = rot * scale[:, None, None]
    place[:, :3, 3] = move
    return place


def _drive_models(model: LoadedModel, cycle: Motion, f0: NDArray[np.int64], f1: NDArray[np.int64],
                  w: NDArray[np.float64], leg_joints: NDArray[np.float64], scale: NDArray[np.float64],
                  rot: NDArray[np.float64], move: NDArray[np.float64],
                  turns: Appendages | None = None) -> NDArray[np.float32]:
    """Skinning matrices (N, J, 4, 4) of a rigged model's herd: every animal's skeleton
    driven in one call (:func:`app.rigged.drive.drive_joints`, vectorised over animals as
    over frames) from its leg joints in the world ``leg_joints`` (N, L, 5, 3; set down and
    locked), its blended cycle body transform and arms, placed, and its neck, head and
    tail turns (``turns``, each animal's nearest cycle frame's: they are in its heading's
    frame, so the placement does not change them)."""
    root = _placement(scale, rot, move) @ (cycle.root[f0] + (cycle.root[f1] - cycle.root[f0]) * w[:, None, None])
    arms = None
    if cycle.arms.shape[1]:
        blended = _blend(cycle.arms.reshape(cycle.frame_count, -1, 3).astype(np.float32), f0, f1, w)
        arms = _place(blended, scale, rot, move).reshape(len(w), *cycle.arms.shape[1:])
    return model.skin(leg_joints, root, cycle.rig.ankle_lift, arms, turns)


def _set_down(posed: NDArray[np.float64], bones: NDArray[np.int64], legs: LegAdjustment) -> NDArray[np.float64]:
    """Skinning matrices (N, J, 4, 4) with each leg's bones (``bones`` (L, 5): hip, knee,
    ankle, ball, toe joints) set down as ``legs`` says: the thigh turned about the hip,
    the shin turned and moved with the knee, the foot moved."""
    out = posed.copy()
    hip, knee = legs.joints[:, :, 0], legs.joints[:, :, 1] - legs.knee_move  # where they were
    n, count = legs.thigh.shape[:2]
    for rotation, pivot, move, column in ((legs.thigh, hip, np.zeros_like(hip), 0),
                                          (legs.shin, knee, legs.knee_move, 1)):
        # p -> R (p - pivot) + pivot + move, for every leg of every animal at once
        delta = np.tile(np.eye(4), (n, count, 1, 1))
        delta[..., :3, :3] = rotation
        delta[..., :3, 3] = pivot + move - np.einsum("nlij,nlj->nli", rotation, pivot)
        joint = bones[:, column]
        out[:, joint] = delta @ posed[:, joint]
    foot = bones[:, 2:]  # ankle, ball, toe: moved with the foot
    translation = out[..., :3, 3]  # (N, J, 3), a view
    translation[:, foot] += legs.foot_move[:, :, None, :]
    return out


def _blend(rows: NDArray[np.float32], f0: NDArray[np.int64], f1: NDArray[np.int64],
           w: NDArray[np.float64]) -> NDArray[np.float64]:
    """Rows (F, S, K) blended between frames f0 and f1 with weight w (each (N,)): (N, S, K)."""
    a, b = rows[f0].astype(np.float64), rows[f1].astype(np.float64)
    return a + (b - a) * w[:, None, None]


def _place(points: NDArray[np.float64], scale: NDArray[np.float64], rot: NDArray[np.float64],
           move: NDArray[np.float64]) -> NDArray[np.float64]:
    """Points (N, S, 3) in each animal's frame, scaled, turned and moved into the world."""
    return (points * scale[:, None, None]) @ np.swapaxes(rot, 1, 2) + move[:, None, :]
