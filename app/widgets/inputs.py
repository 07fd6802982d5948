"""Small input widgets with units: spin boxes, 2-/3-vectors, field errors and an edit helper.

Spin boxes accept far more than the model does, so that a value out of range reaches the
model and is refused with its reason at the field (:func:`show_field_error`: a red frame
and a line under the field), instead of being clamped silently to the widget's limits.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any

from PyQt6.QtCore import QSignalBlocker, QSize, Qt, pyqtSignal
from PyQt6.QtGui import QFocusEvent, QKeyEvent, QValidator
from PyQt6.QtWidgets import (
    QDoubleSpinBox,
    QFormLayout,
    QHBoxLayout,
    QLabel,
    QLayout,
    QSpinBox,
    QStyle,
    QWidget,
)

from app.document.document import EditError

BIG = 1e9
#: Widest range of integer spin boxes (Qt's are 32-bit).
INT_MAX = 2**31 - 1
_ERROR_STYLE = "border: 1px solid #ff6b6b; border-radius: 2px;"


def parse_number(text: str) -> float | None:
    """The finite number ``text`` spells (``−`` allowed for minus), or None."""
    try:
        value = float(text.strip().replace("\u2212", "-"))
    except ValueError:
        return None
    return value if value == value and abs(value) != float("inf") else None


class _TextRefusal:
    """What :class:`NumberBox` and :class:`IntBox` share: typed text that is no value.

    Qt's spin boxes swallow keys they cannot parse and put back the previous value when a
    typed one is out of their range, without a word. Once something listens to
    ``textRefused`` (:func:`app.editors.field_editors.bind_number_box` does), a box accepts any
    text while typing, and on Enter or when focus leaves with text that is not a value in
    its range, it emits ``textRefused(text)`` and keeps the text, so the field can say why.
    Nothing is committed. Unbound boxes behave as Qt's.
    """

    #: Set by the binding: typed text is checked here, not silently dropped.
    refusing = False

    def _body(self, text: str) -> str:
        body = text.removeprefix(self.prefix()).removesuffix(self.suffix())  # type: ignore[attr-defined]
        return body.strip()

    def _is_special(self, text: str) -> bool:
        special = self.specialValueText()  # type: ignore[attr-defined]
        return bool(special) and text == special

    def _parse(self, body: str) -> float | None:
        return parse_number(body)

    def _state(self, text: str) -> QValidator.State:
        if self._is_special(text):
            return QValidator.State.Acceptable
        value = self._parse(self._body(text))
        if value is None or not self.minimum() <= value <= self.maximum():  # type: ignore[attr-defined]
            return QValidator.State.Intermediate
        return QValidator.State.Acceptable

    def _refuse_pending(self) -> bool:
        """Emit ``textRefused`` for the text in the box when it is no value; True if so."""
        if not self.refusing:
            return False
        edit = self.lineEdit()  # type: ignore[attr-defined]
        text = edit.text() if edit is not None else ""
        if self._state(text) == QValidator.State.Acceptable:
            return False
        self.textRefused.emit(self._body(text))  # type: ignore[attr-defined]
        return True


class NumberBox(_TextRefusal, QDoubleSpinBox):
    """A double spin box that refuses, with a signal, text that is not a number.

    Signals
    -------
    textRefused(str)
        Enter or focus-out with text that is no number in the box's range (the text typed,
        without prefix and suffix).
    """

    textRefused = pyqtSignal(str)
    #: Width (px) that shows a typical value whole (:meth:`VectorEdit.fit_text`); None:
    #: Qt's hint, which is as wide as the range's extreme values.
    text_width: int | None = None

    def minimumSizeHint(self) -> QSize:  # noqa: N802, D102 - Qt API
        hint = super().minimumSizeHint()
        return hint if self.text_width is None else QSize(self.text_width, hint.height())

    def validate(self, text: str | None, pos: int) -> tuple[QValidator.State, str, int]:  # noqa: D102
        text = text or ""
        if not self.refusing:
            return super().validate(text, pos)
        body = self._body(text)
        decimals = body.split(".", 1)[1] if "." in body and "e" not in body.lower() else ""
        if len(decimals) > self.decimals():
            # More digits than the box shows: refused while typing, as Qt does.
            return QValidator.State.Invalid, text, pos
        return self._state(text), text, pos

    def valueFromText(self, text: str | None) -> float:  # noqa: N802, D102 - Qt API
        value = parse_number(self._body(text or "")) if self.refusing else None
        return super().valueFromText(text) if value is None else value

    def keyPressEvent(self, event: QKeyEvent | None) -> None:  # noqa: N802, D102 - Qt API
        if event is not None and event.key() in (Qt.Key.Key_Return, Qt.Key.Key_Enter) \
                and self._refuse_pending():
            event.accept()
            return
        super().keyPressEvent(event)

    def focusOutEvent(self, event: QFocusEvent | None) -> None:  # noqa: N802, D102 - Qt API
        edit = self.lineEdit()
        text = edit.text() if edit is not None else ""
        refused = self._refuse_pending()
        super().focusOutEvent(event)
        if refused and edit is not None:  # Qt put the previous value back: show the text
            edit.setText(text)


class IntBox(_TextRefusal, QSpinBox):
    """An integer spin box that refuses, with a signal, text that is not a whole number.

    Signals
    -------
    textRefused(str)
        As :class:`NumberBox`'s.
    """

    textRefused = pyqtSignal(str)

    def _parse(self, body: str) -> float | None:
        value = parse_number(body)
        return value if value is not None and value.is_integer() else None

    def validate(self, text: str | None, pos: int) -> tuple[QValidator.State, str, int]:  # noqa: D102
        text = text or ""
        if not self.refusing:
            return super().validate(text, pos)
        return self._state(text), text, pos

    def valueFromText(self, text: str | None) -> int:  # noqa: N802, D102 - Qt API
        value = self._parse(self._body(text or "")) if self.refusing else None
        return super().valueFromText(text) if value is None else int(value)

    def keyPressEvent(self, event: QKeyEvent | None) -> None:  # noqa: N802, D102 - Qt API
        if event is not None and event.key() in (Qt.Key.Key_Return, Qt.Key.Key_Enter) \
                and self._refuse_pending():
            event.accept()
            return
        super().keyPressEvent(event)

    def focusOutEvent(self, event: QFocusEvent | None) -> None:  # noqa: N802, D102 - Qt API
        edit = self.lineEdit()
        text = edit.text() if edit is not None else ""
        refused = self._refuse_pending()
        super().focusOutEvent(event)
        if refused and edit is not None:
            edit.setText(text)


def spin(*, minimum: float = -BIG, maximum: float = BIG, decimals: int = 3, step: float = 0.1,
         suffix: str = "", tooltip: str = "") -> QDoubleSpinBox:
    """A double spin box that reports values only when committed (Enter, focus out, arrows)."""
    box = NumberBox()
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
    box = IntBox()
    box.setRange(minimum, maximum)
    box.setKeyboardTracking(False)
    if suffix:
        box.setSuffix(f" {suffix}")
    if tooltip:
        box.setToolTip(tooltip)
    return box


def set_quietly(widget: Any, value: Any) -> None:
    """Set a widget's value without emitting its change signals (clears its field error)."""
    clear_field_error(widget)
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

    def fit_text(self) -> None:
        """Keep each box wide enough for a value such as ``x -00.000 m`` to show whole.

        Without it a narrow form squeezes the boxes to their 70 px floor and cuts the
        unit off (``x 0.00 °/``) or pushes them past the dock's edge; with it the boxes
        that do not fit beside the others wrap onto a second line (issue #34).
        """
        from app.widgets.wrap_row import WrapRow

        layout = self.layout()
        assert layout is not None
        row = WrapRow(spacing=3)
        for box in self.boxes:
            text = f"{box.prefix()}-00.{'0' * box.decimals()}{box.suffix()}"
            buttons = box.style().pixelMetric(QStyle.PixelMetric.PM_ScrollBarExtent)
            width = box.fontMetrics().horizontalAdvance(text) + buttons + 14
            box.setMinimumWidth(width)
            if isinstance(box, NumberBox):
                box.text_width = width
            layout.removeWidget(box)
            row.add(box)
        layout.addWidget(row)

    def value(self) -> tuple[float, ...]:
        """Current vector."""
        return tuple(b.value() for b in self.boxes)

    def set_value(self, value: Sequence[float]) -> None:
        """Show ``value`` without emitting ``edited``."""
        clear_field_error(self)
        for box, v in zip(self.boxes, value, strict=True):
            set_quietly(box, float(v))

    def _emit(self, _v: float) -> None:
        self.edited.emit(self.value())


