"""Material editor: ToF (near-IR), radar and visible-band parameters side by side, and colour.

Materials come from the bundled library and the project; editing a library material saves
an override of the same name into the project (the library file is never written).

The editor shows the material of the selected object, and follows it wherever it changes
(the Inspector, undo/redo, a file opened again); a material picked in its own list is shown
until the selection or the selected object's material changes.

A material is shared by every object that names it: the editor says which objects an edit
changes, and before the first edit of a material the selected object shares with others,
it asks whether to change all of them or give the selected object its own copy
(**Make unique**) first.
"""

from __future__ import annotations

import html
from collections.abc import Callable
from typing import Any

import numpy as np
from PyQt6.QtCore import QSignalBlocker, pyqtSignal
from PyQt6.QtGui import QColor
from PyQt6.QtWidgets import (
    QCheckBox,
    QColorDialog,
    QComboBox,
    QFormLayout,
    QGroupBox,
    QHBoxLayout,
    QInputDialog,
    QLabel,
    QMessageBox,
    QPushButton,
    QVBoxLayout,
    QWidget,
)

from app.document.document import EditError, ProjectDocument, library_material, library_names
from app.document.sensors import radar_wavelength_m
from app.editors.field_editors import FieldSpec, bind_number_box, commit_value
from app.widgets.inputs import BIG, set_quietly, spin, try_edit
from app.widgets.wrap_row import WrapRow
from simcore.scene.materials import BandMaterial, DualBandMaterial, summarize_material
from simcore.scene.radar_config import SPEED_OF_LIGHT

BAND_FIELDS: list[tuple[str, str, float, float, float, str]] = [
    # field, label, min, max, step, tooltip
    ("reflectance", "reflectance", 0.0, 1.0, 0.05,
     "diffuse (Lambertian) reflectance / albedo, 0–1"),
    ("specular", "specular weight", 0.0, 1000.0, 0.1,
     "weight of the rough-surface specular lobe (Beckmann)"),
    ("roughness", "roughness", 0.01, 2.0, 0.05,
     "rms surface slope: width of the specular lobe (0.01 mirror … 2 very rough)"),
    ("metallic", "metallic", 0.0, 1.0, 0.1, "1 removes the diffuse part (metals)"),
    ("opacity", "opacity", 0.0, 1.0, 0.1,
     "0: the band sees through the object (it is not rendered in this band)"),
    ("retro_gain", "retro gain", 0.0, 1e6, 1.0,
     "angle-independent extra return of a retroreflector (band response units)"),
]

#: Smooth-interface fields of the radar band: field, label, unit scale (shown = SI × scale),
#: step, tooltip. 0 shown means "not set" for the optional ones (permittivity, thickness).
#: Words and units of the interface fields in messages and undo texts.
INTERFACE_WORDS = {"permittivity": ("permittivity", ""), "loss_tangent": ("loss tangent", ""),
                   "thickness_m": ("thickness", "mm"), "height_rms_m": ("rms height", "mm")}
#: Interface fields where 0 shown means "not set" (None).
OPTIONAL_FIELDS = {"permittivity": "0 (no smooth interface)", "thickness_m": "0 (thick)"}
INTERFACE_FIELDS: list[tuple[str, str, float, float, str]] = [
    ("permittivity", "permittivity ε′", 1.0, 0.1,
     "relative permittivity at 60 GHz; 0 = no smooth interface (diffuse lobe only). Sets "
     "the coherent (physical-optics) reflection Γ = (1 − n)/(1 + n)"),
    ("loss_tangent", "loss tangent tan δ", 1.0, 0.01,
     "dielectric loss ε″/ε′: absorption inside a slab"),
    ("thickness_m", "thickness (mm)", 1e3, 0.5,
     "slab thickness in mm; 0 = thick (transmits nothing). A slab transmits: the radar "
     "sees what is behind it, attenuated by T² (in and out)"),
    ("height_rms_m", "rms height (mm)", 1e3, 0.05,
     "rms surface height in mm: removes coherent reflection, "
     "exp(−(4π h cos θ / λ)²) of it stays coherent"),
]

