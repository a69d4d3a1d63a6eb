"""Playback: stepping the scene's creatures, the gait clock, driving and the herd."""

from __future__ import annotations

import time
from dataclasses import replace

import numpy as np

from ..errors import GaitlabError
from ..kinematics.drive import Driver
from ..kinematics.herd import Herd
from ..kinematics.motion import Pose
from ..kinematics.poses import reference_foot
from ..kinematics.roll import contact_points, roll_part
from ..rigging import build_rig
from .base import StateBase
from .session import CreatureSession

FRAME_DT = 1.0 / 60.0  # the single-step size, and the fixed step of scripted runs
SAMPLE_RATE = 240.0  # Hz: how often the live gait measurement samples the motion
MAX_FRAME_TIME = 0.1  # s: the most wall time one frame moves the animation on
QUESTION_SECONDS = 8.0  # s: how long "press again" (reset everything, switching presets) stays armed


def step_herd(session: CreatureSession, dt: float) -> None:
    """Move a creature's herd (if it has one) on by ``dt`` s, following it."""
    herd, live = session.herd, session.live
    if herd is None:
        return
    if herd.rig.gait.preset != live.rig.gait.preset:  # driving switched gait
        herd.set_rig(live.rig)
    (point,), (tangent,) = session.world.path.sample(np.array([live.travel]))
    speed = live.travel_per_cycle() * live.frequency
    terrain = session.world.terrain
    herd.step(dt, point, float(np.arctan2(tangent[0], tangent[1])), leader_speed=speed,
              ground_height=None if terrain.flat else terrain.height)


class PlaybackMixin(StateBase):
    """Play, pause, step, scrub, drive; the herd; what each frame's pose tells."""

    def toggle_play(self) -> None:
        self.playing = not self.playing

    def advance(self, dt: float) -> None:
        """Move the animation on by ``dt`` seconds of wall time (if playing), at most
        MAX_FRAME_TIME: a frame that stalls (a loaded machine, a dialog) slows the
        animation down instead of jumping it (a foot could swing and land unseen)."""
        if (self.reset_pending or self._confirm_switch) and time.monotonic() - self._asked_at > QUESTION_SECONDS:
            self.reset_pending, self._confirm_switch = False, None  # a question unanswered lapses
        if self.playing:
            self._step(min(dt, MAX_FRAME_TIME) * self.time_scale)

    def step_frame(self) -> None:
        """One frame forward (pauses playback)."""
        self.playing = False
        self._step(FRAME_DT * max(self.time_scale, 1e-3))

    def _step(self, dt: float) -> None:
        """Step the motion in sub-steps of at most 1/SAMPLE_RATE s (with ``fine_sampling``),
        keeping each sub-step's inputs in :attr:`samples`: the live gait measurement
        samples the motion at this fixed rate, whatever the frame rate."""
        rate = SAMPLE_RATE if self.fine_sampling else 0.0
        steps = max(1, int(np.ceil(dt * rate - 1e-9))) if dt > 0 else 0
        try:
            for _ in range(steps):
                if self.driver is not None:
                    self.driver.step(dt / steps, *self.drive_input)
                else:
                    self.live.step(dt / steps)
                self.samples.append(self.live.frame_inputs())
            for member in self.others:  # the scene's other creatures walk on (a handful)
                member.live.step(dt)
            if dt > 0:
                for session in self.sessions:
                    step_herd(session, dt)
            count = self.live.compromised_count
            if count > self.compromised_told:  # uneven ground: say so once per new foothold, not an error
                self.compromised_told = count
                self.status = (f"uneven ground: {count} foothold(s) so far on the least-bad spot in reach "
                               "(none there lies flat)")
        except GaitlabError as exc:  # ground with no foothold ahead: stop there and say why
            self.playing = False
            self.error = f"paused: {exc}"

    def start_driving(self) -> bool:
        """Drive the creature: W/S (Up/Down) set the speed, A/D (Left/Right) turn; the gait
        follows the speed. The path from here on is laid down by the steering."""
        if self.driver is not None:
            return True
        before = self.live.world
        try:
            if before.in_place:  # driving means travelling
                self.live.world = replace(before, in_place=False)
            self.driver = Driver(self.live, build_rig(self.spec))
        except GaitlabError as exc:
            self.live.world = before
            self.error = f"cannot drive: {exc}"
            return False
        self.world = self.live.world
        self.options = replace(self.options, path=True)
        self.playing = True
        self.status = "driving: W/S or Up/Down speed, A/D or Left/Right turn, Esc to stop"
        return True

    def stop_driving(self) -> None:
        """Back to the panels' gait, going straight on along the path driven so far."""
        if self.driver is None:
            return
        self.driver.release()
        self.driver = None
        self.drive_input = (0.0, 0.0)
        try:
            self.live.set_rig(build_rig(self.spec))
        except GaitlabError as exc:
            self.error = str(exc)
            return
        self.status = "stopped driving: the gait is the Gait panel's again"

    def take_samples(self) -> list[dict]:
        """The sub-steps' inputs since the last call (see :meth:`_step`)."""
        samples, self.samples = self.samples, []
        return samples

    def scrub(self, phase: float) -> None:
        """Put the gait clock at ``phase`` of the current cycle (pauses playback)."""
        self.playing = False
        self.live.set_phase(phase)

    def pose(self) -> Pose:
        return self.live.pose()

    def set_herd(self, count: int) -> bool:
        """``count`` animals in all: this creature and ``count - 1`` more of its kind
        following it (1: none). Out of range shows the error and changes nothing."""
        from ..kinematics.herd import check_herd_size

        try:
            count = check_herd_size(count)
            if count > 1:
                self.leave_in_place()
        except GaitlabError as exc:
            self.error = str(exc)
            return False
        if count == 1:
            self.herd = None
            return True
        point, heading = self._here()
        self.herd = Herd(self.live.rig, count - 1, leader=(float(point[0]), float(point[1])), heading=heading)
        self.frame_view()
        return True

    def note_pose(self, pose: Pose) -> None:
        """Take in the pose drawn this frame: record new footprints, and how far any foot
        planted in both this frame and the last moved between them (:attr:`planted_jump`,
        m; the largest since the viewer started in :attr:`planted_jump_max`)."""
        self.footprints.record(pose, self.live.time)
        rig = self.live.rig
        if self.options.arcs:
            self.arcs.record(pose, self.options.arcs, self.live.time, 1.0 / self.live.frequency, reference_foot(rig))
        else:
            self.arcs.clear()
        self._drop_passed_waypoints()
        last = self._last_pose
        self._last_pose = pose
        if last is None or len(last.contact) != len(pose.contact):
            return
        # What bears each planted foot (a rolling foot's heel, ball or toe tip in turn).
        duty = self.live.duty
        part = roll_part(rig, rig.poses.foot_angle, pose.phase, duty)
        last_part = roll_part(rig, rig.poses.foot_angle, last.phase, duty)
        still = last.contact & pose.contact & (pose.phase > last.phase) & (part == last_part)
        offset = np.array([0.0, 0.0, pose.ground_offset - last.ground_offset])  # in place: the ground moves
        if still.any():
            now = contact_points(rig, rig.poses.foot_angle, pose.phase, duty, pose.contact, pose.heel, pose.joints)
            before = contact_points(rig, rig.poses.foot_angle, last.phase, duty, last.contact, last.heel, last.joints)
            moved = np.linalg.norm(now[still] + offset - before[still], axis=-1)
            self.planted_jump = float(moved.max())
            self.planted_jump_max = max(self.planted_jump_max, self.planted_jump)
