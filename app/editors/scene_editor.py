"""Scene editing panels: the object list and the object/rig inspector."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
from PyQt6.QtCore import QSignalBlocker, Qt, pyqtSignal
from PyQt6.QtGui import QAction
from PyQt6.QtWidgets import (
    QAbstractItemView,
    QComboBox,
    QFileDialog,
    QFormLayout,
    QGroupBox,
    QHBoxLayout,
    QHeaderView,
    QLabel,
    QLineEdit,
    QListWidget,
    QListWidgetItem,
    QMenu,
    QPushButton,
    QScrollArea,
    QStyle,
    QTableWidget,
    QTableWidgetItem,
    QToolButton,
    QVBoxLayout,
    QWidget,
)

from app.dialogs.mesh_import import MeshImportDialog
from app.document.document import RIG, EditError, ProjectDocument
from app.document.scene_edits import (
    KIND_LABELS,
    NEW_OBJECTS,
    add_object,
    delete_object,
    duplicate_object,
    import_mesh,
    rename_object,
)
from app.document.sensors import is_rig_key, radar_wavelength_m, rig_key, rig_of_key, rig_path
from app.editors.field_editors import FieldSpec, bind_number_box, commit_path
from app.editors.person_editor import PersonMotionRows
from app.widgets.inputs import BIG, VectorEdit, set_quietly, spin, try_edit
from simcore.scene import Project, fieldpath
from simcore.scene.model import sensor_kind

#: How the scene list names each kind of sensor on the first rig.
RIG_KIND_WORDS = {"tof": "ToF", "radar": "radar", "rgb": "RGB"}


def rig_label(project: Project) -> str:
    """The first rig's entry in the scene list: the kinds of sensor it carries.

    ``Sensor rig (ToF + radar)`` for the office, ``Sensor rig (radar)`` for a radar-only
    one, ``Sensor rig (no sensors)`` when its sensors sit on the other rigs.
    """
    kinds = [sensor_kind(c) for c in project.rig.sensor_configs().values()]
    words = [w for k, w in RIG_KIND_WORDS.items() if k in kinds]
    return f"Sensor rig ({' + '.join(words) if words else 'no sensors'})"


class ObjectListPanel(QWidget):
    """The scene's objects (and the sensor rig), synced with the selection.

    Double-click a name to rename it. The buttons add, duplicate and delete objects.
    """

    editFailed = pyqtSignal(str)

    def __init__(self, document: ProjectDocument, parent: QWidget | None = None):
        super().__init__(parent)
        self.document = document
        layout = QVBoxLayout(self)
        layout.setContentsMargins(2, 2, 2, 2)
        buttons = QHBoxLayout()
        self.add_button = QToolButton()
        self.add_button.setText("Add ▾")
        self.add_button.setToolTip("Add a primitive, a corner reflector, a point target or "
                                   "import a mesh (STL/OBJ/PLY)")
        self.add_button.setPopupMode(QToolButton.ToolButtonPopupMode.InstantPopup)
        self.add_menu = build_add_menu(self, document, self.editFailed.emit)
        self.add_button.setMenu(self.add_menu)
        self.duplicate_button = QPushButton("Duplicate")
        self.duplicate_button.setToolTip("Copy the selected object (Ctrl+D)")
        self.duplicate_button.clicked.connect(self.duplicate_selected)
        self.delete_button = QPushButton("Delete")
        self.delete_button.setToolTip("Remove the selected object (Del)")
        self.delete_button.clicked.connect(self.delete_selected)
        for w in (self.add_button, self.duplicate_button, self.delete_button):
            buttons.addWidget(w)
        buttons.addStretch(1)
        layout.addLayout(buttons)
        self.list = QListWidget()
        self.list.setToolTip("Objects of the scene; click to select (also by clicking in the "
                             "3D view), double-click to rename")
        self.list.setSelectionMode(QAbstractItemView.SelectionMode.SingleSelection)
        self.list.setEditTriggers(QAbstractItemView.EditTrigger.DoubleClicked
                                  | QAbstractItemView.EditTrigger.EditKeyPressed)
        self.list.currentItemChanged.connect(self._on_current_changed)
        self.list.itemChanged.connect(self._on_item_changed)
        layout.addWidget(self.list, 1)
        self._listed: list[tuple[int, str, str, str]] | None = None
        document.projectChanged.connect(self._rebuild)
        document.selectionChanged.connect(self._select)
        self._rebuild(document.project)

    def _rebuild(self, project: Project) -> None:
        listed = [(o.id, o.name, o.geometry.kind, o.material) for o in project.objects]
        listed.append([r.name for r in project.rigs])
        listed.append(rig_label(project))
        if listed == self._listed:
            return
        self._listed = listed
        with QSignalBlocker(self.list):
            self.list.clear()
            rig = QListWidgetItem(rig_label(project))
            rig.setIcon(self.style().standardIcon(QStyle.StandardPixmap.SP_ComputerIcon))
            font = rig.font()
            font.setBold(True)
            rig.setFont(font)
            rig.setData(Qt.ItemDataRole.UserRole, RIG)
            rig.setToolTip("The first rig, carrying "
                           f"{', '.join(project.rig.sensor_configs()) or 'no sensors'}: "
                           "move it like an object")
            self.list.addItem(rig)
            for i, other in enumerate(project.rigs, start=1):  # issue #30: further rigs
                item = QListWidgetItem(f"Rig {other.name}")
                item.setIcon(rig.icon())
                item.setFont(font)
                item.setData(Qt.ItemDataRole.UserRole, rig_key(project, i))
                item.setToolTip(f"Rig {other.name} with {len(other.sensors)} sensors: move it "
                                "like an object; its sensors are in the Sensors dock")
                self.list.addItem(item)
            for obj in project.objects:
                item = QListWidgetItem(obj.name)
                item.setData(Qt.ItemDataRole.UserRole, obj.id)
                item.setFlags(item.flags() | Qt.ItemFlag.ItemIsEditable)
                item.setToolTip(f"{KIND_LABELS.get(obj.geometry.kind, obj.geometry.kind)}, "
                                f"material {obj.material}, id {obj.id}")
                self.list.addItem(item)
        self._select(self.document.selection)

    def _select(self, key: Any) -> None:
        with QSignalBlocker(self.list):
            self.list.setCurrentItem(None)
            for i in range(self.list.count()):
                item = self.list.item(i)
                if item.data(Qt.ItemDataRole.UserRole) == key and key is not None:
                    self.list.setCurrentItem(item)
                    self.list.scrollToItem(item)
                    break
            else:
                self.list.clearSelection()
        has_object = key is not None and not is_rig_key(key)
        self.duplicate_button.setEnabled(has_object)
        self.delete_button.setEnabled(has_object)

    def _on_current_changed(self, current: QListWidgetItem | None, _prev: Any) -> None:
        self.document.select(None if current is None
                             else current.data(Qt.ItemDataRole.UserRole))

    def _on_item_changed(self, item: QListWidgetItem) -> None:
        key = item.data(Qt.ItemDataRole.UserRole)
        if is_rig_key(key):
            return
        name = item.text().strip()
        if not try_edit(self.editFailed.emit, lambda: rename_object(self.document, key, name)):
            self._listed = None
            self._rebuild(self.document.project)

    def duplicate_selected(self) -> None:
        """Duplicate the selected object."""
        key = self.document.selection
        if key is not None and not is_rig_key(key):
            try_edit(self.editFailed.emit, lambda: duplicate_object(self.document, key))

    def delete_selected(self) -> None:
        """Delete the selected object."""
        key = self.document.selection
        if key is not None and not is_rig_key(key):
            try_edit(self.editFailed.emit, lambda: delete_object(self.document, key))


def build_add_menu(parent: QWidget, document: ProjectDocument, report: Any) -> QMenu:
    """The "Add" menu: primitives, corner reflector, point target, mesh import."""
    menu = QMenu("&Add", parent)
    for kind in NEW_OBJECTS:
        action = QAction(KIND_LABELS[kind], menu)
        action.setToolTip(f"Add a {KIND_LABELS[kind].lower()} on the sensors' boresight, 2 m "
                          "ahead (further if taken), facing them")
        action.triggered.connect(lambda _=False, k=kind: try_edit(
            report, lambda: add_object(document, k)))
        menu.addAction(action)
    menu.addSeparator()
    action = QAction("Import mesh (STL/OBJ/PLY)…", menu)

    def import_dialog() -> None:
        path, _ = QFileDialog.getOpenFileName(parent, "Import mesh", str(document.base_dir),
                                              "Meshes (*.stl *.obj *.ply)")
        if not path:
            return
        try:
            dialog = MeshImportDialog(Path(path), parent)
        except Exception as exc:  # noqa: BLE001 - any unreadable file: say why
            report(f"cannot read {Path(path).name}: {exc}")
            return
        if dialog.exec() == MeshImportDialog.DialogCode.Accepted:
            try_edit(report, lambda: import_mesh(document, Path(path), scale=dialog.scale))

    action.triggered.connect(import_dialog)
    menu.addAction(action)
    return menu


GEOMETRY_FIELDS: dict[str, list[tuple[str, str, str, int, float]]] = {
    # kind: [(field, label, unit, components, minimum)]
    "box": [("size_m", "size", "m", 3, 0.001)],
    "sphere": [("radius_m", "radius", "m", 1, 0.001)],
    "cylinder": [("radius_m", "radius", "m", 1, 0.001), ("height_m", "height", "m", 1, 0.001)],
    "plane": [("size_m", "size", "m", 2, 0.001)],
    "corner_reflector": [("edge_m", "edge length", "m", 1, 0.001)],
    "point_target": [("rcs_m2", "RCS", "m²", 1, 1e-6)],
    "mesh": [("scale", "scale", "", 1, 1e-6)],
    "person": [("height_m", "height", "m", 1, 0.5), ("build", "build", "", 1, 0.6)],
    "ellipsoid": [("radii_m", "semi-axes", "m", 3, 0.001)],
}


def geometry_spec(field: str, label: str, unit: str, n: int) -> FieldSpec:
    """The :class:`FieldSpec` of a geometry field of :data:`GEOMETRY_FIELDS`."""
    return FieldSpec(f"geometry.{field}", label, unit, kind="vector" if n > 1 else "float",
                     components=("x", "y", "z")[:n], dimensions=True)


#: Pose and motion fields of the Inspector (paths below the object or the rig).
POSE_FIELDS = {
    "position_m": FieldSpec("pose.position_m", "position", "m", kind="vector"),
    "rotation_deg": FieldSpec("pose.rotation_deg", "rotation", "°", kind="vector"),
    "velocity_mps": FieldSpec("motion.velocity_mps", "velocity", "m/s", kind="vector"),
    "angular_velocity_dps": FieldSpec("motion.angular_velocity_dps", "angular velocity",
                                      "°/s", kind="vector"),
}


def new_keyframes(keyframes: list[dict[str, Any]], timeline: Any, now: float | None
                  ) -> list[dict[str, Any]]:
    """Keyframes with one more, where "Add keyframe" puts it.

    The first keyframe goes at t = 0 with zero offsets (the base pose). Later ones go at the
    current time ``now`` with the offsets interpolated there (copied after the last one), or,
    when a keyframe is already at ``now`` (or there is no current time), halfway between the
    last keyframe and the timeline's last frame, or one frame period after the last keyframe
    when it is at the end already.
    """
    zero = (0.0, 0.0, 0.0)
    if not keyframes:
        return [{"time_s": 0.0, "position_m": zero, "rotation_deg": zero}]
    times = np.array([k["time_s"] for k in keyframes], dtype=float)
    period = 1.0 / timeline.frame_rate_hz
    end = timeline.frame_time(timeline.n_frames - 1)
    if now is not None and np.all(np.abs(times - now) > 1e-9):
        t = float(now)
    elif times[-1] < end - 0.5 * period:
        t = float(round((0.5 * (times[-1] + end)) / period) * period)
        t = t if t > times[-1] + 1e-9 else end
    else:
        t = float(times[-1] + period)
    t = round(t, 9)
    fields = ("position_m", "rotation_deg")
    if t >= times[-1]:
        values = {f: keyframes[-1][f] for f in fields}
    elif t <= times[0]:
        values = {f: keyframes[0][f] for f in fields}
    else:
        values = {f: tuple(float(np.interp(t, times, [k[f][i] for k in keyframes]))
                           for i in range(3)) for f in fields}
    out = [*keyframes, {"time_s": t, **values}]
    return sorted(out, key=lambda k: k["time_s"])


class ObjectInspector(QScrollArea):
    """Exact values of the selection: name, geometry, material, pose and motion.

    With the rig selected it edits the rig's pose and motion.
    """

    editFailed = pyqtSignal(str)
    editMaterialRequested = pyqtSignal(str)

    def __init__(self, document: ProjectDocument, parent: QWidget | None = None):
        super().__init__(parent)
        self.document = document
        self.setWidgetResizable(True)
        body = QWidget()
        self.setWidget(body)
        outer = QVBoxLayout(body)
        outer.setContentsMargins(4, 4, 4, 4)
        self.heading = QLabel("Nothing selected — click an object in the 3D view or the list")
        self.heading.setWordWrap(True)
        self.heading.setStyleSheet("font-weight: bold;")
        outer.addWidget(self.heading)

        self._build_object_box(outer)
        self._build_pose_box(outer)
        self._build_motion_box(outer)
        outer.addStretch(1)
        self._fit_narrow_column(body)

        #: Current time of the time controls (s); set by the main window.
        self.time_source: Any = None
        document.projectChanged.connect(self.refresh)
        document.selectionChanged.connect(self.refresh)
        self.refresh()

    def _build_object_box(self, outer: QVBoxLayout) -> None:
        """The Object box: name, material (with its Edit… button) and geometry rows."""
        self.object_box = QGroupBox("Object")
        form = QFormLayout(self.object_box)
        self.name_edit = QLineEdit()
        self.name_edit.setToolTip("Unique object name")
        self.name_edit.editingFinished.connect(self._on_name)
        form.addRow("name", self.name_edit)
        mat_row = QHBoxLayout()
        self.material_combo = QComboBox()
        self.material_combo.setToolTip("Dual-band material (library and project materials)")
        self.material_combo.activated.connect(self._on_material)
        self.edit_material_button = QPushButton("Edit…")
        self.edit_material_button.setToolTip("Open this material in the material editor")
        self.edit_material_button.clicked.connect(
            lambda: self.editMaterialRequested.emit(self.material_combo.currentText()))
        mat_row.addWidget(self.material_combo, 1)
        mat_row.addWidget(self.edit_material_button)
        form.addRow("material", mat_row)
        self.geometry_form = QFormLayout()
        form.addRow(self.geometry_form)
        self.geometry_note = QLabel("")
        self.geometry_note.setWordWrap(True)
        self.geometry_note.setStyleSheet("color: #9aa4ae;")
        form.addRow(self.geometry_note)
        self._geometry_kind: str | None = None
        self._geometry_widgets: dict[str, Any] = {}
        outer.addWidget(self.object_box)

    def _build_pose_box(self, outer: QVBoxLayout) -> None:
        """The Pose box: position and rotation in the world frame."""
        self.pose_box = QGroupBox("Pose (world frame, x-y-z extrinsic Euler)")
        pform = QFormLayout(self.pose_box)
        self.position_edit = VectorEdit(suffix="m", decimals=3, step=0.05,
                                        tooltip="position of the origin (m, world frame)")
        self._bind_vector(POSE_FIELDS["position_m"], self.position_edit, "Move")
        self.rotation_edit = VectorEdit(suffix="°", decimals=2, step=5.0, minimum=-360,
                                        maximum=360,
                                        tooltip="rotation about world x, then y, then z (°)")
        self._bind_vector(POSE_FIELDS["rotation_deg"], self.rotation_edit, "Rotate")
        pform.addRow("position", self.position_edit)
        pform.addRow("rotation", self.rotation_edit)
        outer.addWidget(self.pose_box)

    def _build_motion_box(self, outer: QVBoxLayout) -> None:
        """The Motion box: constant velocities, the keyframe repeat mode and keyframes."""
        self.motion_box = QGroupBox("Motion")
        mform = QFormLayout(self.motion_box)
        self.velocity_edit = VectorEdit(suffix="m/s", decimals=3, step=0.1,
                                        tooltip="constant linear velocity (m/s, world frame)")
        self._bind_vector(POSE_FIELDS["velocity_mps"], self.velocity_edit)
        self.angular_edit = VectorEdit(suffix="°/s", decimals=2, step=5.0,
                                       tooltip="constant angular velocity about world axes "
                                               "through the origin (°/s)")
        self._bind_vector(POSE_FIELDS["angular_velocity_dps"], self.angular_edit)
        self.repeat_combo = QComboBox()
        self.repeat_combo.addItems(["hold", "loop", "back_and_forth"])
        self.repeat_combo.setToolTip("After the last keyframe: hold the pose, loop, or play "
                                     "back and forth")
        self.repeat_combo.activated.connect(
            lambda _i: self._set_motion("repeat", self.repeat_combo.currentText()))
        mform.addRow("velocity", self.velocity_edit)
        mform.addRow("angular velocity", self.angular_edit)
        mform.addRow("keyframes repeat", self.repeat_combo)
        self._build_keyframes(mform)
        outer.addWidget(self.motion_box)

    def _build_keyframes(self, form: QFormLayout) -> None:
        """The keyframe table and its Add / Remove buttons, as rows of ``form``."""
        self.keyframe_table = QTableWidget(0, 7)
        self.keyframe_table.setHorizontalHeaderLabels(
            ["t (s)", "x (m)", "y (m)", "z (m)", "rx (°)", "ry (°)", "rz (°)"])
        self.keyframe_table.horizontalHeader().setSectionResizeMode(
            QHeaderView.ResizeMode.Stretch)
        self.keyframe_table.setToolTip("Keyframes: offsets from the base pose at a time (s); "
                                       "position linear, rotation spherical interpolation. "
                                       "Use either keyframes or constant velocities.")
        self.keyframe_table.setMinimumHeight(90)
        self.keyframe_table.itemChanged.connect(self._on_keyframe_edited)
        form.addRow(self.keyframe_table)
        kf_buttons = QHBoxLayout()
        self.add_keyframe_button = QPushButton("Add keyframe")
        self.add_keyframe_button.setToolTip(
            "Add a keyframe at the current time (the first one at t = 0, the base pose), "
            "with the offsets the object has then; when one is already there, halfway "
            "between the last keyframe and the last frame")
        self.add_keyframe_button.clicked.connect(self._add_keyframe)
        self.remove_keyframe_button = QPushButton("Remove keyframe")
        self.remove_keyframe_button.clicked.connect(self._remove_keyframe)
        kf_buttons.addWidget(self.add_keyframe_button)
        kf_buttons.addWidget(self.remove_keyframe_button)
        kf_buttons.addStretch(1)
        form.addRow(kf_buttons)

    @staticmethod
    def _fit_narrow_column(body: QWidget) -> None:
        """Let long form rows wrap and vector boxes fit their text (narrow Scene column)."""
        # In a narrow Scene column (1366×768) a row whose label and fields do not fit puts
        # its fields under the label instead of pushing them past the dock's edge (issue
        # #34: position, rotation and velocity were cut off behind a horizontal scroll bar).
        for form_layout in body.findChildren(QFormLayout):
            form_layout.setRowWrapPolicy(QFormLayout.RowWrapPolicy.WrapLongRows)
        for vector in body.findChildren(VectorEdit):
            vector.fit_text()

    # --- paths ------------------------------------------------------------------------
    def _base_path(self) -> str | None:
        key = self.document.selection
        rig = rig_of_key(self.document.project, key)
        if rig is not None:
            return rig_path(rig)
        idx = self.document.selected_index()
        return None if idx is None else f"objects[{idx}]"

    def _subject(self) -> str:
        """What the selection is called in undo texts: the object's name or "sensor rig"."""
        if self.document.selection == RIG:
            return "sensor rig"
        rig = rig_of_key(self.document.project, self.document.selection)
        if rig is not None:
            return f"rig {self.document.project.all_rigs()[rig].name}"
        idx = self.document.selected_index()
        return "" if idx is None else self.document.project.objects[idx].name

    def _set(self, sub: str, value: Any, text: str, field: QWidget | None = None) -> None:
        """Set one field of the selection; a refused value stays in ``field``, marked.

        The undo text names the object: "Move desk1_top", "Edit motion of sensor rig".
        """
        base = self._base_path()
        if base is None:
            return
        joiner = " of " if " " in text else " "
        text = f"{text}{joiner}{self._subject()}"
        try_edit(self.editFailed.emit,
                 lambda: self.document.set_value(f"{base}.{sub}", value, text=text),
                 self.refresh, field=field)

    def _commit(self, spec: FieldSpec, shown: Any, widget: QWidget, verb: str = "") -> None:
        """Set field ``spec`` of the selection through the one validation path.

        The undo text names the object: "Move desk1_top", "Set size of desk1_top to
        1 × 0.6 × 0.03 m"; a refusal is shown at ``widget`` in the field's unit.
        """
        base = self._base_path()
        if base is None:
            return
        text = f"{verb} {self._subject()}" if verb else None
        commit_path(self.document, spec, shown, widget, path=f"{base}.{spec.path}",
                    text=text, subject=self._subject())

    def _bind_vector(self, spec: FieldSpec, widget: VectorEdit, verb: str = "") -> None:
        for i, box in enumerate(widget.boxes):
            bind_number_box(box, spec, widget, i)
        widget.edited.connect(lambda v: self._commit(spec, v, widget, verb))

    def _set_motion(self, field: str, value: Any, widget: QWidget | None = None) -> None:
        self._set(f"motion.{field}", value, "Edit motion", widget)

    # --- view -------------------------------------------------------------------------
    def refresh(self, *_: object) -> None:
        """Show the selection's current values."""
        project = self.document.project
        key = self.document.selection
        idx = self.document.selected_index()
        rig_i = rig_of_key(project, key)
        is_rig = rig_i is not None
        has = is_rig or idx is not None
        self.object_box.setVisible(idx is not None)
        # Hidden, not greyed: greyed boxes would show the last selection's values.
        self.pose_box.setVisible(has)
        self.motion_box.setVisible(has)
        if not has:
            self.heading.setText("Nothing selected — click an object in the 3D view or list")
            return
        if rig_i is not None:
            rig = project.all_rigs()[rig_i]
            self.heading.setText(("Sensor rig" if rig_i == 0 else f"Rig {rig.name}")
                                 + " — body frame x forward, y left, z up")
            pose, motion = rig.pose, rig.motion
        else:
            assert idx is not None
            obj = project.objects[idx]
            kind = obj.geometry.kind
            self.heading.setText(f"{obj.name} — {KIND_LABELS.get(kind, kind)} (id {obj.id})")
            pose, motion = obj.pose, obj.motion
            set_quietly(self.name_edit, obj.name)
            with QSignalBlocker(self.material_combo):
                self.material_combo.clear()
                self.material_combo.addItems(sorted(self.document.material_table()))
                self.material_combo.setCurrentText(obj.material)
            self._show_geometry(obj.geometry)
        self.position_edit.set_value(pose.position_m)
        self.rotation_edit.set_value(pose.rotation_deg)
        self.velocity_edit.set_value(motion.velocity_mps)
        self.angular_edit.set_value(motion.angular_velocity_dps)
        with QSignalBlocker(self.repeat_combo):
            self.repeat_combo.setCurrentText(motion.repeat)
        with QSignalBlocker(self.keyframe_table):
            self.keyframe_table.setRowCount(len(motion.keyframes))
            for row, kf in enumerate(motion.keyframes):
                values = [kf.time_s, *kf.position_m, *kf.rotation_deg]
                for col, v in enumerate(values):
                    self.keyframe_table.setItem(row, col, QTableWidgetItem(f"{v:g}"))

    def _show_geometry(self, geometry: Any) -> None:
        kind = geometry.kind
        if kind != self._geometry_kind:
            while self.geometry_form.rowCount():
                self.geometry_form.removeRow(0)
            self._geometry_widgets = {}
            for field, label, unit, n, minimum in GEOMETRY_FIELDS.get(kind, []):
                tip = f"{label} ({unit})" if unit else label
                spec = geometry_spec(field, label, unit, n)
                w: Any
                if n == 1:
                    # Wide range: the model refuses bad sizes, with the reason at the field.
                    del minimum
                    w = spin(minimum=-BIG, maximum=BIG, decimals=4, step=0.01, suffix=unit,
                             tooltip=tip)
                    bind_number_box(w, spec)
                    w.valueChanged.connect(lambda v, s=spec, w=w: self._commit(s, v, w))
                else:
                    w = VectorEdit(labels=("x", "y", "z")[:n], suffix=unit, decimals=3,
                                   step=0.05, tooltip=tip)
                    w.fit_text()
                    self._bind_vector(spec, w)
                self.geometry_form.addRow(label, w)
                self._geometry_widgets[field] = w
            self._person_rows = (PersonMotionRows(self.geometry_form, self._set)
                                 if kind == "person" else None)
            self._geometry_kind = kind
        for field, w in self._geometry_widgets.items():
            value = getattr(geometry, field)
            if isinstance(w, VectorEdit):
                w.set_value(value)
            else:
                set_quietly(w, float(value))
        note = ""
        if kind == "corner_reflector":
            lam = radar_wavelength_m(self.document.project)
            note = (f"peak RCS at {lam * 1e3:.2f} mm: {geometry.rcs_m2(lam):.2f} m² "
                    f"(4πa⁴/3λ²); opening along local +z")
        elif kind == "mesh":
            note = f"file: {geometry.path}"
        elif kind == "point_target":
            note = "radar-only point scatterer (invisible to the ToF camera)"
        elif kind == "person" and getattr(self, "_person_rows", None) is not None:
            self._person_rows.show(geometry)  # type: ignore[union-attr]
            note = ("17 ellipsoid segments; stands on its origin facing local +x "
                    "(docs/people.md)")
        self.geometry_note.setText(note)

    # --- edits ------------------------------------------------------------------------
    def _on_name(self) -> None:
        key = self.document.selection
        if key is None or is_rig_key(key):
            return
        name = self.name_edit.text().strip()
        try_edit(self.editFailed.emit, lambda: rename_object(self.document, key, name),
                 self.refresh)

    def _on_material(self, _index: int) -> None:
        name = self.material_combo.currentText()
        base = self._base_path()
        if base is None:
            return
        text = f"Set material of {self._subject()} to {name}"
        try_edit(self.editFailed.emit,
                 lambda: self.document.set_value(f"{base}.material", name, text=text),
                 self.refresh, field=self.material_combo)

    def _keyframes(self) -> list[dict[str, Any]]:
        base = self._base_path()
        if base is None:
            return []
        motion = fieldpath.get(self.document.project, base).motion
        return [k.model_dump() for k in motion.keyframes]

    def _on_keyframe_edited(self, item: QTableWidgetItem) -> None:
        keyframes = self._keyframes()
        row, col = item.row(), item.column()
        try:
            value = float(item.text())
        except ValueError:
            self.editFailed.emit(f"keyframe {row + 1}: {item.text()!r} is not a number")
            self.refresh()
            return
        kf = keyframes[row]
        if col == 0:
            kf["time_s"] = value
        elif col <= 3:
            p = list(kf["position_m"])
            p[col - 1] = value
            kf["position_m"] = tuple(p)
        else:
            r = list(kf["rotation_deg"])
            r[col - 4] = value
            kf["rotation_deg"] = tuple(r)
        self._set_motion("keyframes", keyframes)

    def _add_keyframe(self) -> None:
        now = float(self.time_source()) if self.time_source is not None else None
        keyframes = new_keyframes(self._keyframes(), self.document.project.timeline, now)
        base = self._base_path()
        if base is None:
            return

        def mutate(d: dict[str, Any]) -> None:
            node = fieldpath.get(d, base)
            node["motion"]["keyframes"] = keyframes
            node["motion"]["velocity_mps"] = (0.0, 0.0, 0.0)
            node["motion"]["angular_velocity_dps"] = (0.0, 0.0, 0.0)

        try:
            self.document.edit(f"Add keyframe to {self._subject()}", mutate)
        except EditError as exc:
            self.editFailed.emit(str(exc))

    def _remove_keyframe(self) -> None:
        keyframes = self._keyframes()
        if not keyframes:
            return
        row = self.keyframe_table.currentRow()
        keyframes.pop(row if 0 <= row < len(keyframes) else -1)
        self._set_motion("keyframes", keyframes)