def _layout_contains(layout: QLayout, widget: QWidget) -> bool:
    for i in range(layout.count()):
        item = layout.itemAt(i)
        if item is None:
            continue
        if item.widget() is widget:
            return True
        sub = item.layout()
        if sub is not None and _layout_contains(sub, widget):
            return True
    return False


def _form_row(widget: QWidget) -> tuple[QFormLayout, int] | None:
    """The form layout and row that hold ``widget`` (directly or in a row's sub-layout)."""
    w: QWidget | None = widget
    while w is not None and w.parentWidget() is not None:
        layout = w.parentWidget().layout()
        if isinstance(layout, QFormLayout):
            row, _ = layout.getWidgetPosition(w)
            if row >= 0:
                return layout, row
            for r in range(layout.rowCount()):
                item = layout.itemAt(r, QFormLayout.ItemRole.FieldRole)
                if item is not None and item.layout() is not None and \
                        _layout_contains(item.layout(), w):
                    return layout, r
        w = w.parentWidget()
    return None


def field_error(widget: QWidget) -> str | None:
    """The error shown at ``widget``, or None."""
    value = widget.property("fieldError")
    return str(value) if value else None


def show_field_error(widget: QWidget, message: str) -> None:
    """Mark ``widget`` invalid: red frame, the reason in a line under it and in its tooltip."""
    if not field_error(widget):
        widget.setProperty("plainToolTip", widget.toolTip())
        widget.setProperty("plainStyle", widget.styleSheet())
    widget.setProperty("fieldError", message)
    widget.setStyleSheet(_ERROR_STYLE)
    widget.setToolTip(f"⚠ {message}\n\n{widget.property('plainToolTip') or ''}".strip())
    label = widget.property("errorLabel")
    if not isinstance(label, QLabel):
        label = QLabel()
        label.setWordWrap(True)
        label.setStyleSheet("color: #ff6b6b;")
        label.setObjectName("fieldError")
        place = _form_row(widget)
        if place is not None:
            form, row = place
            form.insertRow(row + 1, "", label)
        elif widget.parentWidget() is not None and widget.parentWidget().layout() is not None:
            widget.parentWidget().layout().addWidget(label)
        widget.setProperty("errorLabel", label)
    label.setText(f"⚠ {message}")
    label.setVisible(True)


def clear_field_error(widget: QWidget) -> None:
    """Remove the mark of :func:`show_field_error` (the field holds a valid value again)."""
    if not isinstance(widget, QWidget) or not field_error(widget):
        return
    widget.setProperty("fieldError", "")
    widget.setStyleSheet(str(widget.property("plainStyle") or ""))
    widget.setToolTip(str(widget.property("plainToolTip") or ""))
    label = widget.property("errorLabel")
    if isinstance(label, QLabel):
        label.setVisible(False)


def try_edit(report: Callable[[str], None], action: Callable[[], Any],
             revert: Callable[[], None] | None = None, *, field: QWidget | None = None) -> bool:
    """Run an edit; on :class:`EditError` show why.

    With ``field`` (the widget that was edited) the reason is shown at the field and the
    field keeps the refused value for the user to correct; nothing is pushed on the undo
    stack. Without it the message goes to ``report`` and ``revert`` restores the widgets.
    """
    try:
        action()
    except EditError as exc:
        if field is not None:
            show_field_error(field, str(exc))
            return False
        report(str(exc))
        if revert is not None:
            revert()
        return False
    if field is not None:
        clear_field_error(field)
    return True
