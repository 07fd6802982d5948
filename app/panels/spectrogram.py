"""Scrolling micro-Doppler spectrogram: Doppler power at a range gate over the last seconds.

Each frame adds one column: the frame's range–Doppler map (already computed by the
pipeline, :class:`app.frame_view.RadarView`) summed over the range gate
(:func:`simcore.dsp.microdoppler.doppler_column_from_map`) — the per-frame spectrogram of
``docs/dsp.md``. The gate is the selected object's true range ± 0.6 m when an object is
selected and its ground truth is known, else the project's ``dsp.spectrogram_range_m``,
else every bin beyond ``dsp.min_range_m``. Columns go into a bounded ring buffer
(:class:`simcore.dsp.microdoppler.SpectrogramBuffer`, ``dsp.spectrogram_history_s`` ×
frame rate columns) on every frame, also while the panel is hidden, so the history is
complete when it is shown; frames skipped by playback leave empty (NaN) columns and a
jump back in time starts a new history. The selected object's true radial velocity is
drawn over the image.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import pyqtgraph as pg
from PyQt6.QtCore import QPointF, QRectF, Qt
from PyQt6.QtWidgets import QWidget

from app.frame_view import FrameView
from app.panels.base import (
    LivePanel,
    _colour_bar,
    _image_plot,
    _set_bar_levels,
    _set_text,
    follow_levels,
)
from simcore.dsp.microdoppler import (
    OBJECT_GATE_HALF_WIDTH_M,
    SpectrogramBuffer,
    doppler_column_from_map,
    gate_bins,
)
from simcore.scene import Project
from simcore.scene.dsp_config import DspConfig

#: Colour span below the image's maximum (dB).
SPAN_DB = 50.0
TRUTH_PEN = pg.mkPen("#4fc3f7", width=2.0, style=Qt.PenStyle.DashLine)


class SpectrogramPanel(LivePanel):
    """Micro-Doppler spectrogram (dB): time (s) across, radial velocity (m/s) up."""

    title = "Micro-Doppler"

    def __init__(self, parent: QWidget | None = None):
        super().__init__(parent)
        self.graphics = pg.GraphicsLayoutWidget()
        self.graphics.setToolTip(
            "Micro-Doppler spectrogram: Doppler power (dB) of the range gate, one column "
            "per frame, newest on the right; velocity positive = moving away (m/s). The "
            "gate follows the selected object's true range; the dashed blue line is its "
            "true radial velocity")
        self.plot, self.image = _image_plot("micro-Doppler", x_label=("time", "s"),
                                            y_label=("radial velocity", "m/s"))
        self.graphics.addItem(self.plot, row=0, col=0)
        self.bar = _colour_bar(self.graphics.ci, self.image, "inferno", "power (dB)", row=0,
                               col=1)
        self.truth_curve = pg.PlotDataItem(pen=TRUTH_PEN)
        self.truth_curve.setZValue(5)
        self.plot.addItem(self.truth_curve)
        self.plot.disableAutoRange()
        self.dsp = DspConfig()
        self.frame_rate_hz = 10.0
        self.buffer: SpectrogramBuffer | None = None
        self._truth: list[float] = []
        self._last_index: int | None = None
        self._gate = (0.0, 0.0)
        self._levels: tuple[float, float] | None = None
        self._range_key: tuple[float, ...] | None = None
        self._finish_layout(self.graphics)
        self.plot.scene().sigMouseMoved.connect(self._on_hover)

    # --- project and frames ---------------------------------------------------------
    def set_project(self, project: Project) -> None:  # noqa: D102
        super().set_project(project)
        rate = float(project.timeline.frame_rate_hz)
        self.dsp = project.dsp       # the gate and history length are read every frame
        if rate != self.frame_rate_hz:
            self.frame_rate_hz = rate
            self.reset()             # the columns' spacing changed

    def reset(self) -> None:
        """Forget the history (a new frame rate, or a jump back in time)."""
        self.buffer = None
        self._truth = []
        self._last_index = None

    @property
    def capacity(self) -> int:
        """Columns kept: ``dsp.spectrogram_history_s`` × frame rate (at least 2)."""
        return max(2, int(math.ceil(self.dsp.spectrogram_history_s * self.frame_rate_hz)))

    def show_frame(self, view: FrameView | None) -> None:
        """Add the frame's column (also while hidden), then draw as the base class does."""
        if view is not None and view.radar is not None:
            try:
                self._accumulate(view)
            except Exception as exc:  # noqa: BLE001 - shown in this panel; others go on
                self.show_error(f"frame {view.index + 1}: {type(exc).__name__}: {exc}")
        super().show_frame(view)

    def _gate_for(self, view: FrameView, r: np.ndarray) -> tuple[float, float]:
        marks = view.objects
        if marks is not None and self.selected_id is not None:
            hit = np.flatnonzero(marks.object_id == self.selected_id)
            if hit.size and np.isfinite(marks.range_m[hit[0]]):
                c = float(marks.range_m[hit[0]])
                return c - OBJECT_GATE_HALF_WIDTH_M, c + OBJECT_GATE_HALF_WIDTH_M
        if self.dsp.spectrogram_range_m is not None:
            lo, hi = self.dsp.spectrogram_range_m
            return float(lo), float(hi)
        return float(self.dsp.min_range_m), float(r[-1])

    def _selected_velocity(self, view: FrameView) -> float:
        marks = view.objects
        if marks is None or self.selected_id is None:
            return float("nan")
        hit = np.flatnonzero(marks.object_id == self.selected_id)
        return float(marks.radial_velocity_mps[hit[0]]) if hit.size else float("nan")

    def _accumulate(self, view: FrameView) -> None:
        radar = view.radar
        assert radar is not None
        v = radar.velocity_axis_mps
        if self.buffer is None or self.buffer.velocity_mps.size != v.size \
                or self.buffer.capacity != self.capacity:
            self.buffer = SpectrogramBuffer(v, capacity=self.capacity)
            self._truth, self._last_index = [], None
        last = self._last_index
        if last is not None and view.index <= last:
            self.buffer.clear()          # replay or a jump back: a new history
            self._truth, last = [], None
        if last is not None:
            for k in range(last + 1, min(view.index, last + 1 + self.capacity)):
                self.buffer.push(np.full(v.size, np.nan), time_s=k / self.frame_rate_hz)
                self._truth.append(float("nan"))
        self._gate = self._gate_for(view, radar.range_axis_m)
        bins = gate_bins(radar.range_axis_m, min_m=self._gate[0], max_m=self._gate[1])
        column = doppler_column_from_map(radar.range_doppler_db, range_bins=bins)
        self.buffer.push(column, time_s=view.time_s)
        self._truth.append(self._selected_velocity(view))
        del self._truth[:-self.buffer.capacity]
        self._last_index = view.index

    # --- drawing ----------------------------------------------------------------------
    def draw(self, view: FrameView) -> None:  # noqa: D102
        if self._no_radar(view) or self.buffer is None or self.buffer.count == 0:
            return
        sg = self.buffer.spectrogram()
        v = sg.velocity_mps
        dt = 1.0 / self.frame_rate_hz
        t_end = float(sg.time_s[-1])
        t0 = t_end - dt * (self.buffer.capacity - 1)
        # Row-major image: rows = velocity (up), columns = time; empty history on the left.
        img = np.full((v.size, self.buffer.capacity), np.nan, dtype=np.float32)
        img[:, self.buffer.capacity - sg.power_db.shape[0]:] = sg.power_db.T
        finite = img[np.isfinite(img)]
        hi = float(finite.max()) if finite.size else 0.0
        self.image.setImage(np.nan_to_num(img, nan=hi - SPAN_DB - 10.0), autoLevels=False)
        self._levels = follow_levels(self._levels, hi - SPAN_DB, hi, tolerance=3.0)
        _set_bar_levels(self.bar, self._levels)
        dv = float(v[1] - v[0]) if v.size > 1 else 1.0
        rect = QRectF(t0 - dt / 2, float(v[0]) - dv / 2, dt * self.buffer.capacity,
                      dv * v.size)
        self.image.setRect(rect)
        # While the history fills, the view starts at the first column (no negative
        # times) and the data grow to the right; once full it scrolls.
        x_lo = max(t0, float(sg.time_s[0])) - dt / 2
        key = (round((x_lo + dt / 2) / dt), float(v[0]), float(v[-1]))
        if key != self._range_key:
            self._range_key = key
            self.plot.vb.setRange(xRange=(x_lo, x_lo + dt * self.buffer.capacity),
                                  yRange=(rect.top(), rect.bottom()), padding=0.0)
        truth = np.asarray(self._truth[-sg.power_db.shape[0]:], dtype=np.float64)
        shown = self.show_truth and np.isfinite(truth).any()
        self.truth_curve.setData(sg.time_s if shown else [], truth if shown else [],
                                 connect="finite")
        peak = float(v[int(np.nanargmax(np.nan_to_num(sg.power_db[-1], nan=-np.inf)))])
        _set_text(self.info, f"t = {view.time_s:.2f} s   gate {self._gate[0]:.2f}–"
                             f"{self._gate[1]:.2f} m   peak {peak:+.2f} m/s")

    def peak_velocity_mps(self) -> float:
        """Velocity of the strongest bin of the newest column (m/s; NaN when empty)."""
        if self.buffer is None or self.buffer.count == 0:
            return float("nan")
        sg = self.buffer.spectrogram()
        col = np.nan_to_num(sg.power_db[-1], nan=-np.inf)
        return float(sg.velocity_mps[int(np.argmax(col))]) if np.isfinite(col).any() \
            else float("nan")

    def _on_hover(self, pos: QPointF) -> None:
        if self.buffer is None or self.buffer.count == 0 or \
                not self.plot.sceneBoundingRect().contains(pos):
            return
        p = self.plot.vb.mapSceneToView(pos)
        sg = self.buffer.spectrogram()
        k = int(np.argmin(np.abs(sg.time_s - p.x())))
        j = int(np.argmin(np.abs(sg.velocity_mps - p.y())))
        value: Any = sg.power_db[k, j]
        _set_text(self.readout, f"t {sg.time_s[k]:.2f} s, v {sg.velocity_mps[j]:+.2f} m/s: "
                                f"{float(value):.1f} dB")
