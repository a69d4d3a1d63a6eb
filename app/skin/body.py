"""A creature's skinned body: one closed, smooth surface around its parts, bound to its
skeleton with up to four joints a vertex.

The surface is the zero level of the smooth union of the parts' signed distances
(:mod:`app.skin.sdf`) in the clip's first frame (the bind pose), polygonised with
scikit-image's marching cubes on a grid fitted to the creature (parts thinner than two
grid cells are thickened to that) and simplified with fast-simplification's quadric
decimation (kept only when the result is still closed). Each vertex follows the joints of
the parts nearest it, weighted by ``exp(-(d - d_min) / s)`` of its distance to each part
(a soft nearest part: one joint in the middle of a bone, blended across a joint), the
four largest kept and normalised. Each vertex takes the colour of the part it lies on
(the creature's coat, ``look.body_color``, or the look's colour of that part: hooves,
feet, neck, beak, feathers), blended where colours meet; the coat is lighter underneath
by ``look.countershade`` (countershading).
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, field
from functools import cached_property
from typing import Literal

import numpy as np
from numpy.typing import NDArray

from ..kinematics.motion import Motion
from ..kinematics.skeleton import ARM_JOINTS, LEG_JOINTS, SkeletonClip, SkeletonLayout
from .sdf import part_distances, union_on_grid

Detail = Literal["full", "coarse"]
VOXELS = {"full": 1.0e6, "coarse": 9.0e4}  # grid cells in the creature's box (cubic cells)
MAX_CELLS = 400  # along its longest extent, at most
FACES = {"full": 6000, "coarse": 4000}  # simplified to about this many triangles
SHADOW_FACES = 2500  # the full body's stand-in for the (soft, low-resolution) shadow map
FAR_FACES = 400  # ... and for an animal far from the camera (a herd's)
SPECK_FACES = 160  # ... and for its shadow when it is a few shadow-map texels long (a big herd's)
INFLUENCES = 4  # joints per vertex
ROOT_SPREAD = 3.0  # weights this much softer where a leg meets the trunk ...
ROOT_REACH = 4.0  # ... within this many of the leg's thickest part's radii of its hip ...
ROOT_BONE = 1.0  # ... and no farther than the next joint down (a horse's thick thigh: four radii reached past the stifle)
PART_BLEND = 0.5  # of its neighbourhood's mean colour: what a small patch's vertex beside the coat takes ...
SMALL_PATCH = 160  # ... in a patch of one colour of fewer vertices than this (a hoof; a bird's wing or legs blend fully)
LIMB_BLEND = 0.3  # of the blend width: how softly a leg joins another leg, and an arm the body (no webs)


@dataclass(frozen=True)
class SkinnedBody:
    """The mesh in the bind pose (the clip's first frame; world space, metres): positions,
    normals (V, 3), linear RGB colours (V, 3), faces (F, 3); each vertex's joints and
    weights (V, 4) (weights >= 0, summing to 1); ``bind`` (J, 4, 4) each joint's world
    matrix in the bind pose; ``seconds`` the time it took to build."""

    positions: NDArray[np.float32]
    normals: NDArray[np.float32]
    colors: NDArray[np.float32]
    faces: NDArray[np.int32]
    joints: NDArray[np.int32]
    weights: NDArray[np.float32]
    bind: NDArray[np.float64]
    layout: SkeletonLayout | None = None  # the bind skeleton's (pose others alike: skeleton_clip(m, layout))
    detail: Detail = "full"
    shadow: SkinnedBody | None = field(default=None, compare=False)  # a coarser body for the shadow pass
    features: SkinnedBody | None = field(default=None, compare=False)  # its eyes, nose and mane (app.skin.features)
    far: SkinnedBody | None = field(default=None, compare=False)  # a much coarser one, drawn far away
    # (whose own ``shadow`` is coarser still: a shadow a few shadow-map texels long)
    seconds: float = field(default=0.0, compare=False)

    @cached_property
    def inverse_bind(self) -> NDArray[np.float64]:
        """The bind matrices' inverses (J, 4, 4)."""
        return np.asarray(np.linalg.inv(self.bind), dtype=np.float64)

    def skin_matrices(self, clip: SkeletonClip, frame: int) -> NDArray[np.float64]:
        """Each joint's skinning matrix (J, 4, 4) at ``frame``: its world matrix then times
        the inverse of its bind matrix."""
        return joint_matrices(clip, frame) @ self.inverse_bind

    def posed(self, clip: SkeletonClip, frame: int) -> NDArray[np.float64]:
        """The vertices (V, 3) at ``frame`` of ``clip`` by linear blend skinning."""
        return self.skinned_by(self.skin_matrices(clip, frame))

    def skinned_by(self, skin: NDArray) -> NDArray[np.float64]:
        """The vertices (V, 3) moved by skinning matrices ``skin`` (J, 4, 4) (linear blend
        skinning, as shaders/skinned.vert does: each vertex's four joints' top three rows
        blended by its weights, then applied once)."""
        rows = np.asarray(skin)[:, :3, :].reshape(len(skin), 12).astype(np.float64)  # (J, 12)
        blended = (self.weights[:, :, None] * rows[self.joints]).sum(axis=1).reshape(-1, 3, 4)  # (V, 3, 4)
        p = self.positions.astype(np.float64)
        return (blended[:, :, 0] * p[:, 0:1] + blended[:, :, 1] * p[:, 1:2] + blended[:, :, 2] * p[:, 2:3]
                + blended[:, :, 3])


def joint_matrices(clip: SkeletonClip, frame: int) -> NDArray[np.float64]:
    """Each joint's world matrix (J, 4, 4) at ``frame``."""
    count = clip.world_position.shape[1]
    m = np.tile(np.eye(4), (count, 1, 1))
    m[:, :3, :3] = clip.world_rotation[frame]
    m[:, :3, 3] = clip.world_position[frame]
    return m


def bind_joints(starts: NDArray[np.float64], ends: NDArray[np.float64] | None, clip: SkeletonClip) -> NDArray:
    """For each part (its start point (N, 3) and, for capsules, end point): the joint it
    moves with. A capsule belongs to the joint at its start whose bone runs towards its
    end; an ellipsoid to the nearest joint."""
    joints = clip.world_position[0]  # (J, 3)
    near = np.linalg.norm(starts[:, None] - joints[None], axis=-1)  # (N, J)
    if ends is None:
        return np.argmin(near, axis=1)
    y = clip.world_rotation[0, :, :, 1]  # each joint's bone direction
    along = np.einsum("njk,jk->nj", (ends - starts)[:, None, :] / np.maximum(
        np.linalg.norm(ends - starts, axis=1)[:, None, None], 1e-12), y)
    return np.argmin(near - 0.01 * along, axis=1)  # nearest start; ties go to the bone pointing the right way


def _parts(motion: Motion) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """The first frame's capsules (C, 8: a, b, r0, r1) and ellipsoids (E, 15: centre,
    axes, radii), without joint markers, eyes, nose or mane, and each part's colour (C + E, 3;
    linear): the coat, or the look's colour of a part that differs from it (hooves, feet,
    neck, beak, feathers)."""
    from ..render.scene import Cap, Ell, motion_instances, skin_overlays

    frame = motion_instances(motion, show_joints=False, by_side=False).frame(0)
    caps = np.asarray(frame.capsules, np.float64)
    ells = np.asarray(frame.ellipsoids, np.float64)
    on_skin = skin_overlays(motion)  # the eyes, nose and mane sit on the skin (found by where they are)
    if len(ells) and len(on_skin):
        ells = ells[np.min(np.linalg.norm(ells[:, None, Ell.CENTRE] - on_skin[None], axis=-1), axis=1) > 1e-4]
    capsules = np.concatenate([caps[:, Cap.A], caps[:, Cap.B], caps[:, Cap.RADII]], axis=1) if len(caps) \
        else np.zeros((0, 8))
    ellipsoids = np.concatenate([ells[:, Ell.CENTRE], *(ells[:, a] for a in Ell.AXES), ells[:, Ell.RADII]],
                                axis=1) if len(ells) else np.zeros((0, 15))
    colors = np.concatenate([caps[:, Cap.COLOR].reshape(-1, 3), ells[:, Ell.COLOR].reshape(-1, 3)])
    return capsules, ellipsoids, colors


def grid_parts(capsules: NDArray[np.float64], ellipsoids: NDArray[np.float64], detail: Detail
               ) -> tuple[NDArray[np.float64], NDArray[np.float64], float, float, NDArray[np.float64],
                          NDArray[np.float64]]:
    """The grid a body's union is sampled on and what it samples: its corners lo, hi (3,)
    (m, a margin beyond every part), the cell (m: as fine as :data:`VOXELS` allows over the
    creature's box, no coarser than :data:`MAX_CELLS` along it), the blend width (m: 0.12
    of the parts' median radius, at least 1.5 cells) and the parts with every radius at
    least 1.1 cells (thin legs two cells across)."""
    lo = np.minimum(capsules[:, 0:3].min(axis=0) if len(capsules) else np.inf,
                    ellipsoids[:, 0:3].min(axis=0) if len(ellipsoids) else np.inf)
    hi = np.maximum(capsules[:, 3:6].max(axis=0) if len(capsules) else -np.inf,
                    ellipsoids[:, 0:3].max(axis=0) if len(ellipsoids) else -np.inf)
    lo = np.minimum(lo, capsules[:, 3:6].min(axis=0)) if len(capsules) else lo
    hi = np.maximum(hi, capsules[:, 0:3].max(axis=0)) if len(capsules) else hi
    reach = max(float(capsules[:, 6:8].max()) if len(capsules) else 0.0,
                float(ellipsoids[:, 12:15].max()) if len(ellipsoids) else 0.0)
    lo, hi = lo - reach, hi + reach
    box = hi - lo  # cells as fine as the budget allows: a long thin creature's legs stay thin
    cell = max(float(np.cbrt(np.prod(box) / VOXELS[detail])), float(box.max()) / MAX_CELLS)
    radii = np.concatenate([capsules[:, 6:8].ravel(), ellipsoids[:, 12:15].ravel()])
    blend = max(1.5 * cell, 0.12 * float(np.median(radii)))
    capsules = capsules.copy()
    capsules[:, 6:8] = np.maximum(capsules[:, 6:8], 1.1 * cell)  # thin legs: at least two cells across
    ellipsoids = ellipsoids.copy()
    ellipsoids[:, 12:15] = np.maximum(ellipsoids[:, 12:15], 1.1 * cell)
    lo, hi = lo - 3.0 * cell - blend, hi + 3.0 * cell + blend  # a closed surface: the grid's edge is outside
    return lo, hi, cell, blend, capsules, ellipsoids


def _surface(capsules: NDArray[np.float64], ellipsoids: NDArray[np.float64], detail: Detail,
             limbs: tuple[NDArray[np.int64], NDArray[np.int64], NDArray[np.bool_]] | None = None
             ) -> tuple[NDArray[np.float64], NDArray[np.int64], float, Callable[[NDArray[np.float64]], NDArray]]:
    """The union's zero surface: vertices (V, 3), faces (F, 3), the blend width (m) and
    the surface's own normal at any points (N, 3) -> (N, 3) (the field's gradient,
    trilinear between grid nodes: smooth, where a simplified mesh's own normals are as
    faceted as its triangles). ``limbs``: each part's leg and arm (P,) and whether it is
    the tail's, see :func:`app.skin.sdf.union_on_grid`."""
    from skimage.measure import marching_cubes

    lo, hi, cell, blend, capsules, ellipsoids = grid_parts(capsules, ellipsoids, detail)
    axes = tuple(np.arange(lo[k], hi[k] + cell, cell) for k in range(3))
    legs, arms, tail = limbs if limbs is not None else (None, None, None)
    volume = union_on_grid(axes, capsules, ellipsoids, blend, legs, arms, LIMB_BLEND * blend,  # type: ignore[arg-type]
                           tail)
    verts, faces, _normals, _values = marching_cubes(volume, level=0.0, spacing=(cell, cell, cell),
                                                     gradient_direction="ascent")
    gradient = np.stack(list(np.gradient(volume.astype(np.float32))), axis=0)  # (3, X, Y, Z), per cell

    def normal_at(points: NDArray[np.float64]) -> NDArray[np.float64]:
        from scipy.ndimage import map_coordinates

        index = ((points - lo) / cell).T  # (3, N) grid coordinates
        g = np.stack([map_coordinates(gradient[k], index, order=1, mode="nearest") for k in range(3)], axis=1)
        return g / np.maximum(np.linalg.norm(g, axis=1, keepdims=True), 1e-12)  # outwards: the field grows out

    return verts + lo, faces.astype(np.int64), blend, normal_at


def _simplify(verts: NDArray[np.float64], faces: NDArray[np.int64], target: int
              ) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
    """Quadric decimation towards ``target`` triangles, cleaned of the degenerate and
    repeated faces it can leave, kept only if still closed; a decimation that opens the
    surface is tried again gentler (less aggressive collapses), then less deep (up to three
    times the target); failing all, the mesh is kept as it is."""
    import fast_simplification
    import trimesh

    for goal in (target, int(1.25 * target), int(1.6 * target), 2 * target, int(2.5 * target), 3 * target):
        if len(faces) <= goal:
            break
        for aggression in (7.0, 3.0):
            points, tris = fast_simplification.simplify(verts.astype(np.float32), faces.astype(np.int32),
                                                        target_count=goal, agg=aggression)
            mesh = trimesh.Trimesh(points, tris, process=True)
            mesh.update_faces(mesh.nondegenerate_faces())
            mesh.update_faces(mesh.unique_faces())
            mesh.remove_unreferenced_vertices()
            if mesh.is_watertight and mesh.is_winding_consistent:
                return np.asarray(mesh.vertices), np.asarray(mesh.faces, dtype=np.int64)
    return verts, faces


def bound_parts(motion: Motion, clip: SkeletonClip) -> tuple[NDArray[np.float64], NDArray[np.float64],
                                                             NDArray[np.int64], tuple[NDArray, NDArray, NDArray]]:
    """The first frame's parts (:func:`_parts`), the joint each moves with (P,) and their
    limbs (:func:`_limbs`): what the body's surface and weights are built from."""
    capsules, ellipsoids, _ = _parts(motion)
    return _bound(motion, clip, capsules, ellipsoids)


def _bound(motion: Motion, clip: SkeletonClip, capsules: NDArray[np.float64], ellipsoids: NDArray[np.float64]
           ) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.int64], tuple[NDArray, NDArray, NDArray]]:
    """:func:`bound_parts` of parts already gathered; the ellipsoids on the trunk but
    nearer a hip (a bird's wings, :func:`~app.render.scene.trunk_parts`) are bound to the
    trunk's nearest joint (bound to the hip, a wing swung with the thigh)."""
    from ..render.scene import trunk_parts

    ell_joint = bind_joints(ellipsoids[:, 0:3], None, clip)
    on_trunk = trunk_parts(motion)
    if len(ellipsoids) and len(on_trunk):
        pick = np.min(np.linalg.norm(ellipsoids[:, None, 0:3] - on_trunk[None], axis=-1), axis=1) < 1e-4
        trunk = np.flatnonzero(_joint_roles(clip.skeleton.names).trunk)
        near = np.linalg.norm(ellipsoids[pick, None, 0:3] - clip.world_position[0, trunk][None], axis=-1)
        ell_joint[pick] = trunk[np.argmin(near, axis=1)]
    part_joint = np.concatenate([_between_limbs(capsules, bind_joints(capsules[:, 0:3], capsules[:, 3:6], clip), clip),
                                 ell_joint]).astype(np.int64)
    return capsules, ellipsoids, part_joint, _limbs(part_joint, clip, _tail_parts(capsules, ellipsoids, motion.tail[0]))


