"""Antenna-array editor: the radar board in millimetres with draggable Tx and Rx elements.

Beside the board, :class:`~app.editors.antenna_table.AntennaTable` lists every element with its
name, x and y in millimetres and its pattern, for typing exact values (one undo step per
cell), and :class:`~app.editors.array_analysis.ArrayAnalysisView` shows the virtual array and its
beam pattern; all three follow every step of a drag.

* **Nothing is hidden.** Tx are drawn as large squares under the smaller Rx circles, so a Tx
  that shares its position with an Rx can still be grabbed by its exposed corners; a click
  (without dragging) on a stack of elements sends the top one to the bottom, so any element
  of a stack can be picked. Elements at one spot get one label ("tx1 · rx2"); crowded labels
  alternate above and below their row.
* **Snapping** rounds dragged positions to a grid through the first Rx whose step is the
  current array pitch (the smallest spacing between element coordinates, so a preset's
  spacing survives a drag), or λ/2 at the chirp's centre or start frequency, or nothing.
* **Warnings** (co-located elements, element spacings that give grating lobes) are shown in
  the board's panel and update during a drag.

Every drag step is pushed as an edit that merges with the rest of the drag into one undo
step; since antenna positions are not part of the render key, the simulator re-uses its
cached render and only the radar front end and DSP run again.
"""

from __future__ import annotations

import html
from typing import Any

import numpy as np
import pyqtgraph as pg
from PyQt6.QtCore import QPointF, Qt, pyqtSignal
from PyQt6.QtWidgets import (
    QCheckBox,
    QComboBox,
    QFormLayout,
    QGridLayout,
    QGroupBox,
    QHBoxLayout,
    QLabel,
    QPushButton,
    QScrollArea,
    QSpinBox,
    QSplitter,
    QVBoxLayout,
    QWidget,
)

from app.document.document import EditError, ProjectDocument
from app.document.sensors import current_radar, current_radar_path, has_kind
from app.editors.antenna_table import AntennaTable
from app.editors.array_analysis import VIRTUAL_COLOUR, ArrayAnalysisView, virtual_positions_mm
from app.widgets.inputs import int_spin, spin
from simcore.scene import fieldpath
from simcore.scene import radar_arrays as arrays
from simcore.scene.radar_config import SPEED_OF_LIGHT, RadarConfig, aliasing_warnings

TX_COLOUR = "#ff6e6e"
RX_COLOUR = "#4fc3f7"
LAYOUTS = ["ULA", "L", "URA", "circular", "MIMO (2 Tx × 4 Rx)"]
#: Snap modes of the board: label → key.
SNAP_MODES = {"array pitch": "pitch", "λ/2 at centre frequency": "centre",
              "λ/2 at start frequency": "start", "off": "off"}
#: Marker sizes (px): a Tx square is larger than an Rx circle so both stay grabbable.
TX_SIZE = 22
RX_SIZE = 12
#: Positions closer than this are one spot (mm).
SAME_SPOT_MM = 1e-3
#: Labels of neighbours closer than this on screen alternate above/below (px).
CROWDED_PX = 34
#: The board's minimum width (px): the array stays readable on a 1366×768 screen.
BOARD_MIN_WIDTH = 200


def half_wavelength_mm(config: RadarConfig) -> float:
    """λ/2 at the chirp's centre frequency (mm)."""
    return 0.5 * config.wavelength_m * 1e3


def half_wavelength_start_mm(config: RadarConfig) -> float:
    """λ/2 at the chirp's start frequency (mm)."""
    return 0.5 * SPEED_OF_LIGHT / config.start_frequency_hz * 1e3


