"""Scene import from glTF/GLB/OBJ assets: poses, names, stored meshes, material mapping.

Known answers: node transforms composed by hand (90° rotations are exact permutations) and
by scipy's quaternions, glTF's (x, y, z) → project (x, −z, y); the library's materials; the
radar and ToF simulated on tiny scenes where only the mapping decides what is seen.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
from gltf_assets import Gltf, box
from scenes import wall_project
from scipy.spatial.transform import Rotation

from simcore.cli import main
from simcore.pipeline import Simulator
from simcore.render.meshes import build_mesh
from simcore.scene import load_project
from simcore.scene.asset_import import build_project, default_mapping
from simcore.scene.assets import AssetError, AssetMaterial, read_asset
from simcore.scene.materials import load_material_library
from simcore.scene.model import Project, SensorRig
from simcore.scene.motion import Pose
from simcore.scene.project_io import save_project

LIBRARY = set(load_material_library())
S45 = math.sqrt(0.5)


def to_project(p: np.ndarray) -> np.ndarray:
    """glTF (x, y, z) → project (x, −z, y)."""
    return np.stack([p[:, 0], -p[:, 2], p[:, 1]], axis=1)


def set_distance(a: np.ndarray, b: np.ndarray) -> float:
    """Largest distance from a point of either set to the nearest point of the other."""
    d = np.linalg.norm(a[:, None, :] - b[None, :, :], axis=2)
    return float(max(d.min(axis=0).max(), d.min(axis=1).max()))


def trs(t=(0, 0, 0), q=(0, 0, 0, 1), s=(1, 1, 1)) -> np.ndarray:
    m = np.eye(4)
    m[:3, :3] = Rotation.from_quat(q).as_matrix() @ np.diag(s)
    m[:3, 3] = t
    return m


def nested_scene() -> tuple[Gltf, dict[str, np.ndarray]]:
    """Nested, rotated, scaled nodes; returns the file and each object's glTF world matrix."""
    g = Gltf()
    steel = g.material("Steel", metallicFactor=1.0, roughnessFactor=0.5)
    wood = g.material("Oak veneer")
    cube = g.mesh([(*box((1, 1, 1)), steel)], name="cube")
    desk = g.mesh([(*box((1, 0.1, 0.5)), wood), (*box((0.1, 1, 0.1)), steel)], name="desk")
    tip_matrix = trs(t=(1, 0, 0), q=(S45, 0, 0, S45), s=(3, 3, 3))
    tip = g.node("tip", mesh=cube, matrix=tip_matrix.T.ravel().tolist())   # column-major
    arm = g.node("arm", mesh=cube, translation=[0, 0, 2], scale=[2, 1, 0.5], children=[tip])
    g.node("base", translation=[1, 2, 3], rotation=[0, S45, 0, S45], children=[arm])
    q_free = Rotation.from_rotvec([0.3, -0.7, 0.2]).as_quat()
    g.node("free", mesh=cube, translation=[-4, 0.5, 7], rotation=q_free.tolist(),
           scale=[0.5, 2, 1.5])
    g.node("chair", mesh=cube, translation=[0, 0, -3])
    g.node("chair", mesh=cube, translation=[0, 0, -5], scale=[-1, 1, 1])   # mirrored
    g.node("desk", mesh=desk, translation=[2, 0, 0])
    base = trs(t=(1, 2, 3), q=(0, S45, 0, S45))
    arm_m = base @ trs(t=(0, 0, 2), s=(2, 1, 0.5))
    worlds = {"arm": arm_m, "tip": arm_m @ tip_matrix,
              "free": trs(t=(-4, 0.5, 7), q=q_free, s=(0.5, 2, 1.5)),
              "chair": trs(t=(0, 0, -3)), "chair_2": trs(t=(0, 0, -5), s=(-1, 1, 1))}
    return g, worlds


