"""The range-profile panel.

Power against range per receive channel, with the CFAR threshold, detections and
ground-truth ranges.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import pyqtgraph as pg
from numpy.typing import NDArray
from PyQt6.QtCore import QPointF, Qt
from PyQt6.QtWidgets import QCheckBox, QWidget

from app.frame_view import FrameView, ObjectMarks
from app.panels.base import (
    CHANNEL_COLOURS,
    DIFF_SPAN_DB,
    NEAR_PEN,
    TRUTH_PEN,
    TRUTH_SELECTED_PEN,
    LivePanel,
    _set_text,
    _set_title,
    _set_view_range,
    detection_pens,
    follow_levels,
    plural,
)
from simcore.dsp.profile import range_profile_cfar
from simcore.scene import Project
from simcore.scene.dsp_config import DspConfig


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
