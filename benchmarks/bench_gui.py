"""GUI throughput and latency on a project, next to the core's own figures from the same run.

Run under a display (Xvfb on a headless machine)::

    xvfb-run -a -s "-screen 0 1920x1080x24" python benchmarks/bench_gui.py [PROJECT]

First the core alone (:func:`simcore.bench.run_benchmark`, as ``tofradar bench``): frame
time and frames/s, antenna-edit time; and, with the same :class:`Simulator`, the frame time
after moving an object and after changing an object's material. Then the main window
(:class:`app.main_window.MainWindow`, 1720×1020) on the same project:

- **playback**: frames shown per second while playing for ``--seconds`` seconds, the
  main thread's CPU time per shown frame (``time.thread_time`` of the GUI thread: drawing,
  painting, event handling), the GUI process's CPU time per shown frame (all its threads,
  Mesa's included; the simulation runs in its own process), and the event loop's
  responsiveness while playing: the longest and 99th-percentile delay of a 10 ms timer and
  of a posted event (the time a key press would wait);
- **edit → panels current**: medians over ``--edits`` edits of the time from the edit
  (through the document, as the editors do) until the panels show the frame of the new
  state — antenna move, object move, material change — with two parts of it: the GUI's
  own handling of the edit until the frame is requested (validation, preflight, every
  view's update) and the frame's wall time in the simulation process;
- **cancel**: the time from cancelling a costly frame until the event loop runs again.

The load average is printed: on a shared machine compare runs only at similar load. No
number here is asserted anywhere; the acceptance ratios are printed for reading.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import time
from pathlib import Path
from typing import Any

import numpy as np

from simcore.bench import run_benchmark
from simcore.pipeline import Simulator
from simcore.resources import EXAMPLES_DIR
from simcore.scene import Project, load_project

OFFICE = EXAMPLES_DIR / "office.json"


def _load() -> float:
    return round(os.getloadavg()[0], 2)


def _moved_object(project: Project, index: int, dx: float) -> Project:
    data = project.model_dump()
    pos = data["objects"][index]["pose"]["position_m"]
    data["objects"][index]["pose"]["position_m"] = (pos[0] + dx, pos[1], pos[2])
    return Project.model_validate(data)


def _material_changed(project: Project, index: int, material: str) -> Project:
    data = project.model_dump()
    data["objects"][index]["material"] = material
    return Project.model_validate(data)


def _edit_object(project: Project) -> int:
    """Index of the object the edits move: the metal plate if there is one, else the last."""
    for i, obj in enumerate(project.objects):
        if obj.name == "metal_plate":
            return i
    return len(project.objects) - 1


def core_figures(path: Path, *, frames: int, edits: int) -> dict[str, Any]:
    """``tofradar bench`` figures plus the core's object-move and material-change times."""
    bench = run_benchmark(path, frames=frames, subset=200, antenna_edits=edits)
    project = load_project(path)
    obj = _edit_object(project)
    moves, materials = [], []
    with Simulator(project, base_dir=path.parent) as sim:
        sim.frame(1)
        for k in range(edits):
            sim.set_project(_moved_object(project, obj, 0.05 * (1 + k % 2)))
            t0 = time.perf_counter()
            sim.frame(1)
            moves.append((time.perf_counter() - t0) * 1e3)
        for k in range(edits):
            sim.set_project(_material_changed(project, obj, ("wood", "aluminium")[k % 2]))
            t0 = time.perf_counter()
            sim.frame(1)
            materials.append((time.perf_counter() - t0) * 1e3)
    return {"fps": bench["fps"], "frame_ms": bench["frame_ms_median"],
            "antenna_edit_ms": bench["antenna_edit_ms"],
            "object_move_ms": statistics.median(moves),
            "material_change_ms": statistics.median(materials),
            "load": bench["machine"]["load_before"]}


class _Responsiveness:
    """Delays of a 10 ms timer and of posted events while the event loop runs."""

    def __init__(self) -> None:
        from PyQt6.QtCore import QTimer

        self.gaps: list[float] = []
        self.posted: list[float] = []
        self._last = time.perf_counter()
        self._timer = QTimer()
        self._timer.timeout.connect(self._tick)
        self._post_timer = QTimer()
        self._post_timer.timeout.connect(self._post)

    def start(self) -> None:
        self._last = time.perf_counter()
        self._timer.start(10)
        self._post_timer.start(37)

    def stop(self) -> None:
        self._timer.stop()
        self._post_timer.stop()

    def _tick(self) -> None:
        now = time.perf_counter()
        self.gaps.append((now - self._last) * 1e3 - 10.0)
        self._last = now

    def _post(self) -> None:
        from PyQt6.QtCore import QTimer

        sent = time.perf_counter()
        QTimer.singleShot(0, lambda: self.posted.append((time.perf_counter() - sent) * 1e3))