BAND_TITLES = {"tof": "ToF (near-IR)", "radar": "Radar (mm-wave)",
               "visible": "Visible (RGB camera)"}
#: The band in a sentence: "ToF reflectance", "radar thickness".
BAND_WORDS = {"tof": "ToF", "radar": "radar", "visible": "visible"}


def band_spec(band: str, field: str) -> FieldSpec:
    """The :class:`FieldSpec` of a band parameter (label, unit, scale) for messages."""
    interface = {f: (scale, step) for f, _l, scale, step, _t in INTERFACE_FIELDS}
    if field in interface:
        words, unit = INTERFACE_WORDS[field]
        scale = interface[field][0]
        decimals = 4
    else:
        words = next((label for f, label, *_ in BAND_FIELDS if f == field), field)
        unit, scale, decimals = "", 1.0, 3
    kind = "bool" if field == "retroreflector" else "float"
    return FieldSpec(field, f"{BAND_WORDS[band]} {words}", unit, kind=kind, scale=scale,
                     decimals=decimals, off_text=OPTIONAL_FIELDS.get(field, ""))


#: Check boxes and toggle buttons whose state reads at a glance on the dark theme.
STYLE_SHEET = """
QCheckBox::indicator { width: 14px; height: 14px; border: 1px solid #9aa4ae;
                       border-radius: 3px; background: #15181c; }
QCheckBox::indicator:checked { background: #4fc3f7; border-color: #b3e5fc; }
QCheckBox::indicator:hover { border-color: #ffffff; }
QPushButton:checked { background: #ff8a65; color: #15181c; font-weight: bold;
                      border: 1px solid #ffccbc; border-radius: 3px; }
"""


def objects_using(document: ProjectDocument, name: str) -> list[str]:
    """Names of the objects whose material is ``name``."""
    return [o.name for o in document.project.objects if o.material == name]


def set_material_color(document: ProjectDocument, name: str,
                       rgb: tuple[float, float, float]) -> None:
    """Set the visible colour (linear RGB, 0–1) of material ``name``."""
    table = document.material_table()
    if name not in table:
        raise EditError(f"materials: unknown material {name!r}")
    value = tuple(float(round(c, 4)) for c in rgb)

    def mutate(d: dict[str, Any]) -> None:
        for m in d["materials"]:
            if m["name"] == name:
                m["color_rgb"] = value
                return
        mat = table[name].model_dump()
        mat["color_rgb"] = value
        d["materials"].append(mat)

    document.edit(f"Set colour of {name} to {', '.join(f'{c:g}' for c in value)}", mutate)


def make_unique(document: ProjectDocument, object_index: int) -> str:
    """Give object ``object_index`` its own copy of its material; returns the copy's name.

    The copy is called ``<material>_<object>`` (with a number if taken); the other objects
    keep the shared material. One undo step.
    """
    obj = document.project.objects[object_index]
    table = document.material_table()
    base = f"{obj.material}_{obj.name}"
    new_name, i = base, 2
    while new_name in table:
        new_name, i = f"{base}_{i}", i + 1
    mat = table[obj.material].model_dump()
    mat["name"] = new_name

    def mutate(d: dict[str, Any]) -> None:
        d["materials"].append(mat)
        d["objects"][object_index]["material"] = new_name

    document.edit(f"Make material of {obj.name} unique", mutate)
    return new_name


def set_material_field(document: ProjectDocument, name: str, band: str, field: str,
                       value: Any, *, text: str | None = None) -> None:
    """Set one band parameter of material ``name`` (copied into the project if needed).

    ``text`` is the undo text (default: "Set <band> <field> of <name> to <value>").
    """
    table = document.material_table()
    if name not in table:
        raise EditError(f"materials: unknown material {name!r}")

    def mutate(d: dict[str, Any]) -> None:
        for m in d["materials"]:
            if m["name"] == name:
                target = m
                break
        else:
            target = table[name].model_dump()
            d["materials"].append(target)
        target.setdefault("bands", {}).setdefault(band, {})[field] = value

    spec = band_spec(band, field)
    document.edit(text or spec.undo_text(value, name), mutate)


