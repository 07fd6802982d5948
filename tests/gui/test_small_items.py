"""Small items of issue #17: Space and focus, icons, undo texts, inspector, empty scene."""

from __future__ import annotations

import pytest
from PyQt6.QtCore import Qt
from PyQt6.QtWidgets import QApplication, QStyle

from app.document.scene_edits import add_object
from app.panels.base import EMPTY_SCENE_HINT, plural

pytestmark = pytest.mark.gui


def _activate(window, qtbot) -> None:
    window.raise_()
    window.activateWindow()
    qtbot.waitUntil(window.isActiveWindow, timeout=5000)


def test_space_toggles_a_focused_checkbox_and_plays_elsewhere(make_window, qtbot):
    window = make_window(None)
    _activate(window, qtbot)
    box = window.profile_panel.raw_box
    box.setFocus()
    qtbot.waitUntil(box.hasFocus, timeout=2000)
    qtbot.keyClick(box, Qt.Key.Key_Space)
    assert box.isChecked() and not window.time.playing
    lst = window.object_list.list
    lst.setFocus()
    qtbot.waitUntil(lst.hasFocus, timeout=2000)
    qtbot.keyClick(lst, Qt.Key.Key_Space)
    assert window.time.playing
    window.time.set_playing(False)


def test_undo_icons_are_not_browser_arrows_and_undo_texts_name_the_object(make_window):
    window = make_window(None)
    back = window.style().standardIcon(QStyle.StandardPixmap.SP_ArrowBack).pixmap(32)
    assert window.undo_action.icon().pixmap(32).toImage() != back.toImage()
    assert not window.undo_action.icon().isNull() and not window.redo_action.icon().isNull()
    doc = window.document
    oid = add_object(doc, "sphere")
    name = doc.project.objects[doc.index_of(oid)].name
    doc.select(oid)
    window.inspector.position_edit.set_value((3.0, 0.5, 1.0))
    window.inspector.position_edit.edited.emit((3.0, 0.5, 1.0))
    assert doc.undo_stack.undoText() == f"Move {name}"
    window.inspector.velocity_edit.edited.emit((0.5, 0.0, 0.0))
    assert doc.undo_stack.undoText() == f"Set velocity of {name} to (0.5, 0, 0) m/s"
    assert window.undo_action.text() == f"&Undo Set velocity of {name} to (0.5, 0, 0) m/s"


def test_inspector_hides_values_of_nothing(make_window):
    window = make_window(None)
    doc = window.document
    oid = add_object(doc, "box")
    doc.select(oid)
    assert window.inspector.pose_box.isVisible()
    doc.select(None)
    assert not window.inspector.pose_box.isVisible()
    assert "Nothing selected" in window.inspector.heading.text()


def test_empty_scene_is_explained_in_every_panel(make_window, qtbot):
    window = make_window(None)
    QApplication.processEvents()
    for name, panel in window.panels.items():
        assert panel.hint.isVisible(), name
        assert panel.hint.text() == EMPTY_SCENE_HINT
    add_object(window.document, "sphere")
    for panel in window.panels.values():
        assert not panel.hint.isVisible()
    assert plural(1, "detection") == "1 detection" and plural(0, "detection") == "0 detections"
