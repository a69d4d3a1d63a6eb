"""The interactive viewer, end to end: a real window on Xvfb driven by real input events
(xdotool), screenshots, recording from the UI, and the no-display message."""

from __future__ import annotations

import contextlib
import json
import os
import shutil
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from app import load_creature
from app.render.scene import srgb_to_linear

pytestmark = pytest.mark.gui
GAITLAB = [sys.executable, "-m", "app"]


@pytest.fixture(scope="module")
def display():
    """A private Xvfb display (started with -displayfd so it picks a free number)."""
    for tool in ("Xvfb", "xdotool"):
        if shutil.which(tool) is None:
            pytest.fail(f"{tool} is missing; run 'bash .ci/setup --test' (it installs xvfb and xdotool)")
    read_fd, write_fd = os.pipe()
    proc = subprocess.Popen(["Xvfb", "-displayfd", str(write_fd), "-screen", "0", "1600x900x24", "-nolisten", "tcp"],
                            pass_fds=(write_fd,), stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    os.close(write_fd)
    with os.fdopen(read_fd) as pipe:
        number = pipe.readline().strip()
    if not number:
        proc.kill()
        pytest.fail("Xvfb did not start")
    yield f":{number}"
    proc.terminate()
    proc.wait(timeout=10)


def env_for(display: str) -> dict:
    return {**os.environ, "DISPLAY": display}


def read_state(path: Path, timeout: float = 120.0, until=None) -> dict:
    """The viewer's state dump, once it exists (and satisfies ``until``). The timeout is only a
    cap for a viewer that never gets there: on a loaded machine it may take long."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if path.exists():
            try:
                state = json.loads(path.read_text())
            except (OSError, json.JSONDecodeError):
                state = None
            if state is not None and (until is None or until(state)):
                return state
        time.sleep(0.1)
    raise AssertionError(f"viewer state {path} not reached in {timeout} s")


def after_frames(dump: Path, frames: int = 3, timeout: float = 120.0) -> dict:
    """The state once the viewer has drawn ``frames`` whole frames after this call: input sent
    before it has then been read, however slow the frames (ImGui reads a press, the moves
    after it and the release in separate frames, but a burst that arrives within one slow
    frame collapses: a drag becomes a click)."""
    sent = time.time_ns()
    first = read_state(dump, timeout, until=lambda s: dump.stat().st_mtime_ns > sent)
    return read_state(dump, timeout, until=lambda s: s["frame"] >= first["frame"] + frames)


def xdotool(display: str, *args: str) -> str:
    out = subprocess.run(["xdotool", *args], env=env_for(display), capture_output=True, text=True, timeout=30)
    assert out.returncode == 0, out.stderr
    return out.stdout.strip()


@contextlib.contextmanager
def running_viewer(display: str, cwd: Path, *args: str):
    """Start ``gaitlab view ARGS`` with a state dump; yield (process, dump path, window id)
    once it is drawing; kill it afterwards if it is still running."""
    dump = cwd / "state.json"
    proc = subprocess.Popen([*GAITLAB, "view", *args, "--dump-state", str(dump)], env=env_for(display), cwd=cwd,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        read_state(dump, until=lambda s: s["frame"] >= 10)
        window = xdotool(display, "search", "--sync", "--name", "Gaitlab").splitlines()[0]
        yield proc, dump, window
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()


def quit_viewer(display: str, proc: subprocess.Popen, window: str) -> None:
    """Ctrl+Q with the pointer over the window; the viewer must exit cleanly."""
    xdotool(display, "mousemove", "--window", window, "400", "200")
    xdotool(display, "key", "ctrl+q")
    assert proc.wait(timeout=30) == 0
    assert "Traceback" not in proc.stderr.read()


def centre(rect) -> tuple[str, str]:
    x0, y0, x1, y1 = rect
    return str(int((x0 + x1) / 2)), str(int((y0 + y1) / 2))


def creature_pixels(image: np.ndarray, hex_color: str, tolerance: float = 14.0) -> int:
    """Pixels whose colour is a shade of ``hex_color`` (shading scales brightness)."""
    rgb = np.sqrt(srgb_to_linear(hex_color)) * 255
    img = image.astype(np.float64)
    scale = (img @ rgb) / (rgb @ rgb)
    return int((np.abs(img - scale[..., None] * rgb).max(axis=-1) < tolerance).sum())


def test_window_opens_with_the_dog_walking_and_the_panels(display: str, tmp_path: Path) -> None:
    shot = tmp_path / "shot.png"
    out = subprocess.run([*GAITLAB, "view", "--frames", "45", "--screenshot", str(shot), "--size", "1024x640"],
                         env=env_for(display), capture_output=True, text=True, timeout=120, cwd=tmp_path)
    assert out.returncode == 0, out.stderr
    image = np.asarray(Image.open(shot).convert("RGB"))
    assert image.shape == (640, 1024, 3)
    sidebar, scene = image[:, :300], image[:, 420:]
    # The panels: a dark sidebar with light text on it.
    assert np.median(sidebar) < 60 and (sidebar.min(axis=-1) > 180).mean() > 0.01
    # The creature: body and both legs' colours in the scene part.
    look = load_creature("dog").look
    assert creature_pixels(scene, look.body_color) > 5000
    # One smooth body in its coat: no legs coloured by side (that is a View option).
    assert creature_pixels(scene, look.left_color) < 20 and creature_pixels(scene, look.right_color) < 20


def test_the_camera_follows_a_travelling_creature(display: str, tmp_path: Path) -> None:
    """Five seconds along a circle over hills: the spider is still in the middle of the view."""
    shot, dump = tmp_path / "shot.png", tmp_path / "state.json"
    out = subprocess.run([*GAITLAB, "view", "spider", "--path", "circle:r=2", "--terrain", "hills:amp=0.05",
                          "--frames", "300", "--screenshot", str(shot), "--size", "1024x640", "--hide-ui",
                          "--dump-state", str(dump)],
                         env=env_for(display), capture_output=True, text=True, timeout=180, cwd=tmp_path)
    assert out.returncode == 0, out.stderr
    state = json.loads(dump.read_text())
    assert state["time"] == pytest.approx(5.0) and state["error"] is None
    image = np.asarray(Image.open(shot).convert("RGB"))
    middle = image[160:480, 256:768]
    look = load_creature("spider").look
    assert creature_pixels(middle, look.body_color) > 2000  # the body, in the middle of the frame


def test_real_input_changes_the_creature_and_pauses(display: str, tmp_path: Path) -> None:
    with running_viewer(display, tmp_path, "--size", "1024x640") as (proc, dump, window):
        state = read_state(dump, until=lambda s: s["frame"] >= 20 and "leg_type.hind.unguligrade" in s["widgets"])
        assert state["playing"] and state["creature"]["legs"]["hind"]["ankle_lift"] == 62

        # Click the hind legs' "unguligrade" button.
        x, y = centre(state["widgets"]["leg_type.hind.unguligrade"])
        xdotool(display, "mousemove", "--window", window, x, y, "click", "1")
        state = read_state(dump, until=lambda s: s["creature"]["legs"]["hind"]["ankle_lift"] > 75)

        # Drag the fore femur slider to the right.
        x0, y0, x1, y1 = state["widgets"]["legs.fore.femur"]
        ym = str(int((y0 + y1) / 2))
        start = state["creature"]["legs"]["fore"]["femur"]
        xdotool(display, "mousemove", "--window", window, str(int(x0 + 10)), ym)
        for step in (("mousedown", "1"), ("mousemove", "--window", window, str(int(x0 + 60)), ym),
                     ("mousemove", "--window", window, str(int(x1 - 30)), ym), ("mouseup", "1")):
            after_frames(dump)  # each step read in a frame of its own, as a hand's drag is
            xdotool(display, *step)
        dragged = read_state(dump, until=lambda s: s["creature"]["legs"]["fore"]["femur"] > start + 0.1)
        femur = dragged["creature"]["legs"]["fore"]["femur"]

        # Ctrl+Z takes the drag back in one step; Ctrl+Y makes it again.
        time.sleep(1.0)  # a moment after the drag, so it is one finished edit
        xdotool(display, "mousemove", "--window", window, "700", "300")
        xdotool(display, "keydown", "ctrl", "sleep", "0.3", "key", "z", "sleep", "0.3", "keyup", "ctrl")
        read_state(dump, until=lambda s: s["creature"]["legs"]["fore"]["femur"] == start)
        xdotool(display, "keydown", "ctrl", "sleep", "0.3", "key", "y", "sleep", "0.3", "keyup", "ctrl")
        read_state(dump, until=lambda s: s["creature"]["legs"]["fore"]["femur"] == femur)

        # Space pauses: the clock stops.
        xdotool(display, "mousemove", "--window", window, "700", "300")
        xdotool(display, "key", "space")
        paused = read_state(dump, until=lambda s: not s["playing"])
        later = read_state(dump, until=lambda s: s["frame"] >= paused["frame"] + 40)
        assert later["clock"] == paused["clock"] and not later["playing"]

        # F1 opens the help, Ctrl+Q quits.
        xdotool(display, "key", "F1")
        read_state(dump, until=lambda s: s["show_help"])
        quit_viewer(display, proc, window)


def test_a_dragged_wings_slider_grows_wings_on_the_live_body(display: str, tmp_path: Path) -> None:
    """The Body rows have wings and beak sliders (the beak's at most the head's length): a
    drag on the bird's wings slider lengthens them, with no error."""
    with running_viewer(display, tmp_path, "bird", "--size", "1024x720") as (proc, dump, window):
        state = read_state(dump, until=lambda s: "body.wings" in s["widgets"] and "body.beak" in s["widgets"])
        assert state["creature"]["body"]["wings"] == pytest.approx(0.42)
        x0, y0, x1, y1 = state["widgets"]["body.wings"]
        ym = str(int((y0 + y1) / 2))
        xdotool(display, "mousemove", "--window", window, str(int(x0 + 0.45 * (x1 - x0))), ym)
        for step in (("mousedown", "1"), ("mousemove", "--window", window, str(int(x0 + 0.7 * (x1 - x0))), ym),
                     ("mousemove", "--window", window, str(int(x0 + 0.85 * (x1 - x0))), ym), ("mouseup", "1")):
            after_frames(dump)
            xdotool(display, *step)
        grown = read_state(dump, until=lambda s: s["creature"]["body"]["wings"] > 0.6)
        assert grown["error"] is None
        quit_viewer(display, proc, window)


def test_f12_takes_the_3d_view_and_paused_shows(display: str, tmp_path: Path) -> None:
    """F12 saves the 3-D view alone; Shift+F12 the whole window; a paused viewer says so."""
    with running_viewer(display, tmp_path, "--size", "1024x640") as (proc, dump, window):
        read_state(dump, until=lambda s: s["frame"] >= 20)
        xdotool(display, "mousemove", "--window", window, "700", "300")
        xdotool(display, "key", "F12")
        read_state(dump, until=lambda s: "screenshot saved" in (s["status"] or ""))
        (scene,) = tmp_path.glob("gaitlab-dog-*.png")
        image = np.asarray(Image.open(scene).convert("RGB"))
        assert image.shape[0] == 640 and image.shape[1] < 1024 - 300  # no sidebar, no panels
        assert np.median(image[:, :40]) > 120  # sky and ground where the dark sidebar would be
        xdotool(display, "key", "space")
        read_state(dump, until=lambda s: not s["playing"])
        xdotool(display, "keydown", "shift", "sleep", "0.3", "key", "F12", "sleep", "0.3", "keyup", "shift")
        read_state(dump, until=lambda s: len(list(tmp_path.glob("gaitlab-dog-*.png"))) == 2)
        whole = max(tmp_path.glob("gaitlab-dog-*.png"), key=lambda p: p.stat().st_mtime_ns)
        image = np.asarray(Image.open(whole).convert("RGB")).astype(int)
        assert image.shape == (640, 1024, 3)
        top = image[:60, 380:]  # the PAUSED sign: amber text at the top of the 3-D view
        amber = (top[..., 0] > 200) & (top[..., 1] > 150) & (top[..., 2] < 140)
        assert amber.sum() > 20
        quit_viewer(display, proc, window)


def load_from_file_field(display: str, dump: Path, window: str, path: Path) -> None:
    """Type ``path`` into the File panel's field and press Load. The tall panels open at
    the start are folded first, so the File panel is on screen (each click seen by a dump
    made after it, however slowly a loaded machine draws)."""
    for title in ("Creature", "Gait"):
        click_widget(display, dump, f"panel.{title}")
    state = read_state(dump, until=lambda s: s["widgets"]["panel.File"][3] < 650)
    x, y = centre(state["widgets"]["panel.File"])
    xdotool(display, "mousemove", "--window", window, x, y, "click", "1")
    state = read_state(dump, until=lambda s: "file" in s["widgets"] and "load" in s["widgets"])
    x, y = centre(state["widgets"]["file"])
    xdotool(display, "mousemove", "--window", window, x, y, "click", "1", "sleep", "0.3", "keydown", "ctrl",
            "sleep", "0.3", "key", "a", "sleep", "0.3", "keyup", "ctrl", "sleep", "0.2", "type", "--delay", "30",
            str(path))
    read_state(dump, until=lambda s: True)
    time.sleep(0.5)
    x, y = centre(read_state(dump)["widgets"]["load"])
    xdotool(display, "mousemove", "--window", window, x, y, "click", "1")


def test_the_file_field_loads_where_no_dialog_opens(display: str, tmp_path: Path) -> None:
    """On a bare Xvfb display no native file dialog can open: the path field is the way in."""
    from app.resources import creatures_dir

    mine = tmp_path / "mycat.toml"
    mine.write_text((creatures_dir() / "cat.toml").read_text().replace('name = "cat"', 'name = "mycat"'))
    with running_viewer(display, tmp_path, "--size", "1024x700") as (proc, dump, window):
        load_from_file_field(display, dump, window, mine)
        state = read_state(dump, until=lambda s: s["creature"]["name"] == "mycat")
        assert str(mine) in state["status"]

        def click(name: str) -> None:
            x, y = centre(read_state(dump)["widgets"][name])
            xdotool(display, "mousemove", "--window", window, x, y, "click", "1")

        # Save over the file just loaded: asked first, overwritten only on a second click.
        before = mine.read_text()
        mine.write_text(before + "# the user's own note\n")
        click("save")
        read_state(dump, until=lambda s: "exists: save again to overwrite it" in (s["status"] or ""))
        assert mine.read_text().endswith("# the user's own note\n")  # not yet
        time.sleep(0.3)
        click("save")
        read_state(dump, until=lambda s: (s["status"] or "").startswith("saved"))
        assert "# the user's own note" not in mine.read_text() and not list(tmp_path.glob(".*partial*"))

        # A shipped preset is never overwritten, whatever the field says.
        preset = creatures_dir() / "cat.toml"
        shipped = preset.read_bytes()
        x, y = centre(read_state(dump)["widgets"]["file"])
        xdotool(display, "mousemove", "--window", window, x, y, "click", "1", "sleep", "0.3", "keydown", "ctrl",
                "sleep", "0.3", "key", "a", "sleep", "0.3", "keyup", "ctrl", "sleep", "0.2", "type", "--delay", "30",
                str(preset))
        time.sleep(0.5)
        click("save")
        read_state(dump, until=lambda s: "is one of Gaitlab's preset creatures" in (s["error"] or ""))
        time.sleep(0.3)
        click("save")
        time.sleep(1.0)
        assert preset.read_bytes() == shipped

        # Reset everything asks first.
        time.sleep(0.3)
        click("reset_all")
        read_state(dump, until=lambda s: "press reset again" in (s["error"] or ""))
        quit_viewer(display, proc, window)


def test_the_file_field_opens_a_rigged_model(display: str, tmp_path: Path) -> None:
    """A .glb typed in the File panel's field and loaded: the model walks in the view (its
    own mesh: the fox's orange), its bone lengths marked as its own."""
    fox = Path(__file__).parent / "data" / "models" / "Fox.glb"
    with running_viewer(display, tmp_path, "--size", "1024x700") as (proc, dump, window):
        load_from_file_field(display, dump, window, fox)
        state = read_state(dump, until=lambda s: s["creature"]["name"] == "Fox")
        assert state["model_bones"] and state["error"] is None and str(fox) in state["status"]
        time.sleep(1.0)
        xdotool(display, "mousemove", "--window", window, "700", "300", "key", "F12")
        read_state(dump, until=lambda s: "screenshot saved" in (s["status"] or ""))
        (scene,) = tmp_path.glob("gaitlab-Fox-*.png")
        image = np.asarray(Image.open(scene).convert("RGB")).astype(int)
        orange = (image[..., 0] > 150) & (image[..., 1] > 50) & (image[..., 1] < 0.75 * image[..., 0]) \
            & (image[..., 2] < 0.5 * image[..., 0])
        assert orange.sum() > 500  # the fox's own coat
        quit_viewer(display, proc, window)


def gif_frames(path: Path) -> list[np.ndarray]:
    frames = []
    with Image.open(path) as gif:
        for i in range(gif.n_frames):
            gif.seek(i)
            frames.append(np.asarray(gif.convert("RGB")))
    return frames


def test_recording_from_the_ui_matches_the_cli(display: str, tmp_path: Path) -> None:
    ui_dir, cli_dir = tmp_path / "ui", tmp_path / "cli"
    ui_dir.mkdir()
    cli_dir.mkdir()
    with running_viewer(display, ui_dir, "cat", "--size", "900x600") as (proc, dump, window):
        xdotool(display, "mousemove", "--window", window, "700", "300")
        xdotool(display, "key", "g")  # record with the Record panel's defaults: cat.gif, 2 cycles, 480x360
        state = read_state(dump, timeout=120, until=lambda s: s["status"].startswith("wrote"))
        assert "cat.gif" in state["status"]
        quit_viewer(display, proc, window)
    out = subprocess.run([*GAITLAB, "render", "cat", "-o", "cat.gif"], cwd=cli_dir, capture_output=True, text=True,
                         timeout=120)
    assert out.returncode == 0, out.stderr
    ui, cli = gif_frames(ui_dir / "cat.gif"), gif_frames(cli_dir / "cat.gif")
    assert len(ui) == len(cli) > 10
    for a, b in zip(ui, cli):
        assert np.array_equal(a, b)


def test_no_display_gives_one_line_and_exit_2(tmp_path: Path) -> None:
    env = {k: v for k, v in os.environ.items() if k not in ("DISPLAY", "WAYLAND_DISPLAY")}
    out = subprocess.run([*GAITLAB, "view"], env=env, capture_output=True, text=True, timeout=60, cwd=tmp_path)
    assert out.returncode == 2 and "Traceback" not in out.stderr
    line, = out.stderr.strip().splitlines()
    assert "no display" in line and "xvfb-run gaitlab view" in line and "gaitlab render" in line


def test_window_survives_resizing(display: str, tmp_path: Path) -> None:
    with running_viewer(display, tmp_path, "--size", "800x500") as (proc, dump, window):
        for w, h in (("1200", "700"), ("200", "120"), ("1", "1")):
            xdotool(display, "windowsize", window, w, h)
            time.sleep(0.3)
        for _ in range(10):  # the last resize can race the earlier ones: repeat until it shows
            xdotool(display, "windowsize", window, "640", "400")
            try:
                state = read_state(dump, timeout=3.0, until=lambda s: s["window"]["size"] == [640, 400])
                break
            except AssertionError:
                continue
        else:
            raise AssertionError("the window never reported its final size 640x400")
        assert state["window"]["framebuffer"] == [640, 400]  # the sizes kept from the resize events
        before = state["frame"]
        read_state(dump, until=lambda s: s["frame"] > before + 20)  # still drawing
        quit_viewer(display, proc, window)


MINIMISED_SCRIPT = """
import sys
from pathlib import Path
from app import load_creature
from app.cast import Actor
from app.ui import viewer
from app.ui.window import GlfwWindow

real = GlfwWindow.framebuffer_size
calls = {"n": 0}

def framebuffer_size(self):
    calls["n"] += 1
    return (0, 0) if 30 <= calls["n"] < 120 else real.fget(self)

GlfwWindow.framebuffer_size = property(framebuffer_size)
options = viewer.ViewerOptions(size=(640, 400), frames=60, screenshot=Path(sys.argv[1]), presets=["dog"])
sys.exit(viewer.run_viewer((Actor(load_creature("dog")),), options))
"""


def test_minimised_window_zero_framebuffer_does_not_crash(display: str, tmp_path: Path) -> None:
    """A minimised window has a 0x0 framebuffer: frames must go on without drawing.
    (Under Xvfb with no window manager nothing minimises, so the size is faked.)"""
    shot = tmp_path / "after.png"
    out = subprocess.run([sys.executable, "-c", MINIMISED_SCRIPT, str(shot)], env=env_for(display),
                         capture_output=True, text=True, timeout=120, cwd=tmp_path)
    assert out.returncode == 0, out.stderr
    assert shot.exists()


def dumps_while(display: str, dump: Path, seconds: float, *keys: str) -> list[dict]:
    """Hold ``keys`` for ``seconds`` (xdotool keydown/keyup), collecting every state dump
    written meanwhile (one before the keys go down, one after they come up)."""
    seen = [read_state(dump)]
    for key in keys:
        xdotool(display, "keydown", key)
    end = time.monotonic() + seconds
    while time.monotonic() < end:
        state = read_state(dump, until=lambda s: s["frame"] > seen[-1]["frame"])
        seen.append(state)
    for key in keys:
        xdotool(display, "keyup", key)
    seen.append(read_state(dump, until=lambda s: s["frame"] > seen[-1]["frame"]))
    return seen


def moved_against_speed(states: list[dict]) -> tuple[float, float]:
    """Distance the body moved over ``states`` and the integral of its reported speed."""
    root = np.array([s["root"] for s in states])[:, [0, 2]]
    steps = np.linalg.norm(np.diff(root, axis=0), axis=1)
    speed = np.array([s["drive"]["speed"] for s in states])
    t = np.array([s["time"] for s in states])
    return float(steps.sum()), float((0.5 * (speed[1:] + speed[:-1]) * np.diff(t)).sum())


def test_drive_mode_w_speeds_up_by_the_reported_speed_and_a_turns_left(display: str, tmp_path: Path) -> None:
    with running_viewer(display, tmp_path, "dog", "--size", "1024x640") as (proc, dump, window):
        xdotool(display, "mousemove", "--window", window, "700", "300")
        xdotool(display, "key", "w")  # the first press starts driving
        start = read_state(dump, until=lambda s: s["drive"] is not None)
        held = dumps_while(display, dump, 2.0, "w")
        moving = [s for s in held if s["drive"] is not None]
        moved, expected = moved_against_speed(moving)
        assert abs(moved - expected) <= 0.1 * expected, (moved, expected)
        assert moving[-1]["drive"]["speed"] > 2.0 * start["drive"]["speed"]
        root0, root1 = np.array(moving[0]["root"]), np.array(moving[-1]["root"])
        assert root1[2] - root0[2] > 0.9 * moved  # straight ahead, +Z
        # At a steady speed the body covers its reported speed x time.
        steady = read_state(dump, until=lambda s: abs(s["drive"]["speed"] - s["drive"]["target"]) < 1e-6)
        later = read_state(dump, until=lambda s: s["time"] > steady["time"] + 1.0)
        moved, expected = moved_against_speed([steady, later])
        assert abs(moved - expected) <= 0.1 * expected, (moved, expected)
        # A turns left (+X for a creature facing +Z), with the curvature positive meanwhile.
        turning = dumps_while(display, dump, 1.5, "a")
        assert max(s["drive"]["curvature"] for s in turning) > 0.0
        assert turning[-1]["root"][0] - turning[0]["root"][0] > 0.3
        assert all(s["error"] is None for s in turning)
        # Esc stops driving: the panels' gait again.
        xdotool(display, "key", "Escape")
        assert read_state(dump, until=lambda s: s["drive"] is None)["error"] is None
        quit_viewer(display, proc, window)


def click_widget(display: str, dump: Path, key: str) -> None:
    """Click the centre of the widget ``key`` (from the state dump's widget rectangles),
    then wait for a dump made after the click: a panel that opened moves the widgets
    below it, and the next click must see where they went (the viewer dumps every 20
    frames and at least every 0.2 s)."""
    state = read_state(dump, until=lambda s: key in s["widgets"])
    xdotool(display, "mousemove", *centre(state["widgets"][key]), "click", "1")
    read_state(dump, until=lambda s: s["frame"] >= state["frame"] + 40)


def test_terrain_slider_regenerates_the_ground_without_a_planted_foot_jump(display: str, tmp_path: Path) -> None:
    with running_viewer(display, tmp_path, "dog", "--terrain", "hills:amp=0.04,wavelength=1.7", "--size",
                        "1024x720") as (proc, dump, window):
        for header in ("panel.Creature", "panel.Gait", "panel.Terrain"):
            click_widget(display, dump, header)
        before = read_state(dump, until=lambda s: "terrain.amp" in s["widgets"])
        assert before["terrain"].startswith("hills:amp=0.04")
        x0, y0, x1, y1 = before["widgets"]["terrain.amp"]
        # Press on the knob (ImGui sliders jump to where they are pressed): 0.04 of 0..1 m.
        x, y = x0 + 0.04 * (x1 - x0), int((y0 + y1) / 2)
        xdotool(display, "mousemove", str(int(x)), str(y))
        after_frames(dump)
        xdotool(display, "mousedown", "1")
        for dx in range(3, 18, 3):  # a drag over several frames, to about 0.1 m
            after_frames(dump, 1)
            xdotool(display, "mousemove", str(int(x) + dx), str(y))
        after_frames(dump)
        xdotool(display, "mouseup", "1")
        after = read_state(dump, until=lambda s: s["terrain"] != before["terrain"])
        later = read_state(dump, until=lambda s: s["time"] > after["time"] + 1.5)
        amp = float(later["terrain"].split("amp=")[1].split(",")[0])
        assert amp > 0.04 and later["error"] is None
        assert later["planted_jump_max"] < 1e-3
        quit_viewer(display, proc, window)


def test_a_click_on_the_ground_adds_a_waypoint_and_the_creature_goes_there(display: str, tmp_path: Path) -> None:
    with running_viewer(display, tmp_path, "dog", "--size", "1024x720") as (proc, dump, window):
        for header in ("panel.Creature", "panel.Gait", "panel.Path", "path.edit"):
            click_widget(display, dump, header)
        # Move first, then click: ImGui would read a jump and a press in one frame as a drag.
        xdotool(display, "mousemove", "900", "620")
        time.sleep(0.4)
        xdotool(display, "click", "1")
        added = read_state(dump, until=lambda s: s["waypoints"] or s["error"])
        assert added["error"] is None and len(added["waypoints"]) == 1
        target = np.array(added["waypoints"][0])
        start = np.array(added["root"])[[0, 2]]
        assert np.linalg.norm(target - start) > 0.3  # somewhere to go
        reached = read_state(dump, until=lambda s: not s["waypoints"])
        assert np.linalg.norm(np.array(reached["root"])[[0, 2]] - target) < 0.6  # just passed it
        assert reached["planted_jump_max"] < 1e-3 and reached["error"] is None
        # A click on the sky adds nothing and says why.
        xdotool(display, "mousemove", "700", "30")
        time.sleep(0.4)
        xdotool(display, "click", "1")
        sky = read_state(dump, until=lambda s: s["error"] is not None)
        assert "no ground under the cursor" in sky["error"] and not sky["waypoints"]
        quit_viewer(display, proc, window)


def test_clicks_are_clicks_at_any_frame_rate_and_the_view_holds_still(display: str, tmp_path: Path) -> None:
    """A press that jitters a few pixels before its release, and a press read in the same
    frame as the jump to it (a slow frame), are clicks: each adds a waypoint and neither
    turns the camera. While waypoints are edited the follow camera does not turn."""
    with running_viewer(display, tmp_path, "dog", "--size", "1024x720") as (proc, dump, window):
        for header in ("panel.Creature", "panel.Gait", "panel.Path", "path.edit"):
            click_widget(display, dump, header)
        before = read_state(dump)["camera"]
        xdotool(display, "mousemove", "900", "620")
        time.sleep(0.4)
        xdotool(display, "mousedown", "1")
        time.sleep(0.3)
        xdotool(display, "mousemove", "903", "622")  # a hand's tremor while pressing
        time.sleep(0.3)
        xdotool(display, "mouseup", "1")
        one = read_state(dump, until=lambda s: s["waypoints"] or s["error"])
        assert one["error"] is None and len(one["waypoints"]) == 1
        # The jump and the press in one event burst: ImGui reads them in one frame.
        xdotool(display, "mousemove", "820", "560", "click", "1")
        two = read_state(dump, until=lambda s: len(s["waypoints"]) >= 2 or s["error"])
        assert two["error"] is None and len(two["waypoints"]) == 2
        later = read_state(dump, until=lambda s: s["frame"] >= two["frame"] + 40)["camera"]
        for camera in (one["camera"], two["camera"], later):
            assert camera["azimuth"] == pytest.approx(before["azimuth"], abs=1e-6)  # no orbit, no turn
            assert camera["elevation"] == pytest.approx(before["elevation"], abs=1e-6)
        quit_viewer(display, proc, window)


def test_the_path_panel_shows_the_route_the_creature_walks(display: str, tmp_path: Path) -> None:
    """Started on a circle from the command line, the Path panel reads circle, with its
    radius and turn; a waypoint route read from the panel's own combo stays put."""
    with running_viewer(display, tmp_path, "dog", "--path", "circle:r=3,dir=right", "--size",
                        "1024x720") as (proc, dump, window):
        for header in ("panel.Creature", "panel.Gait", "panel.Path"):
            click_widget(display, dump, header)
        state = read_state(dump, until=lambda s: "path.kind" in s["widgets"])
        assert state["path_panel"] == {"kind": "circle", "r": 3.0, "dir": "right"}
        assert state["path"].startswith("circle:r=3")
        quit_viewer(display, proc, window)


def test_r_recovers_the_view_of_a_creature_up_a_flight_of_stairs(display: str, tmp_path: Path) -> None:
    """Once the dog has climbed the stairs, R frames it where it is, not at the foot of
    the flight: its root is in the window and the camera aims at its height."""
    with running_viewer(display, tmp_path, "dog", "--terrain", "stairs:rise=0.2,run=0.35,steps=12,start=1",
                        "--size", "1024x720") as (proc, dump, window):
        up = read_state(dump, until=lambda s: s["root"][1] > 0.6, timeout=180.0)
        xdotool(display, "mousemove", "700", "300")
        xdotool(display, "key", "r")
        after = read_state(dump, until=lambda s: s["frame"] >= up["frame"] + 40)
        width, height = after["window"]["size"]
        x, y = after["screen"][0]
        assert 0 <= x < width and 0 <= y < height, (x, y)
        assert abs(after["camera"]["target"][1] - after["root"][1]) < 0.5
        quit_viewer(display, proc, window)


def test_the_layout_holds_still(display: str, tmp_path: Path) -> None:
    """Closing panels (the sidebar no longer overflows) keeps every slider's width: the
    scrollbar's room is reserved; a description that gains a line (fore legs now
    unguligrade) moves nothing below it."""
    with running_viewer(display, tmp_path, "dog", "--size", "1024x720") as (proc, dump, window):
        before = read_state(dump)
        first, lift = before["widgets"], before["creature"]["legs"]["fore"]["ankle_lift"]
        click_widget(display, dump, "leg_type.fore.unguligrade")
        hooves = read_state(dump, until=lambda s: s["creature"]["legs"]["fore"]["ankle_lift"] != lift)
        moved = hooves["widgets"]
        for key in ("legs.fore.ankle_lift", "legs.hind.femur", "body.length"):
            assert moved[key][1] == pytest.approx(first[key][1], abs=0.5), key  # same row, same place
        for header in ("panel.Creature", "panel.Gait"):
            click_widget(display, dump, header)
        short = read_state(dump)["widgets"]
        assert short["phase"][2] - short["phase"][0] == pytest.approx(first["phase"][2] - first["phase"][0], abs=0.5)
        quit_viewer(display, proc, window)


def test_ticking_an_overlay_moves_no_row(display: str, tmp_path: Path) -> None:
    """The footprint count's slider is always there (greyed while footprints are off):
    ticking footprints moves nothing below it."""
    with running_viewer(display, tmp_path, "dog", "--panels", "view", "--size", "1024x720") as (proc, dump, window):
        before = read_state(dump, until=lambda s: "overlay.footprints" in s["widgets"])
        below = [key for key in before["widgets"] if key.startswith("arc")]
        assert below
        click_widget(display, dump, "overlay.footprints")
        after = read_state(dump, until=lambda s: s["frame"] > before["frame"] + 40)
        for key in below:
            assert after["widgets"][key][1] == pytest.approx(before["widgets"][key][1], abs=0.5), key
        quit_viewer(display, proc, window)


def test_picking_another_terrain_moves_no_panel(display: str, tmp_path: Path) -> None:
    """The Terrain panel keeps room for the kind with the most rows: from flat to stairs
    (five sliders) the Path panel below stays where it was."""
    with running_viewer(display, tmp_path, "dog", "--panels", "terrain,path", "--size",
                        "1024x720") as (proc, dump, window):
        before = read_state(dump, until=lambda s: "path.kind" in s["widgets"])
        xdotool(display, "mousemove", *centre(before["widgets"]["terrain.kind"]), "click", "1")
        time.sleep(0.5)
        # The kinds' list opens below the combo: flat, slope, hills, stairs, ...
        x0, y0, x1, y1 = before["widgets"]["terrain.kind"]
        from app.worlds.kinds import TERRAIN_KINDS
        index = list(TERRAIN_KINDS).index("stairs")
        row = y1 - y0
        xdotool(display, "mousemove", str(int((x0 + x1) / 2)), str(int(y1 + (index + 0.5) * row)), "click", "1")
        after = read_state(dump, until=lambda s: s["terrain"].startswith("stairs"))
        after = read_state(dump, until=lambda s: s["frame"] > after["frame"] + 40)
        assert after["widgets"]["path.kind"][1] == pytest.approx(before["widgets"]["path.kind"][1], abs=0.5)
        quit_viewer(display, proc, window)


def test_a_herd_scene_opens_and_renders(display: str, tmp_path: Path) -> None:
    from app.resources import scenes_dir

    shots = {}
    for name, args in (("one", ["dog"]), ("herd", [str(scenes_dir() / "herd.toml")])):
        shot = tmp_path / f"{name}.png"
        out = subprocess.run([*GAITLAB, "view", *args, "--frames", "60", "--screenshot", str(shot), "--hide-ui",
                              "--size", "800x600"], env=env_for(display), capture_output=True, text=True, timeout=180,
                             cwd=tmp_path)
        assert out.returncode == 0 and "Traceback" not in out.stderr, out.stderr
        shots[name] = np.asarray(Image.open(shot).convert("RGB"))
    body = load_creature("dog").look.body_color
    one, herd = creature_pixels(shots["one"], body), creature_pixels(shots["herd"], body)
    assert one > 500 and herd > 500
    # Many bodies: the herd's tan spreads over more separate places than one dog's.
    mask = np.zeros(shots["herd"].shape[:2], dtype=bool)
    rgb = np.sqrt(srgb_to_linear(body)) * 255
    img = shots["herd"].astype(float)
    scale = (img @ rgb) / (rgb @ rgb)
    mask = np.abs(img - scale[..., None] * rgb).max(axis=-1) < 14.0
    from scipy import ndimage

    blobs = ndimage.label(mask)[1]
    assert blobs >= 8


def test_a_click_on_a_scene_creature_puts_it_in_the_panels(display: str, tmp_path: Path) -> None:
    from app.resources import scenes_dir

    with running_viewer(display, tmp_path, str(scenes_dir() / "garden.toml"), "--size", "1024x720") as (
            proc, dump, window):
        state = read_state(dump)
        assert state["scene"] == ["ant", "centipede"] and state["selected"] == 0
        assert state["creature"]["name"] == "ant"
        # The camera follows the ant: wait until the centipede is in view, then pause so
        # it stays where the dump says.
        in_view = lambda s: 420 < s["screen"][1][0] < 990 and 40 < s["screen"][1][1] < 680
        xdotool(display, "mousemove", "700", "700")
        for _ in range(5):
            read_state(dump, until=in_view)
            xdotool(display, "key", "space")
            paused = read_state(dump, until=lambda s: not s["playing"])
            paused = read_state(dump, until=lambda s, p=paused: s["frame"] > p["frame"])
            if in_view(paused):
                break
            xdotool(display, "key", "space")  # it walked out before the pause: play on, try again
        assert in_view(paused)
        x, y = paused["screen"][1]  # the centipede's body on screen
        xdotool(display, "mousemove", str(int(x)), str(int(y)))
        time.sleep(0.4)
        xdotool(display, "click", "1")
        picked = read_state(dump, until=lambda s: s["selected"] == 1)
        assert picked["creature"]["name"] == "centipede" and picked["error"] is None
        quit_viewer(display, proc, window)


def test_key_poses_panel_styles_timing_and_arcs(display: str, tmp_path: Path) -> None:
    """The Key poses panel: a style button re-keys the walk; the frames-per-cycle row
    shows the timing; the View panel's arc boxes draw the last cycle's paths, beaded."""
    with running_viewer(display, tmp_path, "human", "--size", "1024x720") as (proc, dump, window):
        for header in ("panel.Creature", "panel.Gait", "panel.Key poses"):
            click_widget(display, dump, header)
        state = read_state(dump, until=lambda s: "style.double-bounce" in s["widgets"])
        assert "gait.frames_per_cycle" in state["widgets"] and "poses.down_height" in state["widgets"]
        assert state["creature"]["poses"]["style"] == "normal"
        click_widget(display, dump, "style.double-bounce")
        bounced = read_state(dump, until=lambda s: s["creature"]["poses"].get("style") == "double-bounce")
        poses = bounced["creature"]["poses"]
        assert poses["down_height"] < poses["contact_height"] and poses["up_height"] < poses["pass_height"]
        assert bounced["error"] is None
        click_widget(display, dump, "poses.ghosts")
        assert read_state(dump, until=lambda s: s["ghosts"] == 5)["error"] is None
        click_widget(display, dump, "poses.ghosts")
        click_widget(display, dump, "panel.Key poses")
        click_widget(display, dump, "panel.View")
        click_widget(display, dump, "arc.toe")
        click_widget(display, dump, "arc.hand")
        drawn = read_state(dump, until=lambda s: min(s["arcs"].get("toe", 0), s["arcs"].get("hand", 0)) > 20
                           and s["arc_beads"] >= 16)
        assert set(drawn["arcs"]) == {"toe", "hand"} and drawn["error"] is None
        shot = tmp_path / "arcs.png"
        xdotool(display, "mousemove", "--window", window, "700", "300")
        image = np.asarray(Image.open(_grab(display, shot)).convert("RGB")).astype(int)
        yellow = (image[..., 0] > 200) & (image[..., 1] > 150) & (image[..., 2] < 90)  # the toe's arc
        assert yellow.sum() > 100
        # The Body panel's overlap: a click at 40% along the arms' delay slider (0..0.5 cycle).
        click_widget(display, dump, "panel.View")
        click_widget(display, dump, "panel.Body")
        x0, y0, x1, y1 = read_state(dump, until=lambda s: "overlap.arms" in s["widgets"])["widgets"]["overlap.arms"]
        xdotool(display, "mousemove", str(int(x0 + 0.4 * (x1 - x0))), str(int((y0 + y1) / 2)))
        time.sleep(0.4)
        xdotool(display, "click", "1")
        delayed = read_state(dump, until=lambda s: abs(s["creature"].get("overlap", {}).get("arms", 0.0) - 0.2) < 0.03)
        assert delayed["error"] is None
        quit_viewer(display, proc, window)


def _grab(display: str, path: Path) -> Path:
    """A screenshot of the whole X display."""
    from PIL import ImageGrab

    ImageGrab.grab(xdisplay=display).save(path)
    return path