def _wait(app: Any, predicate: Any, timeout_s: float = 60.0) -> None:
    end = time.perf_counter() + timeout_s
    while not predicate():
        if time.perf_counter() > end:
            raise TimeoutError("the GUI did not show the frame in time")
        app.processEvents()
        time.sleep(0.001)


def _cancel_ms(app: Any, window: Any) -> float:
    """Time from cancelling a costly frame (1024 chirps) until the event loop runs again.

    The GUI test of cancelling (tests/gui/test_robustness.py) shows that control comes back
    while the frame cannot end; this is how long it takes.
    """
    from PyQt6.QtCore import QTimer

    window.document.set_value("rig.radar.chirps_per_frame", 1024)
    _wait(app, lambda: window.sim.busy)
    ticked: list[float] = []
    t0 = time.perf_counter()
    window.cancel_frame()
    QTimer.singleShot(0, lambda: ticked.append(time.perf_counter()))
    _wait(app, lambda: bool(ticked))
    window.undo_action.trigger()
    _wait(app, window.frame_is_current)
    return (ticked[0] - t0) * 1e3


def gui_figures(path: Path, *, seconds: float, edits: int) -> dict[str, Any]:
    """Playback rate, main-thread cost per frame and edit latencies of the main window."""
    from PyQt6.QtCore import QSettings
    from PyQt6.QtWidgets import QApplication

    from app.main_window import MainWindow
    from app.theme import apply_dark_theme

    app = QApplication.instance() or QApplication([])
    apply_dark_theme(app)
    tmp = Path(os.environ.get("TMPDIR", "/tmp")) / "tofradar-bench-gui.ini"
    window = MainWindow(path, settings=QSettings(str(tmp), QSettings.Format.IniFormat))
    window.resize(1720, 1020)
    window.show()
    try:
        _wait(app, window.frame_is_current)
        window.time.set_index(1)
        _wait(app, window.frame_is_current)
        # Playback.
        shown = [0]
        window.sim.frameReady.connect(lambda _v: shown.__setitem__(0, shown[0] + 1))
        probe = _Responsiveness()
        draw_ms = getattr(window, "frame_draw_ms", [])  # absent before issue 14
        draw_ms.clear()
        render_ms = getattr(window.viewport, "render_ms", [])  # absent before the offscreen view
        render_ms.clear()
        renders0 = window.viewport.render_count
        probe.start()
        window.time.set_playing(True)
        c0, m0, t0 = time.process_time(), time.thread_time(), time.perf_counter()
        n0 = shown[0]
        while time.perf_counter() - t0 < seconds:
            app.processEvents()
            time.sleep(0.001)
        wall = time.perf_counter() - t0
        n = shown[0] - n0
        renders = window.viewport.render_count - renders0
        cpu, main = time.process_time() - c0, time.thread_time() - m0
        window.time.set_playing(False)
        probe.stop()
        _wait(app, window.frame_is_current)
        playback = {
            "fps": n / wall, "frames": n, "seconds": wall,
            "main_thread_ms_per_frame": main * 1e3 / max(n, 1),
            "gui_process_cpu_ms_per_frame": cpu * 1e3 / max(n, 1),
            "on_frame_ms_median": statistics.median(draw_ms or [0.0]),
            "view_renders_per_frame": renders / max(n, 1),
            "view_render_ms_median": statistics.median(render_ms or [float("nan")]),
            "timer_delay_ms_max": max(probe.gaps or [0.0]),
            "timer_delay_ms_p99": float(np.percentile(probe.gaps or [0.0], 99)),
            "posted_event_ms_max": max(probe.posted or [0.0]),
            "posted_event_ms_p99": float(np.percentile(probe.posted or [0.0], 99)),
            "timeline_fps": window.document.project.timeline.frame_rate_hz,
        }
        # Edits → panels current.
        doc = window.document
        obj = _edit_object(doc.project)
        rx0 = doc.project.rig.radar.rx[0].position_mm
        pos0 = doc.project.objects[obj].pose.position_m
        half = doc.project.rig.radar.wavelength_m * 5e2
        kinds = {
            "antenna_edit_ms": lambda k: doc.set_value(
                "rig.radar.rx[0].position_mm", (rx0[0] + half * (1 + k % 2), rx0[1])),
            "object_move_ms": lambda k: doc.set_value(
                f"objects[{obj}].pose.position_m",
                (pos0[0] + 0.05 * (1 + k % 2), pos0[1], pos0[2])),
            "material_change_ms": lambda k: doc.set_value(
                f"objects[{obj}].material", ("wood", "aluminium")[k % 2]),
        }
        latency: dict[str, float] = {}
        parts: dict[str, dict[str, float]] = {}
        sent: list[float] = []
        request = window.sim.request

        def timed_request(*args: Any, **kwargs: Any) -> Any:
            sent.append(time.perf_counter())
            return request(*args, **kwargs)

        window.sim.request = timed_request
        for name, edit in kinds.items():
            times, before, compute = [], [], []
            for k in range(edits + 1):
                app.processEvents()
                time.sleep(0.2)  # the window idle, as after a user's pause
                sent.clear()
                t0 = time.perf_counter()
                edit(k)
                _wait(app, window.frame_is_current)
                app.processEvents()  # the paint of the panels
                if k:  # the first of each kind warms caches
                    times.append((time.perf_counter() - t0) * 1e3)
                    before.append((sent[0] - t0) * 1e3 if sent else float("nan"))
                    compute.append(window.last_view.timings_ms.get("wall", float("nan")))
            latency[name] = statistics.median(times)
            parts[name] = {"edit_to_request_ms": statistics.median(before),
                           "simulation_process_ms": statistics.median(compute)}
        return {"playback": playback, "latency": latency, "latency_parts": parts,
                "cancel_ms": _cancel_ms(app, window)}
    finally:
        window.document.undo_stack.setClean()
        window.close()
        window.deleteLater()
        app.processEvents()


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("project", nargs="?", default=str(OFFICE))
    parser.add_argument("--frames", type=int, default=20, help="core frames to time")
    parser.add_argument("--seconds", type=float, default=8.0, help="playback to time (s)")
    parser.add_argument("--edits", type=int, default=5, help="edits of each kind")
    parser.add_argument("--json", action="store_true")
    args = parser.parse_args()
    path = Path(args.project)
    load_before = _load()
    core = core_figures(path, frames=args.frames, edits=args.edits)
    gui = gui_figures(path, seconds=args.seconds, edits=args.edits)
    result = {"project": str(path), "core": core, "gui": gui,
              "load_before": load_before, "load_after": _load()}
    if args.json:
        print(json.dumps(result, indent=2))
        return
    p, lat = gui["playback"], gui["latency"]
    target_fps = min(core["fps"], p["timeline_fps"])
    print(f"{path.name}  load {load_before} → {result['load_after']}")
    print(f"core: {core['fps']:.1f} frames/s ({core['frame_ms']:.0f} ms), antenna edit "
          f"{core['antenna_edit_ms']:.0f} ms, object move {core['object_move_ms']:.0f} ms, "
          f"material change {core['material_change_ms']:.0f} ms")
    print(f"playback: {p['fps']:.2f} frames/s shown ({p['fps'] / target_fps:.2f} × "
          f"min(core {core['fps']:.1f}, timeline {p['timeline_fps']:.0f})); main thread "
          f"{p['main_thread_ms_per_frame']:.1f} ms CPU per shown frame (on_frame median "
          f"{p['on_frame_ms_median']:.1f} ms), GUI process {p['gui_process_cpu_ms_per_frame']:.1f}"
          f" ms CPU per frame; 3D view {p['view_renders_per_frame']:.2f} renders per frame, "
          f"{p['view_render_ms_median']:.0f} ms each; input delay max "
          f"{p['posted_event_ms_max']:.0f} ms, p99 {p['posted_event_ms_p99']:.0f} ms; "
          f"cancelling a costly frame gives control back in {gui['cancel_ms']:.0f} ms")
    for name, core_key in (("antenna_edit_ms", "antenna_edit_ms"),
                           ("object_move_ms", "frame_ms"),
                           ("material_change_ms", "frame_ms")):
        part = gui["latency_parts"][name]
        # The core's own time for the same edit: the part of the latency the GUI cannot cut.
        own = "" if core_key == name else (f", {lat[name] / core[name]:.2f} × the core's own "
                                           f"{name[:-3].replace('_', ' ')} {core[name]:.0f} ms")
        print(f"{name[:-3].replace('_', ' ')} → panels: {lat[name]:.0f} ms "
              f"({lat[name] / core[core_key]:.1f} × core {core_key[:-3].replace('_', ' ')} "
              f"{core[core_key]:.0f} ms{own}; edit → request {part['edit_to_request_ms']:.0f} "
              f"ms, simulation process {part['simulation_process_ms']:.0f} ms)")


if __name__ == "__main__":
    main()
