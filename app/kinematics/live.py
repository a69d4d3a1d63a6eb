"""Real-time motion for the viewer: an integrated clock and seamless gait changes.

The clock advances by ``frequency * dt`` each step, so changing speed never jumps. A gait
change (preset, phase offsets, duty factor, stride, step height, bob, frequency, wave
shape) reaches each foot without a jump and without dragging a planted foot:

- each foot takes the new duty factor and step height at its next touchdown, the one
  instant where the oscillator's position does not depend on them;
- each foot takes the new stride at its next lift-off, and its swing eases from the old
  stride to the new one, so it lands exactly where the new stance begins;
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
        self._freq_from = self._freq_to = g.frequency
        self._bob_from = self._bob_to = g.bob
        self._wave_from = self._wave_to = g.wave
        self._blend = 1.0  # progress of the frequency / bob / wave blend, 0..1
        self._feet_settled = True
        self._speed_cap = self._steady_swing_speed()  # m/s no swinging foot may exceed

    # The planted wave's swing, sampled: d(forward)/ds (smootherstep, per stride) and
    # d(lift)/ds (per step height) at swing progress s.
    _S = np.linspace(0.0, 1.0, 41)
    _DFWD = 30.0 * _S ** 2 * (_S - 1.0) ** 2
    _DLIFT = np.pi * np.cos(np.pi * _S)

    def _swing_terms(self, duty, stride_travel, step_height):
        """Per foot and swing sample (L, 41): fore-aft and vertical speed (m/s) per unit of
        phase speed (cycles/s)."""
        duty = np.asarray(duty, dtype=np.float64)[..., None]
        a = self._DFWD * (np.asarray(stride_travel)[..., None] * float(self.rig.l_rest.mean())) / (1.0 - duty)
        b = self._DLIFT * (np.asarray(step_height)[..., None] * self.rig.l_rest[:, None]) / (1.0 - duty)
        return a, b

    def _swing_speed(self, phase_speed, duty, stride_travel, step_height, ground_speed) -> np.ndarray:
        """Peak speed over the ground (m/s) of each foot's swing at ``phase_speed``."""
        a, b = self._swing_terms(np.broadcast_to(duty, (self.rig.leg_count,)), stride_travel, step_height)
        return np.hypot(ground_speed + phase_speed * a, phase_speed * b).max(axis=-1)

    def _steady_swing_speed(self) -> float:
        g = self.rig.gait
        ground = g.stride * float(self.rig.l_rest.mean()) / g.duty_factor * g.frequency
        return float(self._swing_speed(g.frequency, g.duty_factor, g.stride, g.step_height, ground).max())

    def _phase_speed_cap(self) -> np.ndarray:
        """Per foot, the fastest phase speed (cycles/s) that keeps its swing's peak speed
        over the ground under the cap: the smallest root over the swing samples of
        |(G + w a, w b)| = cap."""
        ground = self._ground_speed() * self.frequency
        a, b = self._swing_terms(self.duty, 0.5 * (self.stride + self.stride_lift), self.step_height)
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
        self._feet_settled = bool(
            offset_error <= 1e-12 and np.all(self.duty == g.duty_factor) and np.all(self.stride == g.stride)
            and np.all(self.stride_lift == g.stride) and np.all(self.step_height == g.step_height))

    def set_spec(self, spec: CreatureSpec, blend: bool = True) -> None:
        """Switch to a new creature spec; gait changes blend unless ``blend`` is False."""
        frequency, bob, wave = self.frequency, self.bob, self._wave_now()
        speed_now = max(self._speed_cap, float(np.max(self._swing_speed(
            frequency, self.duty, 0.5 * (self.stride + self.stride_lift), self.step_height,
            self._ground_speed() * frequency))))
        self.rig = build_rig(spec)
        g = self.rig.gait
        if not blend:
            self._adopt_all()
            return
        self._update_settled()
        self._speed_cap = max(speed_now, self._steady_swing_speed())
        if (g.frequency, g.bob, g.wave) != (self._freq_to, self._bob_to, self._wave_to):
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
        self.stride_lift = np.where(lifted, self.stride, self.stride_lift)
        self.stride = np.where(lifted, g.stride, self.stride)
        self.duty = np.where(landed, g.duty_factor, self.duty)
        self.step_height = np.where(landed, g.step_height, self.step_height)

        # Feet in the air move their phase offset towards the new one. Slowing a swing
        # (offset up) is always safe; speeding it up (offset down) only while the speed cap
        # leaves room, otherwise the foot goes the long way round by slowing.
        airborne = ~landed & (after >= self.duty)
        need = np.mod(g.offsets - self.offsets + 0.5, 1.0) - 0.5
        limit = SWING_RETIME * cycles
        if self.blending:
            fastest = self._phase_speed_cap() * dt  # phase advance this step may not exceed it
            room = np.maximum(cycles - fastest, -limit)  # lowest allowed change (< 0: room to speed up)
            need = np.where((need < 0) & (room >= 0), need + 1.0, need)
            settled = (np.isclose(self.duty, g.duty_factor) & np.isclose(self.stride, g.stride)
                       & np.isclose(self.stride_lift, g.stride) & np.isclose(self.step_height, g.step_height))
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
        if not self._feet_settled:
            self._update_settled()
        if not self.blending:
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

    def pose(self) -> Pose:
        """The pose now."""
        rig = self.rig
        clock = np.array([self.clock])
        duty = self.duty[None, :]
        waves = None
        if self._blend < 1.0 and self._wave_from != self._wave_to:
            w = _smoothstep(self._blend)
            old = foot_waves(rig, clock, self.offsets, duty, self._wave_from)
            new = foot_waves(rig, clock, self.offsets, duty, self._wave_to)
            waves = (new[0], _mix_waves(old[1], new[1], w), _mix_waves(old[2], new[2], w))
        # In the air the stride eases from the one the foot left to the one it will land in.
        phase = self.foot_phase()
        airborne = phase >= self.duty
        swing = np.where(airborne, (phase - self.duty) / (1.0 - self.duty), 0.0)
        ease = swing * swing * (3.0 - 2.0 * swing)
        stride = np.where(airborne, self.stride_lift + (self.stride - self.stride_lift) * ease, self.stride)
        motion = solve_motion(rig, clock, offsets=self.offsets, duty=duty, stride=stride[None, :],
                              step_height=self.step_height[None, :], bob=self.bob,
                              ground_offset=np.array([self.ground]), times=np.array([self.time]), waves=waves)
        return motion.pose(0)
