"""Field paths (simcore.scene.fieldpath): one syntax for sweeps and GUI edits."""

from __future__ import annotations

import pytest
from pydantic import ValidationError

from simcore.resources import example_path
from simcore.runs.sweep import SweepError, expand, parse_vary
from simcore.scene import Project, load_project
from simcore.scene.fieldpath import FieldPathError, format_path, get, parse, set_in, with_value


@pytest.mark.parametrize(("path", "parts"), [
    ("name", ("name",)),
    ("rig.radar.chirps_per_frame", ("rig", "radar", "chirps_per_frame")),
    ("objects[1].pose.position_m[0]", ("objects", 1, "pose", "position_m", 0)),
    ("rig.radar.rx[2].position_mm", ("rig", "radar", "rx", 2, "position_mm")),
    ("a[10][3]", ("a", 10, 3)),
    ("_x1.y_2", ("_x1", "y_2")),
])
def test_parse_and_format_are_inverse(path, parts):
    assert parse(path) == parts
    assert format_path(parts) == path


@pytest.mark.parametrize("bad", [
    "", ".name", "name.", "objects.1.pose", "objects[1]pose", "objects[-1]", "objects[x]",
    "a..b", "[0].a", "a b", "a.[0]", "objects[1", "1abc",
])
def test_malformed_paths_are_refused(bad):
    with pytest.raises(FieldPathError, match="cannot parse field path"):
        parse(bad)


@pytest.fixture(scope="module")
def office() -> Project:
    return load_project(example_path("office"))


def test_get_reads_models_and_documents_alike(office):
    doc = office.model_dump()
    for path in ("rig.radar.chirps_per_frame", "objects[1].pose.position_m[0]",
                 "rig.radar.rx[2].position_mm", "objects[0].name", "dsp.cfar_pfa"):
        from_doc = get(doc, path)
        from_model = get(office, path)
        assert from_doc == (from_model.model_dump() if hasattr(from_model, "model_dump")
                            else from_model), path
    assert get(office, "objects[1].pose.position_m[0]") == office.objects[1].pose.position_m[0]
    assert get(office, "rig.radar.rx[2].position_mm") == office.rig.radar.rx[2].position_mm
    assert get(office, "rig.radar.chirps_per_frame") == office.rig.radar.chirps_per_frame


@pytest.mark.parametrize(("path", "missing"), [
    ("rig.radar.rx[99].position_mm", "rig.radar.rx[99]"),
    ("rig.radar.no_such_field", "rig.radar.no_such_field"),
    ("objects[0].name.first", "objects[0].name.first"),
    ("rig[0]", "rig[0]"),
])
def test_missing_fields_name_the_first_missing_prefix(office, path, missing):
    for node in (office, office.model_dump()):
        with pytest.raises(FieldPathError, match=rf"^{_escape(missing)} does not exist$"):
            get(node, path)


def _escape(text: str) -> str:
    return text.replace("[", r"\[").replace("]", r"\]").replace(".", r"\.")


def test_set_in_edits_lists_and_tuples_in_place():
    doc = {"rig": {"radar": {"rx": [{"position_mm": (0.0, 0.0)}, {"position_mm": (2.5, 0.0)}]}},
           "objects": [{"pose": {"position_m": [1.0, 2.0, 3.0]}}]}
    set_in(doc, "rig.radar.rx[1].position_mm[1]", 7.5)
    set_in(doc, "objects[0].pose.position_m[2]", -1.0)
    set_in(doc, "rig.radar.rx[0]", {"position_mm": (9.0, 9.0)})
    assert doc == {"rig": {"radar": {"rx": [{"position_mm": (9.0, 9.0)},
                                            {"position_mm": (2.5, 7.5)}]}},
                   "objects": [{"pose": {"position_m": [1.0, 2.0, -1.0]}}]}
    with pytest.raises(FieldPathError, match=r"^objects\[1\] does not exist$"):
        set_in(doc, "objects[1].pose", {})
    with pytest.raises(FieldPathError, match=r"^objects\[0\]\.velocity does not exist$"):
        set_in(doc, "objects[0].velocity", 1.0)  # fields are never created


def test_with_value_returns_a_validated_copy(office):
    moved = with_value(office, "objects[1].pose.position_m[0]", 4.25)
    assert moved.objects[1].pose.position_m[0] == 4.25
    assert moved.objects[1].pose.position_m[1:] == office.objects[1].pose.position_m[1:]
    assert office.objects[1].pose.position_m[0] != 4.25  # the original is untouched
    assert with_value(office, "rig.radar.rx[2].position_mm", (1.0, 2.0)).rig.radar.rx[
        2].position_mm == (1.0, 2.0)
    with pytest.raises(ValidationError):
        with_value(office, "rig.radar.chirps_per_frame", -3)


def test_sweep_uses_the_same_paths(office):
    vary = parse_vary("objects[1].pose.position_m[0]=1:2:0.5")
    assert vary.values == (1.0, 1.5, 2.0)
    variants = expand(office, [vary, parse_vary("rig.radar.chirps_per_frame=8,32")])
    assert len(variants) == 6
    params, project = variants[-1]
    assert params == {"objects[1].pose.position_m[0]": 2.0, "rig.radar.chirps_per_frame": 32}
    assert get(project, "objects[1].pose.position_m[0]") == 2.0
    assert project.rig.radar.chirps_per_frame == 32
    with pytest.raises(SweepError, match="cannot parse field path 'objects.1.pose'"):
        parse_vary("objects.1.pose=1,2")
    with pytest.raises(SweepError, match=r"^--vary: objects\[99\] does not exist in the project$"):
        expand(office, [parse_vary("objects[99].pose.position_m[0]=1,2")])
