"""What every live panel shares: :class:`LivePanel`, its drawing helpers, pens and colours.

The panels themselves are one module each: :mod:`app.panels.tof`,
:mod:`app.panels.range_profile`, :mod:`app.panels.range_doppler`,
:mod:`app.panels.range_azimuth` (both on :mod:`app.panels.maps`), :mod:`app.panels.rgb`
and :mod:`app.panels.spectrogram`.

Every panel shows the latest :class:`~app.frame_view.FrameView`; when the panel is hidden
(a closed or tabbed-away dock) the view is kept and drawn when the panel is shown again,
so no time is spent drawing what nobody sees. Hovering over a plot shows the value under
the cursor in the panel's read-out line.

Drawing a frame costs little: a panel only sets new data on its items. Plot titles, legends,
axis ranges and colour-bar levels are set only when they change (the ranges with some
hysteresis), because each such change re-lays out and repaints the axes; the per-frame text
(time, counts, peak) goes into a plain label above the plot. A panel that cannot draw a
frame shows why in its own error line and keeps going: one panel's failure never stops the
others or playback.
"""

from __future__ import annotations

import logging
import traceback
from typing import Any

import numpy as np
import pyqtgraph as pg
from numpy.typing import NDArray
from PyQt6.QtCore import QPointF, QSignalBlocker, pyqtSignal
from PyQt6.QtGui import QColor, QFont
from PyQt6.QtWidgets import (
    QComboBox,
    QGraphicsItem,
    QHBoxLayout,
    QLabel,
    QPushButton,
    QSizePolicy,
    QVBoxLayout,
    QWidget,
)

from app.document.identity import follow_sensor
from app.frame_view import FrameView, ObjectMarks
from simcore.scene import Project

pg.setConfigOptions(imageAxisOrder="row-major", antialias=True, background="#15181c",
                    foreground="#c8ccd2")

#: Colour of invalid ToF pixels (saturated, too dark or no return).
INVALID_RGBA = (255, 0, 200, 255)
CHANNEL_COLOURS = ["#4fc3f7", "#ffb74d", "#81c784", "#e57373", "#ba68c8", "#fff176",
                   "#4db6ac", "#f06292"]
DETECTION_BRUSH = pg.mkBrush(255, 255, 255, 40)
#: Detections labelled noise (no object above the noise in their cell), when coloured.
NOISE_BRUSH = pg.mkBrush(150, 150, 150, 90)
DETECTION_PEN = pg.mkPen("#ffffff", width=1.5)
#: Returns of the selected object, and its ground-truth mark.
SELECTED_PEN = pg.mkPen("#ffeb3b", width=3.0)
TRUTH_PEN = pg.mkPen("#80deea", width=1.5)
TRUTH_SELECTED_PEN = pg.mkPen("#ffeb3b", width=2.5)
#: ToF outlines of objects (RGBA): every object, the selected one.
OUTLINE_RGBA = (255, 255, 255, 150)
OUTLINE_SELECTED_RGBA = (255, 235, 59, 255)
#: With more ground-truth marks than this in a panel, only the selected object is labelled.
MAX_TRUTH_LABELS = 6
#: A truth mark within this distance of the mouse (px) is named in the read-out line.
HOVER_PX = 8
#: Nearest-surface marks (issue #34): where the radar sees an object begin.
NEAR_PEN = pg.mkPen("#80deea", width=1.2)
#: Colour map and half-range (dB) of difference views (A/B comparison).
DIFF_CMAP = "CET-D1"
DIFF_SPAN_DB = 20.0
log = logging.getLogger(__name__)


#: Shown in every live panel while the scene has no objects.
EMPTY_SCENE_HINT = ("The scene is empty: the ToF camera sees no surface (magenta = no valid "
                    "depth) and the radar only noise. Add an object (Add ▾ in the toolbar): "
                    "it lands 2 m in front of the sensors, facing them.")


def plural(n: int, word: str) -> str:
    """``1 detection``, ``2 detections``."""
    return f"{n} {word}" if n == 1 else f"{n} {word}s"


def detection_pens(detections: Any, selected_id: int | None) -> Any:
    """One pen per detection: the selected object's returns stand out (yellow, thick)."""
    labels = getattr(detections, "object_id", None)
    if selected_id is None or labels is None:
        return DETECTION_PEN
    return [SELECTED_PEN if int(i) == selected_id else DETECTION_PEN for i in labels]