def array_pitch_mm(positions_mm: np.ndarray, *, fallback_mm: float) -> float:
    """Smallest non-zero spacing between element coordinates along board x or y (mm).

    Parameters
    ----------
    positions_mm : ndarray, shape (n, 2)
        Board positions of all elements (Tx and Rx).
    fallback_mm : float
        Returned when no two elements differ along an axis, or when the smallest spacing is
        below a quarter of it (irregular layouts such as circles).

    Examples
    --------
    >>> array_pitch_mm(np.array([[2.498, 0.0], [0.0, 0.0], [0.0, -2.498]]), fallback_mm=2.379)
    2.498
    """
    pts = np.asarray(positions_mm, dtype=np.float64).reshape(-1, 2)
    gaps = []
    for axis in range(2):
        d = np.diff(np.sort(pts[:, axis]))
        d = d[d > SAME_SPOT_MM]
        if len(d):
            gaps.append(float(d.min()))
    if not gaps or min(gaps) < 0.25 * fallback_mm:
        return float(fallback_mm)
    return min(gaps)


def snap_to_grid(position_mm: tuple[float, float], step_mm: float,
                 origin_mm: tuple[float, float] = (0.0, 0.0)) -> tuple[float, float]:
    """Round a board position to the nearest node of a grid (step, through ``origin_mm``)."""
    return tuple(float(round(o + round((p - o) / step_mm) * step_mm, 6))  # type: ignore[return-value]
                 for p, o in zip(position_mm, origin_mm, strict=True))


