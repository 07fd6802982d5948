"""Exploring sensors: antenna board and array analysis, saving, materials, timeline, help."""

from __future__ import annotations

import numpy as np
import pytest
from PyQt6.QtCore import QEvent, QPointF, Qt
from PyQt6.QtGui import QMouseEvent
from PyQt6.QtWidgets import QApplication

from app.document.document import ProjectDocument
from app.editors.antenna_editor import AntennaEditor
from simcore.resources import EXAMPLES_DIR
from simcore.scene import load_project

pytestmark = pytest.mark.gui

OFFICE = EXAMPLES_DIR / "office.json"


# --- helpers -------------------------------------------------------------------------------
def _send(view, kind: QEvent.Type, pos: QPointF, buttons: Qt.MouseButton) -> None:
    vp = view.viewport()
    button = Qt.MouseButton.NoButton if kind == QEvent.Type.MouseMove else \
        Qt.MouseButton.LeftButton
    QApplication.sendEvent(vp, QMouseEvent(kind, pos, vp.mapToGlobal(pos), button, buttons,
                                           Qt.KeyboardModifier.NoModifier))


def _press_drag(qtbot, view, a: QPointF, b: QPointF, steps: int = 6) -> None:
    """Press at widget point ``a``, move to ``b`` in steps, release (real mouse events)."""
    left, none = Qt.MouseButton.LeftButton, Qt.MouseButton.NoButton
    _send(view, QEvent.Type.MouseMove, a, none)
    _send(view, QEvent.Type.MouseButtonPress, a, left)
    for s in np.linspace(0, 1, steps + 1)[1:]:
        _send(view, QEvent.Type.MouseMove, a + (b - a) * float(s), left)
        qtbot.wait(15)
    _send(view, QEvent.Type.MouseButtonRelease, b, none)
    qtbot.wait(15)


def _click(qtbot, view, a: QPointF) -> None:
    _send(view, QEvent.Type.MouseMove, a, Qt.MouseButton.NoButton)
    _send(view, QEvent.Type.MouseButtonPress, a, Qt.MouseButton.LeftButton)
    _send(view, QEvent.Type.MouseButtonRelease, a, Qt.MouseButton.NoButton)
    qtbot.wait(15)


def _board_point(board, x_mm: float, y_mm: float) -> QPointF:
    """Widget (viewport) coordinates of a board position."""
    scene = board.getPlotItem().vb.mapViewToScene(QPointF(x_mm, y_mm))
    return board.mapFromScene(scene).toPointF()


@pytest.fixture
def antenna_editor(qtbot):
    """An antenna editor on the office example, shown at a readable size."""
    doc = ProjectDocument()
    doc.open(OFFICE)
    editor = AntennaEditor(doc)
    doc.setParent(editor)
    qtbot.addWidget(editor)
    editor.resize(1400, 420)
    editor.show()
    qtbot.waitExposed(editor)
    qtbot.wait(50)
    return editor


def _independent_af_db(tx_mm, rx_mm, lam_m, az_deg, el_deg, steer_az=0.0, steer_el=0.0):
    """|Σ_tx Σ_rx exp(j 2π (p_tx + p_rx)·(u − u0) / λ)|² / N², dB: written out per pair."""
    def u(az, el):
        az, el = np.radians(az), np.radians(el)
        return np.array([np.sin(az) * np.cos(el), -np.sin(el), np.cos(az) * np.cos(el)])

    out = []
    u0 = u(steer_az, steer_el)
    for az, el in zip(np.broadcast_to(az_deg, np.broadcast(az_deg, el_deg).shape),
                      np.broadcast_to(el_deg, np.broadcast(az_deg, el_deg).shape), strict=True):
        d = u(az, el) - u0
        total = 0j
        for t in tx_mm:
            for r in rx_mm:
                p = np.array([t[0] + r[0], t[1] + r[1], 0.0]) * 1e-3
                total += np.exp(2j * np.pi * float(p @ d) / lam_m)
        out.append(abs(total) ** 2 / (len(tx_mm) * len(rx_mm)) ** 2)
    return 10 * np.log10(np.maximum(out, 1e-30))