def object_outlines(ids: NDArray[np.int32], selected_id: int | None) -> NDArray[np.uint8]:
    """RGBA image (H, W, 4) of the boundaries between objects in a ground-truth id image.

    A pixel is on an outline when it shows an object (id ≥ 0) and a 4-neighbour shows
    another id (another object or the background); the selected object's outline is drawn
    in :data:`OUTLINE_SELECTED_RGBA`, the others in :data:`OUTLINE_RGBA`.
    """
    edge = np.zeros(ids.shape, dtype=bool)
    edge[:, :-1] |= ids[:, :-1] != ids[:, 1:]
    edge[:, 1:] |= ids[:, 1:] != ids[:, :-1]
    edge[:-1, :] |= ids[:-1, :] != ids[1:, :]
    edge[1:, :] |= ids[1:, :] != ids[:-1, :]
    edge &= ids >= 0
    out = np.zeros((*ids.shape, 4), dtype=np.uint8)
    out[edge] = OUTLINE_RGBA
    if selected_id is not None:
        out[edge & (ids == selected_id)] = OUTLINE_SELECTED_RGBA
    return out


def label_brush(object_id: int) -> Any:
    """Brush of a detection coloured by its ground-truth label (grey for noise, −1)."""
    if object_id < 0:
        return NOISE_BRUSH
    colour = pg.intColor(int(object_id), hues=9, values=1, alpha=200)
    return pg.mkBrush(colour)


def detection_brushes(detections: Any, *, by_label: bool) -> Any:
    """One brush per detection: by ground-truth label when asked and known, else plain."""
    labels = getattr(detections, "object_id", None)
    if not by_label or labels is None:
        return DETECTION_BRUSH
    return [label_brush(int(i)) for i in labels]


def _set_text(label: Any, text: str) -> None:
    """Set a label's text only when it changed (a change re-lays out the label)."""
    if label.text() != text:
        label.setText(text)


def _set_title(plot: pg.PlotItem, text: str) -> None:
    """Set a plot title only when it changed (a change re-lays out the whole plot)."""
    if getattr(plot, "_tofradar_title", None) != text:
        plot._tofradar_title = text  # noqa: SLF001 - our own marker on the item
        plot.setTitle(text)


def _set_view_range(plot: pg.PlotItem, key: Any, *, x: tuple[float, float],
                    y: tuple[float, float]) -> None:
    """Set the plot's view range when ``key`` (the data extent) changed; else leave it.

    Auto-range is off: re-fitting the view to every frame's data would move the axes, and
    repaint them, on every frame. A user's zoom is kept until the data extent changes.
    """
    if getattr(plot, "_tofradar_range_key", None) != key:
        plot._tofradar_range_key = key  # noqa: SLF001
        plot.vb.setRange(xRange=x, yRange=y, padding=0.0)


def follow_levels(current: tuple[float, float] | None, low: float, high: float, *,
                  tolerance: float) -> tuple[float, float]:
    """Colour levels that follow (low, high) with hysteresis.

    The current levels are kept while both ends are within ``tolerance`` of the new ones,
    so the colour bar (its axis) is re-laid out only when the data's range really moves.
    """
    if (current is not None and abs(current[0] - low) <= tolerance
            and abs(current[1] - high) <= tolerance):
        return current
    return (float(low), float(high))


def _set_bar_levels(bar: pg.ColorBarItem, levels: tuple[float, float]) -> None:
    if tuple(bar.levels()) != tuple(levels):
        bar.setLevels(levels)


