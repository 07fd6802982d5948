"""Project files: validation messages, migrations, atomic and exact round trips."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from simcore.examples import mesh_files
from simcore.resources import EXAMPLES_DIR
from simcore.scene import (
    Box,
    Project,
    ProjectError,
    SceneObject,
    load_project,
    project_io,
    save_project,
)
from simcore.scene.project_io import project_to_json

BAD = Path(__file__).parent / "data" / "bad_projects"
OLD = Path(__file__).parent / "data" / "old_projects"

# file → text that the one clear message must contain (the field and/or the value)
EXPECTED = {
    "bad_json.json": "not valid JSON",
    "wrong_type.json": "objects[0].geometry(box).size_m",
    "nan_value.json": "NaN is not a valid number",
    "inf_value.json": "Infinity is not a valid number",
    "negative_size.json":
        "objects[0].geometry(box).size_m[1]: Input should be greater than 0 (got -2.0)",
    "missing_mesh.json": "objects[0].geometry.path: mesh file not found",
    "unknown_material.json": "objects[0].material: unknown material 'unobtainium'",
    "unknown_version.json": "format_version: 99 is newer than this tofradar supports",
    "missing_version.json": "format_version: must be an integer",
    "unknown_field.json": "objectz: Extra inputs are not permitted",
    "unknown_geometry.json": "objects[0].geometry",
    "duplicate_id.json": "duplicate object id 1",
    "bad_radar.json": "rig.radar.sample_rate_hz: Input should be greater than 0 (got 0)",
    "not_object.json": "expected a JSON object",
    "keyframes_unordered.json": "keyframe times must be strictly increasing",
    "unknown_rig_front_material.json":
        "rig.radar.rig_front_material: unknown material 'unobtainium'",
}


def test_corpus_is_complete():
    assert {p.name for p in BAD.glob("*.json")} == set(EXPECTED)


@pytest.mark.parametrize("name", sorted(EXPECTED))
def test_bad_project_gives_one_clear_error(name):
    with pytest.raises(ProjectError) as info:
        load_project(BAD / name)
    assert EXPECTED[name] in str(info.value)
    assert str(BAD / name) in str(info.value)


@pytest.mark.parametrize("name", sorted(EXPECTED))
def test_cli_validate_reports_without_traceback(name):
    proc = subprocess.run([sys.executable, "-m", "simcore.cli", "validate", str(BAD / name)],
                          capture_output=True, text=True, timeout=60)
    assert proc.returncode == 2
    assert "Traceback" not in proc.stderr + proc.stdout
    assert EXPECTED[name] in proc.stderr


@pytest.mark.parametrize("path", sorted(EXAMPLES_DIR.glob("*.json")), ids=lambda p: p.name)
def test_examples_validate_and_round_trip_byte_identical(path, tmp_path):
    project = load_project(path)
    text = path.read_text(encoding="utf-8")
    assert project_to_json(project) == text, "example files are stored in canonical form"
    out = tmp_path / "copy.json"
    for rel in mesh_files(path):      # an imported example's meshes come along
        (tmp_path / rel).parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(path.parent / rel, tmp_path / rel)
    save_project(project, out)
    save_project(load_project(out), tmp_path / "copy2.json")
    assert out.read_bytes() == (tmp_path / "copy2.json").read_bytes() == path.read_bytes()


def test_save_is_atomic_and_leaves_no_temp_file(tmp_path, monkeypatch):
    target = tmp_path / "p.json"
    save_project(Project(name="first"), target)
    original = target.read_bytes()

    def broken_replace(src: str, dst: str) -> None:
        raise OSError("disk full")

    monkeypatch.setattr(os, "replace", broken_replace)
    with pytest.raises(OSError, match="disk full"):
        save_project(Project(name="second"), target)
    assert target.read_bytes() == original
    assert [p.name for p in tmp_path.iterdir()] == ["p.json"]


def test_migration_registry_upgrades_old_versions():
    # A hypothetical version-1 file stored the project name under "title".
    def v1_to_v2(data: dict) -> dict:
        data["name"] = data.pop("title")
        return data

    doc = project_io.migrate({"format_version": 1, "title": "old"}, migrations={1: v1_to_v2},
                             current=2)
    assert doc == {"format_version": 2, "name": "old"}
    with pytest.raises(ProjectError, match="format_version: 0 is not a known version"):
        project_io.migrate({"format_version": 0}, migrations={1: v1_to_v2}, current=2)


def test_mesh_objects_load_relative_to_project(tmp_path):
    from vtkmodules.vtkFiltersSources import vtkCubeSource
    from vtkmodules.vtkIOGeometry import vtkSTLWriter

    (tmp_path / "meshes").mkdir()
    cube = vtkCubeSource()
    writer = vtkSTLWriter()
    writer.SetInputConnection(cube.GetOutputPort())
    writer.SetFileName(str(tmp_path / "meshes" / "cube.stl"))
    writer.Write()
    doc = {"format_version": 1, "objects": [
        {"id": 1, "name": "cube", "geometry": {"kind": "mesh", "path": "meshes/cube.stl"}}]}
    (tmp_path / "p.json").write_text(json.dumps(doc))
    project = load_project(tmp_path / "p.json")
    assert project.objects[0].geometry.path == "meshes/cube.stl"


def test_assignment_is_validated():
    obj = SceneObject(id=1, name="a", geometry=Box())
    with pytest.raises(ValueError, match="greater than 0"):
        obj.geometry = Box(size_m=(1, 0, 1))


def test_version_1_files_still_load(tmp_path):
    """Version 1 kept ``tof``/``radar`` on the material; version 2 keys bands by name."""
    old = load_project(OLD / "v1_materials.json")
    material = old.materials[0]
    assert material.band("tof").reflectance == 0.9
    assert material.band("radar").opacity == 0.0
    assert material.band("visible").opacity == 1.0        # not set: the defaults
    office_v1 = load_project(OLD / "v1_office.json")
    office = load_project(EXAMPLES_DIR / "office.json")
    # The same scene; only the radar render grid changed since (it now covers the
    # antennas' field of view in elevation too), and the example turned the BGT60TR13C's
    # anti-aliasing low-pass on (the vendor's 500 kHz; an old file keeps its own value).
    render = ("render_width", "render_height", "render_fov_h_deg", "if_lowpass_hz")
    for name in render:
        setattr(office.rig.radar, name, getattr(office_v1.rig.radar, name))
    # The office now ships with the ToF effects on; the v1 file keeps them off (defaults).
    for name in ("multipath", "specular", "wiggling", "distortion", "vignetting",
                 "stray_light"):
        assert getattr(office_v1.rig.tof, name) is False
        setattr(office.rig.tof, name, False)
    # Multipath from the room's surfaces in both sensors (issue 42): the v1 file has none.
    assert office_v1.rig.radar.multipath_order == 0
    assert office_v1.rig.tof.multipath_surfel_m == 0.25
    assert office_v1.rig.tof.multipath_model == "screen"
    office.rig.radar.multipath_order = 0
    office.rig.tof.multipath_surfel_m = 0.25
    office.rig.tof.multipath_model = "screen"
    office.description = office_v1.description      # which now names both multipaths
    # Motion artefacts too, by reprojection in the office (renders in the v1 defaults).
    assert office_v1.rig.tof.motion_artifacts is False
    assert office_v1.rig.tof.motion_sampling == "renders"
    office.rig.tof.motion_artifacts = False
    office.rig.tof.motion_sampling = "renders"
    # And its walker, a sliding cylinder then, is an articulated person now (issue 29).
    assert office.objects[-1].geometry.kind == "person"
    office.objects[-1] = office_v1.objects[-1]
    assert office_v1 == office


def test_material_summary_states_the_fresnel_reflection_and_slab_loss() -> None:
    """summarize_band: a dielectric half-space of ε′ = 4 reflects |Γ| = (2 − 1)/(2 + 1) = 1/3
    (−9.5 dB) at normal incidence; a lossless λ/2-thick slab (in the material) is matched
    and transmits everything (0.0 dB two-way); a metal reflects 1; opacity 0 is invisible."""
    from simcore.scene.materials import BandMaterial, summarize_band

    assert "|Γ| 0.33 (-9.5 dB)" in summarize_band("radar", BandMaterial(permittivity=4.0))
    f = 60e9
    half_wave = 299_792_458.0 / f / 2 / 2.0                   # λ/(2n), n = 2
    slab = BandMaterial(permittivity=4.0, thickness_m=half_wave)
    text = summarize_band("radar", slab, f)
    assert "transmits, 0.0 dB two-way loss" in text and "|Γ|" not in text, text
    assert "|Γ| 1.00 (0.0 dB)" in summarize_band("radar", BandMaterial(metallic=1.0))
    assert summarize_band("tof", BandMaterial(opacity=0.0)) == "invisible"
    assert summarize_band("tof", BandMaterial(reflectance=0.8)).startswith("diffuse 0.80")