# --- antenna board -------------------------------------------------------------------------
def test_tx_under_an_rx_can_be_dragged(antenna_editor, qtbot):
    ed = antenna_editor
    doc, board = ed.document, ed.board
    radar = doc.project.rig.radar
    assert radar.tx[0].position_mm == radar.rx[1].position_mm == (0.0, 0.0)
    pitch = board.snap_step_mm
    np.testing.assert_allclose(pitch, radar.rx[0].position_mm[0])  # the preset's spacing
    # Press on the Tx's exposed corner (outside the Rx circle on top of it) and drag.
    corner = _board_point(board, 0.0, 0.0) + QPointF(8, 8)
    target = _board_point(board, 0.0, 2 * pitch) + QPointF(8, 8)
    undo = doc.undo_stack.count()
    _press_drag(qtbot, board, corner, target)
    radar = doc.project.rig.radar
    np.testing.assert_allclose(radar.tx[0].position_mm, (0.0, 2 * pitch), atol=1e-6)
    assert radar.rx[1].position_mm == (0.0, 0.0)
    assert doc.undo_stack.count() == undo + 1, "one drag = one undo step"
    doc.undo_stack.undo()
    assert doc.project.rig.radar.tx[0].position_mm == (0.0, 0.0)
    qtbot.wait(20)
    # A click on the shared spot sends the top element (rx2) below: the next press there
    # grabs tx1.
    centre = _board_point(board, 0.0, 0.0)
    assert board.top_element_at((0.0, 0.0)) == ("rx", 1)
    _click(qtbot, board, centre)
    assert board.top_element_at((0.0, 0.0)) == ("tx", 0)
    _press_drag(qtbot, board, centre, _board_point(board, -pitch, 0.0))
    radar = doc.project.rig.radar
    np.testing.assert_allclose(radar.tx[0].position_mm, (-pitch, 0.0), atol=1e-6)
    assert radar.rx[1].position_mm == (0.0, 0.0)


def test_drags_keep_the_preset_pitch_and_warnings_show_on_the_board(antenna_editor, qtbot):
    ed = antenna_editor
    doc, board = ed.document, ed.board
    radar = doc.project.rig.radar
    pitch = radar.rx[0].position_mm[0]  # 2.498 mm: λ/2 at 60 GHz, not at the centre
    assert abs(pitch - 0.5 * radar.wavelength_m * 1e3) > 0.1
    assert "tx1, rx2 share (0, 0) mm" in ed.notes.text() and not ed.warnings.text()
    # Drag rx1 by about 2.4 pitches: it lands 2 pitches further, on the preset's grid.
    start = _board_point(board, *radar.rx[0].position_mm)
    end = _board_point(board, pitch + 2.4 * pitch, 0.3)
    _press_drag(qtbot, board, start, end)
    np.testing.assert_allclose(doc.project.rig.radar.rx[0].position_mm, (3 * pitch, 0.0),
                               atol=1e-6)
    # Spacing 3 pitches > λ/2: the board warns about grating lobes right away.
    assert "grating lobes" in ed.warnings.text()
    assert "grating lobes" in ed.analysis.summary.text()
    # λ/2 at the centre frequency, stated in the panel.
    ed.snap_mode.setCurrentText("λ/2 at centre frequency")
    np.testing.assert_allclose(board.snap_step_mm, 0.5 * radar.wavelength_m * 1e3)
    assert "centre frequency" in ed.info.text()


