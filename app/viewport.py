"""The central 3D viewport: scene, sensor rig, fields of view, radar point cloud, gizmo.

The viewport listens to the :class:`~app.document.ProjectDocument`: it draws every object
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
from PyQt6.QtWidgets import QVBoxLayout, QWidget
from pyvista.plotting.affine_widget import AffineWidget3D
from pyvistaqt import QtInteractor
from vtkmodules.vtkRenderingCore import vtkPropPicker

from app.document import RIG, EditError, ProjectDocument
from app.frame_view import FrameView
from app.scene_geometry import (
    RADAR_COLOUR,
    SELECTION_COLOUR,
    TOF_COLOUR,
    base_pose_for_world,
    display_mesh,
    frustum,
    frustum_edges,
    material_colour,
    radar_fov_v_deg,
)
from simcore.scene import Project
from simcore.scene.snapshot import SceneSnapshot, take_snapshot

SelectionKey = int | str | None
#: After a render of T ms the view waits RENDER_DUTY × T ms before the next one.
RENDER_DUTY = 1.0


class TransformGizmo(AffineWidget3D):
    """pyvista's affine widget, reporting the *new* matrix while dragging.

    pyvista calls its interact callback with the matrix from before the move; this
    subclass calls ``on_drag(matrix, finished)`` after the move, and again on release.
    """

    def __init__(self, plotter: Any, actor: Any, *, origin: NDArray[np.float64], scale: float,
                 on_drag: Any):
        self._on_drag = on_drag
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

    def __init__(self, document: ProjectDocument, parent: QWidget | None = None):
        super().__init__(parent)
        self.document = document
        layout = QVBoxLayout(self)
        layout.setContentsMargins(0, 0, 0, 0)
        # No multisampling: on software OpenGL (Mesa llvmpipe) it multiplies the frame time.
        self.plotter = QtInteractor(self, auto_update=False, multi_samples=0)
        layout.addWidget(self.plotter.interactor)
        self.setMinimumSize(320, 240)
        self._time_s = 0.0
        self._snap: SceneSnapshot | None = None
        self._snap_stale = False
        self._synced_key: tuple[Any, ...] | None = None
        self._synced_time: float | None = None
        self._object_poses: dict[int, NDArray[np.float64]] = {}
        self._rig_pose: NDArray[np.float64] | None = None
        self._actors: dict[int, tuple[str, Any]] = {}  # id -> (geometry key, actor)
        self._rig_actors: dict[str, Any] = {}
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
        self._drawn_state: tuple[Any, ...] | None = None
        self._closed = False
        #: VTK renders of the view so far.
        self.render_count = 0
        self.last_render_ms = 0.0
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
    def _setup_scene(self) -> None:
        p = self.plotter
        p.set_background("#1e2227", top="#3a4350")
        p.enable_lightkit()
        p.add_axes(interactive=False, line_width=2, labels_off=False)
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
        if not (self.isVisible() and self.plotter.isVisible()):
            self._needs_render = True
            return
        self._needs_render = False
        wait_s = self._render_pause_until - time.perf_counter()
        if wait_s > 0:
            if not self._pause_timer.isActive():
                self._pause_timer.start(int(wait_s * 1e3) + 1)
            return
        self._pause_timer.stop()
        self.plotter.update()

    def render_now(self) -> None:
        """Schedule the repaint of the view (only while visible)."""
        self.request_render()

    def _render_started(self, *_: Any) -> None:
        self._render_t0 = time.perf_counter()

    def _count_render(self, *_: Any) -> None:
        self.render_count += 1
        end = time.perf_counter()
        self.last_render_ms = (end - self._render_t0) * 1e3
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
        self.plotter.close()

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
        self._sensor_key = ""
        self._drawn_state = None
        self._camera_set = False
        self._remove_gizmo()
        self.set_detections(None)
        self._sync(self.document.project)

    def _on_project_changed(self, project: Project) -> None:
        # An edit of what the view does not draw (antennas, waveform, DSP, materials'
        # radar band…) costs no snapshot and no render.
        key = self._scene_key(project)
        if key == self._synced_key and self._synced_time == self._time_s:
            return
        self._sync(project)

    @staticmethod
    def _scene_key(project: Project) -> tuple[Any, ...]:
        """Everything of a project that the 3D view draws (compared with ==)."""
        rig = project.rig
        return (project.objects, project.materials, rig.pose, rig.motion,
                rig.tof.pose_on_rig, rig.radar.pose_on_rig, rig.tof.fov_h_deg,
                rig.tof.fov_v_deg, rig.tof.unambiguous_range_m, rig.radar.render_fov_h_deg,
                radar_fov_v_deg(project), rig.radar.max_range_m)

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
            mat = materials.get(obj.material)
            prop = actor.prop
            prop.color = material_colour(obj.material)
            tof_opacity = mat.band("tof").opacity if mat is not None else 1.0
            prop.opacity = 0.35 if tof_opacity < 0.5 else 1.0
            selected = obj.id == self.document.selection
            prop.show_edges = selected
            prop.edge_color = SELECTION_COLOUR
            prop.line_width = 2 if selected else 1
            if obj.geometry.kind == "point_target":
                prop.color = RADAR_COLOUR
            if obj.geometry.kind in ("box", "plane"):
                size = (np.array(obj.geometry.size_m) if obj.geometry.kind == "box"
                        else np.array([*obj.geometry.size_m, 0.0]))
                if size.max() >= 2.0 and size.min() <= 0.3:
                    axis = state.transform[:3, int(np.argmin(size))]
                    self._slabs[obj.id] = (state.transform[:3, 3].copy(), axis)
        for oid in list(self._actors):
            if oid not in seen:
                self.plotter.remove_actor(self._actors.pop(oid)[1], render=False)
        self._sync_rig(project, snap)
        if not self._camera_set:
            self.reset_camera()
            self._camera_set = True
        # Edits that change nothing drawn here (antennas, waveform, DSP) cost no render.
        state = (
            tuple((o.id, self._actors[o.id][0], o.material, s.transform.tobytes())
                  for o, s in zip(project.objects, snap.objects, strict=True)),
            snap.rig.transform.tobytes(), snap.sensors["tof"].transform.tobytes(),
            snap.sensors["radar"].transform.tobytes(), self._sensor_key, self.document.selection,
            tuple((m.name, m.band("tof").opacity) for m in project.materials))
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
                self._actors[ids[i]][1].user_matrix = poses[i]
                self._object_poses[ids[i]] = poses[i]
            if moved:
                self._drawn_state = None  # the next edit re-checks everything
                self.request_render()
        self.set_detections(view)

    def _sync_rig(self, project: Project, snap: SceneSnapshot) -> None:
        rig = project.rig
        key = (f"{rig.tof.fov_h_deg},{rig.tof.fov_v_deg},{rig.tof.unambiguous_range_m},"
               f"{rig.radar.render_fov_h_deg},{radar_fov_v_deg(project)},{rig.radar.max_range_m}")
        if key != self._sensor_key:
            for actor in self._rig_actors.values():
                self.plotter.remove_actor(actor, render=False)
            self._rig_actors = {}
            p = self.plotter
            body = pv.Box(bounds=(-0.04, 0.02, -0.09, 0.09, -0.03, 0.03))
            self._rig_actors["body"] = p.add_mesh(body, color="#5a6b7d", render=False,
                                                  name="rig-body")
            arrows = (pv.Arrow(start=(0, 0, 0), direction=(1, 0, 0), scale=0.25)
                      + pv.Arrow(start=(0, 0, 0), direction=(0, 1, 0), scale=0.15)
                      + pv.Arrow(start=(0, 0, 0), direction=(0, 0, 1), scale=0.15))
            self._rig_actors["axes"] = p.add_mesh(arrows, color="#9fb3c8", render=False,
                                                  pickable=False, name="rig-axes")
            tof_depth = min(rig.tof.unambiguous_range_m, 4.0)
            radar_depth = min(rig.radar.max_range_m, 6.0)
            tof_fov = (rig.tof.fov_h_deg, rig.tof.fov_v_deg)
            radar_fov = (rig.radar.render_fov_h_deg, radar_fov_v_deg(project))
            self._rig_actors["tof_fov"] = p.add_mesh(
                frustum(*tof_fov, tof_depth), color=TOF_COLOUR, opacity=0.06, pickable=False,
                render=False, name="tof-fov")
            self._rig_actors["tof_edges"] = p.add_mesh(
                frustum_edges(*tof_fov, tof_depth), color=TOF_COLOUR, line_width=1.5,
                pickable=False, render=False, name="tof-fov-edges")
            self._rig_actors["radar_fov"] = p.add_mesh(
                frustum(*radar_fov, radar_depth), color=RADAR_COLOUR, opacity=0.04,
                pickable=False, render=False, name="radar-fov")
            self._rig_actors["radar_edges"] = p.add_mesh(
                frustum_edges(*radar_fov, radar_depth), color=RADAR_COLOUR, line_width=1.5,
                pickable=False, render=False, name="radar-fov-edges")
            self._sensor_key = key
        rig_t = snap.rig.transform
        self._rig_actors["body"].user_matrix = rig_t
        self._rig_actors["axes"].user_matrix = rig_t
        for name in ("tof_fov", "tof_edges"):
            self._rig_actors[name].user_matrix = snap.sensors["tof"].transform
        for name in ("radar_fov", "radar_edges"):
            self._rig_actors[name].user_matrix = snap.sensors["radar"].transform
        body = self._rig_actors["body"].prop
        body.show_edges = self.document.selection == RIG
        body.edge_color = SELECTION_COLOUR

    def set_sensor_fov_visible(self, *, tof: bool, radar: bool) -> None:
        """Show or hide the ToF and radar field-of-view frustums."""
        for name in ("tof_fov", "tof_edges"):
            self._rig_actors[name].SetVisibility(tof)
        for name in ("radar_fov", "radar_edges"):
            self._rig_actors[name].SetVisibility(radar)
        self.request_render()

    def reset_camera(self) -> None:
        """Look at the scene from behind and above the rig."""
        project = self.document.project
        rig = take_snapshot(project, self._time_s).rig.transform
        if project.objects and self._actors:
            bounds = np.array(self.plotter.bounds)
            centre = np.array([(bounds[0] + bounds[1]) / 2, (bounds[2] + bounds[3]) / 2,
                               (bounds[4] + bounds[5]) / 2])
            size = float(np.linalg.norm(bounds[1::2] - bounds[::2]))
        else:
            centre, size = rig[:3, 3] + rig[:3, 0] * 2, 5.0
        size = max(min(size, 40.0), 2.0)
        fwd = rig[:3, 0]
        left = rig[:3, 1]
        eye = centre - fwd * size * 0.75 - left * size * 0.45 + np.array([0, 0, size * 0.6])
        self.plotter.camera_position = [tuple(eye), tuple(centre), (0, 0, 1)]
        self.plotter.camera.view_angle = 35.0
        self.plotter.reset_camera_clipping_range()
        self._update_cutaway(render=False)
        self.request_render()

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
            mat = materials.get(by_id[oid].material)
            base = 0.35 if mat is not None and mat.band("tof").opacity < 0.5 else 1.0
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
            vmax = float(self.document.project.rig.radar.max_velocity_mps)
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
        if actor is self._rig_actors.get("body"):
            return RIG
        return None

    def display_position_of(self, key: SelectionKey) -> tuple[int, int] | None:
        """Display coordinates (VTK, origin bottom-left) of an object's or the rig's origin."""
        snap = self._snapshot
        if snap is None:
            return None
        if key == RIG:
            world = snap.rig.origin
        else:
            try:
                world = snap.objects[self.document.index_of(int(key))].origin  # type: ignore[arg-type]
            except (KeyError, TypeError):
                return None
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
        if key == RIG:
            return snap.rig.transform
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
                                     on_drag=self._on_gizmo_drag)

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
            if key == RIG:
                pose = base_pose_for_world(project.rig.pose, project.rig.motion, self._time_s,
                                           world)
                self.document.set_value("rig.pose", pose.model_dump(), text="Move sensor rig",
                                        merge_key=merge)
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
