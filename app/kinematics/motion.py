"""From a rig, a gait clock and a world to poses: feet, legs, body, neck, head and tail.

:func:`solve_motion` is the frame path, vectorised over frames and legs. It takes one
:class:`MotionInputs` (the clock, each foot's :class:`~app.kinematics.footfalls.FootPlan`,
where the body is along its path) and runs the steps: foot targets, girdles, spine, hips
and leg IK, head and tail, root. For a constant gait the whole clip is one call
(:func:`simulate`); the viewer and speed ramps fill the same inputs frame by frame
(:class:`~app.kinematics.live.LiveMotion`).

Conventions: Y up, the creature faces +Z (+X is its left) at the start of its path.
Positions are in the world, except in place (``World(in_place=True)``): then the body
stays at the origin and ``ground_offset`` says how far the ground has moved back under
it, so planted feet keep still relative to the ground.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field, fields, replace
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..choices import WaveShape
from .arms import arm_chains, arm_swing
from .body import place_girdles, root_frames, spine_through
from .footfalls import FootPlan, foot_directions, foot_targets, plan_constant_gait
from .gait import ground_speed
from .leg import solve_legs
from .oscillator import FootWave, foot_wave
from .path import Path
from .poses import body_height, reference_foot
from .rig import Rig
from .roll import foot_roll, heel_points
from .terrain import Terrain
from .walker import walking_weight
from .world import World, WorldError

TIGHTEST_TURN = 0.2  # body lengths: the smallest turning radius a path may ask for
REACH_TOLERANCE = 0.01  # m a planted foot may miss its foothold before the ground counts as out of reach
REACHED = 1e-6  # m: a foot this near its foothold stands on it
MAX_LIFT_MISS = 0.2  # of L_max: the farthest a foot lifts early or lands late short of its foothold


_POINTS = {"points": True}  # a field holding world positions (they move with the creature, or the ground)
_PER_CLIP = {"per_clip": True}  # a field that is the same for every frame of a clip (no time axis in a Motion)


@dataclass(frozen=True)
class _BodyParts:
    """The fields a :class:`Pose` and a :class:`Motion` share, declared once: a Motion
    has each with a leading time axis T (except the per-clip ones).

    joints (L, 5, 3) hip, knee, ankle, ball, toe tip; contact (L,) planted; phase (L,)
    foot phase since touchdown; spine (S, 3) segment centres, spine_tangent (S, 3),
    spine_radius (S,); neck (2, 3) base and top; head (2, 3) back of skull and nose;
    tail (K+1, 3) chain; root (4, 4) body transform; heel (L, 3) where each foot's heel
    touches (the ball for feet that do not roll or stand on their toes); arms (A, 4, 3)
    shoulder, elbow, wrist and hand tip of each arm (A = 0 or 2, left first).
    """

    joints: NDArray[np.float64] = field(metadata=_POINTS)
    contact: NDArray[np.bool_]
    phase: NDArray[np.float64]
    spine: NDArray[np.float64] = field(metadata=_POINTS)
    spine_tangent: NDArray[np.float64]
    spine_radius: NDArray[np.float64] = field(metadata=_PER_CLIP)
    neck: NDArray[np.float64] = field(metadata=_POINTS)
    head: NDArray[np.float64] = field(metadata=_POINTS)
    tail: NDArray[np.float64] = field(metadata=_POINTS)
    root: NDArray[np.float64]
    leg_names: tuple[str, ...] = field(metadata=_PER_CLIP)
    heel: NDArray[np.float64] = field(metadata=_POINTS)
    arms: NDArray[np.float64] = field(metadata=_POINTS)


POINT_FIELDS: tuple[str, ...] = tuple(f.name for f in fields(_BodyParts) if f.metadata.get("points"))
PER_CLIP_FIELDS: tuple[str, ...] = tuple(f.name for f in fields(_BodyParts) if f.metadata.get("per_clip"))


@dataclass(frozen=True)
class Pose(_BodyParts):
    """One frame. Shapes: L legs, S body segments, K tail segments; metres (the shared
    fields: see :class:`_BodyParts`). ground_offset: how far (m) the ground has moved
    backwards (-Z) since time 0 (in place; 0 when travelling); travel: the body's arc
    length along its path (m); ear_lag (rad) how far the ears are turned back by their
    follow-through (up when < 0).
    """

    ground_offset: float
    travel: float
    ear_lag: float


@dataclass(frozen=True)
class Motion(_BodyParts):
    """A clip: every :class:`Pose` field with a leading time axis T (but the per-clip
    ones), plus the clock, the rig and the world it walked in.

    times (T,) seconds; clock (T,) cycles since the start; fps frames per second;
    ``path`` and ``terrain`` are the world's.
    """

    times: NDArray[np.float64]
    clock: NDArray[np.float64]
    ground_offset: NDArray[np.float64]  # (T,): a Pose's number, per frame
    travel: NDArray[np.float64]
    ear_lag: NDArray[np.float64]  # (T,) rad
    fps: float
    rig: Rig
    world: World = field(default_factory=World)
    gaits: tuple[str, ...] = ()  # per frame, for speed-driven clips (empty otherwise)
    reach_error: NDArray[np.float64] | None = None  # (T, L) m between each ball and its target
    compromised: NDArray[np.bool_] | None = None  # (T, L) the foot stands on (or swings to) uneven ground
    lifted: NDArray[np.bool_] | None = None  # (T, L) planned stance where the leg could not reach: off the ground

    @property
    def frame_count(self) -> int:
        return int(self.times.shape[0])

    @property
    def path(self) -> Path:
        return self.world.path

    @property
    def terrain(self) -> Terrain:
        return self.world.terrain

    @property
    def in_place(self) -> bool:
        return self.world.in_place

    def frames(self, first: int) -> Motion:
        """The clip from frame ``first`` on."""
        per_frame = [f.name for f in fields(Pose) if f.name not in PER_CLIP_FIELDS] + ["times", "clock"]
        values = {name: getattr(self, name)[first:] for name in per_frame}
        if self.reach_error is not None:
            values["reach_error"] = self.reach_error[first:]
        for name in ("compromised", "lifted"):
            value = getattr(self, name)
            if value is not None:
                values[name] = value[first:]
        if self.gaits:
            values["gaits"] = self.gaits[first:]
        return replace(self, **values)

    def pose(self, index: int) -> Pose:
        """Frame ``index`` as a :class:`Pose`."""
        values: dict[str, Any] = {}
        for f in fields(Pose):
            value = getattr(self, f.name)
            values[f.name] = value if f.name in PER_CLIP_FIELDS else value[index]
        for name in ("ground_offset", "travel", "ear_lag"):  # numbers in a pose
            values[name] = float(values[name])
        return Pose(**values)


@dataclass(frozen=True)
class MotionInputs:
    """Everything one call of :func:`solve_motion` needs, per frame (T) and foot (L).

    clock (T,) cycles; times (T,) s; plan: the feet (see FootPlan); travel (T,) the body
    centre's arc length along the path (m); stride (T, L) the planted feet's travel
    relative to their hips (m, for the standing height); bob (T,) leg rest lengths; wave:
    the oscillator shape; ``waves`` optionally replaces the oscillators (a cross-fade of
    two shapes: foot wave and bob wave); trunk (T, 2) the spine's flexion and pitch
    amplitudes (default: the gait's); frequency (T,) cycles/s (default: the gait's);
    height_shift (T,) m added to a posed body's height (what is left of a jump a change of
    duty factor made, :func:`app.kinematics.poses.settle`); running_shift (T,) added to
    how far a biped runs (0 walking to 1 running: its lean and bent elbows), likewise.
    """

    clock: NDArray[np.float64]
    times: NDArray[np.float64]
    plan: FootPlan
    travel: NDArray[np.float64]
    stride: NDArray[np.float64]
    bob: NDArray[np.float64]
    wave: WaveShape
    waves: tuple[FootWave, FootWave] | None = None
    trunk: NDArray[np.float64] | None = None
    frequency: NDArray[np.float64] | None = None
    height_shift: NDArray[np.float64] | None = None
    running_shift: NDArray[np.float64] | None = None


def trunk_motion(rig: Rig, phase: NDArray[np.float64], wave: FootWave, trunk: NDArray[np.float64] | None
                 ) -> tuple[NDArray[np.float64], NDArray[np.float64]] | None:
    """The spine's flexion and the trunk's pitch (T,) each, rad, for a body with two or
    more girdles (None when the gait asks for neither). The spine flexes (arches up) as
    the hind feet land, reaching forward, and extends half a cycle later as they push off
    (the mean cosine of the hind feet's phases (T, L): smooth through the footfalls, and
    nothing when they step half a cycle apart); the
    trunk pitches nose up while the fore feet are in the air and the hind feet down, nose
    down the other way round. ``trunk`` (T, 2) gives the amplitudes (either way), or the
    gait's."""
    if rig.girdle_rest_height.size < 2:
        return None
    amp = np.broadcast_to([rig.gait.flex, rig.gait.pitch], (phase.shape[0], 2)) if trunk is None else trunk
    if not np.any(amp):
        return None
    fore, hind = [0, 1], [reference_foot(rig), reference_foot(rig) + 1]
    flex = amp[:, 0] * np.cos(2.0 * np.pi * phase[:, hind]).mean(axis=1)  # feet out of step cancel
    pitch = amp[:, 1] * (wave.lift[:, fore].mean(axis=1) - wave.lift[:, hind].mean(axis=1))
    return flex, pitch


