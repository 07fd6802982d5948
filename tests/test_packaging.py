"""Packaging: bundled resources, `tofradar examples`, one version, a headless launcher.

The built wheel itself is checked in a fresh venv by `make check-wheel`
(tools/check_wheel.sh), which `make test` runs.
"""

from __future__ import annotations

import glob
import json
import re
import subprocess
import sys
from importlib.resources import files
from pathlib import Path

import pytest

import simcore
from simcore import examples as examples_mod
from simcore.cli import main
from simcore.examples import ExamplesError, copy_examples, list_examples, mesh_files
from simcore.resources import EXAMPLES_DIR, MATERIALS_FILE, RESOURCES_DIR, example_path

ROOT = Path(__file__).resolve().parents[1]
# The repository's examples folder: what the package must list and copy.
EXAMPLE_NAMES = sorted(p.stem for p in (ROOT / "resources" / "examples").glob("*.json"))


def test_resources_come_from_inside_the_package():
    package_dir = Path(str(files("simcore")))
    assert RESOURCES_DIR == package_dir / "_resources"
    assert MATERIALS_FILE.is_file()
    assert json.loads(MATERIALS_FILE.read_text())["materials"]
    assert example_path("office") == EXAMPLES_DIR / "office.json"
    # In the repository the package's resources are the top-level resources/ folder.
    assert RESOURCES_DIR.resolve() == (ROOT / "resources").resolve()


def test_resources_found_from_any_directory(tmp_path):
    code = ("from simcore.resources import MATERIALS_FILE, example_path\n"
            "print(MATERIALS_FILE.is_file(), example_path('wall').is_file())")
    proc = subprocess.run([sys.executable, "-c", code], cwd=tmp_path, capture_output=True,
                          text=True, check=True, timeout=60)
    assert proc.stdout.split() == ["True", "True"]


def test_package_data_covers_every_bundled_file():
    tomllib = pytest.importorskip("tomllib")
    config = tomllib.loads((ROOT / "pyproject.toml").read_text())
    patterns = config["tool"]["setuptools"]["package-data"]["simcore"]
    shipped = {Path(m) for p in patterns
               for m in glob.glob(p, root_dir=ROOT / "simcore", recursive=True)}
    bundled = {p.relative_to(ROOT / "simcore") for p in RESOURCES_DIR.rglob("*") if p.is_file()}
    assert Path("_resources/examples/office.json") in bundled
    assert Path("_resources/furniture/sofa.obj") in shipped     # the furniture meshes
    assert bundled == shipped


def test_list_examples_names_and_one_line_summaries():
    found = list_examples()
    assert {"office", "wall", "point_targets"} <= set(EXAMPLE_NAMES)
    assert [e.name for e in found] == EXAMPLE_NAMES
    for e in found:
        assert e.summary and "\n" not in e.summary and not e.summary.endswith(".")


def test_examples_command_lists_them(capsys):
    assert main(["examples"]) == 0
    out = capsys.readouterr().out.splitlines()
    n = len(EXAMPLE_NAMES)
    assert [line.split()[0] for line in out[:n]] == [f"{name}.json" for name in EXAMPLE_NAMES]
    wall = out[EXAMPLE_NAMES.index("wall")].split(None, 1)[1]
    assert wall == ("A flat concrete wall 2.0 m in front of the rig, normal to the boresight, "
                    "larger than both fields of view")
    assert out[n] == "copy them into a folder with: tofradar examples --copy DIR"


