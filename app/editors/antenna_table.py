"""The antenna editor's numeric table: name, board x and y in millimetres, element pattern.

One row per element (Tx first, then Rx). A committed cell is one edit of the project — one
undo step named in the user's words ("Set x of rx2 to 1.25 mm") — so the board and the
table always show the same project. A cell that cannot be read, or a value the model
refuses, is not committed: the table gets the field's red frame with the reason under it
(:func:`app.widgets.inputs.show_field_error`, as every editor of the GUI) and the cell keeps what
was typed, marked red, for the user to correct.

The pattern column reads ``default`` (the configuration's element pattern), ``cos A×B``
(a cosine-power pattern, azimuth × elevation exponents; ``cos A`` for both) or, for a
tabulated pattern loaded from a project file, ``table E×A`` (shown, not editable here).
"""

from __future__ import annotations

import re
from typing import Any

from PyQt6.QtCore import QSignalBlocker, QSize, Qt, pyqtSignal
from PyQt6.QtGui import QBrush, QColor
from PyQt6.QtWidgets import (
    QAbstractItemView,
    QHeaderView,
    QTableWidget,
    QTableWidgetItem,
    QVBoxLayout,
    QWidget,
)

from app.document.document import EditError, ProjectDocument
from app.document.sensors import current_radar, current_radar_path, has_kind
from app.widgets.inputs import clear_field_error, show_field_error
from simcore.scene import fieldpath
from simcore.scene.radar_config import CosinePattern, RadarConfig

#: Columns of the table.
COLUMNS = ("element", "x (mm)", "y (mm)", "pattern")
NAME, X, Y, PATTERN = range(4)
_ERROR_BRUSH = QBrush(QColor("#5a1f24"))
_COS = re.compile(r"^\s*cos\s*([0-9.eE+-]+)\s*(?:[×x*]\s*([0-9.eE+-]+))?\s*$")


def pattern_text(pattern: Any) -> str:
    """How the pattern column shows an element's pattern (None: the configuration's)."""
    if pattern is None:
        return "default"
    if isinstance(pattern, CosinePattern):
        if pattern.exponent_az == pattern.exponent_el:
            return f"cos {pattern.exponent_az:g}"
        return f"cos {pattern.exponent_az:g}×{pattern.exponent_el:g}"
    return f"table {len(pattern.elevation_deg)}×{len(pattern.azimuth_deg)}"


def parse_pattern(text: str) -> dict[str, Any] | None:
    """Read a pattern cell: ``default`` → None, ``cos A[×B]`` → a cosine pattern's fields.

    Raises
    ------
    ValueError
        The text is neither (the message says what is accepted).
    """
    if text.strip().lower() in ("", "default"):
        return None
    m = _COS.match(text)
    if m is None:
        raise ValueError(f"pattern: type 'default' or 'cos A×B' (cosine exponents, azimuth × "
                         f"elevation; got {text.strip()!r})")
    az = float(m.group(1))
    el = float(m.group(2)) if m.group(2) is not None else az
    return {"kind": "cosine", "exponent_az": az, "exponent_el": el}


def parse_mm(text: str, *, what: str) -> float:
    """A millimetre cell as a float (an ``mm`` suffix is allowed)."""
    cleaned = text.strip().removesuffix("mm").strip().replace("−", "-")
    try:
        value = float(cleaned)
    except ValueError:
        raise ValueError(f"{what}: type a number of millimetres (got {text.strip()!r})"
                         ) from None
    if value != value or value in (float("inf"), float("-inf")):
        raise ValueError(f"{what}: type a finite number of millimetres (got {text.strip()!r})")
    return value