class LivePanel(QWidget):
    """Base class: keeps the latest frame view and draws it only while visible.

    Signals
    -------
    detectionClicked(int)
        The user clicked the marker of this index in ``view.radar.detections``.
    objectClicked(int)
        The user clicked the ground-truth mark of the object with this id.
    sensorChanged(str)
        The panel shows another sensor now (picked, renamed, or the one shown was removed;
        "" when none of its kind is left).
    """

    title = "panel"
    detectionClicked = pyqtSignal(int)
    objectClicked = pyqtSignal(int)
    sensorChanged = pyqtSignal(str)
    #: Whether the panel has an A/B comparison (freeze a reference, show the difference).
    comparable = False
    #: The kind of sensor the panel shows (``"tof"``, ``"radar"``, ``"rgb"``): a combo box
    #: picks which one of that kind (issue #30); None: no choice.
    sensor_kind: str | None = None

    def __init__(self, parent: QWidget | None = None):
        super().__init__(parent)
        self._pending: FrameView | None = None
        self.view: FrameView | None = None
        #: Colour detection markers by their ground-truth object (View menu).
        self.colour_by_label = False
        #: Mark each object's true position (View → Show ground truth).
        self.show_truth = True
        #: Object names by id and the selected object id (linked selection).
        self.object_names: dict[int, str] = {}
        self.selected_id: int | None = None
        #: A/B comparison: the frozen reference frame and whether the difference is shown.
        self.reference: FrameView | None = None
        self.show_difference = False
        #: Frames drawn, and the message of the last frame that could not be drawn.
        self.draw_count = 0
        self.error: str | None = None
        self.info = QLabel(" ")
        self.info.setObjectName("info")
        self.info.setStyleSheet("color: #c8ccd2; padding: 1px 4px;")
        self.info.setToolTip("What the panel shows: frame time and counts")
        # The text may be cut on a small screen; it never widens the panel.
        self.info.setSizePolicy(QSizePolicy.Policy.Ignored, QSizePolicy.Policy.Preferred)
        self.error_label = QLabel("")
        self.error_label.setObjectName("error")
        self.error_label.setWordWrap(True)
        self.error_label.setStyleSheet("color: #ff6b6b; padding: 1px 4px;")
        self.error_label.setVisible(False)
        #: Why the panel shows little: an empty scene (set_project).
        self.hint = QLabel(EMPTY_SCENE_HINT)
        self.hint.setObjectName("hint")
        self.hint.setWordWrap(True)
        self.hint.setStyleSheet("color: #9aa4ae; font-style: italic; padding: 1px 4px;")
        self.hint.setVisible(False)
        self.readout = QLabel(" ")
        self.readout.setObjectName("readout")
        self.readout.setStyleSheet("color: #c8ccd2; font-family: monospace; padding: 1px 4px;")
        self.readout.setToolTip("Value under the mouse cursor")
        self.readout.setSizePolicy(QSizePolicy.Policy.Ignored, QSizePolicy.Policy.Preferred)
        self._layout = QVBoxLayout(self)
        self._layout.setContentsMargins(2, 2, 2, 2)
        self._layout.setSpacing(1)
        #: The sensor shown (None: the first of :attr:`sensor_kind`) and the project seen
        #: last (to follow a renamed sensor).
        self.sensor: str | None = None
        self._project: Project | None = None
        self.sensor_combo = QComboBox()
        self.sensor_combo.setObjectName("sensor")
        self.sensor_combo.setToolTip("The sensor this panel shows; the choice is kept across "
                                     "frames and edits and follows a renamed sensor")
        self.sensor_combo.activated.connect(
            lambda _i: self.set_sensor(self.sensor_combo.currentText()))

    def _finish_layout(self, widget: QWidget) -> None:
        top = self.top_row = QHBoxLayout()
        top.setContentsMargins(0, 0, 0, 0)
        if self.sensor_kind is not None:
            top.addWidget(self.sensor_combo)
        top.addWidget(self.info, 1)
        if self.comparable:
            self._build_compare_buttons(top)
        self._layout.addLayout(top)
        self._layout.addWidget(self.hint)
        self._layout.addWidget(self.error_label)
        self._layout.addWidget(widget, 1)
        self._layout.addWidget(self.readout)

    def _build_compare_buttons(self, row: QHBoxLayout) -> None:
        self.freeze_button = QPushButton("Freeze A")
        self.freeze_button.setToolTip("Keep this frame as reference A; after an edit, "
                                      "'A − B' shows the difference (dB)")
        self.freeze_button.clicked.connect(self.freeze_reference)
        self.diff_button = QPushButton("A − B")
        self.diff_button.setCheckable(True)
        self.diff_button.setEnabled(False)
        self.diff_button.setToolTip("Show the current frame minus the frozen reference (dB)")
        self.diff_button.toggled.connect(self.set_show_difference)
        for b in (self.freeze_button, self.diff_button):
            b.setStyleSheet("padding: 0px 6px;")
            row.addWidget(b)

    # --- linked selection, ground truth, A/B comparison ---------------------------------
    def set_selected(self, object_id: int | None) -> None:
        """Highlight the returns and the outline of object ``object_id`` (None: nothing)."""
        if object_id != self.selected_id:
            self.selected_id = object_id
            self.redraw()

    def set_show_truth(self, on: bool) -> None:  # noqa: FBT001 - Qt slot
        """Show or hide the ground-truth marks."""
        if bool(on) != self.show_truth:
            self.show_truth = bool(on)
            self.redraw()

    def freeze_reference(self) -> None:
        """Keep the frame shown now as the reference of the difference view."""
        self.reference = self.view
        if self.comparable:
            self.diff_button.setEnabled(self.reference is not None)
            self.freeze_button.setText("Freeze A ✓" if self.reference is not None
                                       else "Freeze A")

    def set_show_difference(self, on: bool) -> None:  # noqa: FBT001 - Qt slot
        """Show the current frame minus the reference (needs a frozen reference)."""
        on = bool(on) and self.reference is not None
        if self.comparable and self.diff_button.isChecked() != on:
            self.diff_button.setChecked(on)
        if on != self.show_difference:
            self.show_difference = on
            self.redraw()

    def redraw(self) -> None:
        """Draw the current frame again (a display option changed)."""
        if self._pending is None and self.view is not None:
            self._pending = self.view
        if self.isVisible():
            self._flush()

    def object_label(self, object_id: int) -> str:
        """Name of an object for marks and read-outs."""
        return self.object_names.get(int(object_id), f"object {object_id}")

    def set_sensor(self, name: str) -> None:
        """Show sensor ``name`` (of the panel's kind) from now on, redrawing the frame."""
        if self._project is not None and self.sensor_kind is not None and \
                name not in self._project.sensors_of_kind(self.sensor_kind):
            raise KeyError(f"no {self.sensor_kind} sensor {name!r}")
        changed = name != self.sensor
        self.sensor = name
        with QSignalBlocker(self.sensor_combo):
            self.sensor_combo.setCurrentText(name)
        if changed:
            self.sensorChanged.emit(name)
            if self._project is not None:
                self.set_project(self._project)
            if self.comparable and self.reference is not None:
                self.reference = None  # a reference of another sensor compares nothing
                self.freeze_button.setText("Freeze A")
                self.diff_button.setEnabled(False)
                self.set_show_difference(False)
            self.redraw()

    def shown_sensor_config(self, project: Project) -> Any:
        """Configuration of the sensor the panel shows (None: none of its kind)."""
        if self.sensor_kind is None:
            return None
        names = project.sensors_of_kind(self.sensor_kind)
        return names.get(self.sensor or "", next(iter(names.values()), None))

    def _follow_sensors(self, project: Project) -> None:
        """Keep the sensor shown through edits: follow a rename, else fall back."""
        kind = self.sensor_kind
        if kind is None:
            return
        names = list(project.sensors_of_kind(kind))
        was = self.sensor
        if self.sensor is not None:
            self.sensor = follow_sensor(self._project, project, self.sensor, kind)
        if self.sensor is None and names:
            self.sensor = names[0]
        if self.sensor != was:
            self.sensorChanged.emit(self.sensor or "")
        with QSignalBlocker(self.sensor_combo):
            if [self.sensor_combo.itemText(i) for i in range(self.sensor_combo.count())] \
                    != names:
                self.sensor_combo.clear()
                self.sensor_combo.addItems(names)
            if self.sensor is not None:
                self.sensor_combo.setCurrentText(self.sensor)
        self.sensor_combo.setVisible(len(names) > 1)

    def set_project(self, project: Project) -> None:
        """Follow the project: object names, the radar's angular coverage (subclasses more)."""
        self._follow_sensors(project)
        self._project = project
        self.object_names = {o.id: o.name for o in project.objects}
        self.hint.setVisible(not project.objects)
        self.coverage_deg = (project.dsp.azimuth_min_deg, project.dsp.azimuth_max_deg,
                             project.dsp.elevation_min_deg, project.dsp.elevation_max_deg)

    def _visible_marks(self, view: FrameView) -> ObjectMarks | None:
        """The frame's ground truth inside the radar's angular coverage, when shown."""
        marks = view.objects if self.show_truth else None
        if marks is None:
            return None
        az0, az1, el0, el1 = getattr(self, "coverage_deg", (-90.0, 90.0, -90.0, 90.0))
        keep = ((marks.azimuth_deg >= az0) & (marks.azimuth_deg <= az1)
                & (marks.elevation_deg >= el0) & (marks.elevation_deg <= el1)
                & np.isfinite(marks.range_m))
        near = None if marks.nearest_range_m is None else marks.nearest_range_m[keep]
        return ObjectMarks(marks.object_id[keep], marks.range_m[keep],
                           marks.radial_velocity_mps[keep], marks.azimuth_deg[keep],
                           marks.elevation_deg[keep], near)

    def truth_name_at(self, pos: QPointF, xs: Any, ys: Any | None, ids: Any) -> str:
        """Name of the truth mark within :data:`HOVER_PX` of scene point ``pos``, or "".

        ``xs`` (and ``ys``, None for vertical lines) are the marks' view coordinates in the
        panel's plot; a hover names every mark, also when too many are shown to label
        them all (issue #34).
        """
        plot = getattr(self, "plot", None)
        if plot is None or len(ids) == 0:
            return ""
        best, best_d = "", float(HOVER_PX)
        for k, oid in enumerate(ids):
            y = plot.vb.mapSceneToView(pos).y() if ys is None else float(ys[k])
            p = plot.vb.mapViewToScene(QPointF(float(xs[k]), y))
            d = abs(p.x() - pos.x()) if ys is None else float(np.hypot(p.x() - pos.x(),
                                                                       p.y() - pos.y()))
            if d <= best_d:
                best, best_d = self.object_label(int(oid)), d
        return best

    def _labelled(self, object_id: int, n_shown: int) -> bool:
        """Whether a truth mark gets its name (all when few, else only the selected one)."""
        return n_shown <= MAX_TRUTH_LABELS or object_id == self.selected_id

    def show_frame(self, view: FrameView | None) -> None:
        """Show ``view`` now if visible, else remember it for when the panel is shown."""
        self._pending = view
        if self.isVisible():
            self._flush()
        elif self.error is not None:
            # A message about an older frame (stopped, not computed) no longer applies.
            self.error = None
            self.error_label.setVisible(False)

    def showEvent(self, event: Any) -> None:  # noqa: N802, D102 - Qt API
        super().showEvent(event)
        self._flush()

    def draw_now(self) -> None:
        """Draw the pending view even while hidden (for image export)."""
        self._flush()

    def _flush(self) -> None:
        if self._pending is None:
            return
        view, self._pending = self._pending, None
        if self.sensor_kind is not None and self.sensor is not None:
            mine = view.for_sensor(self.sensor_kind, self.sensor)
            if mine is None:  # the sensor did not capture in this frame: keep its last
                _set_text(self.info, f"{self.sensor}: no capture in frame {view.index + 1} "
                          "(its frame rate is lower); showing its last")
                return
            view = mine
        self.view = view
        try:
            self.draw(view)
        except Exception as exc:  # noqa: BLE001 - shown in this panel; the others go on
            self.show_error(f"frame {view.index + 1} could not be drawn here: "
                            f"{type(exc).__name__}: {exc}")
            log.warning("%s: drawing frame %d failed\n%s", self.title, view.index,
                        traceback.format_exc())
        else:
            self.draw_count += 1
            if self.error is not None:
                self.error = None
                self.error_label.setVisible(False)

    def show_error(self, message: str) -> None:
        """Show ``message`` in the panel's error line (until the next frame draws)."""
        self.error = message
        _set_text(self.error_label, f"⚠ {message}")
        self.error_label.setVisible(True)

    def draw(self, view: FrameView) -> None:
        """Draw ``view`` (subclasses)."""
        raise NotImplementedError

    def _no_radar(self, view: FrameView) -> bool:
        """True (and say so) when the frame has no radar products."""
        if view.radar is not None:
            return False
        _set_text(self.info, "no radar products in this frame")
        return True


