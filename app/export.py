"""Exports: the headless dataset job in a thread, and PNG images of the panels.

The dataset job is :func:`simcore.runner.run_dataset`, the same one ``tofradar run`` uses; the
GUI shows its progress in a dialog whose Cancel button stops it after the current frame.
"""

from __future__ import annotations

import re
import threading
from pathlib import Path

from PyQt6.QtCore import QThread, pyqtSignal
from PyQt6.QtWidgets import QWidget

from simcore.scene import Project
from simcore.scene.project_io import project_to_json


class DatasetExportJob(QThread):
    """Runs :func:`simcore.runner.run_dataset` (the CLI's ``tofradar run``) off the GUI thread.

    Signals
    -------
    progress(int, int)
        Frames written, frames in total.
    done(str)
        Finished; the message says what was written (or that it was cancelled).
    failed(str)
        The job failed; the message says why.
    """

    progress = pyqtSignal(int, int)
    done = pyqtSignal(str)
    failed = pyqtSignal(str)

    def __init__(self, project: Project, base_dir: Path, out: Path, *, n_frames: int,
                 overwrite: bool = True, parent: QWidget | None = None):
        super().__init__(parent)
        self.project_json = project_to_json(project)
        self.seed = project.seed
        self.base_dir = base_dir
        self.out = out
        self.n_frames = n_frames
        self.overwrite = overwrite
        self._cancel = threading.Event()
        self.report = None

    def cancel(self) -> None:
        """Stop after the frame being computed; the file stays valid (resumable)."""
        self._cancel.set()

    def run(self) -> None:  # noqa: D102 - QThread API
        from simcore.runner import run_dataset

        def on_frame(done: int, total: int, _result: object) -> bool:
            self.progress.emit(done, total)
            return not self._cancel.is_set()

        try:
            report = run_dataset(self.project_json, self.base_dir, self.out,
                                 n_frames=self.n_frames, seed=self.seed,
                                 overwrite=self.overwrite, on_frame=on_frame)
        except Exception as exc:  # noqa: BLE001 - reported in a dialog
            self.failed.emit(f"{type(exc).__name__}: {exc}")
            return
        self.report = report
        if report.interrupted:
            self.done.emit(f"Cancelled: {report.frames_done} of {self.n_frames} frames are in "
                           f"{self.out} (continue with 'tofradar run --resume')")
        else:
            self.done.emit(f"Wrote {report.frames_done} frames to {self.out}")


def safe_file_stem(title: str) -> str:
    """A file-name-safe version of a panel title."""
    return re.sub(r"[^A-Za-z0-9]+", "_", title).strip("_").lower() or "panel"


def export_panel_images(panels: dict[str, QWidget], folder: Path) -> list[Path]:
    """Save a PNG of every panel (title → widget) into ``folder``; returns the files."""
    folder.mkdir(parents=True, exist_ok=True)
    written = []
    for title, widget in panels.items():
        path = folder / f"{safe_file_stem(title)}.png"
        if widget.grab().save(str(path)):
            written.append(path)
    return written