def oscillators(rig: Rig, plan: FootPlan, wave: WaveShape) -> tuple[FootWave, FootWave]:
    """Each foot's oscillator at its phase, and the one sampled for the body bob (shifted
    by the bob phase)."""
    return (foot_wave(plan.phase, plan.duty, wave),
            foot_wave(plan.phase - rig.motion.bob_phase, plan.duty, wave))


def _leg_frames(rig: Rig, heading: NDArray[np.float64], normal: NDArray[np.float64]):
    """Each leg's frame (forward, up): up is the ground normal under its foot; forward is
    the girdle's heading (mammal legs) or the outward direction (sprawled legs), made
    perpendicular to up. Returns (3,) vectors when every leg shares one frame."""
    legs = np.arange(rig.leg_count)
    direction = foot_directions(rig, heading[..., [0, 2]], legs)
    forward = np.stack([direction[..., 0], np.zeros(direction.shape[:-1]), direction[..., 1]], axis=-1)
    forward = forward - np.sum(forward * normal, axis=-1, keepdims=True) * normal
    forward /= np.linalg.norm(forward, axis=-1, keepdims=True)
    first_f, first_u = forward.reshape(-1, 3)[0], normal.reshape(-1, 3)[0]
    if np.all(forward == first_f) and np.all(normal == first_u):
        return first_f.copy(), first_u.copy()
    return forward, normal


