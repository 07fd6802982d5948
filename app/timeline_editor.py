"""Timeline and seed editor: duration, frame rate and the project's random seed.

Edits go through the document (one undo step each) and are saved with the project
(``timeline.duration_s``, ``timeline.frame_rate_hz``, ``seed``).
"""

from __future__ import annotations

from PyQt6.QtCore import pyqtSignal
from PyQt6.QtWidgets import QFormLayout, QGroupBox, QLabel, QVBoxLayout, QWidget

from app.document import ProjectDocument
from app.widgets import int_spin, set_quietly, spin, try_edit

#: Ranges of the editors (the model only asks for positive values).
MAX_DURATION_S = 3600.0
MIN_DURATION_S = 0.001
MIN_FRAME_RATE_HZ = 0.01
MAX_FRAME_RATE_HZ = 10_000.0
MAX_SEED = 2**31 - 1


class TimelineEditor(QWidget):
    """Duration (s), frame rate (Hz) and seed, with the frame count and period they give."""

    editFailed = pyqtSignal(str)

    def __init__(self, document: ProjectDocument, parent: QWidget | None = None):
        super().__init__(parent)
        self.document = document
        layout = QVBoxLayout(self)
        layout.setContentsMargins(4, 4, 4, 4)
        box = QGroupBox("Timeline")
        form = QFormLayout(box)
        self.duration = spin(
            minimum=MIN_DURATION_S, maximum=MAX_DURATION_S, decimals=3, step=0.5, suffix="s",
            tooltip=f"Simulated time span ({MIN_DURATION_S:g}–{MAX_DURATION_S:g} s). Frames "
                    "are taken at t = k / frame rate for k = 0 … round(duration × rate) − 1.")
        self.duration.valueChanged.connect(
            lambda v: self._set("timeline.duration_s", float(v), "Set duration",
                                self.duration))
        form.addRow("duration", self.duration)
        self.frame_rate = spin(
            minimum=MIN_FRAME_RATE_HZ, maximum=MAX_FRAME_RATE_HZ, decimals=2, step=1.0,
            suffix="Hz",
            tooltip=f"Frames per second of both sensors ({MIN_FRAME_RATE_HZ:g}–"
                    f"{MAX_FRAME_RATE_HZ:g} Hz); the radar's chirps of one frame must fit in "
                    "one frame period")
        self.frame_rate.valueChanged.connect(
            lambda v: self._set("timeline.frame_rate_hz", float(v), "Set frame rate",
                                self.frame_rate))
        form.addRow("frame rate", self.frame_rate)
        self.derived = QLabel("")
        self.derived.setStyleSheet("color: #9aa4ae;")
        self.derived.setToolTip("What the duration and frame rate give")
        form.addRow(self.derived)
        self.warning = QLabel("")
        self.warning.setStyleSheet("color: #ff6e6e;")
        self.warning.setWordWrap(True)
        form.addRow(self.warning)
        layout.addWidget(box)
        seed_box = QGroupBox("Randomness")
        sform = QFormLayout(seed_box)
        self.seed = int_spin(
            minimum=0, maximum=MAX_SEED,
            tooltip=f"Seed of every random draw (noise, speckle) (0–{MAX_SEED}): the same "
                    "seed gives bit-identical frames; change it for another noise "
                    "realisation")
        self.seed.valueChanged.connect(
            lambda v: self._set("seed", int(v), "Set seed", self.seed))
        sform.addRow("seed", self.seed)
        layout.addWidget(seed_box)
        layout.addStretch(1)
        document.projectChanged.connect(self.refresh)
        self.refresh()

    def _set(self, path: str, value: object, text: str, widget: QWidget) -> None:
        """One undoable edit; a refused value stays in ``widget``, marked with the reason."""
        try_edit(self.editFailed.emit,
                 lambda: self.document.set_value(path, value, text=text), self.refresh,
                 field=widget)

    def refresh(self, *_: object) -> None:
        """Show the project's timeline and seed."""
        project = self.document.project
        tl = project.timeline
        set_quietly(self.duration, tl.duration_s)
        set_quietly(self.frame_rate, tl.frame_rate_hz)
        set_quietly(self.seed, project.seed)
        period = 1.0 / tl.frame_rate_hz
        self.derived.setText(
            f"{tl.n_frames} frames, one every {period * 1e3:.4g} ms; last frame at "
            f"t = {tl.frame_time(tl.n_frames - 1):.4g} s")
        radar_s = project.rig.radar.frame_duration_s
        if radar_s > period:
            self.warning.setText(
                f"⚠ the radar's frame ({radar_s * 1e3:.3g} ms of chirps) is longer than the "
                f"frame period ({period * 1e3:.3g} ms): lower the frame rate or the chirp "
                "count")
        else:
            self.warning.setText("")
