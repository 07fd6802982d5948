"""The Sensors dock's first page: every rig and every sensor of the project (issue #30).

A tree lists each rig with its sensors (kind, frame rate, trigger offset). Buttons add a
rig, add a ToF camera, radar or RGB camera to the selected rig (on the first rig, into its
empty built-in ``tof``/``radar``/``rgb`` field first), copy a sensor under a new name and
remove a sensor or rig (any sensor but the project's last); the name box renames the
selection (a valid identifier, unique); the timing boxes set the selected sensor's frame
rate and trigger offset. Each edit is one undo step. Picking a sensor makes it the one the
other Sensors pages, the antenna editor and the array analysis edit; picking a rig selects
it in the scene, where the Inspector edits its pose and motion like the first rig's.
"""

from __future__ import annotations

from typing import Any

from PyQt6.QtCore import QSignalBlocker, Qt, pyqtSignal
from PyQt6.QtWidgets import (
    QFormLayout,
    QGroupBox,
    QHBoxLayout,
    QLabel,
    QLineEdit,
    QMenu,
    QPushButton,
    QSizePolicy,
    QToolButton,
    QTreeWidget,
    QTreeWidgetItem,
    QVBoxLayout,
    QWidget,
)

from app.document.document import EditError, ProjectDocument
from app.document.identity import follow_sensor
from app.document.sensors import (
    KIND_WORDS,
    add_rig,
    add_sensor,
    copy_sensor,
    is_built_in,
    removal_refusal,
    remove_rig,
    remove_sensor,
    rename_refusal,
    rename_rig,
    rename_sensor,
    rig_index,
    rig_key,
    sensor_path,
)
from app.editors.field_editors import FieldForm, FieldSpec
from app.widgets.inputs import clear_field_error, try_edit
from app.widgets.wrap_row import WrapRow
from simcore.scene import Project
from simcore.scene.model import sensor_kind

#: The selected sensor's timing (the paths name the built-in ToF camera; the form edits
#: the selected sensor's fields).
TIMING_FIELDS: list[FieldSpec] = [
    FieldSpec("rig.tof.frame_rate_hz", "frame rate", "Hz",
              "frames per second of this sensor; it must be the timeline's rate divided by "
              "a whole number (lowest value: the timeline's rate)", off_text="timeline's",
              decimals=3, step=1.0),
    FieldSpec("rig.tof.trigger_offset_s", "trigger offset", "ms",
              "delay of this sensor's capture after the frame's time; shorter than its "
              "frame period", scale=1e3, decimals=3, step=0.1),
]


def _timing(config: Any, timeline_rate_hz: float) -> tuple[str, str]:
    rate = config.frame_rate_hz
    rate_text = f"{timeline_rate_hz:g} Hz (timeline)" if rate is None else f"{rate:g} Hz"
    return rate_text, f"{config.trigger_offset_s * 1e3:g} ms"


