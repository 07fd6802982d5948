"""Frames computed in a simulation process: latest request wins, prefetch, cancel.

:class:`SimulationController` lives in the GUI thread and talks to one child process
(``python -m app.sim_process``) over a socket pair watched by a :class:`QSocketNotifier`,
so the GUI thread never waits for it. The child owns the
:class:`simcore.pipeline.Simulator` and sends back compact
:class:`~app.frame_view.FrameView` objects.

- **Latest wins.** The child computes one request at a time. A request that arrives while
  a frame is computing waits in a single slot and replaces any request already waiting;
  every request carries a serial number and results older than the latest request are
  dropped instead of being shown.
- **Pipelined playback.** :meth:`~SimulationController.prefetch` asks for the frame that
  playback will show next while the GUI draws the current one; when playback then
  requests it, the request adopts the frame in flight (or the finished one) instead of
  starting over. A prefetch never delays a real request: it runs only when nothing else
  waits.
- **Cancel.** :meth:`~SimulationController.cancel` terminates the process (the engine has
  no cancellation points inside a frame) and starts a fresh one; control returns at once.
- **Priorities.** The child is a separate process, so its threads never hold the GUI's
  GIL, and it runs at a lower CPU priority (nice 5, ``TOFRADAR_SIM_NICE``): when the
  cores are short, the GUI thread comes first; the simulator still gets every cycle the
  GUI leaves idle.
"""

from __future__ import annotations

import dataclasses
import os
import socket
import subprocess
import sys
import time
from dataclasses import dataclass
from multiprocessing.connection import Connection
from pathlib import Path
from typing import Any

from PyQt6.QtCore import QObject, QSocketNotifier, pyqtSignal

import app
import simcore
from app.frame_view import FrameView
from simcore.scene import Project

#: CPU priority offset of the simulation process (``TOFRADAR_SIM_NICE`` overrides it).
#: Measured (shared 2-core machine, load 8–9, a burst of edits): longest GUI stall
#: 228–282 ms at 5 against 554–584 ms at 0; see docs/gui.md.
DEFAULT_NICE = 5
#: The process is not restarted after this many deaths in a row before it was ready.
MAX_FAILED_STARTS = 3


@dataclass
class FrameRequest:
    """One frame to compute: the project as it was when asked, and the frame index."""

    serial: int
    project: Project
    base_dir: Path
    index: int
    requested_at: float
    prefetch: bool = False
    then: int | None = None   # the frame likely asked for after this one (playback)

    def same_frame(self, project: Project, base_dir: Path, index: int) -> bool:
        """True when this request computes the frame ``index`` of this very project."""
        return (self.project is project and self.base_dir == base_dir
                and self.index == index)


