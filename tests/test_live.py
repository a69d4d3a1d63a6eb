"""Real-time motion: integrated clock and smooth gait changes (no foot jumps)."""

from __future__ import annotations

import functools

import numpy as np
import pytest

from app import build_rig, load_creature
from app.gaits import gaits_for
from app.kinematics.live import BLEND_CYCLES, LiveMotion

DT = 1.0 / 60.0


def run(live: LiveMotion, seconds: float) -> np.ndarray:
    """Foot (ball) positions in ground coordinates, (frames, 4, 3)."""
    feet = []
    for _ in range(int(round(seconds / DT))):
        live.step(DT)
        pose = live.pose()
        ball = pose.joints[:, 3].copy()
        ball[:, 2] += pose.ground_offset  # where the foot is on the (moving) ground
        feet.append(ball)
    return np.array(feet)


def max_step(feet: np.ndarray) -> float:
    return float(np.linalg.norm(np.diff(feet, axis=0), axis=-1).max())


def steady_max_step(spec, seconds: float = 1.2, alignments: int = 6) -> float:
    """The largest frame-to-frame foot displacement of a steady gait, over runs started
    at several sub-frame offsets (a single run only samples the swing peak by chance)."""
    best = 0.0
    for k in range(alignments):
        live = LiveMotion(build_rig(spec))
        live.step(DT * k / alignments)
        best = max(best, max_step(run(live, seconds)))
    return best


def test_clock_integrates_frequency() -> None:
    dog = load_creature("dog")
    live = LiveMotion(build_rig(dog))
    f = live.rig.gait.frequency
    for _ in range(60):
        live.step(DT)
    assert live.clock == pytest.approx(f * 1.0)
    live.set_rig(build_rig(dog.with_overrides({"gait.frequency": 2 * f})))
    before = live.clock
    live.step(DT)
    assert live.clock - before == pytest.approx(f * DT)  # the old speed holds at the first step...
    for _ in range(200):
        live.step(DT)
    last = live.clock
    live.step(DT)
    assert live.clock - last == pytest.approx(2 * f * DT)  # ...and the new one after the blend


@functools.cache
def dog_steady_max_step(gait: str) -> float:
    return steady_max_step(load_creature("dog").with_overrides({"gait.preset": gait}))


@pytest.mark.parametrize("to_gait", [g for g in gaits_for(2) if g != "walk"])
def test_gait_switch_has_no_foot_jump(to_gait: str) -> None:
    spec = load_creature("dog")
    reference = max(dog_steady_max_step("walk"), dog_steady_max_step(to_gait))
    live = LiveMotion(build_rig(spec))
    before = run(live, 0.73)  # switch mid-step
    live.set_rig(build_rig(spec.with_overrides({"gait.preset": to_gait})))
    during = run(live, 5.5)  # the feet reach the new gait within a few cycles
    feet = np.concatenate([before, during])
    # 5%: the reference samples the peak at 60 fps, and a switch that completes within a
    # cycle and a half may swing a foot a few percent faster than either steady gait.
    assert max_step(feet) <= reference * 1.05
    assert not live.blending  # every foot has reached the new gait


def test_wave_shape_change_cross_fades() -> None:
    spec = load_creature("horse")
    live = LiveMotion(build_rig(spec))
    before = run(live, 0.5)
    live.set_rig(build_rig(spec.with_overrides({"gait.wave": "skewed-sine"})))
    assert live.blending
    during = run(live, BLEND_CYCLES / live.rig.gait.frequency + 0.2)
    reference = max(steady_max_step(spec), steady_max_step(spec.with_overrides({"gait.wave": "skewed-sine"})))
    assert max_step(np.concatenate([before, during])) <= reference * 1.01


def test_bone_length_change_applies_at_once() -> None:
    dog = load_creature("dog")
    live = LiveMotion(build_rig(dog))
    live.step(DT)
    live.set_rig(build_rig(dog.with_overrides({"legs.hind.femur": 0.3})))
    bones = np.linalg.norm(np.diff(live.pose().joints, axis=1), axis=-1)
    assert bones[2, 0] == pytest.approx(0.3)


def test_scrub_sets_the_phase_within_the_cycle() -> None:
    live = LiveMotion(build_rig(load_creature("dog")))
    for _ in range(100):
        live.step(DT)
    cycle = np.floor(live.clock)
    live.set_phase(0.25)
    assert live.clock == pytest.approx(cycle + 0.25) and live.phase == pytest.approx(0.25)
