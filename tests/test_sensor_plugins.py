"""Sensors are plug-ins: any set of sensors under any names, written from their schemas.

Projects built as a user would, from the bundled office: its sensors renamed, radar-only,
ToF-only, three rigs of mixed sensors; bad sensor tables; and the rule that no code
outside a sensor's own package names a sensor group by a literal path.
"""

from __future__ import annotations

import ast
import copy
import json
import re
from pathlib import Path

import h5py
import numpy as np
import pytest

import simcore.sensors.base as sensor_base
from simcore.cli import main
from simcore.io import open_dataset
from simcore.pipeline import Simulator
from simcore.resources import example_path
from simcore.scene import load_project
from simcore.scene.layout import reserved_names
from simcore.scene.project_io import project_from_dict
from simcore.sensors.schema import nan_allowed, schema_of, schemas

ROOT = Path(__file__).resolve().parents[1]


def office_doc() -> dict:
    return json.loads(example_path("office").read_text())


def renamed(doc: dict, tof: str = "cam_front", radar: str = "fmcw_front") -> dict:
    """The document with its built-in ToF camera and radar moved into the table, renamed."""
    out = copy.deepcopy(doc)
    rig = out["rig"]
    cam, rad = rig.get("tof") or {}, rig.get("radar") or {}
    rig["tof"], rig["radar"] = None, None
    rig["sensors"] = {tof: {**cam, "kind": "tof"}, radar: {**rad, "kind": "radar"},
                      **(rig.get("sensors") or {})}
    return out


def without(doc: dict, field: str) -> dict:
    out = copy.deepcopy(doc)
    out["rig"][field] = None
    return out


def three_rigs(doc: dict) -> dict:
    """The office with two more rigs: a radar-only one and one with a ToF camera + RGB."""
    out = copy.deepcopy(doc)
    radar = dict(out["rig"].get("radar") or {})
    tof = dict(out["rig"].get("tof") or {})
    out["rigs"] = [
        {"name": "door", "pose": {"position_m": [0.5, -1.0, 0.0]},
         "sensors": {"door_radar": {**radar, "kind": "radar"}}},
        {"name": "shelf", "pose": {"position_m": [0.0, 1.0, 0.3]},
         "sensors": {"shelf_cam": {**tof, "kind": "tof"},
                     "shelf_rgb": {"kind": "rgb", "width": 160, "height": 120}}},
    ]
    return out


def write(tmp_path: Path, name: str, doc: dict) -> Path:
    """The project next to copies of the office's meshes (relative paths keep working)."""
    path = tmp_path / f"{name}.json"
    path.write_text(json.dumps(doc))
    return path


# --- the rule: only a sensor's own package names its group --------------------------------

_GROUP_LITERAL = re.compile(r"^/(tof|radar|rgb)(/|$)|^(tof|radar|rgb)/")


def _literal_group_paths(path: Path) -> list[str]:
    """String constants of code (not docstrings) that spell a built-in sensor group path."""
    tree = ast.parse(path.read_text())
    docstrings = set()
    for node in ast.walk(tree):
        if isinstance(node, (ast.Module, ast.ClassDef, ast.FunctionDef, ast.AsyncFunctionDef)):
            body = node.body
            if body and isinstance(body[0], ast.Expr) and isinstance(body[0].value, ast.Constant):
                docstrings.add(id(body[0].value))
    found = []
    for node in ast.walk(tree):
        if isinstance(node, ast.JoinedStr):   # f"/radar/{x}": its literal head counts
            head = node.values[0] if node.values else None
            if isinstance(head, ast.Constant) and isinstance(head.value, str) \
                    and _GROUP_LITERAL.match(head.value):
                found.append(f"{path.relative_to(ROOT)}:{node.lineno}: f{head.value!r}...")
            for part in node.values:
                docstrings.add(id(part))
            continue
        if isinstance(node, ast.Constant) and isinstance(node.value, str) \
                and id(node) not in docstrings and _GROUP_LITERAL.match(node.value):
            found.append(f"{path.relative_to(ROOT)}:{node.lineno}: {node.value!r}")
    return found


def test_no_code_outside_a_sensor_package_names_a_sensor_group():
    offenders = []
    for path in sorted((ROOT / "simcore").rglob("*.py")) + sorted((ROOT / "app").rglob("*.py")):
        rel = path.relative_to(ROOT).as_posix()
        if re.match(r"simcore/sensors/(tof|radar|rgb)/", rel):
            continue        # a sensor's own package names its own group
        offenders += _literal_group_paths(path)
    assert not offenders, "\n".join(offenders)


def test_the_rule_catches_a_literal_group_path(tmp_path):
    # The check itself must fail on what it forbids (and let docstrings and names pass).
    probe = ROOT / "tests" / "_probe_literal_paths.py"
    probe.write_text('"""Docstring mentioning /radar/adc is fine."""\n'
                     'A = "/radar/adc"\nB = f"/tof/{1}"\nC = "radar"\nD = f"/{C}/adc"\n')
    try:
        found = _literal_group_paths(probe)
    finally:
        probe.unlink()
    assert len(found) == 2 and "'/radar/adc'" in found[0] and "/tof/" in found[1]