def _body_heights(rig: Rig, inputs: MotionInputs, wave: str, bob: NDArray[np.float64],
                  delays: Sequence[float] = (0.0,)) -> list[NDArray[np.float64]]:
    """How far (m) each girdle (T, G) stands above or below its standing height from the
    gait's rhythm each of ``delays`` cycles ago: the key poses' height (a run's flights once
    the feet leave the ground together), or the bob. A posed body's heights at every delay
    are one vectorised evaluation (the frames stacked delay by delay)."""
    plan = inputs.plan
    frames, girdles = plan.phase.shape[0], rig.girdle_rest_height.size
    if rig.poses.heights is not None:
        ref = reference_foot(rig)
        frequency = inputs.frequency if inputs.frequency is not None else np.full(frames, rig.gait.frequency)
        k = len(delays)
        phase = np.concatenate([plan.phase - delay for delay in delays])
        height = body_height(rig, phase, np.tile(plan.duty, (k, 1)), np.tile(frequency, k),
                             np.tile(inputs.stride[:, ref], k)).reshape(k, frames)
        return [np.broadcast_to(h[:, None], (frames, girdles)) for h in height]
    out = []
    for delay in delays:  # (the bob: a handful of delayed parts at most)
        lift = foot_wave(plan.phase - rig.motion.bob_phase - delay, plan.duty, wave).lift  # type: ignore[arg-type]
        girdle_lift = np.maximum(lift[:, 0::2], lift[:, 1::2])
        out.append(bob[:, None] * rig.girdle_rest_height * (girdle_lift - 0.5))
    return out


_DELAYED = (("head", 0), ("neck", 0), ("tail", -1), ("ears", 0))  # parts that follow through, and their girdle


def _overlap(rig: Rig, inputs: MotionInputs, wave: str, bob: NDArray[np.float64]
             ) -> tuple[dict[str, NDArray[np.float64]], NDArray[np.float64]]:
    """Each delayed part's lag (T,): how much higher (m) its end of the body stood its delay
    ago than now (the head and neck at the front girdle, the tail at the rear one); and the
    height now (T, G) (:func:`_body_heights`)."""
    parts = [(part, girdle, getattr(rig.overlap, part)) for part, girdle in _DELAYED if getattr(rig.overlap, part) > 0]
    if not parts and rig.poses.heights is None:  # nothing follows through, and the bob is placed elsewhere
        return {}, np.zeros((inputs.plan.phase.shape[0], rig.girdle_rest_height.size))
    heights = _body_heights(rig, inputs, wave, bob, [0.0] + [delay for _, _, delay in parts])
    now = heights[0]
    lag = {part: then[:, girdle] - now[:, girdle] for (part, girdle, _), then in zip(parts, heights[1:])}
    return lag, now