def test_arm_vertex_by_hand(tmp_path):
    """The arm's world position written out: scale, +2 z, 90° about y, +(1,2,3), to z-up."""
    g, _ = nested_scene()
    scene = read_asset(g.write_glb(tmp_path / "s.glb"))
    arm = next(o for o in scene.objects if o.name == "arm")
    v = box((1, 1, 1))[0].astype(np.float64)
    # glTF: (2vx, vy, 0.5vz + 2) → R_y(90°): (0.5vz + 2, vy, −2vx) → + (1, 2, 3)
    # → project (x, −z, y) = (0.5vz + 3, 2vx − 3, vy + 2)
    expected = np.stack([0.5 * v[:, 2] + 3, 2 * v[:, 0] - 3, v[:, 1] + 2], axis=1)
    got = arm.world_points()
    assert len(got) == len(expected)
    assert np.abs(np.sort(got, axis=0) - np.sort(expected, axis=0)).max() < 1e-6
    for p in expected:
        assert np.linalg.norm(got - p, axis=1).min() < 1e-6


@pytest.mark.parametrize("form", ["glb", "gltf"])
def test_every_node_at_its_world_pose_with_its_name(form, tmp_path):
    g, worlds = nested_scene()
    path = g.write_glb(tmp_path / "s.glb") if form == "glb" else g.write_gltf(
        tmp_path / "s.gltf")
    scene = read_asset(path)
    names = [o.name for o in scene.objects]
    assert sorted(names) == sorted(["arm", "tip", "free", "chair", "chair_2", "desk.Oak veneer",
                                    "desk.Steel"])
    cube = box((1, 1, 1))[0].astype(np.float64)
    for name, world in worlds.items():
        obj = scene.objects[names.index(name)]
        expected = to_project(cube @ world[:3, :3].T + world[:3, 3])
        got = obj.world_points()
        err = max(np.linalg.norm(got - p, axis=1).min() for p in expected)
        assert err < 1e-6, name
        # The pose is rigid (scale and shear baked into the stored points).
        r = obj.pose.rotation_matrix()
        assert np.allclose(r @ r.T, np.eye(3), atol=1e-12) and np.linalg.det(r) > 0
    # A mirrored node keeps outward normals: its triangles' winding is flipped.
    mirrored = scene.objects[names.index("chair_2")]
    normal = np.cross(*(mirrored.world_points()[mirrored.triangles[:, k]]
                        - mirrored.world_points()[mirrored.triangles[:, 0]] for k in (1, 2)))
    centres = mirrored.world_points()[mirrored.triangles].mean(axis=1)
    outward = centres - mirrored.world_points().mean(axis=0)
    assert (np.einsum("ij,ij->i", normal, outward) > 0).all()
    assert scene.materials["Steel"].metallic == 1.0
    assert scene.materials["Steel"].roughness == 0.5


def test_stored_meshes_reload_at_the_same_world_positions(tmp_path):
    g, worlds = nested_scene()
    scene = read_asset(g.write_glb(tmp_path / "s.glb"))
    out = tmp_path / "project" / "scene.json"
    out.parent.mkdir()
    result = build_project(scene, out)
    save_project(result.project, out)
    project = load_project(out)
    assert [o.name for o in project.objects] == [o.name for o in scene.objects]
    for obj, src in zip(project.objects, scene.objects, strict=True):
        rel = Path(obj.geometry.path)
        assert not rel.is_absolute() and ".." not in rel.parts
        mesh = build_mesh(obj.geometry, base_dir=out.parent)
        m = obj.pose.matrix()
        world = mesh.points @ m[:3, :3].T + m[:3, 3]
        assert set_distance(world, src.world_points()) < 1e-6
    assert len({o.id for o in project.objects}) == len(project.objects)


def test_obj_objects_and_materials_with_y_up(tmp_path):
    text = ("mtllib room.mtl\no crate\nusemtl CardboardBox\n"
            "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n"
            "o door\nusemtl BrushedSteel\nv 0 0 2\nv 1 0 2\nv 1 2 2\nf 5 6 7\n")
    path = tmp_path / "room.obj"
    path.write_text(text)
    scene = read_asset(path)
    assert [o.name for o in scene.objects] == ["crate", "door"]
    assert set(scene.materials) >= {"CardboardBox", "BrushedSteel"}
    door = scene.objects[1]
    expected = to_project(np.array([[0, 0, 2], [1, 0, 2], [1, 2, 2]], float))
    assert np.abs(np.sort(door.world_points(), 0) - np.sort(expected, 0)).max() < 1e-9
    z_up = read_asset(path, up="z").objects[1]
    raw = np.array([[0, 0, 2], [1, 0, 2], [1, 2, 2]], float)
    assert np.abs(np.sort(z_up.world_points(), 0) - np.sort(raw, 0)).max() < 1e-9


