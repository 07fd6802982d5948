"""Editors: sensors with derived quantities, antenna layouts, materials, meshes, time, files."""

from __future__ import annotations

import h5py
import numpy as np
import pytest
import pyvista as pv
from PyQt6.QtWidgets import QMessageBox

from app.document.scene_edits import import_mesh
from app.widgets.inputs import field_error

pytestmark = pytest.mark.gui


def test_sensor_editor_derived_quantities_and_aliasing_warnings(make_window, wait_frame):
    window = make_window()
    ed = window.sensor_editor
    text = ed.derived.text()
    assert "2.50 cm" in text and "6.40 m" in text  # BGT60TR13C: range bin, max range
    assert ed.warnings.isHidden()
    # Double the chirp slope: the back wall (5.5 m) lies beyond the unambiguous range.
    ed.radar_widgets["bandwidth_hz"].setValue(12.0)
    assert window.document.project.rig.radar.bandwidth_hz == pytest.approx(12e9)
    assert "3.20 m" in ed.derived.text() and "1.25 cm" in ed.derived.text()
    assert not ed.warnings.isHidden()
    assert "unambiguous range" in ed.warnings.text()
    # An invalid edit is refused with the reason at the field; the project is unchanged.
    before, steps = window.document.project, window.document.undo_stack.count()
    field = ed.radar_widgets["chirp_time_s"]
    field.setValue(50.0)  # 512 samples at 1 MHz need 512 µs
    assert window.document.project is before
    assert window.document.undo_stack.count() == steps
    assert "exceeds chirp time = 50.0 µs" in (field_error(field) or ""), field_error(field)
    assert field.value() == pytest.approx(50.0), "the refused value stays, marked"
    # A preset replaces the waveform and antennas but keeps the mounting pose.
    ed.apply_radar_preset("tdm_mimo_2tx4rx")
    radar = window.document.project.rig.radar
    assert len(radar.tx) == 2 and len(radar.rx) == 4 and radar.complex_iq
    assert radar.pose_on_rig.position_m == (0.0, -0.03, 0.0)
    assert "2 Tx × 4 Rx" in ed.derived.text()
    wait_frame(window)
    assert window.last_view.radar.profile_db.shape[0] == 8


def test_antenna_layout_presets(make_window):
    window = make_window()
    ed = window.antenna_editor
    half = 0.5 * window.document.project.rig.radar.wavelength_m * 1e3  # spacing 0.5 λ
    original = window.document.project.rig.radar
    ed.n_spin.setValue(4)
    ed.apply_layout("ULA")
    rx = [a.position_mm for a in window.document.project.rig.radar.rx]
    np.testing.assert_allclose(np.diff([p[0] for p in rx]), half, rtol=1e-6)
    ed.nx_spin.setValue(3)
    ed.ny_spin.setValue(2)
    ed.apply_layout("URA")
    assert len(window.document.project.rig.radar.rx) == 6
    ed.n_spin.setValue(8)
    ed.apply_layout("circular")
    pts = np.array([a.position_mm for a in window.document.project.rig.radar.rx])
    assert len(pts) == 8
    np.testing.assert_allclose(np.linalg.norm(pts - pts.mean(axis=0), axis=1),
                               np.linalg.norm(pts[0] - pts.mean(axis=0)), rtol=1e-6)
    ed.apply_layout("MIMO (2 Tx × 4 Rx)")
    radar = window.document.project.rig.radar
    virt = np.array(sorted(t.position_mm[0] + r.position_mm[0] for t in radar.tx
                           for r in radar.rx))
    np.testing.assert_allclose(np.diff(virt), half, rtol=1e-6)
    assert len(ed.board.targets) == 6
    for _ in range(4):
        window.undo_action.trigger()
    assert window.document.project.rig.radar == original


def test_material_editor_save_into_project_and_assign(make_window, monkeypatch):
    from PyQt6.QtWidgets import QInputDialog

    window = make_window()
    doc = window.document
    ed = window.material_editor
    doc.select(doc.project.object_by_name("book").id)
    assert ed.current == "paper"
    # Paper is drawn for the radar (a thin slab that mostly transmits), not invisible.
    assert not ed.radar_invisible.isChecked()
    monkeypatch.setattr(QInputDialog, "getText", lambda *a, **k: ("wet_paper", True))
    ed.save_button.click()
    assert ed.current == "wet_paper"
    assert [m.name for m in doc.project.materials] == ["wet_paper"]
    ed.radar_invisible.click()
    assert doc.project.materials[0].band("radar").opacity == 0.0
    ed.radar_invisible.click()
    ed.radar_editor.widgets["reflectance"].setValue(0.4)
    mat = doc.project.materials[0]
    assert mat.band("radar").opacity == 1.0 and mat.band("radar").reflectance == 0.4
    assert mat.band("tof").reflectance == 0.8  # the ToF side is untouched
    ed.assign_button.click()
    assert doc.project.object_by_name("book").material == "wet_paper"
    assert window.inspector.material_combo.currentText() == "wet_paper"


