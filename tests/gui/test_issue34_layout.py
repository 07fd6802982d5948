"""Issue #34, defects 3, 4, 6, 7 and 8: each test replays what a new user did.

3. a layout readable at 1366×768 and 1920×1080 (antenna board ≥ 200 px, no column of the
   Sensors or Materials tab cut off, the range-profile legend beside the data);
4. the antenna editor's numeric table, in sync with the board both ways, one undo step
   per edit, bad input refused at the field;
6. truth marks at an object's nearest surface point as well as its reference point, and
   names on hover when more than six objects are shown;
7. the export dialog: format, frames or duration, seed, previews, destination, and a
   closing dialog that opens the folder or the dataset;
8. the range profile's title says whether static clutter removal is on.
"""

from __future__ import annotations

from pathlib import Path

import h5py
import pytest
from PyQt6.QtCore import QPointF, QRect, Qt, QUrl
from PyQt6.QtWidgets import QApplication, QMessageBox, QPushButton

from app.widgets.inputs import field_error
from simcore.resources import EXAMPLES_DIR

pytestmark = pytest.mark.gui


def _columns() -> tuple[int, int, int, int]:
    """The antenna table's columns (imported here: the table is new in issue #34)."""
    from app.editors.antenna_table import NAME, PATTERN, X, Y

    return NAME, X, Y, PATTERN


def _visible_rect(widget) -> QRect:
    """The part of ``widget`` its ancestors leave visible (window coordinates)."""
    rect = QRect(widget.mapTo(widget.window(), widget.rect().topLeft()), widget.size())
    parent = widget.parentWidget()
    while parent is not None:
        top_left = parent.mapTo(parent.window(), parent.rect().topLeft()) \
            if parent is not parent.window() else parent.rect().topLeft()
        rect = rect.intersected(QRect(top_left, parent.size()))
        parent = parent.parentWidget()
    return rect


def _fully_visible(widget) -> tuple[bool, tuple[int, int, int]]:
    """No part of ``widget`` is cut off at its ancestors' left or right edge.

    A column stacked under another may lie below the scrolled view (the dock scrolls
    vertically to it); only a cut across its width hides part of every row.
    """
    x0 = widget.mapTo(widget.window(), widget.rect().topLeft()).x()
    left, right = x0, x0 + widget.width()
    parent = widget.parentWidget()
    while parent is not None and parent is not parent.window():
        p0 = parent.mapTo(parent.window(), parent.rect().topLeft()).x()
        left, right = max(left, p0), min(right, p0 + parent.width())
        parent = parent.parentWidget()
    return right - left >= widget.width() - 1, (left, right, widget.width())


def _default_layout(window, size):
    """The window as a first start on a screen of ``size`` lays it out."""
    window.restoreState(window._default_state)
    window.resize(*size)
    window.size_docks(window.size())
    for _ in range(5):
        QApplication.processEvents()


# --- 3: layout ---------------------------------------------------------------------------
@pytest.mark.parametrize("size", [(1366, 768), (1920, 1080)])
def test_default_layout_is_readable(make_window, wait_frame, size):
    window = make_window()
    wait_frame(window)
    _default_layout(window, size)
    window.docks["antennas"].raise_()
    QApplication.processEvents()
    board = window.antenna_editor.board
    assert board.width() >= 200, board.width()
    assert _visible_rect(board).width() >= 200
    assert _fully_visible(window.antenna_editor.table.table)[0]
    # Nothing of the antenna editor lies past the dock's right edge (the beam pattern was
    # cut off behind a horizontal scroll bar at 1366×768).
    assert not window.docks["antennas"].widget().horizontalScrollBar().isVisible()
    pattern = window.antenna_editor.analysis.pattern_plot
    assert _fully_visible(pattern)[0]
    # …and the plot inside it is no wider than the widget (a long title widens it).
    assert pattern.getPlotItem().geometry().width() <= pattern.width() + 0.5
    # Inspector: an object's vectors (size, position, velocity…) fit the Scene column, each
    # value whole, instead of lying past its edge behind a horizontal scroll bar.
    doc = window.document
    doc.select(doc.project.object_by_name("desk1_top").id)
    QApplication.processEvents()
    inspector = window.inspector
    assert not inspector.horizontalScrollBar().isVisible()
    size = inspector._geometry_widgets["size_m"]
    for box in [*size.boxes, *inspector.angular_edit.boxes]:
        assert _fully_visible(box)[0]
        text = box.lineEdit().text()                 # "x 0.800 m": prefix, value, unit
        assert box.lineEdit().fontMetrics().horizontalAdvance(text) <= box.lineEdit().width()
    # Sensors: the derived-quantities column is whole (beside or under the form).
    window.docks["sensors"].raise_()
    QApplication.processEvents()
    derived = window.sensor_editor.derived
    ok, where = _fully_visible(derived.parentWidget())
    assert derived.isVisible() and ok, where
    # Materials: the Visible band's column is whole.
    window.docks["materials"].raise_()
    QApplication.processEvents()
    visible = window.material_editor.visible_editor
    assert visible.isVisible() and _fully_visible(visible)[0]


