"""The viewer's live gait monitor: a rolling history of the feet and, every half second,
the gait measured from it by the same analysis as ``gaitlab analyze`` (no GL, no imgui).

In the viewer the measurement runs in a worker process (:meth:`GaitMonitor.update`): the
frame only hands over the resampled history (about 0.1 MB) and later picks up the report,
so a measurement never stalls a frame, whatever the number of feet. :meth:`measure` does
the same work synchronously (tests, state dumps).
"""

from __future__ import annotations

import multiprocessing
import signal
from collections import deque
from concurrent.futures import Future, ProcessPoolExecutor
from concurrent.futures.process import BrokenProcessPool

import numpy as np
from numpy.typing import NDArray

from ..analysis import AnalysisError, FootTracks, analyze_tracks
from ..analysis.metrics import GaitReport
from ..kinematics.live import stack_inputs
from ..kinematics.motion import Motion, Pose, solve_motion
from ..kinematics.rig import Rig
from ..kinematics.world import World


def _ignore_interrupts() -> None:
    """In the measuring process: Ctrl-C is the viewer's to handle (it stops the worker)."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)


ANALYSIS_FPS = 240.0  # the history is resampled to this rate before analysis (the sampling rate)


class GaitMonitor:
    """Keeps the last ``seconds`` of foot motion (in the ground's frame, so planted feet
    stand still) and measures the gait from it."""

    def __init__(self, seconds: float = 4.0, every: float = 0.5) -> None:
        self.seconds = seconds
        self.every = every
        self._times: deque[float] = deque()
        self._heel: deque[NDArray] = deque()
        self._toe: deque[NDArray] = deque()
        self._body: deque[NDArray] = deque()
        self._contact: deque[NDArray] = deque()
        self.names: tuple[str, ...] = ()
        self.report: GaitReport | None = None
        self.error: str | None = None
        self._last_measure = -np.inf
        self.hip_height: float | None = None
        self.wanted = False  # set by the Plots panel each frame it is drawn
        self._executor: ProcessPoolExecutor | None = None
        self._pending: Future | None = None

    def clear(self) -> None:
        for buffer in (self._times, self._heel, self._toe, self._body, self._contact):
            buffer.clear()
        self.report = None
        self._last_measure = -np.inf
        if self._pending is not None:  # a measurement of the motion just cleared: drop it
            self._pending.cancel()
            self._pending = None

    def record_samples(self, rig: Rig, world: World, samples: list[dict],
                       frequency: float | None = None) -> Motion | None:
        """Add sub-step samples (:meth:`LiveMotion.frame_inputs` dicts), solved in one
        vectorised call: the history's rate is the simulation's, not the frame rate.
        Returns the solved samples (None without any)."""
        if not samples:
            return None
        motion = solve_motion(rig, world, stack_inputs(samples))
        heel, toe = motion.heel.copy(), motion.joints[:, :, 4].copy()
        heel[..., 2] += motion.ground_offset[:, None]
        toe[..., 2] += motion.ground_offset[:, None]
        if not world.terrain.flat:  # heights above the ground under each foot, as on a flat floor
            heel[..., 1] -= world.terrain.height(heel[..., [0, 2]])
            toe[..., 1] -= world.terrain.height(toe[..., [0, 2]])
        body = motion.root[:, :3, 3].copy()
        body[:, 2] += motion.ground_offset
        for i in range(motion.frame_count):
            self._append(float(motion.times[i]), heel[i], toe[i], body[i], motion.contact[i], rig.leg_names,
                         rig.hip_height, frequency)
        return motion

    def record(self, pose: Pose, time: float, hip_height: float | None = None, frequency: float | None = None) -> None:
        """Add a frame (animation time ``time`` in seconds); repeated times are ignored.
        ``frequency`` (Hz) sizes the window to about three strides (1.5 to 6 s)."""
        shift = np.array([0.0, 0.0, pose.ground_offset])
        self._append(time, pose.heel + shift, pose.joints[:, 4] + shift, pose.root[:3, 3] + shift,
                     pose.contact.copy(), pose.leg_names, hip_height, frequency)

    def _append(self, time: float, heel: NDArray, toe: NDArray, body: NDArray, contact: NDArray,
                names: tuple[str, ...], hip_height: float | None, frequency: float | None) -> None:
        if frequency:
            self.seconds = float(np.clip(3.0 / frequency, 1.5, 6.0))
        if self.names != names:
            self.names = names
            self.clear()
        if self._times and time <= self._times[-1]:
            return
        self._times.append(time)
        self._heel.append(heel)
        self._toe.append(toe)
        self._body.append(body)
        self._contact.append(contact)
        self.hip_height = hip_height
        while self._times and self._times[-1] - self._times[0] > self.seconds:
            for buffer in (self._times, self._heel, self._toe, self._body, self._contact):
                buffer.popleft()

    @property
    def times(self) -> NDArray[np.float64]:
        return np.array(self._times)

    def heights(self) -> NDArray[np.float64]:
        """Ball heights (T, L), metres."""
        return np.array(self._heel)[:, :, 1] if self._times else np.zeros((0, len(self.names)))

    def contact(self) -> NDArray[np.bool_]:
        return np.array(self._contact) if self._times else np.zeros((0, len(self.names)), dtype=bool)

    def tracks(self) -> FootTracks | None:
        """The history resampled to a uniform rate, as analysis input."""
        if len(self._times) < 8:
            return None
        t = self.times
        uniform = np.arange(t[0], t[-1], 1.0 / ANALYSIS_FPS)
        if len(uniform) < 8:
            return None

        # Linear interpolation weights, found once and applied to every buffer.
        right = np.clip(np.searchsorted(t, uniform, side="right"), 1, len(t) - 1)
        left = right - 1
        w = (uniform - t[left]) / (t[right] - t[left])  # times strictly increase (see record)

        def resample(buffer) -> NDArray:
            data = np.array(buffer)
            weight = w.reshape((-1,) + (1,) * (data.ndim - 1))
            return data[left] * (1.0 - weight) + data[right] * weight

        return FootTracks(times=uniform - uniform[0], names=self.names, heel=resample(self._heel),
                          toe=resample(self._toe), body=resample(self._body), source="live",
                          hip_height=self.hip_height, exact=True)

    def update(self, now: float) -> GaitReport | None:
        """The non-blocking :meth:`measure`: collect a finished measurement if there is
        one, and start the next in the worker process every ``every`` seconds."""
        if self._pending is not None and self._pending.done():
            pending, self._pending = self._pending, None
            try:
                report = pending.result()
            except AnalysisError as exc:
                self.error = str(exc)
            except BrokenProcessPool:  # the worker died (e.g. killed): a new one next time
                self.error = "the measuring process stopped; starting another"
                self._shutdown()
            except Exception as exc:  # a bug in the analysis: say so in one line, keep the worker
                detail = str(exc).splitlines()[0][:160] if str(exc) else ""
                self.error = f"measurement failed: {type(exc).__name__}: {detail}"
            else:
                if report is not None and report.tracks is not None and report.tracks.names == self.names:
                    self.report, self.error = report, None
        if self._pending is None and now - self._last_measure >= self.every:
            self._last_measure = now
            tracks = self.tracks()
            if tracks is None:
                self.error = "collecting motion..."
            else:
                if self._executor is None:
                    self._executor = ProcessPoolExecutor(max_workers=1, initializer=_ignore_interrupts,
                                                         mp_context=multiprocessing.get_context("spawn"))
                self._pending = self._executor.submit(analyze_tracks, tracks)
        return self.report

    def _shutdown(self) -> None:
        if self._executor is not None:
            self._executor.shutdown(wait=False, cancel_futures=True)
            self._executor = None
        self._pending = None

    def close(self) -> None:
        """Stop the worker process (the viewer calls this when its window closes)."""
        self._shutdown()

    def measure(self, now: float, force: bool = False) -> GaitReport | None:
        """Re-measure if ``every`` seconds of animation passed since the last time."""
        if not force and now - self._last_measure < self.every:
            return self.report
        self._last_measure = now
        tracks = self.tracks()
        if tracks is None:
            self.error = "collecting motion..."
            return self.report
        try:
            self.report = analyze_tracks(tracks)
            self.error = None
        except AnalysisError as exc:
            self.error = str(exc)
        return self.report
