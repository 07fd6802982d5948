"""Scenario specs that add furniture and people by count and draw materials (issue 32).

Known answers: counts inside the requested ranges, footprints (computed here from the
parts' geometry) inside the room and apart from each other and from the rig, walks
inside the room at the drawn speed, material parameters inside their ranges and the rest
equal to the library's; the same seed gives the same bytes.
"""

from __future__ import annotations

import json
import math
import re
from pathlib import Path

import numpy as np
import pytest

from simcore.cli import main
from simcore.resources import RESOURCES_DIR
from simcore.scene import load_project

ROOM_X, ROOM_Y = (0.5, 5.4), (-2.4, 2.4)
SPEC = {
    "name": "furnished", "base": "office",
    "materials": {"wood_var": {"from": "wood", "bands": {
        "radar": {"permittivity": {"uniform": [1.8, 2.4]}},
        "tof": {"reflectance": {"uniform": [0.3, 0.6]}}}}},
    "room": {"x_m": list(ROOM_X), "y_m": list(ROOM_Y), "rig_clearance_m": 0.6},
    "furniture": [
        {"piece": "desk", "count": [0, 2], "materials": {"top": {"choice": ["wood_var", "wood"]}}},
        {"piece": "chair", "count": [1, 3]},
        {"piece": "box", "count": [0, 4]},
        {"piece": "shelf", "count": [0, 1]},
        {"piece": "plant", "count": [0, 1]}],
    "people": [{"count": [1, 2], "waypoints": [1, 4], "speed_mps": {"uniform": [0.5, 1.0]},
                "gesture": {"choice": [None, {"kind": "wave"}]},
                "vital_signs": {"breathing_rate_hz": {"uniform": [0.2, 0.4]}}}],
}
RANGES = {"desk": (0, 2), "chair": (1, 3), "box": (0, 4), "shelf": (0, 1), "plant": (0, 1)}


def _write(tmp_path: Path, doc: object, name: str = "spec.json") -> Path:
    path = tmp_path / name
    path.write_text(json.dumps(doc))
    return path


def _generate(spec: Path, out: Path, *extra: str) -> int:
    return main(["generate", str(spec), "--out", str(out), "--quiet", *extra])


def _part_rect(obj: dict) -> tuple[float, float, float, float]:
    """Floor-plane bounding box of a part turned about z only (independent of the code)."""
    g, p = obj["geometry"], obj["pose"]["position_m"]
    yaw = math.radians(obj["pose"]["rotation_deg"][2])
    if g["kind"] == "box":
        sx, sy = g["size_m"][0] / 2, g["size_m"][1] / 2
        corners = [(p[0] + a * math.cos(yaw) - b * math.sin(yaw),
                    p[1] + a * math.sin(yaw) + b * math.cos(yaw))
                   for a in (-sx, sx) for b in (-sy, sy)]
        xs, ys = zip(*corners, strict=True)
        return min(xs), min(ys), max(xs), max(ys)
    r = g["radius_m"]
    return p[0] - r, p[1] - r, p[0] + r, p[1] + r


def _apart(a, b, tol=1e-5) -> bool:
    return a[2] <= b[0] + tol or b[2] <= a[0] + tol or a[3] <= b[1] + tol or b[3] <= a[1] + tol


@pytest.fixture(scope="module")
def scenes(tmp_path_factory) -> list[dict]:
    tmp = tmp_path_factory.mktemp("furnish")
    spec = _write(tmp, SPEC)
    assert _generate(spec, tmp / "out", "--count", "60", "--seed", "4") == 0
    docs = []
    for f in sorted((tmp / "out").glob("scene_*.json")):
        load_project(f)                                # every scene validates
        docs.append(json.loads(f.read_text()))
    return docs