class AntennaTable(QWidget):
    """Numeric table of the radar's elements, bound to the document's project.

    Signals
    -------
    editFailed(str)
        An edit was refused (the reason is also shown under the table).
    """

    editFailed = pyqtSignal(str)

    def __init__(self, document: ProjectDocument, parent: QWidget | None = None):
        super().__init__(parent)
        self.document = document
        layout = QVBoxLayout(self)
        layout.setContentsMargins(0, 0, 0, 0)
        layout.setSpacing(2)
        self.table = QTableWidget(0, len(COLUMNS))
        self.table.setObjectName("antennaTable")
        self.table.setHorizontalHeaderLabels(list(COLUMNS))
        self.table.verticalHeader().setVisible(False)
        self.table.verticalHeader().setDefaultSectionSize(22)
        self.table.setMinimumHeight(80)
        header = self.table.horizontalHeader()
        for col in range(len(COLUMNS)):
            header.setSectionResizeMode(col, QHeaderView.ResizeMode.ResizeToContents)
        header.setStretchLastSection(True)
        self.table.setEditTriggers(QAbstractItemView.EditTrigger.DoubleClicked
                                   | QAbstractItemView.EditTrigger.EditKeyPressed
                                   | QAbstractItemView.EditTrigger.AnyKeyPressed)
        self.table.setToolTip(
            "Every element of the radar board: Tx (red) then Rx (blue). Double-click or type "
            "to edit: name, board x and y in mm (x right, y down), pattern 'default' (the "
            "configuration's element pattern) or 'cos A×B' (cosine-power exponents, azimuth "
            "× elevation). Each edit is one undo step; the board follows.")
        self.table.setMinimumWidth(200)
        self.table.itemChanged.connect(self._on_item_changed)
        layout.addWidget(self.table, 1)
        self.rows: list[tuple[str, int]] = []
        document.projectChanged.connect(self.refresh)
        document.currentSensorChanged.connect(self.refresh)
        self.refresh()

    def sizeHint(self) -> QSize:  # noqa: N802, D102 - Qt API
        # As wide as the columns need: the board and the beam pattern share the rest.
        return QSize(self.table.minimumWidth(), super().sizeHint().height())

    def showEvent(self, event: Any) -> None:  # noqa: N802, D102 - Qt API
        super().showEvent(event)
        self._fit_width()  # the theme's font is known now

    # --- showing ------------------------------------------------------------------------
    def refresh(self, *_: object) -> None:
        """Show the project's elements (a cell being edited is left alone)."""
        if not has_kind(self.document.project, "radar"):
            self.setEnabled(False)  # a ToF-only project: nothing to edit here
            return
        self.setEnabled(True)
        radar = current_radar(self.document)
        rows = [("tx", i) for i in range(len(radar.tx))] + [("rx", i) for i in range(len(radar.rx))]
        with QSignalBlocker(self.table):
            if self.table.rowCount() != len(rows):
                self.table.setRowCount(len(rows))
            self.rows = rows
            for r, (role, i) in enumerate(rows):
                a = getattr(radar, role)[i]
                colour = QColor("#ff6e6e" if role == "tx" else "#4fc3f7")
                values = (a.name or f"{role}{i + 1}", f"{a.position_mm[0]:g}",
                          f"{a.position_mm[1]:g}", pattern_text(a.pattern))
                for col, text in enumerate(values):
                    item = self.table.item(r, col)
                    if item is None:
                        item = QTableWidgetItem()
                        self.table.setItem(r, col, item)
                    item.setText(text)
                    item.setData(Qt.ItemDataRole.BackgroundRole, None)
                    if col == NAME:
                        item.setForeground(colour)
                        item.setToolTip(f"{'transmit' if role == 'tx' else 'receive'} element")
                    flags = item.flags() | Qt.ItemFlag.ItemIsEditable
                    if col == PATTERN and text.startswith("table"):
                        flags &= ~Qt.ItemFlag.ItemIsEditable
                        item.setToolTip("a tabulated pattern from the project file "
                                        "(edit it there)")
                    item.setFlags(flags)
        clear_field_error(self.table)
        self._fit_width()

    def _fit_width(self) -> None:
        """Wide enough for every column at its content's width: no column is clipped."""
        header = self.table.horizontalHeader()
        width = sum(max(header.sectionSizeHint(c), self.table.sizeHintForColumn(c))
                    for c in range(len(COLUMNS)))
        width += 2 * self.table.frameWidth() + self.table.verticalScrollBar().sizeHint().width()
        self.table.setMinimumWidth(max(200, width + 32))

    def element_rows(self) -> list[tuple[str, str, str, str]]:
        """The table's text, row by row (name, x, y, pattern)."""
        return [tuple(self.table.item(r, c).text() for c in range(len(COLUMNS)))  # type: ignore[misc]
                for r in range(self.table.rowCount())]

    def row_of(self, role: str, index: int) -> int:
        """Table row of Tx/Rx ``index``."""
        return self.rows.index((role, index))

    # --- editing ------------------------------------------------------------------------
    def set_cell(self, role: str, index: int, column: int, text: str) -> None:
        """Type ``text`` into a cell and commit it (what the user does; used by tests)."""
        self.table.item(self.row_of(role, index), column).setText(text)

    def _on_item_changed(self, item: QTableWidgetItem) -> None:
        row, col = item.row(), item.column()
        if row >= len(self.rows):
            return
        role, index = self.rows[row]
        radar = current_radar(self.document)
        element = getattr(radar, role)[index]
        name = element.name or f"{role}{index + 1}"
        try:
            self._commit(radar, role, index, name, col, item.text())
        except (EditError, ValueError) as exc:
            self._refuse(item, str(exc))
            return
        clear_field_error(self.table)

    def _commit(self, radar: RadarConfig, role: str, index: int, name: str, col: int,
                text: str) -> None:
        path = f"{current_radar_path(self.document)}.{role}[{index}]"
        element = getattr(radar, role)[index]
        if col == NAME:
            new = text.strip()
            if new == element.name:
                return
            self.document.set_value(f"{path}.name", new, text=f"Rename {name} to {new}")
        elif col in (X, Y):
            axis = "x" if col == X else "y"
            value = parse_mm(text, what=f"{name} {axis}")
            old = element.position_mm
            pos = (value, old[1]) if col == X else (old[0], value)
            if pos == tuple(old):
                self.refresh()  # "1.50" typed for 1.5: show the project's value again
                return
            self.document.set_value(f"{path}.position_mm", pos,
                                    text=f"Set {axis} of {name} to {value:g} mm")
        else:
            pattern = parse_pattern(text)
            shown = pattern_text(element.pattern)
            if text.strip() == shown:
                return

            def mutate(d: dict[str, Any]) -> None:
                radar = fieldpath.get(d, current_radar_path(self.document))
                radar[role][index]["pattern"] = pattern

            words = "default" if pattern is None else text.strip()
            self.document.edit(f"Set pattern of {name} to {words}", mutate)

    def _refuse(self, item: QTableWidgetItem, message: str) -> None:
        """Keep the typed text in its cell, marked red; the reason under the table."""
        with QSignalBlocker(self.table):
            item.setBackground(_ERROR_BRUSH)
        show_field_error(self.table, message)
        self.editFailed.emit(message)


__all__ = ["COLUMNS", "AntennaTable", "parse_mm", "parse_pattern", "pattern_text"]
