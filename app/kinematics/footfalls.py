"""Footfalls: phases decide *when* a foot lands and lifts, the world decides *where*.

A foot's step k is the stance that starts when its phase clock ``clock - offset`` passes
the integer k. Its foothold is the foot's neutral point (its rest position beside its
girdle, see :attr:`Rig.neutral_feet`) at the moment of mid-stance on the body's path —
so it lands half a step ahead of the hip and leaves half a step behind (terrain seed) —
snapped to acceptable ground (:mod:`app.kinematics.footholds`). A planted foot is a
constant in world space: zero slip by construction. A swinging foot goes from its
lift-off foothold to the next one along an eased chord, raised along the averaged normal
of the two by its step height (more where the ground between them is higher: stairs).

:func:`plan_constant_gait` plans a whole clip of a constant gait at once, vectorised over
every step of every foot; :class:`~app.kinematics.live.LiveMotion` plans one step at a
time as feet lift off. Both fill the same :class:`FootPlan`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from ..choices import WaveShape
from .easing import smootherstep
from .footholds import EDGE_MARGIN, Footholds, place_feet
from .oscillator import foot_wave
from .path import left_of
from .rig import Rig
from .walker import heel_to_toe, walker_ease, walker_lift
from .world import World, WorldError

SEARCH_RADIUS = 0.3  # of the leg rest length: how far from its ideal spot a foot may land
GRIP_SLOPE = np.radians(60.0)  # the steepest ground a sprawled, clawed foot holds on to (at least)
WIDER_SEARCH = (2.0, 3.0)  # ... and, where all of that is too steep, how much further it looks
MAX_LIFT = 1.5  # of the leg's rest length: the highest a swing may rise
CLEARANCE = 0.3  # of the step height: the least room under a swinging foot over the ground between footholds
_CLEAR_SAMPLES = np.linspace(0.06, 0.94, 31)


@dataclass(frozen=True)
class FootPlan:
    """Each foot in each frame (arrays (T, L, ...)): its phase since touchdown and duty
    factor, whether it is planted, its swing progress (0 in stance), the foothold it
    stands on or left (``start``) and the one it swings to (``end``, equal to ``start``
    in stance), their ground normals, its swing's apex height (m), the body's arc
    length along the path when the swing starts and ends (``lift_at``, ``land_at``), and
    the horizontal (x, z) unit direction each foothold's foot points (``start_dir``,
    ``end_dir``, (T, L, 2): the foot's direction at its mid-stance, fixed for its stance),
    and whether the foothold it stands on (in stance) or swings to is compromised (uneven
    ground, :class:`~app.kinematics.footholds.Footholds`)."""

    phase: NDArray[np.float64]
    duty: NDArray[np.float64]
    contact: NDArray[np.bool_]
    swing: NDArray[np.float64]
    start: NDArray[np.float64]
    end: NDArray[np.float64]
    start_normal: NDArray[np.float64]
    end_normal: NDArray[np.float64]
    apex: NDArray[np.float64]
    lift_at: NDArray[np.float64]
    land_at: NDArray[np.float64]
    start_dir: NDArray[np.float64]
    end_dir: NDArray[np.float64]
    compromised: NDArray[np.bool_]


def swing_ease(swing: NDArray[np.float64], wave: WaveShape) -> NDArray[np.float64]:
    """Progress (0..1) along the chord between footholds at swing progress ``swing``: a
    smootherstep for the planted wave, a sine ease for the seed's skewed waves. Both start
    and end at rest, so a foot leaves and meets the ground without a jolt."""
    if wave == "planted":
        return smootherstep(swing)
    return 0.5 - 0.5 * np.cos(np.pi * swing)


def footprint(rig: Rig) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """Each foot's reach (m) ahead of its ball (toe), behind it (heel, where a low ankle
    would touch) and to the side, shape (L,) each."""
    ball_radius = 0.5 * rig.bone_radius
    heel = rig.metatarsus * np.cos(rig.ankle_lift) * np.clip(1.0 - 2.0 * np.sin(rig.ankle_lift), 0.0, 1.0)
    heel = np.where(rig.roll_amount > 0, np.maximum(heel, rig.heel_length), heel)  # a rolling heel bears weight
    return rig.toe + ball_radius, np.maximum(heel, ball_radius), ball_radius


def foot_directions(rig: Rig, tangent: NDArray[np.float64], legs: NDArray[np.int64]) -> NDArray[np.float64]:
    """The (x, z) direction feet ``legs`` (...) point, given their girdles' path tangents
    (..., 2): along the body for mammal legs, outwards (turned forward by the splay) for
    sprawled legs."""
    left = left_of(tangent)
    out = (rig.hip_side * np.cos(rig.splay))[legs][..., None] * left + np.sin(rig.splay)[legs][..., None] * tangent
    return np.where(rig.knee_out[legs][..., None], out, tangent)


def neutral_points(rig: Rig, world: World, s: NDArray[np.float64], legs: NDArray[np.int64]
                   ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The ground (x, z) under each foot's rest position when the body's centre is at arc
    length ``s`` (N,) of the path, for legs ``legs`` (N,); also the girdle's tangents."""
    girdle = rig.girdle[legs]
    s_girdle = s + (rig.girdle_position[girdle] - 0.5) * rig.body_length
    point, tangent = world.path.sample(s_girdle)
    rest = rig.neutral_feet[legs]  # (N, 2): lateral, forward
    return point + left_of(tangent) * rest[:, :1] + tangent * rest[:, 1:], tangent


