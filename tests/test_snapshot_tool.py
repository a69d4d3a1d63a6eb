"""The golden-image comparison itself: tolerance, and what it writes on failure."""

from __future__ import annotations

import numpy as np
import pytest

import conftest
from conftest import Snapshot


def test_snapshot_tolerates_tiny_differences_and_reports_real_ones(tmp_path, monkeypatch) -> None:
    monkeypatch.setattr(conftest, "SNAPSHOTS", tmp_path)
    monkeypatch.setattr(conftest, "FAILED", tmp_path / "failed")
    rng = np.random.default_rng(0)
    image = rng.integers(0, 255, size=(40, 60, 3), dtype=np.uint8)
    Snapshot(update=True).check("probe", image)
    assert (tmp_path / "probe.png").exists()

    nearly = image.copy()
    nearly[0, 0] = nearly[0, 0] // 2  # one pixel off: within tolerance
    Snapshot(update=False).check("probe", nearly)

    broken = image.copy()
    broken[:10] = 0  # a quarter of the image changed
    with pytest.raises(pytest.fail.Exception, match="differ by more than"):
        Snapshot(update=False).check("probe", broken)
    assert (tmp_path / "failed" / "probe.actual.png").exists()
    assert (tmp_path / "failed" / "probe.diff.png").exists()


def test_missing_golden_fails_without_update(tmp_path, monkeypatch) -> None:
    monkeypatch.setattr(conftest, "SNAPSHOTS", tmp_path)
    with pytest.raises(pytest.fail.Exception, match="no golden image"):
        Snapshot(update=False).check("absent", np.zeros((4, 4, 3), np.uint8))
