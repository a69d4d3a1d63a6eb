"""The foot oscillators: closed-form duty factor, its inverse, continuity, exact waves."""

from __future__ import annotations

import numpy as np
import pytest

from app.kinematics.oscillator import bias_from_duty, duty_from_bias, foot_wave, peak_wave, slope_wave, touchdown_angle


def measured_duty(bias: float, samples: int = 400_000) -> float:
    """Fraction of a cycle where the seed's vertical wave says 'planted' (peak(x+pi/2) <= 0)."""
    x = (np.arange(samples) + 0.5) / samples * 2 * np.pi
    return float((peak_wave(x + np.pi / 2, bias) <= 0).mean())


@pytest.mark.parametrize("bias", np.linspace(-7, 7, 29))
def test_closed_form_duty_matches_measured_wave(bias: float) -> None:
    assert duty_from_bias(bias) == pytest.approx(measured_duty(bias), abs=2e-5)


def test_duty_reference_values() -> None:
    assert float(duty_from_bias(1.0)) == pytest.approx(0.643, abs=5e-4)
    assert float(duty_from_bias(3.0)) == pytest.approx(0.78, abs=5e-3)
    assert float(duty_from_bias(-1.6)) == pytest.approx(0.30, abs=5e-3)
    assert float(duty_from_bias(0.0)) == 0.5


def test_inverse_round_trips() -> None:
    b = np.linspace(-40, 40, 161)
    assert np.allclose(bias_from_duty(duty_from_bias(b)), b, atol=1e-9)
    d = np.linspace(0.05, 0.95, 91)
    assert np.allclose(duty_from_bias(bias_from_duty(d)), d, atol=1e-12)


def test_waves_are_continuous_through_zero_bias() -> None:
    x = np.linspace(0, 2 * np.pi, 1001)
    for b in (0.0, 1e-14, -1e-14, 1e-9, -1e-9, 1e-6, -1e-6):
        assert np.allclose(peak_wave(x, b), np.sin(x), atol=1e-5)
        assert np.allclose(slope_wave(x, b), np.sin(x), atol=1e-5)
    assert float(touchdown_angle(0.0)) == pytest.approx(np.pi / 2)
    assert float(touchdown_angle(1e-9)) == pytest.approx(np.pi / 2, abs=1e-8)


def test_skewed_wave_keeps_phase_offset_through_half_duty() -> None:
    phase = np.linspace(0, 1, 501, endpoint=False)
    centre = foot_wave(phase, 0.5, "skewed-sine")
    for d in (0.5 - 1e-9, 0.5 + 1e-9):
        near = foot_wave(phase, d, "skewed-sine")
        assert np.allclose(near.forward, centre.forward, atol=1e-6)
        assert np.allclose(near.lift, centre.lift, atol=1e-6)


def test_slope_wave_spans_exactly_minus_one_to_one() -> None:
    x = np.linspace(0, 2 * np.pi, 200_001)
    for b in (-5.0, -1.0, 0.3, 2.0, 8.0):
        w = slope_wave(x, b)
        assert w.max() == pytest.approx(1.0, abs=1e-6) and w.min() == pytest.approx(-1.0, abs=1e-6)


@pytest.mark.parametrize("shape", ["planted", "skewed-sine"])
@pytest.mark.parametrize("duty", [0.2, 0.5, 0.75, 0.9])
def test_touchdown_at_phase_zero_and_exact_duty(shape: str, duty: float) -> None:
    phase = (np.arange(10_000) + 0.5) / 10_000
    wave = foot_wave(phase, duty, shape)
    assert wave.contact.mean() == pytest.approx(duty, abs=1e-4)
    assert np.all(wave.lift[wave.contact] == 0.0)
    assert np.all(wave.lift[~wave.contact] >= 0.0)
    assert wave.lift.max() == pytest.approx(1.0, abs=1e-3)
    # lift is continuous: zero at touchdown (phase -> 1) and at lift-off (phase -> duty)
    edges = foot_wave(np.array([0.0, duty - 1e-9, duty + 1e-9, 1 - 1e-9]), duty, shape)
    assert np.allclose(edges.lift, 0.0, atol=1e-6)
    assert edges.forward[0] == pytest.approx(edges.forward[3], abs=1e-6)


def test_planted_wave_moves_the_foot_back_at_constant_speed() -> None:
    duty = 0.65
    phase = np.linspace(0.0, duty, 200, endpoint=False)
    wave = foot_wave(phase, duty, "planted")
    speed = np.diff(wave.forward) / np.diff(phase)
    assert np.allclose(speed, -1.0 / duty)
    assert wave.forward[0] == pytest.approx(0.5)


def test_unknown_wave_shape_is_rejected() -> None:
    with pytest.raises(ValueError, match="unknown wave shape"):
        foot_wave(0.1, 0.5, "square")  # type: ignore[arg-type]
