"""From a creature file to a rig: the one adapter between :mod:`app.spec` (what the file
says, in its units) and :mod:`app.kinematics` (SI units, radians, per-leg arrays).

Everything that does not change from frame to frame is derived here once: the legs'
maximum / rest / minimum lengths, which way each knee points, where each hip sits, the
resolved gait, and the gaits that speeds switch between.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from .choices import PLANTIGRADE_BELOW
from .gaits import gaits_for
from .kinematics.gait import GaitParams, natural_frequency
from .kinematics.oscillator import duty_from_bias
from .kinematics.rig import ArmShape, BodyShape, KeyPoses, Rig, SecondaryMotion, SpeedGaits, leg_lengths
from .spec import CreatureSpec, GaitSpec, leg_type, resolve_phases
from .styles import DEFAULT_TIMING_FPS, STYLES, style_heights

OUT_KNEE_POLE = np.array([0.6, 1.0])  # sprawled legs' knees bend up, and a little out (leg frame: forward=out, up)


def resolve_duty(gait: GaitSpec) -> float:
    """The duty factor: given directly, from the bias, or the preset's."""
    if gait.duty_factor is not None:
        return float(gait.duty_factor)
    if gait.bias is not None:
        return float(duty_from_bias(gait.bias))
    return gait.preset_spec.duty_factor


def resolve_frequency(gait: GaitSpec, hip_height: float) -> float:
    """The stride frequency (Hz): given, from frames per cycle at the timing frame rate, or
    the preset's natural frequency for the hip height (m)."""
    if gait.frequency is not None:
        return float(gait.frequency)
    if gait.frames_per_cycle is not None:
        return (gait.timing_fps or DEFAULT_TIMING_FPS) / gait.frames_per_cycle
    return natural_frequency(gait.preset_spec.cadence, hip_height)


def trunk_factor(spec: CreatureSpec, hip_height: float) -> float:
    """How much of a gait's spine flex and trunk pitch a creature shows: its hind legs' type
    (digitigrade 1, plantigrade 0.6, unguligrade 0.4: a horse's back is stiff) times its
    size (smaller bends more: (0.4 m / hip height)^0.25 within 0.7..1.3), times the
    file's ``motion.spine_flex``."""
    hind = spec.girdles[-1][0]
    kind = {"digitigrade": 1.0, "plantigrade": 0.6, "unguligrade": 0.4}[leg_type(hind.ankle_lift)]
    size = float(np.clip((0.4 / max(hip_height, 1e-3)) ** 0.25, 0.7, 1.3))
    return kind * size * spec.motion.spine_flex


def resolve_gait(gait: GaitSpec, feet: tuple[str, ...], hip_height: float, bob: float | None = None,
                 trunk: float = 0.0) -> GaitParams:
    """Combine a gait spec with its preset. ``hip_height`` (m) sets the default frequency;
    ``trunk`` scales the preset's spine flex and trunk pitch (see :func:`trunk_factor`)."""
    preset = gait.preset_spec
    return GaitParams(
        preset=gait.preset,
        frequency=resolve_frequency(gait, hip_height),
        duty_factor=resolve_duty(gait),
        offsets=resolve_phases(gait, feet),
        stride=preset.stride if gait.stride is None else gait.stride,
        step_height=preset.step_height if gait.step_height is None else gait.step_height,
        bob=preset.bob if bob is None else bob,
        wave=gait.wave,
        flex=math.radians(preset.flex) * trunk,
        pitch=math.radians(preset.pitch) * trunk,
    )


def speed_ladder(spec: CreatureSpec) -> tuple[tuple[str, float], ...]:
    """The gaits ``--speed`` climbs, slow to fast, each with the Froude number from which
    it is used, fitted to the body: a tetrapod walks, trots (``speed.walk_trot``) and
    gallops (``speed.trot_gallop``, its ``speed.gallop``); a biped that walks or runs
    walks, then runs (``speed.walk_trot``); a hexapod goes from the tetrapod gait to the
    tripod (``speed.walk_trot``); other bodies keep their own gait, scaled by speed."""
    pairs, own, speed = spec.pair_count, spec.gait.preset, spec.speed
    fits = set(gaits_for(pairs))
    if pairs == 2 and {"walk", "trot", speed.gallop} <= fits:
        return (("walk", 0.0), ("trot", speed.walk_trot), (speed.gallop, speed.trot_gallop))
    if pairs == 1 and own in ("walk", "run"):
        return (("walk", 0.0), ("run", speed.walk_trot))
    if pairs == 3 and own in ("tetrapod", "tripod"):
        return (("tetrapod", 0.0), ("tripod", speed.walk_trot))
    return ((own, 0.0),)


