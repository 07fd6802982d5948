"""Mesh import with a unit choice and a size read-out.

Mesh files carry no unit: an STL exported in millimetres read as metres is 1000× too
large. The dialog reads the file's bounding box, guesses the unit from its size
(:func:`guess_unit`), shows the size the object will have in the scene for the chosen
unit, and imports with that scale.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from numpy.typing import NDArray
from PyQt6.QtWidgets import (
    QComboBox,
    QDialog,
    QDialogButtonBox,
    QFormLayout,
    QLabel,
    QWidget,
)

from simcore.scene.mesh_files import read_mesh_arrays

#: Units a mesh file may be in: name → metres per file unit.
UNITS: dict[str, float] = {"m": 1.0, "cm": 0.01, "mm": 0.001, "inch": 0.0254}


def mesh_extent(path: Path) -> NDArray[np.float64]:
    """Edge lengths (x, y, z) of the mesh's bounding box, in file units."""
    points, _faces = read_mesh_arrays(Path(path))
    if len(points) == 0:
        return np.zeros(3)
    return np.asarray(points.max(axis=0) - points.min(axis=0), dtype=np.float64)


def guess_unit(extent: NDArray[np.float64]) -> str:
    """The likeliest unit of a file whose bounding box is ``extent`` (file units).

    Indoor scenes span centimetres to tens of metres: a largest edge above 50 file units
    is taken as millimetres (a 5 cm … metre-sized object), anything smaller as metres.

    Examples
    --------
    >>> guess_unit(np.array([1200.0, 800.0, 750.0])), guess_unit(np.array([1.2, 0.8, 0.75]))
    ('mm', 'm')
    """
    largest = float(np.max(extent)) if len(extent) else 0.0
    return "mm" if largest > 50.0 else "m"


def size_text(extent: NDArray[np.float64], unit: str) -> str:
    """``"1.20 × 0.80 × 0.75 m"``: the scene size of a mesh of ``extent`` file units."""
    metres = np.asarray(extent) * UNITS[unit]
    return " × ".join(f"{v:.3g}" for v in metres) + " m"


class MeshImportDialog(QDialog):
    """Choose the unit of a mesh file, seeing the size it will have in the scene."""

    def __init__(self, path: Path, parent: QWidget | None = None):
        super().__init__(parent)
        self.setWindowTitle(f"Import {Path(path).name}")
        self.extent = mesh_extent(path)
        form = QFormLayout(self)
        form.addRow("file", QLabel(str(path)))
        form.addRow("bounding box", QLabel(" × ".join(f"{v:.4g}" for v in self.extent)
                                           + " (file units)"))
        self.unit = QComboBox()
        self.unit.addItems(list(UNITS))
        self.unit.setToolTip("The unit the file was written in (mesh files do not say)")
        self.unit.setCurrentText(guess_unit(self.extent))
        form.addRow("file unit", self.unit)
        self.size = QLabel("")
        self.size.setToolTip("Size of the object in the scene with this unit")
        form.addRow("size in the scene", self.size)
        self.unit.currentTextChanged.connect(self._update)
        buttons = QDialogButtonBox(QDialogButtonBox.StandardButton.Ok
                                   | QDialogButtonBox.StandardButton.Cancel)
        buttons.accepted.connect(self.accept)
        buttons.rejected.connect(self.reject)
        form.addRow(buttons)
        self._update()

    def _update(self, *_: object) -> None:
        self.size.setText(size_text(self.extent, self.unit.currentText()))

    @property
    def scale(self) -> float:
        """Metres per file unit of the chosen unit."""
        return UNITS[self.unit.currentText()]


__all__ = ["UNITS", "MeshImportDialog", "guess_unit", "mesh_extent", "size_text"]