def stance_directions(rig: Rig, world: World, s_mid: NDArray[np.float64], legs: NDArray[np.int64]
                      ) -> NDArray[np.float64]:
    """The horizontal (x, z) direction (N, 2) feet ``legs`` (N,) point in a stance centred on
    body arc length ``s_mid`` (N,): the foot's own heading for that whole stance."""
    _, tangent = neutral_points(rig, world, s_mid, legs)
    return foot_directions(rig, tangent, legs)


def foot_max_slope(rig: Rig, terrain_max_slope: float) -> NDArray[np.float64]:
    """The steepest ground (rad) each foot (L,) stands on: the terrain's ``max_slope``, and
    for a sprawled, clawed leg (an arthropod's: its knee out) at least :data:`GRIP_SLOPE`,
    as ants, spiders and centipedes hold on to steep ground."""
    return np.where(rig.knee_out, max(terrain_max_slope, GRIP_SLOPE), terrain_max_slope)


def plan_footholds(rig: Rig, world: World, s_mid: NDArray[np.float64], legs: NDArray[np.int64]) -> Footholds:
    """Footholds (N,) for legs ``legs`` whose stance is centred on body arc length ``s_mid``.
    Where all the ground in a foot's reach is steeper than ``max_slope`` it looks two and
    three times as far (the step longer or shorter: a compromised foothold); raises
    :class:`WorldError` when that is all too steep as well (uneven ground only compromises
    a foothold: ``Footholds.compromised``)."""
    ideal, tangent = neutral_points(rig, world, s_mid, legs)
    front, back, side = footprint(rig)
    search = np.maximum(SEARCH_RADIUS * rig.l_rest[legs], 3.0 * EDGE_MARGIN)
    steepest = foot_max_slope(rig, world.terrain.max_slope)[legs]
    # A rolling sole keeps its heading through the stance; other feet may turn under the body.
    rigid = ((rig.roll_amount > 0) & (rig.heel_length > 0))[legs]
    heading = np.where(rigid[:, None], foot_directions(rig, tangent, legs), np.nan)
    held = place_feet(world.terrain, ideal, front[legs], back[legs], side[legs], search, steepest, heading)
    for wider in WIDER_SEARCH:  # a patch too steep all round: look further, the step longer or shorter
        if held.ok.all():
            break
        redo = np.nonzero(~held.ok)[0]
        again = place_feet(world.terrain, ideal[redo], front[legs[redo]], back[legs[redo]], side[legs[redo]],
                           wider * search[redo], steepest[redo], heading[redo])
        held.points[redo], held.normals[redo], held.ok[redo] = again.points, again.normals, again.ok
        held.compromised[redo] = again.ok  # off its stride: counted as compromised
    if not held.ok.all():
        search = search * WIDER_SEARCH[-1]  # what was searched, for the message
        i = int(np.argmin(held.ok))
        x, z = ideal[i]
        raise WorldError(f"terrain {world.terrain.describe()}: no foothold for foot {rig.leg_names[legs[i]]} near "
                         f"(x={x:.2f}, z={z:.2f}): all the ground within {search[i]:.2f} m is steeper than "
                         f"max_slope = {np.degrees(steepest[i]):.0f} deg (raise max_slope, or make the ground "
                         "gentler there)")
    return held