def test_material_columns_stack_instead_of_being_cut_off_in_a_narrow_dock(make_window,
                                                                          wait_frame):
    window = make_window()
    wait_frame(window)
    _default_layout(window, (1366, 768))
    window.docks["materials"].raise_()
    # The user widens the live panels: the Materials dock gets narrow.
    window.resizeDocks([window.docks["tof"]], [900], Qt.Orientation.Horizontal)
    for _ in range(5):
        QApplication.processEvents()
    bands = window.material_editor.bands
    assert bands.width() < bands.side_by_side_width()             # too narrow for a row
    assert bands.stacked
    assert _fully_visible(window.material_editor.visible_editor)[0]


@pytest.mark.parametrize("size", [(1366, 768), (1297, 729)])
def test_range_profile_legend_is_beside_the_data(make_window, wait_frame, size):
    # 1297×729: the window a first start opens on a 1366×768 screen (95 % of it).
    window = make_window()
    wait_frame(window)
    _default_layout(window, size)
    panel = window.profile_panel
    panel.draw_now()
    QApplication.processEvents()
    legend = panel.legend.sceneBoundingRect()
    data = panel.plot.vb.sceneBoundingRect()
    # Right of the data (to the pixel), not over it.
    assert legend.width() > 0 and legend.left() >= data.right() - 1.0, (legend, data)
    # The plot fits its widget: the range axis and its "range (m)" are not cut off below
    # (the legend's three rows made the plot taller than the dock at 1297×729).
    axis = panel.plot.getAxis("bottom").sceneBoundingRect()
    assert axis.bottom() <= panel.plot_widget.height() + 0.5, (axis, panel.plot_widget.height())


def test_beam_pattern_names_its_curves_outside_the_data(make_window):
    window = make_window()
    plot = window.antenna_editor.analysis.pattern_plot.getPlotItem()
    assert plot.legend is None                      # no legend box drawn over the curves
    title = plot.titleLabel.text
    assert "azimuth" in title and "elevation" in title


# --- 4: antenna table ------------------------------------------------------------------
def test_antenna_table_types_positions_in_mm_in_sync_with_the_board(make_window, qtbot):
    NAME, X, Y, PATTERN = _columns()  # noqa: N806
    window = make_window()
    ed = window.antenna_editor
    doc = window.document
    table = ed.table
    radar = doc.project.rig.radar
    rows = table.element_rows()
    assert len(rows) == len(radar.tx) + len(radar.rx)
    assert rows[table.row_of("rx", 1)][NAME] == radar.rx[1].name
    # Type an exact x for rx2: one undo step, the project and the board follow.
    depth = doc.undo_stack.count()
    table.set_cell("rx", 1, X, "1.25")
    assert doc.project.rig.radar.rx[1].position_mm == (1.25, radar.rx[1].position_mm[1])
    assert doc.undo_stack.count() == depth + 1
    assert "1.25 mm" in doc.undo_stack.undoText()
    assert ed.board.targets[("rx", 1)].pos().x() == pytest.approx(1.25)
    table.set_cell("rx", 1, Y, "-3 mm")
    assert doc.project.rig.radar.rx[1].position_mm == (1.25, -3.0)
    assert doc.undo_stack.count() == depth + 2
    # A drag on the board shows in the table.
    ed.move_element("rx", 0, (5.0, 2.5), finished=True)
    assert table.element_rows()[table.row_of("rx", 0)][X:Y + 1] == ("5", "2.5")
    # Undo goes back one cell edit at a time, and the table follows.
    doc.undo_stack.undo()  # the drag
    doc.undo_stack.undo()  # y
    assert table.element_rows()[table.row_of("rx", 1)][Y] == f"{radar.rx[1].position_mm[1]:g}"
    # Rename and pattern.
    table.set_cell("tx", 0, NAME, "txA")
    assert doc.project.rig.radar.tx[0].name == "txA"
    table.set_cell("tx", 0, PATTERN, "cos 2×4")
    pattern = doc.project.rig.radar.tx[0].pattern
    assert (pattern.exponent_az, pattern.exponent_el) == (2.0, 4.0)


