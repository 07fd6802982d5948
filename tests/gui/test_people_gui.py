"""A person in the GUI: added from the scene editor's kinds, standing on the floor facing
the sensors, its fields editable, drawn in the 3D view."""

from __future__ import annotations

import numpy as np
import pytest
from PyQt6.QtWidgets import QApplication

pytestmark = pytest.mark.gui


def test_add_person_faces_the_sensors_and_draws(make_window, tmp_path):
    from app.scene_edits import NEW_OBJECTS, add_object
    from simcore.resources import example_path
    from simcore.scene.people import Person

    window = make_window(example_path("wall"))
    doc = window.document
    assert "person" in NEW_OBJECTS
    oid = add_object(doc, "person")
    obj = doc.project.objects[doc.index_of(oid)]
    assert isinstance(obj.geometry, Person)
    assert obj.pose.position_m[2] == 0.0  # on the floor
    # The rig looks along +x: the person's +x (its face) points back at it.
    assert obj.pose.rotation_deg[2] == pytest.approx(180.0) or \
        obj.pose.rotation_deg[2] == pytest.approx(-180.0)
    # Fields edit through the document like any geometry field.
    i = doc.index_of(oid)
    doc.set_value(f"objects[{i}].geometry.height_m", 1.6)
    doc.set_value(f"objects[{i}].geometry.motion.walk", {"speed_mps": 1.0})
    assert doc.project.objects[i].geometry.height_m == 1.6
    assert doc.project.objects[i].geometry.motion.walk.speed_mps == 1.0
    for _ in range(20):
        QApplication.processEvents()
    image = window.grab()
    path = tmp_path / "person.png"
    image.save(str(path))
    assert path.stat().st_size > 0
    assert np.isfinite(obj.geometry.height_m)


def test_inspector_edits_the_motion_block(make_window):
    from simcore.resources import example_path

    window = make_window(example_path("vital_signs"))
    doc = window.document
    doc.select(1)
    for _ in range(5):
        QApplication.processEvents()
    inspectors = [w for w in window.findChildren(object) if hasattr(w, "_person_rows")
                  and getattr(w, "_person_rows", None) is not None]
    assert inspectors, "the inspector shows the person's motion rows"
    rows = inspectors[0]._person_rows
    assert rows.widgets["posture"].currentText() == "sitting"
    assert rows.widgets["breath_hz"].value() == pytest.approx(0.25)
    rows.widgets["breath_hz"].setValue(0.3)  # committed like an edit
    assert doc.project.objects[0].geometry.motion.vital_signs.breathing_rate_hz == \
        pytest.approx(0.3)
    rows.widgets["posture"].setCurrentText("standing")
    assert doc.project.objects[0].geometry.motion.posture == "standing"
    doc.undo_stack.undo()
    assert doc.project.objects[0].geometry.motion.posture == "sitting"
