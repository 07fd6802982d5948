"""Many sensors on many rigs in the GUI (issue #30): the sensor editor, panels, 3D view."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from app.document.document import ProjectDocument
from app.document.sensors import rig_states, sensor_path, sensor_states
from app.frame_view import FrameView, RadarView, TofView
from app.widgets.inputs import field_error
from simcore.scene import Project
from simcore.scene.radar_config import SPEED_OF_LIGHT
from simcore.scene.snapshot import take_snapshot

pytestmark = pytest.mark.gui


def _steps(window) -> list[str]:
    stack = window.document.undo_stack
    return [stack.text(i) for i in range(stack.index())]


def _radar_view(profile_db: float, n: int = 32) -> RadarView:
    """A radar view whose profile is flat at ``profile_db`` (tells two radars apart)."""
    r = np.linspace(0.0, 5.0, n)
    v = np.linspace(-1.0, 1.0, 8)
    a = np.linspace(-60.0, 60.0, 16)
    from app.frame_view import Detections

    return RadarView(r, np.full((1, n), profile_db, np.float32), None, v,
                     np.full((8, n), profile_db, np.float32), a,
                     np.full((16, n), profile_db, np.float32), Detections.empty(), ["rx1"])


def _tof_view(depth_m: float) -> TofView:
    depth = np.full((4, 6), depth_m, np.float32)
    return TofView(depth, np.ones_like(depth), np.ones(depth.shape, bool), 7.5)


def test_add_radar_on_new_rig_rename_pick_in_panel_and_undo(make_window, qtbot):
    window = make_window()
    doc, ed, panel = window.document, window.sensor_editor, window.profile_panel
    original, n0 = doc.project, doc.undo_stack.index()
    rigs = ed.rigs
    # A new rig: 1 m to the left (+y) of the first rig, one undo step.
    rigs.add_rig()
    project = doc.project
    assert [r.name for r in project.all_rigs()] == ["rig", "rig2"]
    x, y, z = original.rig.pose.position_m
    assert project.rigs[0].pose.position_m == pytest.approx((x, y + 1.0, z))
    assert doc.selection == "rig:rig2", "picking a rig selects it for the Inspector"
    # A radar on it: default settings, named uniquely, one undo step.
    rigs.add_sensor("radar")
    assert rigs.selected == ("sensor", "radar_2")
    assert sensor_path(doc.project, "radar_2") == "rigs[0].sensors.radar_2"
    assert _steps(window)[n0:] == ["Add rig rig2", "Add radar radar_2 to rig2"]
    # The Radar page now edits radar_2: a bandwidth of 3 GHz gives c / 2B = 5.00 cm.
    assert doc.current_sensor("radar") == "radar_2"
    assert "radar_2 on rig2" in ed.radar_box.title()
    ed.radar_widgets["bandwidth_hz"].setValue(3.0)
    assert doc.project.rigs[0].sensors["radar_2"].bandwidth_hz == pytest.approx(3e9)
    assert doc.project.rig.radar.bandwidth_hz == original.rig.radar.bandwidth_hz
    res_cm = SPEED_OF_LIGHT / (2 * 3e9) * 100
    assert f"{res_cm:.2f} cm" in ed.derived.text()
    # The link budget page too.
    ed.link_form.widgets["rig.radar.tx_power_dbm"].setValue(-3.0)
    assert doc.project.rigs[0].sensors["radar_2"].tx_power_dbm == -3.0
    assert doc.project.rig.radar.tx_power_dbm == original.rig.radar.tx_power_dbm
    # The range profile panel offers both radars and keeps the one picked.
    combo = panel.sensor_combo
    assert [combo.itemText(i) for i in range(combo.count())] == ["radar", "radar_2"]
    assert combo.isVisible()
    panel.set_sensor("radar_2")
    # A name that is no identifier, or one already taken, is refused at the name box.
    steps = doc.undo_stack.index()
    for bad, why in (("front radar", "is not valid"), ("tof", "is taken")):
        rigs.name_edit.setText(bad)
        rigs.name_edit.editingFinished.emit()
        assert why in (field_error(rigs.name_edit) or ""), field_error(rigs.name_edit)
        assert doc.undo_stack.index() == steps
    rigs.name_edit.setText("front")
    rigs.name_edit.editingFinished.emit()
    assert field_error(rigs.name_edit) is None
    assert list(doc.project.rigs[0].sensors) == ["front"]
    assert _steps(window)[-1] == "Rename sensor radar_2 to front"
    # Every view follows the rename: the panel, the editors, the tree.
    assert panel.sensor == "front" and combo.currentText() == "front"
    assert doc.current_sensor("radar") == "front"
    assert rigs.selected == ("sensor", "front")
    assert "front on rig2" in ed.radar_box.title()
    doc.undo_stack.undo()
    assert panel.sensor == "radar_2" and doc.current_sensor("radar") == "radar_2"
    doc.undo_stack.redo()
    assert panel.sensor == "front"
    # Undo of every step restores the project exactly.
    while doc.undo_stack.index() > n0:
        doc.undo_stack.undo()
    assert doc.project == original
    assert panel.sensor == "radar" and doc.current_sensor("radar") == "radar"


def test_panel_draws_the_picked_sensor_and_keeps_it_across_frames(make_window, wait_frame,
                                                                   qtbot):
    """Two radars' views in one frame: the panel draws the one picked, frame after frame."""
    window = make_window()
    doc, panel = window.document, window.profile_panel
    window.sensor_editor.rigs.add_rig()
    window.sensor_editor.rigs.add_sensor("radar")
    panel.set_sensor("radar_2")
    wait_frame(window)  # no frame of the simulation comes after this one
    # Flat maps at −40 dB (radar) and −10 dB (radar_2): the processed profile, the mean
    # over Doppler, is flat at the picked radar's level.
    base = FrameView(index=0, time_s=0.0, tof=_tof_view(1.0), radar=_radar_view(-40.0),
                     object_poses=np.zeros((0, 4, 4)), rig_pose=np.eye(4),
                     tofs={"tof": _tof_view(1.0)},
                     radars={"radar": _radar_view(-40.0), "radar_2": _radar_view(-10.0)})
    for index in range(3):
        panel.show_frame(dataclasses.replace(base, index=index))
        qtbot.waitUntil(lambda i=index: panel.view is not None and panel.view.index == i)
        _, ys = panel.processed.getData()
        np.testing.assert_allclose(ys, -10.0, atol=1e-3)
    # A frame without radar_2 (a lower frame rate) leaves its last frame shown and says so.
    panel.show_frame(dataclasses.replace(base, index=3, radars={"radar": _radar_view(-40.0)}))
    assert panel.view.index == 2 and "no capture in frame 4" in panel.info.text()
    # An edit of the project does not change the choice.
    doc.set_value("dsp.min_range_m", 0.2)
    wait_frame(window)
    assert panel.sensor == "radar_2" and panel.sensor_combo.currentText() == "radar_2"
    panel.show_frame(base)
    qtbot.waitUntil(lambda: panel.view is not None and panel.view.index == 0)
    panel.set_sensor("radar")  # redraws the frame shown with the other radar
    _, ys = panel.processed.getData()
    np.testing.assert_allclose(ys, -40.0, atol=1e-3)


