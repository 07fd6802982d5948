"""Exports: the headless dataset job in a thread, its dialog, and PNG images of the panels.

The dataset job is :func:`simcore.runs.runner.run_dataset`, the same one ``tofradar run`` uses; the
GUI shows its progress in a dialog whose Cancel button stops it after the current frame.
:class:`ExportDialog` asks for what ``tofradar run`` takes (issue #34): destination and
format (HDF5 ``.h5``, a Zarr store ``.zarr`` or MCAP ``.mcap``), frames or duration, seed,
and a folder of PNG
previews (``--preview DIR``); :func:`completion_box` ends the export with buttons that
open the folder or the dataset.
"""

from __future__ import annotations

import re
import threading
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from PyQt6.QtCore import QThread, QUrl, pyqtSignal
from PyQt6.QtWidgets import (
    QCheckBox,
    QComboBox,
    QDialog,
    QDialogButtonBox,
    QDoubleSpinBox,
    QFileDialog,
    QFormLayout,
    QHBoxLayout,
    QLabel,
    QLineEdit,
    QMessageBox,
    QPushButton,
    QRadioButton,
    QSpinBox,
    QWidget,
)

from app.widgets.inputs import INT_MAX, clear_field_error, show_field_error
from simcore.scene import Project
from simcore.scene.project_io import project_to_json

#: Output formats of ``tofradar run --out``: label → file suffix.
FORMATS = {"HDF5 dataset (.h5)": ".h5", "Zarr store (.zarr)": ".zarr",
           "MCAP recording (.mcap)": ".mcap"}
#: The suffixes in words, for the destination's message ("…end in .h5, .zarr or .mcap").
SUFFIX_WORDS = ", ".join(list(FORMATS.values())[:-1]) + f" or {list(FORMATS.values())[-1]}"


class DatasetExportJob(QThread):
    """Runs :func:`simcore.runs.runner.run_dataset` (the CLI's ``tofradar run``) off the GUI thread.

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
                 overwrite: bool = True, seed: int | None = None,
                 preview_dir: Path | None = None, parent: QWidget | None = None):
        super().__init__(parent)
        self.project_json = project_to_json(project)
        self.seed = project.seed if seed is None else int(seed)
        self.preview_dir = preview_dir
        self._preview_axes = None if preview_dir is None else preview_axes(project)
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
        from simcore.runs.runner import run_dataset

        def on_frame(done: int, total: int, result: Any) -> bool:
            if self.preview_dir is not None:
                from simcore.io.previews import save_frame_previews

                save_frame_previews(self.preview_dir, result.index, result.items,
                                    self._preview_axes)
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


def preview_axes(project: Project) -> Any:
    """What the preview figures of each sensor need, as ``tofradar run --preview`` draws them."""
    from simcore.io.previews import preview_sensors

    return preview_sensors(project)


@dataclass(frozen=True)
class ExportChoice:
    """What :class:`ExportDialog` asks for: ``tofradar run``'s options."""

    out: Path
    n_frames: int
    seed: int
    preview_dir: Path | None


