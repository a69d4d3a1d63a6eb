"""Each leg's sagittal angles and its strikes, from Gaitlab's own motion or from a BVH
clip, ready to average over cycles (:mod:`.angles`).

For a clip the legs are found as ``analyze`` finds feet (the same joint-name rules): the
knee is the ankle joint's parent and the hip the knee's. The body's forward direction is
the line between the hips turned a quarter turn (bipeds) or the pelvis's horizontal
velocity (others), pointed the way the body travels. The ankle's zero is the skeleton's
rest pose (every rotation 0), as a static calibration trial would give it.

Pure numpy, no GL.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from .angles import LegAngles, leg_angles, strikes_from_contact
from .bvh import BvhClip, InputError, read_bvh
from .sources import FootMap, find_feet, resolve_feet


@dataclass(frozen=True)
class Legs:
    """Legs of one source: name -> angles (T,) each, name -> strike frames, frames per
    second, and a note on what was found."""

    angles: dict[str, LegAngles]
    strikes: dict[str, NDArray[np.intp]]
    fps: float
    source: str
    note: str = ""


def motion_legs(motion) -> Legs:
    """Every leg of a Gaitlab :class:`~app.kinematics.motion.Motion` (its strikes are the
    frames its contact begins)."""
    rig = motion.rig
    forward = motion.root[:, :3, 2]
    angles, strikes = {}, {}
    for index, name in enumerate(rig.leg_names):
        j = motion.joints[:, index]
        zero = -float(np.degrees(rig.ankle_lift[index]))  # the rest pose's foot against its shank
        angles[name] = leg_angles(j[:, 0], j[:, 1], j[:, 2], j[:, 3], forward, ankle_zero=zero)
        strikes[name] = strikes_from_contact(motion.contact[:, index])
    return Legs(angles, strikes, float(motion.fps), f"Gaitlab {rig.name}")


def _rest_dorsiflexion(clip: BvhClip, hip: str, knee: str, ankle: str, toe: str) -> float:
    """The ankle's reading in the skeleton's rest pose: every rotation channel at 0 (the
    position channels as in the first frame, where a joint's position replaces its offset)."""
    rest = BvhClip(path=clip.path, joints=clip.joints, frames=clip.frames[:1].copy(), frame_time=clip.frame_time)
    for joint in clip.joints:
        for k, channel in enumerate(joint.channels):
            if channel[1:].lower() == "rotation":
                rest.frames[0, joint.first_channel + k] = 0.0
    p = rest.positions([hip, knee, ankle, toe])[0]
    forward = np.cross(np.array([0.0, 1.0, 0.0]), np.cross(p[3] - p[2], np.array([0.0, 1.0, 0.0])))
    if np.linalg.norm(forward) < 1e-9:
        return 0.0
    a = leg_angles(p[None, 0], p[None, 1], p[None, 2], p[None, 3], forward[None])
    return float(a.ankle[0])


def foremost_strikes(ankle: NDArray[np.float64], root: NDArray[np.float64], forward: NDArray[np.float64],
                     events: NDArray[np.intp]) -> NDArray[np.intp]:
    """Heel strikes (frames) of a clip's foot by Zeni, Richards & Higginson (2008, Gait
    Posture 27:710): the strike is where the foot is farthest ahead of the body. ankle,
    root (T, 3); forward (T, 3); ``events`` (K,) the contact events' strikes, which give
    the cycle length (a touch of the toes late in the swing can pass for a strike there,
    but not for the foremost point). Falls back to ``events`` with fewer than three."""
    if len(events) < 3:
        return events
    from .filters import find_peaks

    unit = forward / np.maximum(np.linalg.norm(forward, axis=-1, keepdims=True), 1e-12)
    ahead = np.sum((ankle - root) * unit, axis=-1)
    cycle = float(np.median(np.diff(events)))
    peaks, _ = find_peaks(ahead, distance=max(1, int(0.6 * cycle)), prominence=0.3 * float(np.ptp(ahead)))
    return peaks.astype(np.intp) if len(peaks) >= 2 else events


def leg_chains(clip: BvhClip, path: str, feet: dict[str, tuple[str, str | None]] | None = None
               ) -> tuple[FootMap, dict[str, tuple[str, str, str, str]]]:
    """Each foot's joints in a BVH clip, foot name -> (hip, knee, ankle, toe): the feet
    as ``analyze`` finds them (or ``feet``), the knee the ankle joint's parent and the hip
    the knee's. Raises :class:`InputError` for a foot without them."""
    mapping = FootMap(resolve_feet(feet, clip.names), "given with --feet") if feet else find_feet(clip.names, path)
    chains = {}
    for foot, (ankle, toe) in mapping.feet.items():
        if ankle.endswith("_ball") and clip.joints[clip.index(ankle)].parent >= 0:  # a Gaitlab export's foot
            ankle = clip.joints[clip.joints[clip.index(ankle)].parent].name
        knee_index = clip.joints[clip.index(ankle)].parent
        hip_index = clip.joints[knee_index].parent if knee_index >= 0 else -1
        if hip_index < 0 or toe is None:
            raise InputError(f"{path}: foot {foot} ({ankle}) has no knee and hip above it or no toe joint after "
                             "it; this needs hip, knee, ankle and toe joints")
        chains[foot] = (clip.joints[hip_index].name, clip.joints[knee_index].name, ankle, toe)
    return mapping, chains


def bvh_legs(path: str, feet: dict[str, tuple[str, str | None]] | None = None) -> Legs:
    """Every leg of a BVH clip with its strikes (from ``analyze``'s events)."""
    from . import analyze_tracks
    from .sources import MAX_COORDINATE, _leading_jumps, _to_y_up, detect_up, tracks_from_bvh

    clip = read_bvh(path)
    if clip.frames.shape[0] < 2:
        raise InputError(f"{path}: the clip holds {clip.frames.shape[0]} frame(s); comparing joint angles needs at "
                         "least one full stride")
    mapping, chains = leg_chains(clip, path, feet)
    names = [n for chain in chains.values() for n in chain] + [clip.joints[0].name]
    points = clip.positions(names)  # (T, N, 3)
    if not np.all(np.abs(points) < MAX_COORDINATE):
        raise InputError(f"{path}: joint positions reach {float(np.nanmax(np.abs(points))):.3g} (or are not finite); "
                         f"positions must be under {MAX_COORDINATE:g} in file units")
    feet_pts = points[:, [4 * i + 2 for i in range(len(chains))]]
    toes_pts = points[:, [4 * i + 3 for i in range(len(chains))]]
    skip = _leading_jumps(np.concatenate([feet_pts, toes_pts, points[:, -1:]], axis=1))
    up_axis = detect_up(points[skip:, -1], feet_pts[skip:])
    points = _to_y_up(points[skip:], up_axis)
    root = points[:, -1]
    velocity = np.gradient(root, axis=0)
    velocity[:, 1] = 0.0
    window = max(1, int(round(1.0 / clip.frame_time)))
    kernel = np.ones(window) / window
    heading = np.stack([np.convolve(velocity[:, k], kernel, mode="same") for k in range(3)], axis=-1)
    if {"L", "R"} <= set(chains):  # a biped: across the hips, pointed the way it goes
        left, right = (points[:, 4 * list(chains).index(side)] for side in ("L", "R"))
        across = np.cross(left - right, np.array([0.0, 1.0, 0.0]))
        sign = 1.0 if float(np.sum(across * heading)) >= 0 else -1.0
        forward = across * sign
    else:
        forward = heading
    tracks, _ = tracks_from_bvh(path, mapping.feet)
    report = analyze_tracks(tracks)
    angles, strikes = {}, {}
    for i, (foot, (hip, knee, ankle, toe)) in enumerate(chains.items()):
        p = points[:, 4 * i:4 * i + 4]
        zero = _rest_dorsiflexion(clip, hip, knee, ankle, toe)
        angles[foot] = leg_angles(p[:, 0], p[:, 1], p[:, 2], p[:, 3], forward, ankle_zero=zero)
        events = next((fe for fe in report.foot_events if fe.name == foot), None)
        found = np.array([s.strike for s in events.steps if s.complete], dtype=np.intp) \
            if events is not None else np.zeros(0, dtype=np.intp)
        strikes[foot] = foremost_strikes(p[:, 2], root, forward, found)
    note = f"{mapping.rig} joints" + (f"; skipped {skip} leading frames" if skip else "")
    return Legs(angles, strikes, 1.0 / clip.frame_time, path, note)
