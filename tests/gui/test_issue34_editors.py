"""Issue 34, defects 1, 2 and 5: the material editor edits the selected object's material,
every field refuses bad input with a message in its own unit and label, values round-trip
exactly as typed, and undo labels are in the user's words.

Each test replays the sequence a user went through (typed keys, the Inspector's combo).
"""

from __future__ import annotations

import re

import pytest
from PyQt6.QtCore import Qt

from app.document.document import ProjectDocument
from app.editors.material_editor import MaterialEditor
from app.editors.scene_editor import ObjectInspector
from app.editors.sensor_editor import SensorEditor
from app.editors.timeline_editor import TimelineEditor
from app.widgets.inputs import field_error
from simcore.resources import EXAMPLES_DIR
from simcore.scene import load_project

pytestmark = pytest.mark.gui

OFFICE = EXAMPLES_DIR / "office.json"
#: What a message in the user's words never contains: model names, exponents, dicts.
INTERNAL = re.compile(r"[a-z]+_(?:hz|m|s|deg|dbm|db|mps)\b|\de[+-]\d|\{")


def _type(qtbot, box, text: str) -> None:
    """Select the box's text, type ``text`` and press Enter, as a user does."""
    box.setFocus()
    box.lineEdit().selectAll()
    qtbot.keyClicks(box, text)
    qtbot.keyClick(box, Qt.Key.Key_Return)


@pytest.fixture
def office(qtbot):
    """The office demo with the Inspector and the Materials editor on one document."""
    doc = ProjectDocument()
    doc.open(OFFICE)
    inspector = ObjectInspector(doc)
    materials = MaterialEditor(doc)
    doc.setParent(materials)
    for w in (inspector, materials):
        qtbot.addWidget(w)
        w.show()
    asked: list[tuple[str, list[str]]] = []
    materials.ask_shared_edit = lambda name, users, obj: asked.append((name, users)) or "all"
    return doc, inspector, materials, asked


def _set_material_in_inspector(inspector: ObjectInspector, name: str) -> None:
    combo = inspector.material_combo
    combo.setCurrentIndex(combo.findText(name))
    combo.activated.emit(combo.currentIndex())


# --- defect 1: the Materials editor follows the selected object's material ----------------
def test_material_editor_follows_a_material_changed_in_the_inspector(office, tmp_path):
    doc, inspector, ed, asked = office
    desk = doc.project.object_by_name("desk1_top")
    doc.select(desk.id)
    assert ed.current == "wood"
    _set_material_in_inspector(inspector, "aluminium")
    assert doc.project.object_by_name("desk1_top").material == "aluminium"
    assert ed.current == "aluminium"
    # aluminium is shared (the desk legs, the plate…): Make unique is offered.
    assert ed.unique_button.isEnabled()
    assert "desk1_top" in ed.users.text() and "desk1_leg1" in ed.users.text()
    ed.tof_invisible.click()
    table = doc.material_table()
    assert table["aluminium"].band("tof").opacity == 0.0
    assert table["wood"].band("tof").opacity == 1.0        # wood (desk2_top) untouched
    assert asked and asked[-1][0] == "aluminium" and "desk1_top" in asked[-1][1]
    # Undo the opacity and the material change: the editor follows back to wood.
    doc.undo_stack.undo()
    doc.undo_stack.undo()
    assert doc.project.object_by_name("desk1_top").material == "wood"
    assert ed.current == "wood" and ed.unique_button.isEnabled()
    doc.undo_stack.redo()
    assert ed.current == "aluminium"
    # A file reloaded with another material for the selected object: the editor shows it.
    out = tmp_path / "desk.json"
    doc.save(out)
    doc.undo_stack.undo()
    doc.select(desk.id)
    assert ed.current == "wood"
    doc.open(out)
    doc.select(desk.id)
    assert ed.current == "aluminium"


def test_material_picked_in_the_editor_gives_way_to_a_change_of_the_object(office):
    doc, inspector, ed, _ = office
    doc.select(doc.project.object_by_name("desk1_top").id)
    ed.combo.setCurrentIndex(ed.combo.findData("glass"))
    ed.combo.activated.emit(ed.combo.currentIndex())
    assert ed.current == "glass"                         # browsing another material
    assert not ed.unique_button.isEnabled()
    assert "desk1_top" in ed.selection_note.text()       # says it is not desk1_top's
    _set_material_in_inspector(inspector, "aluminium")
    assert ed.current == "aluminium"


