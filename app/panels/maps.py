"""The shared base of the two map panels (range–Doppler and range–azimuth).

An image with a colour bar, detections and ground truth drawn over it.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import pyqtgraph as pg
from numpy.typing import NDArray
from PyQt6.QtCore import QPointF, QRectF, Qt

from app.frame_view import ObjectMarks
from app.panels.base import (
    DETECTION_BRUSH,
    DETECTION_PEN,
    DIFF_CMAP,
    DIFF_SPAN_DB,
    NEAR_PEN,
    TRUTH_PEN,
    TRUTH_SELECTED_PEN,
    LivePanel,
    _colour_bar,
    _image_plot,
    _set_bar_levels,
    _set_view_range,
    detection_brushes,
    detection_pens,
    follow_levels,
)


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
