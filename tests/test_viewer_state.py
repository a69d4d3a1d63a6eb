"""What every viewer control does to the creature and the view — no window needed."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from app import load_creature
from app.gaits import GAIT_PRESETS
from app.kinematics.oscillator import duty_from_bias
from app.ui.state import ViewerState


@pytest.fixture
def state() -> ViewerState:
    return ViewerState(load_creature("dog"))


def test_slider_sets_the_key_and_reset_restores_it(state: ViewerState) -> None:
    assert state.set("legs.hind.femur", 0.3)
    assert state.spec.leg("hind").femur == 0.3 and state.is_modified("legs.hind.femur")
    assert state.live.rig.femur[2] == pytest.approx(0.3)  # the motion uses it at once
    assert state.reset("legs.hind.femur")
    assert state.spec.leg("hind").femur == 0.21 and not state.is_modified("legs.hind.femur")


def test_rejected_value_keeps_the_creature_and_shows_the_error(state: ViewerState) -> None:
    before = state.spec
    assert not state.set("gait.duty_factor", 0.99)
    assert state.spec == before
    assert "gait.duty_factor" in state.error and "(0.05, 0.95)" in state.error
    assert state.set("gait.duty_factor", 0.6) and state.error is None


def test_gait_values_show_the_preset_numbers_until_edited(state: ViewerState) -> None:
    assert state.get("gait.duty_factor") == pytest.approx(GAIT_PRESETS["walk"].duty_factor)
    assert state.get("gait.front_back") == 0.25 and state.get("gait.left_right") == 0.5
    assert state.get("gait.phases.RF") == pytest.approx(0.75)
    assert not state.is_modified("gait.duty_factor")


def test_duty_and_bias_are_linked(state: ViewerState) -> None:
    state.set_bias(1.0)
    assert state.get("gait.duty_factor") == pytest.approx(float(duty_from_bias(1.0)))
    state.set_duty(0.75)
    assert float(duty_from_bias(state.get("gait.bias"))) == pytest.approx(0.75, abs=1e-9)
    assert state.spec.gait.bias is None  # setting one clears the other


def test_gait_preset_switch_blends(state: ViewerState) -> None:
    state.set("gait.step_height", 0.3)
    assert state.set_gait("gallop")
    assert state.spec.gait.preset == "gallop" and state.spec.gait.step_height is None
    assert state.live.blending
    assert not state.set_gait("moonwalk") and "unknown gait" in state.error


def test_per_foot_phase_edit_makes_explicit_phases_and_reset_returns(state: ViewerState) -> None:
    state.set("gait.phases.LF", 0.4)
    assert state.spec.gait.phases is not None and not state.gait_is_symmetric
    assert state.get("gait.phases.LF") == pytest.approx(0.4)
    state.reset("gait.phases.LF")
    assert state.spec.gait.phases is None and state.gait_is_symmetric


@pytest.mark.parametrize("kind, lo, hi", [("plantigrade", 0, 25), ("digitigrade", 25, 75), ("unguligrade", 75, 90)])
def test_leg_type_buttons(state: ViewerState, kind: str, lo: float, hi: float) -> None:
    assert state.set_leg_type("fore", kind)
    assert lo <= state.spec.leg("fore").ankle_lift < hi and state.leg_type("fore") == kind
    assert state.spec.leg("hind").ankle_lift == 62  # the other pair is untouched


def test_playback_controls(state: ViewerState) -> None:
    clock = state.live.clock
    state.advance(0.5)
    assert state.live.clock > clock
    state.toggle_play()
    paused = state.live.clock
    state.advance(0.5)
    assert state.live.clock == paused and not state.playing
    state.step_frame()
    assert state.live.clock > paused
    state.scrub(0.3)
    assert state.live.phase == pytest.approx(0.3)
    state.playing, state.time_scale = True, 0.0
    frozen = state.live.clock
    state.advance(1.0)
    assert state.live.clock == frozen  # time scale 0 freezes


def test_camera_controls(state: ViewerState) -> None:
    start = state.camera
    state.orbit(100, 0)
    assert state.camera.azimuth != start.azimuth
    state.zoom(2)
    assert state.camera.distance < start.distance
    state.pan(50, 0, 500)
    assert state.camera.target != start.target
    state.frame_view("side")
    assert state.camera_preset == "side" and state.camera.azimuth == 0
    state.side_ortho()
    assert state.camera.ortho and state.camera_preset == "side"
    state.focus((1.0, 0.0, 2.0))
    assert state.camera.target == (1.0, 0.0, 2.0)
    state.focus(None)
    assert np.allclose(state.camera.target, state.pose().root[:3, 3])


def test_creature_preset_and_files(state: ViewerState, tmp_path: Path) -> None:
    assert state.load_preset("horse") and state.spec.name == "horse" and state.base.name == "horse"
    state.set("body.length", 1.2)
    target = tmp_path / "my_horse.toml"
    assert state.save(str(target)) and target.exists()
    assert state.load("cat") and state.spec.name == "cat"
    assert state.load(str(target)) and state.spec.body.length == 1.2
    broken = tmp_path / "broken.toml"
    broken.write_text("[body\nlength = 1")
    before = state.spec
    assert not state.load(str(broken))
    assert state.spec == before and "TOML syntax error" in state.error
    assert not state.save(str(tmp_path / "missing" / "x.toml")) and "does not exist" in state.error


def test_record_request_matches_the_cli_defaults(state: ViewerState, tmp_path: Path) -> None:
    state.record.folder = str(tmp_path)
    request = state.record_request()
    assert request.output == tmp_path / "dog.gif" and request.cycles == 2.0 and request.seconds is None
    assert request.view.size == (480, 360) and request.view.camera == "three-quarter" and request.fps == 25.0
    assert request.view.antialias == "fxaa" and request.view.samples == 4  # as gaitlab render
    state.record.format, state.record.unit, state.record.length = "mp4", "seconds", 3.0
    state.record.antialias = "msaa"
    request = state.record_request()
    assert request.output.suffix == ".mp4" and request.seconds == 3.0 and request.view.antialias == "msaa"


def test_save_never_overwrites_a_preset_or_a_file_unasked(state: ViewerState, tmp_path: Path,
                                                         monkeypatch: pytest.MonkeyPatch) -> None:
    """Issue 12, item 1: the path starts as <name>.toml in the working folder; a shipped
    preset is refused; an existing file is overwritten only when asked twice."""
    from app.resources import creatures_dir

    monkeypatch.chdir(tmp_path)
    assert state.file_path == f"{state.spec.name}.toml"  # not the preset's own file
    preset = creatures_dir() / f"{state.spec.name}.toml"
    before = preset.read_bytes()
    assert not state.save(str(preset)) and "preset creatures" in state.error
    assert preset.read_bytes() == before
    state.set("gait.duty_factor", 0.6000000238418579)  # what a float32 slider hands over...
    from app.ui.panels.widgets import shown

    state.set("gait.duty_factor", shown(0.6000000238418579, "%.3f  (b = 1.0)"))  # ...as the panel rounds it
    assert state.save() and (tmp_path / f"{state.spec.name}.toml").exists()
    saved = tmp_path / f"{state.spec.name}.toml"
    assert "duty_factor = 0.6\n" in saved.read_text()
    assert saved.stat().st_mode & 0o777 == 0o666 & ~_umask()
    state.set("body.length", 0.61)
    assert state.save() and "length = 0.61" in saved.read_text()  # its own file, saved a moment ago: no asking
    saved.write_text(saved.read_text() + "# someone else's note\n")  # changed since: ask first
    state.set("body.length", 0.62)
    assert not state.save() and "exists: save again to overwrite it" in state.status and state.overwrite_pending
    assert state.error is None  # a question, not an error
    assert "length = 0.62" not in saved.read_text()
    assert state.save() and "length = 0.62" in saved.read_text()  # asked twice: overwritten
    assert not state.overwrite_pending


def _umask() -> int:
    import os

    mask = os.umask(0)
    os.umask(mask)
    return mask


def test_reset_everything_asks_first_and_labels_show_edits(state: ViewerState) -> None:
    state.set("legs.hind.femur", 0.3)
    state.set("gait.duty_factor", 0.6)
    assert state.creature_label == "dog*" and state.gait_label == "walk*"
    assert not state.reset_all() and state.reset_pending and "press reset again" in state.error
    assert state.spec.leg("hind").femur == 0.3  # nothing lost yet
    assert state.reset_all() and state.spec == state.base and not state.reset_pending
    assert state.creature_label == "dog" and state.gait_label == "walk"


def test_an_untouched_preset_is_not_labelled_as_edited() -> None:
    """The human's file tunes its walk (duty, stride, step height): loaded as it is, its gait
    reads "walk", not "walk*"; adjusted, "walk*"; another gait picked, that gait's own
    defaults are the untouched ones."""
    human = ViewerState(load_creature("human"))
    assert human.creature_label == "human" and human.gait_label == "walk"
    human.set("gait.duty_factor", 0.62)
    assert human.gait_label == "walk*"
    human.set("gait.preset", "run")
    assert human.gait_label == "run"


def test_record_asks_before_writing_over_a_file_it_did_not_write(state: ViewerState, tmp_path) -> None:
    state.record.folder = str(tmp_path)
    target = state.record.path(state.spec.name)
    assert state.confirm_record()  # nothing there yet
    target.write_bytes(b"GIF89a someone else's")
    assert not state.confirm_record() and "record again to overwrite it" in (state.status or "")
    assert state.confirm_record()  # asked twice: go ahead
    state.recorded(target)  # written by this viewer: recording it again needs no asking
    assert state.confirm_record() and state.confirm_record()


def test_undo_and_redo_say_what_they_changed(state: ViewerState) -> None:
    state.set("gait.duty_factor", 0.7)
    assert state.undo() and state.status.startswith("undone: gait.duty_factor")
    assert state.redo() and state.status == "redone: gait.duty_factor 0.7"
    # A key that goes back to the preset's own value says so (it read "None").
    state.set("gait.step_height", 0.2)
    assert state.undo() and state.status == "undone: gait.step_height back to the preset's"


def test_the_description_says_what_no_longer_holds(state: ViewerState) -> None:
    loaded = state.creature_description
    assert "edited" not in loaded
    state.set_leg_type("fore", "unguligrade")
    assert state.creature_description.startswith(loaded) and "fore legs now unguligrade" in state.creature_description
    state.set_leg_type("fore", "digitigrade")  # the dog's own again
    assert state.creature_description == loaded


def test_leg_type_button_restores_the_creatures_own_values(state: ViewerState) -> None:
    state.set_leg_type("fore", "plantigrade")
    state.set_leg_type("fore", "digitigrade")
    assert state.spec.leg("fore").ankle_lift == 72 and state.spec.leg("fore").toe == 0.05  # the dog's own


def test_view_presets_set_their_own_projection_and_r_returns_home(state: ViewerState) -> None:
    state.side_ortho()
    assert state.camera.ortho
    state.frame_view("front")
    assert not state.camera.ortho and state.camera_preset == "front"
    state.orbit(200, 40)
    state.default_view()
    assert state.camera_preset == "three-quarter" and not state.camera.ortho


def test_undo_and_redo_edits(state: ViewerState, monkeypatch: pytest.MonkeyPatch) -> None:
    import app.ui.state as state_module

    clock = iter(float(t) for t in range(0, 1000, 5))  # edits 5 s apart: each its own step
    monkeypatch.setattr(state_module.time, "monotonic", lambda: next(clock))
    start = state.spec
    state.set("legs.hind.femur", 0.3)
    state.set("gait.duty_factor", 0.6)
    assert state.undo() and state.spec.gait.duty_factor is None and state.spec.leg("hind").femur == 0.3
    assert state.undo() and state.spec == start and not state.undo()
    assert state.redo() and state.spec.leg("hind").femur == 0.3
    assert state.redo() and state.spec.gait.duty_factor == 0.6 and not state.redo()
    # A slider drag (many changes of one key in quick succession) is one step.
    monkeypatch.setattr(state_module.time, "monotonic", lambda: 2000.0)
    for value in (0.31, 0.32, 0.33, 0.34):
        state.set("legs.fore.femur", value)
    assert state.undo() and state.spec.leg("fore").femur == start.leg("fore").femur
    # A drag at two frames a second (changes 5 s apart here): the mouse held the slider from
    # one change to the next, so it is still one step; the next press starts another.
    monkeypatch.setattr(state_module.time, "monotonic", lambda: next(clock))
    for held, value in ((False, 0.41), (True, 0.42), (True, 0.43), (False, 0.5), (True, 0.51)):
        state.drag_held = held
        state.set("legs.fore.femur", value)
    assert state.undo() and state.spec.leg("fore").femur == 0.43
    assert state.undo() and state.spec.leg("fore").femur == start.leg("fore").femur


def test_recent_files_and_the_dialog_fallback(state: ViewerState, tmp_path: Path) -> None:
    from app.ui.file_dialog import dialogs_available

    first, second = tmp_path / "a.toml", tmp_path / "b.toml"
    assert state.save(str(first)) and state.save(str(second))
    assert state.load(str(first))
    assert state.recent[:2] == [str(first.resolve()), str(second.resolve())]  # newest first, no repeats
    # On a machine without zenity or kdialog (this one, CI) no dialog can open: the path
    # field is the way in, and the panel says so.
    import shutil

    assert dialogs_available() == any(shutil.which(t) for t in ("zenity", "kdialog", "qarma", "matedialog"))


def test_a_copy_of_the_preset_folder_is_protected_too(tmp_path: Path) -> None:
    import shutil

    from app.resources import creatures_dir
    from app.ui.files import is_shipped

    copy = tmp_path / "creatures"
    shutil.copytree(creatures_dir(), copy)
    assert is_shipped(copy / "dog.toml") and is_shipped(creatures_dir() / "cat.toml")
    assert not is_shipped(tmp_path / "dog.toml")


def test_export_from_the_viewer_writes_what_is_on_screen(tmp_path) -> None:
    """The File panel's export: this creature and gait, from the current time, into the
    Record panel's folder (issue 10)."""
    from app.analysis.bvh import read_bvh

    state = ViewerState(load_creature("cat").with_overrides({"gait.preset": "trot"}))
    state.advance(0.5)
    state.record.folder = str(tmp_path)
    state.record.export_format = "bvh"
    assert state.export(), state.error
    clip = read_bvh(tmp_path / "cat.bvh")
    assert "exported" in state.status and clip.frames.shape[0] > 10
    state.record.folder = str(tmp_path / "missing")
    assert not state.export() and "does not exist" in state.error