def test_copy_tof_camera_and_remove_sensors(make_window, wait_frame, qtbot):
    window = make_window()
    doc, rigs, tof_panel = window.document, window.sensor_editor.rigs, window.tof_panel
    original = doc.project
    rigs.select("sensor", "tof")
    # The built-in ToF camera can be removed (issue 40: a radar-only project is ordinary).
    assert rigs.remove_button.isEnabled()
    assert rigs.remove_button.toolTip() == "Remove ToF camera tof from rig rig"
    rigs.copy_selected()
    copy = doc.project.rig.sensors["tof_copy"]
    assert copy.kind == "tof"
    assert copy.model_dump(exclude={"kind"}) == original.rig.tof.model_dump()
    assert _steps(window)[-1] == "Copy ToF camera tof as tof_copy"
    assert [tof_panel.sensor_combo.itemText(i) for i in range(tof_panel.sensor_combo.count())
            ] == ["tof", "tof_copy"]
    # The ToF page edits the copy: its width changes, the original's does not.
    window.sensor_editor.tof_width.setValue(64)
    assert doc.project.rig.sensors["tof_copy"].width == 64
    assert doc.project.rig.tof.width == original.rig.tof.width
    tof_panel.set_sensor("tof_copy")
    wait_frame(window)
    # The panel shows the copy's own image: 64 columns, the built-in camera's unchanged.
    height = original.rig.tof.height
    assert tof_panel.view.tof.depth_m.shape == (height, 64)
    assert window.last_view.tofs["tof"].depth_m.shape == (height, original.rig.tof.width)
    # Remove the copy: one undo step; the panel falls back to the built-in camera.
    rigs.select("sensor", "tof_copy")
    assert rigs.remove_button.isEnabled()
    rigs.remove_selected()
    assert "tof_copy" not in doc.project.sensor_configs()
    assert _steps(window)[-1] == "Remove ToF camera tof_copy"
    assert tof_panel.sensor == "tof" and doc.current_sensor("tof") == "tof"
    assert rigs.selected == ("rig", "rig")
    doc.undo_stack.undo()
    assert "tof_copy" in doc.project.sensor_configs()
    # A rig goes with its sensors; the first rig cannot be removed.
    rigs.add_rig()
    rigs.add_sensor("rgb")
    name = rigs.selected[1]
    assert doc.project.sensors_of_kind("rgb") == {name: doc.project.rigs[0].sensors[name]}
    assert not window.docks["rgb"].isHidden(), "an RGB camera on any rig shows its panel"
    rigs.select("rig", "rig2")
    rigs.remove_selected()
    assert doc.project.rigs == [] and name not in doc.project.sensor_configs()
    rigs.select("rig", "rig")
    assert not rigs.remove_button.isEnabled()
    assert "first rig cannot be removed" in rigs.remove_button.toolTip()


