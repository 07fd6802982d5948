"""The RGB camera's colour image, shown when the rig carries an RGB camera (``rig.rgb``)."""

from __future__ import annotations

from typing import Any

import pyqtgraph as pg
from PyQt6.QtCore import QPointF
from PyQt6.QtWidgets import QWidget

from app.frame_view import FrameView
from app.panels.base import LivePanel, _set_text


class RgbPanel(LivePanel):
    """Colour image (8-bit sRGB) of the RGB camera, from the frame's own snapshot."""

    sensor_kind = "rgb"

    title = "RGB camera"

    def __init__(self, parent: QWidget | None = None):
        super().__init__(parent)
        self.graphics = pg.GraphicsLayoutWidget()
        self.graphics.setToolTip("Colour image of the RGB camera (visible band, 8-bit sRGB), "
                                 "from the same scene snapshot as the ToF and radar data")
        self.plot = pg.PlotItem(title="colour")
        self.plot.setLabel("bottom", "column", "px")
        self.plot.setLabel("left", "row", "px")
        self.image = pg.ImageItem(axisOrder="row-major")
        self.plot.addItem(self.image)
        self.plot.invertY(True)
        self.plot.setAspectLocked(True)
        self.plot.disableAutoRange()
        for side in ("bottom", "left"):
            self.plot.getAxis(side).enableAutoSIPrefix(False)   # pixels, never "kpx"
        self.graphics.addItem(self.plot, row=0, col=0)
        self._shape: tuple[int, ...] | None = None
        self._finish_layout(self.graphics)
        self.plot.scene().sigMouseMoved.connect(self._on_hover)

    def draw(self, view: FrameView) -> None:  # noqa: D102
        if view.rgb is None:
            _set_text(self.info, "the rig carries no RGB camera (set rig.rgb in the project)")
            return
        self.image.setImage(view.rgb, autoLevels=False, levels=(0, 255))
        if self._shape != view.rgb.shape:
            self._shape = view.rgb.shape
            h, w = view.rgb.shape[:2]
            self.plot.vb.setRange(xRange=(0, w), yRange=(0, h), padding=0.0)
        h, w = view.rgb.shape[:2]
        _set_text(self.info, f"t = {view.time_s:.2f} s   frame {view.index + 1}   {w}×{h} px")

    def _on_hover(self, pos: QPointF) -> None:
        view: Any = self.view
        if view is None or view.rgb is None:
            return
        p = self.plot.vb.mapSceneToView(pos)
        row, col = int(p.y()), int(p.x())
        h, w = view.rgb.shape[:2]
        if 0 <= row < h and 0 <= col < w:
            r, g, b = (int(v) for v in view.rgb[row, col])
            _set_text(self.readout, f"row {row}, col {col}: sRGB ({r}, {g}, {b})")