def _speed_gaits(spec: CreatureSpec, hip_height: float) -> SpeedGaits:
    """The gaits of :func:`speed_ladder`, resolved for this creature (its own gait as the
    file adjusts it when it is the only one)."""
    ladder = speed_ladder(spec)
    gaits = {}
    for name, _ in ladder:
        own = spec.gait if name == spec.gait.preset and len(ladder) == 1 else GaitSpec(preset=name, wave=spec.gait.wave)
        gaits[name] = resolve_gait(own, spec.foot_names, hip_height, bob=spec.motion.bob,
                                   trunk=trunk_factor(spec, hip_height) if spec.pair_count >= 2 else 0.0)
    return SpeedGaits(ladder=ladder, hysteresis=spec.speed.hysteresis, gaits=gaits)


def key_poses(spec: CreatureSpec, hip_height: float) -> KeyPoses:
    """The key poses: the file's values, the rest from its style (heights scaled by the
    hip height, m); heights only when the poses shape the walk (a style or a height given)."""
    poses = spec.poses
    style = STYLES[poses.style or "normal"]
    heights = None
    if poses.shaped:
        given = (poses.contact_height, poses.down_height, poses.pass_height, poses.up_height)
        defaults = style_heights(style.name, hip_height)
        heights = np.array([defaults[i] if v is None else float(v) for i, v in enumerate(given)])
    pick = lambda value, default: math.radians(default if value is None else value)
    return KeyPoses(heights=heights, foot_angle=pick(poses.foot_angle, style.foot_angle),
                    arm_swing=pick(poses.arm_swing, style.arm_swing), torso_lean=pick(poses.torso_lean, style.torso_lean),
                    swing_knee=None if poses.swing_knee is None else math.radians(poses.swing_knee))


def arm_shape(spec: CreatureSpec) -> ArmShape | None:
    """The arms in SI units, or None."""
    arms = spec.arms
    if arms is None:
        return None
    width = arms.shoulder_width if arms.shoulder_width is not None else spec.body.width
    return ArmShape(upper=arms.upper, fore=arms.fore, hand=arms.hand, radius=arms.radius, shoulder_width=width,
                    position=arms.position, elbow=math.radians(arms.elbow))


def _natural(spec: CreatureSpec) -> bool:
    """Whether the creature's key poses default to the natural walk's heights
    (:mod:`app.kinematics.natural`): the normal style on feet that roll heel to toe."""
    return (spec.poses.style or "normal") == "normal" and spec.poses.shaped and any(
        leg.roll > 0 and leg.ankle_lift < PLANTIGRADE_BELOW for leg in spec.legs)


def _with_natural_heights(spec: CreatureSpec, rig: Rig) -> Rig:
    """The rig with the key-pose heights its file leaves open taken from the natural walk."""
    from .kinematics.natural import natural_heights

    poses = spec.poses
    given = (poses.contact_height, poses.down_height, poses.pass_height, poses.up_height)
    if all(v is not None for v in given):
        return rig
    natural = natural_heights(rig)
    heights = np.array([natural[i] if v is None else float(v) for i, v in enumerate(given)])
    return replace(rig, poses=replace(rig.poses, heights=heights))


def style_key_heights(spec: CreatureSpec, name: str) -> tuple[float, float, float, float]:
    """A style's key-pose heights (m from the rest height) for this creature: the normal
    style of a heel-to-toe walker is its natural walk; the others are fractions of the
    hip height."""
    rig = build_rig(spec)
    if name == "normal" and _natural(replace(spec, poses=replace(spec.poses, style="normal"))):
        from .kinematics.natural import natural_heights

        return tuple(float(h) for h in natural_heights(rig))  # type: ignore[return-value]
    return style_heights(name, rig.hip_height)