def save_material_as(document: ProjectDocument, source: str, new_name: str) -> None:
    """Copy material ``source`` into the project under ``new_name``."""
    table = document.material_table()
    if new_name in table and new_name != source:
        raise EditError(f"materials: a material called {new_name!r} already exists")
    mat = table[source].model_dump()
    mat["name"] = new_name

    def mutate(d: dict[str, Any]) -> None:
        d["materials"] = [m for m in d["materials"] if m["name"] != new_name] + [mat]

    document.edit(f"Save material {new_name}", mutate)


def _from_shown(field: str, shown: float) -> float | None:
    """Shown value of an interface field, None where 0 means "not set"."""
    if field in OPTIONAL_FIELDS and shown == 0.0:
        return None
    return float(shown)


def interface_summary(band_material: BandMaterial, frequency_hz: float = 63e9) -> str:
    """"Γ … dB, two-way transmission … dB" of a radar band material, in words."""
    if not band_material.is_smooth_interface():
        return "no smooth interface: diffuse return only"
    gamma, trans = band_material.coefficients(frequency_hz)
    refl = f"Γ = {20 * np.log10(max(abs(gamma), 1e-12)):.1f} dB"
    if abs(trans) <= 1e-9:
        return f"{refl}; opaque"
    return f"{refl}; two-way transmission {40 * np.log10(abs(trans)):.1f} dB"


class BandEditor(QGroupBox):
    """The parameters of one band."""

    edited = pyqtSignal(str, str, object)  # band, field, shown value (None: not set)

    def __init__(self, band: str, parent: QWidget | None = None):
        super().__init__(BAND_TITLES[band], parent)
        self.band = band
        form = QFormLayout(self)
        self.widgets: dict[str, Any] = {}
        for field, label, lo, hi, step, tip in BAND_FIELDS:
            del lo, hi  # the model checks the range and says why at the field
            box = spin(minimum=-BIG, maximum=BIG, decimals=3, step=step,
                       tooltip=f"{BAND_TITLES[band]}: {tip}")
            box.valueChanged.connect(lambda v, f=field: self.edited.emit(self.band, f, float(v)))
            bind_number_box(box, band_spec(band, field))
            form.addRow(label, box)
            self.widgets[field] = box
        retro = QCheckBox("retroreflector")
        retro.setToolTip(f"{BAND_TITLES[band]}: returns energy straight back to the sensor "
                         "at any angle (corner reflectors, reflective tape)")
        retro.toggled.connect(lambda on: self.edited.emit(self.band, "retroreflector", bool(on)))
        form.addRow("", retro)
        self.widgets["retroreflector"] = retro
        self.scales: dict[str, float] = {}
        #: Frequency of the Γ / T read-out: the radar's chirp centre (set by the owner).
        self.frequency_hz = 63e9
        self.interface = QLabel("")
        if band == "radar":
            for field, label, scale, step, tip in INTERFACE_FIELDS:
                box = spin(minimum=-BIG, maximum=BIG, decimals=4, step=step,
                           tooltip=f"{BAND_TITLES[band]}: {tip}")
                box.valueChanged.connect(
                    lambda v, f=field: self.edited.emit(self.band, f, _from_shown(f, v)))
                bind_number_box(box, band_spec(band, field))
                form.addRow(label, box)
                self.widgets[field] = box
                self.scales[field] = scale
            self.interface.setWordWrap(True)
            self.interface.setToolTip("Reflection and two-way transmission of this material "
                                      "at the radar's chirp centre frequency, normal "
                                      "incidence")
            form.addRow(self.interface)

    def show_values(self, band_material: Any) -> None:
        """Show a :class:`BandMaterial`."""
        for field, w in self.widgets.items():
            value = getattr(band_material, field)
            if field in self.scales:
                value = 0.0 if value is None else band_spec(self.band, field).to_shown(value)
            set_quietly(w, value)
        if self.band == "radar":
            self.interface.setText(interface_summary(band_material, self.frequency_hz))