def test_material_description_follows_the_values(make_window):
    """The library's prose shows while the values are the library's; after an edit it is
    struck through and the line computed from the values says what the material does."""
    window = make_window()
    doc = window.document
    ed = window.material_editor
    doc.select(doc.project.object_by_name("book").id)
    assert ed.current == "paper"
    text = ed.description.text()
    assert "mostly transparent to 60 GHz radar" in text and "<s>" not in text
    assert "radar: invisible" not in text
    ed.radar_invisible.click()                     # paper becomes invisible to the radar
    text = ed.description.text()
    assert "<s>" in text and "radar: invisible" in text, text
    window.undo_action.trigger()
    assert "<s>" not in ed.description.text()


def test_import_mesh_duplicate_delete(make_window, wait_frame, tmp_path):
    window = make_window(None)
    doc = window.document
    stl = tmp_path / "bunny_like.stl"
    pv.Sphere(radius=0.3).save(stl)
    oid = import_mesh(doc, stl)
    obj = doc.project.objects[doc.index_of(oid)]
    assert obj.geometry.kind == "mesh" and obj.name == "bunny_like"
    assert obj.id in window.viewport._actors
    window.duplicate_action.trigger()
    assert [o.name for o in doc.project.objects] == ["bunny_like", "bunny_like_copy"]
    window.delete_action.trigger()
    assert [o.name for o in doc.project.objects] == ["bunny_like"]
    wait_frame(window)
    assert window.last_view.radar is not None


def test_time_controls_step_play_and_motion(make_window, wait_frame, qtbot):
    window = make_window()
    wait_frame(window)
    doc = window.document
    person = doc.index_of(doc.project.object_by_name("person").id)
    p0 = window.viewport._snapshot.objects[person].origin.copy()
    window.time_bar.forward_button.click()
    assert window.time.index == 1
    wait_frame(window)
    assert window.last_view.index == 1
    assert window.last_view.time_s == pytest.approx(0.1)
    window.time_bar.slider.setValue(10)
    assert window.time.index == 10
    p10 = window.viewport._snapshot.objects[person].origin
    assert np.linalg.norm(p10 - p0) > 0.2  # the person walks (keyframes)
    wait_frame(window)
    window.time_bar.play_button.click()
    assert window.time.playing
    qtbot.waitUntil(lambda: window.time.index >= 12, timeout=30_000)
    window.time_bar.play_button.click()
    assert not window.time.playing
    assert "frame" in window.time_bar.label.text()


def test_unsaved_changes_prompt_and_recent_files(make_window, tmp_path):
    window = make_window()
    doc = window.document
    doc.set_value("name", "changed")
    answers = []

    def ask():
        answers.append(1)
        return QMessageBox.StandardButton.Cancel

    window.ask_save_changes = ask
    window.new_project()
    assert answers and doc.project.name == "changed"  # cancelled: nothing happened
    window.ask_save_changes = lambda: QMessageBox.StandardButton.Discard
    window.new_project()
    assert doc.project.objects == [] and doc.path is None and not doc.is_dirty
    assert window.windowTitle().startswith("untitled")
    out = tmp_path / "empty.json"
    assert window.save_to(out)
    assert window.recent_files()[0] == str(out.resolve())


def test_export_dataset_and_panel_images(make_window, wait_frame, qtbot, tmp_path):
    window = make_window()
    wait_frame(window)
    images = window.export_images(tmp_path / "images")
    assert len(images) == 5 and all(p.stat().st_size > 5_000 for p in images)
    out = tmp_path / "office.h5"
    job = window.export_dataset(out, n_frames=2)
    assert window.progress_dialog.isVisible()
    qtbot.waitUntil(lambda: job.isFinished(), timeout=120_000)
    qtbot.wait(20)
    assert not window.progress_dialog.isVisible()
    assert job.report is not None and job.report.frames_done == 2
    with h5py.File(out) as f:
        assert f["/time"].shape == (2,)
        assert f["/tof/depth"].shape[0] == 2
    # Cancel: the job stops after the frame in progress and says so.
    out2 = tmp_path / "cancelled.h5"
    job = window.export_dataset(out2, n_frames=8)
    qtbot.waitUntil(lambda: window.progress_dialog.value() >= 1, timeout=120_000)
    from PyQt6.QtWidgets import QPushButton

    cancel = [b for b in window.progress_dialog.findChildren(QPushButton)
              if b.text() == "Cancel"][0]
    cancel.click()
    qtbot.waitUntil(lambda: job.isFinished(), timeout=120_000)
    assert job.report.interrupted and job.report.frames_done < 8
    with h5py.File(out2) as f:
        assert f["/time"].shape == (job.report.frames_done,)


