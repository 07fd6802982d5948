"""Live panels: ToF depth and amplitude, range profile, range–Doppler, range–azimuth.

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
from PyQt6.QtCore import QPointF, QRectF, QSignalBlocker, Qt, pyqtSignal
from PyQt6.QtGui import QColor, QFont
from PyQt6.QtWidgets import (
    QCheckBox,
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
from simcore.dsp.profile import range_profile_cfar
from simcore.scene import Project
from simcore.scene.dsp_config import DspConfig

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


class TofPanel(LivePanel):
    """ToF depth (m) and amplitude images with colour bars; invalid pixels in magenta."""

    sensor_kind = "tof"

    title = "ToF camera"

    def __init__(self, parent: QWidget | None = None):
        super().__init__(parent)
        self.graphics = pg.GraphicsLayoutWidget()
        self.graphics.setToolTip("ToF depth (m) and demodulated amplitude (DN); magenta "
                                 "pixels are invalid (saturated, too dark or no return)")
        self.depth_plot, self.depth_image = _image_plot(
            "depth", x_label=("column", "px"), y_label=("row", "px"))
        self.amp_plot, self.amp_image = _image_plot(
            "amplitude", x_label=("column", "px"), y_label=("row", "px"))
        self.depth_invalid = pg.ImageItem(axisOrder="row-major")
        self.amp_invalid = pg.ImageItem(axisOrder="row-major")
        for plot, overlay in ((self.depth_plot, self.depth_invalid),
                              (self.amp_plot, self.amp_invalid)):
            plot.addItem(overlay)
            overlay.setZValue(5)
            plot.invertY(True)
            plot.setAspectLocked(True)
        self.graphics.addItem(self.depth_plot, row=0, col=0)
        self.depth_bar = _colour_bar(self.graphics.ci, self.depth_image, "turbo", "depth (m)",
                                     row=0, col=1)
        self.graphics.addItem(self.amp_plot, row=0, col=2)
        self.amp_bar = _colour_bar(self.graphics.ci, self.amp_image, "inferno",
                                   "amplitude (DN)", row=0, col=3)
        self._amp_levels: tuple[float, float] | None = None
        self._amp_unit = "DN"
        self._invalid: NDArray[np.bool_] | None = None
        # Ground-truth outlines of the objects (the selected one in yellow).
        self.depth_outline = pg.ImageItem(axisOrder="row-major")
        self.amp_outline = pg.ImageItem(axisOrder="row-major")
        self._outline_key: tuple[Any, ...] | None = None
        for plot, outline in ((self.depth_plot, self.depth_outline),
                              (self.amp_plot, self.amp_outline)):
            plot.addItem(outline)
            outline.setZValue(6)
            for side in ("bottom", "left"):
                plot.getAxis(side).enableAutoSIPrefix(False)  # "px", never "kpx"
        self._finish_layout(self.graphics)
        for plot in (self.depth_plot, self.amp_plot):
            plot.disableAutoRange()
            plot.scene().sigMouseMoved.connect(self._on_hover)

    def draw(self, view: FrameView) -> None:  # noqa: D102
        tof = view.tof
        if tof is None:
            _set_text(self.info, "no ToF camera in this project")
            return
        depth = np.nan_to_num(tof.depth_m, nan=0.0)
        self.depth_image.setImage(depth, autoLevels=False)
        _set_bar_levels(self.depth_bar, (0.0, float(tof.max_range_m)))
        amp = tof.amplitude
        hi = float(np.percentile(amp[tof.valid], 99)) if tof.valid.any() else 1.0
        hi = max(hi, 1e-6)
        levels = follow_levels(self._amp_levels, 0.0, hi, tolerance=0.15 * hi)
        self._amp_levels = levels
        self.amp_image.setImage(amp, autoLevels=False)
        _set_bar_levels(self.amp_bar, levels)
        if self._amp_unit != tof.amplitude_unit:
            self._amp_unit = tof.amplitude_unit
            self.amp_bar.getAxis("left").setLabel(f"amplitude ({tof.amplitude_unit})")
        invalid = ~tof.valid
        if self._invalid is None or not np.array_equal(invalid, self._invalid):
            self._invalid = invalid
            overlay = np.zeros((*tof.valid.shape, 4), dtype=np.uint8)
            overlay[invalid] = INVALID_RGBA
            self.depth_invalid.setImage(overlay, autoLevels=False, levels=(0, 255))
            self.amp_invalid.setImage(overlay, autoLevels=False, levels=(0, 255))
        self._draw_outlines(tof.gt_object_id if self.show_truth else None)
        h, w = depth.shape
        for plot in (self.depth_plot, self.amp_plot):
            _set_view_range(plot, (h, w), x=(0, w), y=(0, h))
        _set_text(self.info, f"t = {view.time_s:.2f} s   frame {view.index + 1}   "
                             f"{int(invalid.sum())} invalid px (magenta)")

    def _draw_outlines(self, ids: NDArray[np.int32] | None) -> None:
        """Outline every object of the ground-truth id image; the selected one in yellow."""
        if ids is None:
            for item in (self.depth_outline, self.amp_outline):
                item.setVisible(False)
            self._outline_key = None
            return
        key = (ids.shape, self.selected_id, hash(ids.tobytes()))
        if key != self._outline_key:
            self._outline_key = key
            self.outlines = object_outlines(ids, self.selected_id)
            for item in (self.depth_outline, self.amp_outline):
                item.setImage(self.outlines, autoLevels=False, levels=(0, 255))
        for item in (self.depth_outline, self.amp_outline):
            item.setVisible(True)

    def _on_hover(self, pos: QPointF) -> None:
        if self.view is None or self.view.tof is None:
            return
        tof = self.view.tof
        for plot in (self.depth_plot, self.amp_plot):
            if plot.sceneBoundingRect().contains(pos):
                p = plot.vb.mapSceneToView(pos)
                col, row = int(np.floor(p.x())), int(np.floor(p.y()))
                h, w = tof.depth_m.shape
                if 0 <= row < h and 0 <= col < w:
                    if tof.valid[row, col]:
                        text = (f"px ({col}, {row})  depth {tof.depth_m[row, col]:.3f} m  "
                                f"amplitude {tof.amplitude[row, col]:.1f} {tof.amplitude_unit}")
                    else:
                        text = f"px ({col}, {row})  invalid"
                    ids = tof.gt_object_id
                    if ids is not None and ids.shape == tof.depth_m.shape and ids[row, col] >= 0:
                        text += f"  [{self.object_label(int(ids[row, col]))}]"
                    self.readout.setText(text)
                return


class RangeProfilePanel(LivePanel):
    """Processed range profile (dB) with its own 1-D CFAR threshold, detections, truth.

    The profile is the range–Doppler map the detector works on (static clutter removal,
    windows and channel integration included) averaged over Doppler, and the dashed
    threshold is a 1-D CFAR along range on that same curve
    (:func:`simcore.dsp.profile.range_profile_cfar`), so curve and threshold are on one
    scale. The chirp-averaged raw spectra of the channels can be shown beside it (labelled
    "raw"). Vertical lines mark each object's true range; A/B comparison shows a frozen
    reference profile and the difference.
    """

    sensor_kind = "radar"

    title = "Range profile"
    comparable = True

    def __init__(self, parent: QWidget | None = None):
        super().__init__(parent)
        self.dsp = DspConfig()
        self.looks = 1
        self.show_raw = False
        self.plot_widget = pg.PlotWidget(title="range profile")
        self.plot_widget.setToolTip(
            "Processed range profile: the range–Doppler map (windows applied, static "
            "clutter removal when it is on — the title says — channels integrated) "
            "averaged over Doppler, dB; dashed: 1-D CFAR "
            "threshold on this curve; triangles: detections of the 2-D detector; vertical "
            "lines: each object's nearest surface point (solid: where the radar sees it "
            "begin) and its reference point (dashed, named); hover a line for its object; "
            "'raw channels': chirp-averaged raw spectra")
        self.plot = self.plot_widget.getPlotItem()
        self.plot.setLabel("bottom", "range", "m")
        self.plot.setLabel("left", "power", "dB")
        self.plot.showGrid(x=True, y=True, alpha=0.2)
        # The legend has its own column right of the data (issue #34: drawn over the view
        # it hid the curve and the detections at the far end of the range).
        self.legend = pg.LegendItem(offset=None, labelTextSize="7pt", verSpacing=-6)
        self.plot.legend = self.legend  # named items join it (PlotItem.addItem)
        # It spans the data's row and the range axis's: its three rows then never make the
        # plot taller than a 1366×768 window's dock, which cut off the axis's "range (m)".
        self.plot.layout.addItem(self.legend, 2, 3, 2, 1)
        self.curves: list[pg.PlotDataItem] = []
        self.processed = self.plot.plot(pen=pg.mkPen("#ffffff", width=2.0),
                                        name="processed")
        self.threshold = self.plot.plot(pen=pg.mkPen("#ff8a65", width=1.2,
                                                     style=Qt.PenStyle.DashLine),
                                        name="1-D CFAR")
        self.reference_curve = self.plot.plot(pen=pg.mkPen("#9e9e9e", width=1.2,
                                                           style=Qt.PenStyle.DotLine))
        self.difference_curve = self.plot.plot(pen=pg.mkPen("#ce93d8", width=1.6))
        self.markers = pg.ScatterPlotItem(symbol="t1", size=11, pen=pg.mkPen("#ffeb3b"),
                                          brush=pg.mkBrush("#ffeb3b"))
        self.markers.sigClicked.connect(self._on_marker_clicked)
        self.plot.addItem(self.markers)
        self.legend.addItem(self.markers, "detections")
        self.truth_lines: list[pg.InfiniteLine] = []
        #: Solid vertical lines at each object's nearest surface point (dashed: reference),
        #: all in one item (one path to paint per frame), the selected one's in yellow.
        self.near_lines = pg.PlotDataItem(pen=NEAR_PEN, connect="pairs")
        self.near_selected = pg.PlotDataItem(pen=TRUTH_SELECTED_PEN, connect="pairs")
        for item in (self.near_lines, self.near_selected):
            item.setZValue(-0.5)
            self.plot.addItem(item)
        self.truth_shown: list[tuple[int, float, float]] = []
        self.raw_box = QCheckBox("raw channels")
        self.raw_box.setToolTip("Also draw each channel's chirp-averaged raw range spectrum "
                                "(before clutter removal and Doppler processing)")
        self.raw_box.toggled.connect(self.set_show_raw)
        self._names: list[str] = []
        self._y: tuple[float, float] | None = None
        self.profile_db: NDArray[np.float32] | None = None
        self.threshold_db: NDArray[np.float32] | None = None
        self.plot.disableAutoRange()
        self._finish_layout(self.plot_widget)
        self.top_row.insertWidget(1, self.raw_box)
        self.plot.scene().sigMouseMoved.connect(self._on_hover)

    def set_project(self, project: Project) -> None:  # noqa: D102
        super().set_project(project)
        radar = self.shown_sensor_config(project)
        self.dsp = project.dsp
        if radar is not None:  # (a ToF-only project: the panel is hidden and draws nothing)
            self.looks = max(1, len(radar.tx) * len(radar.rx) * radar.chirps_per_frame)

    def set_show_raw(self, on: bool) -> None:  # noqa: FBT001 - Qt slot
        """Show the raw per-channel spectra beside the processed profile."""
        self.show_raw = bool(on)
        self.redraw()

    def processed_title(self) -> str:
        """The profile's title; it says whether static clutter removal is on (issue #34)."""
        state = "on" if self.dsp.static_clutter_removal else "off"
        return f"range profile (processed, static clutter removal {state})"

    def processed_profile(self, view: FrameView) -> Any:
        """The frame's processed profile and its 1-D CFAR (:class:`ProfileCfar`)."""
        assert view.radar is not None
        d = self.dsp
        return range_profile_cfar(view.radar.range_doppler_db, method=d.cfar_method,
                                  train=d.cfar_train_range, guard=d.cfar_guard_range,
                                  pfa=d.cfar_pfa, rank=d.cfar_os_rank, n_integrated=self.looks)

    def draw(self, view: FrameView) -> None:  # noqa: D102
        if self._no_radar(view):
            return
        radar = view.radar
        assert radar is not None
        r = radar.range_axis_m
        prof = self.processed_profile(view)
        self.profile_db, self.threshold_db = prof.profile_db, prof.threshold_db
        ref = self._reference_profile(len(r))
        diff = self.show_difference and ref is not None
        self._draw_raw(radar, visible=self.show_raw and not diff)
        if diff:
            assert ref is not None
            delta = prof.profile_db - ref
            self.difference_curve.setData(r, delta)
            for item in (self.processed, self.threshold, self.reference_curve):
                item.setData([], [])
            span = max(DIFF_SPAN_DB / 2, float(np.ceil(np.nanmax(np.abs(delta)) / 5) * 5))
            _set_title(self.plot, "A − B: current minus frozen reference (dB)")
            self._y = (-span, span)
        else:
            self.difference_curve.setData([], [])
            self.processed.setData(r, prof.profile_db)
            self.threshold.setData(r, prof.threshold_db)
            if ref is not None:
                self.reference_curve.setData(r, ref)
            else:
                self.reference_curve.setData([], [])
            _set_title(self.plot, self.processed_title()
                       + (" + reference A" if ref is not None else ""))
            curves = [prof.profile_db, prof.threshold_db]
            if self.show_raw:
                curves.append(radar.profile_db.ravel())
            finite = np.concatenate([c[np.isfinite(c)] for c in curves])
            lo = float(np.floor(finite.min() / 10) * 10) if finite.size else -100.0
            hi = float(np.ceil(finite.max() / 10) * 10 + 10) if finite.size else 0.0
            self._y = follow_levels(self._y, lo, hi, tolerance=10.0)
        det = radar.detections
        if len(det) and not diff:
            levels = np.interp(det.range_m, r, prof.profile_db) + 2.0
            self.markers.setData(det.range_m, levels,
                                 pen=detection_pens(det, self.selected_id))
        else:
            self.markers.setData([], [])
        self._draw_truth(self._visible_marks(view), x_max=float(r[-1]) if len(r) else 0.0)
        x_max = float(r[-1]) if len(r) else 1.0
        _set_view_range(self.plot, (len(r), x_max, self._y), x=(0.0, x_max), y=self._y)
        peak = self._peak_range(r, prof)
        _set_text(self.info, f"t = {view.time_s:.2f} s   {peak}   {plural(len(det), 'detection')}")

    def _peak_range(self, r: NDArray[np.float64], prof: Any) -> str:
        """The strongest range bin above the profile's own threshold ('—' on pure noise)."""
        # Beyond the leakage zone, like RadarView.profile_peak_range_m.
        above = prof.detections & (r >= max(self.dsp.min_range_m, 0.3))
        if not above.any():
            return "peak —"
        i = int(np.flatnonzero(above)[np.argmax(prof.profile_db[above])])
        return f"peak {r[i]:.2f} m"

    def _reference_profile(self, n: int) -> NDArray[np.float32] | None:
        ref = self.reference
        if ref is None or ref.radar is None or len(ref.radar.range_axis_m) != n:
            return None
        return self.processed_profile(ref).profile_db

    def _draw_raw(self, radar: Any, *, visible: bool) -> None:
        n = radar.profile_db.shape[0]
        names = [f"{name} raw" for name in radar.channel_names[:n]] if visible else []
        if names != self._names:
            self._rebuild_curves(names)
        for i, curve in enumerate(self.curves):
            curve.setData(radar.range_axis_m, radar.profile_db[i])

    def _draw_truth(self, marks: ObjectMarks | None, *, x_max: float) -> None:
        near_all = (None if marks is None else marks.nearest_range_m)
        shown = [] if marks is None else [
            (int(i), float(rng)) for i, rng in zip(marks.object_id, marks.range_m, strict=True)
            if np.isfinite(rng) and 0 < rng <= x_max]
        near = [] if marks is None or near_all is None else [
            float(n) for i, rng, n in zip(marks.object_id, marks.range_m, near_all, strict=True)
            if np.isfinite(rng) and 0 < rng <= x_max]
        self.truth_shown = [(oid, rng, near[k] if near else rng)
                            for k, (oid, rng) in enumerate(shown)]
        self._draw_near([(oid, n) for oid, _r, n in self.truth_shown
                         if near and np.isfinite(n)])
        while len(self.truth_lines) < len(shown):
            line = pg.InfiniteLine(angle=90, movable=False, pen=TRUTH_PEN,
                                   label="", labelOpts={"position": 0.92, "color": "#80deea",
                                                        "rotateAxis": (1, 0)})
            self.plot.addItem(line)
            self.truth_lines.append(line)
        for k, line in enumerate(self.truth_lines):
            if k >= len(shown):
                line.setVisible(False)
                continue
            oid, rng = shown[k]
            line.setVisible(True)
            if line.value() != rng:                  # moves its label too: ≈ 0.4 ms
                line.setValue(rng)
            line.object_id = oid
            selected = oid == self.selected_id
            if getattr(line, "selected", None) is not selected:
                line.setPen(TRUTH_SELECTED_PEN if selected else pg.mkPen(
                    "#80deea", width=1, style=Qt.PenStyle.DashLine))
                line.selected = selected
            text = self.object_label(oid) if self._labelled(oid, len(shown)) else ""
            if line.label.format != text:
                line.label.setFormat(text)

    def _draw_near(self, shown: list[tuple[int, float]]) -> None:
        """A solid line at each object's nearest surface point (what the radar sees first)."""
        key = (tuple(shown), self.selected_id)
        if getattr(self, "_near_key", None) == key:
            return  # a still scene: nothing to redraw
        self._near_key = key
        for item, rows in ((self.near_lines, [r for o, r in shown if o != self.selected_id]),
                           (self.near_selected, [r for o, r in shown if o == self.selected_id])):
            x = np.repeat(np.asarray(rows, dtype=np.float64), 2)
            # Far beyond any dB range: the view clips them to its height.
            item.setData(x, np.tile([-1e4, 1e4], len(rows)))

    def near_ranges(self) -> list[float]:
        """Ranges of the nearest-surface lines drawn (m)."""
        values = []
        for item in (self.near_lines, self.near_selected):
            x, _ = item.getData()
            values += [] if x is None else [float(v) for v in x[::2]]
        return sorted(values)

    def _rebuild_curves(self, names: list[str]) -> None:
        for curve in self.curves:
            self.plot.removeItem(curve)
            self.legend.removeItem(curve)
        self.curves = []
        for i, name in enumerate(names):
            colour = CHANNEL_COLOURS[i % len(CHANNEL_COLOURS)]
            curve = self.plot.plot(pen=pg.mkPen(colour, width=1.0), name=name)
            curve.setZValue(-1)
            self.curves.append(curve)
        self.legend.setColumnCount(1 if len(names) <= 4 else 3)
        self._names = names

    def _on_marker_clicked(self, _item: Any, points: Any, *_: Any) -> None:
        if len(points):
            self.detectionClicked.emit(int(points[0].index()))

    def _on_hover(self, pos: QPointF) -> None:
        radar = None if self.view is None else self.view.radar
        if radar is None or not self.plot.sceneBoundingRect().contains(pos):
            return
        p = self.plot.vb.mapSceneToView(pos)
        i = int(np.clip(np.searchsorted(radar.range_axis_m, p.x()), 0,
                        len(radar.range_axis_m) - 1))
        text = f"range {radar.range_axis_m[i]:.3f} m:"
        if self.profile_db is not None and len(self.profile_db) == len(radar.range_axis_m):
            assert self.threshold_db is not None
            text += (f" processed {self.profile_db[i]:.1f} (threshold "
                     f"{self.threshold_db[i]:.1f})")
        values = "  ".join(f"{name} {radar.profile_db[k, i]:.1f}"
                           for k, name in enumerate(radar.channel_names))
        text = f"{text}  raw {values} dB"
        shown = self.truth_shown if self.show_truth else []
        for xs in ([n for _, _, n in shown], [r for _, r, _ in shown]):
            name = self.truth_name_at(pos, xs, None, [oid for oid, _, _ in shown])
            if name:
                oid = next(o for o, _, _ in shown if self.object_label(o) == name)
                _, rng, near = next(t for t in shown if t[0] == oid)
                text = (f"→ {name}: nearest surface {near:.3f} m, reference point "
                        f"{rng:.3f} m   |   {text}")
                break
        self.readout.setText(text)