def swing_support(rig: Rig, world: World, legs: NDArray[np.int64], start: NDArray[np.float64],
                  end: NDArray[np.float64], lift_at: NDArray[np.float64], land_at: NDArray[np.float64],
                  body_at: NDArray[np.float64], ease: NDArray[np.float64]) -> NDArray[np.float64]:
    """Where swinging feet are (without their lift), shape (N, M, 3): moving relative to
    their hip's neutral point in the girdle's frame, from ``start`` relative to where that
    point was at ``lift_at`` to ``end`` relative to where it will be at ``land_at`` (body
    arc lengths, (N,)), eased by ``ease`` (N, M) while the body is at ``body_at`` (N, M).
    The height eases between the footholds' heights in the world."""
    n, m = ease.shape
    at = np.concatenate([np.stack([lift_at, land_at], axis=-1), body_at], axis=1)  # (N, 2 + M)
    point, tangent = neutral_points(rig, world, at.reshape(-1), np.repeat(legs, m + 2))
    point, tangent = point.reshape(n, m + 2, 2), tangent.reshape(n, m + 2, 2)
    left = left_of(tangent)
    rel_start = start[:, [0, 2]] - point[:, 0]
    rel_end = end[:, [0, 2]] - point[:, 1]
    a0 = np.stack([np.sum(rel_start * tangent[:, 0], -1), np.sum(rel_start * left[:, 0], -1)], -1)[:, None]
    a1 = np.stack([np.sum(rel_end * tangent[:, 1], -1), np.sum(rel_end * left[:, 1], -1)], -1)[:, None]
    a = a0 + (a1 - a0) * ease[..., None]  # (N, M, 2)
    xz = point[:, 2:] + tangent[:, 2:] * a[..., :1] + left[:, 2:] * a[..., 1:]
    y = start[:, None, 1] + (end[:, None, 1] - start[:, None, 1]) * np.clip(ease, 0.0, 1.0)
    return np.stack([xz[..., 0], y, xz[..., 1]], axis=-1)