def cache_axes(root: QWidget) -> int:
    """Let Qt keep every pyqtgraph axis under ``root`` as a picture; the number of axes.

    An axis redraws its ticks and labels (text: ≈ 1.3 ms each in software) whenever the
    view it sits in repaints — with every new image or curve during playback, though its
    range did not change. Cached in device coordinates it is blitted instead, and drawn
    again only when it changes (pyqtgraph calls ``update()`` on a new range, label or
    size, which drops the cached picture).
    """
    count = 0
    for view in root.findChildren(pg.GraphicsView):
        scene = view.scene()
        if scene is None:
            continue
        for item in scene.items():
            if isinstance(item, pg.AxisItem):
                item.setCacheMode(QGraphicsItem.CacheMode.DeviceCoordinateCache)
                count += 1
    return count


def _image_plot(title: str, *, x_label: tuple[str, str], y_label: tuple[str, str]
                ) -> tuple[pg.PlotItem, pg.ImageItem]:
    plot = pg.PlotItem(title=title)
    plot.setLabel("bottom", *x_label)
    plot.setLabel("left", *y_label)
    # No grid over images: an axis that draws a grid covers the whole plot, so every new
    # image would repaint the axes (their text included) too.
    image = pg.ImageItem(axisOrder="row-major")
    plot.addItem(image)
    return plot, image


def _colour_bar(plot_layout: pg.GraphicsLayout, image: pg.ImageItem, cmap: str, label: str,
                *, row: int, col: int) -> pg.ColorBarItem:
    bar = pg.ColorBarItem(colorMap=pg.colormap.get(cmap), interactive=False, width=14,
                          label=label)
    bar.setImageItem(image)
    plot_layout.addItem(bar, row=row, col=col)
    return bar


def bold_font(size: int = 9) -> QFont:
    """A bold UI font."""
    font = QFont()
    font.setPointSize(size)
    font.setBold(True)
    return font


__all__ = ["INVALID_RGBA", "LivePanel", "QColor", "bold_font"]