def _rect(x: NDArray[np.float64], y: NDArray[np.float64]) -> QRectF:
    """Rectangle covering bin centres ``x``, ``y`` with half a bin on each side."""
    dx = float(x[1] - x[0]) if len(x) > 1 else 1.0
    dy = float(y[1] - y[0]) if len(y) > 1 else 1.0
    return QRectF(float(x[0]) - dx / 2, float(y[0]) - dy / 2, dx * len(x), dy * len(y))


def _set_image_rect(image: pg.ImageItem, plot: pg.PlotItem, rect: QRectF) -> None:
    """Place ``image`` on ``rect`` and fit the view to it, only when the rectangle changed."""
    # setRect scales by the image size of the moment: a new shape needs it again.
    shape = None if image.image is None else image.image.shape
    key = (shape, rect.x(), rect.y(), rect.width(), rect.height())
    if getattr(image, "_tofradar_rect", None) != key:
        image._tofradar_rect = key  # noqa: SLF001
        image.setRect(rect)
        _set_view_range(plot, key, x=(rect.left(), rect.right()), y=(rect.top(), rect.bottom()))


class MapPanel(LivePanel):
    """A radar map panel: image, colour bar, detections, truth marks, A/B difference."""

    sensor_kind = "radar"

    comparable = True
    cmap = "viridis"
    bar_label = "power (dB)"

    def _build_map(self, title: str, *, x_label: tuple[str, str], y_label: tuple[str, str],
                   tooltip: str) -> None:
        self.graphics = pg.GraphicsLayoutWidget()
        self.graphics.setToolTip(tooltip)
        self.plot, self.image = _image_plot(title, x_label=x_label, y_label=y_label)
        self.graphics.addItem(self.plot, row=0, col=0)
        self.bar = _colour_bar(self.graphics.ci, self.image, self.cmap, self.bar_label, row=0,
                               col=1)
        self.markers = pg.ScatterPlotItem(symbol="o", size=12, pen=DETECTION_PEN,
                                          brush=DETECTION_BRUSH)
        self.markers.setZValue(10)
        self.markers.sigClicked.connect(self._on_marker_clicked)
        self.plot.addItem(self.markers)
        # Below the detections: a click on a detection over its own truth mark means it.
        self.truth = pg.ScatterPlotItem(symbol="+", size=16, pen=TRUTH_PEN, brush=None)
        self.truth.setZValue(9)
        self.truth.sigClicked.connect(self._on_truth_clicked)
        self.plot.addItem(self.truth)
        # Where the radar sees each object begin: its nearest surface point (issue #34).
        self.truth_near = pg.ScatterPlotItem(symbol="x", size=8, pen=NEAR_PEN, brush=None)
        self.truth_near.setZValue(9)
        self.truth_near.setAcceptedMouseButtons(Qt.MouseButton.NoButton)
        self.plot.addItem(self.truth_near)
        self.truth_labels: list[pg.TextItem] = []
        self._diff_shown: bool | None = None
        self._levels: tuple[float, float] | None = None
        self.plot.disableAutoRange()
        self._finish_layout(self.graphics)
        self.plot.scene().sigMouseMoved.connect(self._on_hover)

    def _on_marker_clicked(self, _item: Any, points: Any, *_: Any) -> None:
        if len(points):
            self.detectionClicked.emit(int(points[0].index()))

    def _on_truth_clicked(self, _item: Any, points: Any, *_: Any) -> None:
        if len(points) and points[0].data() is not None:
            self.objectClicked.emit(int(points[0].data()))

    def _on_hover(self, pos: QPointF) -> None:
        raise NotImplementedError

    def _show_map(self, image: NDArray[np.float32], reference: NDArray[np.float32] | None, *,
                  span_db: float, fill: float | None = None) -> None:
        """Draw ``image`` (dB), or ``image − reference`` in the difference view."""
        diff = self.show_difference and reference is not None and \
            reference.shape == image.shape
        if diff != self._diff_shown:
            self._diff_shown = diff
            self.bar.setColorMap(pg.colormap.get(DIFF_CMAP if diff else self.cmap))
            self.bar.getAxis("left").setLabel("A − B (dB)" if diff else self.bar_label)
            self._levels = None
        if diff:
            assert reference is not None
            delta = np.nan_to_num(image - reference, nan=0.0)
            self.image.setImage(delta, autoLevels=False)
            _set_bar_levels(self.bar, (-DIFF_SPAN_DB, DIFF_SPAN_DB))
            return
        hi = float(np.nanmax(image))
        self.image.setImage(image if fill is None else np.nan_to_num(image, nan=hi - fill),
                            autoLevels=False)
        self._levels = follow_levels(self._levels, hi - span_db, hi, tolerance=3.0)
        _set_bar_levels(self.bar, self._levels)

    def _show_detections(self, det: Any, x: Any, y: Any) -> None:
        self.markers.setData(x, y, brush=detection_brushes(det, by_label=self.colour_by_label),
                             pen=detection_pens(det, self.selected_id))

    def truth_hover_text(self, pos: QPointF) -> str:
        """``"→ name   "`` for the truth cross under the mouse, else ``""``."""
        if not self.show_truth:
            return ""
        x, y = self.truth.getData()
        ids = [p.data() for p in self.truth.points()] if x is not None and len(x) else []
        name = self.truth_name_at(pos, x, y, ids) if ids else ""
        return f"→ {name}   " if name else ""

    def _show_truth(self, marks: ObjectMarks | None, x: Any, y: Any, inside: Any,
                    near: tuple[Any, Any] | None = None) -> None:
        """Crosses at each object's true position (map coordinates ``x``, ``y``).

        ``near``: map coordinates of each object's nearest surface point, drawn as small
        crosses (issue #34).
        """
        if marks is None:
            self.truth.setData([], [])
            self.truth_near.setData([], [])
            keep: list[int] = []
        else:
            keep = [k for k in range(len(marks.object_id)) if inside[k]]
            if near is None:
                self.truth_near.setData([], [])
            else:
                nx, ny = (np.asarray(c, dtype=np.float64)[keep] for c in near)
                ok = np.isfinite(nx) & np.isfinite(ny)
                self.truth_near.setData(nx[ok], ny[ok])
            pens = [TRUTH_SELECTED_PEN if int(marks.object_id[k]) == self.selected_id
                    else TRUTH_PEN for k in keep]
            self.truth.setData(np.asarray(x)[keep], np.asarray(y)[keep], pen=pens,
                               data=[int(marks.object_id[k]) for k in keep])
        while len(self.truth_labels) < len(keep):
            label = pg.TextItem("", color="#80deea", anchor=(0, 1))
            label.setZValue(11)
            self.plot.addItem(label)
            self.truth_labels.append(label)
        for n, label in enumerate(self.truth_labels):
            if n >= len(keep):
                label.setVisible(False)
                continue
            assert marks is not None
            k = keep[n]
            oid = int(marks.object_id[k])
            label.setVisible(self._labelled(oid, len(keep)))
            label.setText(self.object_label(oid),
                          color="#ffeb3b" if oid == self.selected_id else "#80deea")
            label.setPos(float(np.asarray(x)[k]), float(np.asarray(y)[k]))



