"""From a rig and a gait clock to poses: feet, legs, body, neck, head and tail.

:func:`solve_motion` is the frame path. It is vectorised over frames and legs: the
gait inputs may vary per frame (blends in the viewer) and broadcast as (T, L). For a
constant gait the whole clip is one call (:func:`simulate`).

Conventions: Y up, the creature faces +Z, +X is its left. In-place locomotion: the
creature stays near the origin and the ground moves backwards under it at the speed of
the planted feet (``ground_offset``), so planted feet keep still relative to the ground.
"""

from __future__ import annotations

from dataclasses import dataclass, fields

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..spec import CreatureSpec
from .leg import solve_legs
from .oscillator import FootWave, foot_wave
from .rig import Rig, build_rig
from .spine import arc_length_parameters, bezier, bezier_tangent

UP = np.array([0.0, 1.0, 0.0])
FORWARD = np.array([0.0, 0.0, 1.0])
TAIL_DROOP = 0.4  # the tail's last segment hangs this much further (fraction of tail_angle)
TAIL_WAVE_LAG = 0.15  # cycle fraction by which the tail tip lags its base
REACH_MARGIN = 0.97  # planted feet stay within this fraction of the leg's full extension
MIN_CROUCH = 0.6  # ... by lowering the body, but never below this fraction of its rest height


@dataclass(frozen=True)
class Pose:
    """One frame. Shapes: L legs, S body segments, K tail segments; metres.

    joints (L, 5, 3) hip, knee, ankle, ball, toe tip; contact (L,) planted; phase (L,)
    foot phase since touchdown; spine (S, 3) segment centres, spine_tangent (S, 3),
    spine_radius (S,); neck (2, 3) base and top; head (2, 3) back of skull and nose;
    tail (K+1, 3) chain; root (4, 4) body transform; ground_offset: how far (m) the
    ground has moved backwards (-Z) since time 0.
    """

    joints: NDArray[np.float64]
    contact: NDArray[np.bool_]
    phase: NDArray[np.float64]
    spine: NDArray[np.float64]
    spine_tangent: NDArray[np.float64]
    spine_radius: NDArray[np.float64]
    neck: NDArray[np.float64]
    head: NDArray[np.float64]
    tail: NDArray[np.float64]
    root: NDArray[np.float64]
    ground_offset: float
    leg_names: tuple[str, ...]


@dataclass(frozen=True)
class Motion:
    """A clip: every :class:`Pose` field with a leading time axis T, plus the clock.

    times (T,) seconds; clock (T,) cycles since the start; fps frames per second.
    """

    times: NDArray[np.float64]
    clock: NDArray[np.float64]
    joints: NDArray[np.float64]
    contact: NDArray[np.bool_]
    phase: NDArray[np.float64]
    spine: NDArray[np.float64]
    spine_tangent: NDArray[np.float64]
    spine_radius: NDArray[np.float64]
    neck: NDArray[np.float64]
    head: NDArray[np.float64]
    tail: NDArray[np.float64]
    root: NDArray[np.float64]
    ground_offset: NDArray[np.float64]
    leg_names: tuple[str, ...]
    fps: float
    rig: Rig
    gaits: tuple[str, ...] = ()  # per frame, for speed-driven clips (empty otherwise)

    @property
    def frame_count(self) -> int:
        return int(self.times.shape[0])

    def pose(self, index: int) -> Pose:
        """Frame ``index`` as a :class:`Pose`."""
        static = {"spine_radius", "leg_names"}
        values = {}
        for f in fields(Pose):
            value = getattr(self, f.name)
            values[f.name] = value if f.name in static else value[index]
        values["ground_offset"] = float(self.ground_offset[index])
        return Pose(**values)


def _rotate_y(v: NDArray[np.float64], angle: NDArray[np.float64]) -> NDArray[np.float64]:
    """Rotate vectors (..., 3) about +Y by ``angle`` (...) radians."""
    c, s = np.cos(angle), np.sin(angle)
    x, y, z = v[..., 0], v[..., 1], v[..., 2]
    x, y, z, c, s = np.broadcast_arrays(x, y, z, c, s)
    return np.stack([c * x + s * z, y, -s * x + c * z], axis=-1)


def _unit(v: NDArray[np.float64]) -> NDArray[np.float64]:
    return v / np.maximum(np.linalg.norm(v, axis=-1, keepdims=True), 1e-12)


def _pitch(direction: NDArray[np.float64], angle: ArrayLike) -> NDArray[np.float64]:
    """Tilt a (nearly horizontal) direction up by ``angle`` radians towards +Y."""
    flat = _unit(direction * np.array([1.0, 0.0, 1.0]))
    angle = np.asarray(angle)[..., None]
    return np.cos(angle) * flat + np.sin(angle) * UP


