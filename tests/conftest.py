"""Shared fixtures: one headless GL context per session, golden-image comparison."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

SNAPSHOTS = Path(__file__).parent / "snapshots"
FAILED = SNAPSHOTS / "failed"


def pytest_addoption(parser: pytest.Parser) -> None:
    parser.addoption("--update-snapshots", action="store_true", default=False,
                     help="rewrite the golden PNGs under tests/snapshots/ from the current renderer")


@pytest.fixture(scope="session")
def gl_ctx():
    """A headless (EGL) OpenGL context shared by the rendering tests."""
    from app.render.context import create_headless_context

    ctx = create_headless_context()
    yield ctx
    ctx.release()


class Snapshot:
    """Compare images with golden PNGs, with a tolerance for tiny rasteriser differences.

    An image matches when at most ``max_bad_fraction`` of its pixels differ by more than
    ``threshold`` (0-255, any channel) and the mean absolute difference is at most
    ``max_mean``. On a mismatch the actual image and an amplified difference image are
    written to tests/snapshots/failed/.
    """

    def __init__(self, update: bool) -> None:
        self.update = update

    def check(self, name: str, image: np.ndarray, threshold: int = 24, max_bad_fraction: float = 0.004,
              max_mean: float = 1.0) -> None:
        from PIL import Image

        golden_path = SNAPSHOTS / f"{name}.png"
        if self.update or not golden_path.exists():
            if not self.update:
                pytest.fail(f"no golden image {golden_path.name}; run pytest --update-snapshots and review it")
            SNAPSHOTS.mkdir(parents=True, exist_ok=True)
            Image.fromarray(image).save(golden_path)
            return
        golden = np.asarray(Image.open(golden_path).convert("RGB"))
        if golden.shape != image.shape:
            self._fail(name, image, golden, f"size {image.shape[1]}x{image.shape[0]} != golden "
                                            f"{golden.shape[1]}x{golden.shape[0]}")
        diff = np.abs(image.astype(np.int16) - golden.astype(np.int16)).max(axis=-1)
        bad = float((diff > threshold).mean())
        mean = float(np.abs(image.astype(np.float64) - golden).mean())
        if bad > max_bad_fraction or mean > max_mean:
            self._fail(name, image, golden, f"{bad:.2%} of pixels differ by more than {threshold} "
                                            f"(allowed {max_bad_fraction:.2%}), mean difference {mean:.2f} "
                                            f"(allowed {max_mean})")

    @staticmethod
    def _fail(name: str, image: np.ndarray, golden: np.ndarray, why: str) -> None:
        from PIL import Image

        FAILED.mkdir(parents=True, exist_ok=True)
        Image.fromarray(image).save(FAILED / f"{name}.actual.png")
        if golden.shape == image.shape:
            amplified = np.clip(np.abs(image.astype(np.int16) - golden.astype(np.int16)) * 8, 0, 255)
            Image.fromarray(amplified.astype(np.uint8)).save(FAILED / f"{name}.diff.png")
        pytest.fail(f"snapshot {name}: {why}; see tests/snapshots/failed/{name}.actual.png and .diff.png")


@pytest.fixture
def snapshot(request: pytest.FixtureRequest) -> Snapshot:
    return Snapshot(request.config.getoption("--update-snapshots"))