@pytest.mark.parametrize("text", ["abc", "5000", "nan"])
def test_antenna_table_refuses_bad_input_at_the_field(make_window, text):
    _, X, _, _ = _columns()  # noqa: N806
    window = make_window()
    doc = window.document
    table = window.antenna_editor.table
    before = doc.project.rig.radar.rx[0].position_mm
    depth = doc.undo_stack.count()
    table.set_cell("rx", 0, X, text)
    assert doc.project.rig.radar.rx[0].position_mm == before      # nothing committed
    assert doc.undo_stack.count() == depth
    message = field_error(table.table)
    assert message, "no red frame / message"
    assert "red" in table.table.styleSheet() or "#ff6b6b" in table.table.styleSheet()
    item = table.table.item(table.row_of("rx", 0), X)
    assert item.text() == text                                   # kept for correcting
    # A good value clears the mark.
    table.set_cell("rx", 0, X, "0.5")
    assert field_error(table.table) is None
    assert doc.project.rig.radar.rx[0].position_mm[0] == 0.5


# --- 6: truth marks ------------------------------------------------------------------------
def _boxes(window, centres: list[float], *, size: float = 0.5, lateral: float = 0.0) -> None:
    """Replace the scene by boxes on the radar's boresight (world +x in the empty project)."""

    def mutate(d):
        d["objects"] = [
            {"id": k + 1, "name": f"box{k + 1}",
             "geometry": {"kind": "box", "size_m": (size, size, size)},
             "pose": {"position_m": (c, lateral * (k - len(centres) / 2), 0.0)},
             "material": "aluminium"}
            for k, c in enumerate(centres)]

    window.document.edit("boxes", mutate)


def test_a_box_truth_shows_its_front_face_as_well_as_its_centre(make_window, wait_frame):
    window = make_window(None)
    _boxes(window, [2.0])
    wait_frame(window)
    panel = window.profile_panel
    panel.draw_now()
    refs = [line.value() for line in panel.truth_lines if line.isVisible()]
    near = panel.near_ranges()
    assert refs == [pytest.approx(2.0)]
    assert near == [pytest.approx(1.75, abs=1e-5)]                # the face the radar sees
    rd = window.rd_panel
    rd.draw_now()
    x, _ = rd.truth_near.getData()
    assert list(x) == [pytest.approx(1.75, abs=1e-5)]


def test_truth_names_on_hover_when_more_than_six_objects(make_window, wait_frame):
    window = make_window(None)
    centres = [1.0 + 0.6 * k for k in range(8)]
    _boxes(window, centres, size=0.2, lateral=0.05)
    wait_frame(window)
    panel = window.profile_panel
    panel.draw_now()
    shown = [line for line in panel.truth_lines if line.isVisible()]
    assert len(shown) > 6
    assert all(line.label.format == "" for line in shown)        # too many to label
    target = shown[3]
    oid = target.object_id
    scene = panel.plot.vb.mapViewToScene(QPointF(target.value(), -50.0))
    panel._on_hover(scene)
    name = panel.object_label(oid)
    assert f"→ {name}:" in panel.readout.text()
    assert f"reference point {target.value():.3f} m" in panel.readout.text()


# --- 7: export dialog -------------------------------------------------------------------
def test_export_dialog_offers_the_cli_options_and_ends_with_an_open_dialog(make_window,
                                                                            wait_frame,
                                                                            qtbot, tmp_path):
    window = make_window()
    wait_frame(window)
    opened: list[QUrl] = []
    window.open_url = lambda url: opened.append(url) or True
    dialog = window.export_dataset_dialog()
    # Every format of tofradar run --out (simcore.io.writer.open_writer).
    assert [dialog.format.itemText(i) for i in range(dialog.format.count())] == [
        "HDF5 dataset (.h5)", "Zarr store (.zarr)", "MCAP recording (.mcap)"]
    dialog.format.setCurrentIndex(2)
    assert dialog.destination.text().endswith(".mcap")
    dialog.format.setCurrentIndex(1)
    assert dialog.destination.text().endswith(".zarr")
    dialog.format.setCurrentIndex(0)
    out = tmp_path / "run.h5"
    dialog.destination.setText(str(out))
    # Duration: 0.25 s at the timeline's rate.
    dialog.by_duration.setChecked(True)
    rate = window.document.project.timeline.frame_rate_hz
    dialog.duration.setValue(2 / rate)
    assert dialog.n_frames() == 2
    dialog.seed.setValue(1234)
    dialog.previews.setChecked(True)
    previews = tmp_path / "previews"
    dialog.preview_dir.setText(str(previews))
    dialog.accept()
    job = window.export_job
    assert job is not None and job.seed == 1234
    qtbot.waitUntil(job.isFinished, timeout=120_000)
    qtbot.waitUntil(lambda: window.completion_dialog is not None
                    and window.completion_dialog.isVisible(), timeout=10_000)
    with h5py.File(out) as f:
        assert f["/time"].shape == (2,)
    assert sorted(previews.glob("frame_00000_*.png")) and sorted(previews.glob("frame_00001_*"))
    box = window.completion_dialog
    buttons = {b.text(): b for b in box.findChildren(QPushButton)}
    assert {"Open folder", "Open dataset", "Open previews"} <= set(buttons)
    assert buttons["Open dataset"].property("url") == QUrl.fromLocalFile(str(out.resolve()))
    assert buttons["Open folder"].property("url") == QUrl.fromLocalFile(str(tmp_path.resolve()))
    buttons["Open dataset"].click()
    assert opened == [QUrl.fromLocalFile(str(out.resolve()))]
    assert box.isVisible()                                       # stays for "Open folder"
    box.close()


