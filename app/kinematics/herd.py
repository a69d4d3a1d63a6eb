"""A herd: many animals of one kind moving together, vectorised across animals.

One gait cycle of the creature is solved once, in place (:func:`cycle_motion`); every
animal is that cycle played at its own phase and rate, scaled by its own size and set
down at its own position and heading. Per frame the whole herd is a handful of array
operations whatever its size: steering (follow a leader along the path, keep a place in
the group, keep apart from neighbours), clocks, and the pose transform.

An animal's planted feet stand still on the ground when it walks straight: its body
moves at exactly the speed the cycle's feet sweep back at (size x rate x the cycle's
speed). Turning, the cycle would swing them about the body, so each foot is locked where
it lands until it lifts (:meth:`Herd.step` keeps the locks): the leg reaches to it, and
in the swing that follows the foot eases back onto the cycle's path by touchdown.

On uneven ground each animal stands on the plane of the ground under it, and then each
leg reaches down or folds up to the ground under its own foot (:func:`legs_to_ground`):
the foot moves to its lock and straight up or down, the knee bends in the leg's own
plane, every bone keeps its length. One vectorised solve for every leg of every animal.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from ..choices import MAX_HERD
from ..errors import GaitlabError
from .body import unit
from .clip import clip_motion
from .motion import Motion
from .rig import Rig
from .world import IN_PLACE

CYCLE_FRAMES = 64  # frames of the solved cycle; poses between them are blended
ROOM = 1.2  # the room an animal keeps about it, in its own extent (nose to rump, flank to flank)
MAX_SETTLE = 0.3  # the most an animal settles lower for a planted foot out of reach, in leg lengths
UP = np.array([0.0, 1.0, 0.0])


def check_herd_size(n: int) -> int:
    """``n`` if it is a herd size Gaitlab draws (1 to MAX_HERD), else a one-line error."""
    if isinstance(n, bool) or int(n) != n or not 1 <= n <= MAX_HERD:
        raise GaitlabError(f"herd of {n}: give 1 to {MAX_HERD} animals")
    return int(n)


def cycle_motion(rig: Rig) -> Motion:
    """One whole gait cycle of ``rig`` in place, CYCLE_FRAMES frames (the last leads into
    the first)."""
    fps = CYCLE_FRAMES * rig.gait.frequency
    motion, _ = clip_motion(rig, fps, cycles=1.0, world=IN_PLACE)
    return motion


@dataclass(frozen=True)
class HerdVariation:
    """How much animals differ: size and speed as +- fractions."""

    size: float = 0.10
    speed: float = 0.10


HEADING_SPREAD = 20.0  # degrees: how far an animal's heading may differ from the leader's at the start
GROUP_ASPECT = 1.6  # a group is this much longer (behind the leader) than it is wide
CANDIDATES = 24  # places tried for each animal
MIN_GAP = 0.8  # of the spacing: the least room a place must have to be taken at once
WANDER = 0.12  # of the spacing: how far an animal's place drifts in the group, either way
WANDER_HZ = (0.02, 0.06)  # how fast it drifts (each animal its own, on each axis)


def loose_group(count: int, spacing: float, rng: np.random.Generator) -> NDArray[np.float64]:
    """Places (count, 2) in a loose group behind its leader (metres to the leader's left
    and ahead, none nearer its tail than ``spacing``): scattered over a half-ellipse about
    ``spacing`` apart (each animal takes
    the farthest from the others of :data:`CANDIDATES` random spots, best-candidate
    sampling), the group :data:`GROUP_ASPECT` times as long as it is wide, thinning out
    towards its edges. No rows, no columns: a herd, not a parade."""
    area = count * (spacing * 0.9) ** 2  # each animal's share of the ground
    half_width = math.sqrt(area / (math.pi * GROUP_ASPECT / 2.0))
    depth = GROUP_ASPECT * half_width
    places = np.zeros((0, 2))
    for _ in range(count):  # at start only: never in the frame path
        r = np.sqrt(rng.uniform(0.0, 1.0, CANDIDATES))
        a = rng.uniform(0.0, np.pi, CANDIDATES)
        spots = np.column_stack([half_width * r * np.cos(a), -spacing - depth * r * np.sin(a)])  # clear of the leader
        if len(places):
            gap = np.min(np.linalg.norm(spots[:, None, :] - places[None, :, :], axis=-1), axis=1)
            # The first random spot with room enough (some close, some far: clumps and
            # gaps, as herds have), else the roomiest.
            room = np.flatnonzero(gap >= MIN_GAP * spacing)
            spot = spots[int(room[0]) if len(room) else int(np.argmax(gap))]
        else:
            spot = spots[int(np.argmin(np.linalg.norm(spots, axis=-1)))]  # the first close behind the leader
        places = np.vstack([places, spot])
    return places


def _wrap(angle: NDArray[np.float64]) -> NDArray[np.float64]:
    return (angle + np.pi) % (2.0 * np.pi) - np.pi


class Herd:
    """``count`` animals of ``rig`` around a leader point that moves along the ground.

    State (arrays over animals, N = count): ``position`` (N, 2) x, z in metres,
    ``heading`` (N,) radians (0 faces +Z, positive turns left), ``size`` (N,) scale,
    ``phase`` (N,) cycle fraction, ``rate`` (N,) how fast each plays the cycle relative to
    the rig's frequency, ``slot`` (N, 2) each animal's place in the group (metres to the
    leader's left and ahead).
    """

    def __init__(self, rig: Rig, count: int, leader: tuple[float, float] = (0.0, 0.0), heading: float = 0.0,
                 seed: int = 1, variation: HerdVariation = HerdVariation()) -> None:
        count = check_herd_size(count)
        rng = np.random.default_rng(seed)
        self.count = count
        self.variation = variation
        self.size = 1.0 + variation.size * rng.uniform(-1.0, 1.0, count)
        if rig.model:  # a rigged model's bones are its own: every animal is its size
            self.size = np.ones(count)
        self.pace = 1.0 + variation.speed * rng.uniform(-1.0, 1.0, count)  # each one's preferred speed factor
        self.phase = rng.uniform(0.0, 1.0, count)
        self.rate = self.pace.copy()
        self.set_rig(rig)
        front, back, _ = self.extent
        # Places at least as far apart as the room each animal keeps (nose to rump ahead).
        spacing = max(1.6 * max(rig.body_length, rig.body.width * 3.0), 1.1 * ROOM * (front + back))
        self.home = loose_group(count, spacing, rng)  # each one's own place in the group
        self.slot = self.home.copy()  # ... where it is now, drifting about it
        self.wander_rate = 2.0 * np.pi * rng.uniform(*WANDER_HZ, (count, 2))  # rad/s
        self.wander_phase = rng.uniform(0.0, 2.0 * np.pi, (count, 2))
        self.time = 0.0
        self.spacing = spacing
        c, s = math.cos(heading), math.sin(heading)
        leader_xz = np.asarray(leader, dtype=np.float64)
        self.position = leader_xz + np.column_stack([c * self.slot[:, 0] + s * self.slot[:, 1],
                                                     -s * self.slot[:, 0] + c * self.slot[:, 1]])
        # Each one looking its own way a little; they turn to their places as they go.
        self.heading = float(heading) + np.radians(HEADING_SPREAD) * rng.uniform(-1.0, 1.0, count)
        self.rng = rng
        self.unlock_feet()

    def set_rig(self, rig: Rig) -> None:
        """A new creature (edited in the panels): re-solve the cycle every animal plays."""
        self.rig = rig
        self.cycle = cycle_motion(rig)
        # How far apart (m, at size 1) its feet stand along and across the body: the corners
        # whose ground an animal stands on.
        feet = np.abs(self.cycle.joints[:, :, 3][..., [0, 2]]).max(axis=(0, 1))
        self.reach = (max(2.0 * float(feet[1]), 1e-3), max(2.0 * float(feet[0]), 1e-3))
        # How far (m, at size 1) the animal reaches ahead of its centre (the nose), behind
        # it (the rump) and to either side: the room it takes in the group.
        cycle = self.cycle
        z = np.concatenate([cycle.head[:, :, 2], cycle.spine[:, :, 2]], axis=1)
        x = np.concatenate([cycle.spine[:, :, 0], cycle.joints[:, :, :, 0].reshape(cycle.frame_count, -1)], axis=1)
        self.extent = (max(float(z.max()), 1e-3), max(float(-z.min()), 1e-3), max(float(np.abs(x).max()), 1e-3))
        self.frequency = rig.gait.frequency
        # Each foot's swing in the cycle: the frame it lifts at and how many frames it lasts
        # (one swing a cycle; a foot that never lifts has none).
        contact = self.cycle.contact
        lifts = ~contact & np.roll(contact, 1, axis=0)  # (F, L): first frame of a swing
        self._swing_start = lifts.argmax(axis=0).astype(np.float64)
        self._swing_frames = np.where(lifts.any(axis=0), (~contact).sum(axis=0), 0).astype(np.float64)
        self.unlock_feet()
        travel = self.cycle.travel
        frames = len(travel)
        self.cycle_speed = float((travel[-1] - travel[0]) * frames / (frames - 1) * self.frequency)  # m/s

    @property
    def speed(self) -> NDArray[np.float64]:
        """Each animal's ground speed now (m/s)."""
        return self.cycle_speed * self.size * self.rate

    def unlock_feet(self) -> None:
        """Forget where the feet are locked (a herd set down anew): each locks where it
        next stands."""
        if not hasattr(self, "cycle"):
            return
        legs = self.cycle.contact.shape[1]
        self._locked = np.zeros((self.count, legs), dtype=bool)
        self._lock = np.zeros((self.count, legs, 2))
        self._anchor = np.zeros((self.count, legs, 3))
        self._lift_shift = np.zeros((self.count, legs, 2))
        self._locked_phase: NDArray[np.float64] | None = None
        self.foot_shift: NDArray[np.float64] | None = None

    def _swinging(self) -> tuple[NDArray[np.bool_], NDArray[np.float64]]:
        """Which feet swing now (N, L) and how far through its swing each is (0 at lift-off,
        1 at touchdown)."""
        swinging, progress, _ = self._swing_state()
        return swinging, progress

    def _swing_state(self) -> tuple[NDArray[np.bool_], NDArray[np.float64], NDArray[np.float64]]:
        """:meth:`_swinging`, and the cycle frames since each foot last lifted (N, L)."""
        frames = self.cycle.frame_count
        since_lift = (self.phase[:, None] * frames - self._swing_start[None, :]) % frames
        swinging = (since_lift < self._swing_frames[None, :]) & (self._swing_frames[None, :] > 0)
        return swinging, np.clip(since_lift / np.maximum(self._swing_frames, 1.0)[None, :], 0.0, 1.0), since_lift

    def _ground_anchor(self, f0: NDArray[np.int64], f1: NDArray[np.int64],
                       w: NDArray[np.float64]) -> NDArray[np.float64]:
        """Each ball in the cycle's frame plus how far the cycle's ground has moved back
        (N, L, 3; size 1): constant through a stance for a foot that stands still on the
        ground, changing only as a foot rolls (heel to ball to toe)."""
        balls = self.cycle.joints[:, :, 3]
        local = balls[f0] + (balls[f1] - balls[f0]) * w[:, None, None]
        travel = self.cycle.travel
        length = self.cycle_speed / max(self.frequency, 1e-9)  # ground a cycle moves by (m)
        ahead = travel[f1] + np.where(f1 < f0, length, 0.0)  # the cycle's last frame leads into its first
        anchor = local.copy()
        anchor[..., 2] += (travel[f0] + (ahead - travel[f0]) * w)[:, None]
        return anchor

    def _lock_feet(self, ground_height=None) -> None:
        """Keep each standing foot where it landed: lock a foot's ball (x, z) as it lands,
        keep it until it lifts (moving it only as the cycle rolls it on the ground), then
        ease the foot from its lock back onto the cycle's path over its swing. A step that
        passes a whole swing lifts and lands the foot. Sets :attr:`foot_shift` (N, L, 2):
        how far (m) each foot stands or swings off where the cycle, carried by the animal,
        puts it."""
        f0, f1, w = self.blend()
        balls = self.cycle.joints[:, :, 3]  # (F, L, 3)
        local = balls[f0] + (balls[f1] - balls[f0]) * w[:, None, None]
        scale, rot, move = self.transforms(ground_height)
        turn = np.swapaxes(rot, 1, 2)
        carried = ((local * scale[:, None, None]) @ turn + move[:, None, :])[..., [0, 2]]
        swinging, progress, since_lift = self._swing_state()
        # A standing foot's anchor: not blended into its swing's first frame (that is the lift).
        into_swing = ~swinging & self.cycle.contact[f0] & ~self.cycle.contact[f1]
        anchor = np.where(into_swing[..., None], self._ground_anchor(f0, f1, np.zeros_like(w)),
                          self._ground_anchor(f0, f1, w))
        frames = self.cycle.frame_count
        if self._locked_phase is None:
            advanced = np.zeros((self.count, 1))
        else:
            advanced = ((self.phase - self._locked_phase) % 1.0)[:, None] * frames
        passed = (since_lift < advanced) & (self._swing_frames[None, :] > 0)  # lifted since the last step
        self._locked_phase = self.phase.copy()
        standing = ~swinging
        lifted = (swinging | passed) & self._locked
        self._lift_shift = np.where(lifted[..., None], self._lock - carried, self._lift_shift)
        landed = standing & (~self._locked | passed)
        self._lock = np.where(landed[..., None], carried, self._lock)
        self._anchor = np.where(landed[..., None], anchor, self._anchor)
        # A standing foot: its lock, moved by the cycle's roll since it landed (turned with the animal).
        length = self.cycle_speed / max(self.frequency, 1e-9)
        roll = anchor - self._anchor
        roll[..., 2] = (roll[..., 2] + 0.5 * length) % length - 0.5 * length  # across the cycle's wrap
        rolled = self._lock + ((roll * scale[:, None, None]) @ turn)[..., [0, 2]]
        ease = 1.0 - progress * progress * (3.0 - 2.0 * progress)
        self.foot_shift = np.where(standing[..., None], rolled - carried, self._lift_shift * ease[..., None])
        self._locked = standing

    def step(self, dt: float, leader: NDArray[np.float64], leader_heading: float,
             leader_speed: float | None = None, ground_height=None) -> None:
        """Advance ``dt`` seconds, the group following ``leader`` (x, z) heading
        ``leader_heading`` (radians) at ``leader_speed`` m/s (default: the cycle's own
        speed): each animal steers for its place in the group, away from neighbours
        nearer than about a body length, and sets its speed to keep its place (within
        +-35% of its own pace at the leader's speed). Standing feet stay where they
        landed, on ``ground_height((K, 2)) -> (K,)`` (default flat)."""
        if dt <= 0:
            return
        # The cycle played faster or slower to go at the leader's speed (a driven leader
        # changes gait too: the owner re-solves the cycle then, see set_rig).
        follow = 1.0 if leader_speed is None else float(np.clip(leader_speed / max(self.cycle_speed, 1e-9),
                                                                  0.25, 4.0))
        # Places drift slowly about their homes: the group mills as it goes.
        self.time += dt
        self.slot = self.home + WANDER * self.spacing * np.sin(self.wander_rate * self.time + self.wander_phase)
        c, s = math.cos(leader_heading), math.sin(leader_heading)
        target = np.asarray(leader, dtype=np.float64) + np.column_stack(
            [c * self.slot[:, 0] + s * self.slot[:, 1], -s * self.slot[:, 0] + c * self.slot[:, 1]])
        to_target = target - self.position
        forward = np.column_stack([np.sin(self.heading), np.cos(self.heading)])
        # Separation: push from every neighbour whose body comes within ROOM of this one's,
        # judged in this animal's frame: nose to rump along it, flank to flank across it.
        delta = self.position[:, None, :] - self.position[None, :, :]  # (N, N, 2): from j to i
        along = np.sum(delta * forward[:, None, :], axis=-1)
        sideways = delta[..., 0] * forward[:, None, 1] - delta[..., 1] * forward[:, None, 0]
        front, back, half_width = self.extent
        size = 0.5 * (self.size[:, None] + self.size[None, :])
        dist = np.hypot(along / ((front + back) * size), sideways / (2.0 * half_width * size))  # 1: touching
        np.fill_diagonal(dist, np.inf)
        near = dist < ROOM
        push = np.where(near, ROOM / np.where(near, np.maximum(dist, 1e-6), 1.0) - 1.0, 0.0)[..., None] * delta
        separation = push.sum(axis=1)
        steer = to_target / max(self.spacing, 1e-6) + 2.0 * separation / max(self.rig.body_length, 1e-6)
        steer = steer + 0.6 * np.array([s, c])  # and along the way the group is going
        wanted = np.arctan2(steer[:, 0], steer[:, 1])
        # Turn no faster than a turn of two body lengths' radius at the present speed.
        max_turn = self.speed / (2.0 * self.rig.body_length * self.size) * dt
        self.heading = self.heading + np.clip(_wrap(wanted - self.heading), -max_turn, max_turn)
        # Speed: behind its place, faster; ahead, slower; a neighbour close ahead, slower.
        along = np.sum(to_target * forward, axis=1) / max(self.spacing, 1e-6)
        ahead = np.sum(-delta * forward[:, None, :], axis=-1)  # (N, N): j in front of i
        blocked = np.any((ahead > 0) & (dist < ROOM), axis=1)
        rate = follow * self.pace * np.clip(1.0 + 0.5 * along, 0.65, 1.35) * np.where(blocked, 0.75, 1.0)
        self.rate += np.clip(rate - self.rate, -0.5 * follow * dt, 0.5 * follow * dt)  # speed changes ease in
        forward = np.column_stack([np.sin(self.heading), np.cos(self.heading)])
        self.position = self.position + forward * (self.speed * dt)[:, None]
        self.phase = (self.phase + self.frequency * self.rate * dt) % 1.0
        self._lock_feet(ground_height)

    def blend(self) -> tuple[NDArray[np.int64], NDArray[np.int64], NDArray[np.float64]]:
        """Each animal's pose as a blend of two cycle frames: first (N,), second (N,) and
        the weight of the second (N,)."""
        frames = self.cycle.frame_count
        f = self.phase * frames
        f0 = np.floor(f).astype(np.int64) % frames
        return f0, (f0 + 1) % frames, f - np.floor(f)

    def transforms(self, ground_height=None) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
        """Per animal: scale (N,), rotation about +Y (N, 3, 3) and translation (N, 3) that
        take the in-place cycle's pose to the world (on ground of height
        ``ground_height((N, 2)) -> (N,)`` under each animal, default flat)."""
        c, s = np.cos(self.heading), np.sin(self.heading)
        forward = np.column_stack([s, np.zeros(self.count), c])
        left = np.column_stack([c, np.zeros(self.count), -s])
        if ground_height is None:
            y = np.zeros(self.count)
        else:
            # Each animal stands on the plane through the ground under its four corners
            # (girdles and sides): pitched up a hill, rolled across a slope.
            half_length = 0.5 * self.reach[0] * self.size
            half_width = 0.5 * self.reach[1] * self.size
            xz_f, xz_l = forward[:, [0, 2]], left[:, [0, 2]]
            corners = np.stack([self.position + xz_f * half_length[:, None], self.position - xz_f * half_length[:, None],
                                self.position + xz_l * half_width[:, None], self.position - xz_l * half_width[:, None]])
            h = ground_height(corners.reshape(-1, 2)).reshape(4, self.count)
            y = ground_height(self.position)
            forward[:, 1] = (h[0] - h[1]) / (2.0 * half_length)
            left[:, 1] = (h[2] - h[3]) / (2.0 * half_width)
            forward /= np.linalg.norm(forward, axis=1, keepdims=True)
            up = np.cross(forward, left)
            up /= np.linalg.norm(up, axis=1, keepdims=True)
            left = np.cross(up, forward)
        rot = np.stack([left, np.cross(forward, left), forward], axis=-1)  # columns: local x, y, z in the world
        return self.size, rot, np.column_stack([self.position[:, 0], y, self.position[:, 1]])

    def joints(self, ground_height=None) -> NDArray[np.float64]:
        """Every animal's leg joints in the world, (N, L, 5, 3): on uneven ground (given
        ``ground_height``) each foot set down on the ground under it."""
        return self.legs(ground_height)[0]

    def legs(self, ground_height=None, transforms=None) -> tuple[NDArray[np.float64], LegAdjustment | None]:
        """Every animal's leg joints in the world (N, L, 5, 3) and how each leg was set
        down on the ground and its foot's lock (None where the cycle's feet stand as they
        are: flat ground, no foot off its cycle). ``transforms``: :meth:`transforms` for
        this ground, when the caller has them."""
        f0, f1, w = self.blend()
        # In place, the body stays at the origin and planted feet sweep back with the
        # ground: in the body's frame, which is what each animal carries along.
        local = self.cycle.joints[f0] * (1.0 - w)[:, None, None, None] + self.cycle.joints[f1] * w[:, None, None, None]
        scale, rot, move = self.transforms(ground_height) if transforms is None else transforms
        n = local.shape[0]
        joints = ((local * scale[:, None, None, None]).reshape(n, -1, 3) @ np.swapaxes(rot, 1, 2)).reshape(local.shape)
        joints += move[:, None, None, :]
        lift = local[:, :, 3, 1] * scale[:, None]  # each ball's height above the cycle's ground (m)
        shift, standing, off_cycle = self.foot_shift, None, False
        if shift is not None:
            # A standing foot keeps the cycle's height for it (a rolling foot's ball rises
            # at heel strike), but not the blend into its swing's first frame.
            standing = ~self._swinging()[0]
            into_swing = standing & ~self.cycle.contact[f1] & self.cycle.contact[f0]
            at_f0 = self.cycle.joints[f0][:, :, 3, 1] * scale[:, None]
            off_cycle = bool(np.any(np.abs(shift) > 1e-9) or np.any(into_swing & (lift != at_f0)))
            lift = np.where(into_swing, at_f0, lift)
        if ground_height is None and not off_cycle:
            return joints, None
        adjusted = legs_to_ground(joints, flat_ground if ground_height is None else ground_height, lift,
                                  shift, standing)
        return adjusted.joints, adjusted


@dataclass(frozen=True)
class LegAdjustment:
    """How :func:`legs_to_ground` set each leg (N animals, L legs) down: the new joints
    (N, L, 5, 3); the thigh's rotation about the hip and the shin's about the knee
    (N, L, 3, 3), the knee's move and the foot's (ankle, ball and toe) move (N, L, 3) m
    from where the animal's settling left them; short (N, L) m by which each foot still
    misses its ground; lowered (N,) m how far each animal settled below the plane it
    stands on, for a planted foot in a hollow."""

    joints: NDArray[np.float64]
    thigh: NDArray[np.float64]
    shin: NDArray[np.float64]
    knee_move: NDArray[np.float64]
    foot_move: NDArray[np.float64]
    short: NDArray[np.float64]
    lowered: NDArray[np.float64]


def skew(v: NDArray[np.float64]) -> NDArray[np.float64]:
    """The cross-product matrices (..., 3, 3) of vectors ``v`` (..., 3): skew(v) @ x = v x x."""
    k = np.zeros(v.shape[:-1] + (3, 3))
    k[..., 0, 1], k[..., 0, 2], k[..., 1, 2] = -v[..., 2], v[..., 1], -v[..., 0]
    return k - np.swapaxes(k, -1, -2)


def rotation_about(axis: NDArray[np.float64], angle: float) -> NDArray[np.float64]:
    """Rotations (..., 3, 3) by ``angle`` rad about unit axes ``axis`` (..., 3) (Rodrigues)."""
    k = skew(axis)
    return np.eye(3) + np.sin(angle) * k + (1.0 - np.cos(angle)) * (k @ k)


def rotation_between(a: NDArray[np.float64], b: NDArray[np.float64]) -> NDArray[np.float64]:
    """The smallest rotation (..., 3, 3) taking unit vectors a to b (..., 3) (Rodrigues);
    for opposite vectors, a half turn about an axis perpendicular to a."""
    v = np.cross(a, b)
    c = np.sum(a * b, axis=-1)[..., None, None]
    k = skew(v)
    turn = np.eye(3) + k + (k @ k) / np.maximum(1.0 + c, 1e-9)
    opposite = c[..., 0, 0] < -1.0 + 1e-9
    if np.any(opposite):
        side = np.where(np.abs(a[..., :1]) < 0.9, np.array([1.0, 0.0, 0.0]), np.array([0.0, 1.0, 0.0]))
        axis = np.cross(a, side)
        axis /= np.linalg.norm(axis, axis=-1, keepdims=True)
        half = 2.0 * axis[..., :, None] * axis[..., None, :] - np.eye(3)  # a half turn about the axis
        turn = np.where(opposite[..., None, None], half, turn)
    return turn


def flat_ground(xz: NDArray[np.float64]) -> NDArray[np.float64]:
    """The flat floor's height (0 m) at points ``xz`` (K, 2)."""
    return np.zeros(len(xz))


def legs_to_ground(joints: NDArray[np.float64], ground_height, lift: NDArray[np.float64],
                   shift: NDArray[np.float64] | None = None, planted: NDArray[np.bool_] | None = None) -> LegAdjustment:
    """Set each foot of ``joints`` (N, L, 5, 3: hip, knee, ankle, ball, toe) down on the
    ground: its ball ``lift`` (N, L) m above ``ground_height((K, 2)) -> (K,)`` under it
    (0 for a planted foot), moved first by ``shift`` (N, L, 2) m along x and z (a foot's
    lock; ``planted`` (N, L): the feet standing, default those with no lift). The foot
    (ankle, ball, toe) moves across by the shift and straight up or down; the
    hip stays, unless a planted foot lies beyond the leg's reach (in a hollow): then the
    whole animal settles lower just enough for it to reach (up to MAX_SETTLE leg lengths); the knee is
    re-solved in the plane of hip, knee and ankle (two-bone IK, bending the same way). A
    foot the leg still cannot reach stops at the leg's full stretch towards it, one too
    near at its full fold. Bone lengths are kept exactly."""
    n, legs = joints.shape[:2]
    across = np.zeros((n, legs, 3))
    if shift is not None:
        across[..., 0], across[..., 2] = shift[..., 0], shift[..., 1]
    ground = ground_height((joints[:, :, 3] + across)[..., [0, 2]].reshape(-1, 2)).reshape(n, legs)
    knee_from_hip = joints[:, :, 1] - joints[:, :, 0]
    femur = np.linalg.norm(knee_from_hip, axis=-1)
    tibia = np.linalg.norm(joints[:, :, 2] - joints[:, :, 1], axis=-1)
    longest, shortest = femur + tibia - 1e-9, np.abs(femur - tibia) + 1e-9
    # Where each ankle must go (the foot moved up or down to its ground): fixed in the world.
    target = joints[:, :, 2] + across
    target[..., 1] += ground + lift - joints[:, :, 3, 1]
    planted = lift < 1e-6 if planted is None else planted
    # A planted foot beyond its leg's reach (in a hollow, or locked far back): the animal
    # settles straight down until every planted foot is within reach; lowering the hip by h
    # shortens the hip-to-foot line to sqrt(r^2 + (drop - h)^2), r across and drop below.
    hip = joints[:, :, 0]
    to_target = target - hip
    across_r2 = to_target[..., 0] ** 2 + to_target[..., 2] ** 2
    drop = -to_target[..., 1]
    need = drop - np.sqrt(np.maximum(longest ** 2 - across_r2, 0.0))
    reachable = across_r2 < longest ** 2
    need = np.where(reachable, need, drop)  # too far across: down to the foot's level, the nearest it comes
    lowered = np.clip(np.where(planted, need, 0.0).max(axis=1), 0.0, None) + 1e-9
    lowered = np.minimum(lowered, MAX_SETTLE * longest.max(axis=1))
    hip = hip - lowered[:, None, None] * UP
    to_target = target - hip
    reach = np.linalg.norm(to_target, axis=-1)
    along = to_target / np.maximum(reach, 1e-12)[..., None]
    d = np.clip(reach, shortest, longest)
    new_ankle = hip + along * d[..., None]
    # The knee bends towards where it was, across the hip-ankle line (a leg straight along
    # it bends forward, across it, as a knee does: any way at all keeps the bones' lengths).
    bend = knee_from_hip - np.sum(knee_from_hip * along, axis=-1, keepdims=True) * along
    size = np.linalg.norm(bend, axis=-1, keepdims=True)
    straight = size < 1e-9 * np.maximum(femur[..., None], 1e-12)
    if np.any(straight):
        across = np.cross(along, np.array([1.0, 0.0, 0.0]))
        across = np.where(np.linalg.norm(across, axis=-1, keepdims=True) < 1e-6, np.cross(along, UP), across)
        bend = np.where(straight, across, bend)
        size = np.linalg.norm(bend, axis=-1, keepdims=True)
    bend = bend / np.maximum(size, 1e-12)
    cos_a = np.clip((femur ** 2 + d ** 2 - tibia ** 2) / np.maximum(2.0 * femur * d, 1e-12), -1.0, 1.0)
    new_knee = hip + femur[..., None] * (cos_a[..., None] * along + np.sqrt(1.0 - cos_a ** 2)[..., None] * bend)
    shift = lowered[:, None, None] * UP  # (N, 1, 3) the animal's settling
    knee, ankle = joints[:, :, 1] - shift, joints[:, :, 2] - shift  # the leg as it was, settled with the body
    foot_move = new_ankle - ankle
    out = joints - shift[:, :, None, :]
    out[:, :, 1] = new_knee
    out[:, :, 2:] += foot_move[:, :, None, :]
    thigh = rotation_between(unit(knee - hip), unit(new_knee - hip))
    shin = rotation_between(unit(ankle - knee), unit(new_ankle - new_knee))
    return LegAdjustment(joints=out, thigh=thigh, shin=shin, knee_move=new_knee - knee, foot_move=foot_move,
                         short=np.linalg.norm(target - new_ankle, axis=-1), lowered=lowered)


@dataclass(frozen=True)
class HerdTrack:
    """A herd over a clip's frames: position (T, N, 2), heading (T, N), phase (T, N) and
    each foot's shift off its cycle (T, N, L, 2; see :meth:`Herd._lock_feet`)."""

    position: NDArray[np.float64]
    heading: NDArray[np.float64]
    phase: NDArray[np.float64]
    foot_shift: NDArray[np.float64]

    def apply(self, herd: Herd, index: int) -> Herd:
        """Put ``herd`` where it is at frame ``index`` (and return it)."""
        herd.position, herd.heading, herd.phase = self.position[index], self.heading[index], self.phase[index]
        herd.foot_shift = self.foot_shift[index]
        return herd

    def first(self, frames: int = 1) -> HerdTrack:
        """The track's first ``frames`` frames."""
        return HerdTrack(self.position[:frames], self.heading[:frames], self.phase[:frames],
                         self.foot_shift[:frames])


def follow_leader(herd: Herd, leader: NDArray[np.float64], heading: NDArray[np.float64], fps: float,
                  ground_height=None) -> HerdTrack:
    """Step ``herd`` after a leader at ``leader`` (T, 2) heading ``heading`` (T,) radians,
    one step per frame at ``fps``, on ``ground_height`` (default flat); the herd starts in
    its places around the first frame's leader, its feet standing where the cycle puts
    them. One vectorised step per frame (a loop over frames, never over animals)."""
    frames = len(leader)
    c, s = math.cos(float(heading[0])), math.sin(float(heading[0]))
    slot = herd.slot
    herd.position = leader[0] + np.column_stack([c * slot[:, 0] + s * slot[:, 1], -s * slot[:, 0] + c * slot[:, 1]])
    herd.heading = np.full(herd.count, float(heading[0]))
    herd.unlock_feet()
    herd._lock_feet(ground_height)
    position = np.empty((frames, herd.count, 2))
    headings = np.empty((frames, herd.count))
    phase = np.empty((frames, herd.count))
    shifts = np.empty((frames, *herd._lock.shape))
    for i in range(frames):
        if i:
            herd.step(1.0 / fps, leader[i], float(heading[i]), ground_height=ground_height)
        position[i], headings[i], phase[i] = herd.position, herd.heading, herd.phase
        assert herd.foot_shift is not None
        shifts[i] = herd.foot_shift
    return HerdTrack(position, headings, phase, shifts)