@dataclass(frozen=True)
class _JointRoles:
    """What each joint (J,) of a skeleton is, from its name (``LF_hip``, ``L1_knee``,
    ``L_shoulder``): ``leg`` and ``arm`` the limb it belongs to (1, 2, ...; 0 none),
    ``below`` the joint under a limb's top joint (its knee or elbow; -1 for other
    joints)."""

    leg: NDArray[np.int64]
    arm: NDArray[np.int64]
    below: NDArray[np.int64]

    @property
    def top(self) -> NDArray[np.bool_]:
        """Each limb's first joint: a hip (fore or hind) or a shoulder."""
        return self.below >= 0

    @property
    def trunk(self) -> NDArray[np.bool_]:
        return (self.leg == 0) & (self.arm == 0)


def _joint_roles(names: tuple[str, ...]) -> _JointRoles:
    sides = [n.split("_", 1) if "_" in n else (n, "") for n in names]
    leg_names = sorted({side for side, part in sides if part in LEG_JOINTS and side[:1] in "LR"})
    leg = np.array([leg_names.index(side) + 1 if part in LEG_JOINTS and side in leg_names else 0
                    for side, part in sides])
    arm = np.array([1 if side == "L" and part in ARM_JOINTS else 2 if side == "R" and part in ARM_JOINTS else 0
                    for side, part in sides])
    index = {name: j for j, name in enumerate(names)}
    below = np.array([index.get(f"{side}_{chain[1]}", -1) if (leg[j] or arm[j]) and part == chain[0] else -1
                      for j, (side, part) in enumerate(sides)
                      for chain in [LEG_JOINTS if leg[j] else ARM_JOINTS]])
    return _JointRoles(leg=leg, arm=arm, below=below)