def test_sensor_timing_fields_validate_with_units(make_window):
    window = make_window()
    doc, rigs = window.document, window.sensor_editor.rigs
    rigs.select("sensor", "radar")
    rate = rigs.timing.widgets["rig.tof.frame_rate_hz"]
    offset = rigs.timing.widgets["rig.tof.trigger_offset_s"]
    timeline = doc.project.timeline.frame_rate_hz
    assert timeline == 10.0
    rate.setValue(5.0)  # the timeline's 10 Hz / 2
    assert doc.project.rig.radar.frame_rate_hz == 5.0
    assert doc.project.rig.tof.frame_rate_hz is None, "the picked sensor's field, no other"
    steps = doc.undo_stack.index()
    rate.setValue(3.0)  # 10 / 3 is no whole number
    assert "not the timeline's 10 Hz divided by a whole number" in (field_error(rate) or "")
    assert doc.undo_stack.index() == steps and doc.project.rig.radar.frame_rate_hz == 5.0
    offset.setValue(50.0)  # ms: half of the 200 ms frame period at 5 Hz
    assert doc.project.rig.radar.trigger_offset_s == pytest.approx(0.05)
    offset.setValue(250.0)
    message = field_error(offset) or ""
    assert "not shorter than the sensor's frame period" in message
    assert not message.startswith("@"), "the field path is shown as words, not as a marker"
    assert doc.project.rig.radar.trigger_offset_s == pytest.approx(0.05)
    item = rigs.tree.topLevelItem(0).child(1)
    assert (item.text(0), item.text(2), item.text(3)) == ("radar", "5 Hz", "50 ms")


