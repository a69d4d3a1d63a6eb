"""Skinned bodies in a frame: which body, and where its joints are (no OpenGL).

A :class:`BodyDraw` is one creature's :class:`~app.skin.SkinnedBody` with its joints'
skinning matrices for a frame (or every frame of a clip). :class:`BodyCache` builds each
creature's body once per shape (0.1-0.5 s; the rig's gait, speed or colours aside from
the coat do not rebuild it) and keeps the last few. :func:`pose_body` and
:func:`motion_body` give the draws of a live pose and of a whole clip.
"""

from __future__ import annotations

import hashlib
import pickle
import threading
from collections import OrderedDict
from collections.abc import Sequence
from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import NDArray

from ..kinematics.appendages import Appendages, appendage_turns
from ..kinematics.motion import Motion, Pose
from ..kinematics.rig import KeyPoses, Overlap, Rig, SecondaryMotion
from ..kinematics.skeleton import skeleton_clip
from ..skin import SkinnedBody, build_body
from ..skin.body import Detail, joint_matrices


@dataclass(frozen=True)
class BodyDraw:
    """A body and its skinning matrices: (J, 4, 4) for a frame, (T, J, 4, 4) for a clip;
    ``reach`` (J,) how far (m) the surface lies from each joint (bounds and shadows)."""

    body: SkinnedBody
    skin: NDArray[np.float32]

    def frame(self, index: int) -> BodyDraw:
        return BodyDraw(self.body, self.skin[index]) if self.skin.ndim == 4 else self

    def spheres(self) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Bounding spheres (J, 3), (J,) of a frame's body: each joint where it is now with
        the reach of its vertices."""
        centres = np.einsum("jab,jb->ja", self.skin.astype(np.float64), self.body.bind[:, :, 3])[:, :3]
        return centres, joint_reach(self.body)

    def surface_points(self) -> NDArray[np.float64]:
        """Where a frame's skin is (V, 3), m: its vertices skinned on the CPU (linear blend
        skinning, as skinned.vert does), for what needs the body's outline on screen (FXAA's
        tiles; a joint's bounding sphere reaches as far as its farthest vertex every way)."""
        return self.body.skinned_by(self.skin)

    def placed(self, matrices: NDArray[np.float64]) -> list[BodyDraw]:
        """The frame's body moved by each of ``matrices`` (N, 4, 4) (a herd's animals)."""
        return [BodyDraw(self.body, (m @ self.skin).astype(np.float32)) for m in matrices]


def joint_reach(body: SkinnedBody) -> NDArray[np.float64]:
    """How far (m) each joint's vertices (those it weighs most) lie from it, (J,)."""
    cached = _REACH.get(id(body))
    if cached is not None and cached[0] is body:
        return cached[1]
    centres = body.bind[:, :3, 3]
    main = body.joints[:, 0]
    distance = np.linalg.norm(body.positions - centres[main], axis=1)
    reach = np.zeros(len(centres))
    np.maximum.at(reach, main, distance)
    _REACH[id(body)] = (body, reach)
    return reach


_REACH: dict[int, tuple[SkinnedBody, NDArray[np.float64]]] = {}
_SIZE: dict[int, tuple[SkinnedBody, float]] = {}


def body_size(body: SkinnedBody) -> float:
    """The body's longest extent (m) in its bind pose (kept per body)."""
    cached = _SIZE.get(id(body))
    if cached is None or cached[0] is not body:
        cached = _SIZE[id(body)] = (body, float(np.ptp(body.positions, axis=0).max()))
    return cached[1]


FAR_SIZES = 4.0  # body sizes from the camera beyond which a body is drawn with its far stand-in
SPECK_PIXELS = 120.0  # ... and fewer pixels long than this, with the far stand-in's shadow mesh
SHADOW_TEXELS = (64.0, 40.0)  # a body this many shadow-map texels long or more casts its shadow stand-in,
# else one this long its far body, else the far body's own coarser shadow (a big herd's specks)