# --- defect 1: a shared material says which objects an edit changes, before it does -------
def test_edit_of_a_shared_material_names_the_objects_first(office):
    doc, _inspector, ed, _ = office
    doc.select(doc.project.object_by_name("desk1_top").id)
    seen = []

    def ask(name, users, obj):
        # Asked before anything changed.
        seen.append((name, users, obj, doc.material_table()["wood"].band("tof").opacity))
        return "cancel"

    ed.ask_shared_edit = ask
    steps = doc.undo_stack.count()
    ed.tof_invisible.click()
    assert seen == [("wood", ["desk1_top", "desk2_top"], "desk1_top", 1.0)]
    assert doc.undo_stack.count() == steps and not ed.tof_invisible.isChecked()
    # "Only desk1_top": the object gets its own copy, and only it turns invisible.
    ed.ask_shared_edit = lambda name, users, obj: "unique"
    ed.tof_invisible.click()
    table = doc.material_table()
    assert doc.project.object_by_name("desk1_top").material == "wood_desk1_top"
    assert table["wood_desk1_top"].band("tof").opacity == 0.0
    assert table["wood"].band("tof").opacity == 1.0
    assert doc.project.object_by_name("desk2_top").material == "wood"
    assert ed.current == "wood_desk1_top" and ed.tof_invisible.isChecked()


# --- defect 2: one validation path; nothing clamped, nothing dropped ----------------------
@pytest.fixture
def timeline(qtbot):
    doc = ProjectDocument()
    doc.open(OFFICE)
    ed = TimelineEditor(doc)
    doc.setParent(ed)
    qtbot.addWidget(ed)
    ed.show()
    qtbot.waitExposed(ed)
    return doc, ed


@pytest.mark.parametrize(("field", "typed", "message"), [
    ("duration", "-1", "Duration must be above 0 s (got -1 s)"),
    ("duration", "0", "Duration must be above 0 s (got 0 s)"),
    ("frame_rate", "0", "Frame rate must be above 0 Hz (got 0 Hz)"),
    ("seed", "-3", "Seed must be at least 0 (got -3)"),
    ("duration", "abc", "Duration: “abc” is not a number"),
    ("seed", "1.5", "Seed: “1.5” is not a whole number"),
])
def test_timeline_and_seed_refuse_bad_input_at_the_field(timeline, qtbot, field, typed,
                                                         message):
    doc, ed = timeline
    before, steps = doc.project, doc.undo_stack.count()
    box = getattr(ed, field)
    _type(qtbot, box, typed)
    assert field_error(box) == message
    assert doc.project is before and doc.undo_stack.count() == steps
    assert typed in box.lineEdit().text(), "the refused text stays in the field"
    # Leaving the field keeps the refusal, and commits nothing.
    ed.seed.setFocus() if field != "seed" else ed.duration.setFocus()
    assert doc.project is before and field_error(box) == message
    # A valid value clears the mark and is one undo step named in the user's words.
    _type(qtbot, box, "2")
    assert field_error(box) is None
    assert doc.undo_stack.count() == steps + 1
    label = {"duration": "Set duration to 2 s", "frame_rate": "Set frame rate to 2 Hz",
             "seed": "Set seed to 2"}[field]
    assert doc.undo_stack.text(steps) == label


@pytest.fixture
def sensors(qtbot):
    doc = ProjectDocument()
    doc.open(OFFICE)
    ed = SensorEditor(doc)
    doc.setParent(ed)
    qtbot.addWidget(ed)
    ed.show()
    qtbot.waitExposed(ed)
    return doc, ed