def swing_apex(rig: Rig, world: World, start: NDArray[np.float64], end: NDArray[np.float64],
               legs: NDArray[np.int64], step_height: NDArray[np.float64], duty: NDArray[np.float64],
               wave: WaveShape, lift_at: NDArray[np.float64], land_at: NDArray[np.float64]) -> NDArray[np.float64]:
    """The apex height (m) of swings from ``start`` to ``end`` (N, 3): the step height, or
    more where the ground along the way (under the ball and the toe tip) would otherwise
    come within CLEARANCE of the foot. step_height (N,) in metres; duty (N,); the body
    moves from arc length ``lift_at`` to ``land_at`` (N,) during the swing."""
    n = start.shape[0]
    if n == 0 or world.terrain.flat:
        return np.asarray(step_height, dtype=np.float64) * np.ones(n)
    s = _CLEAR_SAMPLES
    phase = duty[:, None] + s[None, :] * (1.0 - duty[:, None])
    shape = foot_wave(phase, duty[:, None], wave).lift  # (N, M)
    ease = swing_ease(np.broadcast_to(s, shape.shape), wave)
    walker = heel_to_toe(rig)[legs][:, None]
    if walker.any():
        shape = np.where(walker, walker_lift(s[None, :], duty[:, None], shape), shape)
        ease = np.where(walker, walker_ease(s[None, :], duty[:, None]), ease)
    body_at = lift_at[:, None] + (land_at - lift_at)[:, None] * s[None, :]
    base = swing_support(rig, world, legs, start, end, lift_at, land_at, body_at, ease)  # (N, M, 3)
    chord = end[:, [0, 2]] - start[:, [0, 2]]
    ahead = chord / np.maximum(np.linalg.norm(chord, axis=-1, keepdims=True), 1e-9)
    reach = (rig.toe[legs] + 0.5 * rig.bone_radius[legs])[:, None, None]
    xz = base[..., [0, 2]]
    ground = world.terrain.height(xz)
    for k in (-1.0, -0.5, 0.5, 1.0):  # under the toe tip and the heel, whichever way the foot turns
        ground = np.maximum(ground, world.terrain.height(xz + k * reach * ahead[:, None, :]))
    need = (ground + CLEARANCE * step_height[:, None] - base[..., 1]) / np.maximum(shape, 0.2)
    apex = np.maximum(step_height, need.max(axis=1))
    return np.minimum(apex, MAX_LIFT * rig.l_rest[legs])


def plan_constant_gait(rig: Rig, world: World, clock: NDArray[np.float64], travel_per_cycle: float,
                       origin: float = 0.0) -> FootPlan:
    """The footfalls of a constant gait for clock values (T,), the body's centre moving
    ``travel_per_cycle`` metres along the path per cycle (at arc length ``origin`` at
    clock 0).

    Every step of every foot that the clip touches is planned in one vectorised pass.
    """
    gait = rig.gait
    legs = np.arange(rig.leg_count)
    offsets = gait.offsets
    duty = gait.duty_factor
    u = clock[:, None] - offsets[None, :]
    k = np.floor(u)
    phase = u - k
    k_min = int(k.min())
    k_max = int(k.max()) + 1
    steps = np.arange(k_min, k_max + 1, dtype=np.float64)  # (K,)
    s_mid = origin + travel_per_cycle * (steps[:, None] + offsets[None, :] + 0.5 * duty)  # (K, L)
    leg_index = np.broadcast_to(legs, s_mid.shape)
    held = plan_footholds(rig, world, s_mid.reshape(-1), leg_index.reshape(-1))
    count = steps.shape[0]
    dirs = stance_directions(rig, world, s_mid.reshape(-1), leg_index.reshape(-1)).reshape(count, rig.leg_count, 2)
    points = held.points.reshape(count, rig.leg_count, 3)
    normals = held.normals.reshape(count, rig.leg_count, 3)
    compromised = held.compromised.reshape(count, rig.leg_count)
    step_m = np.broadcast_to(gait.step_height * rig.l_rest, (count - 1, rig.leg_count))
    lift_steps = origin + travel_per_cycle * (steps[:-1, None] + offsets[None, :] + duty)  # (K-1, L)
    apex = swing_apex(rig, world, points[:-1].reshape(-1, 3), points[1:].reshape(-1, 3),
                      leg_index[:-1].reshape(-1), step_m.reshape(-1), np.full(step_m.size, duty),
                      gait.wave, lift_steps.reshape(-1),
                      (lift_steps + travel_per_cycle * (1.0 - duty)).reshape(-1)).reshape(count - 1, rig.leg_count)
    index = (k - k_min).astype(np.int64)  # (T, L)
    contact = phase < duty
    swing = np.where(contact, 0.0, (phase - duty) / (1.0 - duty))
    nxt = np.where(contact, index, index + 1)
    lift_at = origin + travel_per_cycle * (k + offsets + duty)
    return FootPlan(phase=phase, duty=np.broadcast_to(duty, phase.shape), contact=contact, swing=swing,
                    start=points[index, legs], end=points[nxt, legs], start_normal=normals[index, legs],
                    end_normal=normals[nxt, legs], apex=apex[np.minimum(index, count - 2), legs],
                    lift_at=lift_at, land_at=lift_at + travel_per_cycle * (1.0 - duty), start_dir=dirs[index, legs],
                    compromised=compromised[nxt, legs],
                    end_dir=dirs[nxt, legs])