def solve_motion(rig: Rig, world: World, inputs: MotionInputs, fps: float = 60.0) -> Motion:
    """Poses for every frame of ``inputs`` (see the module docstring for the steps)."""
    plan = inputs.plan
    frames = inputs.clock.shape[0]
    wave, bob_wave = inputs.waves if inputs.waves is not None else oscillators(rig, plan, inputs.wave)

    # 1. Feet: targets from the plan, lifted by the oscillator, rolled heel to toe.
    feet = foot_targets(plan, wave.lift, inputs.wave, rig, world, inputs.travel)
    roll = foot_roll(rig, plan, feet.ball, rig.poses.foot_angle)
    ball = feet.ball if roll is None else roll.ball

    # 2. Girdles: on the path, at the height of their feet's ground (and of the key poses).
    planted = np.where(plan.contact, 1.0, np.clip(np.maximum(1.0 - 4.0 * plan.swing, 4.0 * plan.swing - 3.0), 0, 1))
    posed = rig.poses.heights is not None
    bob = np.zeros_like(inputs.bob) if posed else inputs.bob
    lag, now = _overlap(rig, inputs, inputs.wave, bob)  # (3. the parts that follow through)
    height = now[:, 0] if posed else None
    if height is not None and inputs.height_shift is not None:
        height = height + inputs.height_shift
    trunk = trunk_motion(rig, plan.phase, wave, inputs.trunk)
    girdles = place_girdles(rig, world, inputs.travel, feet.support, ball, planted, inputs.stride,
                            bob, bob_wave.lift, wave.forward, pose_height=height,
                            reach=None if roll is None else (roll.ankle, roll.reach),
                            pitch=None if trunk is None else trunk[1], phase=plan.phase)

    # 3. Spine, neck, head, tail (following through by their overlap).
    running = 1.0 - walking_weight(plan.duty[:, reference_foot(rig)])  # a biped's run: lean in, elbows bent
    if inputs.running_shift is not None:
        running = np.clip(running + inputs.running_shift, 0.0, 1.0)
    spine = spine_through(rig, world, girdles, inputs.travel, inputs.clock, lag, flex=None if trunk is None else trunk[0],
                          running=running if rig.body.upright else None, phase=plan.phase)
    ear_lag = np.arctan2(lag["ears"], max(rig.body.ear_length, 1e-3)) if "ears" in lag else np.zeros(frames)

    # 4. Hips beside the girdle centres, then the legs in their own frames.
    hips = girdles.centre[:, rig.girdle] + (rig.hip_side * rig.hip_offset)[None, :, None] * \
        girdles.lateral[:, rig.girdle]
    forward, up = _leg_frames(rig, girdles.heading[:, rig.girdle], feet.normal)
    ground: float | NDArray[np.float64] = 0.0
    if not world.terrain.flat:  # the ground under the ball and under the toe tip, whichever is higher
        toe_tip = ball[..., [0, 2]] + np.broadcast_to(forward, ball.shape)[..., [0, 2]] * rig.toe[:, None]
        ground = np.maximum(world.terrain.height(ball[..., [0, 2]]), world.terrain.height(toe_tip))
    rolls = {}
    if roll is not None:  # a rolling foot's leg works in the plane the foot points in
        w = roll.forward_weight[..., None]
        up = np.broadcast_to(up, ball.shape)
        forward = np.broadcast_to(forward, ball.shape) * (1.0 - w) + roll.forward * w
        forward = forward - np.sum(forward * up, axis=-1, keepdims=True) * up
        forward = forward / np.linalg.norm(forward, axis=-1, keepdims=True)
        rolls = dict(ankle_angle=roll.ankle_angle, ankle_weight=roll.ankle_weight, toe_drop=roll.toe_drop,
                     toe_weight=roll.toe_weight, dorsiflexion=roll.dorsiflexion, dorsi_weight=roll.dorsi_weight,
                     knee_target=roll.knee, knee_weight=roll.knee_weight,
                     knee_floor=roll.knee_floor, knee_ceiling=roll.knee_ceiling,
                     band_weight=roll.band_weight)
        # A rolled foot's ankle angle is its own, not the one L_max assumes: let the leg
        # reach as far as its bones do (place_girdles keeps the ankle within reach).
        l_max = np.where(roll.sets_ankle, 0.999 * (rig.femur + rig.tibia + rig.metatarsus), rig.l_max)
    else:
        l_max = rig.l_max
    joints = solve_legs(
        hips, ball, forward, up, np.sin(np.pi * wave.swing),
        femur=rig.femur, tibia=rig.tibia, metatarsus=rig.metatarsus, toe=rig.toe,
        ankle_lift=rig.ankle_lift, l_max=l_max, l_rest=rig.l_rest, l_min=rig.l_min,
        knee_sign=rig.knee_sign, swing_rest=rig.swing_rest, ground_height=ground, knee_pole=rig.knee_pole, **rolls,
    )
    heel = heel_points(rig, joints, forward, up)
    root = root_frames(spine)
    reach_error = np.linalg.norm(joints[:, :, 3] - ball, axis=-1)
    lifted = stance_ends_out_of_reach(plan.contact, reach_error, plan.phase / np.maximum(plan.duty, 1e-9),
                                      MAX_LIFT_MISS * rig.l_max)

    # 5. Arms, swinging against the legs of the rearmost pair.
    if rig.arms is not None:
        ref = reference_foot(rig)
        angle = arm_swing(rig.poses.arm_swing, rig.overlap.arms, plan.phase[:, [ref + 1, ref]])
        assert spine.shoulder is not None and spine.shoulder_lateral is not None  # a trunk with arms has shoulders
        arms = arm_chains(rig.arms, spine.shoulder, spine.shoulder_lateral, angle, running)
    else:
        arms = np.zeros((frames, 0, 4, 3))

    spine_pts, spine_tan, neck, head, tail = spine.segments, spine.tangents, spine.neck, spine.head, spine.tail
    ground_offset = np.zeros(frames)
    if world.in_place:
        # The body stays at the origin; the ground moves back under it by the travel.
        ground_offset = inputs.travel.copy()
        shift = np.zeros((frames, 3))
        shift[:, 2] = -inputs.travel
        joints = joints + shift[:, None, None, :]
        heel = heel + shift[:, None, :]
        arms = arms + shift[:, None, None, :]
        spine_pts, neck, head, tail = (a + shift[:, None, :] for a in (spine_pts, neck, head, tail))
        root = root.copy()
        root[:, 2, 3] -= inputs.travel
    return Motion(times=inputs.times, clock=inputs.clock, joints=joints, contact=plan.contact & ~lifted,
                  phase=plan.phase,
                  spine=spine_pts, spine_tangent=spine_tan, spine_radius=spine.radius, neck=neck, head=head,
                  tail=tail, root=root, ground_offset=ground_offset, travel=inputs.travel,
                  leg_names=rig.leg_names, fps=fps, rig=rig, heel=heel, arms=arms, ear_lag=ear_lag, world=world,
                  reach_error=reach_error, compromised=plan.compromised, lifted=lifted)


