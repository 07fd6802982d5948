"""Randomized scenarios (issue 32): deterministic projects, valid, within their
distributions; hostile specs end with one clear error line."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from simcore.cli import main
from simcore.resources import RESOURCES_DIR
from simcore.scene import load_project

WAREHOUSE = RESOURCES_DIR / "scenarios" / "warehouse_family.json"
OFFICE = RESOURCES_DIR / "scenarios" / "office_family.json"


def generate(spec: Path, out: Path, *extra: str) -> int:
    return main(["generate", str(spec), "--out", str(out), *extra])


def test_same_seed_gives_byte_identical_projects_and_another_seed_differs(tmp_path):
    assert generate(OFFICE, tmp_path / "a", "--count", "4", "--seed", "11") == 0
    assert generate(OFFICE, tmp_path / "b", "--count", "4", "--seed", "11") == 0
    assert generate(OFFICE, tmp_path / "c", "--count", "4", "--seed", "12") == 0
    for i in range(4):
        name = f"scene_{i:05d}.json"
        assert (tmp_path / "a" / name).read_bytes() == (tmp_path / "b" / name).read_bytes()
        assert (tmp_path / "a" / name).read_bytes() != (tmp_path / "c" / name).read_bytes()
    record = json.loads(load_project(tmp_path / "a" / "scene_00002.json").description)
    assert record["seed"] == 11 and record["index"] == 2
    assert record["spec"]["name"] == "office_family"


def test_draws_follow_their_distributions(tmp_path):
    """Uniform draws: all in [low, high], mean (low+high)/2 within 4 standard errors."""
    n = 400
    assert generate(WAREHOUSE, tmp_path / "w", "--count", str(n), "--seed", "3") == 0
    spec = json.loads(WAREHOUSE.read_text())["vary"]
    x0, materials, rot = [], [], []
    for i in range(n):
        p = load_project(tmp_path / "w" / f"scene_{i:05d}.json")
        x0.append(p.objects[3].pose.position_m[0])
        materials.append(p.objects[0].material)
        rot.append(p.objects[3].pose.rotation_deg[2])
    low, high = spec["objects[3].pose.position_m[0]"]["uniform"]
    x = np.array(x0)
    assert x.min() >= low and x.max() <= high
    sigma = (high - low) / np.sqrt(12 * n)
    assert abs(x.mean() - (low + high) / 2) < 4 * sigma
    assert set(materials) == set(spec["objects[0].material"]["choice"])   # every choice drawn
    r = np.array(rot)
    assert r.min() >= -45.0 and r.max() <= 45.0             # the normal's clipping bounds
    assert abs(r.mean()) < 4 * 15.0 / np.sqrt(n)


@pytest.mark.slow
@pytest.mark.parametrize("family", [WAREHOUSE, OFFICE], ids=["warehouse", "office"])
def test_a_thousand_projects_validate_and_a_sample_runs(tmp_path, family):
    assert generate(family, tmp_path / "k", "--count", "1000", "--seed", "5") == 0
    files = sorted((tmp_path / "k").glob("scene_*.json"))
    assert len(files) == 1000
    for f in files:
        load_project(f)                      # validation: raises on any invalid project
    for f in files[:: 400]:
        assert main(["run", str(f), "--out", str(tmp_path / (f.stem + ".h5")), "--frames",
                     "1", "--quiet"]) == 0


def _spec(tmp_path: Path, doc: object, name: str = "spec.json") -> Path:
    path = tmp_path / name
    path.write_text(doc if isinstance(doc, str) else json.dumps(doc))
    return path


@pytest.mark.parametrize(("doc", "needle"), [
    ({"name": "x", "base": "office", "vary": {"rig.pose.position_m[0]": {"uniform": [2, 1]}}},
     "low <= high"),
    ({"name": "x", "base": "office", "vary": {"rig.pose.position_m[0]": {"gauss": [0, 1]}}},
     "a distribution is one of"),
    ({"name": "x", "base": "office",
      "vary": {"rig.pose.position_m[0]": {"normal": {"mean": 0, "std": -1}}}},
     "greater than or equal to 0"),
    ({"name": "x", "base": "office", "vary": {"objects[0].geometry.size_m[0]":
                                              {"uniform": [-2.0, -1.0]}}},
     "not a valid project"),
    ({"name": "x", "base": "office", "colour": "red"}, "colour"),
    ({"name": "x", "base": "office", "vary": {"no.such.field": {"uniform": [0, 1]}}},
     "does not exist"),
    ({"name": "x", "base": "nowhere"}, "neither a project file"),
    ("[" * 5000 + "]" * 5000, "spec.json"),
    ("{not json", "not valid"),
])
def test_hostile_specs_get_one_error_line(tmp_path, capsys, doc, needle):
    spec = _spec(tmp_path, doc)
    assert generate(spec, tmp_path / "out", "--count", "2") == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("tofradar: error: ") and needle in err[0], err


def test_huge_counts_and_bad_seeds_are_refused(tmp_path, capsys):
    for extra in (["--count", "100001"], ["--count", "0"], ["--count", "3", "--seed", "-1"]):
        with pytest.raises(SystemExit) as stop:
            generate(WAREHOUSE, tmp_path / "o", *extra)
        assert stop.value.code == 2
        err = capsys.readouterr().err.strip().splitlines()
        assert err[-1].startswith("tofradar: error:") or err[-1].startswith("tofradar generate")


def test_yaml_spec(tmp_path):
    spec = _spec(tmp_path, "name: y\nbase: point_targets\nvary:\n"
                           "  rig.pose.position_m[2]: {uniform: [1.0, 1.1]}\n", "s.yaml")
    assert generate(spec, tmp_path / "y", "--count", "2") == 0
    z = load_project(tmp_path / "y" / "scene_00001.json").rig.pose.position_m[2]
    assert 1.0 <= z <= 1.1


@pytest.mark.parametrize(("text", "needle"), [
    # "Billion laughs": nine levels of nine aliases, 387 million strings once expanded.
    ("name: x\nbase: office\na0: &a0 [l, l, l, l, l, l, l, l, l]\n" + "".join(
        f"a{i}: &a{i} [{', '.join([f'*a{i - 1}'] * 9)}]\n" for i in range(1, 10)),
     "more than 200000 values"),
    ("name: x\nbase: office\nvary: &v\n  self: *v\n", "nested deeper than 32"),   # recursion
])
def test_hostile_yaml_aliases_get_one_error_line_at_once(tmp_path, capsys, text, needle):
    spec = _spec(tmp_path, text, "bomb.yaml")
    assert generate(spec, tmp_path / "out", "--count", "1") == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("tofradar: error: ") and needle in err[0], err
