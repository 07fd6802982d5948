"""A person in the GUI: added from the scene editor's kinds, standing on the floor facing
the sensors, its fields editable, drawn in the 3D view."""

from __future__ import annotations

import numpy as np
import pytest
from PyQt6.QtWidgets import QApplication

pytestmark = pytest.mark.gui


def test_add_person_faces_the_sensors_and_draws(make_window, tmp_path):
    from app.document.scene_edits import NEW_OBJECTS, add_object
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


def test_view_draws_the_segments_where_the_simulation_puts_them(make_window):
    """The 3D view animates the body: at any time each segment's ellipsoid is centred
    where the simulation's own snapshot of the expanded scene puts that segment."""
    from simcore.render.meshes import build_mesh
    from simcore.resources import example_path
    from simcore.scene.people.expand import expand_people, people_of
    from simcore.scene.people.skeleton import SEGMENTS
    from simcore.scene.snapshot import take_snapshot

    window = make_window(example_path("gesture"))
    doc, view = window.document, window.viewport
    person = next(o for o in doc.project.objects if o.geometry.kind == "person")
    expanded = expand_people(doc.project, base_dir=doc.base_dir)
    first = people_of(expanded).people[0].first
    counts = [len(build_mesh(expanded.objects[first + i].geometry).points)
              for i in range(len(SEGMENTS))]
    centres = []
    for t in (0.7, 1.3):
        view.set_time(t)
        for _ in range(3):
            QApplication.processEvents()
        actor = view._actors[person.id][1]
        assert np.allclose(np.asarray(actor.user_matrix), np.eye(4))
        pts = np.asarray(actor.mapper.dataset.points)
        # One ellipsoid per segment, one after the other, each cut to its own size.
        parts = np.split(pts, np.cumsum(counts)[:-1])
        assert len(pts) == sum(counts) and len(parts) == len(SEGMENTS)
        # An ellipsoid's points are symmetric about its centre.
        drawn = np.array([part.mean(axis=0) for part in parts])
        snap = take_snapshot(expanded, t)
        truth = np.array([snap.objects[first + i].transform[:3, 3]
                          for i in range(len(SEGMENTS))])
        np.testing.assert_allclose(drawn, truth, atol=1e-6)
        centres.append(drawn)
    # The gesturing hand moved between the two times (the view is not a rest pose).
    assert np.linalg.norm(centres[1] - centres[0], axis=1).max() > 0.05
