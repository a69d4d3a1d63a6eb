"""A bounded queue of frames consumed by a background thread, so encoding overlaps
rendering on a second core while memory stays at a few frames."""

from __future__ import annotations

import queue
import threading
from collections.abc import Callable

import numpy as np
from numpy.typing import NDArray

_DONE = object()


class BackgroundWriter:
    """Hands frames to ``consume`` on a worker thread, holding at most ``depth`` frames.

    :meth:`put` blocks when the queue is full (so a slow encoder slows rendering instead
    of filling memory) and re-raises, in the caller's thread, whatever ``consume`` raised.
    """

    def __init__(self, consume: Callable[[NDArray[np.uint8]], None], depth: int = 4, name: str = "writer") -> None:
        self._consume = consume
        self._queue: queue.Queue = queue.Queue(maxsize=depth)
        self._error: BaseException | None = None  # raised once, in the caller's thread
        self.failed = False  # sticky: once the consumer failed, close() never reports success
        self._aborted = threading.Event()
        self._thread = threading.Thread(target=self._run, name=f"gaitlab-{name}", daemon=True)
        self._thread.start()

    def _run(self) -> None:
        while True:
            item = self._queue.get()
            if item is _DONE:
                return
            if self._error is not None or self._aborted.is_set():
                continue  # drain without work so put() never blocks forever
            try:
                self._consume(item)
            except BaseException as exc:  # handed to the caller's thread
                self._aborted.set()
                self.failed = True
                self._error = exc

    def _raise(self) -> None:
        if self._error is not None:
            error, self._error = self._error, None
            raise error
        if self.failed:
            raise RuntimeError("the background writer failed earlier")

    def put(self, frame: NDArray[np.uint8]) -> None:
        self._raise()
        while True:
            try:
                self._queue.put(frame, timeout=0.2)
                return
            except queue.Full:
                if not self._thread.is_alive():
                    raise RuntimeError("the background writer stopped") from None
                self._raise()

    def close(self) -> None:
        """Wait for every queued frame to be consumed; re-raise a consumer error."""
        self._queue.put(_DONE)
        self._thread.join()
        self._raise()

    @property
    def aborted(self) -> bool:
        """True once :meth:`abort` was called or the consumer failed (consumers poll it
        to stop long waits early)."""
        return self._aborted.is_set()

    def abort(self) -> None:
        """Drop queued frames and stop the thread (errors are ignored). The consumer should
        return promptly once :attr:`aborted` is set."""
        self._aborted.set()
        while True:
            try:
                self._queue.get_nowait()
            except queue.Empty:
                break
        try:
            self._queue.put_nowait(_DONE)
        except queue.Full:
            pass
        self._thread.join()
        self._error = None
