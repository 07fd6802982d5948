"""File → Import scene…: the mapping dialog, its sensor preview and the one-step undo."""

from __future__ import annotations

import os
from pathlib import Path

import pytest
from gltf_assets import Gltf, box
from PyQt6.QtWidgets import QWidget

from app.dialogs.scene_import import (
    SceneImportDialog,
    import_scene,
    open_import_dialog,
    preview_text,
)
from app.document.document import ProjectDocument
from simcore.scene.materials import load_material_library
from simcore.scene.model import Project
from simcore.scene.project_io import save_project

pytestmark = pytest.mark.gui


@pytest.fixture
def asset(tmp_path) -> Path:
    g = Gltf()
    steel = g.material("Steel")
    thing = g.material("Thing")
    g.node("cabinet", mesh=g.mesh([(*box((0.5, 1.8, 0.6)), steel)]), translation=[2, 0.9, 0])
    g.node("widget", mesh=g.mesh([(*box((0.2, 0.2, 0.2)), thing)]), translation=[1, 0.1, 1])
    return g.write_glb(tmp_path / "room.glb")


@pytest.fixture
def document(tmp_path, qtbot):
    path = tmp_path / "p.json"
    save_project(Project(), path)
    parent = QWidget()
    qtbot.addWidget(parent)
    doc = ProjectDocument(Project(), path, parent=parent)
    return doc, parent


def test_dialog_maps_previews_and_imports_in_one_undo_step(asset, document, tmp_path):
    doc, parent = document
    errors: list[str] = []
    dialog = open_import_dialog(parent, doc, asset, errors.append, execute=False)
    assert isinstance(dialog, SceneImportDialog) and not errors
    # Objects listed by their asset names.
    items = [dialog.objects.item(i).text() for i in range(dialog.objects.count())]
    assert [t.split()[0] for t in items] == ["cabinet", "widget"]
    # Defaults: the name rule for Steel; Thing unmapped (said so), concrete until chosen.
    assert dialog.combos["Steel"].currentText() == "aluminium"
    assert dialog.combos["Thing"].currentText() == "concrete"
    labels = [dialog.grid.item(r, 0).text() for r in range(dialog.grid.rowCount())]
    assert "Thing  (unmapped)" in labels
    # The preview follows the combo: what the sensors see of the chosen material.
    row = labels.index("Thing  (unmapped)")
    glass = load_material_library()["glass"]
    dialog.combos["Thing"].setCurrentText("glass")
    assert dialog.grid.item(row, 2).text() == preview_text(glass, dialog.radar_frequency_hz)
    assert "ToF" in dialog.grid.item(row, 2).text() and "radar" in dialog.grid.item(row, 2).text()
    assert dialog.overrides() == {"Thing": "glass"}
    if os.environ.get("TOFRADAR_SHOT"):
        dialog.grab().save(os.environ["TOFRADAR_SHOT"])
    before = doc.undo_stack.count()
    names = import_scene(doc, dialog.scene, dialog.overrides())
    assert names == ["cabinet", "widget"]
    assert doc.undo_stack.count() == before + 1
    project = doc.project
    assert [o.name for o in project.objects] == ["cabinet", "widget"]
    assert project.materials_map == {"Steel": "aluminium", "Thing": "glass"}
    assert (tmp_path / "p.meshes" / "cabinet.ply").is_file()
    doc.undo_stack.undo()
    assert doc.project.objects == [] and doc.project.materials_map == {}
    doc.undo_stack.redo()
    assert [o.name for o in doc.project.objects] == ["cabinet", "widget"]


def test_bad_asset_and_unsaved_project_are_reported(tmp_path, qtbot, asset):
    parent = QWidget()
    qtbot.addWidget(parent)
    errors: list[str] = []
    bad = tmp_path / "bad.glb"
    bad.write_bytes(b"glTF" + b"\0" * 30)
    doc = ProjectDocument(Project(), None, parent=parent)
    assert open_import_dialog(parent, doc, bad, errors.append, execute=False) is None
    assert len(errors) == 1 and errors[0].startswith("cannot import bad.glb: bad.glb: ")
    dialog = open_import_dialog(parent, doc, asset, errors.append, execute=False)
    with pytest.raises(ValueError, match="save the project first"):
        import_scene(doc, dialog.scene)
    assert doc.project.objects == []


def test_main_window_file_menu_has_import_scene(make_window):
    window = make_window(None)
    file_menu = window.menuBar().actions()[0].menu()
    texts = [a.text() for a in file_menu.actions()]
    assert "Import &scene (glTF/GLB/OBJ)…" in texts