def test_counts_in_range_pieces_inside_the_room_apart_and_clear_of_the_rig(scenes):
    base_names = {o["name"] for o in json.loads(
        (RESOURCES_DIR / "examples" / "office.json").read_text())["objects"]}
    seen = {k: set() for k in RANGES}
    for doc in scenes:
        pieces: dict[str, list[tuple[float, float, float, float]]] = {}
        for obj in doc["objects"]:
            m = re.fullmatch(r"([a-z]+)(\d+)_[a-z]+\d+", obj["name"])
            if obj["name"] in base_names or m is None:
                continue
            pieces.setdefault(f"{m[1]}{m[2]}", []).append(_part_rect(obj))
        counts = {k: 0 for k in RANGES}
        rects = []
        for rs in pieces.values():
            rects.append((min(r[0] for r in rs), min(r[1] for r in rs),
                          max(r[2] for r in rs), max(r[3] for r in rs)))
        for stem in pieces:
            counts[re.sub(r"\d+$", "", stem)] += 1
        for kind, (lo, hi) in RANGES.items():
            assert lo <= counts[kind] <= hi, (kind, counts)
            seen[kind].add(counts[kind])
        rig = doc["rig"]["pose"]["position_m"]
        clear = (rig[0] - 0.6, rig[1] - 0.6, rig[0] + 0.6, rig[1] + 0.6)
        for i, r in enumerate(rects):
            assert ROOM_X[0] - 1e-5 <= r[0] and r[2] <= ROOM_X[1] + 1e-5
            assert ROOM_Y[0] - 1e-5 <= r[1] and r[3] <= ROOM_Y[1] + 1e-5
            assert _apart(r, clear)
            for other in rects[i + 1:]:
                assert _apart(r, other)
    for kind, (lo, hi) in RANGES.items():          # every count of the range occurs
        assert seen[kind] == set(range(lo, hi + 1)), (kind, seen[kind])


def test_people_walk_inside_the_room_at_their_speed_with_drawn_vitals(scenes):
    counts = set()
    for doc in scenes:
        people = [o for o in doc["objects"] if o["name"].startswith("walker")]
        counts.add(len(people))
        for person in people:
            g, base = person["geometry"], person["pose"]["position_m"]
            walk = g["motion"]["walk"]
            speed = walk["speed_mps"]
            assert 0.5 <= speed <= 1.0 and walk["path"] == "keyframes"
            keys = person["motion"]["keyframes"]
            assert 2 <= len(keys) <= 5                  # the start and 1..4 waypoints
            for a, b in zip(keys, keys[1:], strict=False):
                step = math.dist(a["position_m"], b["position_m"])
                assert step / (b["time_s"] - a["time_s"]) == pytest.approx(speed, rel=1e-3)
            for k in keys:
                x, y = base[0] + k["position_m"][0], base[1] + k["position_m"][1]
                assert ROOM_X[0] + 0.3 - 1e-5 <= x <= ROOM_X[1] - 0.3 + 1e-5
                assert ROOM_Y[0] + 0.3 - 1e-5 <= y <= ROOM_Y[1] - 0.3 + 1e-5
            assert 0.2 <= g["motion"]["vital_signs"]["breathing_rate_hz"] <= 0.4
            gesture = g["motion"]["gesture"]
            assert gesture is None or gesture["kind"] == "wave"
    assert counts == {1, 2}


def test_drawn_materials_in_their_ranges_the_rest_from_the_library(scenes):
    library = {m["name"]: m for m in json.loads(
        (RESOURCES_DIR / "materials.json").read_text())["materials"]}
    wood = library["wood"]["bands"]
    eps, refl = [], []
    for doc in scenes:
        (mat,) = [m for m in doc["materials"] if m["name"] == "wood_var"]
        eps.append(mat["bands"]["radar"]["permittivity"])
        refl.append(mat["bands"]["tof"]["reflectance"])
        for band in ("radar", "tof"):
            for key, value in wood[band].items():
                if key not in ("permittivity", "reflectance"):
                    assert mat["bands"][band][key] == value
    assert 1.8 <= min(eps) and max(eps) <= 2.4 and 0.3 <= min(refl) and max(refl) <= 0.6
    assert len(set(eps)) == len(scenes)            # drawn per scene
    tops = {o["material"] for d in scenes for o in d["objects"]
            if re.fullmatch(r"desk\d+_top\d+", o["name"]) and int(o["name"][4]) > 2}
    assert tops == {"wood", "wood_var"}


