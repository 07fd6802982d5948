"""The simulation process: owns a :class:`simcore.pipeline.Simulator`, answers frame requests.

This module runs in a child process started by :class:`app.simulation.SimulationController`
as ``python -m app.sim_process FD NICE``, FD being its end of a socket pair (a plain
subprocess rather than ``multiprocessing``'s spawn, which would re-run the parent's main
script in the child). It imports no Qt: it receives requests over a
pipe, computes the frame with the public ``Simulator(project).frame(i)`` API, turns it into a
compact, picklable :class:`~app.frame_view.FrameView` with :func:`build_frame_view` and
sends that back. Running the simulator in its own process keeps its threads from taking the
GIL and the cores from the GUI thread, and makes a running frame cancellable: the GUI
terminates the process and starts a fresh one.

Messages to the child: ``("frame", serial, project_json | None, base_dir, index, then)``
(the project as JSON text — the evented project model does not pickle —, ``None`` re-uses
the last project sent; ``then``: the frame playback asks for next, started ahead, or
``None``) or ``None`` to quit. Messages back: ``("ready", pid)`` once
at start, then ``("frame", serial, FrameView)`` or ``("error", serial, message)`` per
request.
"""

from __future__ import annotations

import os
import sys
import time
import traceback
from multiprocessing.connection import Connection
from pathlib import Path
from typing import Any


def _compute(state: dict[str, Any], project: Any, base_dir: Path, index: int,
             then: int | None = None) -> Any:
    from app.frame_view import build_frame_view
    from simcore.pipeline import Simulator

    start = time.perf_counter()
    sim = state.get("simulator")
    if sim is None or state.get("base_dir") != base_dir:
        if sim is not None:
            sim.close()
        state["simulator"] = None
        sim = Simulator(project, base_dir=base_dir)
        state["simulator"] = sim
        state["base_dir"] = base_dir
    elif state.get("project") is not project:
        sim.set_project(project)
    state["project"] = project
    index = min(index, sim.n_frames - 1)
    if then is not None and not 0 <= then < sim.n_frames:
        then = None
    frame = sim.frame(index, then=then)
    view = build_frame_view(frame, project, render_count=int(sim.render_count))
    view.timings_ms["wall"] = (time.perf_counter() - start) * 1e3
    return view


def serve(conn: Connection, nice: int = 0) -> None:
    """Answer frame requests on ``conn`` until ``None`` arrives or the pipe closes."""
    if nice:
        try:
            os.nice(nice)
        except OSError:
            pass
    state: dict[str, Any] = {}
    project = None
    conn.send(("ready", os.getpid()))
    try:
        while True:
            try:
                msg = conn.recv()
            except (EOFError, OSError):
                return
            if msg is None:
                return
            _, serial, project_json, base_dir, index, then = msg
            try:
                if project_json is not None:
                    from simcore.scene import Project

                    project = Project.model_validate_json(project_json)
                view = _compute(state, project, base_dir, index, then)
            except Exception as exc:  # noqa: BLE001 - reported to the GUI, process goes on
                detail = "".join(traceback.format_exception_only(type(exc), exc)).strip()
                conn.send(("error", serial, detail))
            else:
                conn.send(("frame", serial, view))
    finally:
        sim = state.get("simulator")
        if sim is not None:
            sim.close()


def main(argv: list[str] | None = None) -> None:
    """Entry point of the child: ``python -m app.sim_process FD [NICE]``."""
    args = sys.argv[1:] if argv is None else argv
    conn = Connection(int(args[0]))
    serve(conn, int(args[1]) if len(args) > 1 else 0)


if __name__ == "__main__":
    main()
