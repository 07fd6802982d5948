"""A row of columns that wraps onto more rows when the dock is too narrow to show them all.

Issue #34: at small window sizes an editor's right-hand column (the Sensors tab's derived
quantities, the Materials tab's Visible band) was cut off at the dock's edge. A
:class:`WrapRow` lays its columns side by side as far as they fit at their minimum widths
and wraps the rest onto the next rows, like words in a line, so every column stays whole
and the dock scrolls vertically instead of hiding a column past its right edge.
"""

from __future__ import annotations

from typing import Any

from PyQt6.QtCore import QSize
from PyQt6.QtWidgets import QGridLayout, QWidget


class WrapRow(QWidget):
    """Columns side by side while they fit; the rest wrap onto further rows."""

    def __init__(self, parent: QWidget | None = None, *, spacing: int = 6):
        super().__init__(parent)
        self.box = QGridLayout(self)
        self.box.setContentsMargins(0, 0, 0, 0)
        self.box.setSpacing(spacing)
        self.columns: list[QWidget] = []
        self._stretch: list[int] = []
        self.per_row = 0

    def add(self, widget: QWidget, stretch: int = 1) -> None:
        """Append a column."""
        self.columns.append(widget)
        self._stretch.append(stretch)
        self._arrange(len(self.columns))

    def _widths(self) -> list[int]:
        return [max(w.minimumSizeHint().width(), w.minimumWidth()) for w in self.columns]

    def side_by_side_width(self) -> int:
        """The width the columns need all in one row (px)."""
        widths = self._widths()
        return sum(widths) + self.box.spacing() * max(0, len(widths) - 1)

    def fitting(self, width: int) -> int:
        """How many columns fit side by side in ``width`` px (at least one)."""
        used, n = 0, 0
        for w in self._widths():
            used += w + (self.box.spacing() if n else 0)
            if used > width and n:
                break
            n += 1
        return max(1, n)

    @property
    def stacked(self) -> bool:
        """Whether some columns are wrapped onto a further row."""
        return self.per_row < len(self.columns)

    def _arrange(self, per_row: int) -> None:
        if per_row == self.per_row:
            return
        for w in self.columns:
            self.box.removeWidget(w)
        for c in range(max(self.per_row, per_row, len(self.columns))):
            self.box.setColumnStretch(c, 0)
        self.per_row = per_row
        for k, w in enumerate(self.columns):
            self.box.addWidget(w, k // per_row, k % per_row)
        for c in range(per_row):
            self.box.setColumnStretch(c, self._stretch[c] if c < len(self._stretch) else 1)
        self.updateGeometry()

    def minimumSizeHint(self) -> QSize:  # noqa: N802, D102 - Qt API
        # As narrow as the widest column: the others then wrap (resizeEvent).
        return QSize(max(self._widths(), default=0), super().minimumSizeHint().height())

    def resizeEvent(self, event: Any) -> None:  # noqa: N802, D102 - Qt API
        self._arrange(self.fitting(event.size().width()))
        super().resizeEvent(event)


__all__ = ["WrapRow"]
