"""The ToF effect checkboxes: each sets its switch (undoable), has a tooltip, follows it."""

from __future__ import annotations

import pytest

from app.document.document import ProjectDocument
from app.editors.sensor_editor import SensorEditor
from app.editors.tof_effects import TOF_EFFECTS

pytestmark = pytest.mark.gui


def test_each_effect_checkbox_sets_its_switch_and_undoes(qtbot, tmp_path):  # type: ignore[no-untyped-def]
    doc = ProjectDocument()
    ed = SensorEditor(doc)
    doc.setParent(ed)
    qtbot.addWidget(ed)
    boxes = ed.tof_effects.boxes
    assert set(boxes) == {f for f, _, _ in TOF_EFFECTS}
    for field, box in boxes.items():
        assert box.toolTip(), field
        before = getattr(doc.project.rig.tof, field)
        assert box.isChecked() == before
        box.click()
        assert getattr(doc.project.rig.tof, field) is (not before), field
        doc.undo_stack.undo()
        assert getattr(doc.project.rig.tof, field) is before, field
        assert box.isChecked() == before, field
    ed.tabs.setCurrentIndex(ed.tabs.count() - 1)
    ed.resize(900, 1100)
    ed.show()
    qtbot.waitExposed(ed)
    ed.grab().save(str(tmp_path.parent / "tof_effects.png"))