def test_export_dialog_proposes_no_destination_in_the_bundled_examples(make_window,
                                                                        wait_frame):
    window = make_window(EXAMPLES_DIR / "office.json")   # the example, opened as a template
    assert window.document.template is not None
    wait_frame(window)
    dialog = window.export_dataset_dialog()
    proposed = Path(dialog.destination.text()).resolve()
    assert EXAMPLES_DIR.resolve() not in proposed.parents
    assert proposed.parent == window.document.suggested_save_path().parent.resolve()
    dialog.reject()


def test_export_dialog_refuses_a_destination_without_a_format(make_window, tmp_path):
    window = make_window()
    dialog = window.export_dataset_dialog()
    dialog.destination.setText(str(tmp_path / "run.txt"))
    dialog.accept()
    assert dialog.isVisible() and window.export_job is None
    assert ".h5, .zarr or .mcap" in (field_error(dialog.destination) or "")
    dialog.reject()


def test_export_dialog_writes_a_zarr_store(make_window, wait_frame, qtbot, tmp_path):
    """Zarr, which tofradar run --out also writes: the store is a folder the dialog takes."""
    from simcore.io import open_dataset

    window = make_window()
    wait_frame(window)
    window.open_url = lambda url: True
    dialog = window.export_dataset_dialog()
    out = tmp_path / "run.zarr"
    dialog.destination.setText(str(out))
    assert dialog.format.currentText() == "Zarr store (.zarr)"      # follows the suffix
    dialog.frames.setValue(1)
    dialog.accept()
    job = window.export_job
    assert job is not None
    qtbot.waitUntil(job.isFinished, timeout=120_000)
    qtbot.waitUntil(lambda: window.completion_dialog is not None
                    and window.completion_dialog.isVisible(), timeout=10_000)
    ds = open_dataset(out)
    try:
        assert ds.sizes["frame"] == 1
    finally:
        ds.close()
    buttons = {b.text(): b for b in window.completion_dialog.findChildren(QPushButton)}
    assert buttons["Open dataset"].property("url") == QUrl.fromLocalFile(str(out.resolve()))
    window.completion_dialog.close()


# --- 8: clutter removal in the title ------------------------------------------------------
def test_range_profile_title_says_whether_static_clutter_removal_is_on(make_window,
                                                                       wait_frame):
    window = make_window()
    wait_frame(window)
    panel = window.profile_panel
    assert window.document.project.dsp.static_clutter_removal is False
    panel.draw_now()
    assert "static clutter removal off" in panel.plot.titleLabel.text
    window.document.set_value("dsp.static_clutter_removal", True)
    wait_frame(window)
    panel.draw_now()
    assert "static clutter removal on" in panel.plot.titleLabel.text


def test_office_demo_and_docs_agree_about_static_clutter_removal():
    import json

    from simcore.resources import EXAMPLES_DIR

    office = json.loads((EXAMPLES_DIR / "office.json").read_text())
    docs = (Path(__file__).parents[2] / "docs" / "gui.md").read_text()
    assert office["dsp"]["static_clutter_removal"] is False
    # The docs no longer call the processed profile clutter-removed unconditionally.
    assert "(static clutter removal, windows, channels integrated)" not in docs
    assert "after static clutter removal and windows" not in docs
    assert "static clutter removal on/off" in docs


def test_completion_box_without_a_dataset_offers_only_the_folder(qtbot, tmp_path):
    from app.dialogs.export import completion_box

    parent = QMessageBox()
    box = completion_box(parent, "Cancelled", tmp_path / "missing.h5", None, lambda u: None)
    texts = {b.text() for b in box.findChildren(QPushButton)}
    assert "Open folder" in texts and "Open dataset" not in texts
    box.deleteLater()
    parent.deleteLater()
