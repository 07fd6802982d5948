"""Fixtures of the GUI tests: a main window with its own settings, frame waiting, leak checks,
and a simulation process frozen on demand (a frame that cannot end, on any machine).

Run under Xvfb: ``xvfb-run -a -s "-screen 0 1920x1080x24" python -m pytest -m gui tests/gui``.
"""

from __future__ import annotations

import atexit
import contextlib
import gc
import os
import shutil
import signal
import subprocess
import threading
from collections.abc import Callable, Iterator
from pathlib import Path

import numpy as np
import pytest


def _own_display_per_xdist_worker() -> None:
    """Under pytest-xdist (``make pytest-gui``), each worker gets an Xvfb of its own.

    Two workers' windows on one X server take the keyboard focus and the active window
    from each other, and several tests wait for their window to be active or a field to
    have the focus. Only where a display was given (the worker then needs one) and Xvfb is
    installed; the server ends with the worker.
    """
    if not (os.environ.get("PYTEST_XDIST_WORKER") and os.environ.get("DISPLAY")
            and shutil.which("Xvfb")):
        return
    read, write = os.pipe()
    server = subprocess.Popen(["Xvfb", "-displayfd", str(write), "-screen", "0",
                               "1920x1080x24", "-nolisten", "tcp"], pass_fds=(write,),
                              stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    os.close(write)
    with os.fdopen(read) as fh:
        number = fh.readline().strip()
    if not number:
        server.kill()
        raise RuntimeError("the xdist worker's own Xvfb did not start")
    atexit.register(server.terminate)
    os.environ["DISPLAY"] = f":{number}"


_own_display_per_xdist_worker()

if not (os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY")):
    pytest.skip("GUI tests need a display (run them under xvfb-run)", allow_module_level=True)

from PyQt6.QtCore import QEvent, QSettings  # noqa: E402
from PyQt6.QtWidgets import QApplication, QMessageBox  # noqa: E402

from app.main_window import MainWindow  # noqa: E402
from app.theme import apply_dark_theme  # noqa: E402
from simcore.resources import EXAMPLES_DIR  # noqa: E402

OFFICE = EXAMPLES_DIR / "office.json"


def _office_with_screen_multipath() -> Path:
    """A copy of the office whose ToF camera uses the screen multipath model (§8).

    The default project of :func:`make_window`. The office ships the whole-room model,
    whose first frame (the room's exchange and ~5 000 receiver rows) costs a new
    window's simulation process about 1.5 s of CPU; some sixty windows opened on it
    would add two minutes to the suite without testing the GUI more. The GUI tests that
    need the office as shipped (an example opened as a template, the room model's
    fields) open :data:`OFFICE` itself.
    """
    import json
    import tempfile

    folder = Path(tempfile.mkdtemp(prefix="tofradar-gui-office-"))
    atexit.register(shutil.rmtree, folder, ignore_errors=True)
    data = json.loads(OFFICE.read_text(encoding="utf-8"))
    data["rig"]["tof"]["multipath_model"] = "screen"
    path = folder / "office.json"
    path.write_text(json.dumps(data, indent=2), encoding="utf-8")
    return path


#: What :func:`make_window` opens by default (see :func:`_office_with_screen_multipath`).
OFFICE_SCREEN = _office_with_screen_multipath()
#: The least time any wait of a GUI test allows (``qtbot.waitUntil``, ``waitExposed``, and
#: so ``wait_frame``). A wait is for something that must happen, never a timing check: on a
#: loaded 2-core machine (the test suite on both cores, Xvfb and software OpenGL beside it)
#: a new window's first frame took over 60 s, and a 2-5 s wait for a click's effect failed
#: for the same reason. A wait that is met returns at once; only a real failure waits
#: this long (and pytest-timeout's 15 min stops a hang).
WAIT_FLOOR_MS = 300_000
FRAME_TIMEOUT_MS = WAIT_FLOOR_MS


@pytest.fixture(autouse=True)
def no_leaked_windows(qapp: QApplication) -> Iterator[None]:
    """Fail a test that leaves top-level windows open or worker threads running."""
    apply_dark_theme(qapp)
    threads_before = {t.ident for t in threading.enumerate()}
    yield
    for w in qapp.topLevelWidgets():
        if w.isVisible():
            w.close()
    qapp.processEvents()
    # Delete what this test closed now, not at some later test's event processing: a
    # pyqtgraph item whose Python wrapper the garbage collector frees while its scene is
    # still painted crashes the process (seen once in ~190 tests: AxisItem "has been
    # deleted" in GraphicsView.paintEvent, then a segfault).
    QApplication.sendPostedEvents(None, QEvent.Type.DeferredDelete.value)
    gc.collect()
    qapp.processEvents()
    leaked = [w for w in qapp.topLevelWidgets() if w.isVisible()]
    assert not leaked, f"top-level widgets left open: {leaked}"
    extra = [t for t in threading.enumerate() if t.ident not in threads_before and t.is_alive()
             and not t.daemon]
    assert not extra, f"threads left running: {extra}"


@pytest.fixture(autouse=True)
def patient_waits(qtbot, monkeypatch: pytest.MonkeyPatch) -> None:
    """Every ``qtbot.waitUntil`` and ``qtbot.waitExposed`` allows at least
    :data:`WAIT_FLOOR_MS`, whatever timeout its test wrote."""
    wait_until, wait_exposed = qtbot.waitUntil, qtbot.waitExposed

    def until(callback, *, timeout: int = 5000) -> None:
        wait_until(callback, timeout=max(timeout, WAIT_FLOOR_MS))

    def exposed(widget, *, timeout: int = 5000):
        return wait_exposed(widget, timeout=max(timeout, WAIT_FLOOR_MS))

    monkeypatch.setattr(qtbot, "waitUntil", until)
    monkeypatch.setattr(qtbot, "waitExposed", exposed)


@pytest.fixture
def make_window(qtbot, tmp_path: Path) -> Iterator:
    """Factory of main windows that are shut down (changes discarded) at the end."""
    made: list[MainWindow] = []

    def factory(project: Path | None = OFFICE_SCREEN) -> MainWindow:
        settings = QSettings(str(tmp_path / "settings.ini"), QSettings.Format.IniFormat)
        window = MainWindow(project, settings=settings)
        window.ask_save_changes = lambda: QMessageBox.StandardButton.Discard
        # Edits of a shared material change all its objects, without asking.
        window.material_editor.ask_shared_edit = lambda *_: "all"
        window.resize(1720, 1020)
        window.show()
        qtbot.waitExposed(window)
        made.append(window)
        return window

    yield factory
    for window in made:
        window.document.undo_stack.setClean()
        window.close()
        # Closing released the VTK window and stopped the simulation worker.
        assert window.viewport._closed
        assert not window.sim.is_running()
        window.deleteLater()
    QApplication.processEvents()


@pytest.fixture
def wait_frame(qtbot):
    """``wait_frame(window)``: wait until the panels show the current state's frame."""

    def wait(window: MainWindow, timeout: int = FRAME_TIMEOUT_MS) -> None:
        qtbot.waitUntil(window.frame_is_current, timeout=timeout)

    return wait


@pytest.fixture
def is_non_blank():
    """``is_non_blank(qimage)``: the image is not one flat colour."""
    return non_blank


def non_blank(image, *, min_std: float = 4.0) -> bool:
    """True when a QImage is not a single flat colour."""
    from PyQt6.QtGui import QImage

    img = image.convertToFormat(QImage.Format.Format_RGB32)
    ptr = img.constBits()
    ptr.setsize(img.sizeInBytes())
    arr = np.frombuffer(ptr, dtype=np.uint8).reshape(img.height(), img.bytesPerLine())
    arr = arr[:, : img.width() * 4].reshape(img.height(), img.width(), 4)[..., :3]
    return float(arr.std()) > min_std and len(np.unique(arr.reshape(-1, 3), axis=0)) > 16


@pytest.fixture
def frozen_simulation() -> Callable[..., contextlib.AbstractContextManager[int]]:
    """``with frozen_simulation(window) as pid:`` the window's simulation process is stopped
    (SIGSTOP) for the block and continued after it.

    A frame in flight then cannot end, however fast or loaded the machine: a test shows
    that the GUI goes on without a frame (input, cancel, newer requests) by what happens
    while it is frozen, not by wall-clock thresholds (issue 41: no test's outcome may
    depend on the machine's load; timings are in ``benchmarks/bench_gui.py``).
    """

    @contextlib.contextmanager
    def freeze(window: MainWindow) -> Iterator[int]:
        pid = window.sim.process_id
        assert pid is not None, "no simulation process to freeze"
        os.kill(pid, signal.SIGSTOP)
        try:
            yield pid
        finally:
            with contextlib.suppress(ProcessLookupError):
                os.kill(pid, signal.SIGCONT)

    return freeze