def test_inspector_and_3d_view_show_every_rig_and_sensor(make_window, qtbot):
    window = make_window()
    doc, rigs, view = window.document, window.sensor_editor.rigs, window.viewport
    rigs.add_rig()
    rigs.add_sensor("tof")
    # The Inspector edits the selected rig's pose like the first rig's.
    assert doc.selection == "rig:rig2"
    inspector = window.inspector
    assert inspector.heading.text().startswith("Rig rig2")
    inspector.position_edit.boxes[0].setValue(2.5)
    assert doc.project.rigs[0].pose.position_m[0] == 2.5
    assert doc.undo_stack.text(doc.undo_stack.index() - 1) == "Move rig rig2"
    # Every rig has a body, every sensor a frustum and a name at its place.
    qtbot.waitUntil(lambda: "label:tof_2" in view._rig_actors)
    project = doc.project
    states = sensor_states(project, view.time_s)
    snap = take_snapshot(project, view.time_s)
    for name in ("tof", "radar"):  # the first rig's: the engine's own snapshot
        np.testing.assert_allclose(states[name].transform, snap.sensors[name].transform)
    # tof_2 sits at rig2's pose times its mount: the rig at (2.5, y0 + 1, z0), not rotated.
    x0, y0, z0 = doc.project.rig.pose.position_m
    expected = np.array([2.5, y0 + 1.0, z0]) + np.asarray(
        project.rigs[0].sensors["tof_2"].pose_on_rig.position_m)
    np.testing.assert_allclose(states["tof_2"].transform[:3, 3], expected, atol=1e-12)
    np.testing.assert_allclose(np.asarray(view._rig_actors["fov:tof_2"].user_matrix),
                               states["tof_2"].transform, atol=1e-9)
    np.testing.assert_allclose(view._rig_actors["label:tof_2"].GetPosition(),
                               expected + (0, 0, 0.07), atol=1e-9)
    assert view._rig_actors["label:tof_2"].GetInput() == "tof_2"
    np.testing.assert_allclose(np.asarray(view._rig_actors["body:rig2"].user_matrix),
                               rig_states(project, view.time_s)[1].transform)
    # The FOV switch hides every ToF frustum, the names stay.
    view.set_sensor_fov_visible(tof=False, radar=True)
    assert not view._rig_actors["fov:tof_2"].GetVisibility()
    assert not view._rig_actors["tof_fov"].GetVisibility()
    assert view._rig_actors["radar_fov"].GetVisibility()
    assert view._rig_actors["label:tof_2"].GetVisibility()
    view.set_sensor_fov_visible(tof=True, radar=True)
    # The scene list has an entry per rig; picking it selects the rig.
    labels = [window.object_list.list.item(i).text() for i in range(2)]
    assert labels[1] == "Rig rig2"


def test_document_follows_the_current_sensor_without_a_window():
    """The editors' sensor follows renames through undo/redo; a removed one falls back."""
    from app.document import sensors

    doc = ProjectDocument(Project())
    sensors.add_rig(doc)
    name = sensors.add_sensor(doc, 1, "radar")
    doc.set_current_sensor("radar", name)
    sensors.rename_sensor(doc, name, "rear")
    assert doc.current_sensor("radar") == "rear"
    doc.undo_stack.undo()
    assert doc.current_sensor("radar") == name
    sensors.remove_sensor(doc, name)
    assert doc.current_sensor("radar") == "radar"
    # The built-in radar can go too (issue 40); then the ToF camera is the last sensor.
    sensors.remove_sensor(doc, "radar")
    assert doc.current_sensor("radar") is None and doc.project.rig.radar is None
    with pytest.raises(Exception, match="only sensor and cannot be removed"):
        sensors.remove_sensor(doc, "tof")


