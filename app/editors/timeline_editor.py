"""Timeline and seed editor: duration, frame rate and the project's random seed.

Edits go through the document (one undo step each) and are saved with the project
(``timeline.duration_s``, ``timeline.frame_rate_hz``, ``seed``). The fields take the one
validation path of every editor (:func:`app.editors.field_editors.commit_value`): −1 s, a frame
rate of 0 or a seed of −3 are refused at the field with the reason, never clamped.
"""

from __future__ import annotations

from PyQt6.QtCore import pyqtSignal
from PyQt6.QtWidgets import QGroupBox, QLabel, QVBoxLayout, QWidget

from app.document.document import ProjectDocument
from app.editors.field_editors import FieldForm, FieldSpec

#: Limits of the GUI beyond the model's (which only asks for positive values).
MAX_DURATION_S = 3600.0
MAX_FRAME_RATE_HZ = 10_000.0
MAX_SEED = 2**31 - 1

DURATION = FieldSpec(
    "timeline.duration_s", "duration", "s",
    "Simulated time span. Frames are taken at t = k / frame rate for "
    "k = 0 … round(duration × rate) − 1", decimals=3, step=0.5, maximum=MAX_DURATION_S)
FRAME_RATE = FieldSpec(
    "timeline.frame_rate_hz", "frame rate", "Hz",
    "Frames per second of both sensors; the radar's chirps of one frame must fit in one "
    "frame period", decimals=2, step=1.0, maximum=MAX_FRAME_RATE_HZ)
SEED = FieldSpec(
    "seed", "seed", "",
    "Seed of every random draw (noise, speckle): the same seed gives bit-identical frames; "
    "change it for another noise realisation", kind="int", maximum=MAX_SEED)


class TimelineEditor(QWidget):
    """Duration (s), frame rate (Hz) and seed, with the frame count and period they give."""

    editFailed = pyqtSignal(str)

    def __init__(self, document: ProjectDocument, parent: QWidget | None = None):
        super().__init__(parent)
        self.document = document
        layout = QVBoxLayout(self)
        layout.setContentsMargins(4, 4, 4, 4)
        box = QGroupBox("Timeline")
        self.timeline_form = FieldForm(document, [DURATION, FRAME_RATE])
        self.timeline_form.editFailed.connect(self.editFailed)
        QVBoxLayout(box).addWidget(self.timeline_form)
        self.duration = self.timeline_form.widgets[DURATION.path]
        self.frame_rate = self.timeline_form.widgets[FRAME_RATE.path]
        form = self.timeline_form.form
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
        self.seed_form = FieldForm(document, [SEED])
        self.seed_form.editFailed.connect(self.editFailed)
        QVBoxLayout(seed_box).addWidget(self.seed_form)
        self.seed = self.seed_form.widgets[SEED.path]
        layout.addWidget(seed_box)
        layout.addStretch(1)
        document.projectChanged.connect(self.refresh)
        self.refresh()

    def refresh(self, *_: object) -> None:
        """Show what the project's timeline gives (the forms show its values)."""
        project = self.document.project
        tl = project.timeline
        period = 1.0 / tl.frame_rate_hz
        self.derived.setText(
            f"{tl.n_frames} frames, one every {period * 1e3:.4g} ms; last frame at "
            f"t = {tl.frame_time(tl.n_frames - 1):.4g} s")
        # Every radar's chirps must fit into the frame period (none in a ToF-only project).
        long = [(name, cfg.frame_duration_s)  # type: ignore[attr-defined]
                for name, cfg in project.sensors_of_kind("radar").items()
                if cfg.frame_duration_s > period]  # type: ignore[attr-defined]
        if long:
            name, radar_s = long[0]
            which = "the radar's" if len(project.sensors_of_kind("radar")) == 1 else \
                f"radar {name}'s"
            self.warning.setText(
                f"⚠ {which} frame ({radar_s * 1e3:.3g} ms of chirps) is longer than the "
                f"frame period ({period * 1e3:.3g} ms): lower the frame rate or the chirp "
                "count")
        else:
            self.warning.setText("")