def _limbs(part_joint: NDArray[np.int64], clip: SkeletonClip, tail_parts: NDArray[np.bool_]
           ) -> tuple[NDArray[np.int64], NDArray[np.int64], NDArray[np.bool_]]:
    """Each part's leg and arm (P,) each: 1, 2, ... for the limb it moves with (a leg's
    joints from the hip to the toe; an arm's from the shoulder to the hand), 0 for the
    trunk, head and tail; and whether it is one of the tail's segments (``tail_parts``
    (P,), :func:`_tail_parts`, among the trunk's)."""
    roles = _joint_roles(clip.skeleton.names)
    legs, arms = roles.leg[part_joint], roles.arm[part_joint]
    return legs, arms, tail_parts & (legs == 0) & (arms == 0)


def _tail_parts(capsules: NDArray[np.float64], ellipsoids: NDArray[np.float64], tail: NDArray[np.float64]
                ) -> NDArray[np.bool_]:
    """Which parts (P,) are the tail's segments: capsules with both ends on the tail's
    points (K + 1, 3) in the bind pose (the trunk's rear cap starts at the tail's base
    and is bound to its first joint, but is the rump's)."""
    def on_tail(points: NDArray[np.float64]) -> NDArray[np.bool_]:
        return np.linalg.norm(points[:, None] - tail[None], axis=-1).min(axis=1) < 1e-6 if len(tail) \
            else np.zeros(len(points), bool)

    segments = on_tail(capsules[:, 0:3]) & on_tail(capsules[:, 3:6])
    return np.concatenate([segments, np.zeros(len(ellipsoids), bool)])