def test_export_from_the_viewer_starts_at_the_phase_on_screen(tmp_path) -> None:
    """After scrubbing the cycle, the export begins with the pose the viewer shows."""
    from app.analysis.bvh import read_bvh

    state = ViewerState(load_creature("dog"))
    state.advance(0.4)
    state.live.set_phase(0.6)  # scrubbed: the clock moved, the time did not
    state.record.folder = str(tmp_path)
    state.record.export_format = "bvh"
    assert state.export(), state.error
    pose = state.pose()
    clip = read_bvh(tmp_path / "dog.bvh")
    names = [f"{leg}_{part}" for leg in pose.leg_names for part in ("hip", "ball")]
    first = clip.positions(names)[0].reshape(len(pose.leg_names), 2, 3)
    shown = pose.joints[:, [0, 3]]
    assert np.abs((first[:, 1] - first[:, 0]) - (shown[:, 1] - shown[:, 0])).max() < 0.01  # feet relative to hips


def _in_clear_view(state) -> bool:
    """The creature's root is inside the view and no ground lies between it and the eye."""
    root = state.pose().root[:3, 3]
    clip = np.array(state.camera.view_proj(16 / 9), dtype=np.float64) @ np.append(root, 1.0)
    ndc = clip[:2] / clip[3]
    eye = np.asarray(state.camera.eye, dtype=np.float64)
    line = eye[None] + np.linspace(0.05, 0.95, 60)[:, None] * (root - eye)[None]
    hidden = np.any(line[:, 1] < state.world.terrain.height(line[:, [0, 2]]) - 1e-3)
    return bool(clip[3] > 0 and np.all(np.abs(ndc) < 0.95) and not hidden)


