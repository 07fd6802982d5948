"""The ToF panel: depth and amplitude images of one ToF camera, with object outlines.

Invalid pixels (saturated, too dark or no return) are drawn in magenta; hovering shows the
depth and amplitude under the cursor.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import pyqtgraph as pg
from numpy.typing import NDArray
from PyQt6.QtCore import QPointF
from PyQt6.QtWidgets import QWidget

from app.frame_view import FrameView
from app.panels.base import (
    INVALID_RGBA,
    LivePanel,
    _colour_bar,
    _image_plot,
    _set_bar_levels,
    _set_text,
    _set_view_range,
    follow_levels,
    object_outlines,
)


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
