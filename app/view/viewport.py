"""The central 3D viewport: scene, sensor rig, fields of view, radar point cloud, gizmo.

The viewport listens to the :class:`~app.document.document.ProjectDocument`: it draws every object
at the current time, highlights the selection, and attaches a transform gizmo (arrows to
move along the world axes, rings to rotate about them) to the selected object or to the
rig. Clicking an object selects it. Gizmo drags go through :meth:`SceneViewport.drag_to`,
which turns the dragged world transform into the object's base pose and pushes it as an
undoable edit (all steps of one drag merge into one undo step).
"""

from __future__ import annotations

import time
from typing import Any

import numpy as np
import pyvista as pv
from numpy.typing import NDArray
from PyQt6.QtCore import QTimer, pyqtSignal
from PyQt6.QtWidgets import QButtonGroup, QHBoxLayout, QLabel, QToolButton, QVBoxLayout, QWidget
from pyvista.plotting.affine_widget import AffineWidget3D
from vtkmodules.vtkRenderingCore import vtkBillboardTextActor3D, vtkPropPicker

from app.document.document import EditError, ProjectDocument
from app.document.sensors import rig_key, rig_of_key, rig_path, rig_states, sensor_states
from app.frame_view import FrameView
from app.view.offscreen_view import OffscreenCanvas
from app.view.scene_geometry import (
    RADAR_COLOUR,
    RGB_COLOUR,
    SELECTION_COLOUR,
    TOF_COLOUR,
    PersonPoser,
    base_pose_for_world,
    display_mesh,
    frustum,
    frustum_edges,
    material_colour,
    radar_fov_v_deg,
)
from simcore.scene import Project
from simcore.scene.materials import BandMaterial
from simcore.scene.model import sensor_kind
from simcore.scene.snapshot import SceneSnapshot, take_snapshot
from simcore.sensors.tof.camera import slab_transmittance

SelectionKey = int | str | None
#: After a render of T ms the view waits RENDER_DUTY × T ms before the next one.
RENDER_DUTY = 1.0
#: The band views of the 3D view: band name → (button text, what the view shows).
BAND_VIEWS = {
    "tof": ("ToF", "ToF view (near infrared): see-through objects are transparent to the "
                   "ToF camera"),
    "radar": ("Radar", "radar view (60 GHz): see-through objects are transparent to the "
                       "radar"),
    "visible": ("Visible", "visible view: see-through objects are transparent to the RGB "
                           "camera"),
}
#: Spacing of the ground grid's lines (m).
GRID_STEP_M = 1.0


def band_transmission(band: BandMaterial, name: str) -> float:
    """One-pass power transmission of a band material (0: opaque), as its sensor sees it.

    Radar: ``|T|²`` of the slab at 63 GHz (:meth:`BandMaterial.coefficients`); ToF: the
    incoherent slab at 850 nm (:func:`~simcore.sensors.tof.camera.slab_transmittance`);
    visible light: 0 (only the opacity counts).
    """
    if band.opacity <= 0:
        return 0.0
    if name == "radar":
        return float(abs(band.coefficients(63e9)[1]) ** 2)
    if name == "tof":
        return float(slab_transmittance(band, 850e-9))
    return 0.0


def band_display_opacity(band_opacity: float) -> float:
    """Opacity an object is drawn with in a band view, from its material's band opacity.

    Opaque in the band → solid; transparent (opacity 0: the band's render pass leaves the
    object out) → 0.15, a ghost that is still there to find and select; in between,
    linear.
    """
    return 1.0 if band_opacity >= 0.999 else 0.15 + 0.45 * float(band_opacity)


class TransformGizmo(AffineWidget3D):
    """pyvista's affine widget, reporting the *new* matrix while dragging.

    pyvista calls its interact callback with the matrix from before the move; this
    subclass calls ``on_drag(matrix, finished)`` after the move, and again on release.
    """

    def __init__(self, plotter: Any, actor: Any, *, origin: NDArray[np.float64], scale: float,
                 on_drag: Any, restore_style: Any):
        self._on_drag = on_drag
        self._restore_style = restore_style
        super().__init__(plotter, actor, origin=tuple(origin), scale=scale,
                         release_callback=self._released, line_radius=0.03)

    @property
    def dragging(self) -> bool:
        """True while the left button holds an arrow or a ring."""
        return bool(self._pressing_down)

    @property
    def hovered(self) -> bool:
        """True when the mouse is over one of the gizmo's handles."""
        return self._selected_actor is not None

    def _move_callback(self, interactor: Any, event: Any) -> None:
        before = np.array(self._main_actor.user_matrix)
        super()._move_callback(interactor, event)
        after = np.array(self._main_actor.user_matrix)
        if self._pressing_down and not np.array_equal(before, after):
            self._on_drag(after, finished=False)

    def _release_callback(self, interactor: Any, event: Any) -> None:
        super()._release_callback(interactor, event)
        # pyvista's widget leaves the trackball style behind: back to the view's own.
        self._restore_style()

    def _released(self, matrix: NDArray[np.float64]) -> None:
        self._on_drag(np.array(matrix), finished=True)

    def enable(self) -> None:  # noqa: D102 - no plotter-wide picking (the viewport picks)
        self._mouse_move_observer = self._pl.iren.add_observer("MouseMoveEvent",
                                                               self._move_callback)
        self._left_press_observer = self._pl.iren.add_observer(
            "LeftButtonPressEvent", self._press_callback, interactor_style_fallback=False)
        self._left_release_observer = self._pl.iren.add_observer(
            "LeftButtonReleaseEvent", self._release_callback, interactor_style_fallback=False)

    def disable(self) -> None:  # noqa: D102
        for obs in (self._mouse_move_observer, self._left_press_observer,
                    self._left_release_observer):
            if obs:
                self._pl.iren.remove_observer(obs)
        self._mouse_move_observer = self._left_press_observer = None
        self._left_release_observer = None