def test_same_seed_same_bytes_other_seed_differs(tmp_path):
    spec = _write(tmp_path, SPEC)
    for out, seed in (("a", "9"), ("b", "9"), ("c", "10")):
        assert _generate(spec, tmp_path / out, "--count", "3", "--seed", seed) == 0
    for i in range(3):
        name = f"scene_{i:05d}.json"
        a = (tmp_path / "a" / name).read_bytes()
        assert a == (tmp_path / "b" / name).read_bytes()
        assert a != (tmp_path / "c" / name).read_bytes()


def test_bundled_office_family_furnishes_and_runs(tmp_path):
    spec = RESOURCES_DIR / "scenarios" / "office_family.json"
    assert _generate(spec, tmp_path / "o", "--count", "2", "--seed", "1") == 0
    doc = json.loads((tmp_path / "o" / "scene_00001.json").read_text())
    assert any(o["name"].startswith("walker") for o in doc["objects"])
    assert main(["run", str(tmp_path / "o" / "scene_00001.json"), "--out",
                 str(tmp_path / "s.h5"), "--frames", "1", "--quiet"]) == 0


def _with(**changes: object) -> dict:
    doc = json.loads(json.dumps(SPEC))
    doc.update(changes)
    return doc


@pytest.mark.parametrize(("doc", "needle"), [
    (_with(furniture=[{"piece": "piano", "count": [1, 2]}]), "piece 'piano' is not one of"),
    (_with(furniture=[{"piece": "desk", "count": [3, 1]}]), "low <= high"),
    (_with(furniture=[{"piece": "desk", "count": [0, 100000]}]), "high <= 200"),
    (_with(furniture=[{"piece": "shelf", "count": [200, 200]}] * 4), "at most 5000"),
    (_with(furniture=[{"piece": "desk", "count": [-1, 1]}]), "0 <= low"),
    (_with(furniture=[{"piece": "desk", "count": [1, 1], "materials": {"seat": {
        "choice": ["wood"]}}}]), "has no part 'seat'"),
    (_with(furniture=[{"piece": "desk", "count": [1, 1], "colour": "red"}]), "colour"),
    (_with(room=None), "need a 'room'"),
    (_with(room={"x_m": [2, 1], "y_m": [0, 1]}), "low < high"),
    (_with(room={"x_m": [0, "nan"], "y_m": [0, 1]}), "room.x_m"),
    (_with(room={"x_m": [0.5, 1.0], "y_m": [0.0, 0.5]}), "no free place"),
    (_with(furniture=[{"piece": "desk", "count": [40, 40]}]), "no free place"),
    (_with(materials={"m": {"from": "unobtainium"}}), "'unobtainium' is not a material"),
    (_with(materials={"m": {"from": "wood", "bands": {"xray": {}}}}), "has no band 'xray'"),
    (_with(materials={"m": {"from": "wood", "bands": {"radar": {"roughness": {
        "uniform": [5, 6]}}}}}), "not a valid project"),
    (_with(people=[{"count": [1, 1], "vital_signs": {"pulse": {"uniform": [1, 2]}}}]),
     "unknown vital sign 'pulse'"),
    (_with(people=[{"count": [1, 1], "waypoints": [0, 1000]}]), "high <= 50"),
    (_with(people=[{"count": [1, 1], "gesture": {"choice": [{"kind": "dance"}]}}]),
     "not a valid project"),
])
def test_hostile_furnishing_specs_get_one_error_line(tmp_path, capsys, doc, needle):
    spec = _write(tmp_path, doc)
    assert _generate(spec, tmp_path / "out", "--count", "2") == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("tofradar: error: ") and needle in err[0], err


def test_piece_sizes_within_their_documented_ranges(scenes):
    """The desk's top: 1.0-1.6 m by 0.6-0.8 m at 0.70-0.76 m (docs/scenarios.md)."""
    tops = [o for d in scenes for o in d["objects"]
            if re.fullmatch(r"desk\d+_top\d+", o["name"]) and int(o["name"][4]) > 2]
    assert tops
    for top in tops:
        d, w, t = top["geometry"]["size_m"]
        assert 0.6 <= d <= 0.8 and 1.0 <= w <= 1.6
        assert 0.70 <= top["pose"]["position_m"][2] + t / 2 <= 0.76 + 1e-6
    assert np.isfinite([o["pose"]["position_m"] for o in tops]).all()