def layout_positions(name: str, *, n: int, nx: int, ny: int, spacing_mm: float
                     ) -> tuple[list[tuple[float, float]] | None, list[tuple[float, float]]]:
    """Tx (None = keep) and Rx board positions (mm) of a layout preset."""
    d = spacing_mm
    if name == "ULA":
        return None, [a.position_mm for a in arrays.ula(n, d)]
    if name == "L":
        k = max(2, (n + 1) // 2)
        return None, [a.position_mm for a in arrays.l_shape(k, n + 1 - k, d)]
    if name == "URA":
        return None, [a.position_mm for a in arrays.ura(nx, ny, d)]
    if name == "circular":
        radius = d / (2 * np.sin(np.pi / max(n, 2)))  # neighbour spacing = d
        return None, [a.position_mm for a in arrays.circular(n, radius)]
    if name.startswith("MIMO"):
        rx = [(i * d, 0.0) for i in range(4)]
        tx = [(-8.0 * d, 0.0), (-4.0 * d, 0.0)]  # 4·d apart: 8 virtual elements, d spacing
        return tx, rx
    raise ValueError(f"unknown layout {name!r}")


def next_element_position(radar: RadarConfig, role: str, pitch_mm: float
                          ) -> tuple[float, float]:
    """Where "+ Rx" / "+ Tx" puts a new element.

    Rx: one pitch right of the rightmost element of the longest Rx row. Tx: continuing the
    Tx row at its spacing, or for a single Tx, one Rx-row length (row elements × pitch) to
    its right, so the virtual array (p_tx + p_rx) extends the row without gaps or overlaps.
    Occupied spots are skipped.
    """
    rx = np.array([a.position_mm for a in radar.rx], dtype=np.float64)
    tx = np.array([a.position_mm for a in radar.tx], dtype=np.float64)
    rows, counts = np.unique(np.round(rx[:, 1], 6), return_counts=True)
    row_y = float(rows[np.argmax(counts)])
    row_n = int(counts.max())
    if role == "rx":
        y, x = row_y, float(rx[np.isclose(rx[:, 1], row_y, atol=1e-6), 0].max())
        step = pitch_mm
    else:
        y = float(tx[-1, 1])
        in_row = np.sort(tx[np.isclose(tx[:, 1], y, atol=1e-6), 0])
        x = float(in_row[-1])
        step = float(in_row[-1] - in_row[-2]) if len(in_row) >= 2 else row_n * pitch_mm
    taken = tx if role == "tx" else rx
    x += step
    while np.any(np.all(np.abs(taken - (x, y)) < SAME_SPOT_MM, axis=1)):
        x += step
    return (float(round(x, 6)), float(round(y, 6)))


class ElementItem(pg.TargetItem):
    """A draggable Tx/Rx marker; a click without a drag asks the board to re-stack it."""

    def __init__(self, role: str, index: int, clicked: Any, **kwargs: Any):
        super().__init__(**kwargs)
        self.role = role
        self.index = index
        self._clicked = clicked

    def mouseClickEvent(self, ev: Any) -> None:  # noqa: N802, D102 - pyqtgraph API
        if ev.button() == Qt.MouseButton.LeftButton and not self.moving:
            ev.accept()
            self._clicked(self)
            return
        super().mouseClickEvent(ev)


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
                        "y down, mm. Drag Tx (red squares) and Rx (blue circles); yellow "
                        "diamonds: the virtual array p_tx + p_rx (TDM-MIMO). A Tx under "
                        "an Rx can be grabbed by its corners; a click on a stack of elements "
                        "brings the one below to the top.")
        plot = self.getPlotItem()
        plot.setLabel("bottom", "board x", "mm")
        plot.setLabel("left", "board y (down)", "mm")
        plot.invertY(True)
        plot.setAspectLocked(True)
        plot.hideButtons()
        plot.setMenuEnabled(False)
        self.grid_lines = pg.PlotDataItem(pen=pg.mkPen("#3a4350", width=1), connect="pairs")
        plot.addItem(self.grid_lines)
        # The virtual array (p_tx + p_rx) under the elements; it takes no mouse events.
        self.virtual_dots = pg.ScatterPlotItem(size=9, symbol="d", pen=pg.mkPen("#202020"),
                                               brush=pg.mkBrush(VIRTUAL_COLOUR))
        self.virtual_dots.setZValue(5)
        self.virtual_dots.setAcceptedMouseButtons(Qt.MouseButton.NoButton)
        plot.addItem(self.virtual_dots)
        self.show_virtual = True
        self.targets: dict[tuple[str, int], ElementItem] = {}
        self.labels: list[tuple[pg.TextItem, tuple[float, float], int]] = []
        self.names: dict[tuple[str, int], str] = {}
        self.snap_step_mm: float | None = 2.5
        self.snap_origin_mm: tuple[float, float] = (0.0, 0.0)
        self._quiet = False
        self._ranged = False
        plot.vb.sigRangeChanged.connect(lambda *_: self._place_labels())

    def set_elements(self, tx: list[tuple[str, tuple[float, float]]],
                     rx: list[tuple[str, tuple[float, float]]], *, grid_mm: float,
                     grid_origin_mm: tuple[float, float] = (0.0, 0.0)) -> None:
        """Show Tx and Rx elements (name, position) and a grid around them."""
        plot = self.getPlotItem()
        wanted = [("tx", i, n or f"tx{i + 1}", p) for i, (n, p) in enumerate(tx)] + [
            ("rx", i, n or f"rx{i + 1}", p) for i, (n, p) in enumerate(rx)]
        keys = {(role, i) for role, i, _, _ in wanted}
        for key in list(self.targets):
            if key not in keys:
                plot.removeItem(self.targets.pop(key))
        self._quiet = True
        try:
            for role, i, name, pos in wanted:
                self.names[(role, i)] = name
                target = self.targets.get((role, i))
                if target is None:
                    target = self._make_target(role, i, pos)
                    plot.addItem(target)
                    self.targets[(role, i)] = target
                elif not target.moving:
                    target.setPos(QPointF(*pos))
        finally:
            self._quiet = False
        self._make_labels([(role, i, name, p) for role, i, name, p in wanted])
        virtual = virtual_positions_mm(np.array([p for _, p in tx]), np.array([p for _, p in rx]))
        self.virtual_dots.setData(pos=virtual if self.show_virtual else np.zeros((0, 2)))
        self._draw_grid([p for *_, p in wanted], grid_mm, grid_origin_mm)

    def _make_target(self, role: str, index: int, pos: tuple[float, float]) -> ElementItem:
        colour = TX_COLOUR if role == "tx" else RX_COLOUR
        target = ElementItem(
            role, index, self._restack, pos=pos, size=TX_SIZE if role == "tx" else RX_SIZE,
            symbol="s" if role == "tx" else "o", pen=pg.mkPen("#ffffff", width=1),
            brush=pg.mkBrush(colour), hoverBrush=pg.mkBrush("#ffffff"), movable=True)
        # Rx (small) above Tx (large): the Tx's corners stay exposed.
        target.setZValue(20 if role == "rx" else 10)
        target.sigPositionChanged.connect(
            lambda t, r=role, k=index: self._on_moved(r, k, t, finished=False))
        target.sigPositionChangeFinished.connect(
            lambda t, r=role, k=index: self._on_moved(r, k, t, finished=True))
        return target

    def stacked_with(self, target: ElementItem) -> list[ElementItem]:
        """Targets at the same spot as ``target`` (itself included)."""
        p = target.pos()
        return [t for t in self.targets.values()
                if abs(t.pos().x() - p.x()) < SAME_SPOT_MM and abs(t.pos().y() - p.y())
                < SAME_SPOT_MM]

    def _restack(self, target: ElementItem) -> None:
        """Send the clicked element below the others at its spot (pick cycling)."""
        stack = self.stacked_with(target)
        if len(stack) > 1:
            target.setZValue(min(t.zValue() for t in stack) - 1)

    def top_element_at(self, position_mm: tuple[float, float]) -> tuple[str, int] | None:
        """The element a press at ``position_mm`` would grab: the top one there."""
        hit = [t for t in self.targets.values()
               if abs(t.pos().x() - position_mm[0]) < SAME_SPOT_MM
               and abs(t.pos().y() - position_mm[1]) < SAME_SPOT_MM]
        if not hit:
            return None
        top = max(hit, key=lambda t: t.zValue())
        return top.role, top.index

    # --- labels -------------------------------------------------------------------------
    def _make_labels(self, wanted: list[tuple[str, int, str, tuple[float, float]]]) -> None:
        """One label per spot; the existing text items are re-used (an edit moves them)."""
        plot = self.getPlotItem()
        spare = [item for item, _, _ in self.labels]
        self.labels = []
        spots: dict[tuple[float, float], list[tuple[str, str]]] = {}
        for role, _i, name, pos in wanted:
            key = (round(pos[0] / SAME_SPOT_MM) * SAME_SPOT_MM,
                   round(pos[1] / SAME_SPOT_MM) * SAME_SPOT_MM)
            spots.setdefault(key, []).append((role, name))
        for pos, members in spots.items():
            text = " · ".join(
                f'<span style="color:{TX_COLOUR if r == "tx" else RX_COLOUR}">'
                f"{html.escape(n)}</span>" for r, n in sorted(members))
            markup = f'<span style="font-size:8pt">{text}</span>'
            if spare:
                item = spare.pop(0)
                if item.property("markup") != markup:
                    item.setHtml(markup)
            else:
                item = pg.TextItem(html=markup, anchor=(0.5, 1.0))
                item.setZValue(30)
                item.setAcceptedMouseButtons(Qt.MouseButton.NoButton)
                plot.addItem(item)
            item.setProperty("markup", markup)
            self.labels.append((item, pos, 1))
        for item in spare:
            plot.removeItem(item)
        self._place_labels()

    def label_texts(self) -> list[str]:
        """Plain text of every label (one per spot)."""
        return [item.textItem.toPlainText() for item, _, _ in self.labels]

    def _place_labels(self) -> None:
        """Put labels above their spot; crowded neighbours in a row alternate below."""
        if not self.labels:
            return
        px = self.getPlotItem().vb.viewPixelSize()
        px_x = px[0] if px[0] > 0 else 1.0
        px_y = px[1] if px[1] > 0 else 1.0
        order = sorted(range(len(self.labels)),
                       key=lambda k: (self.labels[k][1][1], self.labels[k][1][0]))
        below = False
        previous: tuple[float, float] | None = None
        for k in order:
            item, pos, _ = self.labels[k]
            same_row = previous is not None and abs(previous[1] - pos[1]) < SAME_SPOT_MM
            crowded = same_row and abs(pos[0] - previous[0]) / px_x < CROWDED_PX  # type: ignore[index]
            below = (not below) if crowded else False
            offset = (0.5 * TX_SIZE + 1) * px_y
            if below:
                item.setAnchor((0.5, 0.0))
                item.setPos(pos[0], pos[1] + offset)  # y points down on the board
            else:
                item.setAnchor((0.5, 1.0))
                item.setPos(pos[0], pos[1] - offset)
            self.labels[k] = (item, pos, -1 if below else 1)
            previous = pos

    # --- grid and dragging --------------------------------------------------------------
    def _draw_grid(self, points: list[tuple[float, float]], step: float,
                   origin: tuple[float, float]) -> None:
        pts = np.array(points, dtype=float).reshape(-1, 2)
        o = np.asarray(origin, dtype=float)
        lo = o + np.floor((pts.min(axis=0) - 3 * step - o) / step) * step
        hi = o + np.ceil((pts.max(axis=0) + 3 * step - o) / step) * step
        xs = np.arange(lo[0], hi[0] + step / 2, step)
        ys = np.arange(lo[1], hi[1] + step / 2, step)
        x = np.concatenate([np.repeat(xs, 2), np.tile([lo[0], hi[0]], len(ys))])
        y = np.concatenate([np.tile([lo[1], hi[1]], len(xs)), np.repeat(ys, 2)])
        self.grid_lines.setData(x, y)
        if not self._ranged:
            span = max(float(np.ptp(pts[:, 0])), float(np.ptp(pts[:, 1])), step)
            centre = 0.5 * (pts.min(axis=0) + pts.max(axis=0))
            half = 0.5 * span + 1.5 * step
            self.getPlotItem().setRange(xRange=(centre[0] - half, centre[0] + half),
                                        yRange=(centre[1] - half, centre[1] + half),
                                        padding=0.0)
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
            pos = snap_to_grid(pos, self.snap_step_mm, self.snap_origin_mm)
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
    """Board view, array analysis, snapping, warnings, layout presets, add/remove buttons."""

    editFailed = pyqtSignal(str)

    def __init__(self, document: ProjectDocument, parent: QWidget | None = None):
        super().__init__(parent)
        self.document = document
        self._key: tuple | None = None
        layout = QHBoxLayout(self)
        layout.setContentsMargins(2, 2, 2, 2)
        self.splitter = QSplitter(Qt.Orientation.Horizontal)
        self.board = AntennaBoardView()
        self.board.elementDragged.connect(self.move_element)
        # Readable on a small screen: the board never narrower than BOARD_MIN_WIDTH (the
        # dock scrolls instead), the numeric table beside it (issue #34).
        self.board.setMinimumWidth(BOARD_MIN_WIDTH)
        self.table = AntennaTable(document)
        self.table.editFailed.connect(self.editFailed)
        self.analysis = ArrayAnalysisView(document)
        # The table and the snap / preset controls share the column beside the board.
        self.side_splitter = QSplitter(Qt.Orientation.Vertical)
        self.side_splitter.addWidget(self.table)
        self.side_splitter.addWidget(self._build_side())
        self.side_splitter.setChildrenCollapsible(False)
        self.side_splitter.setStretchFactor(0, 3)
        self.side_splitter.setStretchFactor(1, 2)
        self.side_splitter.setSizes([3 * 10_000, 2 * 10_000])  # 3 : 2 from the start
        self.splitter.addWidget(self.board)
        self.splitter.addWidget(self.side_splitter)
        self.splitter.addWidget(self.analysis)
        for k, stretch in enumerate((3, 1, 4)):
            self.splitter.setStretchFactor(k, stretch)
        self.splitter.setChildrenCollapsible(False)
        layout.addWidget(self.splitter)
        document.projectChanged.connect(self.refresh)
        document.currentSensorChanged.connect(self.refresh)
        document.projectReplaced.connect(self._refit)
        self.refresh()

    def _build_side(self) -> QWidget:
        side_widget = QWidget()
        side = QVBoxLayout(side_widget)
        side.setContentsMargins(2, 0, 2, 0)
        self._build_view_options(side)
        side.addWidget(self._build_presets())
        side.addLayout(self._build_element_buttons())
        side.addStretch(1)
        scroll = QScrollArea()
        scroll.setWidgetResizable(True)
        scroll.setWidget(side_widget)
        scroll.setHorizontalScrollBarPolicy(Qt.ScrollBarPolicy.ScrollBarAlwaysOff)
        for combo in (self.snap_mode, self.layout_combo):
            combo.setSizeAdjustPolicy(
                QComboBox.SizeAdjustPolicy.AdjustToMinimumContentsLengthWithIcon)
            combo.setMinimumContentsLength(8)
        self.side_widget = side_widget
        scroll.setMinimumWidth(side_widget.minimumSizeHint().width()
                               + scroll.verticalScrollBar().sizeHint().width() + 4)
        return scroll

    def _build_view_options(self, side: QVBoxLayout) -> None:
        """Snap mode, the virtual-array switch, and the info, warning and note lines."""
        row = QHBoxLayout()
        row.addWidget(QLabel("snap"))
        self.snap_mode = QComboBox()
        self.snap_mode.addItems(list(SNAP_MODES))
        self.snap_mode.setToolTip(
            "Round dragged positions to a grid through the first Rx: the current array pitch "
            "(smallest spacing between elements, so a preset's spacing survives a drag), λ/2 "
            "at the chirp's centre or start frequency, or no snapping")
        self.snap_mode.currentIndexChanged.connect(lambda _i: self.refresh())
        row.addWidget(self.snap_mode, 1)
        side.addLayout(row)
        self.virtual_check = QCheckBox("show the virtual array")
        self.virtual_check.setChecked(True)
        self.virtual_check.setToolTip("Yellow diamonds on the board: one virtual element at "
                                      "p_tx + p_rx per Tx/Rx pair (TDM-MIMO)")
        self.virtual_check.toggled.connect(self._toggle_virtual)
        side.addWidget(self.virtual_check)
        self.info = QLabel("")
        self.info.setStyleSheet("color: #9aa4ae;")
        self.info.setWordWrap(True)
        side.addWidget(self.info)
        self.warnings = QLabel("")
        self.warnings.setStyleSheet("color: #ff6e6e;")
        self.warnings.setWordWrap(True)
        self.warnings.setToolTip("Problems of the antenna layout, updated while you drag")
        side.addWidget(self.warnings)
        self.notes = QLabel("")
        self.notes.setStyleSheet("color: #ffd54a;")
        self.notes.setWordWrap(True)
        self.notes.setToolTip("Elements drawn at one spot: all of them can still be picked")
        side.addWidget(self.notes)

    def _build_presets(self) -> QGroupBox:
        """The layout preset box: layout, element count, URA grid, spacing, Apply."""
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
        self.nx_spin = int_spin(minimum=1, maximum=16,
                                tooltip="URA columns × rows (uniform rectangular array)")
        self.nx_spin.setValue(2)
        self.ny_spin = int_spin(minimum=1, maximum=16, tooltip="URA rows")
        self.ny_spin.setValue(2)
        grid = QHBoxLayout()
        grid.addWidget(self.nx_spin)
        grid.addWidget(QLabel("×"))
        grid.addWidget(self.ny_spin)
        form.addRow("URA", grid)
        self.spacing = spin(minimum=0.05, maximum=8.0, decimals=2, step=0.25, suffix="λ",
                            tooltip="element spacing in wavelengths at the chirp's centre "
                                    "frequency (0.5 = λ/2)")
        self.spacing.setValue(0.5)
        form.addRow("spacing", self.spacing)
        apply = QPushButton("Apply layout")
        apply.setToolTip("Replace the Rx elements (and for MIMO the Tx) by this layout")
        apply.clicked.connect(lambda: self.apply_layout(self.layout_combo.currentText()))
        form.addRow(apply)
        return presets

    def _build_element_buttons(self) -> QGridLayout:
        """+ Rx, − Rx, + Tx, − Tx."""
        buttons = QGridLayout()
        self.add_rx_button = QPushButton("+ Rx")
        self.add_rx_button.setToolTip("Add a receive element one pitch right of the longest "
                                      "Rx row")
        self.add_rx_button.clicked.connect(lambda: self.add_element("rx"))
        self.add_tx_button = QPushButton("+ Tx")
        self.add_tx_button.setToolTip("Add a transmit element (TDM-MIMO) continuing the Tx "
                                      "row, spaced so the virtual array extends without gaps")
        self.add_tx_button.clicked.connect(lambda: self.add_element("tx"))
        self.remove_rx_button = QPushButton("− Rx")
        self.remove_rx_button.clicked.connect(lambda: self.remove_element("rx"))
        self.remove_tx_button = QPushButton("− Tx")
        self.remove_tx_button.clicked.connect(lambda: self.remove_element("tx"))
        for k, b in enumerate((self.add_rx_button, self.remove_rx_button, self.add_tx_button,
                               self.remove_tx_button)):
            buttons.addWidget(b, k // 2, k % 2)
        return buttons

    def _refit(self) -> None:
        """A new project: fit the board to it on the next refresh."""
        self.board.reset_range()
        self._key = None

    def _toggle_virtual(self, on: bool) -> None:  # noqa: FBT001 - Qt slot
        self.board.show_virtual = on
        self.refresh()

    def snap_step(self, radar: RadarConfig) -> float | None:
        """Grid step (mm) of the chosen snap mode, or None (off)."""
        mode = SNAP_MODES[self.snap_mode.currentText()]
        if mode == "off":
            return None
        if mode == "centre":
            return half_wavelength_mm(radar)
        if mode == "start":
            return half_wavelength_start_mm(radar)
        return self.pitch_mm(radar)

    @staticmethod
    def pitch_mm(radar: RadarConfig) -> float:
        """The current array pitch (mm); λ/2 at the centre frequency when there is none."""
        pts = np.array([a.position_mm for a in [*radar.tx, *radar.rx]], dtype=np.float64)
        return array_pitch_mm(pts, fallback_mm=half_wavelength_mm(radar))

    def refresh(self, *_: object) -> None:
        """Show the project's antennas, the snap grid and the layout's warnings."""
        if not has_kind(self.document.project, "radar"):
            self.setEnabled(False)  # a ToF-only project: nothing to edit here
            self._key = None
            return
        self.setEnabled(True)
        radar = current_radar(self.document)
        key = (radar.tx, radar.rx, radar.start_frequency_hz, radar.bandwidth_hz,
               radar.render_fov_h_deg, radar.render_width, radar.render_height,
               self.snap_mode.currentText(), self.board.show_virtual)
        if key == self._key:
            return  # an edit elsewhere (objects, materials): the board is up to date
        self._key = key
        half = half_wavelength_mm(radar)
        step = self.snap_step(radar)
        origin = (float(radar.rx[0].position_mm[0]), float(radar.rx[0].position_mm[1]))
        self.board.snap_step_mm = step
        self.board.snap_origin_mm = origin
        count = (len(radar.tx), len(radar.rx))
        if count != getattr(self, "_count", None):
            self.board.reset_range()  # a new layout: fit the view to it
            self._count = count
        self.board.set_elements([(a.name, a.position_mm) for a in radar.tx],
                                [(a.name, a.position_mm) for a in radar.rx],
                                grid_mm=step or self.pitch_mm(radar), grid_origin_mm=origin)
        f_c = radar.start_frequency_hz + 0.5 * radar.bandwidth_hz
        grid = (f"grid {step:.3f} mm ({self.snap_mode.currentText()}; "
                f"{step / (2 * half):.3f} λ)" if step else "no snapping")
        self.info.setText(
            f"{grid}\nλ/2 = {half:.3f} mm at the centre frequency {f_c / 1e9:.2f} GHz\n"
            f"{len(radar.tx)} Tx, {len(radar.rx)} Rx, {radar.n_channels} virtual channels")
        self.warnings.setText("\n".join(f"⚠ {w}" for w in aliasing_warnings(radar)))
        self.notes.setText("\n".join(self.shared_spots(radar)))
        self.warnings.setVisible(bool(self.warnings.text()))
        self.notes.setVisible(bool(self.notes.text()))
        self.remove_tx_button.setEnabled(len(radar.tx) > 1)
        self.remove_rx_button.setEnabled(len(radar.rx) > 1)
        self.remove_tx_button.setToolTip("Remove the last transmit element" if len(radar.tx) > 1
                                         else "A radar needs at least one Tx")
        self.remove_rx_button.setToolTip("Remove the last receive element" if len(radar.rx) > 1
                                         else "A radar needs at least one Rx")

    @staticmethod
    def shared_spots(radar: RadarConfig) -> list[str]:
        """One note per board spot that holds more than one element."""
        out = []
        spots: dict[tuple[float, float], list[str]] = {}
        for role, items in (("tx", radar.tx), ("rx", radar.rx)):
            for i, a in enumerate(items):
                key = (round(a.position_mm[0], 3), round(a.position_mm[1], 3))
                spots.setdefault(key, []).append(a.name or f"{role}{i + 1}")
        for (x, y), names in spots.items():
            if len(names) > 1:
                out.append(f"{', '.join(names)} share ({x:g}, {y:g}) mm (a click there "
                           "cycles which is on top)")
        return out

    def move_element(self, role: str, index: int, position_mm: tuple[float, float],
                     finished: bool = False) -> None:  # noqa: FBT001, FBT002 - Qt slot
        """Move Tx/Rx ``index`` to ``position_mm`` (the board view's drag path)."""
        try:
            name = current_radar(self.document).model_dump()[role][index]["name"]
            self.document.set_value(f"{current_radar_path(self.document)}.{role}[{index}].position_mm",
                                    (float(position_mm[0]), float(position_mm[1])),
                                    text=f"Move antenna {name or role}",
                                    merge_key=f"antenna:{role}{index}")
        except EditError as exc:
            self.editFailed.emit(str(exc))
        if finished:
            self.document.end_merge()

    def apply_layout(self, name: str) -> None:
        """Replace the Rx (and for MIMO the Tx) positions by a layout preset."""
        radar = current_radar(self.document)
        d = self.spacing.value() * radar.wavelength_m * 1e3
        tx, rx = layout_positions(name, n=self.n_spin.value(), nx=self.nx_spin.value(),
                                  ny=self.ny_spin.value(), spacing_mm=d)

        def mutate(data: dict[str, Any]) -> None:
            r = fieldpath.get(data, current_radar_path(self.document))
            r["rx"] = [{"name": f"rx{i + 1}", "position_mm": tuple(p)} for i, p in enumerate(rx)]
            if tx is not None:
                r["tx"] = [{"name": f"tx{i + 1}", "position_mm": tuple(p)}
                           for i, p in enumerate(tx)]

        try:
            self.document.edit(f"Antenna layout {name}", mutate)
        except EditError as exc:
            self.editFailed.emit(str(exc))
        self._refit()
        self.refresh()

    def add_element(self, role: str) -> None:
        """Append a Tx or Rx element where :func:`next_element_position` puts it."""
        radar = current_radar(self.document)
        items = radar.tx if role == "tx" else radar.rx
        x, y = next_element_position(radar, role, self.pitch_mm(radar))
        names = {a.name for a in items}
        i = len(items) + 1
        while f"{role}{i}" in names:
            i += 1

        def mutate(data: dict[str, Any]) -> None:
            radar = fieldpath.get(data, current_radar_path(self.document))
            radar[role].append({"name": f"{role}{i}", "position_mm": (x, y)})

        try:
            self.document.edit(f"Add {role}", mutate)
        except EditError as exc:
            self.editFailed.emit(str(exc))

    def remove_element(self, role: str) -> None:
        """Remove the last Tx or Rx element (at least one of each stays)."""
        items = getattr(current_radar(self.document), role)
        if len(items) <= 1:
            self.editFailed.emit(f"a radar needs at least one {role.capitalize()}: "
                                 f"{items[0].name or role} stays")
            return
        try:
            path = current_radar_path(self.document)
            self.document.edit(f"Remove {role}", lambda d: fieldpath.get(d, path)[role].pop())
        except EditError as exc:
            self.editFailed.emit(str(exc))
