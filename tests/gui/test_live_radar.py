"""Edits in the GUI reach the radar maps: dragging objects, antennas, stale results."""

from __future__ import annotations

import time

import numpy as np
import pytest
from PyQt6.QtCore import QPointF, Qt
from PyQt6.QtWidgets import QApplication

from app.document.scene_edits import add_object
from app.editors.antenna_editor import snap_to_grid
from simcore.scene.snapshot import take_snapshot

pytestmark = pytest.mark.gui


def _gizmo_steps(start: np.ndarray, end: np.ndarray, steps: int) -> list[np.ndarray]:
    out = []
    for s in np.linspace(0, 1, steps + 1)[1:]:
        m = start.copy()
        m[:3, 3] = start[:3, 3] + s * (end[:3, 3] - start[:3, 3])
        out.append(m)
    return out


def _peak_near(window, lo: float, hi: float) -> float:
    radar = window.last_view.radar
    mean = 10 * np.log10(np.mean(10 ** (radar.profile_db / 10), axis=0))
    mask = (radar.range_axis_m >= lo) & (radar.range_axis_m <= hi)
    return float(radar.range_axis_m[mask][np.argmax(mean[mask])])


def test_dragging_a_sphere_moves_the_range_peak(make_window, wait_frame, qtbot):
    window = make_window()
    wait_frame(window)
    doc = window.document
    rig = take_snapshot(doc.project, 0.0).sensors["radar"].position
    start = rig + np.array([1.4, 0.0, 0.0])
    oid = add_object(doc, "sphere", position_m=tuple(start),
                     geometry={"kind": "sphere", "radius_m": 0.3}, material="aluminium")
    assert doc.selection == oid
    wait_frame(window)
    near_1 = _peak_near(window, 0.5, 2.6)
    assert abs(near_1 - (1.4 - 0.3)) < 0.15, near_1
    # Drag it 0.9 m further away through the gizmo's code path, in several steps.
    world = window.viewport._selected_world()
    target = world.copy()
    target[:3, 3] += np.array([0.9, 0.0, 0.0])
    undo_count = doc.undo_stack.count()
    for m in _gizmo_steps(world, target, 5):
        window.viewport.drag_to(oid, m, finished=False)
        qtbot.wait(30)
    window.viewport.drag_to(oid, target, finished=True)
    assert doc.undo_stack.count() == undo_count + 1, "one drag = one undo step"
    obj = doc.project.objects[doc.index_of(oid)]
    np.testing.assert_allclose(obj.pose.position_m, start + [0.9, 0, 0], atol=1e-6)
    wait_frame(window)
    near_2 = _peak_near(window, 0.5, 2.6)
    assert abs(near_2 - (2.3 - 0.3)) < 0.15, near_2
    assert near_2 - near_1 == pytest.approx(0.9, abs=0.12)
    # Undo restores the position before the drag.
    window.undo_action.trigger()
    np.testing.assert_allclose(doc.project.objects[doc.index_of(oid)].pose.position_m, start,
                               atol=1e-9)
    wait_frame(window)
    assert abs(_peak_near(window, 0.5, 2.6) - near_1) < 0.05


def _drag_item(qtbot, view, start: QPointF, end: QPointF, steps: int = 6) -> None:
    """Press, move and release the left button on a QGraphicsView's viewport."""
    from PyQt6.QtCore import QEvent
    from PyQt6.QtGui import QMouseEvent

    vp = view.viewport()

    def send(kind, pos, buttons):
        button = Qt.MouseButton.LeftButton if kind != QEvent.Type.MouseMove else \
            Qt.MouseButton.NoButton
        ev = QMouseEvent(kind, pos, vp.mapToGlobal(pos), button, buttons,
                         Qt.KeyboardModifier.NoModifier)
        QApplication.sendEvent(vp, ev)

    a = view.mapFromScene(start).toPointF()
    b = view.mapFromScene(end).toPointF()
    send(QEvent.Type.MouseMove, a, Qt.MouseButton.NoButton)
    send(QEvent.Type.MouseButtonPress, a, Qt.MouseButton.LeftButton)
    for s in np.linspace(0, 1, steps + 1)[1:]:
        send(QEvent.Type.MouseMove, a + (b - a) * float(s), Qt.MouseButton.LeftButton)
        qtbot.wait(20)
    send(QEvent.Type.MouseButtonRelease, b, Qt.MouseButton.NoButton)


