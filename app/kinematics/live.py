"""Real-time motion for the viewer and speed ramps: an integrated clock, travel along the
world's path, footholds planned as feet lift off, and seamless gait changes.

The clock advances by ``frequency * dt`` each step and the body by its ground speed, so
changing speed never jumps. Planted feet are constants in the world (they cannot slip);
a foot that lifts off is given its next foothold at once — the neutral point at its
predicted mid-stance, half a step ahead of its hip — and swings there. A gait change
(preset, phase offsets, duty factor, stride, step height, bob, frequency, wave shape)
reaches each foot without a jump:

- each foot takes the new duty factor and step height at its next touchdown, and the new
  stride at its next lift-off; the body's travel per cycle follows the gait's stride
  over its duty factor smoothly, as fast as its planted feet bear it (held in a flight);
- each foot moves its phase offset towards the new one only while it is in the air, at
  most :data:`SWING_RETIME` of the clock's rate; during a switch the new gait is aimed
  at in the alignment that slowing swings alone reaches soonest (:func:`slowing_shift`:
  a gait is its feet's phases relative to each other, so all its offsets may be shifted
  together), re-aimed at every step, so a foot slowed for the speed cap never has to
  catch up; a speed ramp's small changes of duty, stride and frequency are no switch;
- no foot swings faster (peak speed over the ground) than in the faster of the two gaits'
  steady swings: a foot whose swing would be faster is slowed by retiming it, and catches
  up in later swings;
- frequency and body bob blend over :data:`BLEND_CYCLES`; a change of wave shape
  cross-fades the two oscillators over the same time.

Changes of the body or the legs (lengths, ankle lift) apply at once.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from ..choices import WaveShape
from .easing import smoothstep
from .footfalls import (
    FootPlan,
    landing_points,
    neutral_points,
    plan_constant_gait,
    plan_footholds,
    stance_directions,
    swing_apex,
)
from .gait import ground_speed, walking_weight
from .motion import MotionInputs, Pose, check_world, oscillators, solve_motion
from .oscillator import FootWave
from .poses import height_jump, reference_foot, settle
from .rig import Rig
from .world import World, WorldError

BLEND_CYCLES = 0.35
SWING_RETIME = 0.6
LOOK_AHEAD = 20.0  # s of walking on whose footholds a new world must offer
SMALL_CHANGE = 0.03  # relative frequency (and absolute bob) change applied at once
# How quickly the body's travel per cycle follows the gait's: at a rate of the planted
# feet's stance weights (each foot's sin(pi u) over its stance fraction u) per this many
# cycles.
RATE_EASE = 0.2


def _mix_waves(a: FootWave, b: FootWave, w: float) -> FootWave:
    return FootWave(forward=a.forward + (b.forward - a.forward) * w, lift=a.lift + (b.lift - a.lift) * w,
                    contact=b.contact if w >= 0.5 else a.contact, swing=b.swing if w >= 0.5 else a.swing)


# Swing speed profiles sampled over the swing (progress s): d(progress)/ds of each wave's
# ease relative to the hip, and d(lift)/ds, per unit distance and height.
_S = np.linspace(0.0, 1.0, 41)
_DEASE = {"planted": 30.0 * _S ** 2 * (_S - 1.0) ** 2, "skewed-sine": 0.5 * np.pi * np.sin(np.pi * _S)}
_DLIFT = np.pi * np.abs(np.cos(np.pi * _S))


def slowing_shift(current: NDArray[np.float64], target: NDArray[np.float64]) -> float:
    """The shift (cycles) to add to every ``target`` offset so that the feet reach the new
    gait by slowing their swings only, as little as possible: each foot's change
    ``(target + shift - current) mod 1`` is >= 0 and the largest is smallest. (A swing
    may always be slowed; speeding one up is limited by how fast a foot may move.)

    The changes lie on a circle; the best shift starts the arc after its widest gap."""
    d = np.sort(np.mod(target - current, 1.0))
    gaps = np.diff(np.append(d, d[0] + 1.0))
    start = d[(int(np.argmax(gaps)) + 1) % len(d)]
    return float(-start)


class LiveMotion:
    """A creature moving in real time. Call :meth:`step` with the elapsed time, then
    :meth:`pose`. Deterministic given the sequence of calls.

    Per-foot state (arrays (L,)): ``offsets`` (cycle fractions), ``duty``, ``stride``
    (mean leg rest lengths: of the current stance, or of the coming one while in the
    air), ``step_height`` (leg rest lengths); ``start``/``end`` (L, 3) the foothold a foot
    stands on (or left) and the one it swings to, with their normals; ``apex`` (L,) m.
    """

    def __init__(self, rig: Rig, world: World | None = None) -> None:
        self.rig: Rig = rig
        self.world: World = world or World()
        check_world(rig, self.world)
        self.clock = 0.0  # cycles
        self.time = 0.0  # seconds of animation time
        self.travel = 0.0  # metres the body has moved along its path
        self._adopt_all()

    # -- state -------------------------------------------------------------------------

    def _adopt_all(self) -> None:
        """Take the rig's gait at once and stand every foot where that gait puts it."""
        g = self.rig.gait
        n = self.rig.leg_count
        self.offsets = np.array(g.offsets, dtype=np.float64)
        self.offset_shift = 0.0  # cycles added to every offset of the gait (see _set_rig)
        self.duty = np.full(n, g.duty_factor)
        self.stride = np.full(n, g.stride)
        self.stride_lift = self.stride.copy()  # the stride of the stance a foot last left
        self.step_height = np.full(n, g.step_height)
        per_cycle = float(ground_speed(g.stride * self.rig.leg_scale, g.duty_factor))
        plan = plan_constant_gait(self.rig, self.world, np.array([self.clock]), per_cycle,
                                  origin=self.travel - per_cycle * self.clock)
        self.start, self.end = plan.start[0].copy(), plan.end[0].copy()
        self.start_normal, self.end_normal = plan.start_normal[0].copy(), plan.end_normal[0].copy()
        self.start_dir, self.end_dir = plan.start_dir[0].copy(), plan.end_dir[0].copy()
        self.apex = plan.apex[0].copy()
        self.lift_at, self.land_at = plan.lift_at[0].copy(), plan.land_at[0].copy()
        self._rate = per_cycle  # metres per cycle the body travels (travel_per_cycle)
        self.start_compromised = plan.compromised[0].copy()  # feet on uneven ground (the least-bad spot)
        self.end_compromised = plan.compromised[0].copy()
        self.compromised_count = 0  # compromised footholds planned since the start
        self._freq_from = self._freq_to = g.frequency
        self._bob_from = self._bob_to = g.bob
        self._trunk = np.array([g.flex, g.pitch])  # spine flex and trunk pitch amplitudes (rad), eased to the gait's
        self._wave_from = self._wave_to = g.wave
        self._blend = 1.0  # progress of the frequency / bob / wave blend, 0..1
        # A posed body's height jump being eased away: (m, m/s, when (s)), a biped's jump in
        # how far it runs (lean, elbows: (weight, when (s))), and the feet's duty factors at
        # the time they were last seen (see _shifts).
        self._height_jump: tuple[float, float, float] = (0.0, 0.0, 0.0)
        self._running_jump: tuple[float, float] = (0.0, 0.0)
        self._height_seen: tuple[NDArray[np.float64], float] | None = None
        self._feet_settled = True
        self._speed_cap = self._steady_swing_speed()  # m/s no swinging foot may exceed
        self._guard = False  # a gait switch is under way: the speed cap applies
        self._stepped = np.ones(n, dtype=bool)  # foot took a full step since the switch
        self._landed = np.ones(n, dtype=bool)

    @property
    def blending(self) -> bool:
        """True until every foot and every blended value has reached the new gait."""
        return self._blend < 1.0 or not self._feet_settled

    @property
    def frequency(self) -> float:
        w = float(smoothstep(self._blend))
        return self._freq_from + (self._freq_to - self._freq_from) * w

    @property
    def bob(self) -> float:
        w = float(smoothstep(self._blend))
        return self._bob_from + (self._bob_to - self._bob_from) * w

    def _wave_now(self) -> WaveShape:
        return self._wave_to if smoothstep(self._blend) >= 0.5 else self._wave_from

    def target_offsets(self) -> NDArray[np.float64]:
        """The phase offsets (L,) the feet are heading for: the gait's, all shifted by
        :attr:`offset_shift` (a gait is its feet's phases relative to each other)."""
        return np.mod(np.asarray(self.rig.gait.offsets, dtype=np.float64) + self.offset_shift, 1.0)

    def foot_phase(self) -> NDArray[np.float64]:
        """Each foot's phase since its touchdown, (L,)."""
        return np.mod(self.clock - self.offsets, 1.0)

    @property
    def phase(self) -> float:
        """Where the clock is within the current cycle, [0, 1)."""
        return float(self.clock % 1.0)

    def travel_per_cycle(self) -> float:
        """Metres the body moves per cycle now: the gait's stride over its duty factor,
        followed smoothly (:meth:`_follow_feet`)."""
        return self._rate

    def _follow_feet(self, cycles: float) -> None:
        """Move the body's travel per cycle towards the gait's (its stride over its duty
        factor), at a rate of the planted feet's stance weights (each foot's sin(pi u)
        over its stance fraction u: none at touchdown and lift-off) per :data:`RATE_EASE`
        cycles: held through a flight, eased in as feet land. It was the plain mean of
        the planted feet's own stride over duty factor, and each foot takes a new gait's
        numbers at its own touchdown and lift-off (a foot that lifted before a gait switch
        landed with the old stride over the new duty factor): along a speed ramp the body
        jumped by up to 1.6 m/s in one frame and back (a horse's gallop: 95 m/s^2)."""
        phase = self.foot_phase()
        planted = phase < self.duty
        weight = np.where(planted, np.sin(np.pi * np.clip(phase / self.duty, 0.0, 1.0)), 0.0)
        total = float(weight.sum())
        if total <= 0.0:
            return
        g = self.rig.gait
        wanted = float(ground_speed(g.stride, g.duty_factor)) * self.rig.leg_scale
        self._rate += (wanted - self._rate) * -np.expm1(-total * cycles / RATE_EASE)

    # -- swing speeds -----------------------------------------------------------------

    def _swing_terms(self, duty, travel_m, step_height, wave: WaveShape):
        """Per foot and swing sample (L, 41): fore-aft speed relative to the hip and vertical
        speed (m/s) per unit of phase speed (cycles/s), for swings covering ``travel_m``
        metres relative to the hip."""
        duty = np.asarray(duty, dtype=np.float64)[..., None]
        a = _DEASE[wave] * np.asarray(travel_m, dtype=np.float64)[..., None] / (1.0 - duty)
        b = _DLIFT * (np.asarray(step_height)[..., None] * self.rig.l_rest[:, None]) / (1.0 - duty)
        return a, b

    def _swing_speed(self, phase_speed, duty, travel_m, step_height, ground_speed, wave: WaveShape) -> NDArray[np.float64]:
        """Peak speed over the ground (m/s) of each foot's swing at ``phase_speed``, the body
        moving at ``ground_speed`` (m/s)."""
        a, b = self._swing_terms(np.broadcast_to(duty, (self.rig.leg_count,)), travel_m, step_height, wave)
        return np.hypot(ground_speed + phase_speed * a, phase_speed * b).max(axis=-1)

    def _steady_swing_speed(self) -> float:
        """The peak swing speed (m/s) of the rig's gait when steady (depends on the rig only)."""
        cached = self.__dict__.get("_steady")
        if cached is not None and cached[0] is self.rig:
            return cached[1]
        g = self.rig.gait
        travel = g.stride * self.rig.leg_scale
        speed = float(ground_speed(travel, g.duty_factor, g.frequency))
        value = float(self._swing_speed(g.frequency, g.duty_factor, travel, g.step_height, speed, g.wave).max())
        self._steady = (self.rig, value)
        return value

    def _swing_travel(self) -> NDArray[np.float64]:
        """Metres each foot's current (or, while planted, next) swing covers relative to its
        hip: from where it lifts off to where it lands, along the body."""
        phase = self.foot_phase()
        airborne = phase >= self.duty
        legs = np.arange(self.rig.leg_count)
        per_cycle = self.travel_per_cycle()
        at = np.concatenate([self.lift_at, self.land_at, np.full(len(legs), self.travel)])
        point, tangent = neutral_points(self.rig, self.world, at, np.tile(legs, 3))
        point, tangent = point.reshape(3, -1, 2), tangent.reshape(3, -1, 2)
        along = lambda p, i: np.sum((p[:, [0, 2]] - point[i]) * tangent[i], axis=-1)
        now = along(self.end, 1) - along(self.start, 0)
        lift_next = along(self.start, 2) - (self.duty - phase) * per_cycle  # where it will leave the ground
        landing_next = 0.5 * self.rig.gait.stride * self.rig.leg_scale
        return np.maximum(np.where(airborne, now, landing_next - lift_next), 0.0)

    def _phase_speed_cap(self) -> NDArray[np.float64]:
        """Per foot, the fastest phase speed (cycles/s) that keeps its swing's peak speed
        over the ground under the cap: the smallest root over the swing samples of
        |(G + w a, w b)| = cap."""
        ground = self.travel_per_cycle() * self.frequency
        a, b = self._swing_terms(self.duty, self._swing_travel(), self.step_height, self._wave_now())
        cap = self._speed_cap * 0.98  # margin for what the model leaves out (hip sway, stride easing)
        q = a * a + b * b
        disc = np.maximum(ground * ground * a * a - q * (ground * ground - cap * cap), 0.0)
        roots = (-ground * a + np.sqrt(disc)) / np.maximum(q, 1e-300)
        return np.maximum(roots.min(axis=-1), 0.0)

    # -- changes ----------------------------------------------------------------------

    def _nominal_travel(self) -> float:
        return self.rig.gait.stride * self.rig.leg_scale

    def _travel_tolerance(self, straight: float) -> float:
        """How far (relative) a foot's swing may differ from the nominal one and still count
        as steady: on a curved path inner and outer feet step shorter and longer by their
        distance from the path over its radius."""
        lateral = float(np.abs(self.rig.neutral_feet[:, 0]).max())
        return straight + lateral / self.world.path.curvature_radius()

    def _update_settled(self) -> None:
        g = self.rig.gait
        offset_error = np.abs(np.mod(self.offsets - self.target_offsets() + 0.5, 1.0) - 0.5).max()
        self._feet_settled = bool(
            offset_error <= 1e-12 and np.all(self.duty == g.duty_factor) and np.all(self.stride == g.stride)
            and np.all(self.stride_lift == g.stride) and np.all(self.step_height == g.step_height)
            and np.allclose(self._swing_travel(), self._nominal_travel(), rtol=self._travel_tolerance(1e-3),
                            atol=1e-6))

    def set_rig(self, rig: Rig, blend: bool = True) -> None:
        """Switch to a new rig (creature and gait); gait changes blend unless ``blend`` is
        False. On a :class:`WorldError` (a body the world cannot take) nothing changes."""
        saved = dict(self.__dict__)
        try:
            self._set_rig(rig, blend)
        except WorldError:
            self.__dict__.clear()
            self.__dict__.update(saved)
            raise

    def set_world(self, world: World) -> None:
        """Walk in ``world`` from now on (new ground or path under a walking creature).
        Planted feet stay where they stand until they lift; every later foothold is found
        on the new ground. Raises :class:`WorldError` (nothing changes) when the body
        cannot follow the path or a foot would find no foothold a step ahead."""
        self.check_world(world)
        self.world = world

    def check_world(self, world: World) -> None:
        """Raise :class:`WorldError` if :meth:`set_world` would refuse ``world``: a path the
        body cannot follow, or ground that offers a foot no foothold within
        :data:`LOOK_AHEAD` seconds of walking on (so an accepted edit is walkable, not a
        pause a few steps later)."""
        check_world(self.rig, world)
        legs = np.arange(self.rig.leg_count)
        per_cycle = self.travel_per_cycle()
        ahead = self.travel + per_cycle * (1.0 - self.foot_phase()) + 0.5 * self.stride * self.rig.leg_scale
        cycles = int(np.ceil(LOOK_AHEAD * max(self.frequency, 1e-3)))
        if per_cycle > 1e-9 and not world.in_place:
            length = world.path.length
            if np.isfinite(length):  # a path that ends, or one lap of a closed one
                cycles = min(cycles, int(np.ceil(length / per_cycle)) + 1)
        else:
            cycles = 1
        steps = np.arange(cycles)[:, None]
        plan_footholds(self.rig, world, (ahead[None, :] + per_cycle * steps).reshape(-1),
                       np.broadcast_to(legs, (cycles, legs.size)).reshape(-1))  # raises when the ground offers none

    def step(self, dt: float) -> None:
        """Advance by ``dt`` seconds of animation time (0 or negative does nothing). On a
        :class:`WorldError` (no foothold ahead) the motion stays where it was."""
        saved = {k: (v.copy() if isinstance(v, np.ndarray) else v) for k, v in self.__dict__.items()}
        try:
            self._step(dt)
        except WorldError:
            self.__dict__.clear()
            self.__dict__.update(saved)
            raise

    def _set_rig(self, rig: Rig, blend: bool) -> None:
        check_world(rig, self.world)
        frequency, bob, wave = self.frequency, self.bob, self._wave_now()
        speed_now = max(self._speed_cap, float(np.max(self._swing_speed(
            frequency, self.duty, self._swing_travel(), self.step_height, self.travel_per_cycle() * frequency, wave))))
        before = self.rig.gait  # the gait asked for until now (the feet may still be on their way)
        self.rig = rig
        g = rig.gait
        if not blend or rig.leg_count != len(self.offsets):
            self._adopt_all()
            return
        self._update_settled()
        # A switch is judged against the gait asked for before, not against where the feet
        # are: a speed ramp changes duty, stride and frequency a little at every call, and
        # the feet take those at their next touchdown or lift-off; that is no switch.
        offsets_change = not np.allclose(np.mod(np.asarray(g.offsets) - before.offsets + 0.5, 1.0) - 0.5, 0.0,
                                         atol=1e-9)
        big_change = (abs(g.frequency - before.frequency) > SMALL_CHANGE * before.frequency or g.wave != wave
                      or abs(g.duty_factor - before.duty_factor) > SMALL_CHANGE
                      or abs(g.stride - before.stride) > SMALL_CHANGE * before.stride)
        if offsets_change:
            self.offset_shift = slowing_shift(self.offsets, np.asarray(g.offsets, dtype=np.float64))
        if offsets_change or big_change:
            # A gait switch: the speed cap guards it until every foot has reached the new
            # phase and taken a full step in the new gait.
            self._speed_cap = max(speed_now, self._steady_swing_speed())
            self._guard = True
            self._stepped = np.zeros(rig.leg_count, dtype=bool)
            self._landed = np.zeros(rig.leg_count, dtype=bool)
        elif self._guard:
            # A gradual change during a switch (speeding up through it): the cap never falls
            # below the new gait's own steady swings, or the feet could never settle into it.
            self._speed_cap = max(self._speed_cap, self._steady_swing_speed())
        if (g.frequency, g.bob, g.wave) == (self._freq_to, self._bob_to, self._wave_to):
            return
        small = (abs(g.frequency - frequency) <= SMALL_CHANGE * frequency and abs(g.bob - bob) <= SMALL_CHANGE
                 and g.wave == wave)
        if small and self._blend >= 1.0:
            # A gradual change (e.g. a speed ramp, one frame at a time) applies directly: the
            # clock integrates the frequency, so nothing jumps.
            self._freq_from = self._freq_to = g.frequency
            self._bob_from = self._bob_to = g.bob
        elif self._blend < 1.0 and g.wave == self._wave_to:
            self._freq_to, self._bob_to = g.frequency, g.bob  # aim the running blend at the new values
        else:
            self._freq_from, self._bob_from, self._wave_from = frequency, bob, wave
            self._freq_to, self._bob_to, self._wave_to = g.frequency, g.bob, g.wave
            self._blend = 0.0

    # -- time -------------------------------------------------------------------------

    def _step(self, dt: float) -> None:
        if dt <= 0:
            return
        g = self.rig.gait
        cycles = self.frequency * dt
        before = self.foot_phase()
        self.travel += self.travel_per_cycle() * cycles
        self.clock += cycles
        self.time += dt
        if self._blend < 1.0:
            self._blend = min(1.0, self._blend + cycles / BLEND_CYCLES)
        self._trunk += (np.array([g.flex, g.pitch]) - self._trunk) * min(1.0, cycles / BLEND_CYCLES)

        after = self.foot_phase()
        landed = after < before
        lifted = ~landed & (before < self.duty) & (after >= self.duty)
        # A landing foot stands where its swing brought it (its foothold, moved with the hip
        # if the body ran ahead of or behind the plan); a lifting foot carries its stance's
        # stride into the air and will land with the new one.
        if landed.any():
            legs = np.nonzero(landed)[0]
            per_cycle = self.travel_per_cycle()
            touch_at = self.travel - per_cycle * after[legs]
            point = landing_points(self.rig, self.world, legs, self.start[legs], self.end[legs], self.lift_at[legs],
                                   self.land_at[legs], touch_at)
            moved = np.any(point != self.end[legs], axis=1)
            self.end_normal[legs] = np.where(moved[:, None], self.world.terrain.normal(point[:, [0, 2]]),
                                             self.end_normal[legs])
            self.end[legs] = point
        self.start = np.where(landed[:, None], self.end, self.start)
        self.start_normal = np.where(landed[:, None], self.end_normal, self.start_normal)
        self.start_dir = np.where(landed[:, None], self.end_dir, self.start_dir)
        self.start_compromised = np.where(landed, self.end_compromised, self.start_compromised)
        self.stride_lift = np.where(lifted, self.stride, self.stride_lift)
        self.stride = np.where(lifted, g.stride, self.stride)
        self.duty = np.where(landed, g.duty_factor, self.duty)
        self.step_height = np.where(landed, g.step_height, self.step_height)
        self._follow_feet(cycles)
        if lifted.any():
            self._plan_swings(np.nonzero(lifted)[0], after)
        self._stepped |= self._landed & lifted
        self._landed |= landed

        # Feet in the air move their phase offset towards the new one. Slowing a swing
        # (offset up) is always safe; speeding it up (offset down) only while the speed cap
        # leaves room, otherwise the foot goes the long way round by slowing.
        airborne = ~landed & (after >= self.duty)
        limit = SWING_RETIME * cycles
        if self._guard:
            # Aim at the alignment of the new gait that slowing alone reaches soonest: a
            # foot slowed for the speed cap then never has to speed up again (or go the
            # long way round) to get back in step.
            self.offset_shift = slowing_shift(self.offsets, np.asarray(g.offsets, dtype=np.float64))
        if self._guard:
            need = np.mod(self.target_offsets() - self.offsets, 1.0)  # >= 0: by slowing only
            need = np.where(need > 1.0 - 1e-9, 0.0, need)  # on target (up to rounding)
            fastest = self._phase_speed_cap() * dt  # phase advance this step may not exceed it
            room = np.maximum(cycles - fastest, -limit)  # lowest allowed change (< 0: room to speed up)
            settled = (np.isclose(self.duty, g.duty_factor) & np.isclose(self.stride, g.stride)
                       & np.isclose(self.stride_lift, g.stride) & np.isclose(self.step_height, g.step_height)
                       & np.isclose(self._swing_travel(), self._nominal_travel(), rtol=self._travel_tolerance(1e-3)))
            # A foot still in its old stride is slowed if its swing would be too fast; a
            # settled foot is never forced slower than its own gait.
            low = np.where(settled, np.minimum(room, 0.0), room)
            change = np.clip(need, low, limit)
            change = np.maximum(change, np.where(settled, -limit, low))
        else:
            need = np.mod(self.target_offsets() - self.offsets + 0.5, 1.0) - 0.5
            change = np.clip(need, -limit, limit)
        # Keep a retimed foot inside its swing: not past touchdown (phase 1), not back into
        # the stance it has just left (phase = duty).
        change = np.clip(change, after - 1.0 + 1e-9, after - self.duty)
        self.offsets = np.mod(self.offsets + np.where(airborne, change, 0.0), 1.0)
        if not self._feet_settled:  # once settled, only a new gait (set_rig) unsettles the feet
            self._update_settled()
        if self._guard:
            offsets_done = np.abs(np.mod(self.offsets - self.target_offsets() + 0.5, 1.0) - 0.5).max() <= 1e-9
            if offsets_done and self._stepped.all() and np.allclose(
                    self._swing_travel(), self._nominal_travel(), rtol=self._travel_tolerance(0.03)):
                self._guard = False
        if not self._guard:
            self._speed_cap = self._steady_swing_speed()

    def _plan_swings(self, legs: NDArray[np.int64], phase: NDArray[np.float64]) -> None:
        """Give feet that have just lifted off their next foothold: half a (new) stride
        ahead of where their hip's neutral point will be at touchdown — the neutral point
        at mid-stance when the body keeps its speed (the body keeps its present speed
        until touchdown)."""
        per_cycle = self.travel_per_cycle()
        self.lift_at[legs] = self.travel - per_cycle * (phase[legs] - self.duty[legs])
        self.land_at[legs] = self.travel + per_cycle * (1.0 - phase[legs])
        s_mid = self.land_at[legs] + 0.5 * self.stride[legs] * self.rig.leg_scale
        held = plan_footholds(self.rig, self.world, s_mid, legs)
        self.end[legs] = held.points
        self.end_normal[legs] = held.normals
        self.end_compromised[legs] = held.compromised
        self.compromised_count += int(held.compromised.sum())
        self.end_dir[legs] = stance_directions(self.rig, self.world, s_mid, legs)
        step_m = self.step_height[legs] * self.rig.l_rest[legs]
        self.apex[legs] = swing_apex(self.rig, self.world, self.start[legs], self.end[legs], legs, step_m,
                                     self.duty[legs], self._wave_now(), self.lift_at[legs], self.land_at[legs])

    def set_phase(self, phase: float) -> None:
        """Scrub: put the clock at ``phase`` (cycle fraction) within the current cycle; the
        body moves with it and the feet stand where the gait puts them."""
        old = self.clock
        self.clock = float(np.floor(self.clock) + (phase % 1.0))
        self.travel += self.travel_per_cycle() * (self.clock - old)
        self._adopt_all()

    # -- output -----------------------------------------------------------------------

    def frame_plan(self) -> FootPlan:
        """This frame's feet as a one-frame :class:`FootPlan` (arrays (1, L, ...))."""
        phase = self.foot_phase()
        contact = phase < self.duty
        swing = np.where(contact, 0.0, (phase - self.duty) / (1.0 - self.duty))
        end = np.where(contact[:, None], self.start, self.end)
        end_normal = np.where(contact[:, None], self.start_normal, self.end_normal)
        end_dir = np.where(contact[:, None], self.start_dir, self.end_dir)
        land_at = self.land_at.copy()
        airborne = np.nonzero(~contact)[0]
        # On flat ground the aim changes nothing, unless a swing was planned on other
        # ground (the terrain was changed under the creature).
        if airborne.size and (not self.world.terrain.flat or np.any(self.end[airborne, 1] != 0.0)):
            # Aim each swing at where it will really land if the body keeps its present speed
            # (the same spot as planned while it does), on the ground there: the foot's height
            # eases towards that, so it meets the ground without a jump even when the speed
            # or the gait changed mid-swing.
            predicted = self.travel + self.travel_per_cycle() * (1.0 - phase[airborne])
            landing = landing_points(self.rig, self.world, airborne, self.start[airborne], self.end[airborne],
                                     self.lift_at[airborne], self.land_at[airborne], predicted)
            moved = np.any(landing != self.end[airborne], axis=1)
            end[airborne] = landing
            end_normal[airborne] = np.where(moved[:, None], self.world.terrain.normal(landing[:, [0, 2]]),
                                            self.end_normal[airborne])
            land_at[airborne] = predicted
        return FootPlan(phase=phase[None], duty=self.duty[None].copy(), contact=contact[None], swing=swing[None],
                        start=self.start[None].copy(), end=end[None], start_normal=self.start_normal[None].copy(),
                        end_normal=end_normal[None], apex=self.apex[None].copy(), lift_at=self.lift_at[None].copy(),
                        land_at=land_at[None], start_dir=self.start_dir[None].copy(), end_dir=end_dir[None],
                        compromised=np.where(contact, self.start_compromised, self.end_compromised)[None])

    def frame_inputs(self) -> dict:
        """This frame's inputs for :func:`solve_motion` (stackable over frames)."""
        plan = self.frame_plan()
        swing = plan.swing[0]
        ease = smoothstep(swing)
        stride = np.where(plan.contact[0], self.stride, self.stride_lift + (self.stride - self.stride_lift) * ease)
        stride = stride * self.rig.leg_scale
        return {"clock": self.clock, "time": self.time, "travel": self.travel, "bob": self.bob,
                "stride": stride, "plan": plan, "wave": self._wave_now(),
                "trunk": self._trunk.copy(), "frequency": self.frequency,
                **dict(zip(("height_shift", "running_shift"), self._shifts(plan, stride)))}

    def _shifts(self, plan: FootPlan, stride: NDArray[np.float64]) -> tuple[float, float]:
        """What is left now of the jumps changes of duty factor have made in a posed body's
        height (m) and in how far a biped runs (the weight of its run's lean and bent
        elbows, :func:`~app.kinematics.gait.walking_weight`): a foot takes a new gait's
        duty at its touchdown or lift-off, and the body's height (a run's flights, a walk's
        key poses) and its run's lean follow the duty at once (a person's chest moved 4 cm
        in one frame as they began to run); the jumps are eased away over
        :data:`~app.kinematics.poses.HEIGHT_SETTLE` instead, the body keeping its height and
        speed (inertialization). A body without key-pose heights has no height to ease, but
        its arms' run still is (a theropod's elbows)."""
        ref = reference_foot(self.rig)
        duty = plan.duty[0]
        seen = self._height_seen
        if seen is not None and self.time < seen[1]:
            seen = None  # time went back: start afresh
        if seen is not None and self.time > seen[1] and duty[ref] != seen[0][ref]:
            dt = self.time - seen[1]
            if self.rig.poses.heights is not None:
                jump, speed, start = self._height_jump
                left = float(settle(jump, speed, self.time - start))
                rate = (left - float(settle(jump, speed, self.time - start - 1e-4))) / 1e-4
                more, faster = height_jump(self.rig, plan.phase[0], seen[0], duty, self.frequency,
                                           float(stride[ref]), dt)
                self._height_jump = (left + more, rate + faster, self.time)
            weight, began = self._running_jump
            self._running_jump = (float(settle(weight, 0.0, self.time - began)) + float(
                walking_weight(duty[ref]) - walking_weight(seen[0][ref])), self.time)  # running is 1 - walking
        self._height_seen = (duty.copy(), self.time)
        jump, speed, start = self._height_jump
        weight, began = self._running_jump
        return float(settle(jump, speed, self.time - start)), float(settle(weight, 0.0, self.time - began))

    @property
    def cross_fading(self) -> bool:
        """True while two wave shapes are being cross-faded (frame inputs alone do not say so)."""
        return self._blend < 1.0 and self._wave_from != self._wave_to

    def _waves(self, plan: FootPlan) -> tuple[FootWave, FootWave] | None:
        if not self.cross_fading:
            return None
        w = float(smoothstep(self._blend))
        old = oscillators(self.rig, plan, self._wave_from)
        new = oscillators(self.rig, plan, self._wave_to)
        return _mix_waves(old[0], new[0], w), _mix_waves(old[1], new[1], w)

    def pose(self) -> Pose:
        """The pose now."""
        f = self.frame_inputs()
        inputs = MotionInputs(clock=np.array([self.clock]), times=np.array([self.time]), plan=f["plan"],
                              travel=np.array([self.travel]), stride=f["stride"][None], bob=np.array([self.bob]),
                              wave=f["wave"], waves=self._waves(f["plan"]), trunk=f["trunk"][None],
                              frequency=np.array([f["frequency"]]), height_shift=np.array([f["height_shift"]]),
                              running_shift=np.array([f["running_shift"]]))
        return solve_motion(self.rig, self.world, inputs).pose(0)


def stack_inputs(frames: list[dict]) -> MotionInputs:
    """Frame inputs from :meth:`LiveMotion.frame_inputs` as one :class:`MotionInputs`."""
    plans = [f["plan"] for f in frames]
    plan = FootPlan(**{name: np.concatenate([getattr(p, name) for p in plans])
                       for name in FootPlan.__dataclass_fields__})
    waves = {f["wave"] for f in frames}
    return MotionInputs(clock=np.array([f["clock"] for f in frames]), times=np.array([f["time"] for f in frames]),
                        plan=plan, travel=np.array([f["travel"] for f in frames]),
                        stride=np.array([f["stride"] for f in frames]), bob=np.array([f["bob"] for f in frames]),
                        trunk=np.array([f["trunk"] for f in frames]),
                        frequency=np.array([f["frequency"] for f in frames]),
                        height_shift=np.array([f.get("height_shift", 0.0) for f in frames]),
                        running_shift=np.array([f.get("running_shift", 0.0) for f in frames]),
                        wave=waves.pop() if len(waves) == 1 else frames[-1]["wave"])