# --------------------------------------------------------------------------- mapping
@pytest.mark.parametrize(("name", "expected"), [
    ("MetalCabinet", "aluminium"), ("brushed_steel", "aluminium"), ("Alu profile", "aluminium"),
    ("Glass panel", "glass"), ("WoodenDesk", "wood"), ("CardboardBox", "paper"),
    ("Paper", "paper"), ("Sofa fabric", "fabric"), ("Plastic chair", "black_plastic"),
    ("Concrete floor", "concrete"), ("Painted walls", "white_paint"), ("Plaster", "white_paint"),
    ("Skin", "skin"),
])
def test_name_rules(name, expected):
    mapping = default_mapping({name: AssetMaterial(name)}, LIBRARY)[name]
    assert mapping.material == expected and not mapping.unmapped


def test_pbr_metallic_override_and_unmapped():
    mats = {"Finish": AssetMaterial("Finish", metallic=1.0),
            "Matte": AssetMaterial("Matte", metallic=0.0),
            "Thing": AssetMaterial("Thing"),
            "Wood": AssetMaterial("Wood")}
    out = default_mapping(mats, LIBRARY, overrides={"Wood": "fabric"})
    assert out["Finish"].material == "aluminium" and out["Finish"].reason.startswith("PBR")
    assert out["Matte"].unmapped and out["Thing"].unmapped
    assert out["Wood"].material == "fabric" and out["Wood"].reason == "--map"
    with pytest.raises(AssetError, match="unknown material 'nope'"):
        default_mapping(mats, LIBRARY, overrides={"Thing": "nope"})


def test_pbr_roughness_becomes_the_tof_roughness_and_the_map_is_saved(tmp_path):
    g, _ = nested_scene()
    scene = read_asset(g.write_glb(tmp_path / "s.glb"))
    project = build_project(scene, tmp_path / "p.json").project
    steel = next(m for m in project.materials if m.name == "asset:Steel")
    lib = load_material_library()["aluminium"]
    assert steel.band("tof").roughness == pytest.approx(0.5 ** 2)
    assert steel.band("visible").roughness == pytest.approx(0.5 ** 2)
    assert steel.band("radar") == lib.band("radar")
    assert project.materials_map == {"Steel": "aluminium", "Oak veneer": "wood"}
    oak = next(m for m in project.materials if m.name == "asset:Oak veneer")
    assert oak.bands == load_material_library()["wood"].bands


def test_old_projects_load_with_an_empty_map(tmp_path):
    from simcore.resources import example_path

    data = json.loads(example_path("office").read_text())
    assert "materials_map" not in data
    assert load_project(example_path("office")).materials_map == {}


def test_cli_import_into_base_and_materials(tmp_path, capsys):
    g = Gltf()
    thing = g.material("Thing")
    g.node("widget", mesh=g.mesh([(*box((1, 1, 1)), thing)]))
    g.node("widget2", mesh=g.mesh([(*box((1, 1, 1)), thing)]), translation=[3, 0, 0])
    asset = g.write_glb(tmp_path / "w.glb")
    base = Project(objects=[], rig=SensorRig(pose=Pose(position_m=(0, 0, 1.0))))
    base = base.model_copy(update={"objects": wall_project().objects})
    save_project(base, tmp_path / "base.json")
    assert main(["import", str(asset), "--out", str(tmp_path / "p.json"),
                 "--into", str(tmp_path / "base.json")]) == 0
    out = capsys.readouterr().out
    assert out.count("UNMAPPED") == 1 and "Thing -> concrete" in out
    project = load_project(tmp_path / "p.json")
    assert [o.name for o in project.objects] == ["wall", "widget", "widget2"]
    assert project.rig.pose == base.rig.pose
    assert main(["import", str(asset), "--out", str(tmp_path / "q.json"),
                 "--map", "Thing=glass"]) == 0
    assert "Thing -> glass  [--map" in capsys.readouterr().out
    assert main(["materials", str(tmp_path / "q.json")]) == 0
    assert "Thing -> glass (2 objects)" in capsys.readouterr().out
    assert main(["import", str(asset), "--out", str(tmp_path / "q.json"),
                 "--map", "Thing"]) == 2
    assert "expected ASSET_MATERIAL=LIBRARY_MATERIAL" in capsys.readouterr().err