def body_levels(draws: Sequence[BodyDraw], eye: NDArray[np.float64], shadow_texel: float,
                pixel: float | None = None, far: float = FAR_SIZES) -> list[tuple[SkinnedBody, SkinnedBody]]:
    """Each draw's levels of detail: the mesh drawn (the body; its ``far`` stand-in when
    its root lies over ``far`` body sizes from the camera at ``eye`` (3,), m; that
    stand-in's own coarser shadow mesh when the body spans fewer than
    :data:`SPECK_PIXELS` pixels of ``pixel`` radians each, None for an orthographic
    view) and the one casting its shadow, chosen by how many shadow-map texels
    (``shadow_texel`` m each) the body spans (:data:`SHADOW_TEXELS`), never finer than
    the mesh drawn.
    Bodies without stand-ins (a user's model, a coarse body) cast and show themselves."""
    if not draws:
        return []
    bodies = [d.body for d in draws]
    first = np.stack([d.skin[0] for d in draws]).astype(np.float64)  # (N, 4, 4): the root joint's skinning
    bind_root = np.stack([b.bind[0, :3, 3] for b in bodies])  # (N, 3)
    roots = first[:, :3, 3] + np.einsum("nij,nj->ni", first[:, :3, :3], bind_root)
    sizes = np.array([body_size(b) for b in bodies])
    distance = np.linalg.norm(roots - eye, axis=1)
    distant = distance > far * sizes
    tiny = np.zeros(len(bodies), dtype=bool) if pixel is None else sizes < SPECK_PIXELS * pixel * distance
    texels = sizes / max(shadow_texel, 1e-9)
    out = []
    for body, away, small, span in zip(bodies, distant, tiny, texels):
        mid = body.far or body.shadow or body
        speck = (body.far.shadow if body.far is not None else None) or mid
        shown = (speck if small else body.far) if away and body.far is not None else body
        fine = (body.shadow or body) if shown is body else shown
        caster = fine if span >= SHADOW_TEXELS[0] else mid if span >= SHADOW_TEXELS[1] else speck
        out.append((shown, caster if shown is body or shown is mid else speck))
    return out


def shape_key(rig: Rig) -> str:
    """A digest of what a rig's body is built from (bones, radii, trunk, head, tail, arms,
    toes, colours), not its gait."""
    parts = (rig.name, rig.body, rig.femur, rig.tibia, rig.metatarsus, rig.toe, rig.bone_radius, rig.ankle_lift,
             rig.hip_offset, rig.girdle_rest_height, rig.girdle_position, rig.arms,
             replace(rig.look, left_color="", right_color=""), rig.toes, rig.heel, rig.leg_names, rig.roll_amount)
    return hashlib.sha1(pickle.dumps(parts)).hexdigest()


class BodyCache:
    """Bodies by shape, the ``capacity`` most recent kept. :meth:`get` builds what it is
    asked for; :meth:`live` (the viewer) never waits for a full body: it gives the coarse
    one at once (built in about a tenth of a second) while the full one is built in a
    background thread, and the full one from the first frame it is ready."""

    def __init__(self, capacity: int = 8) -> None:
        self.capacity = capacity
        self._bodies: OrderedDict[tuple[str, str], SkinnedBody] = OrderedDict()
        self._keys: dict[int, tuple[Rig, str]] = {}  # id(rig) -> its shape key (rigs are immutable)
        self._lock = threading.Lock()
        self._building: set[str] = set()  # shapes whose full body is being built in the background

    def _key(self, rig: Rig) -> str:
        known = self._keys.get(id(rig))
        if known is None or known[0] is not rig:
            if len(self._keys) > 64:
                self._keys.clear()
            known = self._keys[id(rig)] = (rig, shape_key(rig))
        return known[1]

    def _store(self, key: tuple[str, str], body: SkinnedBody) -> None:
        with self._lock:
            self._bodies[key] = body
            self._bodies.move_to_end(key)
            while len(self._bodies) > self.capacity:
                self._bodies.popitem(last=False)

    def _cached(self, key: tuple[str, str]) -> SkinnedBody | None:
        with self._lock:
            body = self._bodies.get(key)
            if body is not None:
                self._bodies.move_to_end(key)
            return body

    def get(self, rig: Rig, detail: Detail = "full") -> SkinnedBody:
        """The body of ``rig``'s shape (built in the bind pose: :func:`bind_rig`)."""
        key = (self._key(rig), detail)
        body = self._cached(key)
        if body is None:
            body = _build(rig, detail)
            self._store(key, body)
        return body

    def live(self, rig: Rig) -> SkinnedBody:
        """The full body if it is ready, else the coarse one (the full one on its way)."""
        shape = self._key(rig)
        full = self._cached((shape, "full"))
        if full is not None:
            return full
        with self._lock:
            start = shape not in self._building
            self._building.add(shape)
        if start:
            def build() -> None:
                try:
                    self._store((shape, "full"), _build(rig, "full"))
                finally:
                    with self._lock:
                        self._building.discard(shape)

            threading.Thread(target=build, name="gaitlab-body", daemon=True).start()
        return self.get(rig, "coarse")


BIND_STRIDE = 1.0  # leg lengths: the bind pose's stride, the legs apart as in a walk


