"""The range–azimuth panel: the radar's angle map with detections and ground truth."""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray
from PyQt6.QtCore import QPointF, QRectF
from PyQt6.QtWidgets import QWidget

from app.frame_view import FrameView
from app.panels.base import _set_text, plural
from app.panels.maps import MapPanel, _rect, _set_image_rect


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
