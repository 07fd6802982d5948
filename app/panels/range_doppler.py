"""The range–Doppler panel.

Power over range and radial velocity, with detections and ground truth.
"""

from __future__ import annotations

import numpy as np
from PyQt6.QtCore import QPointF
from PyQt6.QtWidgets import QWidget

from app.frame_view import FrameView
from app.panels.base import _set_text, plural
from app.panels.maps import MapPanel, _rect, _set_image_rect


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