def test_the_documented_example_spec_generates(tmp_path):
    """The JSON example of docs/scenarios.md's furniture section is a working spec."""
    text = (Path(__file__).parents[1] / "docs" / "scenarios.md").read_text()
    section = text[text.index("## Furniture, people and materials by count"):]
    start = section.index("```json") + len("```json")
    block = section[start: section.index("```", start)]
    spec = _write(tmp_path, json.loads(block))
    assert _generate(spec, tmp_path / "d", "--count", "3") == 0
    doc = json.loads((tmp_path / "d" / "scene_00002.json").read_text())
    boxes = {o["name"].split("_")[0] for o in doc["objects"] if o["name"].startswith("box")}
    assert 1 <= len(boxes) <= 4


def test_a_scene_regenerates_from_its_own_record(tmp_path):
    """The spec, seed and index a project records give that project again, byte for byte."""
    spec = _write(tmp_path, SPEC)
    assert _generate(spec, tmp_path / "a", "--count", "3", "--seed", "21") == 0
    original = (tmp_path / "a" / "scene_00002.json").read_bytes()
    record = json.loads(json.loads(original)["description"])
    assert record["seed"] == 21 and record["index"] == 2
    again = _write(tmp_path, record["spec"], "again.json")
    assert _generate(again, tmp_path / "b", "--count", "3", "--seed", "21") == 0
    assert (tmp_path / "b" / "scene_00002.json").read_bytes() == original


# ---------------------------------------------------------------- bundled furniture meshes
#: Sizes (depth x, width y, height z; m) the mesh tool builds (tools/make_furniture_meshes.py).
MESH_SIZES = {"sofa": (0.95, 2.0, 0.85), "armchair": (0.9, 0.85, 0.9),
              "bookcase": (0.35, 0.9, 1.8), "dining_table": (0.9, 1.6, 0.75)}


def _obj_vertices(path: Path) -> np.ndarray:
    """Vertices of an OBJ file, parsed here (not with the simulator's reader)."""
    return np.array([[float(v) for v in line.split()[1:4]]
                     for line in path.read_text().splitlines() if line.startswith("v ")])


def test_bundled_furniture_meshes_have_their_documented_sizes_and_stand_on_z0():
    import trimesh

    for name, size in MESH_SIZES.items():
        path = RESOURCES_DIR / "furniture" / f"{name}.obj"
        v = _obj_vertices(path)
        np.testing.assert_allclose(v.max(axis=0) - v.min(axis=0), size, atol=1e-4)
        np.testing.assert_allclose(v.min(axis=0)[2], 0.0, atol=1e-5)
        np.testing.assert_allclose((v.max(axis=0) + v.min(axis=0))[:2] / 2, 0.0, atol=1e-5)
        mesh = trimesh.load(path, force="mesh")           # a standard reader takes it too
        assert len(mesh.faces) > 50 and mesh.area > 0


@pytest.fixture(scope="module")
def mesh_scenes(tmp_path_factory) -> tuple[Path, list[dict]]:
    from hostile import base_project_dict, write_project

    tmp = tmp_path_factory.mktemp("mesh_furniture")
    base = base_project_dict()
    base["timeline"] = {"frame_rate_hz": 10.0, "duration_s": 0.1}
    write_project(base, tmp / "tiny.json")
    spec = {"name": "meshes", "base": "tiny.json",
            "room": {"x_m": [0.5, 6.5], "y_m": [-3.5, 3.5], "floor_z_m": 0.0,
                     "rig_clearance_m": 0.5},
            "furniture": [{"piece": "sofa", "count": [1, 1]},
                          {"piece": "armchair", "count": [1, 2]},
                          {"piece": "bookcase", "count": [0, 1],
                           "materials": {"body": {"choice": ["aluminium"]}}},
                          {"piece": "dining_table", "count": [1, 1]},
                          {"piece": "chair", "count": [1, 2]}]}
    path = _write(tmp, spec)
    assert _generate(path, tmp / "out", "--count", "12", "--seed", "2") == 0
    docs = []
    for f in sorted((tmp / "out").glob("scene_*.json")):
        load_project(f)                                 # validates: the copies are found
        docs.append(json.loads(f.read_text()))
    return tmp / "out", docs


