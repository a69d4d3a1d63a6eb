"""What to draw, as flat instance arrays (numpy only, no OpenGL), vectorised over frames.

The renderer uploads these arrays as instance buffers: one draw call for every capsule
(leg bones, trunk, neck, muzzle, ears, tail) and one for every ellipsoid (skull, eyes,
joint markers). :func:`motion_instances` builds a whole clip in one numpy pass;
:func:`pose_instances` is the same for a single pose.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from functools import lru_cache
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from ..kinematics.body import cross
from ..kinematics.frames import UP
from ..kinematics.motion import Motion, Pose
from ..kinematics.rig import Rig

if TYPE_CHECKING:
    from .bodies import BodyDraw


class Cap:
    """The columns of a capsule row: end points a and b, their radii, the colour."""

    A = slice(0, 3)
    B = slice(3, 6)
    RADII = slice(6, 8)  # radius at a, radius at b
    COLOR = slice(8, 11)
    FLOATS = 11


class Ell:
    """The columns of an ellipsoid row: centre, the three axes, radii along them, colour."""

    CENTRE = slice(0, 3)
    AXES = (slice(3, 6), slice(6, 9), slice(9, 12))  # x, y, z
    RADII = slice(12, 15)
    COLOR = slice(15, 18)
    FLOATS = 18


CAPSULE_FLOATS = Cap.FLOATS
ELLIPSOID_FLOATS = Ell.FLOATS

# Bone radius along the leg as a fraction of the leg's radius at the hip:
# hip, knee, ankle, ball, toe tip.
_LEG_TAPER = np.array([1.15, 0.78, 0.55, 0.5, 0.38])
NOSE_COLOR = np.array([0.03, 0.025, 0.025])  # a mammal's bare nose (drawn on a skinned body, like the eyes)
NOSE_SHAPE = (0.24, 0.17, 0.14)  # of the head's radius: a nose's half width, height and depth
NOSE_GONE = 0.7  # of a long head's measure (_long_head: 0 up to 3.5 head radii long, 1 from 5): no nose from here
NOSE_AT = (-0.06, 0.1)  # of the head's radius: its centre from the head's tip, ahead (-: back) and up
EYE_COLOR = np.array([0.02, 0.02, 0.025])  # the eyes (on a skinned body, not in it: skin_features)
SKULL = (0.9, 0.85, 1.0)  # of the head's radius: the skull's (across, up, along)
JOWL = (0.45, 0.5, 0.8, 1.1, 1.15)  # of it: a long head's jowl, ahead of and below the skull's centre; its radii
# A long head's face below the muzzle, jowl to chin: its centre along the face (of the
# skull-to-nose length) and below its axis (of the head's radius, x how long the head is),
# and its radii across and deep (of the head's radius; deep x how long) and along (of the face)
FACE = (0.52, 0.45, 0.5, 0.75, 0.36)
# Eyes by kind, of the head's radius: their shape (across, up, along), where they look out
# of the skull (ahead, up, apart: a direction from its centre) and how far out of it they
# sit, over the skin's blend (a bird's large eyes bulge from a small head).
EYE_SHAPE = {"animal": (0.2, 0.17, 0.14), "person": (0.2, 0.12, 0.12), "bird": (0.26, 0.25, 0.25)}
EYE_PLACE = {"animal": (0.55, 0.42, 0.5), "person": (0.8, 0.08, 0.36), "bird": (0.3, 0.3, 0.85)}
EYE_OUT = {"animal": 0.1, "person": 0.0, "bird": 0.3}
_UP = UP


@lru_cache(maxsize=256)
def _srgb_to_linear(hex_color: str) -> tuple[float, float, float]:
    r, g, b = (int(hex_color[i:i + 2], 16) / 255.0 for i in (1, 3, 5))
    return r * r, g * g, b * b


def srgb_to_linear(hex_color: str) -> NDArray[np.float64]:
    """``"#rrggbb"`` to the shaders' lighting space (gamma 2.0: the square of the value).

    The shaders convert back with a square root (``to_display`` in lighting.glsl), so an
    unlit colour comes out exactly as written.
    """
    return np.array(_srgb_to_linear(hex_color))


@dataclass(frozen=True)
class SceneInstances:
    """Instance data: capsules (..., N, 11) and ellipsoids (..., M, 18), float32.

    With a leading frame axis for a clip (see :meth:`frame`). Only the first
    ``ellipsoid_casters`` ellipsoids cast shadows (the skull); eyes and joint markers sit
    inside other shapes and are left out of the shadow pass. ``bodies``: skinned bodies
    (:class:`~app.render.bodies.BodyDraw`), drawn with the shapes.
    """

    capsules: NDArray[np.float32]
    ellipsoids: NDArray[np.float32]
    ellipsoid_casters: int = 1
    bodies: tuple[BodyDraw, ...] = ()

    def frame(self, index: int) -> SceneInstances:
        """One frame of a clip's instances."""
        return SceneInstances(self.capsules[index], self.ellipsoids[index], self.ellipsoid_casters,
                              tuple(b.frame(index) for b in self.bodies))

    def __add__(self, other: SceneInstances) -> SceneInstances:
        """Both sets of shapes in one (one frame each); the shadow casters stay first."""
        a, b = self.ellipsoid_casters, other.ellipsoid_casters
        ells = np.concatenate([self.ellipsoids[:a], other.ellipsoids[:b], self.ellipsoids[a:], other.ellipsoids[b:]])
        return SceneInstances(np.concatenate([self.capsules, other.capsules]), ells, a + b,
                              self.bodies + other.bodies)

    def spheres(self, casters_only: bool = False) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Bounding spheres of one frame's shapes: centres (N, 3) and radii (N,) — each
        capsule's two ends with their radii, each ellipsoid's centre with its largest
        radius (``casters_only``: only the ellipsoids that cast shadows)."""
        caps = self.capsules.astype(np.float64)
        ells = self.ellipsoids[:self.ellipsoid_casters] if casters_only else self.ellipsoids
        ells = ells.astype(np.float64)
        body_spheres = [b.spheres() for b in self.bodies]
        centres = np.concatenate([caps[:, Cap.A], caps[:, Cap.B], ells[:, Ell.CENTRE],
                                  *(c for c, _ in body_spheres)]).reshape(-1, 3)
        radii = np.concatenate([caps[:, Cap.RADII].T.ravel(), ells[:, Ell.RADII].max(axis=1),
                                *(r for _, r in body_spheres)])
        return centres, radii

    def box(self) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """World box (lo, hi), each (3,) in metres, around every shape of one frame,
        radii included."""
        centres, radii = self.spheres()
        return (centres - radii[:, None]).min(axis=0), (centres + radii[:, None]).max(axis=0)


def _unit(v: NDArray[np.float64]) -> NDArray[np.float64]:
    return v / np.maximum(np.linalg.norm(v, axis=-1, keepdims=True), 1e-12)


def _frame_axes(z: NDArray[np.float64]) -> tuple[NDArray, NDArray, NDArray]:
    """Orthonormal (x, y, z) frames (..., 3) with z given and y as close to +Y as possible."""
    z = _unit(z)
    x = cross(_UP, z)
    degenerate = np.linalg.norm(x, axis=-1, keepdims=True) < 1e-6
    x = _unit(np.where(degenerate, np.array([1.0, 0.0, 0.0]), x))
    return x, cross(z, x), z


def _capsules(a, b, ra, rb, color) -> NDArray[np.float64]:
    """Capsule rows (..., N, 11) from end points (..., N, 3), radii and colours (broadcast)."""
    shape = np.broadcast_shapes(a.shape, b.shape)[:-1]
    parts = [np.broadcast_to(a, shape + (3,)), np.broadcast_to(b, shape + (3,)),
             np.broadcast_to(np.asarray(ra, dtype=np.float64)[..., None], shape + (1,)),
             np.broadcast_to(np.asarray(rb, dtype=np.float64)[..., None], shape + (1,)),
             np.broadcast_to(color, shape + (3,))]
    return np.concatenate(parts, axis=-1)


def _ellipsoids(centre, axis_z, radii, color) -> NDArray[np.float64]:
    """Ellipsoid rows (..., M, 18) oriented with their z axis along ``axis_z``."""
    x, y, z = _frame_axes(np.broadcast_to(axis_z, centre.shape))
    shape = centre.shape[:-1]
    return np.concatenate([centre, x, y, z, np.broadcast_to(radii, shape + (3,)),
                           np.broadcast_to(color, shape + (3,))], axis=-1)


def side_colors(rig: Rig) -> NDArray[np.float64]:
    """The look's left and right colours (2, 3), linear."""
    return np.stack([srgb_to_linear(rig.look.left_color), srgb_to_linear(rig.look.right_color)])


