"""Real-time motion for the viewer: an integrated clock and seamless gait changes.

The clock advances by ``frequency * dt`` each step, so changing speed never jumps. A gait
change (preset, phase offsets, duty factor, stride, step height, bob, frequency, wave
shape) reaches each foot without a jump and without dragging a planted foot:

- each foot takes the new duty factor and step height at its next touchdown, the one
  instant where the oscillator's position does not depend on them;
- with the planted wave, a foot on the ground is locked to the ground (it moves back
  exactly as far as the ground moves, whatever the speed is doing) and its swing eases
  from wherever it lifted off to where the new stride lands it: no slip, no jump;
- each foot takes the new stride at its next lift-off, and (with the seed's skewed-sine
  waves) its swing eases from the old stride to the new one;
- each foot moves its phase offset towards the new one only while it is in the air,
  at most :data:`SWING_RETIME` of the clock's rate (its swing runs up to that much faster
  or slower), taking the shorter way round the cycle;
- no foot swings faster (peak speed over the ground) than in the faster of the two gaits'
  steady swings: a foot whose old duty factor would make it swing faster at the new
  frequency is slowed by retiming it, and catches up in later swings;
- frequency and body bob blend over :data:`BLEND_CYCLES`;
- a change of wave shape cross-fades the two oscillators over :data:`BLEND_CYCLES`.

Changes of the body or the legs (lengths, ankle lift) apply at once.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from ..spec import CreatureSpec
from .motion import Pose, foot_waves, solve_motion
from .oscillator import FootWave
from .rig import Rig, build_rig

BLEND_CYCLES = 0.35
SWING_RETIME = 0.6
SMALL_CHANGE = 0.03  # relative frequency (and absolute bob) change applied at once


def _smoothstep(x: float) -> float:
    x = min(max(x, 0.0), 1.0)
    return x * x * (3.0 - 2.0 * x)


def _mix_waves(a: FootWave, b: FootWave, w: float) -> FootWave:
    return FootWave(forward=a.forward + (b.forward - a.forward) * w, lift=a.lift + (b.lift - a.lift) * w,
                    contact=b.contact if w >= 0.5 else a.contact, swing=b.swing if w >= 0.5 else a.swing)


class LiveMotion:
    """A creature moving in real time. Call :meth:`step` with the elapsed time, then
    :meth:`pose`. Deterministic given the sequence of calls.

    Per-foot state (arrays (L,)): ``offsets`` (cycle fractions), ``duty``, ``stride``
    (mean leg rest lengths: of the current stance, or of the coming one while in the
    air), ``stride_lift`` (of the stance the foot last left) and ``step_height`` (leg rest
    lengths).
    """

    def __init__(self, spec: CreatureSpec) -> None:
        self.rig: Rig = build_rig(spec)
        self.clock = 0.0  # cycles
        self.time = 0.0  # seconds of animation time
        self.ground = 0.0  # metres the ground has moved
        self._adopt_all()

    def _adopt_all(self) -> None:
        g = self.rig.gait
        n = self.rig.leg_count
        self.offsets = np.array(g.offsets, dtype=np.float64)
        self.duty = np.full(n, g.duty_factor)
        self.stride = np.full(n, g.stride)
        self.stride_lift = self.stride.copy()
        self.step_height = np.full(n, g.step_height)
        # Ground locking (planted wave): where each planted foot touched down (metres ahead
        # of its hip) and the ground's travel then; where each swinging foot lifted off.
        reach = self.stride * float(self.rig.l_rest.mean())
        phase = self.foot_phase()
        self.touch_pos = 0.5 * reach
        self.touch_ground = self.ground - np.where(phase < self.duty, phase / self.duty, 0.0) * reach
        self.lift_pos = -0.5 * reach
        self._freq_from = self._freq_to = g.frequency
        self._bob_from = self._bob_to = g.bob
        self._wave_from = self._wave_to = g.wave
        self._blend = 1.0  # progress of the frequency / bob / wave blend, 0..1
        self._feet_settled = True
        self._speed_cap = self._steady_swing_speed()  # m/s no swinging foot may exceed
        self._guard = False  # a gait switch is under way: the speed cap applies
        self._stepped = np.ones(self.rig.leg_count, dtype=bool)  # foot took a full step since the switch
        self._landed = np.ones(self.rig.leg_count, dtype=bool)

    # The planted wave's swing, sampled: d(forward)/ds (smootherstep, per stride) and
    # d(lift)/ds (per step height) at swing progress s.
    _S = np.linspace(0.0, 1.0, 41)
    _DFWD = 30.0 * _S ** 2 * (_S - 1.0) ** 2
    _DLIFT = np.pi * np.cos(np.pi * _S)

    def _swing_terms(self, duty, travel_m, step_height):
        """Per foot and swing sample (L, 41): fore-aft and vertical speed (m/s) per unit of
        phase speed (cycles/s), for swings covering ``travel_m`` metres."""
        duty = np.asarray(duty, dtype=np.float64)[..., None]
        a = self._DFWD * np.asarray(travel_m, dtype=np.float64)[..., None] / (1.0 - duty)
        b = self._DLIFT * (np.asarray(step_height)[..., None] * self.rig.l_rest[:, None]) / (1.0 - duty)
        return a, b

    def _swing_speed(self, phase_speed, duty, travel_m, step_height, ground_speed) -> np.ndarray:
        """Peak speed over the ground (m/s) of each foot's swing at ``phase_speed``."""
        a, b = self._swing_terms(np.broadcast_to(duty, (self.rig.leg_count,)), travel_m, step_height)
        return np.hypot(ground_speed + phase_speed * a, phase_speed * b).max(axis=-1)

    def _steady_swing_speed(self) -> float:
        g = self.rig.gait
        ground = g.stride * float(self.rig.l_rest.mean()) / g.duty_factor * g.frequency
        travel = g.stride * float(self.rig.l_rest.mean())
        return float(self._swing_speed(g.frequency, g.duty_factor, travel, g.step_height, ground).max())

    def _swing_travel(self) -> np.ndarray:
        """Metres each foot's current (or, while planted, next) swing covers: from its
        lift-off point to its landing point."""
        lm = float(self.rig.l_rest.mean())
        phase = self.foot_phase()
        airborne = phase >= self.duty
        landing_now = 0.5 * self.stride * lm
        landing_next = 0.5 * self.rig.gait.stride * lm  # the stride a planted foot will take at lift-off
        lift_next = self.touch_pos - (self.ground - self.touch_ground) - (self.duty - phase) * self._ground_speed()
        travel = np.where(airborne, landing_now - self.lift_pos, landing_next - lift_next)
        fallback = 0.5 * (self.stride + self.stride_lift) * lm  # the skewed-sine waves: nominal strides
        return np.where(self._wave_now() == "planted", np.maximum(travel, 0.0), fallback)

    def _phase_speed_cap(self) -> np.ndarray:
        """Per foot, the fastest phase speed (cycles/s) that keeps its swing's peak speed
        over the ground under the cap: the smallest root over the swing samples of
        |(G + w a, w b)| = cap."""
        ground = self._ground_speed() * self.frequency
        a, b = self._swing_terms(self.duty, self._swing_travel(), self.step_height)
        cap = self._speed_cap * 0.98  # margin for what the model leaves out (hip sway, stride easing)
        q = a * a + b * b
        disc = np.maximum(ground * ground * a * a - q * (ground * ground - cap * cap), 0.0)
        roots = (-ground * a + np.sqrt(disc)) / np.maximum(q, 1e-300)
        return np.maximum(roots.min(axis=-1), 0.0)

    # -- changes ----------------------------------------------------------------------

    @property
    def spec(self) -> CreatureSpec:
        return self.rig.spec

    @property
    def blending(self) -> bool:
        """True until every foot and every blended value has reached the new gait."""
        return self._blend < 1.0 or not self._feet_settled

    def _update_settled(self) -> None:
        g = self.rig.gait
        offset_error = np.abs(np.mod(self.offsets - g.offsets + 0.5, 1.0) - 0.5).max()
        nominal = g.stride * float(self.rig.l_rest.mean())
        self._feet_settled = bool(
            offset_error <= 1e-12 and np.all(self.duty == g.duty_factor) and np.all(self.stride == g.stride)
            and np.all(self.stride_lift == g.stride) and np.all(self.step_height == g.step_height)
            and np.allclose(self._swing_travel(), nominal, rtol=1e-3, atol=1e-6))

    def set_spec(self, spec: CreatureSpec, blend: bool = True) -> None:
        """Switch to a new creature spec; gait changes blend unless ``blend`` is False."""
        frequency, bob, wave = self.frequency, self.bob, self._wave_now()
        speed_now = max(self._speed_cap, float(np.max(self._swing_speed(
            frequency, self.duty, self._swing_travel(), self.step_height, self._ground_speed() * frequency))))
        self.rig = build_rig(spec)
        g = self.rig.gait
        if not blend:
            self._adopt_all()
            return
        self._update_settled()
        offsets_change = not np.allclose(np.mod(g.offsets - self.offsets + 0.5, 1.0) - 0.5, 0.0, atol=1e-9)
        big_change = (abs(g.frequency - frequency) > SMALL_CHANGE * frequency or g.wave != wave
                      or not np.allclose(self.duty, g.duty_factor, rtol=0, atol=SMALL_CHANGE)
                      or not np.allclose(self.stride, g.stride, rtol=SMALL_CHANGE, atol=0))
        if offsets_change or big_change:
            # A gait switch: the speed cap guards it until every foot has reached the new
            # phase and taken a full step in the new gait. (Gradual changes, like a speed
            # ramp frame by frame, need no guard.)
            self._speed_cap = max(speed_now, self._steady_swing_speed())
            self._guard = True
            self._stepped = np.zeros(self.rig.leg_count, dtype=bool)
            self._landed = np.zeros(self.rig.leg_count, dtype=bool)
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
            # A blend is under way: aim it at the new values instead of starting over.
            self._freq_to, self._bob_to = g.frequency, g.bob
        else:
            self._freq_from, self._bob_from, self._wave_from = frequency, bob, wave
            self._freq_to, self._bob_to, self._wave_to = g.frequency, g.bob, g.wave
            self._blend = 0.0

    @property
    def frequency(self) -> float:
        w = _smoothstep(self._blend)
        return self._freq_from + (self._freq_to - self._freq_from) * w

    @property
    def bob(self) -> float:
        w = _smoothstep(self._blend)
        return self._bob_from + (self._bob_to - self._bob_from) * w

    def _wave_now(self) -> str:
        return self._wave_to if _smoothstep(self._blend) >= 0.5 else self._wave_from

    # -- time -------------------------------------------------------------------------

    def foot_phase(self) -> NDArray[np.float64]:
        """Each foot's phase since its touchdown, (L,)."""
        return np.mod(self.clock - self.offsets, 1.0)

    def step(self, dt: float) -> None:
        """Advance by ``dt`` seconds of animation time (0 or negative does nothing)."""
        if dt <= 0:
            return
        g = self.rig.gait
        cycles = self.frequency * dt
        before = self.foot_phase()
        self.ground += self._ground_speed() * cycles
        self.clock += cycles
        self.time += dt
        if self._blend < 1.0:
            self._blend = min(1.0, self._blend + cycles / BLEND_CYCLES)

        # Feet that lifted off during this step carry their stance's stride into the swing
        # and will land with the new one; feet that touched down take the new duty and
        # step height.
        after = self.foot_phase()
        landed = after < before
        lifted = ~landed & (before < self.duty) & (after >= self.duty)
        lm = float(self.rig.l_rest.mean())
        ground_per_cycle = self._ground_speed()
        # Ground locking: a landing foot fixes its spot (touched down `after` cycles ago);
        # a lifting foot remembers where it left the ground.
        self.touch_pos = np.where(landed, 0.5 * self.stride * lm, self.touch_pos)
        self.touch_ground = np.where(landed, self.ground - after * ground_per_cycle, self.touch_ground)
        left_at = self.touch_pos - (self.ground - (after - self.duty) * ground_per_cycle - self.touch_ground)
        self.lift_pos = np.where(lifted, left_at, self.lift_pos)
        self.stride_lift = np.where(lifted, self.stride, self.stride_lift)
        self.stride = np.where(lifted, g.stride, self.stride)
        self.duty = np.where(landed, g.duty_factor, self.duty)
        self.step_height = np.where(landed, g.step_height, self.step_height)
        self._stepped |= self._landed & lifted
        self._landed |= landed

        # Feet in the air move their phase offset towards the new one. Slowing a swing
        # (offset up) is always safe; speeding it up (offset down) only while the speed cap
        # leaves room, otherwise the foot goes the long way round by slowing.
        airborne = ~landed & (after >= self.duty)
        need = np.mod(g.offsets - self.offsets + 0.5, 1.0) - 0.5
        limit = SWING_RETIME * cycles
        if self._guard:
            fastest = self._phase_speed_cap() * dt  # phase advance this step may not exceed it
            room = np.maximum(cycles - fastest, -limit)  # lowest allowed change (< 0: room to speed up)
            need = np.where((need < 0) & (room >= 0), need + 1.0, need)
            nominal = g.stride * float(self.rig.l_rest.mean())
            settled = (np.isclose(self.duty, g.duty_factor) & np.isclose(self.stride, g.stride)
                       & np.isclose(self.stride_lift, g.stride) & np.isclose(self.step_height, g.step_height)
                       & np.isclose(self._swing_travel(), nominal, rtol=1e-3))
            # A foot still in its old stride is slowed if its swing would be too fast; a
            # settled foot is never forced slower than its own gait.
            low = np.where(settled, np.minimum(room, 0.0), room)
            change = np.clip(need, low, limit)
            change = np.maximum(change, np.where(settled, -limit, low))
        else:
            change = np.clip(need, -limit, limit)
        # Keep a retimed foot inside its swing: not past touchdown (phase 1), not back into
        # the stance it has just left (phase = duty).
        change = np.clip(change, after - 1.0 + 1e-9, after - self.duty)
        self.offsets = np.mod(self.offsets + np.where(airborne, change, 0.0), 1.0)
        self._update_settled()
        offsets_done = np.abs(np.mod(self.offsets - g.offsets + 0.5, 1.0) - 0.5).max() <= 1e-9
        travel_done = np.allclose(self._swing_travel(), g.stride * float(self.rig.l_rest.mean()), rtol=0.03)
        if self._guard and offsets_done and self._stepped.all() and travel_done:
            self._guard = False
        if not self._guard:
            self._speed_cap = self._steady_swing_speed()

    def _ground_speed(self) -> float:
        """Metres per cycle the planted feet are carried back (all feet when none is planted)."""
        planted = self.foot_phase() < self.duty
        feet = planted if planted.any() else np.ones_like(planted)
        return float(np.mean((self.stride / self.duty)[feet])) * float(self.rig.l_rest.mean())

    def set_phase(self, phase: float) -> None:
        """Scrub: put the clock at ``phase`` (cycle fraction) within the current cycle."""
        old = self.clock
        self.clock = float(np.floor(self.clock) + (phase % 1.0))
        self.ground += self._ground_speed() * (self.clock - old)

    @property
    def phase(self) -> float:
        """Where the clock is within the current cycle, [0, 1)."""
        return float(self.clock % 1.0)

    # -- output -----------------------------------------------------------------------

    def frame_inputs(self) -> dict[str, np.ndarray | float | str]:
        """This frame's oscillator inputs for :func:`solve_motion`: clock, offsets (L,),
        duty (L,), stride (L,) (in the air, eased from the stride the foot left to the one
        it will land in), step height (L,), bob, ground offset, time, wave shape."""
        phase = self.foot_phase()
        airborne = phase >= self.duty
        swing = np.where(airborne, (phase - self.duty) / (1.0 - self.duty), 0.0)
        ease = swing * swing * (3.0 - 2.0 * swing)
        stride = np.where(airborne, self.stride_lift + (self.stride - self.stride_lift) * ease, self.stride)
        forward_m = None
        if self._wave_now() == "planted" and not (self._blend < 1.0 and self._wave_from != self._wave_to):
            landing = 0.5 * self.stride * float(self.rig.l_rest.mean())
            glide = swing * swing * swing * (swing * (6.0 * swing - 15.0) + 10.0)  # the planted wave's swing
            forward_m = np.where(airborne, self.lift_pos + (landing - self.lift_pos) * glide,
                                 self.touch_pos - (self.ground - self.touch_ground))
        return {"clock": self.clock, "offsets": self.offsets.copy(), "duty": self.duty.copy(), "stride": stride,
                "step_height": self.step_height.copy(), "bob": self.bob, "ground": self.ground, "time": self.time,
                "wave": self._wave_now(), "forward_m": forward_m}

    def pose(self) -> Pose:
        """The pose now."""
        rig = self.rig
        inputs = self.frame_inputs()
        clock = np.array([self.clock])
        duty = self.duty[None, :]
        waves = None
        if self._blend < 1.0 and self._wave_from != self._wave_to:
            w = _smoothstep(self._blend)
            old = foot_waves(rig, clock, self.offsets, duty, self._wave_from)
            new = foot_waves(rig, clock, self.offsets, duty, self._wave_to)
            waves = (new[0], _mix_waves(old[1], new[1], w), _mix_waves(old[2], new[2], w))
        forward_m = None if inputs["forward_m"] is None else inputs["forward_m"][None, :]
        motion = solve_motion(rig, clock, offsets=self.offsets, duty=duty, stride=inputs["stride"][None, :],
                              step_height=self.step_height[None, :], bob=self.bob,
                              ground_offset=np.array([self.ground]), times=np.array([self.time]), waves=waves,
                              forward_m=forward_m)
        return motion.pose(0)