# --- schemas --------------------------------------------------------------------------------

def test_every_kind_declares_each_output_once_with_dims_unit_and_dtype():
    for kind, schema in schemas().items():
        names = [o.name for o in schema.outputs]
        assert len(names) == len(set(names)), kind
        for out in schema.outputs:
            assert out.unit is not None and out.dtype, (kind, out.name)
            assert all(isinstance(d, str) and d for d in out.dims), (kind, out.name)
            if out.preview is not None:
                assert out.preview.label and out.preview.title


def test_nan_policy_follows_the_schema_for_any_sensor_name():
    kinds = {"cam": "tof", "tof": "tof", "r2": "radar"}
    assert nan_allowed("/cam/gt_range", kinds) and nan_allowed("/tof/gt_range", kinds)
    assert not nan_allowed("/cam/depth", kinds)
    assert nan_allowed("/r2/bird_eye", kinds) and not nan_allowed("/r2/adc", kinds)
    assert not nan_allowed("/objects/velocity", kinds)


def test_reserved_names_come_from_the_layout():
    names = reserved_names()
    # Every dataset under /objects and /people, and every top-level group.
    assert {"velocity", "aabb", "segments", "poses", "objects", "meta", "time"} <= names
    assert "front_radar" not in names and "cam" not in names


# --- projects a user builds --------------------------------------------------------------------