def test_dragging_an_rx_changes_azimuth_without_rerender(make_window, wait_frame, qtbot):
    window = make_window()
    wait_frame(window)
    doc = window.document
    window.docks["antennas"].raise_()
    qtbot.wait(50)
    before = window.last_view.radar.detections
    az_before = np.sort(before.azimuth_deg)
    renders = window.sim.render_count
    assert renders > 0
    board = window.antenna_editor.board
    half = window.antenna_editor.board.snap_step_mm
    rx0 = doc.project.rig.radar.rx[0].position_mm
    start = board.element_scene_pos("rx", 0)
    end_view = QPointF(rx0[0] + 2 * half, rx0[1])
    end = board.getPlotItem().vb.mapViewToScene(end_view)
    undo_count = doc.undo_stack.count()
    t0 = time.perf_counter()
    _drag_item(qtbot, board, start, end)
    new_pos = doc.project.rig.radar.rx[0].position_mm
    assert new_pos == snap_to_grid((rx0[0] + 2 * half, rx0[1]), half), new_pos
    assert doc.undo_stack.count() == undo_count + 1
    wait_frame(window)
    latency_ms = (time.perf_counter() - t0) * 1e3
    after = window.last_view.radar.detections
    assert window.sim.render_count == renders, "moving an antenna must not re-render"
    assert window.last_view.render_count == renders
    az_after = np.sort(after.azimuth_deg)
    assert len(az_after) > 0
    changed = len(az_after) != len(az_before) or np.max(np.abs(az_after - az_before)) > 2.0
    assert changed, (az_before, az_after)
    print(f"antenna drag -> updated radar maps: {latency_ms:.0f} ms "
          f"(last request latency {window.last_view.latency_ms:.0f} ms)")
    window.undo_action.trigger()
    assert doc.project.rig.radar.rx[0].position_mm == rx0


def test_latest_request_wins_and_gui_stays_responsive(make_window, wait_frame, qtbot):
    window = make_window()
    wait_frame(window)
    doc = window.document
    doc.set_value("rig.pose.position_m", (0.01, 0.0, 1.2))  # warm-up edit
    wait_frame(window)
    dropped_before = window.sim.dropped
    gaps = []
    last = [time.perf_counter()]

    def tick():
        now = time.perf_counter()
        gaps.append(now - last[0])
        last[0] = now

    from PyQt6.QtCore import QTimer

    timer = QTimer()
    timer.timeout.connect(tick)
    timer.start(10)
    qtbot.wait(30)
    gaps.clear()
    # A burst of edits: every one requests a frame, only the last may be shown.
    for i in range(8):
        doc.set_value("rig.pose.position_m", (0.02 * (i + 1), 0.0, 1.2))
        qtbot.wait(60)
    serial = window.sim.latest_serial
    wait_frame(window)
    timer.stop()
    assert window.last_view.request_serial == serial
    assert window.sim.dropped > dropped_before or window.sim.latest_serial - serial == 0
    shown = window.viewport._snapshot.rig.origin
    np.testing.assert_allclose(shown, (0.16, 0.0, 1.2))
    p90 = float(np.percentile(gaps, 90))
    print(f"event loop during a burst of edits: longest stall {max(gaps) * 1e3:.0f} ms, "
          f"90th percentile {p90 * 1e3:.0f} ms")
    # Thresholds leave room for a 2-core machine where software OpenGL repaints the whole
    # window on the same cores (p90 ≈ 330 ms measured in CI); a GUI thread that computed
    # the frames itself would stall for whole frame times on every edit of the burst.
    assert max(gaps) < 1.0, f"event loop blocked for {max(gaps) * 1e3:.0f} ms"
    assert p90 < 0.6, f"event loop sluggish: 90th percentile {p90 * 1e3:.0f} ms"