def test_add_and_remove_elements(antenna_editor):
    ed = antenna_editor
    doc = ed.document
    pitch = doc.project.rig.radar.rx[0].position_mm[0]
    ed.add_element("rx")  # continues the horizontal row (rx2, rx1) to the right
    np.testing.assert_allclose(doc.project.rig.radar.rx[-1].position_mm, (2 * pitch, 0.0),
                               atol=1e-6)
    ed.add_element("tx")  # a second Tx one row length (3 elements) to the right
    radar = doc.project.rig.radar
    np.testing.assert_allclose(radar.tx[-1].position_mm, (3 * pitch, 0.0), atol=1e-6)
    virtual_x = sorted({round(t.position_mm[0] + r.position_mm[0], 4) for t in radar.tx
                        for r in radar.rx if r.position_mm[1] == 0.0})
    np.testing.assert_allclose(np.diff(virtual_x), pitch, atol=1e-4)  # a gap-free row
    ed.remove_element("tx")
    assert len(doc.project.rig.radar.tx) == 1
    messages = []
    ed.editFailed.connect(messages.append)
    count = doc.undo_stack.count()
    ed.remove_element("tx")
    assert messages == ["a radar needs at least one Tx: tx1 stays"]
    assert doc.undo_stack.count() == count
    assert not ed.remove_tx_button.isEnabled()


def test_labels_do_not_overlap(antenna_editor, qtbot):
    ed = antenna_editor
    assert "rx2 · tx1" in ed.board.label_texts()  # one label for the shared spot
    ed.apply_layout("MIMO (2 Tx × 4 Rx)")
    qtbot.wait(50)
    rects = [item.sceneBoundingRect() for item, _, _ in ed.board.labels]
    assert len(rects) == 6
    for i, a in enumerate(rects):
        for b in rects[i + 1:]:
            assert not a.intersects(b), (a, b)


def test_beam_pattern_follows_steering_and_element_moves(antenna_editor, qtbot):
    ed = antenna_editor
    doc, view = ed.document, ed.analysis
    ed.apply_layout("MIMO (2 Tx × 4 Rx)")
    radar = doc.project.rig.radar
    tx = [a.position_mm for a in radar.tx]
    rx = [a.position_mm for a in radar.rx]
    lam = radar.wavelength_m
    angles = view.pattern.angles_deg
    pick = angles[::20]

    def expected_az(tx, rx, steer=0.0):
        return _independent_af_db(tx, rx, lam, pick, 0.0, steer_az=steer)

    shown = view.az_curve.getData()[1][::20]
    ok = expected_az(tx, rx) > -40
    np.testing.assert_allclose(shown[ok], expected_az(tx, rx)[ok], atol=1e-6)
    assert angles[np.argmax(view.az_curve.getData()[1])] == 0.0
    # A steering phase moves the main lobe to 20°.
    view.steer_az.setValue(20.0)
    az = view.az_curve.getData()[1]
    assert abs(angles[np.argmax(az)] - 20.0) < 0.3
    exp = expected_az(tx, rx, 20.0)
    ok = exp > -40
    np.testing.assert_allclose(az[::20][ok], exp[ok], atol=1e-6)
    view.steer_az.setValue(0.0)
    # Moving rx4 one pitch further out (a gap in the virtual row) changes the pattern to the
    # array factor of the new layout, live.
    pitch = rx[1][0] - rx[0][0]
    doc.set_value("rig.radar.rx[3].position_mm", (rx[3][0] + pitch, 0.0))
    rx2 = [*rx[:3], (rx[3][0] + pitch, 0.0)]
    az = view.az_curve.getData()[1]
    exp = expected_az(tx, rx2)
    ok = exp > -40
    np.testing.assert_allclose(az[::20][ok], exp[ok], atol=1e-6)
    # Elevation cut of an L (office rx): the vertical pair sets it.
    doc.undo_stack.undo()
    doc.undo_stack.undo()
    radar = doc.project.rig.radar
    el = view.el_curve.getData()[1]
    exp_el = _independent_af_db([a.position_mm for a in radar.tx],
                                [a.position_mm for a in radar.rx], lam, 0.0, pick)
    ok = exp_el > -40
    np.testing.assert_allclose(el[::20][ok], exp_el[ok], atol=1e-6)