def leg_colors(rig: Rig) -> NDArray[np.float64]:
    """Each leg's colour (L, 3), linear: the look's left or right colour by its side."""
    return side_colors(rig)[(rig.hip_side < 0).astype(int)]


HOOF_COLOR = np.array([0.23, 0.2, 0.18]) ** 2  # dark horn (linear)
HOOF_FROM = 0.1  # of the toe (pastern and hoof) from the fetlock: where the hoof's horn begins
FETLOCK_UP = 0.8  # of the toe's radius at the fetlock: how far up the cannon the fetlock's (coat) bulge lies
BEAK_COLOR = np.array([0.66, 0.58, 0.47]) ** 2  # a beak's horn, unless the look gives one (linear)
BEAK_SHAPE = (0.5, 0.24)  # of the head's radius: a beak's half width and half depth (broad and flat)
BEAK_INTO = 0.9  # of the head's radius from the skull's centre: where a beak meets the face (a shorter one keeps a muzzle)
HUMP_AT = 0.08  # of the trunk: how far behind the fore legs a hump stands highest
HUMP_SHAPE = (0.75, 0.55, 0.28)  # a hump's radii: of the trunk's radius across and up (plus half its height), of its length along
WING_AT = 0.72  # along the trunk (0 rear, 1 front): where a folded wing's shoulder lies
WING_SHAPE = (0.09, 0.3, 0.5)  # of body.wings: a folded wing's half thickness, half height and half length
WING_DROOP = 0.3  # rad: a folded wing runs back and down from the shoulder
WING_LEAN = 0.35  # rad: its top leans in against the flank
WING_OUT = 0.9  # of the trunk's radius under it: how far out its middle lies (its outer face clears the skin)
SEGMENT_TUBE = 0.6  # of a segmented trunk's radius: the tube under its plates
MEMBRANE_SHADE = 0.45  # of the body's colour: the membranes between a segmented trunk's plates
PLATE_SHAPE = (1.45, 0.72, 0.42)  # a segment's plate: of the trunk's radius across and up, of the gap between pairs along
TOE_SPREAD = 0.42  # rad: a splayed toe's angle from the middle toe
TOE_SHAPES = {  # splayed toes: (angle out from the middle toe in TOE_SPREADs, length, radius: of the middle toe's)
    1: ((0.0, 1.0, 1.0),),
    2: ((-0.15, 1.0, 1.0), (0.85, 0.62, 0.75)),  # an ostrich's: a big inner toe and a small outer one
    3: ((-1.0, 0.8, 0.75), (0.0, 1.0, 0.9), (1.0, 0.8, 0.75)),
    4: ((-1.0, 0.8, 0.75), (0.0, 1.0, 0.9), (1.0, 0.8, 0.75), (None, 0.4, 0.7)),  # and a hind toe (the hallux)
}


@dataclass(frozen=True)
class Palette:
    """A creature's colours where parts differ from its coat (linear RGB, (3,) each): the
    coat, the lower legs and feet, the neck and head, a beak and feathers."""

    coat: NDArray[np.float64]
    legs: NDArray[np.float64]
    neck: NDArray[np.float64]
    beak: NDArray[np.float64]
    plume: NDArray[np.float64]


def palette(rig: Rig) -> Palette:
    """The look's colours (unset ones from the coat; a beak's from horn)."""
    look = rig.look
    coat = srgb_to_linear(look.body_color)

    def given(color: str | None, default: NDArray[np.float64]) -> NDArray[np.float64]:
        return default if color is None else srgb_to_linear(color)

    return Palette(coat=coat, legs=given(look.leg_color, coat), neck=given(look.neck_color, coat),
                   beak=given(look.beak_color, BEAK_COLOR), plume=given(look.plume_color, coat))

ANTENNA_SCAPE = 0.35  # of an arthropod's antenna (ear_length): the first segment, rising before the elbow
SHANK_MUSCLE = 0.6  # of the lower leg from the knee: how far its muscle reaches before the tendons
TORSO_WIDTH, TORSO_DEPTH = 1.2, 0.78  # a person's trunk: of its radius, half its width and half its depth
GLUTE = np.array([0.2, 0.42, 0.22, 0.55, 0.68, 0.5])  # of the pelvis's radius: a buttock's centre from its hip joint
# (inwards, back, down) and its radii (across, up, back)
SHOULDER_LINE = 0.42  # of the chest's radius: the thickness of the line from shoulder to shoulder
THIGH_OUT = 0.2  # of its top radius: how far out of the hip joint a person's thigh begins (the femur's neck)
PERSON_THIGH = 1.6  # of the leg's radius: a person's thigh at its top (the hips ~37 cm across, not a pear)
NECK_SECTIONS = np.array([0.22, 0.48, 0.72])  # along a mammal's neck, base to head: its deep, flattened sections
NECK_TAPER = 1.6  # how fast a neck slims from the chest's depth to the head's (1: evenly)
NECK_WIDTH = 0.6  # of a section's depth: a mammal's neck is deeper than wide
CREST_DROP = 0.3  # of a section's depth beyond the head's radius: how far it hangs below the crest
MANE_SHADE = 0.3  # of the body's colour (linear): a mane's darker hair
MANE_TUFTS = 14  # flattened ellipsoids along the crest, poll to withers, overlapping into one ridge
MANE_RISE = 0.4  # of the neck from the withers: where a mane reaches its full height (it grows from the back) ...
MANE_POLL = 0.3  # ... and from the poll, where it falls to a short tuft between the ears


