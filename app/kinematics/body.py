"""The body from the feet: girdles, spine, neck, head, tail and the root transform.

Steps, each vectorised over frames (T) and girdles (G) or legs (L):

1. :func:`place_girdles` — each girdle's centre sits on the path at its own arc length
   (so a long body bends with the path), at the height of the ground its feet stand on
   (the mean of its two feet's supports: for two girdles, a plane through the four feet)
   plus its standing height and bob; it rolls towards its higher foot and never stands
   higher than lets its planted feet reach the ground.
2. :func:`spine_through` — a chain of cubic Béziers through the girdle centres (and the
   trunk's ends), tangents along the path with the girdles' yaw; body segments at equal
   arc length, the neck and head off the front, the tail off the rear.
3. :func:`root_frames` — the body's transform at the middle of the trunk.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from functools import lru_cache

import numpy as np
from numpy.typing import NDArray

from .frames import UP
from .path import left_of
from .rig import MIN_CROUCH, REACH_LIMIT, Rig
from .spine import bezier, bezier_tangent
from .world import World

TAIL_SET = 0.45  # of the rump's radius: how far above the spine's end a mammal's tail leaves the croup
TAIL_WAVE_LAG = 0.15  # cycle fraction by which the tail tip lags its base
REACH_MARGIN = 0.97  # planted feet stay within this fraction of the leg's full extension
MAX_ROLL = 0.5  # rad
MAX_STEEP_ROLL = 1.0  # rad: how far a girdle rolls on where both sides' feet could not reach otherwise
STEEP_ROLL_PASSES = 4
NOD = 0.06  # rad: a walking quadruped's neck and head bow, either way, for a neck as long as its legs
NOD_DELAY = 0.15  # of a cycle after a fore foot lands: the head is lowest
SWING = 0.12  # rad: a galloping quadruped's neck swing, either way, for a neck as long as its legs
SWING_DELAY = 0.1  # of a cycle after the fore feet's mean touchdown: the galloping head is lowest
OBLIQUITY_PEAK = 0.18  # of a cycle after a foot's touchdown: the other side of the pelvis lowest
RUN_LEAN = np.radians(5.0)  # rad: a runner's trunk leans this much further forward than its walk (5-10 degrees all told)
ROLL_FOLLOW = 0.8  # how much of the slope between its feet a girdle rolls with
MAX_END_SLOPE = 0.35  # the trunk's ends beyond the girdles pitch at most this much (rise over run)


def unit(v: NDArray[np.float64]) -> NDArray[np.float64]:
    return v / np.maximum(np.linalg.norm(v, axis=-1, keepdims=True), 1e-12)


def cross(a: NDArray[np.float64], b: NDArray[np.float64]) -> NDArray[np.float64]:
    """a x b over the last axis (..., 3), broadcast: np.cross without its overhead on the
    small arrays of one frame."""
    a, b = np.broadcast_arrays(a, b)
    out = np.empty(a.shape)
    out[..., 0] = a[..., 1] * b[..., 2] - a[..., 2] * b[..., 1]
    out[..., 1] = a[..., 2] * b[..., 0] - a[..., 0] * b[..., 2]
    out[..., 2] = a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]
    return out


def rotate_y(v: NDArray[np.float64], angle: NDArray[np.float64]) -> NDArray[np.float64]:
    """Rotate vectors (..., 3) about +Y by ``angle`` (...) radians."""
    c, s = np.cos(angle), np.sin(angle)
    x, y, z = v[..., 0], v[..., 1], v[..., 2]
    x, y, z, c, s = np.broadcast_arrays(x, y, z, c, s)
    return np.stack([c * x + s * z, y, -s * x + c * z], axis=-1)


def pitch(direction: NDArray[np.float64], angle) -> NDArray[np.float64]:
    """Tilt a (nearly horizontal) direction up by ``angle`` radians towards +Y."""
    flat = unit(direction * np.array([1.0, 0.0, 1.0]))
    angle = np.asarray(angle)[..., None]
    return np.cos(angle) * flat + np.sin(angle) * UP


def _flat3(xz: NDArray[np.float64]) -> NDArray[np.float64]:
    return np.stack([xz[..., 0], np.zeros(xz.shape[:-1]), xz[..., 1]], axis=-1)


@dataclass(frozen=True)
class Girdles:
    """centre (T, G, 3); heading (T, G, 3) horizontal unit tangent of the path; lateral
    (T, G, 3) unit axis to the girdle's left (rolled and yawed); yaw (T, G) rad; arc
    length (T, G) of each girdle along the path."""

    centre: NDArray[np.float64]
    heading: NDArray[np.float64]
    lateral: NDArray[np.float64]
    yaw: NDArray[np.float64]
    s: NDArray[np.float64]


def standing_height(rig: Rig, stride_m: NDArray[np.float64], bob: NDArray[np.float64]) -> NDArray[np.float64]:
    """Each girdle's standing height above its feet's ground (T, G): its rest height,
    lowered when the stride would carry a planted foot beyond REACH_MARGIN of full
    extension (bob included), never below MIN_CROUCH of rest. stride_m (T, L); bob (T, 1)."""
    reach = np.sqrt(np.maximum((REACH_MARGIN * rig.l_max) ** 2 - rig.stance_extent(0.5 * stride_m) ** 2, 0.0))
    left, right = reach[:, 0::2], reach[:, 1::2]
    rest = rig.girdle_rest_height
    bob_room = 0.5 * bob * rest
    lowest = np.maximum(MIN_CROUCH * rest, 1.05 * np.maximum(rig.l_min[0::2], rig.l_min[1::2]))
    return np.clip(np.minimum(left, right) - bob_room, lowest, rest)


def place_girdles(rig: Rig, world: World, s: NDArray[np.float64], support: NDArray[np.float64],
                  ball: NDArray[np.float64], planted: NDArray[np.float64], stride_m: NDArray[np.float64],
                  bob: NDArray[np.float64], bob_lift: NDArray[np.float64],
                  forward: NDArray[np.float64], pose_height: NDArray[np.float64] | None = None,
                  reach: tuple[NDArray[np.float64], NDArray[np.float64]] | None = None,
                  pitch: NDArray[np.float64] | None = None, phase: NDArray[np.float64] | None = None) -> Girdles:
    """Girdle frames for body arc lengths s (T,).

    support, ball (T, L, 3): each foot's ground support and ball target; planted (T, L) in
    [0, 1]: how much each foot's reach limits the body (1 planted, fading out in mid-swing);
    stride_m (T, L) m; bob (T,) leg rest lengths; bob_lift, forward (T, L): the oscillator's
    lift for the bob and fore-aft offset for the yaw; pose_height (T,) m: the key poses'
    height, which replaces the bob; reach: (point (T, L, 3), length (L,)): how far each
    hip may be from which point of its foot (default: the ball, REACH_LIMIT of L_max; a
    rolling plantigrade foot's ankle, femur and tibia all but straight, and no nearer
    than they fold); pitch (T,) rad: the trunk pitches nose up by it (each girdle
    raised or lowered by its distance from the trunk's middle); phase (T, L): each foot's
    cycle phase (0 at its touchdown), which times the pelvis's tilt (else the feet's lift).
    """
    s_g = s[:, None] + (rig.girdle_position[None, :] - 0.5) * rig.body_length  # (T, G)
    point, tangent = world.path.sample(s_g)
    heading = _flat3(tangent)
    left = _flat3(left_of(tangent))

    # Height: ground under the feet + standing height + bob.
    y_left, y_right = support[:, 0::2, 1], support[:, 1::2, 1]
    ground = 0.5 * (y_left + y_right)
    bob_t = bob[:, None]
    rest = rig.girdle_rest_height
    stand = standing_height(rig, stride_m, bob_t)
    girdle_lift = np.maximum(bob_lift[:, 0::2], bob_lift[:, 1::2])
    if pose_height is None:
        height = ground + stand + bob_t * rest * (girdle_lift - 0.5)
    else:  # the key poses' heights are from the rest height; reach keeps them possible
        height = ground + rest + pose_height[:, None]
    if pitch is not None:
        height = height + np.tan(pitch)[:, None] * ((rig.girdle_position - 0.5) * rig.body_length)[None, :]
    reach_point, farthest = (ball, REACH_LIMIT * rig.l_max) if reach is None else reach

    # Roll towards the higher foot; yaw with the feet; sway towards the stance side.
    across = np.linalg.norm(support[:, 0::2, [0, 2]] - support[:, 1::2, [0, 2]], axis=-1)
    roll = np.clip(ROLL_FOLLOW * np.arctan2(y_left - y_right, np.maximum(across, 1e-6)), -MAX_ROLL, MAX_ROLL)
    if phase is None:
        roll = roll - rig.motion.pelvis_tilt * (bob_lift[:, 0::2] - bob_lift[:, 1::2])  # the swinging side drops
    else:  # ... most early in the other foot's stance, as a walker's pelvis does (Perry: ~15-20 % of the cycle)
        wave = np.cos(2.0 * np.pi * (phase - OBLIQUITY_PEAK))
        roll = roll + rig.motion.pelvis_tilt * 0.5 * (wave[:, 0::2] - wave[:, 1::2])
    yaw = -rig.motion.yaw * (forward[:, 0::2] - forward[:, 1::2])
    lateral = rotate_y(np.cos(roll)[..., None] * left + np.sin(roll)[..., None] * UP, yaw)
    sway = rig.motion.sway * (bob_lift[:, 1::2] - bob_lift[:, 0::2])  # (T, G) m to the left
    point = point + sway[..., None] * left[..., [0, 2]]

    floor = ground + np.maximum(MIN_CROUCH * rest, 1.05 * np.maximum(rig.l_min[0::2], rig.l_min[1::2]))

    free = (1.0 - planted) * 2.0 * rig.l_max  # a foot in the air does not hold the body

    def limits(lateral: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """The highest and the lowest each girdle may stand (T, G) with its hips along
        ``lateral`` (T, G, 3): never higher than lets a planted foot reach its ball (or a
        rolling foot's ankle), each hip beside the centre, turned and tilted with the
        girdle; nor so low that a planted foot comes nearer than the leg can fold (the
        uphill foot on a slope), nor crouched below MIN_CROUCH. The highest is per foot
        (T, L), as if every foot were planted."""
        side = (rig.hip_side * rig.hip_offset)[None, :, None]
        hip_offset = lateral[:, rig.girdle] * side  # (T, L, 3) from the centre
        hip_xz = point[:, rig.girdle] + hip_offset[..., [0, 2]]
        far = np.linalg.norm(reach_point[..., [0, 2]] - hip_xz, axis=-1)
        allowed = reach_point[..., 1] + np.sqrt(np.maximum(farthest ** 2 - far ** 2, 0.0)) - hip_offset[..., 1]
        horizontal = np.linalg.norm(ball[..., [0, 2]] - hip_xz, axis=-1)
        near = ball[..., 1] + np.sqrt(np.maximum((1.02 * rig.l_min) ** 2 - horizontal ** 2, 0.0))
        if reach is not None:  # ... nor nearer its foot's ankle than femur and tibia can fold
            fold = 1.02 * np.abs(rig.femur - rig.tibia)
            near = np.maximum(near, reach_point[..., 1] + np.sqrt(np.maximum(fold ** 2 - far ** 2, 0.0)))
        near = near - free - hip_offset[..., 1]  # the hip's lowest, as the girdle's (the hips tilt with it)
        return allowed, np.maximum(floor, np.maximum(near[:, 0::2], near[:, 1::2]))

    allowed, lowest = limits(lateral)
    highest = np.minimum((allowed + free)[:, 0::2], (allowed + free)[:, 1::2])
    # Where no height lets both sides' planted feet reach (across a steep slope, the
    # downhill foot too far below, the uphill one too near), the girdle rolls on towards
    # the downhill side (the side that lets it stand less high): its hips come down by
    # the roll, closing the gap.
    pair = 0.5 * (rig.hip_offset[0::2] + rig.hip_offset[1::2])[None, :]
    for _ in range(STEEP_ROLL_PASSES):  # (tilting the hips also moves them across: a few passes)
        short = lowest - highest
        if not np.any(short > 1e-6):
            break
        held = allowed + free
        lower_right = np.where(held[:, 1::2] < held[:, 0::2], 1.0, -1.0)  # + rolls the right hip down
        # Rolling lowers one side's hips as much as it raises the other's: it gains only
        # up to half the difference between the sides (none on level ground).
        gain = np.minimum(np.maximum(short, 0.0), 0.5 * np.abs(held[:, 0::2] - held[:, 1::2]))
        extra = np.where(pair > 1e-6, np.arcsin(np.clip(gain / np.maximum(pair, 1e-9), 0.0, 1.0)), 0.0)
        roll = np.clip(roll + lower_right * extra, -MAX_STEEP_ROLL, MAX_STEEP_ROLL)
        lateral = rotate_y(np.cos(roll)[..., None] * left + np.sin(roll)[..., None] * UP, yaw)
        allowed, lowest = limits(lateral)
        highest = np.minimum((allowed + free)[:, 0::2], (allowed + free)[:, 1::2])
    height = _within_reach(height, allowed, lowest, planted)
    centre = np.stack([point[..., 0], height, point[..., 1]], axis=-1)
    return Girdles(centre=centre, heading=heading, lateral=lateral, yaw=yaw, s=s_g)


def _within_reach(height: NDArray[np.float64], allowed: NDArray[np.float64], lowest: NDArray[np.float64],
                  planted: NDArray[np.float64]) -> NDArray[np.float64]:
    """Each girdle's height (T, G) m held where its feet reach: each foot's highest
    ``allowed`` (T, L) (as if it were planted) pulls the girdle down by its weight
    ``planted`` (T, L), so a foot lifting off lets go of the body as its weight fades
    rather than all at once (a slow walker's trailing leg, stretched in double support,
    let the body jump at toe-off); never below ``lowest`` (T, G)."""
    held = height[..., None] + planted.reshape(*height.shape, 2) * (
        np.minimum(height[..., None], allowed.reshape(*height.shape, 2)) - height[..., None])
    return np.maximum(held.min(axis=-1), lowest)


@dataclass(frozen=True)
class Spine:
    """segments (T, S, 3) centres at equal arc length, tangents (T, S, 3), radius (S,);
    neck (T, 2, 3) base and top; head (T, 2, 3) back of skull and nose; tail (T, K+1, 3);
    middle (T, 3) the trunk's middle and direction (T, 3) its unit tangent there (for an
    upright trunk: the heading); shoulder (T, 3) the point between the shoulders and
    shoulder_lateral (T, 3) the unit axis through them to the left (bodies with arms)."""

    segments: NDArray[np.float64]
    tangents: NDArray[np.float64]
    radius: NDArray[np.float64]
    neck: NDArray[np.float64]
    head: NDArray[np.float64]
    tail: NDArray[np.float64]
    middle: NDArray[np.float64]
    direction: NDArray[np.float64]
    shoulder: NDArray[np.float64] | None = None
    shoulder_lateral: NDArray[np.float64] | None = None


def _knots(rig: Rig, world: World, girdles: Girdles, s: NDArray[np.float64]):
    """Spine knots rear to front: the girdle centres, plus the trunk's ends (positions 0
    and 1) where no girdle sits there. Returns positions (K,), points (T, K, 3), horizontal
    tangents (T, K, 3) and yaw (T, K)."""
    order = np.argsort(rig.girdle_position)  # rear first
    pos = rig.girdle_position[order]
    points = girdles.centre[:, order]
    heading = girdles.heading[:, order]
    yaw = girdles.yaw[:, order]
    extra_pos, extra_pts, extra_head, extra_yaw, where = [], [], [], [], []
    # The trunk's ends carry on from the girdles at the pitch of the girdles' heights above
    # their rest heights (a least-squares line over arc length): level on flat ground
    # whatever the legs' lengths, pitched with the ground on a slope.
    rest = rig.girdle_rest_height[order]
    along = pos * rig.body_length
    if len(pos) > 1:
        centred = along - along.mean()
        slope = ((points[..., 1] - rest) * centred).sum(axis=1) / (centred ** 2).sum()
        slope = np.clip(slope, -MAX_END_SLOPE, MAX_END_SLOPE)  # girdles close together: a short, shaky baseline
    else:
        slope = np.zeros(points.shape[0])
    for end, side in ((0.0, 0), (1.0, -1)):
        if (end < pos[0] - 1e-9) if side == 0 else (end > pos[-1] + 1e-9):
            s_end = s + (end - 0.5) * rig.body_length
            xz, tangent = world.path.sample(s_end)
            y = points[:, side, 1] + slope * (end - pos[side]) * rig.body_length
            if not world.terrain.flat:
                # Never through the ground: above the highest ground under the overhang
                # by the trunk's radius there.
                between = np.linspace(end, pos[side], 5)[:-1]
                xz_between, _ = world.path.sample(s[:, None] + (between - 0.5) * rig.body_length)
                profile = rig.body.radius
                overhang = profile[:max(2, profile.size // 3)] if side == 0 else profile[-max(2, profile.size // 3):]
                y = np.maximum(y, world.terrain.height(xz_between).max(axis=1) + 1.05 * overhang.max())
            extra_pos.append(end)
            extra_pts.append(np.stack([xz[:, 0], y, xz[:, 1]], axis=-1))
            extra_head.append(_flat3(tangent))
            extra_yaw.append(yaw[:, side])
            where.append(side)
    for end, p, h, turn, side in zip(extra_pos, extra_pts, extra_head, extra_yaw, where):
        if side == 0:
            pos = np.concatenate([[end], pos])
            points = np.concatenate([p[:, None], points], axis=1)
            heading = np.concatenate([h[:, None], heading], axis=1)
            yaw = np.concatenate([turn[:, None], yaw], axis=1)
        else:
            pos = np.concatenate([pos, [end]])
            points = np.concatenate([points, p[:, None]], axis=1)
            heading = np.concatenate([heading, h[:, None]], axis=1)
            yaw = np.concatenate([yaw, turn[:, None]], axis=1)
    return pos, points, heading, yaw


def head_nod(rig: Rig, clock: NDArray[np.float64], phase: NDArray[np.float64] | None = None
             ) -> NDArray[np.float64] | float:
    """How far (rad, + down) a quadruped bows its neck and head at cycle time ``clock``
    (T,), timed by its fore feet's phases ``phase`` (T, L) when given (else by the gait's
    offsets: a clip whose gait changes, a speed ramp, nodded all through with its last
    gait's timing, a walk with a gallop's swing). Where the fore feet alternate (walk, trot) it nods twice a stride, lowest
    :data:`NOD_DELAY` of a cycle after each fore foot lands (as it takes the weight), by up
    to :data:`NOD`; where they land together or in quick succession (gallops, canter,
    bounds) the neck swings once a stride, lowest :data:`SWING_DELAY` after the fore feet
    land (the forehand loaded) and highest through the hind stance and the flight, by up
    to :data:`SWING` (Muybridge's galloping horses; fidelity.md). Both for a neck as long as
    the legs, less for shorter necks; nothing for upright or sprawled bodies."""
    front = np.nonzero(rig.girdle == 0)[0]  # the fore pair
    if rig.body.upright or len(front) != 2 or np.any(rig.knee_out[front]) or rig.leg_count < 4:
        return 0.0
    if phase is None:
        left, right = rig.gait.offsets[front]
        since_left = np.asarray(clock) - left  # cycles since the left fore foot landed
        behind = np.mod(right - left, 1.0)  # the right fore foot's landing after the left's (cycles)
    else:
        since_left = phase[:, front[0]]
        behind = np.mod(phase[:, front[0]] - phase[:, front[1]], 1.0)
    apart = np.abs(behind - 0.5)  # 0 when the fore feet alternate
    alternate = np.clip(1.0 - apart / 0.15, 0.0, 1.0)
    size = float(np.clip(rig.body.neck_length / max(rig.hip_height, 1e-6), 0.0, 1.0))
    nod = NOD * alternate * np.cos(4.0 * np.pi * (since_left - NOD_DELAY))
    # Since the fore feet's mean touchdown, on the circle (they may straddle the cycle's start).
    since_both = since_left - 0.5 * (np.mod(behind + 0.5, 1.0) - 0.5)
    swing = SWING * (1.0 - alternate) * np.cos(2.0 * np.pi * (since_both - SWING_DELAY))
    return size * (nod + swing)


def _appendages(rig: Rig, front: NDArray[np.float64], d_front: NDArray[np.float64], rear: NDArray[np.float64],
                d_rear: NDArray[np.float64], yaw_rear: NDArray[np.float64], clock: NDArray[np.float64],
                lag: Mapping[str, NDArray[np.float64]] | None, phase: NDArray[np.float64] | None = None):
    """Neck (T, 2, 3) and head (T, 2, 3) off the trunk's front end (T, 3) along its tangent
    there, tail (T, K+1, 3) off the rear end. ``lag`` gives, per part (head, neck, tail),
    how far (m) the body stood higher (+) a delay ago than now: the part follows through,
    pitching up by that much over its length (overlap)."""
    body = rig.body
    lag = lag or {}

    def follow(part: str, length: float):
        value = lag.get(part)
        return 0.0 if value is None else np.arctan2(value, max(length, 1e-3))

    bow = head_nod(rig, clock, phase)
    neck_dir = pitch(d_front, body.neck_angle + follow("neck", body.neck_length) - bow)
    neck_top = front + body.neck_length * neck_dir
    head_dir = pitch(d_front, -body.head_angle + follow("head", body.head_length) - bow)
    neck = np.stack([front, neck_top], axis=1)
    head = np.stack([neck_top, neck_top + body.head_length * head_dir], axis=1)
    k = np.arange(body.tail_segments)
    along = (k + 1) / body.tail_segments
    droop = body.tail_droop() - np.asarray(follow("tail", body.tail_length))[..., None] * along
    delay = rig.overlap.tail
    sway = rig.motion.tail_sway * along * np.sin(2.0 * np.pi * (clock[:, None] - delay - TAIL_WAVE_LAG * along))
    back = rotate_y(-d_rear[:, None, :], sway + yaw_rear[:, None])  # (T, K, 3)
    tail_dirs = pitch(back, -droop)
    tail = np.concatenate([rear[:, None], rear[:, None] + np.cumsum(
        (body.tail_length / body.tail_segments) * tail_dirs, axis=1)], axis=1)
    return neck, head, tail


def _upright_spine(rig: Rig, girdles: Girdles, clock: NDArray[np.float64],
                   lag: Mapping[str, NDArray[np.float64]] | None, running: NDArray[np.float64] | None = None) -> Spine:
    """An upright trunk (a human's): straight up from its one girdle, leaning forward by
    the key poses' torso lean (and a runner's :data:`RUN_LEAN` more, by ``running`` (T,));
    the shoulders turn against the hips (by the girdle's yaw)."""
    body = rig.body
    pelvis, heading, yaw = girdles.centre[:, 0], girdles.heading[:, 0], girdles.yaw[:, 0]
    lean = rig.poses.torso_lean + (0.0 if running is None else RUN_LEAN * running[:, None])
    axis = np.cos(lean) * UP + np.sin(lean) * heading  # (T, 3)
    fractions = (np.arange(body.segments) + 0.5) / body.segments
    segments = pelvis[:, None] + axis[:, None] * (fractions * body.length)[None, :, None]
    tangents = np.broadcast_to(axis[:, None], segments.shape).copy()
    radius = np.interp(fractions, np.linspace(0.0, 1.0, body.radius.size), body.radius)
    top = pelvis + axis * (body.length + 0.6 * body.radius[-1])
    neck, head, tail = _appendages(rig, top, heading, pelvis - heading * 0.6 * body.radius[0], heading, yaw,
                                   clock, lag)
    shoulder = lateral = None
    if rig.arms is not None:
        shoulder = pelvis + axis * body.length * rig.arms.position
        left = np.stack([heading[:, 2], np.zeros(len(heading)), -heading[:, 0]], axis=-1)
        lateral = rotate_y(left, -yaw)  # counter-rotating to the hips
    return Spine(segments=segments, tangents=tangents, radius=radius, neck=neck, head=head, tail=tail,
                 middle=pelvis + 0.5 * body.length * axis, direction=heading, shoulder=shoulder,
                 shoulder_lateral=lateral)


def _bernstein(t: NDArray[np.float64]) -> NDArray[np.float64]:
    """Cubic Bernstein weights (..., 4) at parameters ``t`` (...)."""
    u = 1.0 - t
    return np.stack([u * u * u, 3.0 * u * u * t, 3.0 * u * t * t, t * t * t], axis=-1)


def _bernstein_slope(t: NDArray[np.float64]) -> NDArray[np.float64]:
    """Their derivatives d/dt (..., 4): the weights of a cubic's tangent."""
    u = 1.0 - t
    return np.stack([-3.0 * u * u, 3.0 * u * u - 6.0 * u * t, 6.0 * u * t - 3.0 * t * t, 3.0 * t * t], axis=-1)


@lru_cache(maxsize=32)
def _arc_grid(pieces: int, ext_rear: float, ext_front: float) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Where :func:`_equal_arc_segments` measures a chain of ``pieces`` cubics: each
    piece's parameters (pieces, n) (the first reaching back by ``ext_rear``, the last on
    by ``ext_front``) and their Bernstein weights (pieces, n, 4)."""
    per = max(8, 64 // pieces)
    grid_t = np.broadcast_to(np.linspace(0.0, 1.0, per + 1), (pieces, per + 1)).copy()
    grid_t[0] = np.linspace(-ext_rear, 1.0, per + 1)
    grid_t[-1] = np.linspace(grid_t[-1, 0], 1.0 + ext_front, per + 1)
    grid_t.flags.writeable = False
    weights = _bernstein(grid_t)
    weights.flags.writeable = False
    return grid_t, weights


def _equal_arc_segments(ctrl: NDArray[np.float64], ext_rear: float, ext_front: float,
                        count: int) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """``count`` points (T, S, 3) and unit tangents (T, S, 3) at equal arc length along a
    chain of cubic Bezier pieces ``ctrl`` (T, K-1, 4, 3), the chain extended before its
    first piece by ``ext_rear`` and after its last by ``ext_front`` (in piece parameter).
    The arc length is measured along straight runs between sampled points."""
    frames, pieces = ctrl.shape[:2]
    grid_t, weights = _arc_grid(pieces, float(ext_rear), float(ext_front))
    per = grid_t.shape[1] - 1
    samples = weights @ ctrl  # (T, K-1, per+1, 3)
    step = np.diff(samples, axis=-2)
    seg_len = np.sqrt(np.sum(step * step, axis=-1))  # (T, K-1, per)
    cum = np.empty((frames, pieces * per + 1))
    cum[:, 0] = 0.0
    np.cumsum(seg_len.reshape(frames, -1), axis=-1, out=cum[:, 1:])
    wanted = ((np.arange(count) + 0.5) / count)[None, :] * cum[:, -1:]  # (T, S)
    idx = np.minimum(np.maximum(np.sum(cum[:, :, None] <= wanted[:, None, :], axis=1) - 1, 0), cum.shape[1] - 2)
    rows = np.arange(frames)[:, None]
    c0, c1 = cum[rows, idx], cum[rows, idx + 1]
    w = np.minimum(np.maximum((wanted - c0) / np.maximum(c1 - c0, 1e-15), 0.0), 1.0)
    seg, sub = np.divmod(idx, per)
    t_lo = grid_t[seg, sub]
    t_seg = t_lo + w * (grid_t[seg, sub + 1] - t_lo)
    seg_ctrl = ctrl[rows, seg]  # (T, S, 4, 3)
    points = np.einsum("tsk,tskc->tsc", _bernstein(t_seg), seg_ctrl)
    d = np.einsum("tsk,tskc->tsc", _bernstein_slope(t_seg), seg_ctrl)
    tangents = d / np.maximum(np.sqrt(np.sum(d * d, axis=-1, keepdims=True)), 1e-12)
    return points, tangents


def spine_through(rig: Rig, world: World, girdles: Girdles, s: NDArray[np.float64],
                  clock: NDArray[np.float64], lag: Mapping[str, NDArray[np.float64]] | None = None,
                  flex: NDArray[np.float64] | None = None, running: NDArray[np.float64] | None = None,
                  phase: NDArray[np.float64] | None = None) -> Spine:
    """The trunk, neck, head and tail for girdles placed by :func:`place_girdles` (``lag``:
    see :func:`_appendages`). ``flex`` (T,) rad arches the spine up (+) or hollows it (-):
    the tangents at its knots turn by ``flex * (0.5 - position)``, so the rear end's and
    the front end's directions differ by ``flex``. ``running`` (T,) in [0, 1]: how far an
    upright trunk takes a runner's extra lean (:data:`RUN_LEAN`). ``phase`` (T, L): the feet's
    phases, which time a quadruped's nod (:func:`head_nod`)."""
    if rig.body.upright:
        return _upright_spine(rig, girdles, clock, lag, running)
    body = rig.body
    frames = s.shape[0]
    pos, knots, heading, yaw = _knots(rig, world, girdles, s)
    count = len(pos)
    if count == 1:  # a single girdle at a trunk end cannot happen (the ends are knots), but be safe
        raise ValueError("a spine needs two knots")
    gap = np.diff(pos) * rig.body_length  # (K-1,) arc length between knots
    # Knot tangents: the path's heading, pitched by the height change between neighbours,
    # turned by the girdle's yaw.
    y = knots[..., 1]
    dy = np.empty_like(y)
    dy[:, 1:-1] = (y[:, 2:] - y[:, :-2]) / (gap[1:] + gap[:-1])
    dy[:, 0] = (y[:, 1] - y[:, 0]) / gap[0]
    dy[:, -1] = (y[:, -1] - y[:, -2]) / gap[-1]
    along_path = unit(heading + dy[..., None] * UP)
    tangent = rotate_y(along_path, yaw)
    if flex is not None:  # turn each knot's tangent up (rear) or down (front) in its vertical plane
        turn = flex[:, None] * (0.5 - pos)[None, :]  # (T, K)
        up = UP - np.sum(UP * tangent, axis=-1, keepdims=True) * tangent
        up = unit(np.where(np.linalg.norm(up, axis=-1, keepdims=True) > 1e-9, up, UP))
        tangent = unit(np.cos(turn)[..., None] * tangent + np.sin(turn)[..., None] * up)
    third = gap / 3.0
    ctrl = np.stack([knots[:, :-1], knots[:, :-1] + tangent[:, :-1] * third[:, None],
                     knots[:, 1:] - tangent[:, 1:] * third[:, None], knots[:, 1:]], axis=-2)  # (T, K-1, 4, 3)

    # Segment centres at equal arc length over the chain, a little beyond both ends.
    ext_rear = 0.9 * body.radius[0] / gap[0]
    ext_front = 0.9 * body.radius[-1] / gap[-1]
    segments, tangents = _equal_arc_segments(ctrl, ext_rear, ext_front, body.segments)
    fractions = (np.arange(body.segments) + 0.5) / body.segments
    spine_radius = np.interp(fractions, np.linspace(0.0, 1.0, body.radius.size), body.radius)

    # Neck and head off the front, tail off the rear.
    front = bezier(ctrl[:, -1], np.full((frames, 1), 1.0 + 0.6 * ext_front))[:, 0]
    rear = bezier(ctrl[:, 0], np.full((frames, 1), -0.6 * ext_rear))[:, 0]
    if rig.four_legged_mammal:  # a mammal's tail is set high, at the top of the croup
        rear = rear + UP * TAIL_SET * body.radius[0]
    neck, head, tail = _appendages(rig, front, tangent[:, -1], rear, tangent[:, 0], yaw[:, 0], clock, lag, phase)

    # The root: the middle of the trunk (position 0.5) and its direction there, on the
    # spine as the path shapes it (the girdles' yaw, a sway of the trunk about the root,
    # left out).
    mid = int(np.clip(np.searchsorted(pos, 0.5, side="right") - 1, 0, count - 2))
    t_mid = np.full((frames, 1), (0.5 - pos[mid]) / (pos[mid + 1] - pos[mid]))
    a, b = knots[:, mid], knots[:, mid + 1]
    mid_ctrl = np.stack([a, a + along_path[:, mid] * third[mid], b - along_path[:, mid + 1] * third[mid], b], axis=-2)
    middle = bezier(mid_ctrl, t_mid)[:, 0]
    direction = bezier_tangent(mid_ctrl, t_mid)[:, 0]
    shoulder = lateral = None
    if rig.arms is not None:  # on the trunk at the arms' position, level across
        where = np.clip(rig.arms.position * segments.shape[1] - 0.5, 0.0, segments.shape[1] - 1.0)
        i = min(int(where), segments.shape[1] - 2)
        w = where - i
        shoulder = segments[:, i] * (1.0 - w) + segments[:, i + 1] * w
        d = unit(tangents[:, i] * (1.0 - w) + tangents[:, i + 1] * w)
        lateral = unit(cross(UP, d))
    return Spine(segments=segments, tangents=tangents, radius=spine_radius, neck=neck, head=head, tail=tail,
                 middle=middle, direction=direction, shoulder=shoulder, shoulder_lateral=lateral)


def root_frames(spine: Spine) -> NDArray[np.float64]:
    """Body transforms (T, 4, 4): at the middle of the trunk, Z along it, Y up-ish."""
    frames = spine.middle.shape[0]
    root = np.zeros((frames, 4, 4))
    x_axis = unit(cross(UP, spine.direction))
    root[:, :3, 0] = x_axis
    root[:, :3, 1] = cross(spine.direction, x_axis)
    root[:, :3, 2] = spine.direction
    root[:, :3, 3] = spine.middle
    root[:, 3, 3] = 1.0
    return root