def test_radar_fields_speak_in_their_units_and_round_trip_exactly(sensors, qtbot):
    doc, ed = sensors
    start = ed.radar_widgets["start_frequency_hz"]
    _type(qtbot, start, "5000")
    assert field_error(start) == "Start frequency must be below 300 GHz (got 5000 GHz)"
    bw = ed.radar_widgets["bandwidth_hz"]
    steps = doc.undo_stack.count()
    _type(qtbot, bw, "2")
    assert doc.project.rig.radar.bandwidth_hz == 2e9                      # exactly
    assert doc.undo_stack.text(steps) == "Set bandwidth to 2 GHz"
    chirp = ed.radar_widgets["chirp_time_s"]
    _type(qtbot, chirp, "64.1")
    assert doc.project.rig.radar.chirp_time_s == 64.1e-6 or field_error(chirp)
    _type(qtbot, bw, "-1")
    assert field_error(bw) == "Bandwidth must be above 0 GHz (got -1 GHz)"
    _type(qtbot, bw, "400")                               # a rule across fields
    assert not INTERNAL.search(field_error(bw) or "x_hz"), field_error(bw)
    _type(qtbot, ed.samples, "x")
    assert field_error(ed.samples) == "Samples / chirp: “x” is not a whole number"
    tx = ed.link_form.widgets["rig.radar.tx_power_dbm"]
    _type(qtbot, tx, "75")
    assert field_error(tx) == "Tx power must be at most 60 dBm (got 75 dBm)"
    pfa = ed.pfa
    before = doc.project
    _type(qtbot, pfa, "abc")
    assert field_error(pfa) == "False-alarm rate: “abc” is not a number"
    _type(qtbot, pfa, "2")
    assert field_error(pfa) == "False-alarm rate must be between 0 and 1, e.g. 1e-6 (got 2)"
    assert doc.project is before
    rot = ed.radar_rot
    _type(qtbot, rot.boxes[2], "400")                     # beyond the box: refused, not 360
    assert field_error(rot) == "Radar rotation on the rig (z) must be at most 360° (got 400°)"
    assert doc.project is before
    hp = ed.link_form.widgets["rig.radar.if_highpass_hz"]
    steps = doc.undo_stack.count()
    _type(qtbot, hp, "123.4")
    assert doc.project.rig.radar.if_highpass_hz == 123400.0
    assert doc.undo_stack.text(steps) == "Set IF high-pass to 123.4 kHz"


def test_object_size_refused_in_metres(office, qtbot):
    doc, inspector, _ed, _ = office
    doc.select(doc.project.object_by_name("desk1_top").id)
    size = inspector._geometry_widgets["size_m"]
    before = doc.project
    _type(qtbot, size.boxes[0], "0")
    assert field_error(size) == "Size (x) must be above 0 m (got 0 m)"
    assert doc.project is before
    steps = doc.undo_stack.count()
    _type(qtbot, size.boxes[0], "1.2")
    assert doc.project.object_by_name("desk1_top").geometry.size_m[0] == 1.2
    assert doc.undo_stack.text(steps) == "Set size of desk1_top to 1.2 × 1.4 × 0.04 m"


def test_material_fields_refuse_in_words(office, qtbot):
    doc, _inspector, ed, _ = office
    ed.show_material("glass")
    refl = ed.tof_editor.widgets["reflectance"]
    before = doc.project
    _type(qtbot, refl, "1.5")
    assert field_error(refl) == "ToF reflectance must be at most 1 (got 1.5)"
    assert doc.project is before
    steps = doc.undo_stack.count()
    thick = ed.radar_editor.widgets["thickness_m"]
    _type(qtbot, thick, "6.2")
    assert doc.material_table()["glass"].band("radar").thickness_m == 0.0062
    assert doc.undo_stack.text(steps) == "Set radar thickness of glass to 6.2 mm"


def test_saved_values_are_those_typed(sensors, qtbot, tmp_path):
    doc, ed = sensors
    _type(qtbot, ed.radar_widgets["start_frequency_hz"], "58.3")
    _type(qtbot, ed.radar_widgets["chirp_repetition_time_s"], "700.1")
    out = tmp_path / "typed.json"
    doc.save(out)
    radar = load_project(out).rig.radar
    assert radar.start_frequency_hz == 58.3e9 and radar.chirp_repetition_time_s == 700.1e-6


@pytest.mark.parametrize("typed", ["2", "58.3", "0.001", "77.123", "123.4", "299.999"])
@pytest.mark.parametrize(("scale", "exponent"), [(1e-9, 9), (1e-6, 6), (1e-3, 3), (1e6, -6),
                                                 (1e3, -3)])
def test_unit_conversion_stores_the_decimal_typed(typed, scale, exponent):
    """The SI value is the double nearest to the typed decimal × 10^k, and back again."""
    from decimal import Decimal

    from app.editors.field_editors import FieldSpec

    spec = FieldSpec("rig.radar.bandwidth_hz", "bandwidth", scale=scale)
    si = spec.to_si(float(typed))
    assert si == float(Decimal(typed).scaleb(exponent))
    assert spec.to_shown(si) == float(typed)
