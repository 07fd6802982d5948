"""GUI side of randomized scenarios (issue 32): a generated project opens like any other;
File ▸ Export scenario spec writes a spec that varies the scene's free-standing objects
and the rig, and that generates valid projects within the ranges around the scene."""

from __future__ import annotations

import json

import pytest
from PyQt6.QtWidgets import QFileDialog

from simcore.resources import EXAMPLES_DIR, RESOURCES_DIR
from simcore.scenarios import generate, load_spec
from simcore.scene import load_project

pytestmark = pytest.mark.gui


def test_open_a_generated_project_and_export_a_spec_of_the_current_scene(
        make_window, tmp_path, monkeypatch):
    files = generate(RESOURCES_DIR / "scenarios" / "office_family.json", tmp_path / "gen",
                     count=2, seed=3)
    window = make_window(EXAMPLES_DIR / "wall.json")
    assert window.open_project(files[1], ask=False)
    assert window.document.project == load_project(files[1])
    assert window.document.project.name == "office_family #1"

    # Edit the scene: the export saves it first, so the spec's base is the current scene.
    window.document.set_value("rig.pose.position_m[0]", 0.25)
    out = tmp_path / "specs" / "my_family.json"
    out.parent.mkdir()
    monkeypatch.setattr(QFileDialog, "getSaveFileName",
                        lambda *a, **k: (str(out), "Scenario specs (*.json)"))
    assert window.export_spec_action.isEnabled()
    window.export_spec_action.trigger()
    assert out.is_file() and not window.document.is_dirty
    spec, base = load_spec(out)
    assert base.resolve() == files[1].resolve()
    objects = load_project(files[1]).objects
    # The rig within ±0.1 m of where it stands; only free-standing objects move:
    # not the walls (room structure), not the desks' parts (several parts per stem).
    assert spec.vary["rig.pose.position_m[0]"].uniform == pytest.approx((0.15, 0.35))
    moved = {int(p.split("]")[0].split("[")[1]) for p in spec.vary if p.startswith("objects")}
    names = {objects[i].name for i in moved}
    assert "metal_plate" in names and "book" in names and "person" in names
    assert not names & {"floor", "back_wall", "desk1_top", "desk1_leg1", "chair_seat"}
    scenes = generate(out, tmp_path / "fam", count=5, seed=1)
    for path in scenes:
        p = load_project(path)
        assert 0.15 <= p.rig.pose.position_m[0] <= 0.35
        assert json.loads(p.description)["scenario"] == "my_family"
        for i, o in enumerate(p.objects):
            if i not in moved:
                assert o.pose == objects[i].pose, o.name