def stance_ends_out_of_reach(contact: NDArray[np.bool_], reach_error: NDArray[np.float64],
                             progress: NDArray[np.float64], farthest: NDArray[np.float64] | float = np.inf,
                             ) -> NDArray[np.bool_]:
    """The frames (T, L) at either end of a stance in which the leg cannot reach its
    foothold (``reach_error`` (T, L) m beyond :data:`REACHED`): there the foot lifts early
    (the leg at full stretch behind, as a real stance ends at its leg's limit) or lands
    late (full stretch ahead, down into a hollow): a late landing within the stance's
    first half, an early lift within its second (``progress`` (T, L): 0 at touchdown, 1
    at lift-off). A miss between frames that reach, beyond the stance's half, through a
    whole stance the clip holds from touchdown to lift-off, or by more than ``farthest``
    (L,) m, stays a planted foot that misses, for :func:`check_reach` to judge. (A stance
    the clip cuts is judged on the frames it holds: the same frames are lifted whatever
    the clip's start and length.) Vectorised over frames and legs."""
    frames = contact.shape[0]
    good = contact & (reach_error <= REACHED)
    index = np.arange(frames)[:, None]
    # Nearest frame before/after (inclusive) that reaches, and that is not in stance.
    prev_good = np.maximum.accumulate(np.where(good, index, -1), axis=0)
    prev_swing = np.maximum.accumulate(np.where(contact, -1, index), axis=0)
    next_good = np.minimum.accumulate(np.where(good, index, frames)[::-1], axis=0)[::-1]
    next_swing = np.minimum.accumulate(np.where(contact, frames, index)[::-1], axis=0)[::-1]
    leading = prev_good <= prev_swing  # no reaching frame since the stance began (or the clip)
    trailing = next_good >= next_swing  # none until it ends (or the clip does)
    # A stance that reaches nowhere within the clip is refused, unless the clip cuts it:
    # then it may reach beyond the cut (the frames here are its landing or its lift).
    early_lift = trailing & (progress > 0.5) & (~leading | (prev_swing < 0))
    late_landing = leading & (progress < 0.5) & (~trailing | (next_swing >= frames))
    return contact & ~good & (early_lift | late_landing) & (reach_error <= farthest)


