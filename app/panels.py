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
from PyQt6.QtCore import QPointF, QRectF, Qt
from PyQt6.QtGui import QColor, QFont
from PyQt6.QtWidgets import QLabel, QVBoxLayout, QWidget

from app.frame_view import FrameView

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
log = logging.getLogger(__name__)


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
    """Base class: keeps the latest frame view and draws it only while visible."""

    title = "panel"

    def __init__(self, parent: QWidget | None = None):
        super().__init__(parent)
        self._pending: FrameView | None = None
        self.view: FrameView | None = None
        #: Colour detection markers by their ground-truth object (View menu).
        self.colour_by_label = False
        #: Frames drawn, and the message of the last frame that could not be drawn.
        self.draw_count = 0
        self.error: str | None = None
        self.info = QLabel(" ")
        self.info.setObjectName("info")
        self.info.setStyleSheet("color: #c8ccd2; padding: 1px 4px;")
        self.info.setToolTip("What the panel shows: frame time and counts")
        self.error_label = QLabel("")
        self.error_label.setObjectName("error")
        self.error_label.setWordWrap(True)
        self.error_label.setStyleSheet("color: #ff6b6b; padding: 1px 4px;")
        self.error_label.setVisible(False)
        self.readout = QLabel(" ")
        self.readout.setObjectName("readout")
        self.readout.setStyleSheet("color: #c8ccd2; font-family: monospace; padding: 1px 4px;")
        self.readout.setToolTip("Value under the mouse cursor")
        self._layout = QVBoxLayout(self)
        self._layout.setContentsMargins(2, 2, 2, 2)
        self._layout.setSpacing(1)

    def _finish_layout(self, widget: QWidget) -> None:
        self._layout.addWidget(self.info)
        self._layout.addWidget(self.error_label)
        self._layout.addWidget(widget, 1)
        self._layout.addWidget(self.readout)

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
        self._finish_layout(self.graphics)
        for plot in (self.depth_plot, self.amp_plot):
            plot.disableAutoRange()
            plot.scene().sigMouseMoved.connect(self._on_hover)

    def draw(self, view: FrameView) -> None:  # noqa: D102
        tof = view.tof
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
            self.amp_bar.setLabel("right", f"amplitude ({tof.amplitude_unit})")
        invalid = ~tof.valid
        if self._invalid is None or not np.array_equal(invalid, self._invalid):
            self._invalid = invalid
            overlay = np.zeros((*tof.valid.shape, 4), dtype=np.uint8)
            overlay[invalid] = INVALID_RGBA
            self.depth_invalid.setImage(overlay, autoLevels=False, levels=(0, 255))
            self.amp_invalid.setImage(overlay, autoLevels=False, levels=(0, 255))
        h, w = depth.shape
        for plot in (self.depth_plot, self.amp_plot):
            _set_view_range(plot, (h, w), x=(0, w), y=(0, h))
        _set_text(self.info, f"t = {view.time_s:.2f} s   frame {view.index + 1}   "
                             f"{int(invalid.sum())} invalid px")

    def _on_hover(self, pos: QPointF) -> None:
        if self.view is None:
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
                    self.readout.setText(text)
                return