def test_spacing_beyond_half_wavelength_shows_grating_lobes_where_theory_puts_them(
        antenna_editor):
    ed = antenna_editor
    doc = ed.document
    ed.n_spin.setValue(8)
    ed.spacing.setValue(0.8)
    ed.apply_layout("ULA")  # d = 0.8 λ > λ/2
    assert len(ed.analysis.pattern.grating_lobes()["azimuth"]) == 0  # none while unsteered
    ed.analysis.steer_az.setValue(30.0)
    # Steered to 30°: grating lobe at sin θ = sin 30° − λ/d = 0.5 − 1.25 = −0.75.
    lobes = ed.analysis.pattern.grating_lobes()["azimuth"]
    expected = np.degrees(np.arcsin(0.5 - 1 / 0.8))
    assert len(lobes) == 1 and abs(lobes[0] - expected) < 0.5, (lobes, expected)
    assert doc.project.rig.radar.rx[1].position_mm[0] == pytest.approx(
        0.8 * doc.project.rig.radar.wavelength_m * 1e3, abs=1e-6)


# --- saving ---------------------------------------------------------------------------------
def test_ctrl_s_on_an_opened_example_does_not_modify_it(make_window, qtbot, tmp_path,
                                                         monkeypatch):
    from PyQt6.QtWidgets import QFileDialog

    import app.document.document as document_module

    example_bytes = OFFICE.read_bytes()
    docs = tmp_path / "Documents"
    docs.mkdir()
    monkeypatch.setattr(document_module, "documents_folder", lambda: docs)
    monkeypatch.setattr(document_module, "_LAST_FOLDER", [])
    window = make_window(OFFICE)
    doc = window.document
    assert doc.path is None and doc.template == OFFICE.resolve()
    assert window.windowTitle().startswith("office (example)")
    doc.set_value("objects[0].pose.position_m", (2.5, 0.1, -0.05))
    asked = []
    out = tmp_path / "mine" / "office.json"
    out.parent.mkdir()

    def fake_dialog(parent, title, start, filters):
        asked.append(start)
        return str(out), filters

    monkeypatch.setattr(QFileDialog, "getSaveFileName", fake_dialog)
    window.raise_()
    window.activateWindow()
    qtbot.waitUntil(window.isActiveWindow, timeout=5000)
    window.object_list.list.setFocus()
    qtbot.keyClick(window.object_list.list, Qt.Key.Key_S, Qt.KeyboardModifier.ControlModifier)
    assert asked == [str(docs / "office.json")], asked  # asks, in the user's documents
    assert OFFICE.read_bytes() == example_bytes
    assert doc.path == out.resolve() and doc.template is None and not doc.is_dirty
    assert load_project(out) == doc.project
    assert window.windowTitle().startswith("office.json")
    # Save As now starts in the folder used last.
    asked.clear()
    window.save_as()
    assert asked == [str(out.resolve())]
    # Even when asked to, the document never writes into the examples folder.
    with pytest.raises(PermissionError):
        doc.save(OFFICE)
    assert OFFICE.read_bytes() == example_bytes
    assert not window.save_to(OFFICE)  # an error dialog instead
    window.last_error_dialog.close()
    assert OFFICE.read_bytes() == example_bytes
    # The next session's Save As starts in the folder of the newest recent (non-example) file.
    monkeypatch.setattr(document_module, "_LAST_FOLDER", [])
    document_module.remember_last_folder([str(OFFICE), str(out)])
    assert doc.suggested_save_path().parent == out.parent


# --- materials ------------------------------------------------------------------------------
@pytest.fixture
def material_editor(qtbot):
    from app.editors.material_editor import MaterialEditor

    doc = ProjectDocument()
    doc.open(OFFICE)
    editor = MaterialEditor(doc)
    doc.setParent(editor)
    qtbot.addWidget(editor)
    editor.resize(900, 380)
    editor.show()
    qtbot.waitExposed(editor)
    return editor


