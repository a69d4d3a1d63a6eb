"""Clips as skeletons: local transforms rebuild the joints exactly, leg bones keep their
lengths, every frame is a rotation, and no bone flips from one frame to the next."""

from __future__ import annotations

import numpy as np
import pytest

from app import build_rig, load_creature
from app.kinematics.clip import clip_motion
from app.kinematics.skeleton import LEG_JOINTS, forward_kinematics, skeleton_clip
from app.worlds import make_world

CASES = [("dog", None, None), ("horse", None, None), ("bear", None, None), ("ant", None, None),
         ("spider", None, None), ("centipede", None, None), ("dog", "circle:r=2", "hills:amp=0.1"),
         ("cat", None, "stairs:rise=0.06,run=0.3")]


def angles_between_frames(rotation: np.ndarray) -> np.ndarray:
    rel = np.einsum("tjki,tjkl->tjil", rotation[:-1], rotation[1:])
    return np.degrees(np.arccos(np.clip((np.trace(rel, axis1=2, axis2=3) - 1) / 2, -1, 1)))


@pytest.mark.parametrize("creature, path, terrain", CASES)
def test_skeleton_rebuilds_the_clip(creature: str, path, terrain) -> None:
    motion, _ = clip_motion(build_rig(load_creature(creature)), 60.0, cycles=2, world=make_world(path, terrain))
    clip = skeleton_clip(motion)
    names = clip.skeleton.names
    position, rotation = forward_kinematics(clip.skeleton, clip.local_rotation, clip.local_translation)
    assert np.abs(position - clip.world_position).max() < 1e-9
    assert np.abs(np.einsum("tjki,tjkl->tjil", rotation, rotation) - np.eye(3)).max() < 1e-9
    assert np.allclose(np.linalg.det(rotation), 1.0)
    for leg, leg_name in enumerate(motion.leg_names):  # every leg joint is the clip's own
        for k, part in enumerate(LEG_JOINTS):
            j = names.index(f"{leg_name}_{part}")
            assert np.abs(position[:, j] - motion.joints[:, leg, k]).max() < 1e-9
            if part != "hip":  # bones of the leg: constant length, along the parent's +Y
                assert np.ptp(np.linalg.norm(clip.local_translation[:, j], axis=-1)) < 1e-9
                assert np.abs(clip.local_translation[:, j, [0, 2]]).max() < 1e-9 or part == "toe"
    assert angles_between_frames(rotation).max() < 30.0  # no flips at 60 fps
    parents = clip.skeleton.parents
    assert parents[0] == -1 and all(p < j for j, p in enumerate(parents) if j)  # parents first
