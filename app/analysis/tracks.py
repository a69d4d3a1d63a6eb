"""Foot trajectories in world space: what every analysis input becomes.

Gaitlab's own motion, BVH files and CSV files all turn into a :class:`FootTracks`:
metres, seconds, Y up, one heel and one toe point per foot (the heel is the back of the
contact, e.g. the ankle of a BVH skeleton or the ball of a digitigrade Gaitlab leg),
and the body's position for the direction and speed of travel.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

if TYPE_CHECKING:  # (the kinematics, and scipy.interpolate with them, load only when a motion is analysed)
    from ..kinematics.motion import Motion



@dataclass(frozen=True)
class FootTracks:
    """times (T,) s; names (F,) feet (e.g. LF RF LH RH, or L R); heel, toe (T, F, 3) m;
    body (T, 3) m; hip_height (m) when known (scales the skating thresholds); source text;
    ``exact``: noise-free motion (Gaitlab's own), whose feet's vertical speed can be trusted."""

    times: NDArray[np.float64]
    names: tuple[str, ...]
    heel: NDArray[np.float64]
    toe: NDArray[np.float64]
    body: NDArray[np.float64]
    source: str
    hip_height: float | None = None
    exact: bool = False
    hands: NDArray[np.float64] | None = None  # (T, 2, 3) m, left and right hand tips (bipeds with arms)
    compromised: int = 0  # stances on compromised footholds (Gaitlab's own motion on uneven ground)
    cut_short: int = 0  # stances that lifted early or landed late where the leg could not reach (idem)
    unit_scale: float = 1.0  # metres per unit of the file the tracks were read from

    @property
    def frame_count(self) -> int:
        return int(self.times.shape[0])

    @property
    def fps(self) -> float:
        return float(1.0 / np.median(np.diff(self.times))) if self.frame_count > 1 else 0.0

    @property
    def duration(self) -> float:
        return float(self.times[-1] - self.times[0]) if self.frame_count > 1 else 0.0

    def travel_direction(self, smoothing_seconds: float = 0.5) -> NDArray[np.float64]:
        """Unit horizontal direction of travel per frame (T, 3), from the body's velocity
        averaged over ``smoothing_seconds``; +Z where the body hardly moves."""
        from .filters import running_mean

        velocity = np.gradient(self.body, self.times, axis=0) * np.array([1.0, 0.0, 1.0])
        window = max(1, int(round(smoothing_seconds * self.fps)))
        smooth = running_mean(velocity, window)
        norm = np.linalg.norm(smooth, axis=1, keepdims=True)
        fallback = np.array([0.0, 0.0, 1.0])
        if float(np.median(norm)) < 1e-3:  # in place: use the overall heading of the feet's swings
            return np.broadcast_to(fallback, smooth.shape).copy()
        return np.where(norm > 1e-6, smooth / np.maximum(norm, 1e-12), fallback)

    def forward_velocity(self, points: NDArray[np.float64]) -> NDArray[np.float64]:
        """Velocity (m/s) of points (T, F, 3) along each frame's direction of travel, (T, F);
        a curving path is followed frame by frame."""
        direction = self.travel_direction()
        velocity = np.gradient(points, self.times, axis=0)
        return np.einsum("tfi,ti->tf", velocity, direction)

    def speed(self) -> float:
        """Median horizontal speed of the body (m/s)."""
        velocity = np.gradient(self.body, self.times, axis=0)
        return float(np.median(np.hypot(velocity[:, 0], velocity[:, 2])))


def tracks_from_motion(motion: Motion) -> FootTracks:
    """Gaitlab's motion in world space: a travelling creature as it is; an in-place one put
    on the ground it walks over (the ground moved back by ``ground_offset``, so in the
    ground's frame everything moves forward by it). The heel point is the foot's heel
    (``Motion.heel``: a rolling plantigrade foot's heel, otherwise the ball, what a
    digitigrade or unguligrade foot stands on) and the toe point the toe tip. On terrain
    the feet's heights are measured above the ground under them."""
    shift = np.zeros((motion.frame_count, 3))
    shift[:, 2] = motion.ground_offset
    heel = motion.heel + shift[:, None, :]
    toe = motion.joints[:, :, 4] + shift[:, None, :]
    body = motion.root[:, :3, 3] + shift
    hands = motion.arms[:, :, 3] + shift[:, None, :] if motion.arms.shape[1] == 2 else None
    if not motion.terrain.flat:  # heights above the ground under each point, as on a flat floor
        for points in (heel, toe):
            points[..., 1] -= motion.terrain.height(points[..., [0, 2]])
    return FootTracks(times=motion.times - motion.times[0], names=tuple(motion.leg_names), heel=heel, toe=toe,
                      body=body, source=f"gaitlab:{motion.rig.name}", hip_height=motion.rig.hip_height, exact=True,
                      hands=hands, compromised=_compromised_stances(motion), cut_short=_cut_short_stances(motion))


def _compromised_stances(motion: Motion) -> int:
    """How many stances of the clip stand on compromised footholds (counted at touchdown,
    and the stances under way at its first frame)."""
    if motion.compromised is None:
        return 0
    contact, bad = motion.contact, motion.compromised
    starts = contact.copy()
    starts[1:] &= ~contact[:-1]
    return int(np.count_nonzero(starts & bad))


def _cut_short_stances(motion: Motion) -> int:
    """How many stances lifted early or landed late out of reach (each run of lifted
    frames is one stance's end)."""
    if motion.lifted is None:
        return 0
    lifted = motion.lifted
    starts = lifted.copy()
    starts[1:] &= ~lifted[:-1]
    return int(np.count_nonzero(starts))


LOOP_CLOSE = 0.06  # of the hip height: a clip whose last pose is this near its first is a loop
LOOP_PLAYS = 3  # a loop is analysed as played round this many times


def played_round(tracks: FootTracks, plays: int = LOOP_PLAYS) -> FootTracks | None:
    """A clip of one loop (a game's walk cycle: its last pose, feet against the body, is
    its first, or a frame's change from it) as played round ``plays`` times, each play carried on by the body's travel
    over one loop; None when the clip is no loop. A last frame that repeats the first (a
    closed loop) is played once."""
    if tracks.frame_count < 8:
        return None
    rel = np.concatenate([tracks.heel, tracks.toe], axis=1) - tracks.body[:, None, :]  # (T, 2F, 3)
    gap = float(np.linalg.norm(rel[-1] - rel[0], axis=-1).max())
    step = float(np.median(np.linalg.norm(np.diff(rel, axis=0), axis=-1).max(axis=1)))  # one frame's change
    if gap > max(LOOP_CLOSE * (tracks.hip_height or 1.0), 1.5 * step):  # (a loop may stop a frame short)
        return None
    frames = tracks.frame_count - 1 if gap < 0.5 * step else tracks.frame_count  # (a closing repeat)
    travel = tracks.body[frames] - tracks.body[0] if frames < tracks.frame_count else \
        2.0 * tracks.body[-1] - tracks.body[-2] - tracks.body[0]
    travel = travel * np.array([1.0, 0.0, 1.0])
    dt = float(np.median(np.diff(tracks.times)))
    offsets = np.repeat(np.arange(plays), frames)[:, None] * travel  # (plays * frames, 3)

    def tile(points: NDArray[np.float64]) -> NDArray[np.float64]:
        tiled = np.concatenate([points[:frames]] * plays)
        return tiled + offsets.reshape((len(offsets),) + (1,) * (points.ndim - 2) + (3,))

    return FootTracks(times=tracks.times[0] + dt * np.arange(plays * frames), names=tracks.names,
                      heel=tile(tracks.heel), toe=tile(tracks.toe), body=tile(tracks.body), source=tracks.source,
                      hip_height=tracks.hip_height, exact=tracks.exact,
                      hands=None if tracks.hands is None else tile(tracks.hands), unit_scale=tracks.unit_scale,
                      compromised=tracks.compromised * plays, cut_short=tracks.cut_short * plays)