class ExportDialog(QDialog):
    """Destination and format, frames or duration, seed and previews of a dataset export.

    Parameters
    ----------
    project : Project
        The project to export (its timeline and seed are the defaults).
    base_dir : Path
        Where the destination is proposed.
    """

    def __init__(self, project: Project, base_dir: Path, parent: QWidget | None = None):
        super().__init__(parent)
        self.setWindowTitle("Export dataset")
        self.frame_rate_hz = project.timeline.frame_rate_hz
        form = QFormLayout(self)
        self.format = QComboBox()
        self.format.addItems(list(FORMATS))
        self.format.setToolTip("HDF5: the dataset layout of docs/dataset.md; Zarr: the same "
                               "layout as a folder of chunks (docs/scaling.md); MCAP: a "
                               "recording for Foxglove / ROS 2 tools (as tofradar run --out)")
        self.format.currentIndexChanged.connect(self._follow_format)
        form.addRow("format", self.format)
        row = QHBoxLayout()
        self.destination = QLineEdit(str(base_dir / f"{project.name}.h5"))
        self.destination.setToolTip("The file (a folder for Zarr) to write; an existing one "
                                    "is replaced")
        browse = QPushButton("Browse…")
        browse.clicked.connect(self._browse)
        row.addWidget(self.destination, 1)
        row.addWidget(browse)
        form.addRow("destination", row)
        length = QHBoxLayout()
        self.by_frames = QRadioButton("frames")
        self.by_duration = QRadioButton("duration")
        self.frames = QSpinBox()
        self.frames.setRange(1, INT_MAX)
        n = max(1, round(project.timeline.duration_s * self.frame_rate_hz))
        self.frames.setValue(n)
        self.frames.setToolTip("Number of frames (tofradar run --frames)")
        self.duration = QDoubleSpinBox()
        self.duration.setRange(0.001, 1e7)
        self.duration.setDecimals(3)
        self.duration.setSuffix(" s")
        self.duration.setValue(project.timeline.duration_s)
        self.duration.setToolTip(f"Seconds of the timeline at {self.frame_rate_hz:g} frames/s "
                                 "(tofradar run --duration)")
        self.by_frames.setChecked(True)
        for w in (self.by_frames, self.frames, self.by_duration, self.duration):
            length.addWidget(w)
        form.addRow("length", length)
        self.count = QLabel("")
        self.count.setStyleSheet("color: #9aa4ae;")
        form.addRow("", self.count)
        for signal in (self.frames.valueChanged, self.duration.valueChanged,
                       self.by_frames.toggled):
            signal.connect(self._update_count)
        self.seed = QSpinBox()
        self.seed.setRange(0, INT_MAX)
        self.seed.setValue(project.seed)
        self.seed.setToolTip("Random seed of the noise (tofradar run --seed); the project's "
                             "by default, so the export repeats what the GUI shows")
        form.addRow("seed", self.seed)
        self.previews = QCheckBox("write PNG previews of every frame into")
        self.preview_dir = QLineEdit("")
        self.preview_dir.setToolTip("Folder of labelled PNG figures per frame (tofradar run "
                                    "--preview DIR)")
        self.previews.toggled.connect(self.preview_dir.setEnabled)
        self.preview_dir.setEnabled(False)
        prow = QHBoxLayout()
        prow.addWidget(self.previews)
        prow.addWidget(self.preview_dir, 1)
        form.addRow("previews", prow)
        buttons = QDialogButtonBox(QDialogButtonBox.StandardButton.Ok
                                   | QDialogButtonBox.StandardButton.Cancel)
        buttons.button(QDialogButtonBox.StandardButton.Ok).setText("Export")
        buttons.accepted.connect(self.accept)
        buttons.rejected.connect(self.reject)
        form.addRow(buttons)
        self.destination.textChanged.connect(self._follow_destination)
        self._follow_destination(self.destination.text())
        self._update_count()

    def n_frames(self) -> int:
        """Frames the export writes (from frames, or duration × frame rate)."""
        from simcore.runs.runner import frame_count

        if self.by_frames.isChecked():
            return frame_count(self.frames.value(), None, self.frame_rate_hz, 0)
        return frame_count(None, self.duration.value(), self.frame_rate_hz, 0)

    def _update_count(self, *_: object) -> None:
        try:
            n = self.n_frames()
        except ValueError as exc:
            self.count.setText(f"⚠ {exc}")
            return
        self.count.setText(f"{n} frame{'s' if n != 1 else ''} at {self.frame_rate_hz:g} "
                           f"frames/s = {n / self.frame_rate_hz:g} s")

    def _follow_format(self, _index: int = 0) -> None:
        suffix = FORMATS[self.format.currentText()]
        path = Path(self.destination.text().strip() or "dataset")
        if path.suffix.lower() != suffix:
            self.destination.setText(str(path.with_suffix(suffix)))

    def _follow_destination(self, text: str) -> None:
        suffix = Path(text.strip()).suffix.lower()
        for label, s in FORMATS.items():
            if s == suffix and self.format.currentText() != label:
                self.format.blockSignals(True)
                self.format.setCurrentText(label)
                self.format.blockSignals(False)
        if not self.previews.isChecked():
            stem = Path(text.strip() or "dataset")
            self.preview_dir.setText(str(stem.with_name(f"{stem.stem}_previews")))

    def _browse(self) -> None:
        label = self.format.currentText()
        path, _ = QFileDialog.getSaveFileName(self, "Export dataset", self.destination.text(),
                                              f"{label.split(' (')[0]} (*{FORMATS[label]})")
        if path:
            self.destination.setText(path)
            self._follow_format()

    def choice(self) -> ExportChoice:
        """The options as typed.

        Raises
        ------
        ValueError
            A destination that cannot be written or a frame count over the limit (also
            shown at the field).
        """
        text = self.destination.text().strip()
        out = Path(text)
        problem = ""
        if not text:
            problem = "type the file to write"
        elif out.suffix.lower() not in FORMATS.values():
            problem = f"the file must end in {SUFFIX_WORDS} (got {out.name!r})"
        elif out.is_dir() and out.suffix.lower() != ".zarr":
            problem = f"{out} is a folder; give a file name such as {out / 'run.h5'}"
        if problem:
            show_field_error(self.destination, problem)
            raise ValueError(problem)
        clear_field_error(self.destination)
        try:
            n = self.n_frames()
        except ValueError as exc:
            field = self.frames if self.by_frames.isChecked() else self.duration
            show_field_error(field, str(exc))
            raise
        preview = None
        if self.previews.isChecked():
            folder = self.preview_dir.text().strip()
            if not folder:
                show_field_error(self.preview_dir, "type the folder of the previews")
                raise ValueError("type the folder of the previews")
            preview = Path(folder)
        return ExportChoice(out, n, self.seed.value(), preview)

    def accept(self) -> None:  # noqa: D102 - Qt API
        try:
            self.choice()
        except ValueError:
            return  # the field shows why; the dialog stays open
        super().accept()


def completion_box(parent: QWidget, message: str, out: Path, preview_dir: Path | None,
                   open_url: Any) -> QMessageBox:
    """The export's closing dialog: what was written, and buttons that open it.

    ``open_url(QUrl)`` opens a button's target (the main window passes
    :meth:`QDesktopServices.openUrl`; tests record it). Each button's target is in its
    ``url`` property.
    """
    box = QMessageBox(QMessageBox.Icon.Information, "Export finished", message,
                      QMessageBox.StandardButton.Close, parent)
    box.setObjectName("exportDone")
    targets = [("Open folder", QUrl.fromLocalFile(str(Path(out).resolve().parent)))]
    if Path(out).exists():
        targets.append(("Open dataset", QUrl.fromLocalFile(str(Path(out).resolve()))))
    if preview_dir is not None and Path(preview_dir).exists():
        targets.append(("Open previews", QUrl.fromLocalFile(str(Path(preview_dir).resolve()))))
    for text, url in targets:
        button = box.addButton(text, QMessageBox.ButtonRole.ActionRole)
        button.setProperty("url", url)
        # An action button would close the box; it opens its target and the box stays.
        try:
            button.clicked.disconnect()
        except TypeError:  # nothing connected
            pass
        button.clicked.connect(lambda _=False, u=url: open_url(u))
    return box
