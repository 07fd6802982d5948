"""Frames computed off the GUI thread: one worker, latest request wins, stale results dropped.

:class:`SimulationController` lives in the GUI thread. :meth:`~SimulationController.request`
stores the newest (project, frame index) in a single slot and wakes the worker thread; a
request that arrives while a frame is computing replaces any request still waiting, so the
worker always moves on to the latest state. Every request carries a serial number; results
whose serial is older than the latest request are dropped instead of being shown.

The worker owns one :class:`simcore.pipeline.Simulator` (its VTK render windows live in the
worker thread) and calls :meth:`Simulator.set_project` with every new project, so edits that
touch only the radar antennas, waveform or DSP settings re-use the cached renders.
"""

from __future__ import annotations

import threading
import time
import traceback
from dataclasses import dataclass
from pathlib import Path

from PyQt6.QtCore import QObject, QThread, pyqtSignal

from app.frame_view import FrameView, build_frame_view
from simcore.scene import Project


@dataclass(frozen=True)
class FrameRequest:
    """One frame to compute: the project as it was when asked, and the frame index."""

    serial: int
    project: Project
    base_dir: Path
    index: int
    requested_at: float


class _Worker(QThread):
    """The thread that owns the simulator and computes frames one after another."""

    finished_frame = pyqtSignal(object, object)  # FrameRequest, FrameView
    failed = pyqtSignal(object, str)  # FrameRequest, message
    busy = pyqtSignal(bool)

    def __init__(self, parent: QObject | None = None):
        super().__init__(parent)
        self._cond = threading.Condition()
        self._pending: FrameRequest | None = None
        self._stop = False
        self.simulator = None
        self._base_dir: Path | None = None

    def submit(self, request: FrameRequest) -> None:
        with self._cond:
            self._pending = request  # replaces an older waiting request: latest wins
            self._cond.notify()

    def stop(self) -> None:
        with self._cond:
            self._stop = True
            self._pending = None
            self._cond.notify()

    def run(self) -> None:  # noqa: D102 - QThread API
        try:
            while True:
                with self._cond:
                    while self._pending is None and not self._stop:
                        self._cond.wait()
                    if self._stop:
                        return
                    request, self._pending = self._pending, None
                self.busy.emit(True)
                try:
                    view = self._compute(request)
                except Exception as exc:  # noqa: BLE001 - shown to the user, worker goes on
                    detail = "".join(traceback.format_exception_only(type(exc), exc)).strip()
                    self.failed.emit(request, detail)
                else:
                    self.finished_frame.emit(request, view)
                with self._cond:
                    idle = self._pending is None
                if idle:
                    self.busy.emit(False)
        finally:
            if self.simulator is not None:
                self.simulator.close()
                self.simulator = None

    def _compute(self, request: FrameRequest) -> FrameView:
        from simcore.pipeline import Simulator

        start = time.perf_counter()
        if self.simulator is None or request.base_dir != self._base_dir:
            if self.simulator is not None:
                self.simulator.close()
            self.simulator = None
            self.simulator = Simulator(request.project, base_dir=request.base_dir)
            self._base_dir = request.base_dir
        else:
            self.simulator.set_project(request.project)
        index = min(request.index, self.simulator.n_frames - 1)
        frame = self.simulator.frame(index)
        view = build_frame_view(frame, request.project,
                                render_count=self.simulator.render_count)
        view.timings_ms["wall"] = (time.perf_counter() - start) * 1e3
        return view


class SimulationController(QObject):
    """Asks the worker for frames and hands back only the results of the latest request.

    Signals
    -------
    frameReady(FrameView)
        The frame of the latest request is ready (older results are never emitted).
    failed(str)
        The latest request failed; the message says why.
    busyChanged(bool)
        The worker started or finished working.
    """

    frameReady = pyqtSignal(object)
    failed = pyqtSignal(str)
    busyChanged = pyqtSignal(bool)

    def __init__(self, parent: QObject | None = None):
        super().__init__(parent)
        self._serial = 0
        self._worker = _Worker(self)
        self._worker.finished_frame.connect(self._on_finished)
        self._worker.failed.connect(self._on_failed)
        self._worker.busy.connect(self.busyChanged)
        self._worker.start()
        self.latest: FrameView | None = None
        self.dropped = 0
        self.last_latency_ms: float | None = None
        self._completed: list[float] = []

    @property
    def latest_serial(self) -> int:
        """Serial number of the newest request."""
        return self._serial

    @property
    def render_count(self) -> int:
        """GPU render passes done by the worker's simulator so far (0 before the first)."""
        sim = self._worker.simulator
        return 0 if sim is None else int(sim.render_count)

    def request(self, project: Project, index: int, *, base_dir: Path) -> int:
        """Ask for frame ``index`` of ``project``; returns the request's serial number."""
        self._serial += 1
        self._worker.submit(FrameRequest(self._serial, project, base_dir, int(index),
                                         time.perf_counter()))
        return self._serial

    def frames_per_second(self) -> float:
        """Rate of completed frames over the last few seconds (frames/s)."""
        now = time.perf_counter()
        self._completed = [t for t in self._completed if now - t < 5.0]
        if len(self._completed) < 2:
            return 0.0
        span = self._completed[-1] - self._completed[0]
        return (len(self._completed) - 1) / span if span > 0 else 0.0

    def _on_finished(self, request: FrameRequest, view: FrameView) -> None:
        if request.serial != self._serial:
            self.dropped += 1  # a newer request is pending: this result is stale
            return
        self.last_latency_ms = (time.perf_counter() - request.requested_at) * 1e3
        view.request_serial = request.serial
        view.latency_ms = self.last_latency_ms
        self._completed.append(time.perf_counter())
        self.latest = view
        self.frameReady.emit(view)

    def _on_failed(self, request: FrameRequest, message: str) -> None:
        if request.serial == self._serial:
            self.failed.emit(message)

    def shutdown(self) -> None:
        """Stop the worker thread (waits for the frame in progress) and free the simulator."""
        if self._worker.isRunning():
            self._worker.stop()
            self._worker.wait()