def bind_rig(rig: Rig) -> Rig:
    """The rig in its bind pose, the same whatever gait, key poses, secondary motion or
    overlap it walks with: a walk's alternation (each pair's right foot half a cycle after
    its left, the pairs a quarter cycle apart) on a stride of :data:`BIND_STRIDE`, the
    body carried level (no bob, key-pose heights, sway, turn, lean or lag), so the legs
    stand apart (a smooth union would web legs held together) and the body depends on its
    shape alone, as :func:`shape_key` says."""
    legs = np.arange(rig.leg_count)
    offsets = np.mod(0.25 * (legs // 2) + 0.5 * (legs % 2), 1.0)
    gait = replace(rig.gait, duty_factor=0.75, offsets=offsets, stride=BIND_STRIDE, bob=0.0, flex=0.0, pitch=0.0)
    return replace(rig.with_gait(gait), motion=SecondaryMotion(), overlap=Overlap(), poses=KeyPoses())


def bind_motion(rig: Rig) -> Motion:
    """The one-frame clip a rig's body is built and bound in: :func:`bind_rig` standing in
    place."""
    from ..kinematics.motion import simulate
    from ..kinematics.world import World

    return simulate(bind_rig(rig), 0.0, 30.0, world=World(in_place=True))


def _build(rig: Rig, detail: Detail) -> SkinnedBody:
    """A rig's body, bound standing in place (:func:`bind_motion`: the bind pose)."""
    rest = bind_motion(rig)
    return build_body(rest, skeleton_clip(rest), detail)


_SHARED: BodyCache | None = None


def shared_body_cache() -> BodyCache:
    """The process's body cache (renderers, herds and the viewer share the bodies)."""
    global _SHARED
    if _SHARED is None:
        _SHARED = BodyCache()
    return _SHARED


def pose_motion(pose: Pose, rig: Rig) -> Motion:
    """A pose as a one-frame clip (for its skeleton)."""
    from dataclasses import fields

    values = {f.name: getattr(pose, f.name) for f in fields(Pose)}
    for name in ("ground_offset", "travel", "ear_lag"):
        values[name] = np.array([values[name]])
    from ..kinematics.motion import PER_CLIP_FIELDS

    for name, value in list(values.items()):
        if name not in PER_CLIP_FIELDS and name not in ("ground_offset", "travel", "ear_lag"):
            values[name] = np.asarray(value)[None]
    return Motion(**values, times=np.zeros(1), clock=np.zeros(1), fps=30.0, rig=rig)


def pose_body(pose: Pose, rig: Rig, cache: BodyCache, live: bool = False) -> BodyDraw:
    """The body of a pose (``live``: the viewer's, which never waits for a full body; a
    creature that drives a user's model: that model's mesh)."""
    if rig.model:
        turns = appendage_turns(rig, pose.neck[None], pose.head[None], pose.tail[None], pose.root[None])
        body, skin = model_skin(rig.model, pose.joints[None], pose.root[None], rig.ankle_lift, pose.arms[None], turns)
        return BodyDraw(body, skin[0])
    body = cache.live(rig) if live else cache.get(rig)
    world = joint_matrices(skeleton_clip(pose_motion(pose, rig), body.layout), 0)
    return BodyDraw(body, (world @ body.inverse_bind).astype(np.float32))


def motion_body(motion: Motion, cache: BodyCache) -> BodyDraw:
    """The body through every frame of a clip: skinning matrices (T, J, 4, 4)."""
    if motion.rig.model:
        turns = appendage_turns(motion.rig, motion.neck, motion.head, motion.tail, motion.root)
        return BodyDraw(*model_skin(motion.rig.model, motion.joints, motion.root, motion.rig.ankle_lift,
                                   motion.arms, turns))
    body = cache.get(motion.rig)
    clip = skeleton_clip(motion, body.layout)
    world = np.tile(np.eye(4), clip.world_position.shape[:2] + (1, 1))
    world[..., :3, :3] = clip.world_rotation
    world[..., :3, 3] = clip.world_position
    return BodyDraw(body, (world @ body.inverse_bind).astype(np.float32))


_MODEL_BODIES: dict[int, tuple[object, SkinnedBody]] = {}


def model_skin(path: str, leg_joints: NDArray[np.float64], root: NDArray[np.float64],
               foot_angle: NDArray[np.float64] | None = None, arms: NDArray[np.float64] | None = None,
               turns: Appendages | None = None) -> tuple[SkinnedBody, NDArray[np.float32]]:
    """A user's rigged model (``path``) as a skinned body, and its skinning matrices
    (T, J, 4, 4) for a creature's leg joints (T, L, 5, 3), body transforms (T, 4, 4) and
    flat-foot angles (L,) rad (its rig's ankle lifts), arms (T, A, 4, 3) and neck, head
    and tail turns: its own mesh, weights and colours, its own skeleton moved by the creature."""
    from ..rigged.loaded import load_model

    loaded = load_model(path)
    known = _MODEL_BODIES.get(id(loaded))
    if known is None or known[0] is not loaded:
        model = loaded.model
        body = SkinnedBody(positions=loaded.mesh.astype(np.float32), normals=loaded.normals.astype(np.float32),
                           colors=(model.colors ** 2).astype(np.float32),  # display -> the renderer's linear
                           faces=model.faces.astype(np.int32), joints=model.joints.astype(np.int32),
                           weights=model.weights.astype(np.float32), bind=loaded.bind)
        known = _MODEL_BODIES[id(loaded)] = (loaded, body)
    return known[1], loaded.skin(leg_joints, root, foot_angle, arms, turns)