class RangeDopplerPanel(MapPanel):
    """Range–Doppler map (dB) with CFAR detections and each object's true (range, velocity)."""

    title = "Range–Doppler"

    def __init__(self, parent: QWidget | None = None):
        super().__init__(parent)
        self._build_map("range–Doppler", x_label=("range", "m"),
                        y_label=("radial velocity", "m/s"),
                        tooltip="Range–Doppler map (dB, channels integrated); circles: CFAR "
                                "detections (click one to select its object); crosses: each "
                                "object's true range and radial velocity; velocity positive "
                                "= moving away (m/s)")

    def draw(self, view: FrameView) -> None:  # noqa: D102
        if self._no_radar(view):
            return
        radar = view.radar
        assert radar is not None
        ref = None if self.reference is None or self.reference.radar is None \
            else self.reference.radar.range_doppler_db
        self._show_map(radar.range_doppler_db, ref, span_db=60.0)
        _set_image_rect(self.image, self.plot, _rect(radar.range_axis_m,
                                                     radar.velocity_axis_mps))
        det = radar.detections
        self._show_detections(det, det.range_m, det.velocity_mps)
        marks = self._visible_marks(view)
        if marks is not None:
            r, v = marks.range_m, marks.radial_velocity_mps
            vmax = float(np.max(np.abs(radar.velocity_axis_mps))) if len(
                radar.velocity_axis_mps) else 0.0
            inside = (np.isfinite(r) & (r > 0) & (r <= radar.range_axis_m[-1])
                      & (np.abs(v) <= vmax + 1e-9))
            near = None if marks.nearest_range_m is None else (marks.nearest_range_m, v)
            self._show_truth(marks, r, v, inside, near)
        else:
            self._show_truth(None, [], [], [])
        _set_text(self.info, f"t = {view.time_s:.2f} s   {plural(len(det), 'detection')}")

    def _on_hover(self, pos: QPointF) -> None:
        radar = None if self.view is None else self.view.radar
        if radar is None or not self.plot.sceneBoundingRect().contains(pos):
            return
        p = self.plot.vb.mapSceneToView(pos)
        ri = int(np.argmin(np.abs(radar.range_axis_m - p.x())))
        vi = int(np.argmin(np.abs(radar.velocity_axis_mps - p.y())))
        self.readout.setText(f"{self.truth_hover_text(pos)}range {radar.range_axis_m[ri]:.3f} m"
                             f"  velocity {radar.velocity_axis_mps[vi]:+.3f} m/s: "
                             f"{radar.range_doppler_db[vi, ri]:.1f} dB")


