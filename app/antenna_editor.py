"""Antenna-array editor: the radar board in millimetres with draggable Tx and Rx elements.

Elements snap to a λ/2 grid (optional). Every drag step is pushed as an edit that merges
with the rest of the drag into one undo step; since antenna positions are not part of the
render key, the simulator re-uses its cached render and only the radar front end and DSP
run again, so the radar maps follow the drag.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import pyqtgraph as pg
from PyQt6.QtCore import QPointF, pyqtSignal
from PyQt6.QtWidgets import (
    QCheckBox,
    QComboBox,
    QFormLayout,
    QGroupBox,
    QHBoxLayout,
    QLabel,
    QPushButton,
    QSpinBox,
    QVBoxLayout,
    QWidget,
)

from app.document import EditError, ProjectDocument
from app.widgets import int_spin, spin
from simcore.scene.radar_config import RadarConfig

TX_COLOUR = "#ff6e6e"
RX_COLOUR = "#4fc3f7"
LAYOUTS = ["ULA", "L", "URA", "circular", "MIMO (2 Tx × 4 Rx)"]


def half_wavelength_mm(config: RadarConfig) -> float:
    """λ/2 at the chirp's centre frequency (mm)."""
    return 0.5 * config.wavelength_m * 1e3


def snap_to_grid(position_mm: tuple[float, float], step_mm: float) -> tuple[float, float]:
    """Round a board position to the nearest multiple of ``step_mm`` on each axis."""
    return (float(round(round(position_mm[0] / step_mm) * step_mm, 6)),
            float(round(round(position_mm[1] / step_mm) * step_mm, 6)))


