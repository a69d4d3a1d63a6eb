"""Creature files: presets, round trips, overrides and every kind of bad input."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from app import build_rig, load_creature
from app.errors import SpecError
from app.gaits import GAIT_PRESETS
from app.resources import preset_creature_names
from app.spec import parse_override, resolve_phases

PRESETS = ["ant", "bear", "bird", "cat", "centipede", "deer", "dog", "horse", "human", "spider", "theropod"]


def test_presets_are_all_there() -> None:
    assert preset_creature_names() == PRESETS


@pytest.mark.parametrize("name", PRESETS)
def test_save_load_round_trip(name: str, tmp_path: Path) -> None:
    spec = load_creature(name)
    path = spec.save(tmp_path / f"{name}.toml")
    again = load_creature(path)
    assert again == spec
    assert again.save(tmp_path / "twice.toml").read_text() == path.read_text()
    assert not list(tmp_path.glob(".*"))  # no temporary files left behind


def test_overrides_change_exactly_the_named_keys() -> None:
    dog = load_creature("dog")
    spec = dog.with_overrides({"gait.duty_factor": 0.8, "legs.hind.femur": 0.25, "body.length": 0.6})
    assert spec.gait.duty_factor == 0.8
    assert spec.leg("hind").femur == 0.25 and spec.leg("fore").femur == dog.leg("fore").femur
    assert spec.body.length == 0.6
    assert dog.gait.duty_factor is None  # the original is frozen and untouched


def test_changing_preset_resets_gait_adjustments_unless_given_together() -> None:
    dog = load_creature("dog").with_overrides({"gait.duty_factor": 0.8, "gait.step_height": 0.3})
    trot = dog.with_overrides({"gait.preset": "trot"})
    assert trot.gait.preset == "trot" and trot.gait.duty_factor is None and trot.gait.step_height is None
    tuned = dog.with_overrides({"gait.step_height": 0.05, "gait.preset": "trot"})
    assert tuned.gait.step_height == 0.05


def test_per_foot_phase_override_starts_from_the_current_phases() -> None:
    spec = load_creature("dog").with_overrides({"gait.phases.LF": 0.3})
    phases = dict(zip(("LF", "RF", "LH", "RH"), resolve_phases(spec.gait, spec.foot_names)))
    assert phases == pytest.approx({"LF": 0.3, "RF": 0.75, "LH": 0.0, "RH": 0.5})


def test_bias_gives_duty_through_closed_form() -> None:
    spec = load_creature("dog").with_overrides({"gait.bias": 1.0})
    assert build_rig(spec).gait.duty_factor == pytest.approx(0.643, abs=5e-4)


@pytest.mark.parametrize("gait", list(GAIT_PRESETS))
def test_every_gait_resolves_on_every_creature_it_fits(gait: str) -> None:
    for name in PRESETS:
        spec = load_creature(name)
        if not GAIT_PRESETS[gait].fits(spec.pair_count):
            with pytest.raises(SpecError, match=f"is a gait for .*this creature has {spec.pair_count} leg pair"):
                spec.with_overrides({"gait.preset": gait})
            continue
        rig = build_rig(spec.with_overrides({"gait.preset": gait}))
        assert rig.gait.offsets.shape == (2 * spec.pair_count,)
        assert 0.0 < rig.gait.frequency < 10.0


def write(tmp_path: Path, text: str) -> Path:
    path = tmp_path / "bad.toml"
    path.write_text(text)
    return path


def dog_text(**replace: str) -> str:
    text = (Path(__file__).parents[1] / "creatures" / "dog.toml").read_text()
    for old, new in replace.items():
        assert old in text
        text = text.replace(old, new)
    return text


def expect_error(source, match: str) -> str:
    with pytest.raises(SpecError) as info:
        load_creature(source) if not callable(source) else source()
    message = str(info.value)
    assert "\n" not in message
    assert match in message, message
    return message


def test_unknown_creature_lists_presets() -> None:
    msg = expect_error("dgo", "unknown creature 'dgo'")
    assert "did you mean 'dog'" in msg and all(p in msg for p in PRESETS)


def test_syntax_error_names_file_and_line(tmp_path: Path) -> None:
    text = dog_text(**{"femur = 0.21": "femur = = 0.21"})
    line = text.splitlines().index("femur = = 0.21") + 1
    path = write(tmp_path, text)
    msg = expect_error(path, "TOML syntax error")
    assert str(path) in msg and f"line {line}," in msg


def test_unknown_key_names_path_and_nearest(tmp_path: Path) -> None:
    msg = expect_error(write(tmp_path, dog_text(**{"femur = 0.21": "femru = 0.21"})), "legs.hind.femru")
    assert "did you mean 'legs.hind.femur'" in msg


@pytest.mark.parametrize("value", ["0.0", "-0.2", "nan", "inf", "-inf", '"long"'])
def test_bad_lengths(tmp_path: Path, value: str) -> None:
    expect_error(write(tmp_path, dog_text(**{"tibia = 0.23": f"tibia = {value}"})), "legs.hind.tibia")


@pytest.mark.parametrize("value", ["0.05", "0.95", "1.2", "0", "-0.5"])
def test_duty_factor_outside_open_range(tmp_path: Path, value: str) -> None:
    text = dog_text(**{'preset = "walk"': f'preset = "walk"\nduty_factor = {value}'})
    expect_error(write(tmp_path, text), "gait.duty_factor")


def test_unknown_gait(tmp_path: Path) -> None:
    msg = expect_error(write(tmp_path, dog_text(**{'preset = "walk"': 'preset = "wlak"'})), "gait.preset = 'wlak'")
    assert "did you mean 'walk'" in msg and "trot" in msg


def test_unreachable_geometry(tmp_path: Path) -> None:
    text = dog_text(**{"femur = 0.21": "femur = 0.90", "tibia = 0.23": "tibia = 0.05"})
    expect_error(write(tmp_path, text), "unreachable geometry")


def test_duty_and_bias_together(tmp_path: Path) -> None:
    text = dog_text(**{'preset = "walk"': 'preset = "walk"\nduty_factor = 0.6\nbias = 1.0'})
    expect_error(write(tmp_path, text), "not both")


def test_missing_table(tmp_path: Path) -> None:
    text = dog_text().split("[legs.hind]")[0]
    expect_error(write(tmp_path, text), "[legs.hind]")


def test_override_errors_are_one_line() -> None:
    dog = load_creature("dog")
    expect_error(lambda: parse_override("gait.dutyfactor=0.5"), "did you mean 'gait.duty_factor'")
    key, value = parse_override("gait.duty_factor=abc")
    expect_error(lambda: dog.with_overrides({key: value}), "expected a number")
    expect_error(lambda: dog.with_overrides({"legs.hind.femur": math.nan}), "not a finite number")
    expect_error(lambda: parse_override("novalue"), "expected KEY=VALUE")


def test_parse_override_reads_toml_values() -> None:
    assert parse_override("gait.duty_factor=0.7") == ("gait.duty_factor", 0.7)
    assert parse_override("gait.preset=trot") == ("gait.preset", "trot")
    assert parse_override('gait.wave="skewed-sine"') == ("gait.wave", "skewed-sine")
    assert parse_override("body.segments=10") == ("body.segments", 10)


def test_rig_lengths_follow_the_design_formula() -> None:
    leg = load_creature("dog").leg("hind")
    rig = build_rig(load_creature("dog"))
    a = math.radians(leg.ankle_lift)
    l_max = math.sqrt((leg.femur + leg.tibia) ** 2 - (leg.metatarsus * math.cos(a)) ** 2) + leg.metatarsus * math.sin(a)
    assert rig.l_max[2] == pytest.approx(l_max)
    assert rig.l_rest[2] == pytest.approx(l_max * (1 - leg.natural_bend))
    assert np.all(rig.l_min < rig.l_rest)