class SceneViewport(QWidget):
    """pyvistaqt view of the project at the current time.

    Signals
    -------
    dragFinished()
        A gizmo drag ended.
    editFailed(str)
        A drag produced an invalid project (message names the field).
    """

    dragFinished = pyqtSignal()
    editFailed = pyqtSignal(str)
    bandChanged = pyqtSignal(str)

    def __init__(self, document: ProjectDocument, parent: QWidget | None = None):
        super().__init__(parent)
        self.document = document
        layout = QVBoxLayout(self)
        layout.setContentsMargins(0, 0, 0, 0)
        layout.setSpacing(0)
        self._band = "tof"
        layout.addWidget(self._build_band_bar())
        # Rendered offscreen and shown as a picture: an OpenGL widget would make Qt compose
        # the whole main window through (software) OpenGL on every repaint of any panel.
        self.canvas = OffscreenCanvas(self)
        self.plotter = self.canvas.plotter
        layout.addWidget(self.canvas)
        self.setMinimumSize(320, 240)
        self._time_s = 0.0
        self._snap: SceneSnapshot | None = None
        self._snap_stale = False
        self._synced_key: tuple[Any, ...] | None = None
        self._synced_time: float | None = None
        self._object_poses: dict[int, NDArray[np.float64]] = {}
        self._rig_pose: NDArray[np.float64] | None = None
        self._actors: dict[int, tuple[str, Any]] = {}  # id -> (geometry key, actor)
        #: person id -> (object key, poser or None when its body cannot be evaluated).
        self._posers: dict[int, tuple[str, PersonPoser | None]] = {}
        #: id -> (actor, (colour, opacity, selected)) as last set on the actor's property.
        self._styles: dict[int, tuple[Any, tuple[Any, ...]]] = {}
        self._rig_actors: dict[str, Any] = {}
        #: Sensor kind of each frustum, edge and name actor in ``_rig_actors`` (issue #30).
        self._sensor_kinds: dict[str, str] = {}
        self._fov_visible: dict[str, bool] = {}
        self._sensor_key = ""
        self._cloud: pv.PolyData | None = None
        self._cloud_actor: Any = None
        self._cloud_key: tuple[Any, ...] = ()
        self._gizmo: TransformGizmo | None = None
        self._gizmo_proxy: Any = None
        self._gizmo_key: SelectionKey = None
        self._drag_key: SelectionKey = None
        self._press_pos: tuple[int, int] | None = None
        self._press_on_gizmo = False
        self._needs_render = False
        self._camera_set = False
        self._slabs: dict[int, tuple[NDArray[np.float64], NDArray[np.float64]]] = {}
        self._grid_actor: Any = None
        self._grid_key: tuple[float, ...] = ()
        self._band_text: Any = None
        self._drawn_state: tuple[Any, ...] | None = None
        self._closed = False
        #: VTK renders of the view so far.
        self.render_count = 0
        self.last_render_ms = 0.0
        #: Wall times (ms) of the latest renders (the benchmark reads them).
        self.render_ms: list[float] = []
        self._render_t0 = 0.0
        self._render_pause_until = 0.0
        self._pause_timer = QTimer(self)
        self._pause_timer.setSingleShot(True)
        self._pause_timer.timeout.connect(self.request_render)
        self.plotter.ren_win.AddObserver("StartEvent", self._render_started)
        self.plotter.ren_win.AddObserver("EndEvent", self._count_render)
        self._setup_scene()
        document.projectChanged.connect(self._on_project_changed)
        document.projectReplaced.connect(self._on_project_replaced)
        document.selectionChanged.connect(self._on_selection_changed)
        self._on_project_replaced()

    # --- set-up -----------------------------------------------------------------------
    def _build_band_bar(self) -> QWidget:
        """The strip above the view: which band the 3D view shows."""
        bar = QWidget(self)
        row = QHBoxLayout(bar)
        row.setContentsMargins(6, 2, 6, 2)
        row.setSpacing(2)
        row.addWidget(QLabel("3D view shows the scene as seen in:"))
        self.band_buttons: dict[str, QToolButton] = {}
        group = QButtonGroup(bar)
        group.setExclusive(True)
        for band, (text, tip) in BAND_VIEWS.items():
            button = QToolButton(bar)
            button.setText(text)
            button.setCheckable(True)
            button.setChecked(band == self._band)
            button.setToolTip(f"{tip[0].upper()}{tip[1:]}.")
            button.clicked.connect(lambda _=False, b=band: self.set_band(b))
            group.addButton(button)
            row.addWidget(button)
            self.band_buttons[band] = button
        row.addStretch(1)
        self._band_group = group
        return bar

    def _set_camera_style(self) -> None:
        """Turntable orbit about the world's z axis: the room never tilts.

        Left drag turns the camera about the vertical through the focal point (azimuth)
        and raises or lowers it (elevation, stopped short of the poles); the view-up stays
        +z. Middle drag or Shift + left drag pans, right drag or the wheel zooms.
        """
        self.plotter.enable_terrain_style(mouse_wheel_zooms=True, shift_pans=True)

    def _setup_scene(self) -> None:
        p = self.plotter
        p.set_background("#1e2227", top="#3a4350")
        # Two lights (one with the camera, one from above) look like VTK's five-light kit
        # here and render 3× faster on software OpenGL (office.json at 1320×835: 165 → 50
        # ms per render on Mesa llvmpipe; every light is shaded per pixel).
        p.remove_all_lights()
        p.add_light(pv.Light(light_type="headlight", intensity=0.75))
        p.add_light(pv.Light(position=(0.3, 0.2, 1.0), light_type="scene light",
                             intensity=0.45, positional=False))
        p.add_axes(interactive=False, line_width=2, labels_off=False)
        self._set_camera_style()
        self._band_text = p.add_text(BAND_VIEWS[self._band][1], position="upper_left",
                                     font_size=9, color="#c8ccd2", name="band-view")
        iren = p.iren
        iren.add_observer("LeftButtonPressEvent", self._on_left_press)
        iren.add_observer("LeftButtonReleaseEvent", self._on_left_release)
        iren.add_observer("EndInteractionEvent", lambda *_: self._update_cutaway())
        iren.add_observer("MouseWheelForwardEvent", lambda *_: self._update_cutaway())
        iren.add_observer("MouseWheelBackwardEvent", lambda *_: self._update_cutaway())
        self._picker = vtkPropPicker()
        # The gizmo finds the handle under the mouse with the interactor's picker: a prop
        # picker hits thin arrows and rings (the default point picker misses them).
        iren.interactor.SetPicker(vtkPropPicker())
        self._cloud = pv.PolyData(np.zeros((1, 3)))
        self._cloud["radial velocity (m/s)"] = np.zeros(1)
        self._cloud_actor = p.add_mesh(
            self._cloud, scalars="radial velocity (m/s)", cmap="turbo", clim=(-2, 2),
            render_points_as_spheres=True, point_size=13, pickable=False, render=False,
            scalar_bar_args={"title": "radar points: radial velocity (m/s)",
                             "vertical": False, "position_x": 0.58, "position_y": 0.02,
                             "height": 0.09, "width": 0.4, "title_font_size": 12,
                             "label_font_size": 10, "fmt": "%.1f", "n_labels": 5,
                             "color": "#c8ccd2"})
        self._cloud_actor.SetVisibility(False)

    # --- rendering (never into a hidden view) ------------------------------------------
    def request_render(self) -> None:
        """Render with the next repaint of the window if visible, else when next shown.

        The pyvistaqt widget renders the scene in its paint handler and Qt merges update
        requests: however many edits or frames ask in one pass of the event loop, the
        view renders once, in the same window repaint as the panels that changed with it.
        On a slow (software OpenGL) machine the view renders at most once per
        :data:`RENDER_DUTY` × its own render time, so it cannot take the GUI thread from
        input: a request inside that pause is drawn by the next request after it (the next
        frame while playing) or, when none comes, by a timer at the end of the pause.
        """
        if self._closed:
            return
        if not (self.isVisible() and self.canvas.isVisible()):
            self._needs_render = True
            return
        self._needs_render = False
        wait_s = self._render_pause_until - time.perf_counter()
        if wait_s > 0:
            if not self._pause_timer.isActive():
                self._pause_timer.start(int(wait_s * 1e3) + 1)
            return
        self._pause_timer.stop()
        self.canvas.request_render()

    def render_now(self) -> None:
        """Schedule the repaint of the view (only while visible)."""
        self.request_render()

    def _render_started(self, *_: Any) -> None:
        self._render_t0 = time.perf_counter()

    def _count_render(self, *_: Any) -> None:
        self.render_count += 1
        end = time.perf_counter()
        self.last_render_ms = (end - self._render_t0) * 1e3
        self.render_ms.append(self.last_render_ms)
        del self.render_ms[:-200]
        self._render_pause_until = end + RENDER_DUTY * (end - self._render_t0)

    def showEvent(self, event: Any) -> None:  # noqa: N802, D102 - Qt API
        super().showEvent(event)
        if self._needs_render:
            QTimer.singleShot(0, self.request_render)

    def close_view(self) -> None:
        """Release the VTK window (call before the widget is destroyed)."""
        if self._closed:
            return
        self._closed = True
        self._remove_gizmo()
        self.canvas.close_canvas()

    # --- document -> view --------------------------------------------------------------
    @property
    def time_s(self) -> float:
        """Time (s) the view shows."""
        return self._time_s

    def set_time(self, t: float) -> None:
        """Show the scene at time ``t`` (s)."""
        self._time_s = float(t)
        self._sync(self.document.project)

    def _on_project_replaced(self) -> None:
        for _, actor in self._actors.values():
            self.plotter.remove_actor(actor, render=False)
        self._actors.clear()
        self._styles.clear()
        self._posers.clear()
        self._sensor_key = ""
        self._drawn_state = None
        self._camera_set = False
        self._remove_gizmo()
        self.set_detections(None)
        # A radar-only project opens in the radar's view, a ToF-only one in the ToF view.
        kinds = {sensor_kind(c) for c in self.document.project.sensor_configs().values()}
        if self._band in ("tof", "radar") and self._band not in kinds \
                and kinds & {"tof", "radar"}:
            self._band = "radar" if "radar" in kinds else "tof"
            self.band_buttons[self._band].setChecked(True)
            if self._band_text is not None:
                self._band_text.SetText(2, BAND_VIEWS[self._band][1])
            self.bandChanged.emit(self._band)
        self._sync(self.document.project)

    def _on_project_changed(self, project: Project) -> None:
        # An edit of what the view does not draw (antennas, waveform, DSP, materials'
        # radar band…) costs no snapshot and no render.
        key = self._scene_key(project)
        if key == self._synced_key and self._synced_time == self._time_s:
            return
        self._sync(project)

    @classmethod
    def _scene_key(cls, project: Project) -> tuple[Any, ...]:
        """Everything of a project that the 3D view draws (compared with ==).

        Every rig's pose and motion and every sensor's mount and frustum, whatever sensors
        the rigs carry (a radar-only or ToF-only project too); not their antennas or
        waveforms beyond what the frustums show.
        """
        rigs = tuple((r.name, r.pose, r.motion) for r in project.all_rigs())
        sensors = tuple((name, cfg.pose_on_rig, cls._sensor_look(project, cfg))  # type: ignore[attr-defined]
                        for name, cfg in project.sensor_configs().items())
        return project.objects, project.materials, rigs, sensors

    def _sync(self, project: Project) -> None:
        if self._closed:
            return
        snap = take_snapshot(project, self._time_s)
        self._snap, self._snap_stale = snap, False
        self._synced_key = self._scene_key(project)
        self._synced_time = self._time_s
        self._object_poses = {o.id: s.transform for o, s in zip(project.objects, snap.objects,
                                                                 strict=True)}
        self._rig_pose = snap.rig.transform
        materials = self.document.material_table()
        seen = set()
        self._slabs.clear()
        for obj, state in zip(project.objects, snap.objects, strict=True):
            seen.add(obj.id)
            key = obj.geometry.model_dump_json()
            entry = self._actors.get(obj.id)
            if entry is None or entry[0] != key:
                if entry is not None:
                    self.plotter.remove_actor(entry[1], render=False)
                try:
                    mesh = display_mesh(obj.geometry, base_dir=self.document.base_dir)
                except (ValueError, OSError) as exc:
                    self.editFailed.emit(f"{obj.name}: {exc}")
                    mesh = pv.Octahedron(radius=0.05)
                actor = self.plotter.add_mesh(mesh, color="white", smooth_shading=False,
                                              render=False, name=f"object-{obj.id}")
                self._actors[obj.id] = (key, actor)
            actor = self._actors[obj.id][1]
            actor.user_matrix = state.transform
            if obj.geometry.kind == "person":
                self._pose_person(obj, actor, project.seed, self._time_s)
            selected = obj.id == self.document.selection
            colour = RADAR_COLOUR if obj.geometry.kind == "point_target" else material_colour(
                obj.material)
            style = (colour, self._display_opacity(obj, materials), selected)
            # pyvista's property setters parse and validate (≈ 15 µs each): set on change only.
            drawn = self._styles.get(obj.id)
            if drawn is None or drawn[0] is not actor or drawn[1] != style:
                prop = actor.prop
                prop.color = colour
                prop.opacity = style[1]
                prop.show_edges = selected
                prop.edge_color = SELECTION_COLOUR
                prop.line_width = 2 if selected else 1
                self._styles[obj.id] = (actor, style)
            if obj.geometry.kind in ("box", "plane"):
                size = (np.array(obj.geometry.size_m) if obj.geometry.kind == "box"
                        else np.array([*obj.geometry.size_m, 0.0]))
                if size.max() >= 2.0 and size.min() <= 0.3:
                    axis = state.transform[:3, int(np.argmin(size))]
                    self._slabs[obj.id] = (state.transform[:3, 3].copy(), axis)
        for oid in list(self._actors):
            if oid not in seen:
                self.plotter.remove_actor(self._actors.pop(oid)[1], render=False)
                self._styles.pop(oid, None)
                self._posers.pop(oid, None)
        self._sync_rig(project, snap)
        if not self._camera_set:
            self.reset_camera()
            self._camera_set = True
        # Edits that change nothing drawn here (antennas, waveform, DSP) cost no render.
        state = (
            tuple((o.id, self._actors[o.id][0], o.material, s.transform.tobytes())
                  for o, s in zip(project.objects, snap.objects, strict=True)),
            snap.rig.transform.tobytes(),
            tuple((n, s.transform.tobytes()) for n, s in snap.sensors.items()),
            self._sensor_key, self.document.selection,
            self._time_s if self._posers else None,  # people move their limbs in time
            tuple((m.name, m.band(self._band).opacity) for m in project.materials), self._band)
        self._sync_grid(project, snap)
        self._update_cutaway(render=False)
        if state == self._drawn_state and self._gizmo_key == self.document.selection:
            return
        self._drawn_state = state
        self._sync_gizmo()
        self.request_render()

    @property
    def _snapshot(self) -> SceneSnapshot | None:
        """The scene at the time shown (computed when asked after a frame's fast update)."""
        if self._snap_stale or self._snap is None:
            self._snap = take_snapshot(self.document.project, self._time_s)
            self._snap_stale = False
        return self._snap

    def show_frame(self, view: FrameView) -> None:
        """Show the scene as frame ``view`` saw it, with its radar points: one render.

        During playback the objects' poses come from the frame itself, so no scene snapshot
        is taken here and only the actors that moved are touched. A moving rig, a moving
        selection (the gizmo follows it) or an object list that differs take the full path.
        """
        if self._closed:
            return
        project = self.document.project
        poses = np.asarray(view.object_poses)
        rig_same = self._rig_pose is not None and np.array_equal(view.rig_pose, self._rig_pose)
        ids = [o.id for o in project.objects]
        fast = (rig_same and len(poses) == len(ids) and all(i in self._actors for i in ids)
                and not (self._gizmo is not None and self._gizmo.dragging))
        if fast:
            moved = [i for i, oid in enumerate(ids)
                     if not np.array_equal(poses[i], self._object_poses.get(oid))]
            if self.document.selection in {ids[i] for i in moved}:
                fast = False
        if not fast:
            self.set_time(view.time_s)
        elif view.time_s != self._time_s:
            self._time_s = float(view.time_s)
            self._snap_stale = True
            for i in moved:
                if ids[i] not in self._posers:  # a person's points are posed in the world
                    self._actors[ids[i]][1].user_matrix = poses[i]
                self._object_poses[ids[i]] = poses[i]
            posed = [self._pose_person(obj, self._actors[obj.id][1], project.seed,
                                       self._time_s)
                     for obj in project.objects if obj.id in self._posers]
            if moved or any(posed):
                self._drawn_state = None  # the next edit re-checks everything
                self.request_render()
        self.set_detections(view)

    def _pose_person(self, obj: Any, actor: Any, seed: int, t: float) -> bool:
        """Put a person's display mesh where its segments are at ``t`` (s).

        The mesh's points become world points (the actor's matrix the identity); False
        (drawn at rest on its pose) if its body cannot be evaluated.
        """
        key = f"{obj.id}|{seed}|{obj.model_dump_json()}"
        entry = self._posers.get(obj.id)
        if entry is None or entry[0] != key:
            try:
                poser: PersonPoser | None = PersonPoser(obj, seed=seed,
                                                        base_dir=self.document.base_dir)
            except (ValueError, OSError):
                poser = None
            entry = self._posers[obj.id] = (key, poser)
        poser = entry[1]
        mesh = actor.mapper.dataset
        if poser is None or mesh.n_points != len(poser.local):
            return False
        if mesh.point_data.active_normals is not None:  # the rest normals would be stale
            mesh.GetPointData().SetNormals(None)
        mesh.points = poser.points(t)
        actor.user_matrix = np.eye(4)
        return True

    @staticmethod
    def _sensor_actor_names(name: str) -> tuple[str, str]:
        """Keys in ``_rig_actors`` of a sensor's frustum and edges (built-ins: as before)."""
        if name in ("tof", "radar"):
            return f"{name}_fov", f"{name}_edges"
        return f"fov:{name}", f"edges:{name}"

    @staticmethod
    def _sensor_look(project: Project, cfg: Any) -> tuple[str, float, float, float, float]:
        """(colour, h fov, v fov, depth, face opacity) of a sensor's drawn frustum."""
        kind = sensor_kind(cfg)
        if kind == "tof":
            return (TOF_COLOUR, cfg.fov_h_deg, cfg.fov_v_deg,
                    min(cfg.unambiguous_range_m, 4.0), 0.06)
        if kind == "radar":
            return (RADAR_COLOUR, cfg.render_fov_h_deg, radar_fov_v_deg(project, cfg),
                    min(cfg.max_range_m, 6.0), 0.04)
        return RGB_COLOUR, cfg.fov_h_deg, cfg.fov_v_deg, 2.0, 0.04

    def _sync_rig(self, project: Project, snap: SceneSnapshot) -> None:
        """Draw every rig (body, axes) and every sensor (frustum and name), issue #30."""
        rigs = project.all_rigs()
        looks = {name: (sensor_kind(cfg), self._sensor_look(project, cfg))
                 for rig in rigs for name, cfg in rig.sensor_configs().items()}
        key = repr(([r.name for r in rigs], looks))
        if key != self._sensor_key:
            for actor in self._rig_actors.values():
                self.plotter.remove_actor(actor, render=False)
            self._rig_actors = {}
            self._sensor_kinds = {}
            p = self.plotter
            for i, rig in enumerate(rigs):
                suffix = "" if i == 0 else f":{rig.name}"
                body = pv.Box(bounds=(-0.04, 0.02, -0.09, 0.09, -0.03, 0.03))
                self._rig_actors["body" + suffix] = p.add_mesh(
                    body, color="#5a6b7d", render=False, name="rig-body" + suffix)
                arrows = (pv.Arrow(start=(0, 0, 0), direction=(1, 0, 0), scale=0.25)
                          + pv.Arrow(start=(0, 0, 0), direction=(0, 1, 0), scale=0.15)
                          + pv.Arrow(start=(0, 0, 0), direction=(0, 0, 1), scale=0.15))
                self._rig_actors["axes" + suffix] = p.add_mesh(
                    arrows, color="#9fb3c8", render=False, pickable=False,
                    name="rig-axes" + suffix)
            for name, (kind, (colour, fov_h, fov_v, depth, opacity)) in looks.items():
                fov, edges = self._sensor_actor_names(name)
                self._rig_actors[fov] = p.add_mesh(
                    frustum(fov_h, fov_v, depth), color=colour, opacity=opacity,
                    pickable=False, render=False, name=f"fov-{name}")
                self._rig_actors[edges] = p.add_mesh(
                    frustum_edges(fov_h, fov_v, depth), color=colour, line_width=1.5,
                    pickable=False, render=False, name=f"edges-{name}")
                label = vtkBillboardTextActor3D()
                label.SetInput(name)
                label.GetTextProperty().SetColor(pv.Color(colour).float_rgb)
                label.GetTextProperty().SetFontSize(13)
                label.GetTextProperty().SetBold(True)
                label.SetPickable(False)
                p.add_actor(label, name=f"label-{name}", render=False, pickable=False)
                self._rig_actors[f"label:{name}"] = label
                for k in (fov, edges, f"label:{name}"):
                    self._sensor_kinds[k] = kind
            self._sensor_key = key
            self._apply_fov_visibility()
        states = sensor_states(project, snap.time_s)
        for i, (rig, state) in enumerate(zip(rigs, rig_states(project, snap.time_s),
                                             strict=True)):
            suffix = "" if i == 0 else f":{rig.name}"
            rig_t = snap.rig.transform if i == 0 else state.transform
            self._rig_actors["body" + suffix].user_matrix = rig_t
            self._rig_actors["axes" + suffix].user_matrix = rig_t
            body = self._rig_actors["body" + suffix].prop
            body.show_edges = self.document.selection == rig_key(project, i)
            body.edge_color = SELECTION_COLOUR
        for name in looks:
            transform = snap.sensors[name].transform if name in snap.sensors else \
                states[name].transform
            for k in self._sensor_actor_names(name):
                self._rig_actors[k].user_matrix = transform
            # The name floats just above the sensor (world z up).
            self._rig_actors[f"label:{name}"].SetPosition(*(transform[:3, 3] + (0, 0, 0.07)))

    # --- band views ---------------------------------------------------------------------
    @property
    def band(self) -> str:
        """The band the view shows the scene in (a key of :data:`BAND_VIEWS`)."""
        return self._band

    def set_band(self, band: str) -> None:
        """Draw every object as the sensor of ``band`` sees it ("tof", "radar", "visible").

        An object whose material is transparent in the band (its band opacity below 1;
        the band's render pass leaves it out at 0) is drawn see-through
        (:func:`band_display_opacity`); a point target, which only the radar sees, is a
        ghost in the ToF and visible views.
        """
        if band not in BAND_VIEWS:
            raise ValueError(f"unknown band view {band!r}; known: {', '.join(BAND_VIEWS)}")
        if band == self._band:
            return
        self._band = band
        self.band_buttons[band].setChecked(True)
        if self._band_text is not None:
            self._band_text.SetText(2, BAND_VIEWS[band][1])  # 2: the upper left corner
        self._drawn_state = None
        self._sync(self.document.project)
        self.bandChanged.emit(band)

    @property
    def band_caption(self) -> str:
        """The caption in the view's upper left corner (which band it shows)."""
        return str(self._band_text.GetText(2)) if self._band_text is not None else ""

    def _display_opacity(self, obj: Any, materials: dict[str, Any]) -> float:
        """Opacity of ``obj``'s actor in the current band view."""
        if obj.geometry.kind == "point_target":
            return 1.0 if self._band == "radar" else band_display_opacity(0.0)
        mat = materials.get(obj.material)
        if mat is None:
            return 1.0
        band = mat.band(self._band)
        return band_display_opacity(band.opacity * (1.0 - band_transmission(band, self._band)))

    # --- ground grid ---------------------------------------------------------------------
    def _sync_grid(self, project: Project, snap: SceneSnapshot) -> None:
        """A 1 m grid on the ground plane z = 0 under the scene and the rig (≥ 10 m × 10 m)."""
        points = [snap.rig.origin[:2], snap.rig.origin[:2] + snap.rig.transform[:2, 0] * 4.0]
        points += [s.origin[:2] for s in snap.objects]
        xy = np.array(points)
        lo = np.floor(xy.min(axis=0) / GRID_STEP_M - 2) * GRID_STEP_M
        hi = np.ceil(xy.max(axis=0) / GRID_STEP_M + 2) * GRID_STEP_M
        span = hi - lo
        grow = np.maximum(10.0 - span, 0.0) / 2
        lo, hi = lo - np.ceil(grow), hi + np.ceil(grow)
        key = (*lo.tolist(), *hi.tolist())
        if key == self._grid_key:
            return
        self._grid_key = key
        xs = np.arange(lo[0], hi[0] + GRID_STEP_M / 2, GRID_STEP_M)
        ys = np.arange(lo[1], hi[1] + GRID_STEP_M / 2, GRID_STEP_M)
        z = 0.002  # just above a floor whose top is z = 0
        ends = [((x, lo[1], z), (x, hi[1], z)) for x in xs]
        ends += [((lo[0], y, z), (hi[0], y, z)) for y in ys]
        pts = np.array([p for pair in ends for p in pair], dtype=float)
        lines = np.column_stack([np.full(len(ends), 2), np.arange(0, 2 * len(ends), 2),
                                 np.arange(1, 2 * len(ends), 2)]).ravel()
        grid = pv.PolyData(pts, lines=lines)
        if self._grid_actor is not None:
            self.plotter.remove_actor(self._grid_actor, render=False)
        self._grid_actor = self.plotter.add_mesh(
            grid, color="#6b7685", opacity=0.55, line_width=1, pickable=False,
            render=False, name="ground-grid", lighting=False)

    @property
    def grid_bounds(self) -> tuple[float, float, float, float] | None:
        """(x min, x max, y min, y max) of the ground grid (m), None before the first draw."""
        if not self._grid_key:
            return None
        x0, y0, x1, y1 = self._grid_key
        return x0, x1, y0, y1

    def set_sensor_fov_visible(self, *, tof: bool, radar: bool) -> None:
        """Show or hide the field-of-view frustums of every ToF camera and every radar."""
        self._fov_visible = {"tof": tof, "radar": radar}
        self._apply_fov_visibility()
        self.request_render()

    def _apply_fov_visibility(self) -> None:
        # An RGB camera's frustum follows the ToF switch (the window's one switch sets both).
        for key, kind in self._sensor_kinds.items():
            if not key.startswith("label:"):
                on = self._fov_visible.get("tof" if kind == "rgb" else kind, True)
                self._rig_actors[key].SetVisibility(on)

    def reset_camera(self) -> None:
        """Look at the scene from behind, beside and above the rig, z up.

        The view frames every object and the rig; in a project with no objects it frames
        the rig and both sensors' fields of view (as far as the frustums are drawn).
        """
        project = self.document.project
        rig = take_snapshot(project, self._time_s).rig.transform
        with_objects = bool(project.objects and self._actors)
        bounds = self._framed_bounds(with_objects=with_objects)
        centre = (bounds[::2] + bounds[1::2]) / 2
        fwd = rig[:3, 0].copy()
        fwd[2] = 0.0
        fwd = fwd / np.linalg.norm(fwd) if np.linalg.norm(fwd) > 1e-6 else np.array([1.0, 0, 0])
        left = np.cross([0.0, 0.0, 1.0], fwd)
        direction = -fwd * 0.75 - left * 0.45 + np.array([0.0, 0.0, 0.6])
        camera = self.plotter.camera
        camera.view_angle = 35.0
        self.plotter.camera_position = [tuple(centre + direction), tuple(centre), (0, 0, 1)]
        renderer = self.plotter.renderer
        renderer.ResetCamera(*bounds)
        # ResetCamera fits the bounding sphere; zoom until the box's corners reach the edges
        # (a room's far corners are empty; the frustums of an empty project keep a margin).
        fill = 0.98 if with_objects else 0.88
        corners = [(x, y, z) for x in bounds[:2] for y in bounds[2:4] for z in bounds[4:]]
        extent = 0.0
        for corner in corners:
            renderer.SetWorldPoint(*corner, 1.0)
            renderer.WorldToView()
            vx, vy, _ = renderer.GetViewPoint()
            extent = max(extent, abs(vx), abs(vy))
        if extent > 1e-6:
            camera.zoom(float(np.clip(fill / extent, 0.5, 3.0)))
        self.plotter.reset_camera_clipping_range()
        self._update_cutaway(render=False)
        self.request_render()

    def _framed_bounds(self, *, with_objects: bool) -> NDArray[np.float64]:
        """(xmin, xmax, ymin, ymax, zmin, zmax) of what :meth:`reset_camera` frames."""
        # Without objects: the rig and every sensor's field of view (whatever its name).
        actors = [a for n, a in self._rig_actors.items() if n == "body" or (
            not with_objects and (n.endswith("_fov") or n.startswith("fov:")))]
        if with_objects:
            actors += [a for _, a in self._actors.values()]
        boxes = np.array([a.GetBounds() for a in actors])
        if len(boxes) == 0:
            return np.array([-1.0, 1.0, -1.0, 1.0, 0.0, 2.0])
        bounds = np.empty(6)
        bounds[::2] = boxes[:, ::2].min(axis=0)
        bounds[1::2] = boxes[:, 1::2].max(axis=0)
        return bounds

    def _update_cutaway(self, *, render: bool = True) -> None:
        """Fade the big slabs (walls, ceiling) that stand between the camera and the scene."""
        if not self._slabs or self._closed:
            return
        cam = np.array(self.plotter.camera.position)
        centres = np.array([c for c, _ in self._slabs.values()])
        middle = centres.mean(axis=0)
        materials = self.document.material_table()
        by_id = {o.id: o for o in self.document.project.objects}
        for oid, (centre, axis) in self._slabs.items():
            if oid not in self._actors or oid not in by_id:
                continue
            side_obj = float(np.dot(centre - middle, axis))
            side_cam = float(np.dot(cam - centre, axis))
            between = side_obj * side_cam > 0 and abs(side_obj) > 0.5
            base = self._display_opacity(by_id[oid], materials)
            self._actors[oid][1].prop.opacity = 0.12 if between else base
            self._actors[oid][1].SetPickable(not between)
        if render:
            self.request_render()

    # --- radar point cloud -------------------------------------------------------------
    def set_detections(self, view: FrameView | None) -> None:
        """Overlay the radar detections of ``view`` (world frame), coloured by velocity."""
        if self._closed or self._cloud is None:
            return
        det = None if view is None or view.radar is None else view.radar.detections
        if det is None or len(det) == 0:
            key: tuple[Any, ...] = ()
        else:
            xyz = np.asarray(det.xyz_world_m, dtype=float)
            velocity = np.asarray(det.velocity_mps, dtype=float)
            radars = self.document.project.sensors_of_kind("radar")
            # The radar whose detections these are (the frame's first), else the first.
            name = next((n for n, r in view.radars.items() if r is view.radar), "")  # type: ignore[union-attr]
            radar = radars.get(name) or next(iter(radars.values()), None)
            vmax = float(radar.max_velocity_mps) if radar is not None else 1.0  # type: ignore[attr-defined]
            key = (xyz.tobytes(), velocity.tobytes(), vmax)
        if key == self._cloud_key:
            return  # the same points: no render
        self._cloud_key = key
        if not key:
            self._cloud_actor.SetVisibility(False)
        else:
            cloud = pv.PolyData(xyz)
            cloud["radial velocity (m/s)"] = velocity
            self._cloud.copy_from(cloud)
            self._cloud_actor.mapper.scalar_range = (-vmax, vmax)
            self._cloud_actor.SetVisibility(True)
        self.request_render()

    # --- picking -----------------------------------------------------------------------
    def _on_left_press(self, *_: Any) -> None:
        self._press_pos = self.plotter.iren.get_event_position()
        self._press_on_gizmo = self._gizmo is not None and self._gizmo.hovered

    def _on_left_release(self, *_: Any) -> None:
        pos = self.plotter.iren.get_event_position()
        start, self._press_pos = self._press_pos, None
        if start is None or self._press_on_gizmo:
            return
        if abs(pos[0] - start[0]) + abs(pos[1] - start[1]) > 4:
            return  # a camera drag, not a click
        self.document.select(self.pick(pos))

    def pick(self, pos: tuple[int, int]) -> SelectionKey:
        """The object id (or :data:`RIG`) drawn at display position ``pos``, else None."""
        renderer = self.plotter.renderer
        if not self._picker.PickProp(pos[0], pos[1], renderer):
            return None
        actor = self._picker.GetViewProp()
        for oid, (_, a) in self._actors.items():
            if a is actor:
                return oid
        project = self.document.project
        for i, rig in enumerate(project.all_rigs()):
            if actor is self._rig_actors.get("body" if i == 0 else f"body:{rig.name}"):
                return rig_key(project, i)
        return None

    def display_position_of(self, key: SelectionKey) -> tuple[int, int] | None:
        """Display coordinates (VTK, origin bottom-left) of an object's or the rig's origin.

        A person's point is on its torso (its origin is on the floor between its feet).
        """
        snap = self._snapshot
        if snap is None:
            return None
        rig = rig_of_key(self.document.project, key)
        if rig is not None:
            world = rig_states(self.document.project, snap.time_s)[rig].origin
        else:
            try:
                index = self.document.index_of(int(key))  # type: ignore[arg-type]
                world = snap.objects[index].origin
            except (KeyError, TypeError):
                return None
            geometry = self.document.project.objects[index].geometry
            if geometry.kind == "person":  # its origin is on the floor: aim at the torso
                world = snap.objects[index].transform[:3, :3] @ np.array(
                    [0.0, 0.0, 0.6 * geometry.height_m]) + world
        ren = self.plotter.renderer
        ren.SetWorldPoint(*world, 1.0)
        ren.WorldToDisplay()
        x, y, _ = ren.GetDisplayPoint()
        return int(round(x)), int(round(y))

    # --- selection and gizmo -----------------------------------------------------------
    def _on_selection_changed(self, _key: SelectionKey) -> None:
        self._sync(self.document.project)

    def _selected_world(self) -> NDArray[np.float64] | None:
        key = self.document.selection
        snap = self._snapshot
        if key is None or snap is None:
            return None
        rig = rig_of_key(self.document.project, key)
        if rig is not None:
            return rig_states(self.document.project, snap.time_s)[rig].transform
        idx = self.document.selected_index()
        return None if idx is None else snap.objects[idx].transform

    def _remove_gizmo(self) -> None:
        if self._gizmo is not None:
            self._gizmo.remove()
            self._gizmo = None
        if self._gizmo_proxy is not None:
            self.plotter.remove_actor(self._gizmo_proxy, render=False)
            self._gizmo_proxy = None
        self._gizmo_key = None

    def _sync_gizmo(self) -> None:
        if self._gizmo is not None and self._gizmo.dragging:
            return  # never rebuild under the user's mouse
        world = self._selected_world()
        self._remove_gizmo()
        if world is None:
            return
        proxy = self.plotter.add_mesh(pv.Sphere(radius=0.5), render=False, pickable=False,
                                      name="gizmo-proxy")
        proxy.SetVisibility(False)
        proxy.user_matrix = world
        self._gizmo_proxy = proxy
        self._gizmo_key = self.document.selection
        self._gizmo = TransformGizmo(self.plotter, proxy, origin=world[:3, 3], scale=0.45,
                                     on_drag=self._on_gizmo_drag,
                                     restore_style=self._set_camera_style)

    def _on_gizmo_drag(self, matrix: NDArray[np.float64], *, finished: bool) -> None:
        self.drag_to(self._gizmo_key, matrix, finished=finished)

    def drag_to(self, key: SelectionKey, world: NDArray[np.float64], *, finished: bool) -> None:
        """Move an object (id) or the rig (:data:`RIG`) to the world transform ``world``.

        This is the code path of the viewport's transform gizmo: every step of a drag
        pushes an edit that merges with the previous steps of the same drag; ``finished``
        ends the drag (the next drag is a new undo step) and re-centres the gizmo.
        """
        if key is None:
            return
        project = self.document.project
        world = np.asarray(world, dtype=float)
        merge = f"drag:{key}"
        try:
            rig_i = rig_of_key(project, key)
            if rig_i is not None:
                rig = project.all_rigs()[rig_i]
                pose = base_pose_for_world(rig.pose, rig.motion, self._time_s, world)
                self.document.set_value(f"{rig_path(rig_i)}.pose", pose.model_dump(),
                                        text="Move sensor rig" if rig_i == 0
                                        else f"Move rig {rig.name}", merge_key=merge)
            else:
                idx = self.document.index_of(int(key))
                obj = project.objects[idx]
                pose = base_pose_for_world(obj.pose, obj.motion, self._time_s, world)
                self.document.set_value(f"objects[{idx}].pose", pose.model_dump(),
                                        text=f"Move {obj.name}", merge_key=merge)
        except (EditError, KeyError) as exc:
            self.editFailed.emit(str(exc))
        if finished:
            self.document.end_merge()
            QTimer.singleShot(0, lambda: self._sync(self.document.project))
            self.dragFinished.emit()