def layout_positions(name: str, *, n: int, nx: int, ny: int, spacing_mm: float
                     ) -> tuple[list[tuple[float, float]] | None, list[tuple[float, float]]]:
    """Tx (None = keep) and Rx board positions (mm) of a layout preset.

    Uses :mod:`simcore.scene.radar_arrays` when present.
    """
    try:
        from simcore.sensors import radar_arrays as arrays
    except ImportError:
        arrays = None
    d = spacing_mm
    if name == "ULA":
        rx = [(i * d, 0.0) for i in range(n)]
        if arrays is not None:
            rx = [a.position_mm for a in arrays.ula(n, d)]
        return None, rx
    if name == "L":
        k = max(2, (n + 1) // 2)
        if arrays is not None:
            return None, [a.position_mm for a in arrays.l_shape(k, n + 1 - k, d)]
        return None, [(i * d, 0.0) for i in range(k - 1, 0, -1)] + [(0.0, 0.0)] + [
            (0.0, -j * d) for j in range(1, n + 1 - k)]
    if name == "URA":
        if arrays is not None:
            return None, [a.position_mm for a in arrays.ura(nx, ny, d)]
        return None, [(i * d, j * d) for j in range(ny) for i in range(nx)]
    if name == "circular":
        radius = d / (2 * np.sin(np.pi / max(n, 2)))  # neighbour spacing = d
        if arrays is not None:
            return None, [a.position_mm for a in arrays.circular(n, radius)]
        ang = 2 * np.pi * np.arange(n) / n
        return None, [(float(radius * np.cos(a)), float(radius * np.sin(a))) for a in ang]
    if name.startswith("MIMO"):
        rx = [(i * d, 0.0) for i in range(4)]
        tx = [(-8.0 * d, 0.0), (-4.0 * d, 0.0)]  # 4·d apart: 8 virtual elements, d spacing
        return tx, rx
    raise ValueError(f"unknown layout {name!r}")


class AntennaBoardView(pg.PlotWidget):
    """Board view: x right, y down (seen from behind the board), millimetres.

    Signals
    -------
    elementDragged(str, int, tuple, bool)
        role ("tx"/"rx"), index, board position (mm, snapped), finished.
    """

    elementDragged = pyqtSignal(str, int, tuple, bool)

    def __init__(self, parent: QWidget | None = None):
        super().__init__(parent)
        self.setToolTip("Radar board seen from behind (boresight into the screen): x right, "
                        "y down, mm. Drag Tx (red squares) and Rx (blue circles).")
        plot = self.getPlotItem()
        plot.setLabel("bottom", "board x", "mm")
        plot.setLabel("left", "board y (down)", "mm")
        plot.invertY(True)
        plot.setAspectLocked(True)
        plot.hideButtons()
        plot.setMenuEnabled(False)
        self.grid_lines = pg.PlotDataItem(pen=pg.mkPen("#3a4350", width=1), connect="pairs")
        plot.addItem(self.grid_lines)
        self.targets: dict[tuple[str, int], pg.TargetItem] = {}
        self.snap_step_mm: float | None = 2.5
        self._quiet = False

    def set_elements(self, tx: list[tuple[str, tuple[float, float]]],
                     rx: list[tuple[str, tuple[float, float]]], *, half_lambda_mm: float) -> None:
        """Show Tx and Rx elements (name, position) and a λ/2 grid around them."""
        plot = self.getPlotItem()
        wanted = [("tx", i, n, p) for i, (n, p) in enumerate(tx)] + [
            ("rx", i, n, p) for i, (n, p) in enumerate(rx)]
        keys = {(role, i) for role, i, _, _ in wanted}
        for key in list(self.targets):
            if key not in keys:
                plot.removeItem(self.targets.pop(key))
        self._quiet = True
        try:
            for role, i, name, pos in wanted:
                target = self.targets.get((role, i))
                if target is None:
                    colour = TX_COLOUR if role == "tx" else RX_COLOUR
                    target = pg.TargetItem(
                        pos=pos, size=16, symbol="s" if role == "tx" else "o",
                        pen=pg.mkPen("#ffffff", width=1), brush=pg.mkBrush(colour),
                        hoverBrush=pg.mkBrush("#ffd54a"), movable=True,
                        label=name or f"{role}{i + 1}",
                        # Tx labels below, Rx labels above: a Tx and an Rx may share a spot.
                        labelOpts={"color": colour,
                                   "offset": (10, 12) if role == "tx" else (10, -14)})
                    target.setZValue(10)
                    target.sigPositionChanged.connect(
                        lambda t, r=role, k=i: self._on_moved(r, k, t, finished=False))
                    target.sigPositionChangeFinished.connect(
                        lambda t, r=role, k=i: self._on_moved(r, k, t, finished=True))
                    plot.addItem(target)
                    self.targets[(role, i)] = target
                else:
                    target.setPos(QPointF(*pos))
                    if target.label() is not None:
                        target.label().setFormat(name or f"{role}{i + 1}")
        finally:
            self._quiet = False
        self._draw_grid([p for *_, p in wanted], half_lambda_mm)

    def _draw_grid(self, points: list[tuple[float, float]], step: float) -> None:
        pts = np.array(points, dtype=float).reshape(-1, 2)
        lo = np.floor((pts.min(axis=0) - 4 * step) / step) * step
        hi = np.ceil((pts.max(axis=0) + 4 * step) / step) * step
        xs = np.arange(lo[0], hi[0] + step / 2, step)
        ys = np.arange(lo[1], hi[1] + step / 2, step)
        x = np.concatenate([np.repeat(xs, 2), np.tile([lo[0], hi[0]], len(ys))])
        y = np.concatenate([np.tile([lo[1], hi[1]], len(xs)), np.repeat(ys, 2)])
        self.grid_lines.setData(x, y)
        if not getattr(self, "_ranged", False):
            self.getPlotItem().setRange(xRange=(lo[0], hi[0]), yRange=(lo[1], hi[1]),
                                        padding=0.05)
            self._ranged = True

    def reset_range(self) -> None:
        """Fit the view to the elements on the next update."""
        self._ranged = False

    def _on_moved(self, role: str, index: int, target: pg.TargetItem, *, finished: bool
                  ) -> None:
        if self._quiet:
            return
        p = target.pos()
        pos = (float(p.x()), float(p.y()))
        if self.snap_step_mm:
            pos = snap_to_grid(pos, self.snap_step_mm)
            if (pos[0], pos[1]) != (p.x(), p.y()):
                self._quiet = True
                target.setPos(QPointF(*pos))
                self._quiet = False
        self.elementDragged.emit(role, index, pos, finished)

    def element_scene_pos(self, role: str, index: int) -> QPointF:
        """Scene position of an element (for driving drags in tests)."""
        t = self.targets[(role, index)]
        return self.getPlotItem().vb.mapViewToScene(t.pos())


class AntennaEditor(QWidget):
    """Board view plus snapping, layout presets and add/remove buttons."""

    editFailed = pyqtSignal(str)

    def __init__(self, document: ProjectDocument, parent: QWidget | None = None):
        super().__init__(parent)
        self.document = document
        layout = QHBoxLayout(self)
        layout.setContentsMargins(2, 2, 2, 2)
        self.board = AntennaBoardView()
        self.board.elementDragged.connect(self.move_element)
        layout.addWidget(self.board, 3)
        side = QVBoxLayout()
        self.snap = QCheckBox("snap to λ/2 grid")
        self.snap.setChecked(True)
        self.snap.setToolTip("Round dragged positions to multiples of λ/2 (at the centre "
                             "frequency)")
        self.snap.toggled.connect(lambda _on: self.refresh())
        side.addWidget(self.snap)
        self.info = QLabel("")
        self.info.setStyleSheet("color: #9aa4ae;")
        self.info.setWordWrap(True)
        side.addWidget(self.info)
        presets = QGroupBox("Layout preset (Rx)")
        form = QFormLayout(presets)
        self.layout_combo = QComboBox()
        self.layout_combo.addItems(LAYOUTS)
        self.layout_combo.setToolTip("Uniform linear, L-shaped, uniform rectangular, circular, "
                                     "or a 2-Tx × 4-Rx TDM-MIMO layout (8 virtual elements)")
        form.addRow("layout", self.layout_combo)
        self.n_spin: QSpinBox = int_spin(minimum=1, maximum=64, tooltip="number of Rx elements")
        self.n_spin.setValue(4)
        form.addRow("elements", self.n_spin)
        self.nx_spin = int_spin(minimum=1, maximum=16, tooltip="URA columns")
        self.nx_spin.setValue(2)
        self.ny_spin = int_spin(minimum=1, maximum=16, tooltip="URA rows")
        self.ny_spin.setValue(2)
        grid = QHBoxLayout()
        grid.addWidget(self.nx_spin)
        grid.addWidget(QLabel("×"))
        grid.addWidget(self.ny_spin)
        form.addRow("URA cols × rows", grid)
        self.spacing = spin(minimum=0.05, maximum=8.0, decimals=2, step=0.25, suffix="λ",
                            tooltip="element spacing in wavelengths (0.5 = λ/2)")
        self.spacing.setValue(0.5)
        form.addRow("spacing", self.spacing)
        apply = QPushButton("Apply layout")
        apply.setToolTip("Replace the Rx elements (and for MIMO the Tx) by this layout")
        apply.clicked.connect(lambda: self.apply_layout(self.layout_combo.currentText()))
        form.addRow(apply)
        side.addWidget(presets)
        buttons = QHBoxLayout()
        add_rx = QPushButton("+ Rx")
        add_rx.setToolTip("Add a receive element λ/2 right of the last one")
        add_rx.clicked.connect(lambda: self.add_element("rx"))
        add_tx = QPushButton("+ Tx")
        add_tx.setToolTip("Add a transmit element (TDM-MIMO)")
        add_tx.clicked.connect(lambda: self.add_element("tx"))
        remove_rx = QPushButton("− Rx")
        remove_rx.setToolTip("Remove the last receive element")
        remove_rx.clicked.connect(lambda: self.remove_element("rx"))
        remove_tx = QPushButton("− Tx")
        remove_tx.setToolTip("Remove the last transmit element")
        remove_tx.clicked.connect(lambda: self.remove_element("tx"))
        for b in (add_rx, remove_rx, add_tx, remove_tx):
            buttons.addWidget(b)
        side.addLayout(buttons)
        side.addStretch(1)
        layout.addLayout(side, 2)
        document.projectChanged.connect(self.refresh)
        document.projectReplaced.connect(self.board.reset_range)
        self.refresh()

    def refresh(self, *_: object) -> None:
        """Show the project's antennas."""
        radar = self.document.project.rig.radar
        half = half_wavelength_mm(radar)
        self.board.snap_step_mm = half if self.snap.isChecked() else None
        count = (len(radar.tx), len(radar.rx))
        if count != getattr(self, "_count", None):
            self.board.reset_range()  # a new layout: fit the view to it
            self._count = count
        self.board.set_elements([(a.name, a.position_mm) for a in radar.tx],
                                [(a.name, a.position_mm) for a in radar.rx],
                                half_lambda_mm=half)
        self.info.setText(f"λ/2 = {half:.3f} mm (grid)\n{len(radar.tx)} Tx, {len(radar.rx)} Rx, "
                          f"{len(radar.tx) * len(radar.rx)} virtual channels")

    def move_element(self, role: str, index: int, position_mm: tuple[float, float],
                     finished: bool = False) -> None:  # noqa: FBT001, FBT002 - Qt slot
        """Move Tx/Rx ``index`` to ``position_mm`` (the board view's drag path)."""
        try:
            name = self.document.project.rig.radar.model_dump()[role][index]["name"]
            self.document.set_value(f"rig.radar.{role}[{index}].position_mm",
                                    (float(position_mm[0]), float(position_mm[1])),
                                    text=f"Move antenna {name or role}",
                                    merge_key=f"antenna:{role}{index}")
        except EditError as exc:
            self.editFailed.emit(str(exc))
        if finished:
            self.document.end_merge()

    def apply_layout(self, name: str) -> None:
        """Replace the Rx (and for MIMO the Tx) positions by a layout preset."""
        radar = self.document.project.rig.radar
        d = self.spacing.value() * radar.wavelength_m * 1e3
        tx, rx = layout_positions(name, n=self.n_spin.value(), nx=self.nx_spin.value(),
                                  ny=self.ny_spin.value(), spacing_mm=d)

        def mutate(data: dict[str, Any]) -> None:
            r = data["rig"]["radar"]
            r["rx"] = [{"name": f"rx{i + 1}", "position_mm": tuple(p)} for i, p in enumerate(rx)]
            if tx is not None:
                r["tx"] = [{"name": f"tx{i + 1}", "position_mm": tuple(p)}
                           for i, p in enumerate(tx)]

        try:
            self.document.edit(f"Antenna layout {name}", mutate)
        except EditError as exc:
            self.editFailed.emit(str(exc))
        self.board.reset_range()
        self.refresh()

    def add_element(self, role: str) -> None:
        """Append a Tx or Rx element λ/2 to the right of the rightmost one."""
        radar = self.document.project.rig.radar
        items = radar.tx if role == "tx" else radar.rx
        half = half_wavelength_mm(radar)
        x = max(a.position_mm[0] for a in items) + (4 * half if role == "tx" else half)
        y = items[-1].position_mm[1]
        names = {a.name for a in items}
        i = len(items) + 1
        while f"{role}{i}" in names:
            i += 1

        def mutate(data: dict[str, Any]) -> None:
            data["rig"]["radar"][role].append({"name": f"{role}{i}",
                                               "position_mm": (float(x), float(y))})

        try:
            self.document.edit(f"Add {role}", mutate)
        except EditError as exc:
            self.editFailed.emit(str(exc))

    def remove_element(self, role: str) -> None:
        """Remove the last Tx or Rx element (at least one stays)."""
        try:
            self.document.edit(f"Remove {role}", lambda d: d["rig"]["radar"][role].pop())
        except EditError as exc:
            self.editFailed.emit(str(exc))