def build_rig(spec: CreatureSpec) -> Rig:
    """Derive the rig of a (validated) creature spec."""
    girdles = spec.girdles  # front first
    legs = [leg for leg, _ in girdles for _side in (0, 1)]
    per_leg = lambda attr: np.array([float(getattr(leg, attr)) for leg in legs])
    femur, tibia, meta = per_leg("femur"), per_leg("tibia"), per_leg("metatarsus")
    lift = np.radians(per_leg("ankle_lift"))
    abduction = np.radians(per_leg("abduction"))
    knee_out = np.array([leg.knee == "out" for leg in legs])
    swing_rest = np.where(knee_out, abduction, 0.0)
    l_max, l_rest, l_min = leg_lengths(femur, tibia, meta, lift, per_leg("natural_bend"), swing_rest)
    knee = np.array([{"forward": 1.0, "back": -1.0, "out": 1.0}[leg.knee] for leg in legs])
    half_width = 0.5 * spec.body.width
    hip_offset = np.array([half_width if leg.hip_offset is None else float(leg.hip_offset) for leg in legs])
    rest_height = l_rest * np.cos(abduction)
    # A rolling plantigrade foot stands with its ankle under the hip: the hip's rest height
    # is the leg's span over the ankle (a nearly straight human leg).
    rolls_flat = (per_leg("roll") > 0) & (lift < math.radians(PLANTIGRADE_BELOW))
    bend = np.clip(per_leg("natural_bend"), 0.0, 0.8)
    rest_height = np.where(rolls_flat, (femur + tibia) * (1.0 - bend) + meta * np.sin(lift), rest_height)[0::2]
    body = spec.body
    shape = BodyShape(length=body.length, width=body.width, radius=np.asarray(body.radius, dtype=np.float64),
                      segments=body.segments, neck_length=body.neck_length, neck_angle=math.radians(body.neck_angle),
                      head_length=body.head_length, head_radius=body.head_radius,
                      head_angle=math.radians(body.head_angle), ear_length=body.ear_length,
                      tail_length=body.tail_length, tail_angle=math.radians(body.tail_angle),
                      tail_segments=body.tail_segments, upright=body.posture == "upright",
                      tail_radius=body.tail_radius, mane=body.mane, tail_curl=math.radians(body.tail_curl),
                      wings=body.wings, beak=body.beak, hump=body.hump)
    hip_height = float(rest_height.mean())
    rig = Rig(
        name=spec.name,
        model=spec.source if spec.source.lower().endswith((".glb", ".gltf")) else "",
        leg_names=spec.foot_names,
        femur=femur,
        tibia=tibia,
        metatarsus=meta,
        toe=per_leg("toe"),
        ankle_lift=lift,
        l_max=l_max,
        l_rest=l_rest,
        l_min=l_min,
        knee_sign=knee,
        knee_out=knee_out,
        knee_pole=np.where(knee_out[:, None], OUT_KNEE_POLE, np.stack([knee, np.zeros_like(knee)], axis=-1)),
        swing_rest=swing_rest,
        bone_radius=per_leg("radius"),
        hip_side=np.tile([1.0, -1.0], len(girdles)),
        girdle=np.repeat(np.arange(len(girdles)), 2),
        hip_offset=hip_offset,
        abduction=abduction,
        splay=np.radians(per_leg("splay")),
        # An upright trunk stands on its one girdle: the body's centre on the path is there.
        girdle_position=np.array([0.5 if body.posture == "upright" else p for _, p in girdles]),
        girdle_rest_height=rest_height,
        body=shape,
        gait=resolve_gait(spec.gait, spec.foot_names, hip_height, bob=spec.motion.bob,
                          trunk=trunk_factor(spec, hip_height) if spec.pair_count >= 2 else 0.0),
        motion=SecondaryMotion(yaw=math.radians(spec.motion.yaw), tail_sway=math.radians(spec.motion.tail_sway),
                               bob_phase=spec.motion.bob_phase, pelvis_tilt=math.radians(spec.motion.pelvis_tilt),
                               sway=spec.motion.sway),
        look=spec.look,
        speed=_speed_gaits(spec, hip_height),
        arms=arm_shape(spec),
        poses=key_poses(spec, hip_height),
        overlap=spec.overlap,
        roll=per_leg("roll"),
        heel=per_leg("heel"),
        toes=np.array([int(leg.toes) for leg in legs], dtype=np.int64),
    )
    return _with_natural_heights(spec, rig) if _natural(spec) else rig



def apply_style(spec: CreatureSpec, name: str) -> CreatureSpec:
    """The creature with a walk style's key-pose values written into its ``[poses]`` table
    (heights in metres for its hip height) and ``gait.stride``: a start to edit from.
    Raises SpecError for an unknown style."""
    from .errors import SpecError, did_you_mean

    if name not in STYLES:
        raise SpecError(f"style {name!r}: unknown{did_you_mean(name, STYLES)}; styles are: {', '.join(STYLES)}")
    style = STYLES[name]
    keys = ("contact_height", "down_height", "pass_height", "up_height")
    styled = spec.with_overrides({"poses.style": name, "poses.foot_angle": style.foot_angle,
                                  "poses.arm_swing": style.arm_swing, "poses.torso_lean": style.torso_lean,
                                  "gait.stride": style.stride}, origin=f"style {name}")
    bare = replace(styled, poses=replace(styled.poses, contact_height=None, down_height=None, pass_height=None,
                                         up_height=None))
    heights = style_key_heights(bare, name)
    return styled.with_overrides({f"poses.{k}": round(h, 4) for k, h in zip(keys, heights)}, origin=f"style {name}")