def _between_limbs(capsules: NDArray[np.float64], part_joint: NDArray[np.int64], clip: SkeletonClip
                   ) -> NDArray[np.int64]:
    """``part_joint`` with each capsule that runs from one limb's top joint to another's
    (a person's line from shoulder to shoulder) bound to the trunk joint nearest its
    middle instead: it is the trunk's, and moved with one arm it bent as the arm swung."""
    roles = _joint_roles(clip.skeleton.names)
    points = clip.world_position[0]
    tops, trunk = roles.top, roles.trunk
    if not tops.any() or not trunk.any():
        return part_joint
    out = part_joint.copy()
    top_points = points[tops]
    at_a = np.linalg.norm(capsules[:, None, 0:3] - top_points[None], axis=-1).min(axis=1) < 1e-6
    at_b = np.linalg.norm(capsules[:, None, 3:6] - top_points[None], axis=-1).min(axis=1) < 1e-6
    across = np.flatnonzero(at_a & at_b)
    if len(across):
        middle = 0.5 * (capsules[across, 0:3] + capsules[across, 3:6])
        candidates = np.flatnonzero(trunk)
        nearest = np.linalg.norm(middle[:, None] - points[candidates][None], axis=-1).argmin(axis=1)
        out[across] = candidates[nearest]
    return out


