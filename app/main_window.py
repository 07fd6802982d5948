"""The main window: 3D viewport in the centre, editors and live panels in docks."""

from __future__ import annotations

import time
from pathlib import Path
from typing import Any

from PyQt6.QtCore import QEvent, QObject, QPointF, QSettings, QSize, Qt, QTimer, QUrl
from PyQt6.QtGui import (
    QAction,
    QCloseEvent,
    QColor,
    QDesktopServices,
    QIcon,
    QKeyEvent,
    QKeySequence,
    QPainter,
    QPainterPath,
    QPen,
    QPixmap,
    QPolygonF,
    QShortcut,
)
from PyQt6.QtWidgets import (
    QAbstractButton,
    QAbstractSpinBox,
    QApplication,
    QComboBox,
    QDockWidget,
    QFileDialog,
    QFrame,
    QLabel,
    QLineEdit,
    QMainWindow,
    QMenu,
    QMessageBox,
    QPlainTextEdit,
    QProgressDialog,
    QScrollArea,
    QStyle,
    QTabBar,
    QTextEdit,
    QToolButton,
    QWidget,
)

from app.dialogs.export import DatasetExportJob, ExportDialog, completion_box, export_panel_images
from app.dialogs.help import install_help_menu
from app.dialogs.recording_compare import add_compare_recording_action
from app.dialogs.scenario_export import add_export_spec_action
from app.dialogs.scene_import import build_import_scene_action
from app.document.document import EditError, ProjectDocument, ProjectError, remember_last_folder
from app.document.validation import describe_problem
from app.editors.antenna_editor import AntennaEditor
from app.editors.material_editor import MaterialEditor
from app.editors.scene_editor import ObjectInspector, ObjectListPanel, build_add_menu
from app.editors.sensor_editor import SensorEditor
from app.editors.timeline_editor import TimelineEditor
from app.frame_view import FrameView
from app.panels.base import LivePanel, cache_axes
from app.panels.range_azimuth import RangeAzimuthPanel
from app.panels.range_doppler import RangeDopplerPanel
from app.panels.range_profile import RangeProfilePanel
from app.panels.rgb import RgbPanel
from app.panels.spectrogram import SpectrogramPanel
from app.panels.tof import TofPanel
from app.simulation import SimulationController
from app.view.viewport import SceneViewport
from app.widgets.time_controls import TimeBar, TimeController
from simcore import preflight
from simcore.resources import EXAMPLES_DIR
from simcore.scene import Project
from simcore.scene.model import sensor_kind

MAX_RECENT = 8
#: An edit whose frame would need more than this (bytes, s) is applied only when confirmed.
CONFIRM_MEMORY_BYTES = 4 * 2**30
CONFIRM_SECONDS_PER_FRAME = 3.0
#: A frame computing longer than this (s) shows its time and enables "Stop frame".
SLOW_FRAME_S = 0.5


#: Window size on a large screen; a smaller screen gets what fits (initial_window_size).
PREFERRED_SIZE = (1720, 1020)


def initial_window_size(screen: Any) -> QSize:
    """The preferred window size, shrunk to 95 % of the screen's available area."""
    w, h = PREFERRED_SIZE
    if screen is not None:
        area = screen.availableGeometry()
        w, h = min(w, int(area.width() * 0.95)), min(h, int(area.height() * 0.95))
    return QSize(w, h)


def scrolled(widget: QWidget) -> QScrollArea:
    """``widget`` in a frameless scroll area: a dock stays usable when the window is small."""
    area = QScrollArea()
    area.setWidget(widget)
    area.setWidgetResizable(True)
    area.setFrameShape(QFrame.Shape.NoFrame)
    area.setObjectName(f"scroll_{type(widget).__name__}")
    return area


def _bytes(n: float) -> str:
    for unit in ("B", "KiB", "MiB", "GiB", "TiB"):
        if n < 1024 or unit == "TiB":
            return f"{n:.1f} {unit}" if unit != "B" else f"{int(n)} B"
        n /= 1024
    return f"{n:.1f} TiB"


#: Readable names of the engine's stages in the status bar (unknown names are shown as is).
STAGE_LABELS = {
    "snapshot": "snapshot", "render_tof": "render ToF", "render_tof_samples": "ToF samples",
    "render_radar": "render radar", "render_rgb": "render RGB",
    "render_background": "background", "tof": "ToF", "tof_albedo": "ToF albedo",
    "radar_scatterers": "scatterers", "radar_background_scatterers": "background scatterers",
    "radar_synthesis": "IF synthesis", "radar_background_synthesis": "background IF",
    "radar_receiver": "receiver", "radar_prepare": "prepare", "dsp": "DSP", "rgb": "RGB",
    "radar_labels": "labels", "radar_label_scatterers": "label scatterers"}


def history_icon(*, redo: bool) -> QIcon:
    """The standard undo (or redo) icon: a curved arrow turning back (or forward)."""
    themed = QIcon.fromTheme(QIcon.ThemeIcon.EditRedo if redo else QIcon.ThemeIcon.EditUndo)
    if not themed.isNull():
        return themed
    pixmap = QPixmap(32, 32)
    pixmap.fill(Qt.GlobalColor.transparent)
    painter = QPainter(pixmap)
    painter.setRenderHint(QPainter.RenderHint.Antialiasing)
    if redo:
        painter.translate(32, 0)
        painter.scale(-1, 1)
    pen = QPen(QColor("#d0d4da"), 3.0)
    pen.setCapStyle(Qt.PenCapStyle.RoundCap)
    painter.setPen(pen)
    path = QPainterPath(QPointF(8, 13))
    path.cubicTo(QPointF(16, 6), QPointF(29, 9), QPointF(26, 20))
    path.cubicTo(QPointF(24, 26), QPointF(18, 27), QPointF(14, 26))
    painter.drawPath(path)
    painter.setBrush(QColor("#d0d4da"))
    painter.setPen(Qt.PenStyle.NoPen)
    painter.drawPolygon(QPolygonF([QPointF(3, 14), QPointF(12, 6), QPointF(13, 18)]))
    painter.end()
    return QIcon(pixmap)


class SpaceGoesToWidgets(QObject):
    """Let Space reach the focused button, field or list instead of Play / pause.

    Qt offers a key to the focus widget first as a ShortcutOverride event; accepting it
    for widgets that use Space themselves makes the window-wide shortcut step aside.
    """

    #: Widgets for which Space means something (lists and views keep it for playback).
    TAKERS = (QAbstractButton, QLineEdit, QAbstractSpinBox, QComboBox, QTextEdit,
              QPlainTextEdit)

    def eventFilter(self, obj: QObject | None, event: QEvent | None) -> bool:  # noqa: N802, D102
        if (event is not None and event.type() == QEvent.Type.ShortcutOverride
                and isinstance(event, QKeyEvent) and event.key() == Qt.Key.Key_Space
                and event.modifiers() == Qt.KeyboardModifier.NoModifier
                and isinstance(obj, self.TAKERS)):
            event.accept()
        return False