def hoof_ends(ball: NDArray[np.float64], toe: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Where a hoof's capsule starts and ends (..., 3) each: from just below the fetlock
    (:data:`HOOF_FROM` of the toe) to the toe's tip."""
    return ball + HOOF_FROM * (toe - ball), toe


def skin_features(motion) -> NDArray[np.float64]:
    """The ellipsoid rows (K, 18), in a clip's first frame, of the features that sit on a
    skinned body rather than in its surface: the eyes, a mammal's nose and the mane (the
    body carries them as a second mesh, :attr:`app.skin.SkinnedBody.features`)."""
    rig = motion.rig
    if rig.model:  # a user's model has its own
        return np.zeros((0, ELLIPSOID_FLOATS))
    skull, head_dir = _skull(motion.head[:1], rig)
    eyes = _eyes(skull, head_dir, rig)[0]
    nose = _nose(motion.head[:1, 1], head_dir, rig)[0]
    mane = _mane_rows(motion.neck[:1], motion.spine_radius, rig)[0]
    return np.concatenate([eyes, nose, mane]).astype(np.float64)


def feature_anchors(motion) -> NDArray[np.float64]:
    """For each row of :func:`skin_features`, the point inside the head (K, 3) that a
    feature is seated out from onto the skin (the skull's centre, for the eyes: the skin
    blended over skull, jowl and neck lies outside the skull, and buried them), NaN for
    the features that stay where they are (the nose, the mane)."""
    rows = skin_features(motion)
    anchors = np.full((len(rows), 3), np.nan)
    if len(rows):
        skull, _ = _skull(motion.head[:1], motion.rig)
        eyes = np.all(np.abs(rows[:, Ell.COLOR] - EYE_COLOR) < 1e-6, axis=1)
        anchors[eyes] = skull[0]
    return anchors


def skin_overlays(motion) -> NDArray[np.float64]:
    """The centres (K, 3) of :func:`skin_features`."""
    return skin_features(motion)[:, Ell.CENTRE]


def trunk_parts(motion) -> NDArray[np.float64]:
    """The centres (K, 3), in a clip's first frame, of the ellipsoids that lie on the trunk
    but maybe nearer a hip than the spine (a bird's folded wings, a hump over the
    shoulders, a centipede's plates, a person's buttocks): a skinned body binds them to the
    spine, not the leg they would swing with."""
    wings = np.concatenate([_wings(motion.spine[:1], motion.spine_tangent[:1], motion.spine_radius, motion.rig,
                                   np.zeros(3))[0, :, 0:3],
                            _hump(motion.spine[:1], motion.spine_tangent[:1], motion.spine_radius, motion.rig,
                                  np.zeros(3))[0, :, 0:3]])
    if _segmented(motion.rig):  # a centipede's plates: few segments bound them to the hips
        wings = np.concatenate([wings, _segment_plates(motion.spine[:1], motion.spine_tangent[:1], motion.spine_radius,
                                                       motion.rig, np.zeros(3))[0, :, 0:3]])
    if not (motion.rig.body.upright and motion.arms is not None and motion.joints.shape[1] >= 2):
        return wings
    glutes = _glutes(motion.joints[:1, 0:2, 0], motion.spine_tangent[:1, 0], float(motion.spine_radius[0]),
                     np.zeros(3))[0, :, 0:3]
    return np.concatenate([wings, glutes])


def mane_color(rig: Rig) -> NDArray[np.float64]:
    """A mane's colour (3,), linear: the body's, darker."""
    return MANE_SHADE * srgb_to_linear(rig.look.body_color)


def _neck_top(s: NDArray[np.float64], capsule: tuple[float, float], chest: float, head_radius: float
              ) -> NDArray[np.float64]:
    """How far above its axis a mammal's neck's crest runs (m) at fractions ``s`` of it from
    the base: the neck capsule's radius or a deep section's top, whichever is higher."""
    depth = _neck_depth(s, chest, head_radius)
    return np.maximum(capsule[0] + (capsule[1] - capsule[0]) * s, depth - CREST_DROP * (depth - head_radius))


def _neck_depth(s: NDArray[np.float64], chest: float, head_radius: float) -> NDArray[np.float64]:
    """A mammal's neck's half depth (m) at fractions ``s`` of it from the base: the chest's
    radius there, the head's at the throat, slimming fast out of the breast."""
    return head_radius + (chest - head_radius) * (1.0 - s) ** NECK_TAPER


def _deep_neck(neck: NDArray[np.float64], chest: float, head_radius: float, color: NDArray[np.float64]
               ) -> NDArray[np.float64]:
    """A mammal's neck, deeper than wide (a round tube read as a hose into the chest):
    flattened ellipsoids (T, 3, 18) at :data:`NECK_SECTIONS` of the neck (T, 2, 3), as deep
    as the chest (radius ``chest``, m) at the base and as the head at the throat,
    :data:`NECK_WIDTH` as wide, their extra depth hanging below the crest (the throat and
    the breast)."""
    base, top = neck[:, :1], neck[:, -1:]
    axis = top - base
    length = np.linalg.norm(axis, axis=-1, keepdims=True)
    s = NECK_SECTIONS[None, :, None]
    depth = _neck_depth(s, chest, head_radius)
    _, y, _ = _frame_axes(np.broadcast_to(axis, (axis.shape[0], s.shape[1], 3)))
    centre = base + s * axis - y * CREST_DROP * (depth - head_radius)
    shape = (axis.shape[0], s.shape[1], 1)
    radii = np.concatenate([np.broadcast_to(NECK_WIDTH * depth, shape), np.broadcast_to(depth, shape),
                            np.broadcast_to(0.34 * length, shape)], axis=-1)
    return _ellipsoids(centre, axis, radii, color)


def _neck_radii(rig: Rig, spine_radius: NDArray[np.float64]) -> tuple[float, float]:
    """The neck capsule's radii (m) at its base and at the head: a person's slim neck, an
    animal's deep one rising from the chest, narrower at the throat under a long head's
    jowl."""
    head_radius = rig.body.head_radius
    if rig.body.upright:
        return 0.45 * head_radius, 0.4 * head_radius
    if _eye_kind(rig) == "bird":  # a bird's slender neck under a rounder head
        return 0.68 * float(spine_radius[-1]), 0.6 * head_radius
    return 0.68 * float(spine_radius[-1]), (0.85 - 0.25 * _long_head(rig)) * head_radius


def _long_head(rig: Rig) -> float:
    """How far a head is a long one (0 to 1: over 3.5 to 5 head radii long, a horse's)."""
    return float(np.clip((rig.body.head_length / max(rig.body.head_radius, 1e-9) - 3.5) / 1.5, 0.0, 1.0))


def _mammal_neck(rig: Rig) -> bool:
    """Whether the neck is a mammal's: deeper than wide, maybe maned (four or more
    upright-kneed legs, a horizontal trunk and a neck)."""
    return rig.four_legged_mammal and rig.body.neck_length > 0


def _mane_rows(neck: NDArray[np.float64], spine_radius: NDArray[np.float64], rig: Rig) -> NDArray[np.float64]:
    """The mane's ellipsoid rows (T, K, 18); none (K = 0) without ``body.mane``."""
    if not (_mammal_neck(rig) and rig.body.mane > 0):
        return np.zeros((neck.shape[0], 0, ELLIPSOID_FLOATS))
    return _mane(neck, _neck_radii(rig, spine_radius), float(spine_radius[-1]), rig.body.head_radius,
                 rig.body.mane, mane_color(rig))


def _mane(neck: NDArray[np.float64], capsule: tuple[float, float], chest: float, head_radius: float,
          height: float, color: NDArray[np.float64]) -> NDArray[np.float64]:
    """A mane (T, MANE_TUFTS, 18): flattened ellipsoids standing ``height`` m above the neck's
    crest from the poll back to the withers, thin across."""
    base, top = neck[:, :1], neck[:, -1:]
    axis = top - base
    length = np.linalg.norm(axis, axis=-1, keepdims=True)
    s = np.linspace(0.08, 0.97, MANE_TUFTS)
    _, y, _ = _frame_axes(np.broadcast_to(axis, (axis.shape[0], MANE_TUFTS, 3)))
    crest = _neck_top(s, capsule, chest, head_radius)[None, :, None]
    rise = np.clip(np.minimum((s - s[0]) / MANE_RISE, 0.2 + (s[-1] - s) / MANE_POLL), 0.0, 1.0)
    tall = (height * rise * rise * (3.0 - 2.0 * rise))[None, :, None]  # (1, K, 1): low over the withers and the poll
    # Each tuft from 0.45 of the height under the crest (inside the neck) to 0.65 of its own
    # height above it.
    reach, root = 0.65 * tall, 0.45 * height
    centre = base + s[None, :, None] * axis + y * (crest + 0.5 * (reach - root))
    spacing = np.broadcast_to(length / (MANE_TUFTS - 1), centre.shape[:-1] + (1,))
    radii = np.concatenate([np.broadcast_to(0.15 * height + 0.01, spacing.shape),
                            np.broadcast_to(0.5 * (reach + root), spacing.shape), 1.6 * spacing], axis=-1)
    return _ellipsoids(centre, axis, radii, color)


def _leg_volume(joints: NDArray[np.float64], radii: NDArray[np.float64], rig: Rig,
                leg_color: NDArray[np.float64], foot_color: NDArray[np.float64],
                shin_color: NDArray[np.float64]) -> tuple[list, list]:
    """Muscle and feet for mammal legs (not sprawled insect or spider legs): a thigh or
    upper arm thick at the top and tapering down the femur, in ``leg_color`` (L, 3); the
    lower leg's muscle in ``shin_color`` (L, 3); feet in ``foot_color`` (L, 3) by leg type, a flat sole (plantigrade), a round paw
    (digitigrade) or a dark hoof with a fetlock (unguligrade), or splayed toes
    (``legs.NAME.toes``). Returns capsule and ellipsoid row arrays (T, K, 11 / 18)."""
    from ..choices import leg_type

    legs = np.nonzero(~rig.knee_out)[0]
    if not len(legs):
        return [], []
    j = joints[:, legs]  # (T, M, 5, 3)
    r = radii[legs]  # (M, 5)
    color = leg_color[legs]
    hind = rig.girdle[legs] == rig.girdle.max()
    hip, knee, ball, toe = j[:, :, 0], j[:, :, 1], j[:, :, 3], j[:, :, 4]
    heels = _heels(rig, joints)[:, legs]
    # Thigh (hind) or upper arm (fore): from just above the hip to past the femur's middle.
    # (It starts a little down the bone, so it never shows above the back.)
    top = np.where(hind, PERSON_THIGH if rig.body.upright else 1.85, 1.55) * r[:, 0]
    upper = hip + 0.12 * (knee - hip)
    if rig.body.upright:  # a person's thigh: its flesh lies out over the femur's neck, the hip joint inside it
        partner = joints[:, legs ^ 1, 0]  # the other hip of each pair (legs are stored left, right)
        out = hip - partner
        out = out / np.maximum(np.linalg.norm(out, axis=-1, keepdims=True), 1e-9)
        upper = upper + THIGH_OUT * top[None, :, None] * out
    muscle = _capsules(upper, hip + 0.6 * (knee - hip), top, 1.1 * r[:, 0], color)
    # Forearm or gaskin (a person's calf): the lower leg's muscle, thick below the knee and
    # tapering into the tendons above the ankle (the bare bone was a stick).
    ankle = j[:, :, 2]
    shank = _capsules(knee + 0.08 * (ankle - knee), knee + SHANK_MUSCLE * (ankle - knee), 1.35 * r[:, 1],
                      r[:, 1], shin_color[legs])
    toes = np.zeros(len(legs), dtype=np.int64) if rig.toes is None else rig.toes[legs]
    kinds = ["toes" if n > 0 else leg_type(float(np.degrees(a))) for a, n in zip(rig.ankle_lift[legs], toes)]
    capsules, ellipsoids = [muscle, shank], []
    feet = foot_color[legs]
    for count in np.unique(toes[toes > 0]):
        pick = toes == count
        capsules.append(_splayed_toes(ball[:, pick], toe[:, pick], r[pick, 3], r[pick, 4], rig.hip_side[legs][pick],
                                      int(count), feet[pick]))
    for kind in ("plantigrade", "digitigrade", "unguligrade"):
        pick = np.array([k == kind for k in kinds])
        if not pick.any():
            continue
        b, t, rb, c = ball[:, pick], toe[:, pick], r[pick], feet[pick]
        if kind == "plantigrade":  # a flat sole from heel to toes
            heel = heels[:, pick]
            length = np.linalg.norm(t - heel, axis=-1, keepdims=True)
            radii_e = np.concatenate([np.broadcast_to(1.35 * rb[:, 2:3], length.shape),
                                      np.broadcast_to(0.6 * rb[:, 2:3], length.shape),
                                      0.5 * length + 0.3 * rb[:, 2:3]], axis=-1)
            ellipsoids.append(_ellipsoids(0.5 * (heel + t), t - heel, radii_e, c))
        elif kind == "digitigrade":  # a round paw over the toes
            length = np.linalg.norm(t - b, axis=-1, keepdims=True)
            radii_e = np.concatenate([np.broadcast_to(1.45 * rb[:, 3:4], length.shape),
                                      np.broadcast_to(0.95 * rb[:, 3:4], length.shape),
                                      0.55 * length + 0.7 * rb[:, 3:4]], axis=-1)
            ellipsoids.append(_ellipsoids(0.55 * t + 0.45 * b, t - b, radii_e, c))
        else:  # a hoof below the fetlock
            capsules.append(_capsules(*hoof_ends(b, t), 1.25 * rb[:, 3], 1.45 * rb[:, 3], HOOF_COLOR))
            radii_e = np.broadcast_to(1.3 * rb[:, 3:4], b.shape)
            up = _unit(ankle[:, pick] - b)  # the fetlock's hair sits above the joint, the horn below it
            ellipsoids.append(_ellipsoids(b + FETLOCK_UP * rb[:, 3:4] * up, t - b, radii_e, c))
    return capsules, ellipsoids


def _splayed_toes(ball: NDArray[np.float64], tip: NDArray[np.float64], ball_radius: NDArray[np.float64],
                  tip_radius: NDArray[np.float64], side: NDArray[np.float64], count: int,
                  color: NDArray[np.float64]) -> NDArray[np.float64]:
    """A bird's or theropod's toes (T, M * count, 11) from each ball (T, M, 3): the middle
    toe along the foot's own toe bone (to ``tip``), the others turned out from it about the
    vertical by :data:`TOE_SPREAD` (+ towards the leg's ``side`` (M,): +1 left), shorter,
    and a hind toe back along the ground (:data:`TOE_SHAPES`)."""
    d = tip - ball
    level = d * np.array([1.0, 0.0, 1.0])
    along = np.linalg.norm(level, axis=-1, keepdims=True)
    out = _unit(cross(_UP, d)) * along * side[None, :, None]  # horizontal, as long as the toe's level part
    toes = []
    for turn, length, thick in TOE_SHAPES[count]:
        if turn is None:  # the hind toe: back along the ground, from the ball
            end = ball - length * level
        else:
            angle = turn * TOE_SPREAD
            end = ball + length * (np.cos(angle) * d + np.sin(angle) * out)
        toes.append(_capsules(ball, end, thick * ball_radius, thick * tip_radius, color))
    return np.concatenate(toes, axis=1)


def _heels(rig: Rig, joints: NDArray[np.float64]) -> NDArray[np.float64]:
    """Where each foot's heel (T, L, 3) reaches behind its ankle (``legs.NAME.heel``, the
    plantigrade calcaneus), the ankle itself where it has none; the foot's plane is its
    horizontal direction (ankle to toe tip) and the vertical. joints (T, L, 5, 3)."""
    from ..kinematics.roll import heel_points

    ankle = joints[..., 2, :]
    if rig.heel is None or not np.any(rig.heel > 0):
        return ankle
    forward = joints[..., 4, :] - ankle
    forward[..., 1] = 0.0
    forward /= np.maximum(np.linalg.norm(forward, axis=-1, keepdims=True), 1e-12)
    heel = heel_points(replace(rig, roll=np.ones(rig.leg_count)), joints, forward, UP)
    return np.where((rig.heel > 0)[None, :, None], heel, ankle)


_ARM_TAPER = np.array([1.0, 0.72, 0.5, 0.42])  # shoulder, elbow, wrist, hand tip (of the arm's radius)


def _arm_shapes(arms: NDArray[np.float64], rig: Rig, colors: NDArray[np.float64]) -> tuple[list, list]:
    """Arms (T, A, 4, 3) as tapered capsules with a shoulder muscle and a hand, in each
    side's colour (A, 3)."""
    if arms.shape[1] == 0 or rig.arms is None:
        return [], []
    radius = rig.arms.radius * _ARM_TAPER
    color = colors[:, None, :]
    bones = _capsules(arms[:, :, :-1], arms[:, :, 1:], radius[:-1], radius[1:], color)
    bones = bones.reshape(arms.shape[0], -1, CAPSULE_FLOATS)
    shoulder, elbow, wrist, tip = (arms[:, :, k] for k in range(4))
    muscle = _capsules(shoulder, shoulder + 0.45 * (elbow - shoulder), 1.35 * radius[0], 1.05 * radius[0], colors)
    hand_len = np.linalg.norm(tip - wrist, axis=-1, keepdims=True)
    hand_r = np.concatenate([np.broadcast_to(0.55 * radius[2:3] * 2.0, hand_len.shape),
                             np.broadcast_to(0.45 * radius[2:3] * 2.0, hand_len.shape), 0.45 * hand_len], axis=-1)
    hand = _ellipsoids(0.45 * wrist + 0.55 * tip, tip - wrist, hand_r, colors)
    return [bones, muscle], [hand]


def _skull(head: NDArray[np.float64], rig: Rig) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The skull's centre (T, 3) and the head's direction (T, 3)."""
    head_radius = rig.body.head_radius
    skull_back, nose = head[:, 0], head[:, 1]  # (T, 3)
    head_len = np.linalg.norm(nose - skull_back, axis=-1, keepdims=True)
    head_dir = _unit(nose - skull_back)
    skull = skull_back + head_dir * np.minimum(0.5 * head_radius, 0.3 * head_len)
    if rig.body.upright:
        skull = skull + _UP * 0.75 * head_radius
    return skull, head_dir


def _nose(tip: NDArray[np.float64], head_dir: NDArray[np.float64], rig: Rig) -> NDArray[np.float64]:
    """A four-legged mammal's nose (T, 1, 18): a dark, flattened ellipsoid over the end of
    its muzzle (the head's tip ``tip`` (T, 3)), wider than tall, a little above its axis
    (a dog's, a bear's, smaller on a deer's longer head; a horse's long head is a soft
    muzzle with no bare nose: the nose shrinks away as the head lengthens, so a head's
    length slider never makes it vanish at once); none (T, 0, 18) for other creatures."""
    size = 1.0 - _long_head(rig) / NOSE_GONE
    if not (rig.four_legged_mammal and rig.body.beak <= 0 and size > 0):
        return np.zeros((tip.shape[0], 0, ELLIPSOID_FLOATS))
    hr = rig.body.head_radius
    _, up, _ = _frame_axes(head_dir)
    ahead, above = NOSE_AT
    centre = tip + head_dir * ahead * hr + up * above * hr
    return _ellipsoids(centre[:, None], head_dir[:, None], np.array(NOSE_SHAPE) * hr * size, NOSE_COLOR)


def _eye_kind(rig: Rig) -> str:
    """Whose eyes a creature has: a person's (upright), a bird's (a beak) or an animal's."""
    return "person" if rig.body.upright else "bird" if rig.body.beak > 0 else "animal"


def _eyes(skull: NDArray[np.float64], head_dir: NDArray[np.float64], rig: Rig) -> NDArray[np.float64]:
    """The two eyes (T, 2, 18) on the skull, looking along the head."""
    head_radius = rig.body.head_radius
    hx, hy, _ = _frame_axes(head_dir)
    sides = np.array([1.0, -1.0])[None, :, None]  # left, right
    kind = _eye_kind(rig)
    # A person's eyes look out of the face at mid-height; an animal's sit high on the
    # skull, a bird's on its sides.
    ahead, up, apart = EYE_PLACE[kind]
    if kind != "person":  # on the skull's surface, half out (further in, the skin's blend buried them)
        scale = 1.0 / np.sqrt((apart / SKULL[0]) ** 2 + (up / SKULL[1]) ** 2 + (ahead / SKULL[2]) ** 2) \
            + EYE_OUT[kind] / np.sqrt(apart ** 2 + up ** 2 + ahead ** 2)
        ahead, up, apart = ahead * scale, up * scale, apart * scale
    centres = (skull + head_dir * ahead * head_radius + hy * up * head_radius)[:, None] \
        + sides * hx[:, None] * apart * head_radius
    shape = centres.shape[:-1]
    # Wider than tall, turned with the head: a few pixels across read as eyes, where a
    # small sphere read as a dark "x" once antialiased.
    axes = np.concatenate([np.broadcast_to(a[:, None], shape + (3,)) for a in (hx, hy, head_dir)], axis=-1)
    radii = np.array(EYE_SHAPE[kind]) * head_radius
    return np.concatenate([centres, axes, np.broadcast_to(radii, shape + (3,)), np.broadcast_to(EYE_COLOR, shape + (3,))],
                          axis=-1)


def _segmented(rig: Rig) -> bool:
    """Whether the trunk is a row of segments, one a leg pair (a centipede's: more sprawled
    leg pairs than a spider's four)."""
    return bool(rig.knee_out.all()) and rig.leg_count > 8


def _on_spine(spine: NDArray[np.float64], tangent: NDArray[np.float64], radius: NDArray[np.float64],
              position: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """Where the trunk (its points (T, S, 3), tangents, radii (S,), rear to front) is at
    ``position`` (K,) along it (0 rear, 1 front): points (T, K, 3), unit tangents (T, K, 3)
    and radii (K,), interpolated."""
    count = spine.shape[1]
    at = np.clip(np.asarray(position, dtype=np.float64), 0.0, 1.0) * (count - 1)
    k = np.clip(np.floor(at).astype(int), 0, count - 2)
    w = (at - k)[None, :, None]
    point = (1.0 - w) * spine[:, k] + w * spine[:, k + 1]
    ahead = _unit((1.0 - w) * tangent[:, k] + w * tangent[:, k + 1])
    return point, ahead, np.interp(at, np.arange(count), radius)


def _hump(spine: NDArray[np.float64], tangent: NDArray[np.float64], radius: NDArray[np.float64], rig: Rig,
          color: NDArray[np.float64]) -> NDArray[np.float64]:
    """A hump over the shoulders (T, 1, 18): an ellipsoid over the spine just behind the
    fore legs (:data:`HUMP_AT` of the trunk behind them) whose top stands ``body.hump`` m
    above the back (a grizzly's muscle, a bison's); none (T, 0, 18) without one."""
    height = rig.body.hump
    if height <= 0 or rig.body.upright:
        return np.zeros((spine.shape[0], 0, ELLIPSOID_FLOATS))
    fore = float(rig.girdle_position.max()) - HUMP_AT
    point, ahead, under = _on_spine(spine, tangent, radius, np.array([fore]))
    _, up, _ = _frame_axes(ahead)
    across, tall, along = HUMP_SHAPE
    r = float(under[0])
    radii = np.array([across * r, tall * r + 0.5 * height, along * rig.body.length])
    centre = point + up * (r + height - radii[1])  # its top the hump's height over the back
    return _ellipsoids(centre, ahead, radii, color)


def _segment_plates(spine: NDArray[np.float64], tangent: NDArray[np.float64], radius: NDArray[np.float64], rig: Rig,
                    color: NDArray[np.float64]) -> NDArray[np.float64]:
    """A segmented trunk's plates (T, G, 18): one flattened ellipsoid a leg pair, centred on
    the spine (T, S, 3) at the pair's place along it, :data:`PLATE_SHAPE` of the trunk's
    radius there (``radius`` (S,)) across and up and of the gap to the next pair along."""
    centre, ahead, r = _on_spine(spine, tangent, radius, rig.girdle_position)  # (T, G, 3), (T, G, 3), (G,)
    gap = rig.body.length * np.abs(np.gradient(rig.girdle_position))  # (a segmented trunk has many pairs)
    radii = np.stack([PLATE_SHAPE[0] * r, PLATE_SHAPE[1] * r, PLATE_SHAPE[2] * gap], axis=-1)  # (G, 3)
    return _ellipsoids(centre, ahead, radii, color)


def _beak(nose: NDArray[np.float64], head_dir: NDArray[np.float64], rig: Rig, color: NDArray[np.float64]
          ) -> NDArray[np.float64]:
    """A bird's beak (T, 1, 18): broad, flat and round-tipped, ``body.beak`` long back from
    the head's tip ``nose`` (T, 3) (a muzzle bridges a short one to the skull); none
    (T, 0, 18) without one."""
    length = rig.body.beak
    if length <= 0:
        return np.zeros((nose.shape[0], 0, ELLIPSOID_FLOATS))
    radii = np.array([BEAK_SHAPE[0] * rig.body.head_radius, BEAK_SHAPE[1] * rig.body.head_radius, 0.5 * length])
    return _ellipsoids((nose - 0.5 * length * head_dir)[:, None], head_dir[:, None], radii, color)


def _wings(spine: NDArray[np.float64], tangent: NDArray[np.float64], radius: NDArray[np.float64], rig: Rig,
           color: NDArray[np.float64]) -> NDArray[np.float64]:
    """A bird's folded wings (T, 2, 18), left then right: flat ellipsoids ``body.wings``
    long lying back and down along the flanks from the shoulders (:data:`WING_AT` of the
    trunk (T, S, 3) from its rear), their tops leaning in against it; none (T, 0, 18)
    without wings."""
    length = rig.body.wings
    if length <= 0:
        return np.zeros((spine.shape[0], 0, ELLIPSOID_FLOATS))
    shoulder, forward, _ = (a[:, 0] if a.ndim == 3 else a for a in _on_spine(spine, tangent, radius,
                                                                            np.array([WING_AT])))
    side, up, _ = _frame_axes(forward)  # side: the body's left
    back = -np.cos(WING_DROOP) * forward - np.sin(WING_DROOP) * up
    # The trunk's radius under the wing's middle.
    under = float(_on_spine(spine, tangent, radius, np.array([WING_AT - 0.5 * length / max(rig.body.length, 1e-9)]))[2][0])
    half = np.array(WING_SHAPE) * length
    rows = []
    for sign in (1.0, -1.0):  # left, right
        out = sign * side
        across = np.cos(WING_LEAN) * out + np.sin(WING_LEAN) * up  # the wing's thin axis: out, tipped up
        tall = _unit(cross(back, across))
        tall = np.where(np.sum(tall * up, axis=-1, keepdims=True) < 0, -tall, tall)
        across = cross(tall, back)
        centre = shoulder + 0.5 * length * back + out * (WING_OUT * under + half[0]) + 0.15 * under * up
        rows.append(np.concatenate([centre, across, tall, back, np.broadcast_to(half, centre.shape),
                                    np.broadcast_to(color, centre.shape)], axis=-1)[:, None])
    return np.concatenate(rows, axis=1)


def _joint_markers(joints: NDArray[np.float64], radii: NDArray[np.float64],
                   leg_color: NDArray[np.float64]) -> NDArray[np.float64]:
    """Spheres (T, 3 L, 18) at every knee, ankle and ball."""
    frames = joints.shape[0]
    inner = joints[:, :, 1:4].reshape(frames, -1, 3)  # knee, ankle, ball
    joint_r = (radii[:, 1:4] * 1.08).reshape(-1, 1)
    joint_color = np.repeat(0.8 * leg_color + 0.12, 3, axis=0)
    axes = np.broadcast_to(np.eye(3).reshape(1, 1, 9), inner.shape[:2] + (9,))
    return np.concatenate([inner, axes, np.broadcast_to(joint_r, inner.shape[:2] + (3,)),
                           np.broadcast_to(joint_color, inner.shape)], axis=-1)


def _leg_rows(joints: NDArray[np.float64], rig: Rig, show_joints: bool, parts: bool = True,
              by_side: bool = True) -> tuple[list[NDArray[np.float64]], list[NDArray[np.float64]], list[NDArray[np.float64]]]:
    """The legs' shapes from joints (T, L, 5, 3): capsule rows, foot ellipsoid rows and
    joint-marker rows (lists of (T, K, 11 / 18) arrays; only the markers when not ``parts``)."""
    frames = joints.shape[0]
    colors = palette(rig)
    leg_color = leg_colors(rig) if by_side else np.broadcast_to(colors.coat, (rig.leg_count, 3))
    foot_color = leg_color if by_side else np.broadcast_to(colors.legs, (rig.leg_count, 3))
    radii = rig.bone_radius[:, None] * _LEG_TAPER[None, :]  # (L, 5)
    markers = [_joint_markers(joints, radii, leg_color)] if show_joints else []
    if not parts:
        return [], [], markers
    # Four tapered bones each (the lower two, from the ankle down, in the feet's colour),
    # then muscle and feet.
    # A bird's drumstick (the tibiotarsus, knee to ankle) is bare as its shank is (an
    # ostrich's pink-grey legs from the plumage down): only the thigh in the coat's colour.
    shin_color = foot_color if _eye_kind(rig) == "bird" and not by_side else leg_color
    bone_color = np.stack([leg_color, shin_color, foot_color, foot_color], axis=1)  # (L, 4, 3)
    legs = _capsules(joints[:, :, :-1], joints[:, :, 1:], radii[:, :-1], radii[:, 1:],
                     bone_color).reshape(frames, -1, CAPSULE_FLOATS)
    leg_parts, foot_parts = _leg_volume(joints, radii, rig, leg_color, foot_color, shin_color)
    return [legs, *leg_parts], list(foot_parts), markers


def leg_instances(joints: NDArray[np.float64], rig: Rig, show_joints: bool = True, parts: bool = True,
                  by_side: bool = True) -> SceneInstances:
    """Only the legs' shapes of poses with joints (T, L, 5, 3) (what :func:`motion_instances`
    leaves out with ``legs=False``): capsules (T, N, 11), ellipsoids (T, M, 18)."""
    capsules, feet, markers = _leg_rows(joints, rig, show_joints, parts, by_side)
    frames = joints.shape[0]
    caps = np.concatenate(capsules, axis=1) if capsules else np.zeros((frames, 0, CAPSULE_FLOATS))
    ells = np.concatenate(feet + markers, axis=1) if feet or markers else np.zeros((frames, 0, ELLIPSOID_FLOATS))
    return SceneInstances(capsules=caps.astype(np.float32), ellipsoids=ells.astype(np.float32))


def _glutes(hips: NDArray[np.float64], tangent: NDArray[np.float64], radius: float,
            color: NDArray[np.float64]) -> NDArray[np.float64]:
    """A person's buttocks (T, 2, 18), left and right: ellipsoids behind and a little inside
    and below each hip joint (``hips`` (T, 2, 3), left then right), :data:`GLUTE` of the
    pelvis's ``radius`` (m), upright along the trunk's first ``tangent`` (T, 3) (the side
    view's flat back had run straight down into the thighs)."""
    middle = hips.mean(axis=1, keepdims=True)
    inward = _unit(middle - hips)
    across = _unit(hips[:, 0] - hips[:, 1])
    back = _unit(cross(tangent, across))[:, None]  # the trunk's frame: across x up = back
    up = tangent[:, None]
    at, (r_across, r_up, r_back) = GLUTE[:3], GLUTE[3:]
    centre = hips + radius * (at[0] * inward + at[1] * back - at[2] * up)
    x = np.broadcast_to(cross(back, up), centre.shape)  # the hips' line, square to the trunk
    y = np.broadcast_to(back, centre.shape)
    z = np.broadcast_to(up, centre.shape)
    radii = np.broadcast_to(radius * np.array([r_across, r_back, r_up]), centre.shape)
    return np.concatenate([centre, x, y, z, radii, np.broadcast_to(color, centre.shape)], axis=-1)


def _upright_torso(spine: NDArray[np.float64], tangent: NDArray[np.float64], radius: NDArray[np.float64],
                   hips: NDArray[np.float64], left_shoulder: NDArray[np.float64],
                   right_shoulder: NDArray[np.float64], rig: Rig, color: NDArray[np.float64]) -> list:
    """A person's trunk: flattened ellipsoids along the spine (T, S, 3), wider than deep
    (TORSO_WIDTH and TORSO_DEPTH of each segment's radius (S,)), each turned from the hips'
    line (``hips`` (T, 2, 3), the left and right hip joints) to the shoulders' as it rises,
    buttocks behind the hips (:func:`_glutes`), and a shoulder line from shoulder to
    shoulder (T, 3) each; ellipsoid and capsule rows. (A round tube of capsules read as a
    pill, as deep as it was wide, with domed shoulders.)"""
    hips_across = hips[:, 0] - hips[:, 1]
    count = spine.shape[1]
    rise = (np.arange(count) + 0.5) / count
    shoulders_across = left_shoulder - right_shoulder
    across = (1.0 - rise)[None, :, None] * _unit(hips_across)[:, None] + rise[None, :, None] * _unit(shoulders_across)[:, None]
    across = across - np.sum(across * tangent, axis=-1, keepdims=True) * tangent
    x = _unit(across)
    y = cross(tangent, x)
    step = rig.body.length / count
    radii = np.stack([TORSO_WIDTH * radius, TORSO_DEPTH * radius, np.full(count, 0.85 * step + 0.25 * radius)], axis=-1)
    ells = np.concatenate([spine, x, y, tangent, np.broadcast_to(radii, spine.shape),
                           np.broadcast_to(color, spine.shape)], axis=-1)
    line = _capsules(left_shoulder[:, None], right_shoulder[:, None], SHOULDER_LINE * radius[-1],
                     SHOULDER_LINE * radius[-1], color)
    return [ells, _glutes(hips, tangent[:, 0], float(radius[0]), color), line]


def _instances(joints, spine, spine_tangent, spine_radius, neck, head, tail, rig: Rig,
               show_joints: bool, arms: NDArray[np.float64] | None = None,
               ear_lag: NDArray[np.float64] | None = None, parts: bool = True, by_side: bool = True,
               legs: bool = True) -> SceneInstances:
    """The shared body of :func:`motion_instances` / :func:`pose_instances`; every pose
    array has a leading frame axis T. ``parts`` False leaves only the joint markers (a
    skinned body carries its eyes, nose and mane); ``by_side`` colours legs and arms by
    side; ``legs`` False leaves the legs out (see :func:`leg_instances`)."""
    head_radius = rig.body.head_radius
    ear_length = rig.body.ear_length
    frames = joints.shape[0]
    colors = palette(rig)
    body_color, neck_color = colors.coat, colors.neck
    arm_color = side_colors(rig) if by_side else np.broadcast_to(body_color, (2, 3))
    leg_caps, foot_parts, markers = _leg_rows(joints, rig, show_joints, parts, by_side) if legs else ([], [], [])
    if not parts and rig.model:  # the user's model is drawn instead, with its own eyes
        return SceneInstances(capsules=np.zeros((frames, 0, CAPSULE_FLOATS), np.float32),
                              ellipsoids=np.zeros((frames, 0, ELLIPSOID_FLOATS), np.float32), ellipsoid_casters=0)
    if not parts:  # a skinned body is drawn instead, its eyes, nose and mane skinned with it: only the joint markers
        return SceneInstances(capsules=np.zeros((frames, 0, CAPSULE_FLOATS), np.float32),
                              ellipsoids=np.concatenate([np.zeros((frames, 0, ELLIPSOID_FLOATS)), *markers],
                                                        axis=1).astype(np.float32), ellipsoid_casters=0)

    # Trunk: a tube of tapered capsules through the segment centres, capped past both ends.
    r = spine_radius
    trunk_pts = np.concatenate([spine[:, :1] - spine_tangent[:, :1] * 0.35 * r[0], spine,
                                spine[:, -1:] + spine_tangent[:, -1:] * 0.2 * r[-1]], axis=1)
    trunk_r = np.concatenate([r[:1] * 0.8, r, r[-1:] * 0.9])
    segmented = _segmented(rig)
    if segmented:  # a centipede's trunk: plates over a thinner, darker tube (the membranes between them)
        trunk_r = SEGMENT_TUBE * trunk_r
    trunk = _capsules(trunk_pts[:, :-1], trunk_pts[:, 1:], trunk_r[:-1], trunk_r[1:],
                      MEMBRANE_SHADE * body_color if segmented else body_color)
    upright = rig.body.upright  # a human: a slim neck, the skull sitting on it
    torso: list[NDArray[np.float64]] = [_segment_plates(spine, spine_tangent, r, rig, body_color)] if segmented else []
    if upright and arms is not None and arms.shape[1] == 2 and joints.shape[1] >= 2:
        trunk, torso = trunk[:, :0], _upright_torso(spine, spine_tangent, r, joints[:, 0:2, 0],
                                                    arms[:, 0, 0], arms[:, 1, 0], rig, body_color)
    # A deep neck rising from the chest, narrowing to the head.
    neck_r = _neck_radii(rig, r)
    neck_c = _capsules(neck[:, :1], neck[:, 1:], neck_r[0], neck_r[1], neck_color)
    neck_e = _deep_neck(neck, float(r[-1]), head_radius, neck_color) if _mammal_neck(rig) \
        else np.zeros((frames, 0, ELLIPSOID_FLOATS))
    mane = _mane_rows(neck, r, rig)

    # Head: a round skull and a tapering muzzle towards the nose.
    skull, head_dir = _skull(head, rig)
    nose = head[:, 1]
    # Long heads (a horse's: over four skull radii) keep a broad muzzle; short ones taper.
    long_head = _long_head(rig)
    beak = _beak(nose, head_dir, rig, colors.beak)
    # A beak takes the muzzle's place; a muzzle still bridges a short one to the skull (a
    # feathered face), or it floated ahead of the face.
    face = float(np.min(np.sum((nose - skull) * head_dir, axis=-1))) - BEAK_INTO * head_radius
    tip_r = (0.34 + 0.22 * long_head) * head_radius
    end = 0.3 * head_radius
    if beak.shape[1]:  # a bridge as deep as the beak, its round end short of it (it buried a short beak)
        tip_r = BEAK_SHAPE[1] * head_radius
        end = rig.body.beak + 0.5 * tip_r
    muzzle = _capsules(skull[:, None], (nose - head_dir * end)[:, None], (0.62 + 0.1 * long_head) * head_radius,
                       tip_r, neck_color)[:, :0 if beak.shape[1] and rig.body.beak >= face - 1e-6 else 1]
    tail_base = 0.32 * r[0] if rig.body.tail_radius is None else rig.body.tail_radius
    hair = rig.body.mane > 0 and rig.four_legged_mammal  # a maned animal's tail is hair, full to its end
    plumes = rig.body.wings > 0  # a bird's tail is feathers, in a tuft
    tail_r = np.linspace(tail_base, (0.7 if hair else 0.9 if plumes else 0.25) * tail_base, tail.shape[1])
    tail_color = mane_color(rig) if hair else colors.plume if plumes else body_color
    tail_c = _capsules(tail[:, :-1], tail[:, 1:], tail_r[:-1], tail_r[1:], tail_color)
    hx, hy, _ = _frame_axes(head_dir)
    sides = np.array([1.0, -1.0])[None, :, None]  # left, right
    arm_caps, arm_ells = _arm_shapes(np.zeros((frames, 0, 4, 3)) if arms is None else arms, rig, arm_color)
    capsule_parts = [*leg_caps, *arm_caps, trunk, neck_c, muzzle, tail_c]
    lag = np.zeros(frames) if ear_lag is None else np.asarray(ear_lag, dtype=np.float64)
    c, s_ = np.cos(lag)[:, None], np.sin(lag)[:, None]  # turned back (+) or up (-) by the follow-through
    if ear_length > 0 and rig.knee_out.all():  # an arthropod's antennae: elbowed, reaching forward
        base = (skull + head_dir * 0.72 * head_radius + hy * 0.15 * head_radius)[:, None] \
            + sides * hx[:, None] * 0.2 * head_radius  # on the face, inside and below the eyes
        scape = _unit((0.75 * hy + 0.6 * head_dir)[:, None] + sides * hx[:, None] * 0.35)
        elbow = base + ANTENNA_SCAPE * ear_length * scape
        flagellum = _unit((c * (head_dir + 0.15 * hy) + s_ * (hy - 0.3 * head_dir))[:, None] + sides * hx[:, None] * 0.4)
        tip = elbow + (1.0 - ANTENNA_SCAPE) * ear_length * flagellum
        capsule_parts.append(_capsules(base, elbow, 0.14 * head_radius, 0.1 * head_radius, neck_color))
        capsule_parts.append(_capsules(elbow, tip, 0.1 * head_radius, 0.06 * head_radius, neck_color))
    elif ear_length > 0:
        ear_base = (skull - head_dir * 0.2 * head_radius + hy * 0.6 * head_radius)[:, None] \
            + sides * hx[:, None] * 0.55 * head_radius
        ear_dir = c * (hy - head_dir * 0.35) + s_ * (-head_dir - 0.35 * hy)
        ear_tip = ear_base + ear_length * _unit(ear_dir[:, None] + sides * hx[:, None] * 0.25)
        capsule_parts.append(_capsules(ear_base, ear_tip, 0.3 * head_radius, 0.1 * head_radius, neck_color))

    skull_e = _ellipsoids(skull[:, None], head_dir[:, None], np.array(SKULL) * head_radius, neck_color)
    if long_head > 0:  # a long head (a horse's) is deepest at the jowl, below and behind the eyes
        jowl = skull + head_dir * JOWL[0] * head_radius - hy * JOWL[1] * head_radius
        # ... and its jaw runs on from there to the chin (a wedge, not a thin snout off a
        # round skull): the face's lower half, deeper than wide, along the muzzle.
        face_length = np.linalg.norm(nose - skull, axis=-1, keepdims=True)  # (T, 1)
        along, drop, across, deep, reach = FACE
        face = skull + head_dir * along * face_length - hy * drop * long_head * head_radius
        face_radii = np.concatenate([np.full_like(face_length, across * head_radius),
                                     np.full_like(face_length, deep * long_head * head_radius),
                                     reach * face_length], axis=-1)
        skull_e = np.concatenate([skull_e, _ellipsoids(jowl[:, None], head_dir[:, None],
                                                       long_head * np.array(JOWL[2:]) * head_radius, neck_color),
                                  _ellipsoids(face[:, None], head_dir[:, None], face_radii[:, None], neck_color)],
                                 axis=1)
    wings = _wings(spine, spine_tangent, r, rig, colors.plume)
    hump = _hump(spine, spine_tangent, r, rig, body_color)
    ellipsoid_parts = [skull_e, neck_e, mane, _eyes(skull, head_dir, rig), _nose(nose, head_dir, rig), beak, wings,
                       hump, *foot_parts, *arm_ells, *markers]
    capsule_parts += [part for part in torso if part.shape[-1] == CAPSULE_FLOATS]
    ellipsoid_parts += [part for part in torso if part.shape[-1] == ELLIPSOID_FLOATS]
    return SceneInstances(capsules=np.concatenate(capsule_parts, axis=1).astype(np.float32),
                          ellipsoids=np.concatenate(ellipsoid_parts, axis=1).astype(np.float32))


def motion_instances(motion: Motion, show_joints: bool = True, parts: bool = True,
                     by_side: bool = True, legs: bool = True) -> SceneInstances:
    """Instances of every frame of a clip: capsules (T, N, 11), ellipsoids (T, M, 18)
    (``parts``, ``by_side``, ``legs``: see :func:`_instances`)."""
    return _instances(motion.joints, motion.spine, motion.spine_tangent, motion.spine_radius, motion.neck,
                      motion.head, motion.tail, motion.rig, show_joints, motion.arms, motion.ear_lag, parts, by_side,
                      legs)


def pose_instances(pose: Pose, rig: Rig, show_joints: bool = True, parts: bool = True,
                   by_side: bool = True) -> SceneInstances:
    """Instances of one pose: capsules (N, 11), ellipsoids (M, 18)."""
    batch = _instances(pose.joints[None], pose.spine[None], pose.spine_tangent[None], pose.spine_radius,
                       pose.neck[None], pose.head[None], pose.tail[None], rig, show_joints, pose.arms[None],
                       np.array([pose.ear_lag]), parts, by_side)
    return batch.frame(0)


# Each key pose's ghost colour (contact, down, pass, up, next contact), sRGB: the Key poses
# panel's legend uses the same.
KEY_POSE_COLORS: tuple[str, ...] = ("#7fa7e8", "#7fd18b", "#f0c75e", "#e58fd0", "#7fa7e8")


def ghost_instances(pose: Pose, rig: Rig, color: str = "#e8e8f0", strength: float = 0.75) -> SceneInstances:
    """A pose drawn as a ghost: its shapes (no joint markers) tinted ``strength`` of the way
    towards ``color`` (a key pose's, see :data:`KEY_POSE_COLORS`)."""
    tint = srgb_to_linear(color)
    shapes = pose_instances(pose, rig, show_joints=False)
    caps, ells = shapes.capsules.copy(), shapes.ellipsoids.copy()
    caps[:, Cap.COLOR] = caps[:, Cap.COLOR] * (1.0 - strength) + tint * strength
    ells[:, Ell.COLOR] = ells[:, Ell.COLOR] * (1.0 - strength) + tint * strength
    return SceneInstances(caps.astype(np.float32), ells.astype(np.float32), shapes.ellipsoid_casters)


def frame_instances(parts: list[SceneInstances]) -> SceneInstances:
    """One frame's shapes of several creatures (and herds, ghosts, arcs) as one set to
    draw, every part's shadow casters first: what the viewer and recordings both draw."""
    if len(parts) == 1:
        return parts[0]
    casters = [p.ellipsoids[:p.ellipsoid_casters] for p in parts]
    rest = [p.ellipsoids[p.ellipsoid_casters:] for p in parts]
    return SceneInstances(np.concatenate([p.capsules for p in parts]), np.concatenate(casters + rest),
                          sum(p.ellipsoid_casters for p in parts), tuple(b for p in parts for b in p.bodies))


def creature_points(motion: Motion) -> NDArray[np.float64]:
    """Every joint, head, neck and tail point and the trunk's extent, (T, N, 3)."""
    pad = float(np.max(motion.spine_radius))
    head = motion.head
    if motion.rig.body.upright:  # the skull sits on top of the neck: its crown too
        head = np.concatenate([head, head + _UP * 1.8 * motion.rig.body.head_radius], axis=1)
    return np.concatenate([motion.joints.reshape(motion.frame_count, -1, 3), head, motion.neck, motion.tail,
                           motion.arms.reshape(motion.frame_count, -1, 3), motion.spine - pad, motion.spine + pad],
                          axis=1)


def box_corners(lo: NDArray[np.float64], hi: NDArray[np.float64]) -> NDArray[np.float64]:
    """The 8 corners (8, 3) of the box lo..hi."""
    return np.array([[x, y, z] for x in (lo[0], hi[0]) for y in (lo[1], hi[1]) for z in (lo[2], hi[2])])


def motion_bounds(motion: Motion) -> NDArray[np.float64]:
    """Corners (8, 3) of a box enclosing the creature over the whole clip, down to the
    ground, for camera framing."""
    pts = creature_points(motion).reshape(-1, 3)
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    lo[1] = min(lo[1], 0.0) if motion.terrain.flat else lo[1]
    return box_corners(lo, hi)