def test_examples_copy_then_refuse_to_overwrite(tmp_path, capsys):
    target = tmp_path / "ex"
    assert main(["examples", "--copy", str(target)]) == 0
    assert sorted(p.name for p in target.iterdir() if p.suffix == ".json") == [
        f"{n}.json" for n in EXAMPLE_NAMES]
    assert (target / "office_gltf.meshes" / "cabinet.ply").is_file()   # meshes come along
    assert (target / "wall.json").read_bytes() == example_path("wall").read_bytes()
    assert main(["validate", str(target / "wall.json")]) == 0
    (target / "wall.json").write_text("mine")
    capsys.readouterr()
    assert main(["examples", "--copy", str(target)]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1
    first, more = EXAMPLE_NAMES[0], len(EXAMPLE_NAMES) - 1 + sum(
        len(set(mesh_files(ROOT / "resources" / "examples" / f"{n}.json")))
        for n in EXAMPLE_NAMES)
    assert f"ex/{first}.json exists already (and {more} more); not overwriting" in err, err
    assert (target / "wall.json").read_text() == "mine"


def test_copy_examples_brings_meshes_along(tmp_path, monkeypatch):
    bundled = tmp_path / "bundled"
    (bundled / "meshes").mkdir(parents=True)
    (bundled / "meshes" / "tri.stl").write_text("solid t\nendsolid t\n")
    project = {"description": "A mesh. More.", "objects": [
        {"name": "a", "geometry": {"kind": "mesh", "path": "meshes/tri.stl"}},
        {"name": "b", "geometry": {"kind": "mesh", "path": "meshes/tri.stl"}},
        {"name": "c", "geometry": {"kind": "box"}},
        {"name": "d", "geometry": {"kind": "mesh", "path": "/abs/elsewhere.stl"}}]}
    (bundled / "m.json").write_text(json.dumps(project))
    monkeypatch.setattr(examples_mod, "EXAMPLES_DIR", bundled)
    assert [str(p) for p in mesh_files(bundled / "m.json")] == ["meshes/tri.stl"]
    assert list_examples()[0].summary == "A mesh"
    written = copy_examples(tmp_path / "out")
    assert written == [tmp_path / "out" / "m.json", tmp_path / "out" / "meshes" / "tri.stl"]
    assert (tmp_path / "out" / "meshes" / "tri.stl").read_text().startswith("solid")
    (bundled / "meshes" / "tri.stl").unlink()
    with pytest.raises(ExamplesError, match="lacks its mesh meshes/tri.stl"):
        copy_examples(tmp_path / "out2")


def test_copy_into_a_file_is_refused(tmp_path):
    (tmp_path / "f").write_text("x")
    with pytest.raises(ExamplesError, match="is not a folder"):
        copy_examples(tmp_path / "f")


def test_one_version_source(capsys):
    tomllib = pytest.importorskip("tomllib")
    config = tomllib.loads((ROOT / "pyproject.toml").read_text())
    assert "version" not in config["project"]
    assert config["project"]["dynamic"] == ["version"]
    assert config["tool"]["setuptools"]["dynamic"]["version"] == {"attr": "simcore.__version__"}
    with pytest.raises(SystemExit) as exc:
        main(["--version"])
    assert exc.value.code == 0
    assert capsys.readouterr().out.strip() == f"tofradar {simcore.__version__}"
    changelog = (ROOT / "CHANGELOG.md").read_text()
    assert re.search(r"^## \[?0\.2\.0\]? .*unreleased", changelog, re.M | re.I)
    assert "MIT License" in (ROOT / "LICENSE").read_text()


def test_core_dependencies_leave_the_gui_to_an_extra():
    tomllib = pytest.importorskip("tomllib")
    project = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    gui = ("pyqt6", "pyvistaqt", "pyqtgraph")

    def name(req: str) -> str:
        return re.split(r"[<>=!~\[ ;]", req, maxsplit=1)[0].lower()

    assert not [r for r in project["dependencies"] if name(r) in gui]
    assert {name(r) for r in project["optional-dependencies"]["gui"]} >= set(gui)


def test_launcher_without_qt_says_to_install_the_gui_extra(monkeypatch, capsys):
    from app import launcher

    monkeypatch.setattr(launcher, "find_spec",
                        lambda name: None if name == "PyQt6" else object())
    assert launcher.main(["gui"]) == 2
    assert launcher.main([]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert err == ["tofradar: error: the GUI is not installed (missing PyQt6); install it "
                   "with: pip install 'tofradar[gui]'"] * 2
    # Every other command still works.
    assert launcher.main(["validate", str(example_path("wall"))]) == 0


def test_materials_command_lists_the_table_with_users(capsys):
    """`tofradar materials PROJECT`: every material of the project's table, one summary
    line each, and the objects using it (from the project file, read independently)."""
    import json

    from simcore.resources import example_path

    path = example_path("office")
    assert main(["materials", str(path)]) == 0
    out = capsys.readouterr().out
    data = json.loads(path.read_text())
    users = [o["name"] for o in data["objects"] if o["material"] == "aluminium"]
    assert f"    used by {', '.join(users)}" in out
    assert "aluminium: ToF: metal" in out and "radar: metal" in out
    assert main(["materials"]) == 0                           # the library
    assert "paper: ToF: diffuse 0.80" in capsys.readouterr().out
    assert main(["materials", "no_such_project.json"]) == 2
    assert "file not found" in capsys.readouterr().err