class MaterialEditor(QWidget):
    """Pick a material, edit both bands, toggle radar visibility, save into the project."""

    editFailed = pyqtSignal(str)

    def __init__(self, document: ProjectDocument, parent: QWidget | None = None):
        super().__init__(parent)
        self.document = document
        self._library = library_names()
        layout = QVBoxLayout(self)
        layout.setContentsMargins(4, 4, 4, 4)
        self._build_picker(layout)
        #: Material picked here (list, Edit…, Save as) rather than the selected object's;
        #: dropped when the selection or the selected object's material changes.
        self._pinned: str | None = None
        #: (selected object id, its material) when last shown: a change unpins.
        self._followed: tuple[int | None, str | None] = (None, None)
        #: Shared-material edits already agreed to: (material, object id, users).
        self._agreed: set[tuple[str, int, tuple[str, ...]]] = set()
        #: ``ask_shared_edit(material, users, object)`` → "all", "unique" or "cancel":
        #: asked before the first edit of a material the selected object shares.
        self.ask_shared_edit: Callable[[str, list[str], str], str] = self._ask_shared_edit
        self._build_notes(layout)
        self._build_bands(layout)
        self._build_buttons(layout)
        layout.addStretch(1)
        self.setStyleSheet(STYLE_SHEET)
        document.projectChanged.connect(self.refresh)
        document.selectionChanged.connect(self._follow_selection)
        self.refresh()

    def _build_picker(self, layout: QVBoxLayout) -> None:
        """The top row: material list, Assign to selected, and the colour button."""
        top = QHBoxLayout()
        self.combo = QComboBox()
        self.combo.setToolTip("Materials of the library and of the project (• = saved in the "
                              "project)")
        self.combo.activated.connect(lambda _i: self.show_material(self.current))
        top.addWidget(QLabel("material"))
        top.addWidget(self.combo, 1)
        self.assign_button = QPushButton("Assign to selected")
        self.assign_button.setToolTip("Give the selected object this material")
        self.assign_button.clicked.connect(self.assign_to_selection)
        top.addWidget(self.assign_button)
        layout.addLayout(top)
        self.color_button = QPushButton("colour")
        self.color_button.setToolTip("Colour in visible light (linear RGB), what the RGB camera "
                                     "and the 3D view show")
        self.color_button.clicked.connect(self._pick_color)
        top.insertWidget(2, self.color_button)

    def _build_notes(self, layout: QVBoxLayout) -> None:
        """Whose material is shown, its description, its users and Make unique."""
        self.selection_note = QLabel("")
        self.selection_note.setWordWrap(True)
        self.selection_note.setToolTip("Whose material the editor shows")
        layout.addWidget(self.selection_note)
        self.description = QLabel("")
        self.description.setWordWrap(True)
        self.description.setStyleSheet("color: #9aa4ae;")
        layout.addWidget(self.description)
        users = QHBoxLayout()
        self.users = QLabel("")
        self.users.setWordWrap(True)
        self.users.setToolTip("Objects that use this material: an edit changes all of them")
        users.addWidget(self.users, 1)
        self.unique_button = QPushButton("Make unique")
        self.unique_button.setToolTip("Give the selected object its own copy of this material, "
                                      "so edits change only that object")
        self.unique_button.clicked.connect(self.make_selected_unique)
        users.addWidget(self.unique_button)
        layout.addLayout(users)

    def _build_bands(self, layout: QVBoxLayout) -> None:
        """One editor per band (ToF, radar, visible), stacked when the column is narrow."""
        bands = WrapRow()  # band columns stack when narrow: none is cut off (issue #34)
        self.tof_editor = BandEditor("tof")
        self.radar_editor = BandEditor("radar")
        self.visible_editor = BandEditor("visible")
        for ed in (self.tof_editor, self.radar_editor, self.visible_editor):
            ed.edited.connect(self._on_edited)
            bands.add(ed)
        layout.addWidget(bands)
        self.bands = bands

    def _build_buttons(self, layout: QVBoxLayout) -> None:
        """Invisible to radar / ToF, Save into project as…, Revert to library."""
        buttons = QHBoxLayout()
        self.radar_invisible = QPushButton("Invisible to radar")
        self.radar_invisible.setCheckable(True)
        self.radar_invisible.setToolTip("One click: radar opacity 0 (the radar sees through "
                                        "every object of this material); click again for 1")
        self.radar_invisible.toggled.connect(lambda on: self.set_opacity("radar", on))
        self.tof_invisible = QPushButton("Invisible to ToF")
        self.tof_invisible.setCheckable(True)
        self.tof_invisible.setToolTip("ToF opacity 0 (the camera sees through it, like glass)")
        self.tof_invisible.toggled.connect(lambda on: self.set_opacity("tof", on))
        self.save_button = QPushButton("Save into project as…")
        self.save_button.setToolTip("Store a copy of this material in the project under a new "
                                    "name")
        self.save_button.clicked.connect(self._save_as_dialog)
        self.revert_button = QPushButton("Revert to library")
        self.revert_button.setToolTip("Drop the project's override of this library material")
        self.revert_button.clicked.connect(self.revert_to_library)
        for b in (self.radar_invisible, self.tof_invisible, self.save_button,
                  self.revert_button):
            buttons.addWidget(b)
        buttons.addStretch(1)
        layout.addLayout(buttons)

    @property
    def current(self) -> str:
        """Name of the material being edited."""
        return str(self.combo.currentData() or "")

    def _selected(self) -> tuple[int | None, str | None]:
        """(id, material) of the selected object, or (None, None)."""
        idx = self.document.selected_index()
        if idx is None:
            return None, None
        obj = self.document.project.objects[idx]
        return obj.id, obj.material

    def show_material(self, name: str) -> None:
        """Edit material ``name`` (until the selection or its material changes)."""
        self._followed = self._selected()
        self._pinned = None if name == self._followed[1] else name
        with QSignalBlocker(self.combo):
            idx = self.combo.findData(name)
            if idx >= 0:
                self.combo.setCurrentIndex(idx)
        self.refresh()

    def _follow_selection(self, _key: Any) -> None:
        self.refresh()

    def _target(self) -> str:
        """The material to show: the one picked here, else the selected object's."""
        selected = self._selected()
        if selected != self._followed:
            # Another object, or its material changed (Inspector, undo, reload): follow it.
            self._followed = selected
            self._pinned = None
        return self._pinned or selected[1] or self.current

    def refresh(self, *_: object) -> None:
        """Re-read the material list and the current material's values."""
        table = self.document.material_table()
        project_names = {m.name for m in self.document.project.materials}
        current = self._target()
        with QSignalBlocker(self.combo):
            self.combo.clear()
            for name in sorted(table):
                self.combo.addItem(f"{name} •" if name in project_names else name, name)
            idx = self.combo.findData(current)
            self.combo.setCurrentIndex(max(idx, 0))
        mat = table.get(self.current)
        if mat is None:
            return
        f_radar = SPEED_OF_LIGHT / radar_wavelength_m(self.document.project)
        self.description.setText(self._description(mat, f_radar))
        self.radar_editor.frequency_hz = f_radar
        self.tof_editor.show_values(mat.band("tof"))
        self.radar_editor.show_values(mat.band("radar"))
        self.visible_editor.show_values(mat.band("visible"))
        colour = QColor.fromRgbF(*mat.color_rgb)
        text = "#101010" if colour.lightnessF() > 0.5 else "#f0f0f0"
        self.color_button.setStyleSheet(f"background: {colour.name()}; color: {text};")
        self.color_button.setText("colour " + ", ".join(f"{c:.2f}" for c in mat.color_rgb))
        self._show_users()
        self._show_selection_note()
        set_quietly(self.radar_invisible, mat.band("radar").opacity == 0.0)
        set_quietly(self.tof_invisible, mat.band("tof").opacity == 0.0)
        self.revert_button.setEnabled(self.current in project_names
                                      and self.current in self._library)
        self.assign_button.setEnabled(self.document.selected_index() is not None)

    def _description(self, mat: DualBandMaterial, f_radar: float) -> str:
        """The library's prose, and what the current values do in each band.

        Once the values differ from the library's, its prose is struck through: an edited
        material never shows a stale description.
        """
        lib = library_material(mat.name)
        now = html.escape(summarize_material(mat, f_radar))
        if lib is None or not mat.description:
            return now
        if lib.bands == mat.bands:
            return f"{html.escape(mat.description)}<br>{now}"
        return (f"<s>{html.escape(mat.description)}</s> <i>(library text; the values were "
                f"edited)</i><br><b>Now:</b> {now}")

    def _show_users(self) -> None:
        users = objects_using(self.document, self.current)
        idx = self.document.selected_index()
        selected = self.document.project.objects[idx] if idx is not None else None
        if not users:
            self.users.setText("Used by no object.")
            self.users.setStyleSheet("color: #9aa4ae;")
        elif len(users) == 1:
            self.users.setText(f"Used by {users[0]}.")
            self.users.setStyleSheet("color: #9aa4ae;")
        else:
            self.users.setText(f"Shared by {len(users)} objects: {', '.join(users)} — an edit "
                               "changes all of them.")
            self.users.setStyleSheet("color: #ffb74d;")
        self.unique_button.setEnabled(
            selected is not None and selected.material == self.current and len(users) > 1)

    def _show_selection_note(self) -> None:
        idx = self.document.selected_index()
        if idx is None:
            self.selection_note.setText("No object selected: edits change every object "
                                        "listed below.")
            self.selection_note.setStyleSheet("color: #9aa4ae;")
            return
        obj = self.document.project.objects[idx]
        if obj.material == self.current:
            self.selection_note.setText(f"Material of the selected object <b>"
                                        f"{html.escape(obj.name)}</b>.")
            self.selection_note.setStyleSheet("")
        else:
            self.selection_note.setText(
                f"Not the material of the selected <b>{html.escape(obj.name)}</b> "
                f"({html.escape(obj.material)}): <b>Assign to selected</b> gives it this one.")
            self.selection_note.setStyleSheet("color: #ffb74d;")

    def _ask_shared_edit(self, name: str, users: list[str], obj: str) -> str:
        """Ask whether an edit of shared material ``name`` changes all ``users``."""
        box = QMessageBox(self)
        box.setIcon(QMessageBox.Icon.Question)
        box.setWindowTitle("Shared material")
        box.setText(f"{name} is shared by {len(users)} objects: {', '.join(users)}.")
        box.setInformativeText(f"This edit changes all of them. Change only {obj} by giving "
                               "it its own copy of the material (Make unique)?")
        change_all = box.addButton(f"Change all {len(users)}",
                                   QMessageBox.ButtonRole.AcceptRole)
        only = box.addButton(f"Only {obj} (make unique)", QMessageBox.ButtonRole.AcceptRole)
        box.addButton(QMessageBox.StandardButton.Cancel)
        box.setDefaultButton(only)
        box.exec()
        clicked = box.clickedButton()
        return "all" if clicked is change_all else "unique" if clicked is only else "cancel"

    def _agree_to_edit(self) -> str | None:
        """The material an edit may change now, after asking if it is shared; None: cancel.

        With an object selected whose material is shown and shared by other objects, the
        first edit asks (:attr:`ask_shared_edit`) before anything changes: change all of
        them, or make the selected object's copy unique and edit that.
        """
        name = self.current
        idx = self.document.selected_index()
        if idx is None:
            return name
        obj = self.document.project.objects[idx]
        users = objects_using(self.document, name)
        key = (name, obj.id, tuple(users))
        if obj.material != name or len(users) < 2 or key in self._agreed:
            return name
        answer = self.ask_shared_edit(name, users, obj.name)
        if answer == "all":
            self._agreed.add(key)
            return name
        if answer == "unique":
            new: list[str] = []
            if try_edit(self.editFailed.emit,
                        lambda: new.append(make_unique(self.document, idx))):
                self.show_material(new[0])
                return new[0]
        self.refresh()  # cancelled: the widgets show the material's values again
        return None

    def make_selected_unique(self) -> None:
        """Give the selected object its own copy of the current material and edit that."""
        idx = self.document.selected_index()
        if idx is None:
            return
        new: list[str] = []
        if try_edit(self.editFailed.emit,
                    lambda: new.append(make_unique(self.document, idx))):
            self.show_material(new[0])

    def _pick_color(self) -> None:
        mat = self.document.material_table().get(self.current)
        if mat is None:
            return
        colour = QColorDialog.getColor(QColor.fromRgbF(*mat.color_rgb), self,
                                       f"Colour of {self.current}")
        if colour.isValid():
            self.set_color((colour.redF(), colour.greenF(), colour.blueF()))

    def set_color(self, rgb: tuple[float, float, float]) -> None:
        """Set the current material's visible colour (linear RGB, 0–1)."""
        name = self._agree_to_edit()
        if name is not None:
            try_edit(self.editFailed.emit,
                     lambda: set_material_color(self.document, name, rgb), self.refresh)

    def _on_edited(self, band: str, field: str, shown: Any, *,
                   text: Callable[[str], str] | None = None,
                   widget: QWidget | None = None) -> None:
        """One edit of a band parameter (shown value) through the one validation path.

        ``text(material)`` is the undo text (default "Set ToF reflectance of wood to 0.5").
        """
        editor = {"tof": self.tof_editor, "radar": self.radar_editor,
                  "visible": self.visible_editor}[band]
        widget = widget or editor.widgets.get(field)
        name = self._agree_to_edit()
        if name is None or widget is None:
            return
        commit_value(band_spec(band, field), shown, widget,
                     lambda v, t: set_material_field(self.document, name, band, field, v,
                                                     text=t),
                     text=text(name) if text else None, subject=name)

    def set_opacity(self, band: str, invisible: bool) -> None:  # noqa: FBT001
        """Make the current material invisible (opacity 0) or opaque (1) in ``band``."""
        button = self.tof_invisible if band == "tof" else self.radar_invisible
        what = "invisible" if invisible else "visible"
        words = "ToF" if band == "tof" else band
        self._on_edited(band, "opacity", 0.0 if invisible else 1.0, widget=button,
                        text=lambda name: f"Make {name} {what} to {words}")

    def assign_to_selection(self) -> None:
        """Give the selected object the current material."""
        idx = self.document.selected_index()
        if idx is not None:
            name = self.document.project.objects[idx].name
            try_edit(self.editFailed.emit, lambda: self.document.set_value(
                f"objects[{idx}].material", self.current,
                text=f"Set material of {name} to {self.current}"))

    def revert_to_library(self) -> None:
        """Remove the project's override of the current library material."""
        name = self.current
        try_edit(self.editFailed.emit, lambda: self.document.edit(
            f"Revert material {name}",
            lambda d: d.__setitem__("materials",
                                    [m for m in d["materials"] if m["name"] != name])))

    def _save_as_dialog(self) -> None:
        name, ok = QInputDialog.getText(self, "Save material into project", "New name:",
                                        text=f"{self.current}_custom")
        if ok and name.strip():
            new = name.strip()
            if try_edit(self.editFailed.emit,
                        lambda: save_material_as(self.document, self.current, new)):
                self.show_material(new)