def frame_count(seconds: float, fps: float) -> int:
    """Frames in a clip: ``round(seconds * fps)``, at least one."""
    return max(1, int(round(seconds * fps)))


def travel_per_cycle(rig: Rig) -> float:
    """How far (m) the body moves along its path in one cycle of the rig's gait."""
    return float(ground_speed(rig.gait.stride * rig.leg_scale, rig.gait.duty_factor))


def constant_gait_inputs(rig: Rig, world: World, clock: NDArray[np.float64],
                         times: NDArray[np.float64], origin: float = 0.0) -> MotionInputs:
    """The inputs of a constant gait at clock values (T,), the body at arc length
    ``origin`` (m) at clock 0."""
    per_cycle = travel_per_cycle(rig)
    plan = plan_constant_gait(rig, world, clock, per_cycle, origin=origin)
    stride = np.broadcast_to(rig.stride_length, plan.phase.shape)
    bob = np.full(clock.shape[0], rig.gait.bob)
    return MotionInputs(clock=clock, times=times, plan=plan, travel=origin + per_cycle * clock, stride=stride,
                        bob=bob, wave=rig.gait.wave, frequency=np.full(clock.shape[0], rig.gait.frequency))


def check_world(rig: Rig, world: World) -> None:
    """Refuse a path the body cannot follow: turns tighter than TIGHTEST_TURN body lengths."""
    radius = world.path.curvature_radius()
    if radius < TIGHTEST_TURN * rig.body_length:
        raise WorldError(f"path {world.path.describe()}: turns with a radius of {radius:.3g} m, too tight for the "
                         f"{rig.name} (body {rig.body_length:.3g} m long); give a radius of at least "
                         f"{TIGHTEST_TURN * rig.body_length:.3g} m")


def check_reach(motion: Motion) -> None:
    """Refuse ground that asks more than the legs can reach: a planted foot that misses its
    foothold by more than a centimetre (steps too high, hills too steep for the creature).
    A stance's ends out of reach are no refusal: there the foot lifts early or lands late
    (:func:`stance_ends_out_of_reach`)."""
    if motion.reach_error is None:
        return
    miss = np.where(motion.contact, motion.reach_error, 0.0)
    if miss.max() > REACH_TOLERANCE:
        frame, leg = np.unravel_index(int(miss.argmax()), miss.shape)
        raise WorldError(f"terrain {motion.terrain.describe()}: the {motion.rig.name}'s foot {motion.leg_names[leg]} "
                         f"cannot reach its foothold at t = {motion.times[frame]:.2f} s (short by "
                         f"{miss[frame, leg] * 100:.1f} cm); lower the steps or hills, or choose a bigger creature")


def simulate(rig: Rig, seconds: float = 4.0, fps: float = 60.0, *, world: World | None = None,
             start_phase: float = 0.0) -> Motion:
    """A creature walking its gait for ``seconds`` at ``fps`` (fixed dt = 1/fps) in
    ``world`` (default: straight ahead on flat ground). Deterministic: the clock is
    ``start_phase + frequency * i / fps`` for frame i. Raises :class:`WorldError` for a
    path too tight or ground the legs cannot reach."""
    world = world or World()
    check_world(rig, world)
    times = np.arange(frame_count(seconds, fps)) / fps
    clock = start_phase + rig.gait.frequency * times
    motion = solve_motion(rig, world, constant_gait_inputs(rig, world, clock, times), fps=fps)
    if not world.terrain.flat:
        check_reach(motion)
    return motion

