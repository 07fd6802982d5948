"""A row of columns that wraps into a stack when the dock is too narrow to show them all.

Issue #34: at small window sizes an editor's right-hand column (the Sensors tab's derived
quantities, the Materials tab's Visible band) was cut off at the dock's edge. A
:class:`WrapRow` lays its columns side by side while they fit at their minimum widths,
and one under the other otherwise, so every column stays whole and the dock scrolls
vertically instead of hiding a column past its right edge.
"""

from __future__ import annotations

from typing import Any

from PyQt6.QtCore import QSize
from PyQt6.QtWidgets import QBoxLayout, QWidget


class WrapRow(QWidget):
    """Columns side by side when they fit, stacked when they do not."""

    def __init__(self, parent: QWidget | None = None, *, spacing: int = 6):
        super().__init__(parent)
        self.box = QBoxLayout(QBoxLayout.Direction.LeftToRight, self)
        self.box.setContentsMargins(0, 0, 0, 0)
        self.box.setSpacing(spacing)
        self.columns: list[QWidget] = []

    def add(self, widget: QWidget, stretch: int = 1) -> None:
        """Append a column."""
        self.box.addWidget(widget, stretch)
        self.columns.append(widget)

    def side_by_side_width(self) -> int:
        """The width the columns need side by side (px)."""
        widths = [max(w.minimumSizeHint().width(), w.minimumWidth()) for w in self.columns]
        return sum(widths) + self.box.spacing() * max(0, len(widths) - 1)

    @property
    def stacked(self) -> bool:
        """Whether the columns are shown one under the other."""
        return self.box.direction() == QBoxLayout.Direction.TopToBottom

    def minimumSizeHint(self) -> QSize:  # noqa: N802, D102 - Qt API
        # Narrower than the row: the columns then stack (resizeEvent).
        widths = [max(w.minimumSizeHint().width(), w.minimumWidth()) for w in self.columns]
        return QSize(max(widths, default=0), super().minimumSizeHint().height())

    def resizeEvent(self, event: Any) -> None:  # noqa: N802, D102 - Qt API
        want = (QBoxLayout.Direction.TopToBottom
                if event.size().width() < self.side_by_side_width()
                else QBoxLayout.Direction.LeftToRight)
        if want != self.box.direction():
            self.box.setDirection(want)
            self.updateGeometry()
        super().resizeEvent(event)


__all__ = ["WrapRow"]
