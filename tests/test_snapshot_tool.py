"""The golden-image comparison itself: tolerance, and what it writes on failure."""

from __future__ import annotations

import conftest
import numpy as np
import pytest
from conftest import Snapshot


def test_snapshot_tolerates_tiny_differences_and_reports_real_ones(tmp_path, monkeypatch) -> None:
    monkeypatch.setattr(conftest, "SNAPSHOTS", tmp_path)
    monkeypatch.setattr(conftest, "FAILED", tmp_path / "failed")
    monkeypatch.setattr(conftest, "RENDERER_FILE", tmp_path / "RENDERER.txt")
    monkeypatch.setitem(conftest._RENDERER, "name", "llvmpipe (LLVM 15.0.6, 256 bits)")
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


def test_goldens_record_their_renderer_and_skip_on_another(tmp_path, monkeypatch) -> None:
    monkeypatch.setattr(conftest, "SNAPSHOTS", tmp_path)
    monkeypatch.setattr(conftest, "FAILED", tmp_path / "failed")
    monkeypatch.setattr(conftest, "RENDERER_FILE", tmp_path / "RENDERER.txt")
    monkeypatch.setitem(conftest._RENDERER, "name", "llvmpipe (LLVM 15.0.6, 256 bits)")
    image = np.zeros((8, 8, 3), np.uint8)
    Snapshot(update=True).check("probe", image)
    assert (tmp_path / "RENDERER.txt").read_text().strip() == "llvmpipe (LLVM 15.0.6, 256 bits)"
    monkeypatch.setitem(conftest._RENDERER, "name", "NVIDIA GeForce RTX 4070/PCIe/SSE2")
    with pytest.raises(pytest.skip.Exception, match="made with llvmpipe .* renders with NVIDIA"):
        Snapshot(update=False).check("probe", image + 1)  # not compared: it would fail


def test_the_session_renders_with_the_software_rasteriser() -> None:
    """Where Mesa is installed (CI, this project's machines) the pinning takes effect."""
    renderer = conftest.current_renderer()
    if renderer.startswith("none"):
        pytest.skip(f"no OpenGL: {renderer}")
    if not any(__import__("os").path.exists(p) for p in conftest.MESA_EGL_VENDOR):
        pytest.skip("Mesa's EGL vendor file is not installed here")
    assert "llvmpipe" in renderer