# --------------------------------------------------------------------------- sensors
def small_rig() -> SensorRig:
    rig = SensorRig(pose=Pose(position_m=(0.0, 0.0, 1.0)))
    tof = rig.tof.model_copy(update={"width": 64, "height": 48, "supersampling": 1})
    radar = rig.radar.model_copy(update={"render_width": 64, "render_height": 24})
    return rig.model_copy(update={"tof": tof, "radar": radar})


def sensor_scene(tmp_path: Path, metal: tuple[str, dict], overrides=None) -> Project:
    """A 0.3 m metal box 3 m ahead, behind a 0.6 m cardboard box 2 m ahead (rig at 1 m)."""
    g = Gltf()
    m_metal = g.material(metal[0], **metal[1])
    m_card = g.material("CardboardBox")
    # glTF axes: project x forward = glTF x; project z up = glTF y.
    g.node("metal_box", mesh=g.mesh([(*box((0.3, 0.3, 0.3)), m_metal)]),
           translation=[3.0, 1.0, 0.0])
    g.node("carton", mesh=g.mesh([(*box((0.6, 0.6, 0.6)), m_card)]), translation=[2.0, 1.0, 0.0])
    scene = read_asset(g.write_glb(tmp_path / "boxes.glb"))
    base = Project(rig=small_rig())
    out = tmp_path / "boxes.json"
    project = build_project(scene, out, base=base, overrides=overrides).project
    return project.model_copy(update={"rig": small_rig()})


def radar_rows(project: Project, base_dir: Path):
    with Simulator(project, base_dir=base_dir) as sim:
        frame = sim.frame(0)
    return frame, frame.outputs["radar"].table_rows(0)["/radar/detections"]


@pytest.mark.parametrize("metal", [("Steel", {}), ("Finish", {"metallicFactor": 1.0})],
                         ids=["named", "metallic"])
