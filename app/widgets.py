"""Small input widgets with units: spin boxes, 2-/3-vectors, and an edit helper."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any

from PyQt6.QtCore import QSignalBlocker, pyqtSignal
from PyQt6.QtWidgets import QDoubleSpinBox, QHBoxLayout, QSpinBox, QWidget

from app.document import EditError

BIG = 1e9


def spin(*, minimum: float = -BIG, maximum: float = BIG, decimals: int = 3, step: float = 0.1,
         suffix: str = "", tooltip: str = "") -> QDoubleSpinBox:
    """A double spin box that reports values only when committed (Enter, focus out, arrows)."""
    box = QDoubleSpinBox()
    box.setRange(minimum, maximum)
    box.setDecimals(decimals)
    box.setSingleStep(step)
    box.setKeyboardTracking(False)
    box.setAccelerated(True)
    if suffix:
        box.setSuffix(f" {suffix}")
    if tooltip:
        box.setToolTip(tooltip)
    box.setMinimumWidth(70)
    return box


def int_spin(*, minimum: int = 0, maximum: int = 1_000_000, suffix: str = "",
             tooltip: str = "") -> QSpinBox:
    """An integer spin box that reports values only when committed."""
    box = QSpinBox()
    box.setRange(minimum, maximum)
    box.setKeyboardTracking(False)
    if suffix:
        box.setSuffix(f" {suffix}")
    if tooltip:
        box.setToolTip(tooltip)
    return box


def set_quietly(widget: Any, value: Any) -> None:
    """Set a widget's value without emitting its change signals."""
    with QSignalBlocker(widget):
        if hasattr(widget, "setValue"):
            widget.setValue(value)
        elif hasattr(widget, "setChecked"):
            widget.setChecked(bool(value))
        elif hasattr(widget, "setText"):
            widget.setText(str(value))


class VectorEdit(QWidget):
    """Two or three spin boxes edited as one vector; emits ``edited(tuple)`` on commit."""

    edited = pyqtSignal(tuple)

    def __init__(self, *, labels: Sequence[str] = ("x", "y", "z"), suffix: str = "",
                 decimals: int = 3, step: float = 0.1, minimum: float = -BIG,
                 maximum: float = BIG, tooltip: str = "", parent: QWidget | None = None):
        super().__init__(parent)
        layout = QHBoxLayout(self)
        layout.setContentsMargins(0, 0, 0, 0)
        layout.setSpacing(3)
        self.boxes = []
        for label in labels:
            box = spin(minimum=minimum, maximum=maximum, decimals=decimals, step=step,
                       suffix=suffix, tooltip=f"{tooltip} — {label}" if tooltip else label)
            box.setPrefix(f"{label} ")
            box.valueChanged.connect(self._emit)
            layout.addWidget(box)
            self.boxes.append(box)

    def value(self) -> tuple[float, ...]:
        """Current vector."""
        return tuple(b.value() for b in self.boxes)

    def set_value(self, value: Sequence[float]) -> None:
        """Show ``value`` without emitting ``edited``."""
        for box, v in zip(self.boxes, value, strict=True):
            set_quietly(box, float(v))

    def _emit(self, _v: float) -> None:
        self.edited.emit(self.value())


def try_edit(report: Callable[[str], None], action: Callable[[], Any],
             revert: Callable[[], None] | None = None) -> bool:
    """Run an edit; on :class:`EditError` report its message and revert the widgets."""
    try:
        action()
    except EditError as exc:
        report(str(exc))
        if revert is not None:
            revert()
        return False
    return True