def test_second_radar_on_new_rig_shows_its_own_data(make_window, wait_frame, tmp_path):
    """The engine computes the added radar: its panel shows the target at its own range."""
    project = Project.model_validate({
        "name": "one target", "timeline": {"frame_rate_hz": 10.0, "duration_s": 0.5},
        "rig": {"pose": {"position_m": (0.0, 0.0, 1.0)}},
        "objects": [{"id": 1, "name": "target", "geometry": {"kind": "point_target",
                                                             "rcs_m2": 1.0},
                     "pose": {"position_m": (2.0, 1.0, 1.0)}}]})
    path = tmp_path / "one_target.json"
    path.write_text(project.model_dump_json())
    window = make_window(path)
    doc, panel, rigs = window.document, window.profile_panel, window.sensor_editor.rigs
    original = doc.project
    rigs.add_rig()  # at (0, 1, 1): the target is 2 m straight ahead of it
    rigs.add_sensor("radar")
    panel.set_sensor("radar_2")
    wait_frame(window)
    view = window.last_view
    assert set(view.radars) == {"radar", "radar_2"}
    # Ranges from the poses: radar at (0, 0, 1), radar_2 at (0, 1, 1), target (2, 1, 1).
    expected = {"radar": float(np.hypot(2.0, 1.0)), "radar_2": 2.0}
    bin_m = doc.project.rig.radar.range_resolution_m
    for name, r in expected.items():
        assert abs(view.radars[name].profile_peak_range_m() - r) <= 1.5 * bin_m, name
    # The panel draws radar_2's profile, not the built-in radar's, with its own truth.
    assert abs(panel.view.radar.profile_peak_range_m() - 2.0) <= 1.5 * bin_m
    assert panel.view.objects.range_m == pytest.approx([2.0], abs=1e-9)
    assert view.objects.range_m == pytest.approx([np.hypot(2.0, 1.0)], abs=1e-9)
    panel.set_sensor("radar")  # back to the built-in radar: its own truth again
    assert panel.view.objects.range_m == pytest.approx([np.hypot(2.0, 1.0)], abs=1e-9)
    panel.set_sensor("radar_2")
    np.testing.assert_array_equal(panel.view.radar.profile_db, view.radars["radar_2"].profile_db)
    # Rename: the panel stays on it and its next frames.
    rigs.name_edit.setText("side")
    rigs.name_edit.editingFinished.emit()
    wait_frame(window)
    assert panel.sensor == "side" and set(window.last_view.radars) == {"radar", "side"}
    np.testing.assert_array_equal(panel.view.radar.profile_db,
                                  window.last_view.radars["side"].profile_db)
    # Undo restores the project and the panel shows the built-in radar again.
    while doc.undo_stack.canUndo():
        doc.undo_stack.undo()
    assert doc.project == original
    wait_frame(window)
    assert panel.sensor == "radar" and set(window.last_view.radars) == {"radar"}
    assert abs(panel.view.radar.profile_peak_range_m() - expected["radar"]) <= 1.5 * bin_m


def test_antenna_editor_edits_the_picked_radar(make_window):
    window = make_window()
    doc, rigs, antennas = window.document, window.sensor_editor.rigs, window.antenna_editor
    original = doc.project
    rigs.add_rig()
    rigs.add_sensor("radar")
    n_rx = len(doc.project.rigs[0].sensors["radar_2"].rx)
    n_tx = len(doc.project.rigs[0].sensors["radar_2"].tx)
    antennas.add_element("rx")
    assert len(doc.project.rigs[0].sensors["radar_2"].rx) == n_rx + 1
    assert doc.project.rig.radar.rx == original.rig.radar.rx
    antennas.move_element("rx", 0, (1.25, -2.5), finished=True)
    assert doc.project.rigs[0].sensors["radar_2"].rx[0].position_mm == (1.25, -2.5)
    assert doc.project.rig.radar.rx == original.rig.radar.rx
    # Picking the built-in radar again: the antenna editor edits it.
    rigs.select("sensor", "radar")
    assert doc.current_sensor("radar") == "radar"
    antennas.add_element("tx")
    assert len(doc.project.rig.radar.tx) == len(original.rig.radar.tx) + 1
    assert len(doc.project.rigs[0].sensors["radar_2"].tx) == n_tx