def _pixels_near(widget, rgb: tuple[int, int, int], tol: int = 12) -> int:
    from PyQt6.QtGui import QImage

    img = widget.grab().toImage().convertToFormat(QImage.Format.Format_RGB32)
    ptr = img.constBits()
    ptr.setsize(img.sizeInBytes())
    arr = np.frombuffer(ptr, dtype=np.uint8).reshape(img.height(), img.bytesPerLine())
    arr = arr[:, : img.width() * 4].reshape(img.height(), img.width(), 4)[..., 2::-1]
    return int(np.all(np.abs(arr.astype(int) - rgb) <= tol, axis=-1).sum())


def test_shared_material_edits_name_the_objects_and_make_unique(material_editor, tmp_path):
    ed = material_editor
    doc = ed.document
    book = doc.project.object_by_name("book")
    doc.select(book.id)
    assert ed.current == "paper"
    assert "book" in ed.users.text() and "paper_box" in ed.users.text()
    assert "changes all of them" in ed.users.text()
    assert ed.unique_button.isEnabled()
    steps = doc.undo_stack.count()
    ed.make_selected_unique()
    assert doc.undo_stack.count() == steps + 1  # one step
    assert ed.current == "paper_book"
    assert doc.project.object_by_name("book").material == "paper_book"
    assert doc.project.object_by_name("paper_box").material == "paper"
    assert ed.users.text() == "Used by book."
    ed.tof_editor.widgets["reflectance"].setValue(0.2)
    table = doc.material_table()
    assert table["paper_book"].band("tof").reflectance == 0.2
    assert table["paper"].band("tof").reflectance == 0.8  # the box keeps its paper
    out = tmp_path / "unique.json"
    doc.save(out)
    assert load_project(out) == doc.project
    doc.undo_stack.undo()
    doc.undo_stack.undo()
    assert doc.project.object_by_name("book").material == "paper"
    assert "paper_book" not in doc.material_table()


def test_visible_band_and_colour_round_trip_and_undo(material_editor, tmp_path):
    ed = material_editor
    doc = ed.document
    ed.show_material("wood")
    before = doc.project
    ed.visible_editor.widgets["reflectance"].setValue(0.35)
    ed.set_color((0.2, 0.4, 0.6))
    wood = doc.material_table()["wood"]
    assert wood.band("visible").reflectance == 0.35
    assert wood.color_rgb == (0.2, 0.4, 0.6)
    assert "0.20, 0.40, 0.60" in ed.color_button.text()
    out = tmp_path / "wood.json"
    doc.save(out)
    loaded = load_project(out)
    mat = next(m for m in loaded.materials if m.name == "wood")
    assert mat.color_rgb == (0.2, 0.4, 0.6) and mat.band("visible").reflectance == 0.35
    doc.undo_stack.undo()
    doc.undo_stack.undo()
    assert doc.project == before


def test_band_toggles_read_at_a_glance(material_editor, qtbot):
    ed = material_editor
    ed.show_material("wood")
    retro = ed.radar_editor.widgets["retroreflector"]
    assert not retro.isChecked() and not ed.radar_invisible.isChecked()
    assert _pixels_near(retro, (0x4F, 0xC3, 0xF7)) == 0
    assert _pixels_near(ed.radar_invisible, (0xFF, 0x8A, 0x65)) == 0
    retro.setChecked(True)
    ed.radar_invisible.setChecked(True)
    qtbot.wait(20)
    assert ed.document.material_table()["wood"].band("radar").opacity == 0.0
    assert _pixels_near(retro, (0x4F, 0xC3, 0xF7)) > 60  # a filled, light-blue box
    assert _pixels_near(ed.radar_invisible, (0xFF, 0x8A, 0x65)) > 500  # an orange button