def test_mesh_pieces_land_on_the_floor_in_the_room_without_overlap(mesh_scenes):
    """World footprints from the OBJ vertices turned by each object's pose (parsed here)."""
    out, docs = mesh_scenes
    for name in MESH_SIZES:
        assert (out / "furniture" / f"{name}.obj").read_bytes() == (
            RESOURCES_DIR / "furniture" / f"{name}.obj").read_bytes()
    seen: dict[str, set[int]] = {name: set() for name in MESH_SIZES}
    for doc in docs:
        rects, counts = [], {name: 0 for name in MESH_SIZES}
        for obj in doc["objects"]:
            g = obj["geometry"]
            if g["kind"] == "mesh":
                assert g["path"].startswith("furniture/") and g["scale"] == 1.0
                piece = Path(g["path"]).stem
                counts[piece] += 1
                v = _obj_vertices(out / g["path"])
                yaw = math.radians(obj["pose"]["rotation_deg"][2])
                assert obj["pose"]["rotation_deg"][:2] == [0.0, 0.0]
                rot = np.array([[math.cos(yaw), -math.sin(yaw), 0],
                                [math.sin(yaw), math.cos(yaw), 0], [0, 0, 1]])
                world = v @ rot.T + np.asarray(obj["pose"]["position_m"])
                assert abs(world[:, 2].min()) < 1e-5             # stands on the floor
                np.testing.assert_allclose(world[:, 2].max(), MESH_SIZES[piece][2], atol=1e-5)
                lo, hi = world.min(axis=0), world.max(axis=0)
                rects.append((lo[0], lo[1], hi[0], hi[1]))
                assert obj["material"] == ("aluminium" if piece == "bookcase" else
                                           "wood" if piece == "dining_table" else "fabric")
            elif re.fullmatch(r"chair\d+_[a-z]+\d+", obj["name"]):
                rects.append(_part_rect(obj))
        assert counts["sofa"] == 1 and counts["dining_table"] == 1
        assert 1 <= counts["armchair"] <= 2 and counts["bookcase"] <= 1
        for name, n in counts.items():
            seen[name].add(n)
        for r in rects:
            assert 0.5 - 1e-5 <= r[0] and r[2] <= 6.5 + 1e-5
            assert -3.5 - 1e-5 <= r[1] and r[3] <= 3.5 + 1e-5
    assert seen["armchair"] == {1, 2} and seen["bookcase"] == {0, 1}


def test_mesh_pieces_do_not_overlap_each_other(mesh_scenes):
    out, docs = mesh_scenes
    for doc in docs:
        pieces: dict[str, list[tuple[float, float, float, float]]] = {}
        for obj in doc["objects"]:
            g = obj["geometry"]
            stem = obj["name"].rsplit("_", 1)[0]
            if g["kind"] == "mesh":
                v = _obj_vertices(out / g["path"])
                yaw = math.radians(obj["pose"]["rotation_deg"][2])
                x = v[:, 0] * math.cos(yaw) - v[:, 1] * math.sin(yaw)
                y = v[:, 0] * math.sin(yaw) + v[:, 1] * math.cos(yaw)
                p = obj["pose"]["position_m"]
                pieces.setdefault(stem, []).append((x.min() + p[0], y.min() + p[1],
                                                    x.max() + p[0], y.max() + p[1]))
            elif re.fullmatch(r"chair\d+", stem):
                pieces.setdefault(stem, []).append(_part_rect(obj))
        rects = [(min(r[0] for r in rs), min(r[1] for r in rs), max(r[2] for r in rs),
                  max(r[3] for r in rs)) for rs in pieces.values()]
        assert len(rects) >= 4
        for i, r in enumerate(rects):
            for other in rects[i + 1:]:
                assert _apart(r, other), (r, other)


def test_a_scene_with_mesh_pieces_runs_from_its_own_folder(mesh_scenes, tmp_path,
                                                            monkeypatch):
    out, _ = mesh_scenes
    monkeypatch.chdir(tmp_path)                 # the folder of scenes is complete
    assert main(["run", str(out / "scene_00000.json"), "--out", "one.h5", "--frames", "1",
                 "--quiet"]) == 0
