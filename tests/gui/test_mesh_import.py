"""Mesh import asks for the file's unit and shows the size the object gets in the scene."""

from __future__ import annotations

import numpy as np
import pytest
import pyvista as pv
from PyQt6.QtCore import QTimer
from PyQt6.QtWidgets import QApplication, QFileDialog, QWidget

from app.dialogs.mesh_import import MeshImportDialog, guess_unit, mesh_extent, size_text
from app.document.document import ProjectDocument
from app.editors.scene_editor import build_add_menu

pytestmark = pytest.mark.gui


@pytest.fixture
def desk_mm(tmp_path):
    """A 1200 × 800 × 750 mm box written in millimetres."""
    path = tmp_path / "desk_mm.stl"
    pv.Box(bounds=(0, 1200, 0, 800, 0, 750)).triangulate().save(path)
    return path


def test_unit_guess_and_size_read_out(desk_mm):
    extent = mesh_extent(desk_mm)
    np.testing.assert_allclose(extent, [1200, 800, 750])
    assert guess_unit(extent) == "mm"
    assert size_text(extent, "mm") == "1.2 × 0.8 × 0.75 m"
    assert size_text(extent, "m") == "1.2e+03 × 800 × 750 m"
    assert guess_unit(np.array([1.2, 0.8, 0.75])) == "m"


def test_import_through_the_menu_uses_the_chosen_unit(desk_mm, qtbot, monkeypatch):
    doc = ProjectDocument()
    parent = QWidget()
    qtbot.addWidget(parent)
    doc.setParent(parent)
    errors: list[str] = []
    menu = build_add_menu(parent, doc, errors.append)
    monkeypatch.setattr(QFileDialog, "getOpenFileName",
                        lambda *a, **k: (str(desk_mm), "Meshes (*.stl)"))
    seen: list[str] = []

    def answer() -> None:
        dialog = next(w for w in QApplication.topLevelWidgets()
                      if isinstance(w, MeshImportDialog) and w.isVisible())
        seen.append(dialog.size.text())
        dialog.unit.setCurrentText("cm")
        seen.append(dialog.size.text())
        dialog.accept()

    QTimer.singleShot(200, answer)
    next(a for a in menu.actions() if a.text().startswith("Import mesh")).trigger()
    assert not errors
    assert seen == ["1.2 × 0.8 × 0.75 m", "12 × 8 × 7.5 m"]
    obj = doc.project.objects[-1]
    assert obj.geometry.kind == "mesh" and obj.geometry.scale == pytest.approx(0.01)
