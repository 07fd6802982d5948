"""Time: the current frame of the project timeline, play/pause/step/scrub controls."""

from __future__ import annotations

from PyQt6.QtCore import QObject, QSignalBlocker, Qt, QTimer, pyqtSignal
from PyQt6.QtWidgets import QHBoxLayout, QLabel, QSizePolicy, QSlider, QStyle, QToolButton, QWidget

from app.document.document import ProjectDocument


class TimeController(QObject):
    """Current frame index and playback state of the project timeline.

    While playing, the controller advances one frame per tick of the timeline's frame
    rate, but only once the frame shown has been computed (``frame_done``): playback runs
    in real time when the simulator keeps up, and when it does not, it advances as soon as
    the late frame is shown. :attr:`next_index` is the frame playback shows next, which
    the window asks the simulator to compute ahead while it draws the current one.

    Signals
    -------
    indexChanged(int)
    playingChanged(bool)
    frameShown(int)
        The frame of the current index was shown (or could not be computed).
    """

    indexChanged = pyqtSignal(int)
    playingChanged = pyqtSignal(bool)
    frameShown = pyqtSignal(int)

    def __init__(self, document: ProjectDocument, parent: QObject | None = None):
        super().__init__(parent)
        self.document = document
        self._index = 0
        self._waiting = False
        self._due = False
        self._timer = QTimer(self)
        self._timer.timeout.connect(self._tick)
        document.projectChanged.connect(self._clamp)
        document.projectReplaced.connect(self._rewind)

    @property
    def index(self) -> int:
        """Current frame index."""
        return self._index

    @property
    def n_frames(self) -> int:
        """Frames in the timeline."""
        return self.document.project.timeline.n_frames

    @property
    def time_s(self) -> float:
        """Time of the current frame (s)."""
        return self.document.project.timeline.frame_time(self._index)

    @property
    def next_index(self) -> int:
        """The frame playback shows after the current one (wraps around)."""
        return (self._index + 1) % max(self.n_frames, 1)

    @property
    def playing(self) -> bool:
        """True while playing."""
        return self._timer.isActive()

    def set_index(self, index: int) -> None:
        """Go to frame ``index`` (clamped to the timeline)."""
        index = max(0, min(int(index), self.n_frames - 1))
        if index != self._index:
            self._index = index
            self._waiting = True
            self.indexChanged.emit(index)

    def step(self, delta: int) -> None:
        """Move ``delta`` frames (wrapping around while playing)."""
        n = self.n_frames
        target = self._index + delta
        if self.playing:
            target %= n
        self.set_index(target)

    def set_playing(self, playing: bool) -> None:  # noqa: FBT001 - Qt slot
        """Start or stop playback."""
        if playing == self.playing:
            return
        if playing:
            rate = self.document.project.timeline.frame_rate_hz
            self._timer.start(max(15, int(1000 / rate)))
        else:
            self._timer.stop()
            self._due = False
        self.playingChanged.emit(playing)

    def frame_done(self) -> None:
        """The frame of the current index has been shown (or could not be computed)."""
        self._waiting = False
        self.frameShown.emit(self._index)
        if self._due and self.playing:
            self._due = False
            self.step(1)  # a tick passed while the frame was computing: go on at once

    def _tick(self) -> None:
        if self._waiting:
            self._due = True
        else:
            self.step(1)

    def _rewind(self) -> None:
        self.set_index(0)

    def _clamp(self, _project: object) -> None:
        if self._index >= self.n_frames:
            self.set_index(self.n_frames - 1)


class TimeBar(QWidget):
    """Play/pause, step, a scrub slider and the time read-out."""

    def __init__(self, controller: TimeController, parent: QWidget | None = None):
        super().__init__(parent)
        self.controller = controller
        layout = QHBoxLayout(self)
        layout.setContentsMargins(4, 0, 4, 0)
        icon = self.style().standardIcon
        pix = QStyle.StandardPixmap
        self._play_icon = icon(pix.SP_MediaPlay)
        self._pause_icon = icon(pix.SP_MediaPause)
        self.first_button = QToolButton()
        self.first_button.setIcon(icon(pix.SP_MediaSkipBackward))
        self.first_button.setToolTip("First frame (Home)")
        self.first_button.clicked.connect(lambda: controller.set_index(0))
        self.back_button = QToolButton()
        self.back_button.setIcon(icon(pix.SP_MediaSeekBackward))
        self.back_button.setToolTip("Previous frame (,)")
        self.back_button.clicked.connect(lambda: controller.step(-1))
        self.play_button = QToolButton()
        self.play_button.setIcon(self._play_icon)
        self.play_button.setCheckable(True)
        self.play_button.setToolTip("Play / pause (Space)")
        self.play_button.toggled.connect(controller.set_playing)
        self.forward_button = QToolButton()
        self.forward_button.setIcon(icon(pix.SP_MediaSeekForward))
        self.forward_button.setToolTip("Next frame (.)")
        self.forward_button.clicked.connect(lambda: controller.step(1))
        self.slider = QSlider(Qt.Orientation.Horizontal)
        self.slider.setMinimumWidth(260)
        self.setSizePolicy(QSizePolicy.Policy.Expanding, QSizePolicy.Policy.Preferred)
        self.slider.setToolTip("Scrub through the timeline (frames)")
        self.slider.valueChanged.connect(controller.set_index)
        self.label = QLabel("")
        self.label.setMinimumWidth(150)
        self.label.setToolTip("Simulated time (s) and frame index")
        for w in (self.first_button, self.back_button, self.play_button, self.forward_button,
                  self.slider, self.label):
            layout.addWidget(w)
        # While playing, the read-out follows the frames shown, so it repaints together
        # with the panels instead of once more at every tick.
        controller.indexChanged.connect(lambda _i: None if controller.playing else self.refresh())
        controller.frameShown.connect(self.refresh)
        controller.playingChanged.connect(self._on_playing)
        controller.document.projectChanged.connect(self.refresh)
        self.refresh()

    def _on_playing(self, playing: bool) -> None:  # noqa: FBT001
        with QSignalBlocker(self.play_button):
            self.play_button.setChecked(playing)
        self.play_button.setIcon(self._pause_icon if playing else self._play_icon)

    def refresh(self, *_: object) -> None:
        """Show the current time and timeline length."""
        c = self.controller
        with QSignalBlocker(self.slider):
            self.slider.setRange(0, c.n_frames - 1)
            self.slider.setValue(c.index)
        self.label.setText(f"t = {c.time_s:6.2f} s   frame {c.index + 1}/{c.n_frames}")