class RigSensorList(QWidget):
    """Every rig and sensor of the project: add, copy, rename, remove; timing per sensor.

    Signals
    -------
    editFailed(str)
        An edit was refused and no field could show why.
    """

    editFailed = pyqtSignal(str)

    def __init__(self, document: ProjectDocument, parent: QWidget | None = None):
        super().__init__(parent)
        self.document = document
        #: What is selected: ("rig", rig name) or ("sensor", sensor name).
        self.selected: tuple[str, str] = ("sensor", "radar")
        self._shown: Project | None = None
        self._listed: Any = None
        outer = QVBoxLayout(self)
        outer.setContentsMargins(2, 2, 2, 2)
        row_of_columns = WrapRow()  # the list and the selection's form side by side
        outer.addWidget(row_of_columns, 1)
        left = QWidget()
        layout = QVBoxLayout(left)
        layout.setContentsMargins(0, 0, 0, 0)
        self.tree = QTreeWidget()
        self.tree.setMinimumSize(360, 140)
        # Its height is what the dock leaves: the buttons below stay in view.
        self.tree.setSizePolicy(QSizePolicy.Policy.Expanding, QSizePolicy.Policy.Ignored)
        self.tree.setColumnCount(4)
        self.tree.setHeaderLabels(["name", "kind", "frame rate", "trigger offset"])
        self.tree.setToolTip("Every rig of the project with its sensors; pick a sensor to "
                             "edit it on the other pages and in the antenna editor, pick a "
                             "rig to edit its pose and motion in the Inspector")
        self.tree.setRootIsDecorated(True)
        self.tree.currentItemChanged.connect(self._on_current)
        row = QHBoxLayout()
        self.add_rig_button = QPushButton("Add rig")
        self.add_rig_button.setToolTip("Add an empty rig 1 m to the left of the last one; "
                                       "move it in the 3D view or the Inspector")
        self.add_rig_button.clicked.connect(self.add_rig)
        self.add_sensor_button = QToolButton()
        self.add_sensor_button.setText("Add sensor")
        self.add_sensor_button.setToolTip("Add a ToF camera, radar or RGB camera with "
                                          "default settings to the selected rig")
        self.add_sensor_button.setPopupMode(QToolButton.ToolButtonPopupMode.InstantPopup)
        menu = QMenu(self.add_sensor_button)
        self.add_actions = {}
        for kind, words in KIND_WORDS.items():
            action = menu.addAction(words[:1].upper() + words[1:])
            action.triggered.connect(lambda _c=False, k=kind: self.add_sensor(k))
            self.add_actions[kind] = action
        self.add_sensor_button.setMenu(menu)
        self.copy_button = QPushButton("Copy")
        self.copy_button.setToolTip("Duplicate the selected sensor on its rig under a new "
                                    "name (its settings and pose are copied)")
        self.copy_button.clicked.connect(self.copy_selected)
        self.remove_button = QPushButton("Remove")
        self.remove_button.clicked.connect(self.remove_selected)
        for b in (self.add_rig_button, self.add_sensor_button, self.copy_button,
                  self.remove_button):
            row.addWidget(b)
        row.addStretch(1)
        layout.addLayout(row)  # the buttons above the list: in view however tall it is
        layout.addWidget(self.tree, 1)
        row_of_columns.add(left, 3)
        box = self.details = QGroupBox("Selected")
        box.setMinimumWidth(300)
        form = QFormLayout(box)
        self.name_edit = QLineEdit()
        self.name_edit.setToolTip("The name: a letter, then letters, digits or underscores; "
                                  "unique. It names the sensor's dataset group, MCAP topic and "
                                  "TF frame. Press Enter to rename")
        self.name_edit.editingFinished.connect(self._on_name)
        form.addRow("name", self.name_edit)
        self.where = QLabel("")
        self.where.setWordWrap(True)
        self.where.setStyleSheet("color: #9aa4ae;")
        form.addRow(self.where)
        self.timing = FieldForm(document, TIMING_FIELDS, path_map=self._timing_path)
        self.timing.editFailed.connect(self.editFailed)
        form.addRow(self.timing)
        row_of_columns.add(box, 2)
        document.projectChanged.connect(self.refresh)
        self.refresh()

    # --- the selection ----------------------------------------------------------------
    def _timing_path(self, path: str) -> str:
        kind, name = self.selected
        project = self.document.project
        if kind != "sensor" or name not in project.sensor_configs():
            return path
        return f"{sensor_path(project, name)}.{path.rsplit('.', 1)[1]}"

    def selected_sensor(self) -> str | None:
        """Name of the selected sensor (None when a rig is selected)."""
        kind, name = self.selected
        return name if kind == "sensor" else None

    def selected_rig(self) -> int:
        """Index (in :meth:`Project.all_rigs`) of the selected rig or the selected sensor's."""
        project = self.document.project
        kind, name = self.selected
        try:
            if kind == "sensor":
                return rig_index(project, project.sensor_rig(name).name)
            return rig_index(project, name)
        except KeyError:
            return 0

    def select(self, kind: str, name: str) -> None:
        """Select sensor or rig ``name`` (``kind`` "sensor" or "rig") in the tree."""
        self.selected = (kind, name)
        self.refresh()
        self._on_current(self.tree.currentItem(), None)

    def _on_current(self, item: QTreeWidgetItem | None, _prev: Any) -> None:
        if item is None:
            return
        kind, name = item.data(0, Qt.ItemDataRole.UserRole)
        self.selected = (kind, name)
        project = self.document.project
        if kind == "sensor":
            cfg = project.sensor_config(name)
            sk = sensor_kind(cfg)
            if sk in ("tof", "radar"):
                self.document.set_current_sensor(sk, name)
        else:
            self.document.select(rig_key(project, rig_index(project, name)))
        self._show_details()

    # --- edits ------------------------------------------------------------------------
    def _run(self, action: Any) -> Any:
        try:
            return action()
        except EditError as exc:
            self.editFailed.emit(str(exc))
            return None

    def add_rig(self) -> None:
        """Add a rig and select it."""
        name = self._run(lambda: add_rig(self.document))
        if name:
            self.select("rig", name)

    def add_sensor(self, kind: str) -> None:
        """Add a ``kind`` sensor to the selected rig and select it."""
        rig = self.selected_rig()
        name = self._run(lambda: add_sensor(self.document, rig, kind))
        if name:
            self.select("sensor", name)

    def copy_selected(self) -> None:
        """Copy the selected sensor and select the copy."""
        name = self.selected_sensor()
        if name is None:
            return
        new = self._run(lambda: copy_sensor(self.document, name))
        if new:
            self.select("sensor", new)

    def remove_selected(self) -> None:
        """Remove the selected sensor or rig (then select its rig, or the first rig)."""
        kind, name = self.selected
        project = self.document.project
        if kind == "sensor":
            rig = project.sensor_rig(name).name if name in project.sensor_configs() else "rig"
            if self._run(lambda: remove_sensor(self.document, name) or True):
                self.select("rig", rig)
        else:
            index = rig_index(project, name)
            if self._run(lambda: remove_rig(self.document, index) or True):
                self.select("rig", project.rig.name)

    def rename(self, new_name: str) -> bool:
        """Rename the selection; a refused name stays in the name box, marked with why."""
        kind, name = self.selected
        project = self.document.project
        if kind == "sensor":
            ok = try_edit(self.editFailed.emit,
                          lambda: rename_sensor(self.document, name, new_name),
                          field=self.name_edit)
        else:
            index = rig_index(project, name)
            ok = try_edit(self.editFailed.emit,
                          lambda: rename_rig(self.document, index, new_name),
                          field=self.name_edit)
        if ok:
            self.select(kind, new_name)
        return ok

    def _on_name(self) -> None:
        text = self.name_edit.text().strip()
        if text != self.selected[1]:
            self.rename(text)

    # --- view -------------------------------------------------------------------------
    def refresh(self, *_: object) -> None:
        """List the rigs and sensors; keep the selection (following a rename or undo)."""
        project = self.document.project
        kind, name = self.selected
        if kind == "sensor":
            was = self._shown.sensor_configs().get(name) if self._shown is not None else None
            sk = sensor_kind(was) if was is not None else None
            now = None
            if sk is not None:
                now = follow_sensor(self._shown, project, name, sk)
            elif name in project.sensor_configs():
                now = name
            self.selected = ("sensor", now) if now else ("rig", project.rig.name)
        elif name not in {r.name for r in project.all_rigs()}:
            self.selected = ("rig", project.rig.name)
        self._shown = project
        rate = project.timeline.frame_rate_hz
        listed = (project.rigs, project.rig.name, project.rig.sensor_configs(), rate,
                  self.selected)
        if listed != self._listed:
            self._listed = listed
            self._fill(project)
        self._show_details()

    def _fill(self, project: Project) -> None:
        rate = project.timeline.frame_rate_hz
        current = None
        with QSignalBlocker(self.tree):
            self.tree.clear()
            for i, rig in enumerate(project.all_rigs()):
                top = QTreeWidgetItem([rig.name, "rig", "", ""])
                top.setData(0, Qt.ItemDataRole.UserRole, ("rig", rig.name))
                top.setToolTip(0, f"Rig {rig.name}: pick it to edit its pose and motion in the "
                               "Inspector" + (" (the first rig)" if i == 0 else ""))
                font = top.font(0)
                font.setBold(True)
                top.setFont(0, font)
                self.tree.addTopLevelItem(top)
                if self.selected == ("rig", rig.name):
                    current = top
                for name, cfg in rig.sensor_configs().items():
                    sk = sensor_kind(cfg)
                    item = QTreeWidgetItem([name, KIND_WORDS[sk], *_timing(cfg, rate)])
                    item.setData(0, Qt.ItemDataRole.UserRole, ("sensor", name))
                    tip = f"{KIND_WORDS[sk]} {name} on rig {rig.name}"
                    if is_built_in(project, name):
                        tip += f" (the first rig's built-in field “{name}”)"
                    refusal = removal_refusal(project, name)
                    if refusal:
                        tip += f"; {refusal}"
                    item.setToolTip(0, tip)
                    top.addChild(item)
                    if self.selected == ("sensor", name):
                        current = item
            self.tree.expandAll()
            for col in range(4):
                self.tree.resizeColumnToContents(col)
            if current is not None:
                self.tree.setCurrentItem(current)

    def _show_details(self) -> None:
        project = self.document.project
        kind, name = self.selected
        self.name_edit.setText(name)
        clear_field_error(self.name_edit)
        is_sensor = kind == "sensor"
        self.timing.setVisible(is_sensor)
        self.copy_button.setEnabled(is_sensor)
        if is_sensor:
            cfg = project.sensor_config(name)
            rig = project.sensor_rig(name).name
            words = KIND_WORDS[sensor_kind(cfg)]
            self.details.setTitle(f"{words[:1].upper() + words[1:]} {name}")
            refusal = removal_refusal(project, name)
            rename_no = rename_refusal(project, name)
            self.where.setText(f"on rig {rig}; its position on the rig and its settings are "
                               f"on the {words} page" if sensor_kind(cfg) != "rgb" else
                               f"on rig {rig}")
            self.remove_button.setEnabled(refusal is None)
            self.remove_button.setToolTip(refusal or f"Remove {words} {name} from rig {rig}")
            self.name_edit.setReadOnly(rename_no is not None)
            self.name_edit.setToolTip(rename_no or "Rename the sensor: a letter, then letters, "
                                      "digits or underscores, unique; press Enter")
            self.timing.refresh()
        else:
            index = rig_index(project, name)
            self.details.setTitle(f"Rig {name}")
            self.where.setText(
                f"{len(project.all_rigs()[index].sensor_configs())} sensors; its pose and "
                "motion are in the Inspector (and the 3D view's gizmo)")
            self.remove_button.setEnabled(index > 0)
            self.remove_button.setToolTip(
                "The first rig cannot be removed: it is the project's “rig” (its sensors "
                "can be removed one by one)" if index == 0
                else f"Remove rig {name} with its sensors")
            self.name_edit.setReadOnly(False)
            self.name_edit.setToolTip("Rename the rig: a letter, then letters, digits or "
                                      "underscores, unique; press Enter")


__all__ = ["TIMING_FIELDS", "RigSensorList"]