@pytest.mark.parametrize("creature, terrain", [("dog", "stairs:rise=0.2"), ("human", "stairs"),
                                               ("spider", "hills:amp=0.3")])
def test_the_follow_camera_and_r_keep_the_creature_in_view(creature: str, terrain: str) -> None:
    """Following a creature up a flight of stairs or over hills, the camera keeps it in
    view with no ground in between; R frames it again where it is (up the flight, not at
    its foot)."""
    from app.worlds import make_world

    state = ViewerState(load_creature(creature), make_world("straight", terrain))
    state.default_view()
    seen = []
    for _ in range(30 * 12):
        state.advance(1 / 30)
        state.follow_creature(1 / 30)
        seen.append(_in_clear_view(state))
    assert np.mean(seen) >= 0.98
    state.camera = replace(state.camera, target=(0.0, 0.0, 0.0))  # looking elsewhere
    state.default_view()
    assert _in_clear_view(state)
    assert abs(state.camera.target[1] - state.pose().root[1, 3]) < 0.5


def test_the_follow_camera_keeps_up_with_a_climb_at_any_frame_rate() -> None:
    """The follow camera's height closes on the climbing creature's in time, not per
    frame: at 12 frames a second (a loaded machine) it trails the dog up a flight of
    stairs by what it does at 60. Eased 8 % a frame, it trailed by 0.6 m at 12 fps, and
    R's view of the creature up the flight drifted off it (a GUI test failed on CI)."""
    from app.worlds import make_world

    lags = []
    for fps in (60, 12):
        state = ViewerState(load_creature("dog"), make_world("straight", "stairs:rise=0.2,run=0.35,steps=12,start=1"))
        state.default_view()
        offset = state.camera.target[1] - state.pose().root[1, 3]
        for _ in range(int(6.0 * fps)):
            state.advance(1.0 / fps)
            state.follow_creature(1.0 / fps)
        lags.append(state.pose().root[1, 3] + offset - state.camera.target[1])
    assert lags[0] > 0.05  # climbing: the camera trails a little
    assert abs(lags[1] - lags[0]) < 0.05, lags