class RangeProfilePanel(LivePanel):
    """Range-FFT magnitude (dB) versus range (m) per Rx, CFAR threshold, detections."""

    title = "Range profile"

    def __init__(self, parent: QWidget | None = None):
        super().__init__(parent)
        self.plot_widget = pg.PlotWidget(title="range profile")
        self.plot_widget.setToolTip("Range-FFT magnitude per receive channel (dB, chirp "
                                    "average) versus range (m); dashed: CFAR threshold; "
                                    "triangles: detections")
        self.plot = self.plot_widget.getPlotItem()
        self.plot.setLabel("bottom", "range", "m")
        self.plot.setLabel("left", "magnitude", "dB")
        self.plot.showGrid(x=True, y=True, alpha=0.2)
        self.legend = self.plot.addLegend(offset=(60, 8), labelTextSize="8pt",
                                          brush=pg.mkBrush(21, 24, 28, 200))
        self.curves: list[pg.PlotDataItem] = []
        self.threshold = self.plot.plot(pen=pg.mkPen("#ffffff", width=1.2,
                                                     style=Qt.PenStyle.DashLine),
                                         name="CFAR threshold")
        self.markers = pg.ScatterPlotItem(symbol="t1", size=11, pen=pg.mkPen("#ffeb3b"),
                                          brush=pg.mkBrush("#ffeb3b"))
        self.plot.addItem(self.markers)
        self.legend.addItem(self.markers, "detections")
        self._names: list[str] = []
        self._y: tuple[float, float] | None = None
        self.plot.disableAutoRange()
        self._finish_layout(self.plot_widget)
        self.plot.scene().sigMouseMoved.connect(self._on_hover)

    def draw(self, view: FrameView) -> None:  # noqa: D102
        if self._no_radar(view):
            return
        radar = view.radar
        assert radar is not None
        n = radar.profile_db.shape[0]
        names = list(radar.channel_names[:n])
        if names != self._names:
            self._rebuild_curves(names)
        r = radar.range_axis_m
        for i, curve in enumerate(self.curves):
            curve.setData(r, radar.profile_db[i])
        if radar.threshold_db is not None and len(radar.threshold_db) == len(r):
            self.threshold.setData(r, radar.threshold_db)
        else:
            self.threshold.setData([], [])
        det = radar.detections
        if len(det):
            mean = 10 * np.log10(np.mean(10 ** (radar.profile_db / 10), axis=0))
            levels = np.interp(det.range_m, r, mean) + 2.0
            self.markers.setData(det.range_m, levels)
        else:
            self.markers.setData([], [])
        finite = radar.profile_db[np.isfinite(radar.profile_db)]
        lo = float(np.floor(finite.min() / 10) * 10) if finite.size else -100.0
        hi = float(np.ceil(finite.max() / 10) * 10 + 10) if finite.size else 0.0
        self._y = follow_levels(self._y, lo, hi, tolerance=10.0)
        x_max = float(r[-1]) if len(r) else 1.0
        _set_view_range(self.plot, (len(r), x_max, self._y), x=(0.0, x_max), y=self._y)
        peak = radar.profile_peak_range_m()
        peak_text = "—" if not np.isfinite(peak) else f"{peak:.2f} m"
        _set_text(self.info, f"t = {view.time_s:.2f} s   peak {peak_text}   "
                             f"{len(det)} detections")

    def _rebuild_curves(self, names: list[str]) -> None:
        for curve in self.curves:
            self.plot.removeItem(curve)
            self.legend.removeItem(curve)
        self.curves = []
        for i, name in enumerate(names):
            colour = CHANNEL_COLOURS[i % len(CHANNEL_COLOURS)]
            curve = self.plot.plot(pen=pg.mkPen(colour, width=1.3), name=name)
            self.curves.append(curve)
        self.legend.setColumnCount(1 if len(names) <= 4 else 3)
        self._names = names

    def _on_hover(self, pos: QPointF) -> None:
        radar = None if self.view is None else self.view.radar
        if radar is None or not self.plot.sceneBoundingRect().contains(pos):
            return
        p = self.plot.vb.mapSceneToView(pos)
        i = int(np.clip(np.searchsorted(radar.range_axis_m, p.x()), 0,
                        len(radar.range_axis_m) - 1))
        values = "  ".join(f"{name} {radar.profile_db[k, i]:.1f}"
                           for k, name in enumerate(radar.channel_names))
        self.readout.setText(f"range {radar.range_axis_m[i]:.3f} m: {values} dB")


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


class RangeDopplerPanel(LivePanel):
    """Range–Doppler map (dB) with CFAR detections."""

    title = "Range–Doppler"

    def __init__(self, parent: QWidget | None = None):
        super().__init__(parent)
        self.graphics = pg.GraphicsLayoutWidget()
        self.graphics.setToolTip("Range–Doppler map (dB, channels integrated); circles: CFAR "
                                 "detections; velocity positive = moving away (m/s)")
        self.plot, self.image = _image_plot("range–Doppler", x_label=("range", "m"),
                                            y_label=("radial velocity", "m/s"))
        self.graphics.addItem(self.plot, row=0, col=0)
        self.bar = _colour_bar(self.graphics.ci, self.image, "viridis", "power (dB)", row=0,
                               col=1)
        self.markers = pg.ScatterPlotItem(symbol="o", size=12, pen=DETECTION_PEN,
                                          brush=DETECTION_BRUSH)
        self.markers.setZValue(10)
        self.plot.addItem(self.markers)
        self.plot.disableAutoRange()
        self._levels: tuple[float, float] | None = None
        self._finish_layout(self.graphics)
        self.plot.scene().sigMouseMoved.connect(self._on_hover)

    def draw(self, view: FrameView) -> None:  # noqa: D102
        if self._no_radar(view):
            return
        radar = view.radar
        assert radar is not None
        rd = radar.range_doppler_db
        self.image.setImage(rd, autoLevels=False)
        _set_image_rect(self.image, self.plot, _rect(radar.range_axis_m,
                                                     radar.velocity_axis_mps))
        hi = float(np.nanmax(rd))
        self._levels = follow_levels(self._levels, hi - 60.0, hi, tolerance=3.0)
        _set_bar_levels(self.bar, self._levels)
        det = radar.detections
        self.markers.setData(det.range_m, det.velocity_mps,
                             brush=detection_brushes(det, by_label=self.colour_by_label))
        _set_text(self.info, f"t = {view.time_s:.2f} s   {len(det)} detections")

    def _on_hover(self, pos: QPointF) -> None:
        radar = None if self.view is None else self.view.radar
        if radar is None or not self.plot.sceneBoundingRect().contains(pos):
            return
        p = self.plot.vb.mapSceneToView(pos)
        ri = int(np.argmin(np.abs(radar.range_axis_m - p.x())))
        vi = int(np.argmin(np.abs(radar.velocity_axis_mps - p.y())))
        self.readout.setText(f"range {radar.range_axis_m[ri]:.3f} m  velocity "
                             f"{radar.velocity_axis_mps[vi]:+.3f} m/s: "
                             f"{radar.range_doppler_db[vi, ri]:.1f} dB")


