"""File → Import scene…: a glTF/GLB/OBJ asset as objects, with its materials mapped.

The dialog reads the asset (:func:`simcore.scene.assets.read_asset`), lists its objects by
their asset names and shows one row per asset material: a combo box with the library
material it maps to (the default from the name and PBR rules, see docs/assets.md) and a
preview of what each sensor will see with that choice (ToF, radar, visible: reflects,
transmits, absorbs, and the visible colour). Accepting writes the meshes beside the
project and replaces the project in one undo step.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from PyQt6.QtGui import QAction, QColor
from PyQt6.QtWidgets import (
    QComboBox,
    QDialog,
    QDialogButtonBox,
    QFileDialog,
    QLabel,
    QListWidget,
    QTableWidget,
    QTableWidgetItem,
    QVBoxLayout,
    QWidget,
)

from app.document.document import ProjectDocument
from app.document.sensors import radar_wavelength_m
from simcore.scene.asset_import import build_project, default_mapping
from simcore.scene.assets import AssetScene, read_asset
from simcore.scene.materials import DualBandMaterial, summarize_material
from simcore.scene.radar_config import SPEED_OF_LIGHT

ASSET_FILTER = "3D scenes (*.glb *.gltf *.obj)"


def preview_text(material: DualBandMaterial, radar_frequency_hz: float) -> str:
    """What each sensor sees of ``material`` (one line per band)."""
    return summarize_material(material, radar_frequency_hz).replace("; ", "\n")


class SceneImportDialog(QDialog):
    """Map the asset's materials to library materials, seeing what each sensor will see."""

    def __init__(self, scene: AssetScene, table: dict[str, DualBandMaterial],
                 radar_frequency_hz: float, parent: QWidget | None = None):
        super().__init__(parent)
        self.scene = scene
        self.table = table
        self.radar_frequency_hz = radar_frequency_hz
        self.setWindowTitle(f"Import {scene.source.name}")
        layout = QVBoxLayout(self)
        layout.addWidget(QLabel(f"{len(scene.objects)} objects, {scene.n_triangles} "
                                f"triangles from {scene.source.name}"))
        self.objects = QListWidget()
        for obj in scene.objects:
            self.objects.addItem(f"{obj.name}  ({obj.material}, {len(obj.triangles)} "
                                 "triangles)")
        self.objects.setMaximumHeight(140)
        layout.addWidget(self.objects)
        self.mappings = default_mapping(scene.materials, set(table))
        self.grid = QTableWidget(len(self.mappings), 3)
        self.grid.setHorizontalHeaderLabels(["asset material", "library material",
                                             "what the sensors see"])
        self.combos: dict[str, QComboBox] = {}
        for row, (name, mapping) in enumerate(sorted(self.mappings.items())):
            item = QTableWidgetItem(name + ("  (unmapped)" if mapping.unmapped else ""))
            item.setToolTip(mapping.reason)
            self.grid.setItem(row, 0, item)
            combo = QComboBox()
            combo.addItems(sorted(table))
            combo.setCurrentText(mapping.material)
            combo.currentTextChanged.connect(lambda _t, r=row, n=name: self._preview(r, n))
            self.grid.setCellWidget(row, 1, combo)
            self.combos[name] = combo
            self._preview(row, name)
        self.grid.resizeColumnsToContents()
        self.grid.resizeRowsToContents()
        layout.addWidget(self.grid)
        if scene.skipped:
            layout.addWidget(QLabel("skipped: " + "; ".join(scene.skipped[:5])))
        buttons = QDialogButtonBox(QDialogButtonBox.StandardButton.Ok
                                   | QDialogButtonBox.StandardButton.Cancel)
        buttons.accepted.connect(self.accept)
        buttons.rejected.connect(self.reject)
        layout.addWidget(buttons)
        self.resize(980, 560)

    def _preview(self, row: int, name: str) -> None:
        material = self.table[self.combos[name].currentText()]
        item = QTableWidgetItem(preview_text(material, self.radar_frequency_hz))
        r, g, b = (int(255 * c) for c in material.color_rgb)
        item.setBackground(QColor(r, g, b, 90))
        self.grid.setItem(row, 2, item)
        self.grid.resizeRowToContents(row)

    def overrides(self) -> dict[str, str]:
        """Asset material → library material, for every row changed from its default."""
        return {name: combo.currentText() for name, combo in self.combos.items()
                if combo.currentText() != self.mappings[name].material}


def import_scene(document: ProjectDocument, scene: AssetScene,
                 overrides: dict[str, str] | None = None) -> list[str]:
    """Add the scene's objects to the document as ONE undo step; returns their names.

    The meshes are written beside the project file, so the project must have been saved.
    """
    if document.path is None:
        raise ValueError("save the project first: the imported meshes are stored beside it")
    result = build_project(scene, document.path, base=document.project, overrides=overrides)
    document.push(result.project, f"Import {scene.source.name}")
    return result.object_names


def build_import_scene_action(parent: QWidget, document: ProjectDocument,
                              report: Any) -> QAction:
    """The File → Import scene… action (glTF/GLB/OBJ with the mapping dialog)."""
    action = QAction("Import &scene (glTF/GLB/OBJ)…", parent)
    action.setToolTip("Import every mesh node of a 3D asset as an object, with its materials "
                      "mapped to the library")

    def run() -> None:
        path, _ = QFileDialog.getOpenFileName(parent, "Import scene", str(document.base_dir),
                                              ASSET_FILTER)
        if path:
            open_import_dialog(parent, document, Path(path), report)

    action.triggered.connect(run)
    return action


def open_import_dialog(parent: QWidget | None, document: ProjectDocument, path: Path,
                       report: Any, *, execute: bool = True) -> SceneImportDialog | None:
    """Read ``path``, show the mapping dialog and import on OK (errors go to ``report``)."""
    try:
        scene = read_asset(path)
    except Exception as exc:  # noqa: BLE001 - any unreadable asset: say why, in one line
        report(f"cannot import {path.name}: {exc}")
        return None
    frequency = SPEED_OF_LIGHT / radar_wavelength_m(document.project)
    dialog = SceneImportDialog(scene, document.material_table(), frequency, parent)
    if execute and dialog.exec() == QDialog.DialogCode.Accepted:
        try:
            import_scene(document, scene, dialog.overrides())
        except Exception as exc:  # noqa: BLE001
            report(f"cannot import {path.name}: {exc}")
    return dialog


__all__ = ["SceneImportDialog", "build_import_scene_action", "import_scene",
           "open_import_dialog", "preview_text"]