class SimulationController(QObject):
    """Asks the simulation process for frames and hands back only the latest request's.

    Signals
    -------
    frameReady(FrameView)
        The frame of the latest request is ready (older results are never emitted).
    failed(str)
        The latest request failed; the message says why.
    busyChanged(bool)
        The process started or finished working.
    cancelled()
        A running frame was cancelled (:meth:`cancel`).
    """

    frameReady = pyqtSignal(object)
    failed = pyqtSignal(str)
    busyChanged = pyqtSignal(bool)
    cancelled = pyqtSignal()

    def __init__(self, parent: QObject | None = None, *, nice: int | None = None):
        super().__init__(parent)
        self._nice = (int(os.environ.get("TOFRADAR_SIM_NICE", DEFAULT_NICE)) if nice is None
                      else nice)
        self._serial = 0
        self._proc: Any = None
        self._conn: Any = None
        self._notifier: QSocketNotifier | None = None
        self._ready = False
        self._sent_project: Project | None = None
        self._in_flight: FrameRequest | None = None
        self._in_flight_since = 0.0
        self._waiting: FrameRequest | None = None
        self._prefetch_waiting: FrameRequest | None = None
        self._done: tuple[FrameRequest, FrameView] | None = None  # last prefetched result
        self._busy = False
        self._closed = False
        self._render_count = 0
        self.latest: FrameView | None = None
        self.dropped = 0
        self.restarts = 0
        self._failed_starts = 0
        self.last_latency_ms: float | None = None
        self._completed: list[float] = []
        self._start_process()

    # --- process ----------------------------------------------------------------------
    def _start_process(self) -> None:
        ours, theirs = socket.socketpair()
        env = dict(os.environ)
        # The child imports the same app and simcore packages as this process.
        roots = [str(Path(m.__file__).resolve().parent.parent) for m in (app, simcore)]
        env["PYTHONPATH"] = os.pathsep.join(
            dict.fromkeys([*roots, *filter(None, env.get("PYTHONPATH", "").split(os.pathsep))]))
        proc = subprocess.Popen(
            [sys.executable, "-m", "app.sim_process", str(theirs.fileno()), str(self._nice)],
            pass_fds=[theirs.fileno()], env=env, stdin=subprocess.DEVNULL)
        theirs.close()
        conn = Connection(ours.detach())
        self._proc, self._conn = proc, conn
        self._ready = False
        self._sent_project = None
        self._notifier = QSocketNotifier(conn.fileno(), QSocketNotifier.Type.Read, self)
        self._notifier.activated.connect(self._on_readable)

    def _stop_process(self, *, kill: bool) -> None:
        if self._notifier is not None:
            self._notifier.setEnabled(False)
            self._notifier.deleteLater()
            self._notifier = None
        proc, conn = self._proc, self._conn
        self._proc = self._conn = None
        self._ready = False
        if conn is not None:
            if not kill:
                try:
                    conn.send(None)
                except OSError:
                    pass
            conn.close()
        if proc is None:
            return
        if not kill:
            try:
                proc.wait(5.0)
            except subprocess.TimeoutExpired:
                pass
        for stop in (proc.terminate, proc.kill):
            if proc.poll() is not None:
                break
            stop()
            try:
                proc.wait(0.5)
            except subprocess.TimeoutExpired:
                pass

    @property
    def process_id(self) -> int | None:
        """Process id of the simulation process (``None`` when stopped)."""
        return None if self._proc is None else self._proc.pid

    def is_running(self) -> bool:
        """True while the simulation process is alive."""
        return self._proc is not None and self._proc.poll() is None

    # --- requests ---------------------------------------------------------------------
    @property
    def latest_serial(self) -> int:
        """Serial number of the newest request."""
        return self._serial

    @property
    def busy(self) -> bool:
        """True while a frame is computing."""
        return self._in_flight is not None

    @property
    def busy_for_s(self) -> float:
        """How long the frame now computing has been running (s; 0 when idle)."""
        return 0.0 if self._in_flight is None else time.perf_counter() - self._in_flight_since

    @property
    def render_count(self) -> int:
        """Render passes done by the current simulation process (0 before the first)."""
        return self._render_count

    def request(self, project: Project, index: int, *, base_dir: Path) -> int:
        """Ask for frame ``index`` of ``project``; returns the request's serial number."""
        self._serial += 1
        now = time.perf_counter()
        req = FrameRequest(self._serial, project, base_dir, int(index), now)
        self._waiting = None
        ahead = self._prefetch_waiting
        if ahead is not None and ahead.same_frame(project, base_dir, req.index):
            self._prefetch_waiting = None  # asked for now: no second computation later
        flying = self._in_flight
        if flying is not None and flying.same_frame(project, base_dir, req.index):
            # Playback asks for the frame it prefetched: adopt the frame in flight.
            flying.serial, flying.requested_at, flying.prefetch = req.serial, now, False
            return req.serial
        done = self._done
        if done is not None and done[0].same_frame(project, base_dir, req.index):
            self._done = None
            # Shown at once: the time bar and the panels repaint together.
            self._deliver(req, dataclasses.replace(done[1]))
            return req.serial
        self._waiting = req
        self._dispatch()
        return req.serial

    def prefetch(self, project: Project, index: int, *, base_dir: Path,
                 then: int | None = None) -> None:
        """Compute frame ``index`` ahead, when nothing else waits, for a later :meth:`request`.

        ``then``: the frame playback shows after ``index``; the simulation process starts
        it while it finishes ``index`` (``Simulator.frame(index, then=...)``), so that the
        next prefetch finds it half done.
        """
        for req in (self._in_flight, self._waiting):
            if req is not None and req.same_frame(project, base_dir, index):
                return
        if self._done is not None and self._done[0].same_frame(project, base_dir, index):
            return
        self._prefetch_waiting = FrameRequest(0, project, base_dir, int(index),
                                              time.perf_counter(), prefetch=True,
                                              then=None if then is None else int(then))
        self._dispatch()

    def _dispatch(self) -> None:
        if self._in_flight is not None or not self._ready or self._conn is None:
            return
        req = self._waiting or self._prefetch_waiting
        if req is None:
            self._set_busy(False)
            return
        if req is self._waiting:
            self._waiting = None
        else:
            self._prefetch_waiting = None
        project_json = None
        if req.project is not self._sent_project:
            project_json = req.project.model_dump_json()
        try:
            self._conn.send(("frame", req.serial, project_json, req.base_dir, req.index,
                             req.then))
        except OSError:
            self._on_process_died()
            return
        self._sent_project = req.project
        self._in_flight = req
        self._in_flight_since = time.perf_counter()
        self._set_busy(True)

    def _set_busy(self, busy: bool) -> None:  # noqa: FBT001
        if busy != self._busy:
            self._busy = busy
            self.busyChanged.emit(busy)

    # --- results ----------------------------------------------------------------------
    def _on_readable(self, *_: object) -> None:
        conn = self._conn
        try:
            while conn is not None and conn is self._conn and conn.poll():
                self._handle(conn.recv())
        except (EOFError, OSError):
            self._on_process_died()

    def _handle(self, msg: tuple[Any, ...]) -> None:
        kind = msg[0]
        if kind == "ready":
            self._ready = True
            self._failed_starts = 0
            self._dispatch()
            return
        req, self._in_flight = self._in_flight, None
        if req is None:
            return
        if kind == "frame":
            view: FrameView = msg[2]
            self._render_count = int(view.render_count)
            # Start the next request before drawing this one: compute and drawing overlap.
            if req.prefetch:
                self._done = (req, view)
                self._dispatch()
                return
            self._dispatch()
            self._deliver(req, view)
        else:
            self._dispatch()
            if not req.prefetch and req.serial == self._serial:
                self.failed.emit(str(msg[2]))

    def _deliver(self, req: FrameRequest, view: FrameView) -> None:
        if req.serial != self._serial:
            self.dropped += 1  # a newer request exists: this result is stale
            return
        self.last_latency_ms = (time.perf_counter() - req.requested_at) * 1e3
        view.request_serial = req.serial
        view.latency_ms = self.last_latency_ms
        self._completed.append(time.perf_counter())
        self.latest = view
        self.frameReady.emit(view)

    def _on_process_died(self) -> None:
        if self._closed:
            return
        req, self._in_flight = self._in_flight, None
        code = None if self._proc is None else self._proc.poll()
        started = self._ready
        self._stop_process(kill=True)
        self._set_busy(False)
        self._failed_starts = 0 if started else self._failed_starts + 1
        if self._failed_starts >= MAX_FAILED_STARTS:
            # It dies before it is ready (a broken installation): do not spin restarting.
            self.failed.emit(f"the simulation process cannot start (exit code {code}); "
                             "see the terminal for its error")
            return
        self.restarts += 1
        self._start_process()
        if req is not None and not req.prefetch and req.serial == self._serial:
            self.failed.emit(f"the simulation process stopped (exit code {code}) while "
                             f"computing frame {req.index}; it has been restarted")

    # --- control ----------------------------------------------------------------------
    def cancel(self) -> bool:
        """Stop the frame now computing (restarts the process); False when idle."""
        if self._in_flight is None or self._closed:
            return False
        self._in_flight = None
        self._waiting = None
        self._prefetch_waiting = None
        self._done = None
        self._stop_process(kill=True)
        self.restarts += 1
        self._start_process()
        self._set_busy(False)
        self.cancelled.emit()
        return True

    def frames_per_second(self) -> float:
        """Rate of shown frames over the last few seconds (frames/s)."""
        now = time.perf_counter()
        self._completed = [t for t in self._completed if now - t < 5.0]
        if len(self._completed) < 2:
            return 0.0
        span = self._completed[-1] - self._completed[0]
        return (len(self._completed) - 1) / span if span > 0 else 0.0

    def shutdown(self) -> None:
        """Stop the simulation process (the frame in progress is abandoned)."""
        if self._closed:
            return
        self._closed = True
        self._waiting = self._prefetch_waiting = None
        kill = self._in_flight is not None
        self._in_flight = None
        self._stop_process(kill=kill)
