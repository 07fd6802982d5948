"""The 3D view: offscreen rendering, turntable orbit, band views, ground grid, framing."""

from __future__ import annotations

import numpy as np
import pytest

pytestmark = pytest.mark.gui


def _drag(widget, qtbot, start, delta, *, steps: int = 8, button=None) -> None:
    from PyQt6.QtCore import QPoint, Qt
    from PyQt6.QtTest import QTest

    button = button or Qt.MouseButton.LeftButton
    QTest.mouseMove(widget, start)
    QTest.mousePress(widget, button, Qt.KeyboardModifier.NoModifier, start)
    for k in range(1, steps + 1):
        QTest.mouseMove(widget, start + QPoint(delta.x() * k // steps, delta.y() * k // steps))
        qtbot.wait(10)
    QTest.mouseRelease(widget, button, Qt.KeyboardModifier.NoModifier, start + delta)


def _to_widget(view, world) -> tuple[int, int]:
    """Widget coordinates (Qt, origin top-left) of a world point."""
    ren = view.plotter.renderer
    ren.SetWorldPoint(*world, 1.0)
    ren.WorldToDisplay()
    x, y, _ = ren.GetDisplayPoint()
    return int(round(x)), int(round(view.canvas.height() - y - 1))


def test_window_is_a_raster_surface_and_the_view_draws(make_window, wait_frame,
                                                       is_non_blank):
    """No OpenGL widget in the window: Qt composes it in software, the 3D view is a picture."""
    from PyQt6.QtGui import QSurface
    from PyQt6.QtOpenGLWidgets import QOpenGLWidget

    window = make_window()
    wait_frame(window)
    assert not window.findChildren(QOpenGLWidget)
    assert window.windowHandle().surfaceType() == QSurface.SurfaceType.RasterSurface
    view = window.viewport
    assert is_non_blank(view.canvas.grab().toImage())
    # The window's own grab (screenshots, exports) contains the 3D picture.
    assert is_non_blank(window.grab(view.geometry()).toImage())
    assert view.plotter.screenshot(return_img=True).std() > 5


def test_turntable_orbit_keeps_the_room_upright(make_window, wait_frame, qtbot):
    from PyQt6.QtCore import QPoint

    window = make_window()
    wait_frame(window)
    view = window.viewport
    cam = view.plotter.camera
    np.testing.assert_allclose(cam.up, (0, 0, 1), atol=1e-9)
    before = np.array(cam.position)
    focal = np.array(cam.focal_point)
    centre = QPoint(view.canvas.width() // 2, view.canvas.height() // 2)
    # A diagonal drag: azimuth and elevation together (a trackball would roll the room).
    _drag(view.canvas, qtbot, centre, QPoint(180, 90))
    after = np.array(cam.position)
    assert np.linalg.norm(after - before) > 0.2, "the drag did not orbit"
    np.testing.assert_allclose(cam.up, (0, 0, 1), atol=1e-9)
    np.testing.assert_allclose(cam.focal_point, focal, atol=1e-6)  # orbits, not pans
    # The distance to the focal point is kept (a turntable, not a dolly).
    assert np.linalg.norm(after - focal) == pytest.approx(np.linalg.norm(before - focal),
                                                          rel=1e-6)
    # The drag orbited: it selected nothing.
    assert window.document.selection is None


def test_wheel_zooms(make_window, wait_frame, qtbot):
    from PyQt6.QtCore import QPoint, QPointF, Qt
    from PyQt6.QtGui import QWheelEvent
    from PyQt6.QtWidgets import QApplication

    window = make_window()
    wait_frame(window)
    view = window.viewport
    cam = view.plotter.camera
    d0 = np.linalg.norm(np.subtract(cam.position, cam.focal_point))
    pos = QPointF(view.canvas.width() / 2, view.canvas.height() / 2)
    event = QWheelEvent(pos, view.canvas.mapToGlobal(pos), QPoint(0, 0), QPoint(0, 120),
                        Qt.MouseButton.NoButton, Qt.KeyboardModifier.NoModifier,
                        Qt.ScrollPhase.NoScrollPhase, False)
    QApplication.sendEvent(view.canvas, event)
    d1 = np.linalg.norm(np.subtract(cam.position, cam.focal_point))
    assert d1 < d0
    np.testing.assert_allclose(cam.up, (0, 0, 1), atol=1e-9)


def test_click_picks_the_object_under_the_cursor(make_window, wait_frame, qtbot):
    from PyQt6.QtCore import QPoint, Qt
    from PyQt6.QtTest import QTest

    window = make_window()
    wait_frame(window)
    doc = window.document
    view = window.viewport
    for name in ("person", "metal_plate"):
        oid = doc.project.object_by_name(name).id
        x, y = view.display_position_of(oid)
        QTest.mouseClick(view.canvas, Qt.MouseButton.LeftButton,
                         Qt.KeyboardModifier.NoModifier, QPoint(x, view.canvas.height() - y - 1))
        qtbot.waitUntil(lambda oid=oid: doc.selection == oid, timeout=3000)
        # The selection is highlighted in 3D (edges drawn), and only the selection.
        assert view._actors[oid][1].prop.show_edges
        others = [a for k, (_, a) in view._actors.items() if k != oid]
        assert not any(a.prop.show_edges for a in others)
        assert view._gizmo is not None and view._gizmo_key == oid


def test_selection_from_elsewhere_highlights_in_3d(make_window, wait_frame):
    """A selection made outside the view (list, a detection click) shows in the view."""
    window = make_window()
    wait_frame(window)
    doc = window.document
    view = window.viewport
    book = doc.project.object_by_name("book").id
    doc.select(book)
    assert view._actors[book][1].prop.show_edges
    assert view._gizmo_key == book
    doc.select(None)
    assert not view._actors[book][1].prop.show_edges
    assert view._gizmo is None


def test_radar_view_shows_radar_transparent_objects_see_through(make_window, wait_frame,
                                                                 qtbot):
    window = make_window()
    wait_frame(window)
    doc = window.document
    view = window.viewport
    project = doc.project
    # Paper (the book, the paper box) mostly transmits at 60 GHz (|T|² ≈ 0.85) and is
    # opaque in the infrared.
    book = view._actors[project.object_by_name("book").id][1]
    plate = view._actors[project.object_by_name("metal_plate").id][1]
    assert view.band == "tof"
    assert book.prop.opacity == 1.0 and plate.prop.opacity == 1.0
    seen = []
    view.bandChanged.connect(seen.append)
    view.band_buttons["radar"].click()
    assert view.band == "radar" and seen == ["radar"]
    assert book.prop.opacity < 0.5
    assert plate.prop.opacity == 1.0
    assert view.band_caption.startswith("radar view")
    # Back in the ToF view the book is solid again.
    view.band_buttons["tof"].click()
    assert book.prop.opacity == 1.0
    with pytest.raises(ValueError, match="unknown band view"):
        view.set_band("x-ray")


def test_tof_view_shows_glass_and_point_targets_see_through(make_window, wait_frame):
    """Glass transmits 92 % in the infrared, about 40 % at 60 GHz (drawn more solid there);
    a point target is radar only."""
    window = make_window()
    wait_frame(window)
    doc = window.document
    view = window.viewport
    idx = doc.project.objects.index(doc.project.object_by_name("paper_box"))
    doc.set_value(f"objects[{idx}].material", "glass")
    new_id = max(o.id for o in doc.project.objects) + 1

    def add_target(data):
        target = dict(data["objects"][0], name="target", id=new_id,
                      geometry={"kind": "point_target", "rcs_m2": 1.0})
        data["objects"].append(target)

    doc.edit("Add target", add_target)
    oid_glass = doc.project.object_by_name("paper_box").id
    oid_target = doc.project.object_by_name("target").id
    assert view._actors[oid_glass][1].prop.opacity < 0.5
    assert view._actors[oid_target][1].prop.opacity < 0.5
    tof_glass = view._actors[oid_glass][1].prop.opacity
    view.set_band("radar")
    assert tof_glass < view._actors[oid_glass][1].prop.opacity < 1.0
    assert view._actors[oid_target][1].prop.opacity == 1.0
    view.set_band("visible")
    assert view._actors[oid_glass][1].prop.opacity < 0.5


def test_new_project_has_a_ground_grid_and_frames_the_fields_of_view(make_window, wait_frame):
    window = make_window(None)
    wait_frame(window)
    view = window.viewport
    assert not window.document.project.objects
    grid = view._grid_actor
    assert grid is not None and grid.GetVisibility() and not grid.GetPickable()
    xmin, xmax, ymin, ymax = view.grid_bounds
    assert xmax - xmin >= 10 and ymax - ymin >= 10
    zmin, zmax = grid.GetBounds()[4:]
    assert abs(zmin) < 0.01 and abs(zmax) < 0.01
    np.testing.assert_allclose(view.plotter.camera.up, (0, 0, 1), atol=1e-9)
    # Every corner of both frustums is inside the view, and the frustums fill a good part
    # of it (not zoomed into them, not a speck).
    w, h = view.canvas.width(), view.canvas.height()
    points = []
    for name in ("tof_fov", "radar_fov"):
        actor = view._rig_actors[name]
        local = np.asarray(actor.mapper.dataset.points)
        m = np.asarray(actor.user_matrix)
        points += list(local @ m[:3, :3].T + m[:3, 3])
    xy = np.array([_to_widget(view, p) for p in points])
    assert (xy[:, 0] >= 0).all() and (xy[:, 0] < w).all(), xy
    assert (xy[:, 1] >= 0).all() and (xy[:, 1] < h).all(), xy
    extent = xy.max(axis=0) - xy.min(axis=0)
    assert extent[0] > 0.4 * w or extent[1] > 0.4 * h, extent


def test_gizmo_drag_leaves_the_turntable_orbit(make_window, wait_frame, qtbot):
    """pyvista's gizmo switches to a trackball style on release; the view restores its own."""
    from PyQt6.QtCore import QPoint

    window = make_window()
    wait_frame(window)
    doc = window.document
    view = window.viewport
    oid = doc.project.object_by_name("person").id
    doc.select(oid)
    gizmo = view._gizmo
    arrow = gizmo._arrows[1]
    b = np.array(arrow.bounds)
    tip = ((b[0] + b[1]) / 2, b[2] + 0.9 * (b[3] - b[2]), (b[4] + b[5]) / 2)
    start = QPoint(*_to_widget(view, tip))
    before = doc.project.object_by_name("person").pose.position_m
    from PyQt6.QtTest import QTest

    QTest.mouseMove(view.canvas, QPoint(1, 1))    # Qt drops a move that changes nothing
    QTest.mouseMove(view.canvas, start)
    qtbot.wait(20)
    assert gizmo._selected_actor is arrow
    _drag(view.canvas, qtbot, start, QPoint(-100, 0), steps=5)
    assert doc.project.object_by_name("person").pose.position_m != before
    style = view.plotter.iren.interactor.GetInteractorStyle()
    assert "Terrain" in style.GetClassName()


def test_a_change_renders_at_half_resolution_then_full(make_window, wait_frame, qtbot):
    """A change renders at INTERACTIVE_SCALE at once; SETTLE_S later a full one follows.

    The window's size, DPI and line widths are restored after each reduced render, so a
    click picks the object under the cursor in full-size pixels at any moment.
    """
    from PyQt6.QtCore import QPoint, Qt
    from PyQt6.QtTest import QTest

    from app.view.offscreen_view import INTERACTIVE_SCALE, SETTLE_S

    window = make_window()
    wait_frame(window)
    view = window.viewport
    canvas = view.canvas
    win = view.plotter.render_window
    full = (canvas.width(), canvas.height())
    size, dpi = tuple(win.GetSize()), win.GetDPI()
    qtbot.waitUntil(lambda: canvas.scale == 1.0, timeout=int(SETTLE_S * 1e3) + 3000)
    canvas.request_render()               # one change, after the view has settled
    canvas.repaint()
    assert canvas.scale == INTERACTIVE_SCALE
    assert (canvas._image.width(), canvas._image.height()) == (
        int(size[0] * INTERACTIVE_SCALE), int(size[1] * INTERACTIVE_SCALE))
    assert tuple(win.GetSize()) == size and win.GetDPI() == dpi
    # Picking right after a reduced render works in full-size pixels.
    doc = window.document
    oid = doc.project.object_by_name("person").id
    x, y = view.display_position_of(oid)
    QTest.mouseClick(canvas, Qt.MouseButton.LeftButton, Qt.KeyboardModifier.NoModifier,
                     QPoint(x, canvas.height() - y - 1))
    qtbot.waitUntil(lambda: doc.selection == oid, timeout=3000)
    # When the updates stop, the view settles at full resolution.
    qtbot.waitUntil(lambda: canvas.scale == 1.0, timeout=int(SETTLE_S * 1e3) + 3000)
    assert (canvas._image.width(), canvas._image.height()) == size
    assert (canvas.width(), canvas.height()) == full


def test_cached_axes_redraw_when_their_range_changes(make_window, wait_frame, qtbot):
    """Axes are cached pictures (blitted on repaints) but still follow a new range."""
    import pyqtgraph as pg
    from PyQt6.QtWidgets import QGraphicsItem

    window = make_window()
    wait_frame(window)
    axes = [item for view in window.findChildren(pg.GraphicsView)
            for item in view.scene().items() if isinstance(item, pg.AxisItem)]
    assert axes and all(a.cacheMode() == QGraphicsItem.CacheMode.DeviceCoordinateCache
                        for a in axes)
    panel = window.profile_panel
    axis = panel.plot.getAxis("bottom")
    view = panel.plot_widget

    def axis_pixels():
        rect = axis.mapRectToScene(axis.boundingRect())
        return view.grab(view.mapFromScene(rect).boundingRect()).toImage()

    before = axis_pixels()
    low, high = panel.plot.viewRange()[0]
    panel.plot.setXRange(low + 0.37 * (high - low), high, padding=0)
    qtbot.waitUntil(lambda: axis_pixels() != before, timeout=3000)