def _without_antennas(project: Project) -> tuple[Any, ...]:
    """What the cost check reads of a project's rigs, DSP and timeline, antennas left out.

    Every rig's pose and motion and every sensor's settings, each radar's Tx/Rx layout
    blanked (an antenna drag is checked by the model alone, like an object's).
    """
    sensors = {name: cfg.model_copy(update={"tx": (), "rx": ()})
               if sensor_kind(cfg) == "radar" else cfg
               for name, cfg in project.sensor_configs().items()}
    rigs = [(r.name, r.pose, r.motion) for r in project.all_rigs()]
    return rigs, sensors, project.dsp, project.timeline


def stage_label(key: str) -> str:
    """Readable name of an engine stage: ``radar_background_prepare`` → "background prepare"."""
    if key in STAGE_LABELS:
        return STAGE_LABELS[key]
    words = key.removeprefix("radar_").replace("_", " ")
    return words.replace("tof", "ToF").replace("rgb", "RGB").replace("dsp", "DSP")


class MainWindow(QMainWindow):
    """tofradar's main window.

    Parameters
    ----------
    project_path : path, optional
        Project to open at start (an empty project otherwise).
    settings : QSettings, optional
        Where recent files and the window layout are kept (tests pass a temporary file).
    """

    def __init__(self, project_path: str | Path | None = None, *,
                 settings: QSettings | None = None):
        super().__init__()
        self.settings = settings if settings is not None else QSettings("tofradar", "tofradar")
        self.document = ProjectDocument(parent=self)
        self.sim = SimulationController(self)
        self.time = TimeController(self.document, self)
        # Connected before any view: an edit's frame is requested first, so the simulation
        # computes it while the editors and the 3D view update.
        self.document.projectChanged.connect(self._schedule_frame)
        self.viewport = SceneViewport(self.document)
        self.setCentralWidget(self.viewport)
        self.last_view: FrameView | None = None
        #: Main-thread time spent showing each of the last frames (ms).
        self.frame_draw_ms: list[float] = []
        self.last_error_dialog: QMessageBox | None = None
        self.export_job: DatasetExportJob | None = None
        self.export_dialog: ExportDialog | None = None
        self.completion_dialog: QMessageBox | None = None
        self.progress_dialog: QProgressDialog | None = None
        self._closing = False
        self._cost_cache: tuple[Project, preflight.CostEstimate, list[str]] | None = None
        self.document.before_push = self._check_edit

        self._build_docks()
        self._build_explore_docks()
        self._build_spectrogram_dock()
        cache_axes(self)
        self._build_actions()
        self._build_menus()
        self._build_toolbar()
        self._build_status_bar()
        self._connect()
        self.resize(initial_window_size(self.screen()))  # 1720×1020, or what fits the screen
        self.size_docks(initial_window_size(self.screen()))
        self._default_state = self.saveState()  # View → Reset layout
        self._restore_layout()
        self._update_title()
        if project_path is not None:
            self.open_project(project_path, ask=False)
        else:
            self._schedule_frame()

    # --- construction -----------------------------------------------------------------
    def _dock(self, title: str, widget: QWidget, area: Qt.DockWidgetArea, name: str
              ) -> QDockWidget:
        dock = QDockWidget(title, self)
        dock.setObjectName(name)
        dock.setWidget(widget)
        dock.setAllowedAreas(Qt.DockWidgetArea.AllDockWidgetAreas)
        self.addDockWidget(area, dock)
        return dock

    def _build_docks(self) -> None:
        doc = self.document
        left, right, bottom = (Qt.DockWidgetArea.LeftDockWidgetArea,
                               Qt.DockWidgetArea.RightDockWidgetArea,
                               Qt.DockWidgetArea.BottomDockWidgetArea)
        self.object_list = ObjectListPanel(doc)
        self.inspector = ObjectInspector(doc)
        self.material_editor = MaterialEditor(doc)
        self.sensor_editor = SensorEditor(doc)
        self.antenna_editor = AntennaEditor(doc)
        self.tof_panel = TofPanel()
        self.profile_panel = RangeProfilePanel()
        self.rd_panel = RangeDopplerPanel()
        self.ra_panel = RangeAzimuthPanel()
        self.rgb_panel = RgbPanel()
        self.docks: dict[str, QDockWidget] = {}
        self.setCorner(Qt.Corner.BottomRightCorner, Qt.DockWidgetArea.RightDockWidgetArea)
        # The editors' tab group spans under the scene docks too (issue #34): at 1366×768
        # the antenna board, the Sensors and Materials columns get room to be read.
        self.setCorner(Qt.Corner.BottomLeftCorner, Qt.DockWidgetArea.BottomDockWidgetArea)
        self.docks["scene"] = self._dock("Scene", self.object_list, left, "dock_scene")
        self.docks["inspector"] = self._dock("Inspector", self.inspector, left, "dock_inspector")
        self.docks["tof"] = self._dock("ToF camera", self.tof_panel, right, "dock_tof")
        self.docks["profile"] = self._dock("Range profile", self.profile_panel, right,
                                           "dock_profile")
        self.docks["rd"] = self._dock("Range–Doppler", self.rd_panel, right, "dock_rd")
        self.docks["ra"] = self._dock("Range–azimuth", self.ra_panel, right, "dock_ra")
        self.splitDockWidget(self.docks["rd"], self.docks["ra"], Qt.Orientation.Horizontal)
        # The RGB camera is optional: its panel shares the ToF dock's place and is shown
        # only while the rig carries one (_follow_rig_sensors).
        self.docks["rgb"] = self._dock("RGB camera", self.rgb_panel, right, "dock_rgb")
        self.tabifyDockWidget(self.docks["tof"], self.docks["rgb"])
        self.docks["tof"].raise_()
        self.docks["antennas"] = self._dock("Antenna array", scrolled(self.antenna_editor),
                                            bottom, "dock_antennas")
        self.docks["materials"] = self._dock("Materials", scrolled(self.material_editor),
                                             bottom, "dock_materials")
        self.docks["sensors"] = self._dock("Sensors", self.sensor_editor, bottom, "dock_sensors")
        self.timeline_editor = TimelineEditor(self.document)
        self.docks["timeline"] = self._dock("Timeline and seed", scrolled(self.timeline_editor),
                                            bottom, "dock_timeline")
        # One tab group built in one go: a group re-formed step by step leaves stale tab
        # bars of its earlier forms drawn over the other docks.
        for name in ("materials", "sensors", "timeline"):
            self.tabifyDockWidget(self.docks["antennas"], self.docks[name])
        self.docks["antennas"].raise_()
        self.resizeDocks([self.docks["scene"], self.docks["tof"]], [390, 690],
                         Qt.Orientation.Horizontal)
        self.resizeDocks([self.docks["tof"], self.docks["profile"], self.docks["rd"]],
                         [300, 260, 360], Qt.Orientation.Vertical)
        self.resizeDocks([self.docks["scene"], self.docks["inspector"]], [300, 600],
                         Qt.Orientation.Vertical)
        self.resizeDocks([self.docks["antennas"]], [300], Qt.Orientation.Vertical)
        #: The live panels of the project's sensors (drawn, exported), by title: those of a
        #: kind the project has no sensor of are left out (_follow_rig_sensors).
        self.panels: dict[str, LivePanel] = {}
        #: Every live panel by title, with its dock's key (in the order they are listed).
        self.all_panels: dict[str, tuple[str, LivePanel]] = {
            "ToF camera": ("tof", self.tof_panel), "Range profile": ("profile", self.profile_panel),
            "Range-Doppler": ("rd", self.rd_panel), "Range-azimuth": ("ra", self.ra_panel),
            "RGB camera": ("rgb", self.rgb_panel)}
        #: Whether the project had each dock's sensor kind when last followed (a dock is
        #: shown or hidden when that changes; a missing key: follow the project again).
        self._kind_shown: dict[str, bool] = {}
        self._dock_titles: dict[str, str] = {}
        for _key, panel in self.all_panels.values():
            panel.sensorChanged.connect(lambda _name: self._title_docks())
        self._follow_rig_sensors()

    def _build_spectrogram_dock(self) -> None:
        """Micro-Doppler spectrogram (issue 29): a tab of the bottom dock group.

        The bottom is wide (time runs across) and already tabbed, so the right-hand
        panels keep their geometry. Fed by every frame (also while hidden, so its
        history is complete); it follows the project and the selected object on its own.
        """
        self.spectrogram_panel = SpectrogramPanel()
        self.docks["spectrogram"] = self._dock(
            "Micro-Doppler", self.spectrogram_panel, Qt.DockWidgetArea.BottomDockWidgetArea,
            "dock_spectrogram")
        self.tabifyDockWidget(self.docks["timeline"], self.docks["spectrogram"])
        self.docks["antennas"].raise_()
        self._kind_shown.pop("spectrogram", None)
        self._follow_rig_sensors()
        self.sim.frameReady.connect(self.spectrogram_panel.show_frame)
        doc = self.document
        doc.projectChanged.connect(lambda *_: self.spectrogram_panel.set_project(doc.project))
        doc.selectionChanged.connect(lambda key: self.spectrogram_panel.set_selected(
            key if isinstance(key, int) and not isinstance(key, bool) else None))
        self.spectrogram_panel.set_project(doc.project)

    def size_docks(self, size: QSize) -> None:
        """Share a window of ``size`` between the docks so that each stays readable.

        Issue #34: at 1366×768 the scene column and the live panels give up some width so
        that the editors' tab group below (spanning under the scene column) shows the
        antenna board ≥ 200 px wide beside its table, and every Sensors/Materials column.
        """
        w, h = size.width(), size.height()
        left = int(min(390, max(260, 0.22 * w)))
        right = int(min(690, max(480, 0.44 * w)))
        self.resizeDocks([self.docks["scene"], self.docks["tof"]], [left, right],
                         Qt.Orientation.Horizontal)
        bottom = int(min(300, max(250, 0.33 * h)))
        self.resizeDocks([self.docks["antennas"]], [bottom], Qt.Orientation.Vertical)
        # The scene list keeps half of what is left above the editors on a short screen.
        self.resizeDocks([self.docks["scene"], self.docks["inspector"]],
                         [300, 600] if h >= 900 else [1, 1], Qt.Orientation.Vertical)

    def _build_explore_docks(self) -> None:
        """Timeline & seed editor's errors, keyframes at the current time (issue #17)."""
        self.timeline_editor.editFailed.connect(self.show_status_error)
        self.inspector.time_source = lambda: self.time.time_s
        remember_last_folder(self.recent_files())  # Save As starts there
        self._build_explore_links()

    def _action(self, text: str, slot: Any, *, shortcut: Any = None, tip: str = "",
                checkable: bool = False) -> QAction:
        action = QAction(text, self)
        if shortcut is not None:
            if isinstance(shortcut, list):
                action.setShortcuts(shortcut)
            else:
                action.setShortcut(shortcut)
        if tip:
            action.setToolTip(tip)
            action.setStatusTip(tip)
        action.setCheckable(checkable)
        action.triggered.connect(slot)
        self.addAction(action)
        return action

    def _build_actions(self) -> None:
        a = self._action
        keys = QKeySequence.StandardKey
        self.new_action = a("&New", lambda: self.new_project(), shortcut=keys.New,
                            tip="Start an empty project")
        self.open_action = a("&Open…", lambda: self.open_dialog(),
                             shortcut=QKeySequence.StandardKey.Open, tip="Open a project file")
        self.save_action = a("&Save", lambda: self.save(), shortcut=QKeySequence.StandardKey.Save,
                             tip="Save the project (atomic write)")
        self.save_as_action = a("Save &As…", lambda: self.save_as(),
                                shortcut=QKeySequence("Ctrl+Shift+S"),
                                tip="Save the project under a new name")
        self.export_dataset_action = a("Export &dataset (HDF5 / Zarr / MCAP)…",
                                       lambda: self.export_dataset_dialog(),
                                       tip="Run the headless dataset job on this project")
        self.export_images_action = a("Export panel &images…",
                                      lambda: self.export_images_dialog(),
                                      tip="Save PNG images of the 3D view and the live panels")
        self.quit_action = a("&Quit", lambda: self.close(), shortcut=QKeySequence("Ctrl+Q"))
        self.undo_action = self.document.undo_stack.createUndoAction(self, "&Undo")
        self.undo_action.setShortcut(QKeySequence("Ctrl+Z"))
        self.redo_action = self.document.undo_stack.createRedoAction(self, "&Redo")
        self.redo_action.setShortcuts([QKeySequence("Ctrl+Shift+Z"), QKeySequence("Ctrl+Y")])
        self.addAction(self.undo_action)
        self.addAction(self.redo_action)
        self.duplicate_action = a("&Duplicate", lambda: self.object_list.duplicate_selected(),
                                  shortcut=QKeySequence("Ctrl+D"), tip="Duplicate the selection")
        self.delete_action = a("De&lete", lambda: self.object_list.delete_selected(),
                               tip="Delete the selected object (Del in the scene list or "
                                   "the 3D view)")
        # Del deletes objects only where objects have focus: in a table or a text field it
        # keeps its usual meaning.
        for widget in (self.object_list, self.viewport):
            shortcut = QShortcut(QKeySequence(QKeySequence.StandardKey.Delete), widget)
            shortcut.setContext(Qt.ShortcutContext.WidgetWithChildrenShortcut)
            shortcut.activated.connect(self.object_list.delete_selected)
        self.rename_action = a("&Rename", lambda: self._rename_selected(),
                               shortcut=QKeySequence("F2"), tip="Rename the selected object")
        self.play_action = a("Play / pause", lambda: self.time.set_playing(not self.time.playing),
                             shortcut=QKeySequence("Space"), tip="Play / pause (Space)")
        self.step_forward_action = a("Next frame", lambda: self.time.step(1),
                                     shortcut=QKeySequence("."))
        self.step_back_action = a("Previous frame", lambda: self.time.step(-1),
                                  shortcut=QKeySequence(","))
        self.first_frame_action = a("First frame", lambda: self.time.set_index(0),
                                    shortcut=QKeySequence("Home"))
        self.cancel_frame_action = a("Stop frame", lambda: self.cancel_frame(),
                                     shortcut=QKeySequence("Esc"),
                                     tip="Stop the frame being computed (Esc)")
        self.cancel_frame_action.setIcon(self.style().standardIcon(
            QStyle.StandardPixmap.SP_BrowserStop))
        self.cancel_frame_action.setEnabled(False)
        self.reset_camera_action = a("Reset camera", lambda: self.viewport.reset_camera(),
                                     shortcut=QKeySequence("R"), tip="Look at the whole scene")
        self.show_fov_action = a("Show sensor fields of view", self._toggle_fov, checkable=True,
                                 tip="Draw the ToF (green) and radar (orange) frustums")
        self.show_fov_action.setChecked(True)

    def _build_menus(self) -> None:
        bar = self.menuBar()
        file_menu = bar.addMenu("&File")
        file_menu.addActions([self.new_action, self.open_action])
        self.recent_menu = QMenu("Open &recent", self)
        self.recent_menu.aboutToShow.connect(self._fill_recent_menu)
        file_menu.addMenu(self.recent_menu)
        self.examples_menu = QMenu("Open &example", self)
        for path in sorted(EXAMPLES_DIR.glob("*.json")):
            act = self.examples_menu.addAction(path.stem)
            act.triggered.connect(lambda _=False, p=path: self.open_project(p))
        file_menu.addMenu(self.examples_menu)
        file_menu.addAction(build_import_scene_action(self, self.document,
                                                      self.show_status_error))
        file_menu.addSeparator()
        file_menu.addActions([self.save_action, self.save_as_action])
        file_menu.addSeparator()
        file_menu.addActions([self.export_dataset_action, self.export_images_action])
        self.compare_recording_action = add_compare_recording_action(self, file_menu)
        self.export_spec_action = add_export_spec_action(self, file_menu)
        file_menu.addSeparator()
        file_menu.addAction(self.quit_action)
        edit = bar.addMenu("&Edit")
        edit.addActions([self.undo_action, self.redo_action])
        edit.addSeparator()
        self.add_menu = build_add_menu(self, self.document, self.show_status_error)
        edit.addMenu(self.add_menu)
        edit.addActions([self.duplicate_action, self.rename_action, self.delete_action])
        view = bar.addMenu("&View")
        view.addActions([self.reset_camera_action, self.show_fov_action])
        self.label_colours_action = self._action(
            "Colour detections by object", self.set_colour_by_label, checkable=True,
            tip="Colour the radar detections in the range–Doppler and range–azimuth maps by "
                "their ground-truth object (grey: noise, no object in the cell)")
        view.addAction(self.label_colours_action)
        view.addActions([self.truth_action, self.freeze_action, self.difference_action])
        view.addSeparator()
        for dock in self.docks.values():
            view.addAction(dock.toggleViewAction())
        view.addSeparator()
        self.reset_layout_action = self._action(
            "Reset &layout", lambda: self.reset_layout(),
            tip="Put every panel back where it was at the first start")
        view.addAction(self.reset_layout_action)
        sim = bar.addMenu("&Simulation")
        sim.addActions([self.play_action, self.step_back_action, self.step_forward_action,
                        self.first_frame_action, self.cancel_frame_action])
        help_menu = bar.addMenu("&Help")
        self.help_actions = install_help_menu(self, help_menu)

    def _build_toolbar(self) -> None:
        icon = self.style().standardIcon
        pix = QStyle.StandardPixmap
        for action, kind in ((self.new_action, pix.SP_FileIcon),
                             (self.open_action, pix.SP_DialogOpenButton),
                             (self.save_action, pix.SP_DialogSaveButton),
                             (self.delete_action, pix.SP_TrashIcon),
                             (self.reset_camera_action, pix.SP_BrowserReload)):
            action.setIcon(icon(kind))
        # Curved arrows (the desktop theme's edit-undo/redo when it has them), not the
        # browser's back/forward arrows.
        self.undo_action.setIcon(history_icon(redo=False))
        self.redo_action.setIcon(history_icon(redo=True))
        tb = self.addToolBar("Main")
        tb.setObjectName("toolbar_main")
        tb.setMovable(False)
        tb.setToolButtonStyle(Qt.ToolButtonStyle.ToolButtonTextBesideIcon)
        tb.addActions([self.new_action, self.open_action, self.save_action])
        tb.addSeparator()
        for action in (self.undo_action, self.redo_action):
            # Icon only: the actions' text names the step ("Undo Move sphere").
            button = QToolButton()
            button.setDefaultAction(action)
            button.setToolButtonStyle(Qt.ToolButtonStyle.ToolButtonIconOnly)
            tb.addWidget(button)
        tb.addSeparator()
        add_button = tb.addAction("Add ▾")
        add_button.setToolTip("Add an object")
        add_button.setMenu(self.add_menu)
        add_button.triggered.connect(lambda: self.add_menu.exec(self.cursor().pos()))
        tb.addActions([self.duplicate_action, self.delete_action])
        tb.addSeparator()
        tb.addAction(self.reset_camera_action)
        tb.addSeparator()
        self.time_bar = TimeBar(self.time)
        tb.addWidget(self.time_bar)
        tb.addAction(self.cancel_frame_action)

    def _build_status_bar(self) -> None:
        sb = self.statusBar()
        self.busy_label = QLabel("○ idle")
        self.busy_label.setToolTip("Simulation worker state")
        self.fps_label = QLabel("— fps")
        self.fps_label.setToolTip("Simulated frames per second (completed frames, last 5 s)")
        self.stage_label = QLabel("")
        self.stage_label.setToolTip("Wall time of each pipeline stage of the last frame (ms)")
        self.render_label = QLabel("")
        self.render_label.setToolTip("Render passes so far and latency from edit to display")
        for w in (self.stage_label, self.render_label, self.fps_label, self.busy_label):
            sb.addPermanentWidget(w)
        # The worker state is polled: a label flipping with every frame would cost a
        # window repaint of its own each time.
        self._busy_timer = QTimer(self)
        self._busy_timer.setInterval(250)
        self._busy_timer.timeout.connect(self._update_busy)
        self._busy_timer.start()

    def _connect(self) -> None:
        doc = self.document
        doc.projectChanged.connect(self._follow_rig_sensors)
        doc.dirtyChanged.connect(self._update_title)
        doc.pathChanged.connect(self._update_title)
        doc.undo_stack.indexChanged.connect(self._update_title)
        self.time.indexChanged.connect(self._on_time_changed)
        self.sim.frameReady.connect(self._on_frame)
        self.sim.failed.connect(self._on_sim_failed)
        self.sim.cancelled.connect(self._on_cancelled)
        for editor in (self.object_list, self.inspector, self.material_editor,
                       self.sensor_editor, self.antenna_editor, self.viewport):
            editor.editFailed.connect(self.show_status_error)
        self.inspector.editMaterialRequested.connect(self._edit_material)

    def set_colour_by_label(self, on: bool) -> None:  # noqa: FBT001 - Qt slot
        """Colour detection markers by ground-truth object (True) or plainly (False)."""
        for panel in (self.rd_panel, self.ra_panel):
            panel.colour_by_label = bool(on)
            if panel.view is not None:
                panel.show_frame(panel.view)
        if self.label_colours_action.isChecked() != bool(on):
            self.label_colours_action.setChecked(bool(on))

    # --- ground truth, linked selection, A/B comparison (issue #17) -----------------------
    def _build_explore_links(self) -> None:
        """Ground-truth marks, detection ↔ object selection and A/B comparison in the panels."""
        self.truth_action = self._action(
            "Show ground truth", self.set_show_truth, checkable=True,
            tip="Mark each object's true range, radial velocity and azimuth on the radar "
                "panels and outline the objects in the ToF images")
        self.truth_action.setChecked(True)
        self.freeze_action = self._action(
            "Freeze reference A", lambda: self.freeze_reference(),
            shortcut=QKeySequence("Ctrl+Shift+F"),
            tip="Keep the current range profile and maps as reference A (all radar panels)")
        self.difference_action = self._action(
            "Show difference A − B", self.set_show_difference, checkable=True,
            tip="Show the current radar panels minus the frozen reference (dB)")
        self.difference_action.setEnabled(False)
        #: What the last clicked detection measured (also in the panels' read-out line).
        self.detection_info = ""
        for panel in self.comparable_panels():
            panel.detectionClicked.connect(self.select_detection)
            panel.objectClicked.connect(self.document.select)
        self.document.selectionChanged.connect(self._follow_selection)
        self.document.projectChanged.connect(self._follow_project_in_panels)
        self._follow_project_in_panels()
        self.space_filter = SpaceGoesToWidgets(self)
        app = QApplication.instance()
        if app is not None:
            app.installEventFilter(self.space_filter)

    def comparable_panels(self) -> list[LivePanel]:
        """The radar panels (A/B comparison, clickable detections)."""
        return [self.profile_panel, self.rd_panel, self.ra_panel]

    def _follow_project_in_panels(self, *_: object) -> None:
        for panel in (self.tof_panel, self.rgb_panel, *self.comparable_panels()):
            panel.set_project(self.document.project)

    def _follow_selection(self, key: object) -> None:
        selected = key if isinstance(key, int) and not isinstance(key, bool) else None
        for panel in (self.tof_panel, *self.comparable_panels()):
            panel.set_selected(selected)

    def set_show_truth(self, on: bool) -> None:  # noqa: FBT001 - Qt slot
        """Show or hide the ground-truth marks and outlines."""
        for panel in (self.tof_panel, *self.comparable_panels()):
            panel.set_show_truth(bool(on))
        if self.truth_action.isChecked() != bool(on):
            self.truth_action.setChecked(bool(on))

    def freeze_reference(self) -> None:
        """Freeze every radar panel's current frame as reference A."""
        for panel in self.comparable_panels():
            panel.freeze_reference()
        self.difference_action.setEnabled(self.last_view is not None)
        if self.last_view is not None:
            self.statusBar().showMessage(
                f"Reference A: frame {self.last_view.index + 1}. Edit the configuration, "
                "then View → Show difference A − B", 8000)

    def set_show_difference(self, on: bool) -> None:  # noqa: FBT001 - Qt slot
        """Show the radar panels as the difference to the frozen reference."""
        for panel in self.comparable_panels():
            panel.set_show_difference(bool(on))
        if self.difference_action.isChecked() != bool(on):
            self.difference_action.setChecked(bool(on))

    def select_detection(self, index: int) -> None:
        """Select the object of detection ``index`` of the shown frame and say what it is."""
        radar = None if self.last_view is None else self.last_view.radar
        if radar is None or not 0 <= index < len(radar.detections):
            return
        det = radar.detections
        oid = -1 if det.object_id is None else int(det.object_id[index])
        names = {o.id: o.name for o in self.document.project.objects}
        what = names.get(oid, f"object {oid}") if oid >= 0 else "noise (no object)"
        self.detection_info = (
            f"detection {index + 1}: SNR {det.snr_db[index]:.1f} dB, range "
            f"{det.range_m[index]:.3f} m, velocity {det.velocity_mps[index]:+.3f} m/s, "
            f"azimuth {det.azimuth_deg[index]:+.1f}°, elevation "
            f"{det.elevation_deg[index]:+.1f}° → {what}")
        for panel in self.comparable_panels():
            panel.readout.setText(self.detection_info)
            panel.readout.setToolTip(self.detection_info)  # the line may be cut
        self.statusBar().showMessage(self.detection_info, 20000)
        if oid >= 0:
            self.document.select(oid)

    #: The sensor kind whose data (or settings) each dock shows: a dock is shown only
    #: while the project has a sensor of its kind (issue 40: radar-only, ToF-only).
    DOCK_KINDS = {"tof": "tof", "rgb": "rgb", "profile": "radar", "rd": "radar",
                  "ra": "radar", "spectrogram": "radar", "antennas": "radar"}

    def _follow_rig_sensors(self, *_: object) -> None:
        """Show the panels of the kinds of sensor the project has; hide the others.

        A dock is shown when the project gains a sensor of its kind and hidden when it has
        none left (its View-menu entry disabled); while it has one, the user's choice to
        close it stands. Only the shown panels are drawn and exported.
        """
        project = self.document.project
        has = {kind: bool(project.sensors_of_kind(kind)) for kind in ("tof", "radar", "rgb")}
        self.panels.clear()
        self.panels.update((title, panel) for title, (key, panel) in self.all_panels.items()
                           if has[self.DOCK_KINDS[key]])
        for key, kind in self.DOCK_KINDS.items():
            dock = self.docks.get(key)
            if dock is None or self._kind_shown.get(key) == has[kind]:
                continue
            self._kind_shown[key] = has[kind]
            dock.toggleViewAction().setEnabled(has[kind])
            dock.setVisible(has[kind])
        self._title_docks()

    def _title_docks(self) -> None:
        """Name the sensor each live panel shows in its dock's title (when not built in)."""
        for key, panel in self.all_panels.values():
            base = self._dock_titles.setdefault(key, self.docks[key].windowTitle())
            name = panel.sensor
            shown = base if name in (None, panel.sensor_kind) else f"{base} · {name}"
            if self.docks[key].windowTitle() != shown:
                self.docks[key].setWindowTitle(shown)

    # --- simulation -------------------------------------------------------------------
    def _on_sim_failed(self, message: str) -> None:
        self.show_status_error(f"simulation: {message}")
        for panel in self.panels.values():
            panel.show_error(f"frame {self.time.index + 1} could not be computed: {message}")
        self.time.frame_done()  # playback goes on with the next frame

    def _schedule_frame(self, *_: object) -> None:
        if not self._closing:
            # Ask at once: the worker keeps only the newest request, so a burst of edits
            # costs at most one stale frame, and waiting for the event loop would add the
            # time of every repaint the edit caused.
            self._request_frame()

    def _request_frame(self) -> None:
        if not self._closing:
            self.sim.request(self.document.project, self.time.index,
                             base_dir=self.document.base_dir)

    def _on_time_changed(self, _index: int) -> None:
        if not self.time.playing:
            # While playing, the 3D view follows the frames shown (_on_frame), so scene
            # and point cloud change together in one render per shown frame.
            self.viewport.set_time(self.time.time_s)
        self._schedule_frame()

    def _on_frame(self, view: FrameView) -> None:
        start = time.perf_counter()
        if self.time.playing:
            # Compute the next frame while this one is drawn.
            after = (self.time.next_index + 1) % max(self.time.n_frames, 1)
            self.sim.prefetch(self.document.project, self.time.next_index,
                              base_dir=self.document.base_dir, then=after)
        self.last_view = view
        try:
            for panel in self.panels.values():
                panel.show_frame(view)  # each panel shows its own errors
            self._show_in_viewport(view)
            self._show_frame_status(view)
        finally:
            self.time.frame_done()
            self.frame_draw_ms.append((time.perf_counter() - start) * 1e3)
            del self.frame_draw_ms[:-200]

    def _show_in_viewport(self, view: FrameView) -> None:
        try:
            self.viewport.show_frame(view)
        except Exception as exc:  # noqa: BLE001 - shown; the panels and playback go on
            self.show_status_error(f"3D view: {type(exc).__name__}: {exc}")

    def _show_frame_status(self, view: FrameView) -> None:
        stages = [f"{stage_label(k)} {v:.0f}" for k, v in view.timings_ms.items()
                  if k not in ("total", "wall")]
        self.stage_label.setText(" · ".join(stages) + " ms" if stages else "")
        self.render_label.setText(f"renders {view.render_count} · latency "
                                  f"{view.latency_ms:.0f} ms")
        fps = self.sim.frames_per_second()
        wall = view.timings_ms.get("wall", 0.0)
        self.fps_label.setText(f"{fps:.1f} fps" if fps > 0 else
                               f"{1e3 / wall:.1f} fps" if wall > 0 else "— fps")
        if view.notes:
            self.statusBar().showMessage("; ".join(view.notes), 8000)

    def _update_busy(self) -> None:
        busy_for = self.sim.busy_for_s
        slow = busy_for > SLOW_FRAME_S
        text = (f"● computing {busy_for:.0f} s — Esc stops" if slow
                else "● playing" if self.time.playing else "○ idle")
        if self.busy_label.text() != text:
            self.busy_label.setText(text)
            self.busy_label.setStyleSheet("color: #ffb74d;" if slow else "color: #81c784;")
        if self.cancel_frame_action.isEnabled() != slow:
            self.cancel_frame_action.setEnabled(slow)

    # --- cost and cancel --------------------------------------------------------------
    def memory_budget_bytes(self) -> int:
        """Largest memory a frame may need: the core's default (80 % of what is free)."""
        return preflight.default_memory_budget()

    def _cost(self, project: Project, *, like: tuple[Project, list[str]] | None = None
              ) -> tuple[preflight.CostEstimate, list[str]]:
        """Cost estimate and preflight problems of ``project``.

        ``like`` is a project whose problems ``project`` shares when only its objects,
        materials, names or antenna positions differ: the full preflight (its clearance
        check alone takes 40 scene snapshots, ≈ 0.1–0.3 s) runs for edits of the rig, the
        DSP or the timeline, not for every step of an object or antenna drag; the model
        still validates every such edit.
        """
        cached = self._cost_cache
        if cached is not None and cached[0] is project:
            return cached[1], cached[2]
        base = self.document.base_dir
        cost = preflight.estimate_cost(project, base_dir=base)
        if like is not None:
            before = like[0]
            # Antenna positions (a drag) are checked by the model alone, like objects.
            if _without_antennas(before) == _without_antennas(project):
                return cost, like[1]
        # Meshes come from the user's own file dialog (any folder); an empty scene is where
        # every new project starts: neither is refused while editing.
        problems = [p for p in preflight.check(project, base_dir=base, memory_budget_bytes=2**62,
                                               parse_meshes=False, allow_outside_paths=True)
                    if not p.startswith("objects: the scene has no objects")]
        return cost, problems

    def _check_edit(self, old: Project, new: Project) -> None:
        """Refuse an edit that preflight finds wrong or that costs more than allowed.

        Problems the project already had are not held against the edit. A frame over the
        memory budget is refused; one over :data:`CONFIRM_MEMORY_BYTES` or
        :data:`CONFIRM_SECONDS_PER_FRAME` needs :meth:`confirm_costly`.
        """
        old_cost, old_problems = self._cost(old)
        cost, problems = self._cost(new, like=(old, old_problems))
        new_problems = [p for p in problems if p not in old_problems]
        if new_problems:
            raise EditError("; ".join(describe_problem(p) for p in new_problems))
        self._cost_cache = (new, cost, problems)
        heavier = (cost.memory_bytes > old_cost.memory_bytes
                   or cost.seconds_per_frame > old_cost.seconds_per_frame)
        if not heavier:
            return
        budget = self.memory_budget_bytes()
        if cost.memory_bytes > budget:
            field, part = cost.memory_parts[0]
            raise EditError(f"not applied: a frame would need ≈ {_bytes(cost.memory_bytes)} "
                            f"of memory, over the budget of {_bytes(budget)} (80 % of the "
                            f"free memory); most of it ({_bytes(part)}) for {field}")
        if (cost.memory_bytes > CONFIRM_MEMORY_BYTES
                or cost.seconds_per_frame > CONFIRM_SECONDS_PER_FRAME) \
                and not self.confirm_costly(cost):
            raise EditError(f"not applied (declined): a frame would need ≈ "
                            f"{_bytes(cost.memory_bytes)} of memory and ≈ "
                            f"{cost.seconds_per_frame:.0f} s")

    def confirm_costly(self, cost: preflight.CostEstimate) -> bool:
        """Ask whether to apply a costly configuration (tests replace this method)."""
        answer = QMessageBox.question(
            self, "Costly configuration",
            f"Every frame of this configuration would need about "
            f"{_bytes(cost.memory_bytes)} of memory and {cost.seconds_per_frame:.0f} s "
            f"({cost.render_pixels:,} render pixels, {cost.scatterers:,} radar scatterers, "
            f"{cost.transforms:,} NUFFTs).\n\nApply it anyway? A running frame can be "
            "stopped with Esc.",
            QMessageBox.StandardButton.Yes | QMessageBox.StandardButton.No,
            QMessageBox.StandardButton.No)
        return answer == QMessageBox.StandardButton.Yes

    def cancel_frame(self) -> bool:
        """Stop the frame being computed (the simulation process restarts)."""
        index = self.time.index
        if not self.sim.busy:
            return False
        self.time.set_playing(False)
        self.sim.cancel()
        shown = "nothing" if self.last_view is None else f"frame {self.last_view.index + 1}"
        for panel in self.panels.values():
            panel.show_error(f"frame {index + 1} was stopped; this is {shown}")
        self.statusBar().showMessage(
            f"Frame {index + 1} stopped. Step or press ▶ to compute it again, or change "
            "the configuration (Undo).", 15000)
        self._update_busy()
        return True

    def _on_cancelled(self) -> None:
        self.time.frame_done()

    def frame_is_current(self) -> bool:
        """True when the panels show the frame of the latest project state and time."""
        return (self.last_view is not None
                and self.last_view.request_serial == self.sim.latest_serial)

    # --- messages ---------------------------------------------------------------------
    def show_status_error(self, message: str) -> None:
        """Show an edit or simulation error in the status bar."""
        self.statusBar().showMessage(f"⚠ {message}", 12000)

    def show_error(self, title: str, message: str) -> QMessageBox:
        """Show an error dialog (window-modal, does not block the event loop)."""
        box = QMessageBox(QMessageBox.Icon.Critical, title, message,
                          QMessageBox.StandardButton.Ok, self)
        box.setWindowModality(Qt.WindowModality.WindowModal)
        box.setAttribute(Qt.WidgetAttribute.WA_DeleteOnClose)
        self.last_error_dialog = box
        box.open()
        return box

    def _update_title(self, *_: object) -> None:
        name = self.document.display_name  # "office (example)" for a bundled template
        self.setWindowTitle(f"{name}[*] — tofradar")
        self.setWindowModified(self.document.is_dirty)

    def _toggle_fov(self) -> None:
        on = self.show_fov_action.isChecked()
        self.viewport.set_sensor_fov_visible(tof=on, radar=on)

    def _edit_material(self, name: str) -> None:
        self.material_editor.show_material(name)
        self.docks["materials"].show()
        self.docks["materials"].raise_()

    def _rename_selected(self) -> None:
        idx = self.document.selected_index()
        if idx is None:
            return
        self.docks["inspector"].raise_()
        self.inspector.name_edit.setFocus()
        self.inspector.name_edit.selectAll()

    # --- files ------------------------------------------------------------------------
    def ask_save_changes(self) -> QMessageBox.StandardButton:
        """Ask whether to save unsaved changes (tests replace this method)."""
        buttons = (QMessageBox.StandardButton.Save | QMessageBox.StandardButton.Discard
                   | QMessageBox.StandardButton.Cancel)
        return QMessageBox.question(self, "Unsaved changes",
                                    "The project has unsaved changes. Save them first?",
                                    buttons, QMessageBox.StandardButton.Save)

    def maybe_save(self) -> bool:
        """True when it is fine to drop the current project (saved, discarded or clean)."""
        if not self.document.is_dirty:
            return True
        answer = self.ask_save_changes()
        if answer == QMessageBox.StandardButton.Save:
            return self.save()
        return answer == QMessageBox.StandardButton.Discard

    def new_project(self) -> None:
        """Start an empty project."""
        if self.maybe_save():
            self.document.new()

    def open_dialog(self) -> None:
        """Ask for a project file and open it."""
        if not self.maybe_save():
            return
        start = str(self.document.base_dir)
        path, _ = QFileDialog.getOpenFileName(self, "Open project", start,
                                              "tofradar projects (*.json);;All files (*)")
        if path:
            self.open_project(path, ask=False)

    def open_project(self, path: str | Path, *, ask: bool = True) -> bool:
        """Open ``path``; a bad file shows an error dialog and keeps the current project."""
        if ask and not self.maybe_save():
            return False
        try:
            self.document.open(path)
        except ProjectError as exc:
            self.show_error("Cannot open project", str(exc))
            return False
        self._add_recent(Path(path).resolve())
        self.statusBar().showMessage(f"Opened {path}", 5000)
        return True

    def save(self) -> bool:
        """Save to the current file (asks for a name if there is none)."""
        if self.document.path is None:
            return self.save_as()
        return self.save_to(self.document.path)

    def save_as(self) -> bool:
        """Ask for a file name and save there."""
        start = self.document.suggested_save_path()  # last used folder, never the examples
        path, _ = QFileDialog.getSaveFileName(self, "Save project as", str(start),
                                              "tofradar projects (*.json)")
        if not path:
            return False
        if not path.endswith(".json"):
            path += ".json"
        return self.save_to(Path(path))

    def save_to(self, path: Path) -> bool:
        """Save the project to ``path`` (atomically)."""
        try:
            target = self.document.save(path)
        except OSError as exc:
            self.show_error("Cannot save project", f"{path}: {exc}")
            return False
        self._add_recent(target)
        self.statusBar().showMessage(f"Saved {target}", 5000)
        return True

    def recent_files(self) -> list[str]:
        """Recently opened or saved project files, newest first."""
        value = self.settings.value("recent_files", [])
        if isinstance(value, str):
            value = [value]
        return [str(v) for v in (value or [])]

    def _add_recent(self, path: Path) -> None:
        files = [str(path)] + [f for f in self.recent_files() if f != str(path)]
        self.settings.setValue("recent_files", files[:MAX_RECENT])

    def _fill_recent_menu(self) -> None:
        self.recent_menu.clear()
        files = self.recent_files()
        if not files:
            self.recent_menu.addAction("(none)").setEnabled(False)
        for f in files:
            act = self.recent_menu.addAction(f)
            act.triggered.connect(lambda _=False, p=f: self.open_project(p))

    # --- exports ----------------------------------------------------------------------
    def export_dataset_dialog(self) -> ExportDialog:
        """Ask for destination, format, frames or duration, seed and previews; then export.

        The dialog is window-modal and returned (tests fill it in and accept it).
        """
        # Proposed where Save As would start: never inside the bundled examples.
        folder = self.document.suggested_save_path().parent
        dialog = ExportDialog(self.document.project, folder, self)
        dialog.setWindowModality(Qt.WindowModality.WindowModal)
        dialog.setAttribute(Qt.WidgetAttribute.WA_DeleteOnClose)

        def start() -> None:
            c = dialog.choice()
            self.export_dataset(c.out, n_frames=c.n_frames, seed=c.seed,
                                preview_dir=c.preview_dir)

        dialog.accepted.connect(start)
        self.export_dialog = dialog
        dialog.open()
        return dialog

    def open_url(self, url: QUrl) -> bool:
        """Open a file or folder with the desktop's application (tests replace this)."""
        return QDesktopServices.openUrl(url)

    def export_dataset(self, out: Path, *, n_frames: int, seed: int | None = None,
                       preview_dir: Path | None = None) -> DatasetExportJob:
        """Write ``n_frames`` frames into ``out`` with a cancellable progress dialog.

        ``seed`` defaults to the project's; ``preview_dir`` also writes PNG previews of
        every frame there (as ``tofradar run --preview``). The export ends with a dialog
        that opens the folder or the dataset (:func:`app.dialogs.export.completion_box`).
        """
        job = DatasetExportJob(self.document.project, self.document.base_dir, Path(out),
                               n_frames=n_frames, seed=seed, preview_dir=preview_dir,
                               parent=self)
        dialog = QProgressDialog(f"Writing {out.name}…", "Cancel", 0, n_frames, self)
        dialog.setWindowTitle("Export dataset")
        dialog.setWindowModality(Qt.WindowModality.WindowModal)
        dialog.setMinimumDuration(0)
        dialog.setAutoClose(False)
        dialog.setAutoReset(False)
        dialog.canceled.connect(job.cancel)

        def progress(done: int, total: int) -> None:
            if dialog.wasCanceled():
                job.cancel()
                return
            dialog.setMaximum(total)
            dialog.setValue(done)

        job.progress.connect(progress)

        def finished(message: str) -> None:
            dialog.close()
            self.statusBar().showMessage(message, 10000)
            box = completion_box(self, message, Path(out), preview_dir, self.open_url)
            box.setWindowModality(Qt.WindowModality.WindowModal)
            box.setAttribute(Qt.WidgetAttribute.WA_DeleteOnClose)
            self.completion_dialog = box
            box.open()

        def failed(message: str) -> None:
            dialog.close()
            self.show_error("Export failed", message)

        job.done.connect(finished)
        job.failed.connect(failed)
        self.export_job = job
        self.progress_dialog = dialog
        dialog.show()
        job.start()
        return job

    def export_images_dialog(self) -> None:
        """Ask for a folder and save PNGs of the panels there."""
        folder = QFileDialog.getExistingDirectory(self, "Export panel images",
                                                  str(self.document.base_dir))
        if folder:
            files = self.export_images(Path(folder))
            self.statusBar().showMessage(f"Saved {len(files)} images to {folder}", 8000)

    def export_images(self, folder: Path) -> list[Path]:
        """Save PNGs of the 3D view and every live panel into ``folder``."""
        for panel in self.panels.values():
            panel.draw_now()
        widgets: dict[str, QWidget] = {"3D view": self.viewport, **self.panels}
        return export_panel_images(widgets, folder)

    # --- layout -----------------------------------------------------------------------
    def _restore_layout(self) -> None:
        """Restore the window geometry and dock layout saved by the last session."""
        geometry = self.settings.value("window/geometry")
        state = self.settings.value("window/state")
        if geometry is not None:
            self.restoreGeometry(geometry)
        if state is not None:
            self.restoreState(state)
            # The saved layout keeps the user's choice for the kinds the project has (a
            # closed Range–azimuth dock stays closed); the docks of the others are hidden.
            project = self.document.project
            self._kind_shown = {key: True for key, kind in self.DOCK_KINDS.items()
                                if project.sensors_of_kind(kind)}
            self._follow_rig_sensors()
        self.hide_stale_tab_bars()

    def reset_layout(self) -> None:
        """Put every dock back where a first start puts it, sized to the screen."""
        self.restoreState(self._default_state)
        self.resize(initial_window_size(self.screen()))
        self._kind_shown.clear()
        self._follow_rig_sensors()
        self.hide_stale_tab_bars()

    def hide_stale_tab_bars(self) -> list[QTabBar]:
        """Hide dock tab bars left over from a tab group's earlier forms; return them.

        Qt (6.x) keeps the tab bar of a two-dock group visible after a third dock joins it,
        drawn over whatever dock lies there (the "Antenna array | Materials" bar over the
        Inspector). A live bar shows exactly one tab group of two or more visible docks.
        """
        by_title = {d.windowTitle(): d for d in self.docks.values()}
        stale = []
        for bar in self.findChildren(QTabBar):
            if bar.parent() is not self or not bar.isVisibleTo(self):
                continue
            titles = {bar.tabText(i) for i in range(bar.count())}
            first = by_title.get(bar.tabText(0)) if bar.count() else None
            group = set() if first is None else {first.windowTitle()} | {
                d.windowTitle() for d in self.tabifiedDockWidgets(first) if d.isVisibleTo(self)}
            if len(titles) < 2 or titles != group:
                bar.hide()
                stale.append(bar)
        return stale

    def _save_layout(self) -> None:
        self.settings.setValue("window/geometry", self.saveGeometry())
        self.settings.setValue("window/state", self.saveState())

    # --- closing ----------------------------------------------------------------------
    def closeEvent(self, event: QCloseEvent) -> None:  # noqa: N802, D102 - Qt API
        if not self._closing and not self.maybe_save():
            event.ignore()
            return
        self.shutdown()
        event.accept()

    def shutdown(self) -> None:
        """Stop the workers and release the VTK windows (idempotent)."""
        if self._closing:
            return
        self._closing = True
        app = QApplication.instance()
        if app is not None:
            app.removeEventFilter(self.space_filter)
        self._save_layout()
        self.time.set_playing(False)
        if self.export_job is not None and self.export_job.isRunning():
            self.export_job.cancel()
            self.export_job.wait()
        self.sim.shutdown()
        self.viewport.close_view()