def _weights(verts: NDArray[np.float64], capsules: NDArray[np.float64], ellipsoids: NDArray[np.float64],
             part_joint: NDArray[np.int64], joint_count: int, spread: float,
             roots: NDArray[np.float64] | None = None, root_reach: NDArray[np.float64] | None = None
             ) -> tuple[NDArray[np.int32], NDArray[np.float32]]:
    """Each vertex's four joints and weights (see the module docstring). About the limbs'
    roots (``roots`` (H, 3): hips and shoulders; ``root_reach`` (H,) m) the weights are
    spread ROOT_SPREAD times wider, fading out over the reach: the trunk and the top of
    the leg share the vertices where they meet, which bend there as one (with the narrow
    spread the thigh's vertices swung through the trunk's as a hind leg reached far back
    on stairs, a jagged crease on the rump)."""
    d = part_distances(verts, capsules, ellipsoids)  # (P, V)
    nearest = d.min(axis=0)

    def per_joint(width: NDArray[np.float64] | float) -> NDArray[np.float64]:
        soft = np.exp(-(d - nearest) / width)  # (P, V)
        out = np.zeros((joint_count, len(verts)))
        np.add.at(out, part_joint, soft)
        return out / out.sum(axis=0, keepdims=True)

    shares = per_joint(spread)
    if roots is not None and root_reach is not None and len(roots):
        gap = np.linalg.norm(verts[:, None, :] - roots[None, :, :], axis=-1) / np.maximum(root_reach, 1e-9)  # (V, H)
        near_root = np.clip(1.0 - gap.min(axis=1), 0.0, 1.0) ** 2  # 1 at a root, 0 beyond its reach (V,)
        if near_root.any():
            shares = shares * (1.0 - near_root) + per_joint(ROOT_SPREAD * spread) * near_root
    order = np.argsort(-shares, axis=0)[:INFLUENCES]  # (4, V)
    top = np.take_along_axis(shares, order, axis=0)
    top /= top.sum(axis=0, keepdims=True)
    return order.T.astype(np.int32), top.T.astype(np.float32)