def test_metal_box_behind_cardboard_radar_sees_it_tof_does_not(metal, tmp_path):
    project = sensor_scene(tmp_path, metal)
    ids = {o.name: o.id for o in project.objects}
    frame, rows = radar_rows(project, tmp_path)
    # The radar: the metal box's front face (2.85 m) detected and labelled by its id.
    near = np.abs(rows["range"] - 2.85) < 0.2
    assert near.any()
    k = np.flatnonzero(near)[np.argmax(rows["power_fraction"][near])]
    assert rows["object_id"][k] == ids["metal_box"]
    assert rows["power_fraction"][k] > 0.9
    # The ToF camera: the cardboard box's front face (1.7 m) covers the centre.
    tof = frame.outputs["tof"]
    h, w = tof.gt_object_id.shape
    centre = tof.gt_object_id[h // 2 - 2:h // 2 + 2, w // 2 - 2:w // 2 + 2]
    assert (centre == ids["carton"]).all()
    assert np.abs(tof.depth_m[h // 2 - 2:h // 2 + 2, w // 2 - 2:w // 2 + 2] - 1.7).max() < 0.05


def test_the_same_carton_mapped_to_concrete_hides_the_metal_box(tmp_path):
    project = sensor_scene(tmp_path, ("Steel", {}), overrides={"CardboardBox": "concrete"})
    ids = {o.name: o.id for o in project.objects}
    _, rows = radar_rows(project, tmp_path)
    labelled = rows["object_id"][rows["power_fraction"] > 0.5]
    assert ids["metal_box"] not in labelled
    assert ids["carton"] in labelled


def glass_t() -> float:
    """One-pass near-IR power transmittance of the library's glass (Fresnel, its index)."""
    band = load_material_library()["glass"].band("tof")
    n = math.sqrt(band.permittivity)
    r = ((n - 1) / (n + 1)) ** 2
    return (1 - r) ** 2 / (1 - r * r)


def test_an_imported_glass_panel_transmits_as_the_library_glass(tmp_path):
    def scene(with_pane: bool) -> Project:
        g = Gltf()
        wall = g.material("Painted wall")
        g.node("wall", mesh=g.mesh([(*box((0.1, 20, 20)), wall)]), translation=[2.05, 1, 0])
        if with_pane:
            glass = g.material("Glass panel")
            g.node("pane", mesh=g.mesh([(*box((0.004, 8, 8)), glass)]),
                   translation=[1.002, 1, 0])
        folder = tmp_path / ("pane" if with_pane else "open")
        folder.mkdir()
        asset = read_asset(g.write_glb(folder / "s.glb"))
        p = build_project(asset, folder / "p.json").project
        tof = p.rig.tof.model_copy(update={"crosstalk_sigma_px": 0.0, "width": 64,
                                           "height": 48, "supersampling": 1})
        return p.model_copy(update={"rig": small_rig().model_copy(update={"tof": tof})}), folder

    amps = []
    for with_pane in (False, True):
        project, folder = scene(with_pane)
        with Simulator(project, base_dir=folder, seed=0) as sim:
            frame = sim.frame(0)
        amps.append(frame.outputs["tof"])
    open_out, out = amps
    cfg = project.rig.tof
    fx = 0.5 * cfg.width / math.tan(math.radians(cfg.fov_h_deg) / 2)
    fy = 0.5 * cfg.height / math.tan(math.radians(cfg.fov_v_deg) / 2)
    u = (np.arange(cfg.width) + 0.5 - cfg.width / 2) / fx
    v = (np.arange(cfg.height) + 0.5 - cfg.height / 2) / fy
    tan = np.sqrt(u[None, :] ** 2 + v[:, None] ** 2)
    away = (tan > math.tan(math.radians(12))) & open_out.valid & out.valid
    assert away.sum() > 100
    # Through the pane the camera measures the wall, at the wall's amplitude times T².
    # (The simulator adds noise: medians over the pixels.) The pane is 1 m away.
    assert np.median(np.abs(out.depth_m[away] - open_out.depth_m[away])) < 0.01
    assert np.median(open_out.depth_m[away]) > 1.9
    ratio = np.median(out.amplitude[away]) / np.median(open_out.amplitude[away])
    print(f"amplitude ratio {ratio:.4f}, T² = {glass_t() ** 2:.4f}")
    assert ratio == pytest.approx(glass_t() ** 2, rel=0.02)


def test_a_second_import_into_the_same_project_keeps_the_first_meshes(tmp_path, capsys):
    for name, size in (("a", 1.0), ("b", 2.0)):
        g = Gltf()
        g.node("box", mesh=g.mesh([(*box((size, size, size)), g.material("Steel"))]))
        g.write_glb(tmp_path / f"{name}.glb")
    out = str(tmp_path / "p.json")
    assert main(["import", str(tmp_path / "a.glb"), "--out", out]) == 0
    assert main(["import", str(tmp_path / "b.glb"), "--out", out, "--into", out]) == 0
    project = load_project(out)
    assert [o.name for o in project.objects] == ["box", "box_2"]
    assert len({o.geometry.path for o in project.objects}) == 2
    for obj, size in zip(project.objects, (1.0, 2.0), strict=True):
        mesh = build_mesh(obj.geometry, base_dir=tmp_path)
        assert np.ptp(mesh.points, axis=0) == pytest.approx([size] * 3)


def test_obj_fast_and_line_parsers_agree(tmp_path):
    """The same geometry written plainly (vectorised parser) and with relative indices
    and indentation (the line-by-line parser) gives the same objects."""
    plain = ("o crate\nusemtl Card\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvn 0 0 1\n"
             "f 1/1/1 2/2/1 3/3/1 4/4/1\ngx 1\ng lid\nusemtl Steel\nv 0 0 1\nv 1 0 1\n"
             "v 1 1 1\nf 5//1 6//1 7//1\n")
    relative = ("o crate\nusemtl Card\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
                "  f -4 -3 -2 -1\ng lid\nusemtl Steel\nv 0 0 1\nv 1 0 1\nv 1 1 1\n"
                "f -3 -2 -1\n")
    scenes = []
    for name, text in (("plain", plain), ("relative", relative)):
        (tmp_path / f"{name}.obj").write_text(text)
        scenes.append(read_asset(tmp_path / f"{name}.obj", up="z"))
    a, b = scenes
    assert [(o.name, o.material) for o in a.objects] == [("crate", "Card"), ("lid", "Steel")]
    assert [(o.name, o.material) for o in b.objects] == [("crate", "Card"), ("lid", "Steel")]
    for oa, ob in zip(a.objects, b.objects, strict=True):
        assert len(oa.triangles) == len(ob.triangles)
        assert set_distance(oa.world_points(), ob.world_points()) < 1e-12
    assert len(a.objects[0].triangles) == 2        # the quad as a fan of two triangles


# --------------------------------------------------------------------------- rig, example
def test_a_new_project_looks_at_the_scene_from_a_sensible_place(tmp_path):
    """Without --into: a small scene seen from outside, centred in the ToF image; a room
    seen from inside, 1.5 m above its floor, the rig's forward axis at the room's centre."""
    g = Gltf()
    g.node("crate", mesh=g.mesh([(*box((0.4, 0.3, 0.5)), g.material("Cardboard"))]),
           translation=[5.0, 2.0, -3.0])
    scene = read_asset(g.write_glb(tmp_path / "crate.glb"))
    project = build_project(scene, tmp_path / "crate.json").project
    lo, hi = scene.bounds()
    eye = np.array(project.rig.pose.position_m)
    assert not ((lo <= eye) & (eye <= hi)).all()          # outside the crate
    tof = project.rig.tof.model_copy(update={"width": 32, "height": 24, "supersampling": 1})
    project = project.model_copy(update={"rig": project.rig.model_copy(update={"tof": tof})})
    with Simulator(project, base_dir=tmp_path) as sim:
        ids = sim.frame(0).outputs["tof"].gt_object_id
    assert (ids[11:13, 15:17] == project.objects[0].id).all()

    g = Gltf()
    paint = g.material("Painted walls")
    g.node("floor", mesh=g.mesh([(*box((6.0, 0.1, 5.0)), paint)]), translation=[1, -0.05, 0])
    g.node("ceiling", mesh=g.mesh([(*box((6.0, 0.1, 5.0)), paint)]), translation=[1, 3.05, 0])
    room = read_asset(g.write_glb(tmp_path / "room.glb"))
    pose = build_project(room, tmp_path / "room.json").project.rig.pose
    lo, hi = room.bounds()
    eye = np.array(pose.position_m)
    assert ((lo < eye) & (eye < hi)).all()                 # inside the room
    assert eye[2] == pytest.approx(lo[2] + 1.5)            # 1.5 m above the floor
    assert eye[0] == pytest.approx(lo[0] + 0.15 * (hi[0] - lo[0]))
    forward = pose.rotation_matrix()[:, 0]                  # the rig's body x axis
    to_centre = (lo + hi) / 2 - eye
    assert forward @ to_centre == pytest.approx(np.linalg.norm(to_centre))


def _tool():
    """tools/make_gltf_room.py as a module (it is a script, not a package)."""
    import importlib.util

    path = Path(__file__).resolve().parents[1] / "tools" / "make_gltf_room.py"
    spec = importlib.util.spec_from_file_location("make_gltf_room", path)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_the_bundled_room_is_the_tools_and_imports_as_the_example(tmp_path):
    """resources/examples/office_gltf_room.glb is what tools/make_gltf_room.py writes, its
    named materials map as the issue lists them, and importing it again gives the objects
    and meshes of office_gltf.json."""
    from simcore.resources import example_path

    example = example_path("office_gltf")
    glb = example.parent / "office_gltf_room.glb"
    assert glb.read_bytes() == _tool().room().glb()
    stored = load_project(example)
    assert stored.materials_map == {"Painted walls": "white_paint",
                                    "Metal cabinet": "aluminium", "Glass panel": "glass",
                                    "Wooden desk": "wood", "Cardboard box": "paper"}
    scene = read_asset(glb)
    again = build_project(scene, tmp_path / "again.json",
                          base=stored.model_copy(update={"objects": [],
                                                         "materials_map": {}})).project
    assert [o.name for o in again.objects] == [o.name for o in stored.objects]
    assert again.materials_map == stored.materials_map
    for new, old in zip(again.objects, stored.objects, strict=True):
        assert new.material == old.material
        worlds = []
        for obj, folder in ((new, tmp_path), (old, example.parent)):
            mesh = build_mesh(obj.geometry, base_dir=folder)
            m = obj.pose.matrix()
            worlds.append(mesh.points @ m[:3, :3].T + m[:3, 3])
        assert set_distance(*worlds) < 1e-6, new.name