# --- timeline, seed, keyframes, placement, help -------------------------------------------
def test_timeline_and_seed_editor_round_trip_and_undo(qtbot, tmp_path):
    from app.editors.timeline_editor import TimelineEditor

    doc = ProjectDocument()
    ed = TimelineEditor(doc)
    doc.setParent(ed)
    qtbot.addWidget(ed)
    assert "10 frames" in ed.derived.text() and "0.9 s" in ed.derived.text()
    ed.duration.setValue(2.5)
    ed.frame_rate.setValue(20.0)
    ed.seed.setValue(1234)
    p = doc.project
    assert (p.timeline.duration_s, p.timeline.frame_rate_hz, p.seed) == (2.5, 20.0, 1234)
    assert p.timeline.n_frames == 50
    assert "50 frames" in ed.derived.text() and "50 ms" in ed.derived.text()
    assert doc.undo_stack.count() == 3
    out = tmp_path / "timeline.json"
    doc.save(out)
    loaded = load_project(out)
    assert (loaded.timeline.duration_s, loaded.timeline.frame_rate_hz, loaded.seed) == (
        2.5, 20.0, 1234)
    doc.open(out)
    assert ed.duration.value() == 2.5 and ed.frame_rate.value() == 20.0
    assert ed.seed.value() == 1234
    doc.set_value("seed", 7)
    doc.undo_stack.undo()
    assert ed.seed.value() == 1234
    # A frame rate whose period is shorter than the radar's chirps says so.
    radar_s = doc.project.rig.radar.frame_duration_s
    ed.frame_rate.setValue(round(2.0 / radar_s, 2))
    assert "longer than the frame period" in ed.warning.text()
    assert ed.duration.maximum() > 0 and ed.duration.toolTip() and ed.seed.toolTip()


def test_new_keyframes_land_inside_the_timeline():
    from app.editors.scene_editor import new_keyframes
    from simcore.scene.model import Timeline

    tl = Timeline()  # 1 s at 10 Hz: frames at 0 … 0.9 s
    first = new_keyframes([], tl, 0.4)
    assert [k["time_s"] for k in first] == [0.0]
    second = new_keyframes(first, tl, 0.4)  # at the current time
    assert [k["time_s"] for k in second] == [0.0, 0.4]
    second[1]["position_m"] = (0.0, 0.0, 0.8)
    third = new_keyframes(second, tl, 0.4)  # taken: halfway to the last frame
    assert [k["time_s"] for k in third] == [0.0, 0.4, 0.6]
    assert third[2]["position_m"] == (0.0, 0.0, 0.8)
    middle = new_keyframes(second, tl, 0.2)  # inserted with the interpolated offset
    assert [k["time_s"] for k in middle] == [0.0, 0.2, 0.4]
    np.testing.assert_allclose(middle[1]["position_m"], (0.0, 0.0, 0.4))
    end = new_keyframes([{"time_s": 0.9, "position_m": (0, 0, 0), "rotation_deg": (0, 0, 0)}],
                        tl, None)
    assert end[-1]["time_s"] == pytest.approx(1.0)  # past the end only when at the end


def test_added_objects_sit_on_the_boresight_facing_the_sensors(make_window):
    from scipy.spatial.transform import Rotation

    from app.document.scene_edits import add_object
    from simcore.scene.snapshot import take_snapshot

    window = make_window(None)
    doc = window.document
    # Turn the rig: 30° to the left, looking 10° down, 1.5 m up.
    doc.set_value("rig.pose", {"position_m": (1.0, 2.0, 1.5), "rotation_deg": (0.0, 10.0, 30.0)})
    snap = take_snapshot(doc.project, 0.0)
    sensors = list(snap.sensors.values())
    origin = np.mean([s.transform[:3, 3] for s in sensors], axis=0)
    bore = np.sum([s.transform[:3, 2] for s in sensors], axis=0)
    bore /= np.linalg.norm(bore)
    oid = add_object(doc, "plane")
    obj = doc.project.objects[doc.index_of(oid)]
    np.testing.assert_allclose(obj.pose.position_m, origin + 2.0 * bore, atol=1e-3)
    normal = Rotation.from_euler("xyz", obj.pose.rotation_deg, degrees=True).apply((0, 0, 1))
    np.testing.assert_allclose(normal, -bore, atol=1e-6)  # the plane faces the sensors
    oid2 = add_object(doc, "corner_reflector")  # the spot is taken: a bit further out
    cr = doc.project.objects[doc.index_of(oid2)]
    assert np.linalg.norm(np.subtract(cr.pose.position_m, obj.pose.position_m)) >= 0.4
    np.testing.assert_allclose(
        np.cross(np.subtract(cr.pose.position_m, origin), bore), 0.0, atol=1e-3)
    axis = Rotation.from_euler("xyz", cr.pose.rotation_deg, degrees=True).apply((0, 0, 1))
    np.testing.assert_allclose(axis, -bore, atol=1e-6)
    box_id = add_object(doc, "box")
    box = doc.project.objects[doc.index_of(box_id)]
    assert box.pose.rotation_deg[0] == 0.0 and box.pose.rotation_deg[1] == 0.0
    assert box.pose.rotation_deg[2] == pytest.approx(30.0, abs=1e-6)  # turned, upright


