"""The layer direction of ARCHITECTURE.md, enforced with import-linter (contracts in
pyproject.toml): kinematics and analysis import neither creature files nor OpenGL; the
renderer never opens a window; nothing imports upwards."""

from __future__ import annotations

import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).parents[1]


def test_import_contracts_are_kept() -> None:
    script = Path(sys.executable).with_name("lint-imports")
    command = str(script) if script.exists() else shutil.which("lint-imports")
    if command is None:
        pytest.skip("import-linter is not installed (pip install '.[test]')")
    out = subprocess.run([command, "--no-cache"], capture_output=True, text=True, cwd=ROOT, timeout=120)
    assert out.returncode == 0, out.stdout[-3000:] + out.stderr[-2000:]
    assert "0 broken" in out.stdout


def test_headless_rendering_never_loads_the_window_libraries() -> None:
    code = ("import sys, app.recording.job, app.cli, app.analysis; "
            "bad = [m for m in ('glfw', 'imgui_bundle') if m in sys.modules]; print(bad); sys.exit(bool(bad))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT, timeout=60)
    assert out.returncode == 0, out.stdout + out.stderr


def test_the_command_line_starts_without_numpy() -> None:
    """``gaitlab --version`` and ``--help`` build the whole parser without loading numpy,
    scipy or the kinematics (issue 13: they start in well under half a second; the
    timing itself is in bench/bench_startup.py)."""
    code = ("import sys, app.cli; from app.cli import build_parser; build_parser(); "
            "heavy = [m for m in ('numpy', 'scipy', 'moderngl', 'app.kinematics', 'app.spec') if m in sys.modules]; "
            "print(heavy); sys.exit(bool(heavy))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT, timeout=60)
    assert out.returncode == 0, out.stdout + out.stderr
    version = subprocess.run([sys.executable, "-m", "app", "--version"], capture_output=True, text=True, cwd=ROOT,
                             timeout=60)
    assert version.returncode == 0 and version.stdout.startswith("gaitlab ")