def test_a_stalled_frame_slows_the_animation_instead_of_jumping_it() -> None:
    """A frame that took a second (a loaded machine) moves the walk on by at most 0.1 s:
    a planted foot never jumps to a new foothold between two drawn frames (a 1 s frame
    once swung and landed a dog's foot unseen, 0.41 m on, while the terrain was edited)."""
    from app.ui.playback import MAX_FRAME_TIME

    state = ViewerState(load_creature("dog"))
    state.set_terrain("hills", amp=0.04, wavelength=1.7)
    clock = state.live.clock
    state.advance(1.0)
    assert state.live.clock - clock == pytest.approx(MAX_FRAME_TIME * state.live.frequency, rel=1e-6)
    for amp in (0.05, 0.07, 0.1):
        state.set_terrain("hills", amp=amp, wavelength=1.7)
        for _ in range(4):
            state.advance(1.0)
            state.note_pose(state.pose())
    assert state.planted_jump_max < 1e-3


def test_switching_presets_asks_before_discarding_edits(state: ViewerState) -> None:
    """Edits are not lost to one pick in the creature list: the first pick says what would
    be discarded, the same pick again switches (an untouched creature switches at once)."""
    assert state.set("gait.duty_factor", 0.7)
    assert not state.load_preset("spider")
    assert state.spec.name == "dog" and "discard" in state.status and "spider" in state.status
    assert state.spec.gait.duty_factor == pytest.approx(0.7)
    assert state.load_preset("spider") and state.spec.name == "spider"
    assert state.load_preset("cat") and state.spec.name == "cat"  # nothing edited: no question