def test_help_menu_timeline_dock_and_keyframe_at_current_time(make_window, qtbot):
    import simcore
    from app.dialogs.help import about_text, shortcut_rows
    from app.document.scene_edits import add_object

    window = make_window(None)
    assert "timeline" in window.docks
    actions = window.help_actions
    # About is a modal box: check its text (with the version) rather than opening it.
    assert simcore.__version__ in about_text()
    assert actions["about"].text() == "&About tofradar"
    rows = {what: keys for keys, what in shortcut_rows(window)}
    assert rows["Save"] == "Ctrl+S" and rows["Play / pause"] == "Space"
    actions["shortcuts"].trigger()
    page = window.help_page
    assert page.isVisible() and "Ctrl+S" in page.browser.toPlainText()
    page.close()
    actions["guide"].trigger()
    assert "Getting started" in window.help_page.browser.toPlainText()
    window.help_page.close()
    assert actions["doc:gui.md"].isEnabled()
    # Keyframes land at the slider's time.
    oid = add_object(window.document, "sphere")
    window.time_bar.slider.setValue(3)  # t = 0.3 s
    window.inspector.add_keyframe_button.click()
    window.inspector.add_keyframe_button.click()
    motion = window.document.project.objects[window.document.index_of(oid)].motion
    assert [k.time_s for k in motion.keyframes] == [0.0, pytest.approx(0.3)]
    # The timeline dock sets the slider's range.
    window.timeline_editor.duration.setValue(3.0)
    assert window.time.n_frames == 30 and window.time_bar.slider.maximum() == 29
    window.undo_action.trigger()
    assert window.time_bar.slider.maximum() == 9


def test_radar_interface_fields_edit_save_and_undo(material_editor, tmp_path):
    """Glass: thickness in mm at the field, the slab's transmission read-out follows, the
    edit is one undo step and survives save/load."""
    ed = material_editor
    doc = ed.document
    idx = ed.combo.findText("glass", Qt.MatchFlag.MatchContains)
    ed.combo.setCurrentIndex(idx)
    ed.refresh()
    assert ed.current == "glass"
    box = ed.radar_editor.widgets["thickness_m"]
    assert box.value() == pytest.approx(4.0)                      # 4 mm in the library
    before = ed.radar_editor.interface.text()
    box.setValue(8.0)
    band = doc.material_table()["glass"].band("radar")
    assert band.thickness_m == pytest.approx(0.008)
    # The read-out is the material's own two-way transmission at the radar's chirp centre
    # frequency, recomputed.
    _, t = band.coefficients(299_792_458.0 / doc.project.rig.radar.wavelength_m)
    assert f"{40 * np.log10(abs(t)):.1f} dB" in ed.radar_editor.interface.text()
    assert ed.radar_editor.interface.text() != before
    path = tmp_path / "glass.json"
    doc.save(path)
    assert load_project(path).materials[0].band("radar").thickness_m == pytest.approx(0.008)
    doc.undo_stack.undo()
    assert doc.material_table()["glass"].band("radar").thickness_m == pytest.approx(0.004)
    # 0 means "thick": nothing transmitted.
    box.setValue(0.0)
    assert doc.material_table()["glass"].band("radar").thickness_m is None
    assert "opaque" in ed.radar_editor.interface.text()