@pytest.mark.parametrize("build, name", [
    (lambda d: without(without(d, "tof"), "radar"), None),
])
def test_a_project_needs_a_sensor(tmp_path, capsys, build, name):
    path = write(tmp_path, "none", build(office_doc()))
    assert main(["validate", str(path)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("tofradar: error:")
    assert "rig: the project has no sensor" in err[0]


@pytest.mark.parametrize("edit, field, words", [
    (lambda d: d["rig"].update(sensors={"tof": {"kind": "tof"}}), "rig.sensors.tof",
     "duplicate sensor name 'tof' (also rig.tof)"),
    (lambda d: (d["rig"].update(sensors={"cam": {"kind": "radar"}}),
                d.update(rigs=[{"name": "r2", "sensors": {"cam": {"kind": "tof"}}}])),
     "rigs[0].sensors.cam", "duplicate sensor name 'cam' (also rig.sensors.cam)"),
    (lambda d: d["rig"].update(sensors={"lidar1": {"kind": "lidar"}}),
     "rig.sensors.lidar1.kind", "unknown sensor kind 'lidar'"),
    (lambda d: d["rig"].update(sensors={"velocity": {"kind": "radar"}}),
     "rig.sensors.velocity", "collides with the dataset /objects/velocity"),
    (lambda d: d["rig"].update(sensors={"poses": {"kind": "tof"}}),
     "rig.sensors.poses", "collides with the top-level dataset group /poses"),
    (lambda d: d.update(rigs=[{"name": "segments", "sensors": {"c": {"kind": "tof"}}}]),
     "rigs[0].name", "collides with the dataset /people/segments"),
])
def test_bad_sensor_tables_get_one_line_naming_the_field(tmp_path, capsys, edit, field, words):
    doc = office_doc()
    edit(doc)
    path = write(tmp_path, "bad", doc)
    assert main(["validate", str(path)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1, err
    assert err[0].startswith(f"tofradar: error: {path}: {field}: "), err[0]
    assert words in err[0]


def test_radar_only_and_tof_only_projects_do_only_their_sensors_work():
    doc = office_doc()
    doc["objects"] = [o for o in doc["objects"] if o["name"] != "person"]
    radar_only = project_from_dict(without(doc, "tof"))
    tof_only = project_from_dict(without(doc, "radar"))
    with Simulator(radar_only, base_dir=example_path("office").parent) as sim:
        frame = sim.frame(0)
        assert set(frame.outputs) == {"radar"}
        assert not any(k.startswith(("render_tof", "tof")) for k in frame.timings_ms)
        items = frame.hdf5_items()
        assert not any(p.startswith("/tof") for p in items)
        assert "/objects/radar_range" in items
    with Simulator(tof_only, base_dir=example_path("office").parent) as sim:
        frame = sim.frame(0)
        assert set(frame.outputs) == {"tof"}
        assert not any("radar" in k for k in frame.timings_ms)
        items = frame.hdf5_items()
        assert not any("radar" in p for p in items)


def test_renamed_sensors_give_the_built_in_sensors_outputs(monkeypatch):
    """Same scene, same random streams: the renamed sensors' outputs equal the built-ins'."""
    doc = json.loads(example_path("wall").read_text())
    built_in = project_from_dict(doc)
    names = project_from_dict(renamed(doc, "cam_front", "fmcw_front"))
    streams = {"cam_front": sensor_base.BUILTIN_STREAMS["tof"],
               "fmcw_front": sensor_base.BUILTIN_STREAMS["radar"]}
    original = sensor_base.sensor_rng_stream
    monkeypatch.setattr(sensor_base, "sensor_rng_stream",
                        lambda kind, name, rig_index=0, slot=0: streams.get(name)
                        if name in streams else original(kind, name, rig_index, slot))
    base = example_path("wall").parent
    with Simulator(built_in, base_dir=base) as sim:
        a = sim.frame(1).hdf5_items()
    with Simulator(names, base_dir=base) as sim:
        b = sim.frame(1).hdf5_items()
    pairs = {"tof": "cam_front", "radar": "fmcw_front"}
    compared = 0
    for path, (value, unit) in a.items():
        head, _, rest = path.strip("/").partition("/")
        other = f"/{pairs[head]}/{rest}" if head in pairs else path
        if path.startswith("/objects/radar_"):
            other = "/objects/fmcw_front/" + path.removeprefix("/objects/radar_")
        assert other in b, other
        np.testing.assert_array_equal(b[other][0], value, err_msg=path)
        assert b[other][1] == unit
        compared += head in pairs
    assert compared >= 15    # every ToF and radar output was compared


# --- every writer, every reader, for the projects a user builds ------------------------------

USER_PROJECTS = {
    "renamed": lambda d: renamed(d),
    "radar_only": lambda d: without(d, "tof"),
    "tof_only": lambda d: without(d, "radar"),
    "three_rigs": three_rigs,
}


@pytest.mark.parametrize("name", sorted(USER_PROJECTS))
def test_user_projects_run_to_every_format_and_open(tmp_path, name):
    doc = USER_PROJECTS[name](office_doc())
    doc["timeline"]["duration_s"] = 0.2          # two frames
    project_path = write(tmp_path, name, doc)
    project = load_project(project_path)
    assert main(["validate", str(project_path)]) == 0
    kinds = {n: c.__class__.__name__ for n, c in project.sensor_configs().items()}
    h5, zarr_out, mcap = tmp_path / "x.h5", tmp_path / "x.zarr", tmp_path / "x.mcap"
    for out in (h5, zarr_out, mcap):
        assert main(["run", str(project_path), "--out", str(out), "--frames", "2", "--quiet",
                     "--preview", str(tmp_path / f"prev_{out.suffix[1:]}")]) == 0, out
    radars = list(project.sensors_of_kind("radar"))
    if radars:
        assert main(["products", str(h5)]) == 0
    for out in (h5, zarr_out):
        ds = open_dataset(out)
        try:
            assert ds.sizes["frame"] == 2
            for sensor, cfg in project.sensor_configs().items():
                kind = [k for k, s in schemas().items() if isinstance(cfg, _config_type(k))][0]
                schema = schema_of(kind)
                for output in schema.outputs:
                    if output.optional or output.product or output.dtype == "record":
                        continue
                    var = schema.dataset_path(sensor, output.name).strip("/").replace("/", "_")
                    coord = schema.coord(sensor, output)
                    got = ds[coord] if coord else ds[var]
                    dims = ((("frame",) if output.per_frame else ())
                            + schema.dims(sensor, output))
                    assert got.dims == dims, (out, sensor, output.name, got.dims)
                    assert got.attrs["units"] == output.unit
        finally:
            ds.close()
    previews = {p.name for p in (tmp_path / "prev_h5").iterdir()}
    for sensor, cfg in project.sensor_configs().items():
        kind = [k for k in schemas() if isinstance(cfg, _config_type(k))][0]
        for output in schema_of(kind).previews():
            assert f"frame_00001_{sensor}_{output.name}.png" in previews, (sensor, output)
    if radars:
        with h5py.File(h5, "r") as f:
            for radar in radars:
                assert f"{radar}/spectrogram/power" in f and f"{radar}/vitals/time" in f
    assert mcap.stat().st_size > 0 and kinds


def _config_type(kind: str) -> type:
    from simcore.scene.model import SENSOR_KINDS

    return SENSOR_KINDS[kind][0]


def test_a_named_tof_camera_that_sees_empty_pixels_is_written(tmp_path):
    """NaN is gt_range's documented value for no surface, whatever the camera's name."""
    doc = renamed(json.loads(example_path("wall").read_text()), "side_cam", "side_radar")
    # Turn the rig 60° away from the wall: part of the camera's view is empty.
    doc["rig"]["pose"] = {"position_m": [0.0, 0.0, 0.0], "rotation_deg": [0.0, 0.0, 60.0]}
    path = write(tmp_path, "empty", doc)
    out = tmp_path / "empty.h5"
    assert main(["run", str(path), "--out", str(out), "--frames", "1", "--quiet"]) == 0
    with h5py.File(out, "r") as f:
        gt = f["side_cam/gt_range"][0]
        assert np.isnan(gt).any() and np.isfinite(gt).any()
        assert np.isfinite(f["side_cam/depth"][0]).all()