def foot_waves(rig: Rig, clock: NDArray[np.float64], offsets: ArrayLike, duty: ArrayLike,
               shape: str) -> tuple[NDArray[np.float64], FootWave, FootWave]:
    """Each foot's phase (T, L) and its oscillator, plus the oscillator sampled for the
    body bob (shifted by ``motion.bob_phase``). clock (T,); offsets (T, L) or (L,);
    duty (T, 1) or scalar."""
    phase = np.mod(clock[:, None] - np.asarray(offsets, dtype=np.float64), 1.0)
    wave = foot_wave(phase, duty, shape)  # type: ignore[arg-type]
    bob_wave = foot_wave(phase - rig.spec.motion.bob_phase, duty, shape)  # type: ignore[arg-type]
    return phase, wave, bob_wave


def solve_motion(rig: Rig, clock: ArrayLike, *, offsets: ArrayLike | None = None,
                 duty: ArrayLike | None = None, stride: ArrayLike | None = None,
                 step_height: ArrayLike | None = None, bob: ArrayLike | None = None,
                 ground_offset: ArrayLike | None = None, times: ArrayLike | None = None,
                 fps: float = 60.0,
                 waves: tuple[NDArray[np.float64], FootWave, FootWave] | None = None,
                 forward_m: ArrayLike | None = None) -> Motion:
    """Poses for gait clock values.

    clock: (T,) cycles. Optional gait values (default: the rig's gait): offsets
    (touchdown phases), duty, stride (mean leg rest lengths) and step_height (leg rest
    lengths), each a scalar, (L,) per foot or (T, L); bob (leg rest lengths) a scalar or
    (T,). ground_offset (T,) metres of ground travel (default: the planted feet's mean
    stride / duty times the clock, i.e. how far they have been carried since clock 0).
    ``waves`` replaces the oscillators (phase, wave, bob wave as from
    :func:`foot_waves`), e.g. a cross-fade of two wave shapes. ``forward_m`` (T, L) gives
    each foot's fore-aft offset from its hip in metres directly (feet locked to the ground
    while planted, see LiveMotion) instead of the oscillator's offset times the stride.
    """
    gait = rig.gait
    clock = np.atleast_1d(np.asarray(clock, dtype=np.float64))
    frames = clock.shape[0]
    per_foot = lambda v, default: np.broadcast_to(np.asarray(default if v is None else v, dtype=np.float64),
                                                  (frames, rig.leg_count))  # noqa: E731
    offsets = per_foot(offsets, gait.offsets)
    duty_t = per_foot(duty, gait.duty_factor)
    stride_m = per_foot(stride, gait.stride) * float(rig.l_rest.mean())
    lift_m = per_foot(step_height, gait.step_height) * rig.l_rest
    bob_t = np.broadcast_to(np.asarray(gait.bob if bob is None else bob, dtype=np.float64), (frames,))[:, None]
    spec = rig.spec

    # Feet: oscillators -> targets on the moving ground.
    phase, wave, bob_wave = waves if waves is not None else foot_waves(rig, clock, offsets, duty_t, gait.wave)

    # Body: bob and yaw per pair (fore, hind) from the feet of that pair.
    pairs = np.array([[0, 1], [2, 3]])
    pair_lift = bob_wave.lift[:, pairs].max(axis=-1)  # (T, 2)
    # Long strides lower the body: each pair stands no higher than lets its feet reach both
    # ends of the stride within REACH_MARGIN of full extension (bob included), so planted
    # feet never get pulled off the ground.
    reach = np.sqrt(np.maximum((REACH_MARGIN * rig.l_max) ** 2 - (0.5 * stride_m) ** 2, 0.0))  # (T, L)
    bob_room = 0.5 * bob_t * rig.pair_rest_height  # (T, 2)
    lowest = np.maximum(MIN_CROUCH * rig.pair_rest_height, 1.05 * rig.l_min[pairs].max(axis=-1))
    stand = np.clip(reach[:, pairs].min(axis=-1) - bob_room, lowest, rig.pair_rest_height)
    pair_height = stand + bob_t * rig.pair_rest_height * (pair_lift - 0.5)
    pair_yaw = -np.radians(spec.motion.yaw) * (wave.forward[:, pairs[:, 0]] - wave.forward[:, pairs[:, 1]])

    # Spine: a cubic Bezier from the body's hind end (position 0) to its fore end (1);
    # the end heights are extrapolated from the two pairs, the end tangents carry the yaw.
    p_fore, p_hind = rig.pair_position
    slope = (pair_height[:, 0] - pair_height[:, 1]) / (p_fore - p_hind)
    y0 = pair_height[:, 1] - slope * p_hind
    y1 = y0 + slope
    half = 0.5 * rig.body_length
    p0 = np.stack([np.zeros(frames), y0, np.full(frames, -half)], axis=-1)
    p3 = np.stack([np.zeros(frames), y1, np.full(frames, half)], axis=-1)
    chord = _unit(p3 - p0)
    d_hind = _rotate_y(chord, pair_yaw[:, 1])
    d_fore = _rotate_y(chord, pair_yaw[:, 0])
    third = rig.body_length / 3.0
    ctrl = np.stack([p0, p0 + d_hind * third, p3 - d_fore * third, p3], axis=-2)  # (T, 4, 3)

    centres = bezier(ctrl, np.broadcast_to(rig.pair_position, (frames, 2)))  # (T, 2, 3)
    lateral = _rotate_y(np.broadcast_to(np.array([1.0, 0.0, 0.0]), (frames, 2, 3)), pair_yaw)
    hips = centres[:, rig.pair_index] + (rig.hip_side * rig.half_width)[None, :, None] * lateral[:, rig.pair_index]

    rest_z = (rig.pair_position[rig.pair_index] - 0.5) * rig.body_length
    neutral = np.stack([rig.hip_side * rig.half_width, np.zeros(rig.leg_count), rest_z], axis=-1)  # (L, 3)
    forward = wave.forward * stride_m if forward_m is None else np.broadcast_to(
        np.asarray(forward_m, dtype=np.float64), wave.lift.shape)
    targets = neutral + np.stack([np.zeros_like(wave.lift), wave.lift * lift_m, forward], axis=-1)
    joints = solve_legs(
        hips, targets, FORWARD, UP, np.sin(np.pi * wave.swing),
        femur=rig.femur, tibia=rig.tibia, metatarsus=rig.metatarsus, toe=rig.toe,
        ankle_lift=rig.ankle_lift, l_max=rig.l_max, l_rest=rig.l_rest, l_min=rig.l_min,
        knee_sign=rig.knee_sign,
    )

    # Body segments at equal arc length, a little beyond the hips and shoulders.
    body = spec.body
    radius = np.asarray(body.radius)
    ext_hind = 0.9 * radius[0] / rig.body_length
    ext_fore = 0.9 * radius[-1] / rig.body_length
    fractions = (np.arange(body.segments) + 0.5) / body.segments
    t_seg = arc_length_parameters(ctrl, fractions, -ext_hind, 1.0 + ext_fore)
    spine = bezier(ctrl, t_seg)
    spine_tangent = bezier_tangent(ctrl, t_seg)
    spine_radius = np.interp(fractions, np.linspace(0.0, 1.0, radius.size), radius)

    # Neck and head off the fore end, tail off the hind end.
    ends = bezier(ctrl, np.broadcast_to(np.array([-0.6 * ext_hind, 1.0 + 0.6 * ext_fore]), (frames, 2)))
    neck_dir = _pitch(d_fore, np.radians(body.neck_angle))
    neck_top = ends[:, 1] + body.neck_length * neck_dir
    head_dir = _pitch(d_fore, -np.radians(body.head_angle))
    neck = np.stack([ends[:, 1], neck_top], axis=1)
    head = np.stack([neck_top, neck_top + body.head_length * head_dir], axis=1)

    k = np.arange(body.tail_segments)
    along = (k + 1) / body.tail_segments
    droop = np.minimum(np.radians(body.tail_angle) * (1.0 + TAIL_DROOP * k / body.tail_segments), 0.5 * np.pi)
    sway = np.radians(spec.motion.tail_sway) * along * np.sin(2.0 * np.pi * (clock[:, None] - TAIL_WAVE_LAG * along))
    back = _rotate_y(-d_hind[:, None, :], sway + pair_yaw[:, 1:2])  # (T, K, 3)
    tail_dirs = _pitch(back, -droop)
    tail = np.concatenate([ends[:, None, 0], ends[:, None, 0] + np.cumsum(
        (body.tail_length / body.tail_segments) * tail_dirs, axis=1)], axis=1)

    # Root transform: at the middle of the chord, Z along it, Y up-ish.
    root = np.zeros((frames, 4, 4))
    x_axis = _unit(np.cross(UP, chord))
    root[:, :3, 0] = x_axis
    root[:, :3, 1] = np.cross(chord, x_axis)
    root[:, :3, 2] = chord
    root[:, :3, 3] = 0.5 * (p0 + p3)
    root[:, 3, 3] = 1.0

    if ground_offset is None:
        ground_offset = (stride_m / duty_t).mean(axis=1) * clock
    times = np.arange(frames) / fps if times is None else np.asarray(times, dtype=np.float64)
    return Motion(times=times, clock=clock, joints=joints, contact=wave.contact, phase=phase, spine=spine,
                  spine_tangent=spine_tangent, spine_radius=spine_radius, neck=neck, head=head, tail=tail,
                  root=root, ground_offset=np.asarray(ground_offset, dtype=np.float64), leg_names=rig.leg_names,
                  fps=fps, rig=rig)


def frame_count(seconds: float, fps: float) -> int:
    """Frames in a clip: ``round(seconds * fps)``, at least one."""
    return max(1, int(round(seconds * fps)))


def simulate(spec: CreatureSpec | Rig, seconds: float = 4.0, fps: float = 60.0, *,
             start_phase: float = 0.0) -> Motion:
    """Simulate a creature walking in place for ``seconds`` at ``fps`` (fixed dt = 1/fps).

    Deterministic: the clock is ``start_phase + frequency * i / fps`` for frame i.
    """
    rig = spec if isinstance(spec, Rig) else build_rig(spec)
    times = np.arange(frame_count(seconds, fps)) / fps
    clock = start_phase + rig.gait.frequency * times
    return solve_motion(rig, clock, times=times, fps=fps)