class RangeAzimuthPanel(MapPanel):
    """Bird's-eye range–azimuth map (dB) in radar x (right) / z (forward) metres."""

    title = "Range–azimuth"
    pixel_m = 0.05

    def __init__(self, parent: QWidget | None = None):
        super().__init__(parent)
        self._build_map("bird's-eye", x_label=("lateral x", "m"), y_label=("forward", "m"),
                        tooltip="Range–azimuth map seen from above (dB): lateral x to the "
                                "right and forward distance from the radar (m); circles: "
                                "detections (click one to select its object); crosses: each "
                                "object's true position")
        self.plot.setAspectLocked(True)
        self._grid_key: tuple[Any, ...] | None = None
        self._lookup: tuple[NDArray[np.int64], NDArray[np.int64], NDArray[np.bool_]] | None = None

    def _build_lookup(self, r: NDArray[np.float64], az_deg: NDArray[np.float64]) -> None:
        r_max = float(r[-1])
        n = int(np.ceil(r_max / self.pixel_m))
        xs = (np.arange(-n, n) + 0.5) * self.pixel_m
        zs = (np.arange(n) + 0.5) * self.pixel_m
        xx, zz = np.meshgrid(xs, zs)
        rr = np.hypot(xx, zz)
        aa = np.rad2deg(np.arctan2(xx, zz))
        ri = np.clip(np.rint((rr - r[0]) / (r[1] - r[0])).astype(np.int64), 0, len(r) - 1)
        step = az_deg[1] - az_deg[0] if len(az_deg) > 1 else 1.0
        ai = np.clip(np.rint((aa - az_deg[0]) / step).astype(np.int64), 0, len(az_deg) - 1)
        inside = (rr <= r_max) & (aa >= az_deg[0] - step / 2) & (aa <= az_deg[-1] + step / 2)
        self._lookup = (ai, ri, inside)
        self._extent = QRectF(-n * self.pixel_m, 0.0, 2 * n * self.pixel_m, n * self.pixel_m)

    def bird_eye(self, radar: Any) -> tuple[NDArray[np.float32], QRectF]:
        """Bird's-eye image (dB, NaN outside the coverage) of a radar view and its extent."""
        if radar.bev_db is not None and radar.bev_x_m is not None and radar.bev_z_m is not None:
            # The DSP's own Cartesian resampling of the range–azimuth map.
            return radar.bev_db, _rect(radar.bev_x_m, radar.bev_z_m)
        r, az = radar.range_axis_m, radar.azimuth_axis_deg
        key = (len(r), float(r[0]), float(r[-1]), len(az), float(az[0]), float(az[-1]))
        if key != self._grid_key:
            self._build_lookup(r, az)
            self._grid_key = key
        assert self._lookup is not None
        ai, ri, inside = self._lookup
        bev = np.where(inside, radar.range_azimuth_db[ai, ri], np.nan).astype(np.float32)
        return bev, self._extent

    def draw(self, view: FrameView) -> None:  # noqa: D102
        if self._no_radar(view):
            return
        radar = view.radar
        assert radar is not None
        bev, rect = self.bird_eye(radar)
        self.bev = bev
        ref = None
        if self.reference is not None and self.reference.radar is not None:
            ref = self.bird_eye(self.reference.radar)[0]
        self._show_map(bev, ref, span_db=40.0, fill=200.0)
        _set_image_rect(self.image, self.plot, rect)
        det = radar.detections
        a = np.deg2rad(det.azimuth_deg)
        self._show_detections(det, det.range_m * np.sin(a), det.range_m * np.cos(a))
        marks = self._visible_marks(view)
        if marks is not None:
            r, az = marks.range_m, np.deg2rad(marks.azimuth_deg)
            inside = np.isfinite(r) & (r > 0) & (r <= radar.range_axis_m[-1]) & (
                np.abs(az) < np.pi / 2)
            n = marks.nearest_range_m
            self._show_truth(marks, r * np.sin(az), r * np.cos(az), inside,
                             None if n is None else (n * np.sin(az), n * np.cos(az)))
        else:
            self._show_truth(None, [], [], [])
        _set_text(self.info, f"t = {view.time_s:.2f} s   {plural(len(det), 'detection')}")

    def _on_hover(self, pos: QPointF) -> None:
        radar = None if self.view is None else self.view.radar
        if radar is None or not self.plot.sceneBoundingRect().contains(pos):
            return
        p = self.plot.vb.mapSceneToView(pos)
        rng = float(np.hypot(p.x(), p.y()))
        az = float(np.rad2deg(np.arctan2(p.x(), p.y())))
        ri = int(np.argmin(np.abs(radar.range_axis_m - rng)))
        ai = int(np.argmin(np.abs(radar.azimuth_axis_deg - az)))
        self.readout.setText(f"{self.truth_hover_text(pos)}x {p.x():+.2f} m  forward "
                             f"{p.y():.2f} m  (range {rng:.2f} m, "
                             f"azimuth {az:+.1f}°): {radar.range_azimuth_db[ai, ri]:.1f} dB")


def bold_font(size: int = 9) -> QFont:
    """A bold UI font."""
    font = QFont()
    font.setPointSize(size)
    font.setBold(True)
    return font


__all__ = ["INVALID_RGBA", "LivePanel", "QColor", "RangeAzimuthPanel", "RangeDopplerPanel",
           "RangeProfilePanel", "TofPanel", "bold_font"]