def test_a_question_unanswered_lapses(state: ViewerState, monkeypatch: pytest.MonkeyPatch) -> None:
    """"Press again" for reset everything (and for switching presets over edits) stays
    armed for a few seconds only: a press minutes later asks again (it stayed armed for
    good, so a stray click much later reset everything)."""
    import time as clock

    from app.ui import playback

    now = [1000.0]
    monkeypatch.setattr(clock, "monotonic", lambda: now[0])
    assert state.set("gait.duty_factor", 0.7)
    assert not state.reset_all() and state.reset_pending
    now[0] += playback.QUESTION_SECONDS + 1.0
    state.advance(1 / 60)
    assert not state.reset_pending
    assert not state.reset_all()  # asks again
    assert state.spec.gait.duty_factor == pytest.approx(0.7)
    assert state.reset_all() and state.spec == state.base  # pressed again in time: done


def test_the_window_gives_a_software_rasteriser_a_thread_more_than_the_cores_unless_told():
    from app.ui.window import software_gl_threads

    environ: dict[str, str] = {}
    software_gl_threads(environ, cores=2)
    assert environ == {"LP_NUM_THREADS": "3"}
    chosen = {"LP_NUM_THREADS": "1"}
    software_gl_threads(chosen, cores=8)
    assert chosen == {"LP_NUM_THREADS": "1"}  # the user's choice stands


def test_the_frame_report_splits_each_synced_frame_and_never_reads_below_zero(capsys: pytest.CaptureFixture) -> None:
    """--report-fps: "swap and rest" is what each synced frame left over, so it is never
    negative (the medians of the parts do not add up to the median of the whole)."""
    from types import SimpleNamespace

    from app.ui.viewer import Viewer

    viewer = object.__new__(Viewer)
    viewer.window = SimpleNamespace(framebuffer_size=(1280, 720))
    viewer.state = SimpleNamespace(show_ui=True)
    # (simulate, scene, UI, whole frame, synced) in seconds: the parts' medians add up to
    # more than the median frame, but no frame spent less than its parts.
    synced = [(0.001, 0.010, 0.002, 0.0135, True), (0.005, 0.004, 0.002, 0.0115, True),
              (0.004, 0.008, 0.001, 0.0135, True)]
    viewer.frame_times = [(0.0, 0.0, 0.0, 0.02, False)] * 10 + synced + [(0.0, 0.0, 0.0, 0.016, False)] * 20
    viewer.report()
    line = capsys.readouterr().out
    assert "62.5 fps" in line and "swap and rest 0.50 ms" in line