def _limb_roots(capsules: NDArray[np.float64], part_joint: NDArray[np.int64], clip: SkeletonClip
                ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Where each limb meets the trunk: its hip (a leg's, fore or hind) or a person's
    shoulder joint in the bind pose (H, 3), and how far about it the weights are shared
    (H,): ROOT_REACH times the thickest part that moves with that joint, at most
    ROOT_BONE of the bone below it (a horse's thigh muscle is so thick that four of its
    radii reached past the stifle)."""
    roles = _joint_roles(clip.skeleton.names)
    points = clip.world_position[0]
    radius = np.zeros(len(points))
    np.maximum.at(radius, part_joint[:len(capsules)], capsules[:, 6:8].max(axis=1))
    tops = np.flatnonzero(roles.top)
    bone = np.linalg.norm(points[roles.below[tops]] - points[tops], axis=-1)
    return points[tops], np.minimum(ROOT_REACH * radius[tops], ROOT_BONE * bone)


def _colors(normals: NDArray[np.float64], faces: NDArray[np.int64], nearest: NDArray[np.int64],
            part_colors: NDArray[np.float64], coat: NDArray[np.float64], countershade: float) -> NDArray[np.float32]:
    """Each vertex's colour (V, 3), linear: the colour (of ``part_colors`` (P, 3)) of the
    part ``nearest`` (V,) it; a vertex with a neighbour of another colour (along the mesh's
    edges, ``faces`` (F, 3)) takes its neighbourhood's mean, so two colours meet in a soft
    edge, not a saw-tooth along the triangles; where a small patch of one colour
    (:data:`SMALL_PATCH`: a hoof, a couple of rings of vertices) meets the coat its
    vertices take only :data:`PART_BLEND` of the mean, so it keeps its own colour however
    coarsely it was simplified; on the ``coat`` (3,), lighter where the
    surface faces down by ``countershade`` (0 to 1) (bare skin, horn and feathers are not
    countershaded)."""
    from scipy.sparse import coo_matrix, identity

    count = len(normals)
    a = faces[:, [0, 1, 2, 1, 2, 0]].reshape(-1, 2) if len(faces) else np.zeros((0, 2), np.int64)
    pairs = np.concatenate([a, a[:, ::-1]])
    near = coo_matrix((np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])), shape=(count, count)).tocsr()
    near.data[:] = 1.0  # an edge shared by two triangles counts once
    near = near + identity(count, format="csr")
    near = near.multiply(1.0 / np.asarray(near.sum(axis=1))).tocsr()  # each row averages a vertex's neighbourhood
    on_coat = np.all(np.abs(part_colors - coat[None, :]) < 1e-6, axis=1).astype(np.float64)[nearest]
    values = np.concatenate([part_colors[nearest], on_coat[:, None]], axis=1)
    mean = near @ values
    edge = np.any(np.abs(mean[:, :3] - values[:, :3]) > 1e-9, axis=1)  # a neighbour of another colour
    # Where a small patch of one colour (a hoof, a beak: two rings of vertices deep) meets
    # the coat, the coat's side of the edge takes the mean and the patch's only some of it,
    # so it keeps its colour whatever the simplification left; larger ones blend fully.
    small = _small_patches(pairs, values[:, :3], SMALL_PATCH)
    share = np.where(small & (values[:, 3] < 0.5) & (mean[:, 3] > 1e-9), PART_BLEND, 1.0)[:, None]
    values = np.where(edge[:, None], values + share * (mean - values), values)
    base, on_coat = values[:, :3], values[:, 3]
    under = (np.clip(-normals[:, 1], 0.0, 1.0) * on_coat)[:, None]
    light = base + (1.0 - base) * 0.5
    return (base * (1.0 - countershade * under) + light * countershade * under).astype(np.float32)


def _small_patches(pairs: NDArray[np.int64], colors: NDArray[np.float64], limit: int) -> NDArray[np.bool_]:
    """Whether each vertex lies in a patch of fewer than ``limit`` vertices of its own colour
    (``colors`` (V, 3); a patch: vertices of one colour joined by the mesh's edges,
    ``pairs`` (E, 2))."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    count = len(colors)
    same = np.all(np.abs(colors[pairs[:, 0]] - colors[pairs[:, 1]]) < 1e-9, axis=1)
    linked = pairs[same]
    graph = coo_matrix((np.ones(len(linked)), (linked[:, 0], linked[:, 1])), shape=(count, count))
    _, label = connected_components(graph, directed=False)
    return np.bincount(label)[label] < limit


def build_body(motion: Motion, clip: SkeletonClip, detail: Detail = "full") -> SkinnedBody:
    """The skinned body of the creature of ``motion`` bound to ``clip`` (its skeleton,
    from :func:`app.kinematics.skeleton.skeleton_clip`), in their first frame."""
    import trimesh

    from ..render.scene import feature_anchors, mane_color, skin_features, srgb_to_linear
    from .features import feature_mesh, seat_on_skin

    start = time.perf_counter()
    capsules, ellipsoids, part_colors = _parts(motion)
    capsules, ellipsoids, part_joint, limbs = _bound(motion, clip, capsules, ellipsoids)
    coat = srgb_to_linear(motion.rig.look.body_color)
    verts, faces, blend, normal_at = _surface(capsules, ellipsoids, detail, limbs)
    roots = _limb_roots(capsules, part_joint, clip)
    tail_joints = np.array([k for k, name in enumerate(clip.skeleton.names) if name.startswith("tail")], dtype=np.int64)

    def skinned(verts: NDArray[np.float64], faces: NDArray[np.int64], detail: Detail,
                shadow: SkinnedBody | None = None, far: SkinnedBody | None = None,
                carries_features: bool = False) -> SkinnedBody:
        mesh = trimesh.Trimesh(verts, faces, process=False)
        mesh.fix_normals()
        verts, faces = np.asarray(mesh.vertices), np.asarray(mesh.faces, dtype=np.int64)
        # The surface's own normal (smooth: a simplified mesh's normals are as faceted as
        # its triangles, and blotched the shading) where it agrees with the mesh's side;
        # the mesh's where the field is flat or the mesh folds against it.
        normals = np.asarray(mesh.vertex_normals)
        smooth = normal_at(verts)
        normals = np.where((np.sum(smooth * normals, axis=1) > 0.2)[:, None], smooth, normals)
        joints, weights = _weights(verts, capsules, ellipsoids, part_joint, clip.world_position.shape[1],
                                   0.45 * blend, *roots)
        # Each vertex takes the colour of the part it lies on (hooves are dark horn, a bird's
        # feet scaly, its wings feathers, as in the parts).
        nearest = np.argmin(part_distances(verts, capsules, ellipsoids), axis=0)
        colors = _colors(normals, faces, nearest, part_colors, coat, motion.rig.look.countershade)
        if motion.rig.body.mane > 0 and motion.rig.four_legged_mammal:  # a maned animal's tail is hair of the mane's colour
            hair = np.sum(np.where(np.isin(joints, tail_joints), weights, 0.0), axis=1)[:, None]
            colors = (colors * (1.0 - hair) + mane_color(motion.rig)[None, :] * hair).astype(np.float32)
        bind = joint_matrices(clip, 0)
        features = None
        if carries_features:  # the eyes, nose and mane, skinned as the vertices nearest them
            rows = seat_on_skin(skin_features(motion), feature_anchors(motion), verts, faces)
            on_skin = feature_mesh(rows, verts, joints, weights)
            if on_skin is not None:
                f_positions, f_normals, f_colors, f_faces, f_joints, f_weights = on_skin
                features = SkinnedBody(positions=f_positions, normals=f_normals, colors=f_colors, faces=f_faces,
                                       joints=f_joints, weights=f_weights, bind=bind, layout=clip.layout,
                                       detail=detail)
        return SkinnedBody(positions=verts.astype(np.float32), normals=normals.astype(np.float32),
                           colors=colors,
                           faces=faces.astype(np.int32),
                           joints=joints, weights=weights, bind=bind, layout=clip.layout,
                           detail=detail, shadow=shadow, features=features, far=far,
                           seconds=time.perf_counter() - start)

    shown = _simplify(verts, faces, FACES[detail])
    if detail != "full":
        return skinned(*shown, detail, carries_features=True)
    stand_in = _simplify(*shown, SHADOW_FACES)
    far = _simplify(*stand_in, FAR_FACES)
    speck = skinned(*_simplify(*far, SPECK_FACES), "coarse")  # the far body's shadow
    return skinned(*shown, detail, skinned(*stand_in, "coarse"), skinned(*far, "coarse", shadow=speck),
                   carries_features=True)