def test_motion_editing_in_inspector_and_shortcuts(make_window, qtbot):
    from PyQt6.QtCore import Qt

    from app.document.scene_edits import add_object

    window = make_window(None)
    doc = window.document
    oid = add_object(doc, "sphere", position_m=(2.0, 0.0, 1.0))
    insp = window.inspector
    insp.velocity_edit.boxes[1].setValue(0.5)  # 0.5 m/s along world y
    obj = doc.project.objects[doc.index_of(oid)]
    assert obj.motion.velocity_mps == (0.0, 0.5, 0.0)
    window.time_bar.slider.setValue(window.time.n_frames - 1)  # t = 0.9 s (10 fps, 1 s)
    origin = window.viewport._snapshot.objects[doc.index_of(oid)].origin
    np.testing.assert_allclose(origin, (2.0, 0.45, 1.0), atol=1e-9)
    # Keyframes and constant velocities exclude each other: the edit is refused, with a
    # message; "Add keyframe" switches the object to keyframed motion.
    messages = []
    insp.editFailed.connect(messages.append)
    insp.add_keyframe_button.click()
    insp.add_keyframe_button.click()
    motion = doc.project.objects[doc.index_of(oid)].motion
    assert len(motion.keyframes) == 2 and motion.velocity_mps == (0.0, 0.0, 0.0)
    insp.keyframe_table.item(1, 3).setText("0.4")  # z offset of keyframe 2
    assert doc.project.objects[doc.index_of(oid)].motion.keyframes[1].position_m[2] == 0.4
    insp.keyframe_table.item(1, 0).setText("0")  # time not after keyframe 1: refused
    assert messages and "keyframe" in messages[-1]
    # "Add keyframe" put keyframe 2 at the current time, the last frame (0.9 s).
    assert doc.project.objects[doc.index_of(oid)].motion.keyframes[1].time_s == 0.9
    # Ctrl+Z / Ctrl+Shift+Z undo and redo from anywhere in the window.
    n = doc.undo_stack.index()
    window.raise_()
    window.activateWindow()
    qtbot.waitUntil(window.isActiveWindow, timeout=5000)
    target = window.object_list.list
    target.setFocus()
    qtbot.keyClick(target, Qt.Key.Key_Z, Qt.KeyboardModifier.ControlModifier)
    assert doc.undo_stack.index() == n - 1
    qtbot.keyClick(target, Qt.Key.Key_Z,
                   Qt.KeyboardModifier.ControlModifier | Qt.KeyboardModifier.ShiftModifier)
    assert doc.undo_stack.index() == n
    # Del deletes the selected object from the scene list, not from the keyframe table.
    doc.select(oid)
    insp.keyframe_table.setFocus()
    qtbot.keyClick(insp.keyframe_table, Qt.Key.Key_Delete)
    assert len(doc.project.objects) == 1
    target.setFocus()
    qtbot.keyClick(target, Qt.Key.Key_Delete)
    assert doc.project.objects == []


def test_hover_readouts_show_values(make_window, wait_frame, qtbot):
    window = make_window()
    wait_frame(window)
    rd = window.rd_panel
    centre = rd.plot.vb.mapViewToScene(rd.plot.vb.viewRect().center())
    rd._on_hover(centre)
    assert "m/s" in rd.readout.text() and "dB" in rd.readout.text()
    prof = window.profile_panel
    prof._on_hover(prof.plot.vb.mapViewToScene(prof.plot.vb.viewRect().center()))
    assert "range" in prof.readout.text() and "rx1" in prof.readout.text()
    tof = window.tof_panel
    from PyQt6.QtCore import QPointF

    def pixel_visible() -> bool:
        centre = tof.depth_image.mapToScene(QPointF(112.5, 85.5))
        return tof.view is not None and tof.depth_plot.sceneBoundingRect().contains(centre)

    qtbot.waitUntil(pixel_visible, timeout=5000)  # the view box auto-ranges lazily
    tof._on_hover(tof.depth_image.mapToScene(QPointF(112.5, 85.5)))
    assert "px (112, 85)" in tof.readout.text()
    assert "depth" in tof.readout.text() or "invalid" in tof.readout.text()
    ra = window.ra_panel
    ra._on_hover(ra.plot.vb.mapViewToScene(ra.plot.vb.viewRect().center()))
    assert "azimuth" in ra.readout.text()