class RangeAzimuthPanel(LivePanel):
    """Bird's-eye range–azimuth map (dB) in radar x (right) / z (forward) metres."""

    title = "Range–azimuth"
    pixel_m = 0.05

    def __init__(self, parent: QWidget | None = None):
        super().__init__(parent)
        self.graphics = pg.GraphicsLayoutWidget()
        self.graphics.setToolTip("Range–azimuth map seen from above (dB): lateral x to the "
                                 "right and forward distance from the radar (m); circles: "
                                 "detections")
        self.plot, self.image = _image_plot("bird's-eye",
                                            x_label=("lateral x", "m"),
                                            y_label=("forward", "m"))
        self.plot.setAspectLocked(True)
        self.graphics.addItem(self.plot, row=0, col=0)
        self.bar = _colour_bar(self.graphics.ci, self.image, "viridis", "power (dB)", row=0,
                               col=1)
        self.markers = pg.ScatterPlotItem(symbol="o", size=12, pen=DETECTION_PEN,
                                          brush=DETECTION_BRUSH)
        self.markers.setZValue(10)
        self.plot.addItem(self.markers)
        self._grid_key: tuple[Any, ...] | None = None
        self._lookup: tuple[NDArray[np.int64], NDArray[np.int64], NDArray[np.bool_]] | None = None
        self._levels: tuple[float, float] | None = None
        self.plot.disableAutoRange()
        self._finish_layout(self.graphics)
        self.plot.scene().sigMouseMoved.connect(self._on_hover)

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

    def draw(self, view: FrameView) -> None:  # noqa: D102
        if self._no_radar(view):
            return
        radar = view.radar
        assert radar is not None
        ra = radar.range_azimuth_db
        hi = float(np.nanmax(ra))
        if radar.bev_db is not None and radar.bev_x_m is not None and radar.bev_z_m is not None:
            # The DSP's own Cartesian resampling of the range–azimuth map.
            bev = radar.bev_db
            rect = _rect(radar.bev_x_m, radar.bev_z_m)
        else:
            r, az = radar.range_axis_m, radar.azimuth_axis_deg
            key = (len(r), float(r[0]), float(r[-1]), len(az), float(az[0]), float(az[-1]))
            if key != self._grid_key:
                self._build_lookup(r, az)
                self._grid_key = key
            assert self._lookup is not None
            ai, ri, inside = self._lookup
            bev = np.where(inside, ra[ai, ri], np.nan).astype(np.float32)
            rect = self._extent
        self.bev = bev
        self.image.setImage(np.nan_to_num(bev, nan=hi - 200.0), autoLevels=False)
        _set_image_rect(self.image, self.plot, rect)
        self._levels = follow_levels(self._levels, hi - 40.0, hi, tolerance=3.0)
        _set_bar_levels(self.bar, self._levels)
        det = radar.detections
        a = np.deg2rad(det.azimuth_deg)
        self.markers.setData(det.range_m * np.sin(a), det.range_m * np.cos(a),
                             brush=detection_brushes(det, by_label=self.colour_by_label))
        _set_text(self.info, f"t = {view.time_s:.2f} s   {len(det)} detections")

    def _on_hover(self, pos: QPointF) -> None:
        radar = None if self.view is None else self.view.radar
        if radar is None or not self.plot.sceneBoundingRect().contains(pos):
            return
        p = self.plot.vb.mapSceneToView(pos)
        rng = float(np.hypot(p.x(), p.y()))
        az = float(np.rad2deg(np.arctan2(p.x(), p.y())))
        ri = int(np.argmin(np.abs(radar.range_axis_m - rng)))
        ai = int(np.argmin(np.abs(radar.azimuth_axis_deg - az)))
        self.readout.setText(f"x {p.x():+.2f} m  forward {p.y():.2f} m  (range {rng:.2f} m, "
                             f"azimuth {az:+.1f}°): {radar.range_azimuth_db[ai, ri]:.1f} dB")


def bold_font(size: int = 9) -> QFont:
    """A bold UI font."""
    font = QFont()
    font.setPointSize(size)
    font.setBold(True)
    return font


__all__ = ["INVALID_RGBA", "LivePanel", "QColor", "RangeAzimuthPanel", "RangeDopplerPanel",
           "RangeProfilePanel", "TofPanel", "bold_font"]