@dataclass(frozen=True)
class FootTargets:
    """Per frame and foot (T, L, ...): the ball target, the foot's ground support (the
    point it stands on, sliding from one foothold to the next in swing, no lift) with its
    normal, and the lift above the support (m)."""

    ball: NDArray[np.float64]
    support: NDArray[np.float64]
    normal: NDArray[np.float64]
    lift: NDArray[np.float64]


def landing_points(rig: Rig, world: World, legs: NDArray[np.int64], start: NDArray[np.float64],
                   end: NDArray[np.float64], lift_at: NDArray[np.float64], land_at: NDArray[np.float64],
                   touch_at: NDArray[np.float64]) -> NDArray[np.float64]:
    """Where swings planned from ``start`` (lifted at body arc length ``lift_at``) to ``end``
    (expected at ``land_at``) really land when the body is at ``touch_at`` (N,) at
    touchdown: ``end`` moved with the hip if the body ran ahead of or behind the plan,
    on the ground. Equal to ``end`` when the plan held."""
    point = swing_support(rig, world, legs, start, end, lift_at, land_at, touch_at[:, None],
                          np.ones((len(legs), 1)))[:, 0]
    moved = np.linalg.norm(point[:, [0, 2]] - end[:, [0, 2]], axis=-1) > 1e-9
    point[:, 1] = np.where(moved, world.terrain.height(point[:, [0, 2]]), end[:, 1])
    point[~moved] = end[~moved]
    return point


def foot_targets(plan: FootPlan, lift_shape: NDArray[np.float64], wave: WaveShape, rig: Rig, world: World,
                 travel: NDArray[np.float64]) -> FootTargets:
    """Ball targets from a plan; ``lift_shape`` (T, L) is the oscillator's lift (0..1) and
    ``travel`` (T,) the body's arc length now.

    In swing the foot moves relative to its hip's neutral point (in the girdle's frame):
    from where it left the ground, relative to where the hip's neutral point was then, to
    where it lands, relative to where that point will be — eased, so it starts and ends at
    rest relative to the body, and lands exactly on its foothold. Its height eases between
    the two footholds' heights in the world; the lift is along their averaged normal.
    """
    ease = swing_ease(plan.swing, wave)
    walker = heel_to_toe(rig)[None, :] & ~plan.contact
    if walker.any():  # a walker's foot swings as people's do (app.kinematics.walker)
        ease = np.where(walker, walker_ease(plan.swing, plan.duty), ease)
        lift_shape = np.where(walker, walker_lift(plan.swing, plan.duty, lift_shape), lift_shape)
    ease = ease[..., None]
    swinging = ~plan.contact
    support = plan.start.copy()
    if swinging.any():
        rows = np.nonzero(swinging)
        body_at = np.broadcast_to(travel[:, None], plan.swing.shape)[rows][:, None]
        support[rows] = swing_support(rig, world, rows[1], plan.start[rows], plan.end[rows], plan.lift_at[rows],
                                      plan.land_at[rows], body_at, ease[rows])[:, 0]
    normal = plan.start_normal + (plan.end_normal - plan.start_normal) * ease
    normal = normal / np.linalg.norm(normal, axis=-1, keepdims=True)
    averaged = plan.start_normal + plan.end_normal
    averaged /= np.linalg.norm(averaged, axis=-1, keepdims=True)
    lift = plan.apex * lift_shape
    ball = support + averaged * lift[..., None]
    return FootTargets(ball=ball, support=support, normal=normal, lift=lift)
