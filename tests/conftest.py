"""Shared fixtures: one headless GL context per session, golden-image comparison.

The golden images were rendered by Mesa's software rasteriser (llvmpipe); a GPU driver
draws edges and shading slightly differently. So the session pins Mesa's software
renderer where Mesa is installed (its EGL vendor file, ``LIBGL_ALWAYS_SOFTWARE``), the
renderer is printed in pytest's header, and the golden tests skip, saying why, when the
context is not llvmpipe anyway. ``tests/snapshots/RENDERER.txt`` records the renderer the
goldens were made with.
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pytest

SNAPSHOTS = Path(__file__).parent / "snapshots"
FAILED = SNAPSHOTS / "failed"
RENDERER_FILE = SNAPSHOTS / "RENDERER.txt"
MESA_EGL_VENDOR = ("/usr/share/glvnd/egl_vendor.d/50_mesa.json", "/etc/glvnd/egl_vendor.d/50_mesa.json")
SOFTWARE_RENDERER = "llvmpipe"


def _pin_software_renderer() -> str:
    """Ask for Mesa's llvmpipe before any context exists; a note on what was done."""
    vendor = next((p for p in MESA_EGL_VENDOR if os.path.exists(p)), None)
    notes = []
    if vendor and "__EGL_VENDOR_LIBRARY_FILENAMES" not in os.environ:
        os.environ["__EGL_VENDOR_LIBRARY_FILENAMES"] = vendor
        notes.append(f"EGL vendor pinned to {vendor}")
    os.environ.setdefault("LIBGL_ALWAYS_SOFTWARE", "1")
    os.environ.setdefault("GALLIUM_DRIVER", "llvmpipe")
    return "; ".join(notes) or "software renderer requested"


PINNING = _pin_software_renderer()


def golden_renderer() -> str:
    """The GL_RENDERER the golden images were made with."""
    return RENDERER_FILE.read_text(encoding="utf-8").strip() if RENDERER_FILE.exists() else "unknown"


_RENDERER: dict[str, str] = {}
_CONTEXT: dict[str, object] = {}


def session_context():
    """The session's one headless GL context (made on first use). One only: releasing a
    second standalone EGL context while another is alive corrupts the survivor's
    rendering (seen as noise in every later frame)."""
    if "ctx" not in _CONTEXT:
        from app.render.context import shared_headless_context

        _CONTEXT["ctx"] = shared_headless_context()
    return _CONTEXT["ctx"]


def current_renderer() -> str:
    """This session's GL_RENDERER, or why there is none."""
    if "name" not in _RENDERER:
        try:
            _RENDERER["name"] = session_context().info["GL_RENDERER"]
        except Exception as exc:  # no EGL at all: the GL tests report that themselves
            _RENDERER["name"] = f"none ({str(exc).splitlines()[0][:120]})"
    return _RENDERER["name"]


def pytest_collection_modifyitems(config: pytest.Config, items: list[pytest.Item]) -> None:
    """The very long runs (``long``: minutes on one core) first, so that one worker starts
    on them at once while the other works through the rest (``--dist worksteal`` gives
    each worker half the list and lets an idle one take from the other's): run after
    everything, they kept one core idle for three minutes."""
    items.sort(key=lambda item: item.get_closest_marker("long") is None)  # stable: the rest keep their order


def pytest_report_header(config: pytest.Config) -> list[str]:
    return [f"renderer: {current_renderer()} ({PINNING}); golden images made with: {golden_renderer()}"]


def pytest_addoption(parser: pytest.Parser) -> None:
    parser.addoption("--update-snapshots", action="store_true", default=False,
                     help="rewrite the golden PNGs under tests/snapshots/ from the current renderer")


@pytest.fixture(scope="session")
def gl_ctx():
    """A headless (EGL) OpenGL context shared by the rendering tests."""
    return session_context()


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

        renderer = current_renderer()
        if self.update:
            RENDERER_FILE.write_text(renderer + "\n", encoding="utf-8")
        elif SOFTWARE_RENDERER not in renderer.lower():
            pytest.skip(f"golden images were made with {golden_renderer()}; this machine renders with {renderer} "
                        "(install Mesa's llvmpipe: apt install libegl-mesa0 libgl1-mesa-dri)")
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
                                            f"(allowed {max_mean}); rendered with {renderer}, goldens made with "
                                            f"{golden_renderer()}")

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
