"""Several named sensors on several rigs: poses, capture times, names and shared work (#30).

Known answers: a named radar is the built-in radar's model at its own pose (the same data
as a one-radar project with the radar placed there), its truth is the geometry of its pose,
a sensor at half rate captures exactly every second frame at ``t_i + offset``, a moving
wall is seen where it is at the capture time, renaming a sensor renames its outputs only,
and version-2 project files give the frames of their version-3 re-saves bit for bit.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from simcore.io.reader import open_dataset
from simcore.pipeline import Frame, Simulator
from simcore.resources import example_path
from simcore.scene import Box, Pose, Project, SceneObject, load_project, save_project
from simcore.scene.model import Rig, named_sensor
from simcore.scene.motion import Motion
from simcore.sensors.base import active_sensors, rename_items, sensor_rng_stream
from tests.scenes import wall_project

OLD = Path(__file__).parent / "data" / "old_projects"
#: The dataset paths of a one-ToF one-radar project, as the code before #30 wrote them.
ONE_RIG_PATHS = [
    "/objects/aabb", "/objects/angular_velocity", "/objects/obb_center", "/objects/obb_rotation",
    "/objects/obb_size", "/objects/radar_azimuth", "/objects/radar_elevation",
    "/objects/radar_radial_velocity", "/objects/radar_range", "/objects/reference_point",
    "/objects/velocity", "/poses/objects", "/poses/rig", "/radar/adc", "/radar/bird_eye",
    "/radar/chirp_start_time", "/radar/range_azimuth", "/radar/range_doppler",
    "/radar/range_profile", "/radar/range_profile_integrated", "/time", "/tof/amplitude",
    "/tof/correlation", "/tof/depth", "/tof/exposure_time", "/tof/gt_object_id",
    "/tof/gt_range", "/tof/intensity", "/tof/valid"]
ONE_RIG_STATIC = ["/objects/ids", "/objects/names", "/radar/azimuth_axis",
                  "/radar/bird_eye_x_axis", "/radar/bird_eye_z_axis", "/radar/range_axis",
                  "/radar/velocity_axis"]


def with_rigs(project: Project, *rigs: Rig, **first: Any) -> Project:
    """``project`` with more rigs (and first-rig fields such as ``sensors`` replaced)."""
    doc = project.model_dump()
    doc["rig"].update({k: (v.model_dump() if hasattr(v, "model_dump") else
                           {n: c.model_dump() for n, c in v.items()} if isinstance(v, dict)
                           else v) for k, v in first.items()})
    doc["rigs"] = [r.model_dump() for r in rigs]
    return Project.model_validate(doc)


def radar_frame_of(pose: Pose, mount: Pose) -> tuple[np.ndarray, np.ndarray]:
    """World position of a radar and its body axes (columns) for a rig pose, by hand.

    Rotations here are about z only (yaw ψ): the body x axis is (cos ψ, sin ψ, 0).
    """
    assert pose.rotation_deg[:2] == (0.0, 0.0) and mount.rotation_deg == (0.0, 0.0, 0.0)
    psi = np.radians(pose.rotation_deg[2])
    axes = np.array([[np.cos(psi), -np.sin(psi), 0.0],
                     [np.sin(psi), np.cos(psi), 0.0],
                     [0.0, 0.0, 1.0]])
    return np.asarray(pose.position_m) + axes @ np.asarray(mount.position_m), axes


def geometry(point: np.ndarray, origin: np.ndarray, axes: np.ndarray
             ) -> tuple[float, float, float]:
    """Range (m), azimuth (deg, + right) and elevation (deg, + up) of a point from a radar."""
    fwd, left, up = axes.T @ (point - origin)
    return (float(np.linalg.norm(point - origin)), float(np.degrees(np.arctan2(-left, fwd))),
            float(np.degrees(np.arctan2(up, np.hypot(fwd, left)))))


SIDE_POSE = Pose(position_m=(0.4, -0.7, 1.0), rotation_deg=(0.0, 0.0, 15.0))


def test_a_second_radar_sees_the_targets_where_its_pose_puts_them() -> None:
    """A radar on a second rig, yawed 15°: truth and detections at the geometric range/angle."""
    base = load_project(example_path("point_targets"))
    side = named_sensor(base.rig.radar)
    project = with_rigs(base, Rig(name="cart", pose=SIDE_POSE, sensors={"side": side}))
    origin, axes = radar_frame_of(SIDE_POSE, side.pose_on_rig)
    with Simulator(project) as sim:
        frame = sim.frame(0)
        items = frame.hdf5_items()
        rows = frame.table_rows()
        assert list(sim.static_items()["/poses/rig_names"][0]) == ["rig", "cart"]
    det = frame.outputs["side"].dsp.detections
    resolution = base.rig.radar.range_resolution_m
    for k, obj in enumerate(base.objects):
        r, az, el = geometry(np.asarray(obj.pose.position_m), origin, axes)
        np.testing.assert_allclose(items["/objects/side/range"][0][k], r, rtol=1e-12)
        np.testing.assert_allclose(items["/objects/side/azimuth"][0][k], az, atol=1e-9)
        np.testing.assert_allclose(items["/objects/side/elevation"][0][k], el, atol=1e-9)
        # The detection nearest the predicted range: within a range cell and a few degrees.
        j = int(np.argmin(np.abs(det.range_m - r)))
        print(f"{obj.name}: R {r:.3f} az {az:+.1f} | det {det.range_m[j]:.3f} "
              f"{det.azimuth_deg[j]:+.1f}")
        assert abs(det.range_m[j] - r) < resolution
        assert abs(det.azimuth_deg[j] - az) < 4.0
        # The detection's label: the target it is.
        assert rows["/side/detections"]["object_id"][j] == obj.id
    # Every rig's pose, in project order.
    rigs = items["/poses/rigs"][0]
    assert rigs.shape == (2, 4, 4)
    np.testing.assert_allclose(rigs[1][:3, 3], SIDE_POSE.position_m, atol=1e-12)
    np.testing.assert_allclose(rigs[1][:3, :3], axes, atol=1e-12)
    np.testing.assert_array_equal(rigs[0], items["/poses/rig"][0])
    # The built-in radar's truth is unchanged by the second rig.
    with Simulator(base) as sim:
        alone = sim.frame(0).hdf5_items()
    np.testing.assert_array_equal(items["/objects/radar_range"][0],
                                  alone["/objects/radar_range"][0])
    np.testing.assert_array_equal(items["/radar/adc"][0], alone["/radar/adc"][0])


def test_a_named_radar_is_the_builtin_radar_model_at_its_pose() -> None:
    """Reference: the built-in radar moved to the named radar's pose gives the same data.

    Without receiver noise (the one thing drawn from a sensor's own stream) the ADC cube,
    the maps and the truth are equal bit for bit.
    """
    base = load_project(example_path("point_targets"))
    quiet = base.rig.radar.model_copy(update={"noise_variance_adc": 0.0})
    base = with_rigs(base, radar=quiet)
    named = with_rigs(base, Rig(name="cart", pose=SIDE_POSE,
                                sensors={"side": named_sensor(quiet)}))
    moved = with_rigs(base, pose=SIDE_POSE)
    with Simulator(named) as sim:
        a = sim.frame(1)
    with Simulator(moved) as sim:
        b = sim.frame(1)
    np.testing.assert_array_equal(a.outputs["side"].raw.adc, b.outputs["radar"].raw.adc)
    ia, ib = a.hdf5_items(), b.hdf5_items()
    for q in ("range_doppler", "range_azimuth", "range_profile"):
        np.testing.assert_array_equal(ia[f"/side/{q}"][0], ib[f"/radar/{q}"][0])
    for q in ("range", "radial_velocity", "azimuth", "elevation"):
        np.testing.assert_array_equal(ia[f"/objects/side/{q}"][0], ib[f"/objects/radar_{q}"][0])


def half_rate_project() -> Project:
    base = wall_project()
    base = base.model_copy(update={"timeline": base.timeline.model_copy(
        update={"frame_rate_hz": 10.0, "duration_s": 0.5})})
    tof2 = named_sensor(base.rig.tof.model_copy(
        update={"frame_rate_hz": 5.0, "trigger_offset_s": 0.013}))
    return with_rigs(base, sensors={"tof2": tof2})


def test_a_half_rate_sensor_captures_every_second_frame_at_its_offset() -> None:
    project = half_rate_project()
    with Simulator(project) as sim:
        frames = list(sim.frames(range(5)))
    for f in frames:
        t_i = f.index / 10.0
        assert f.time_s == t_i
        assert ("tof2" in f.outputs) == (f.index % 2 == 0)
        assert {"tof", "radar"} <= set(f.outputs)
        assert f.capture_times["tof2"] == t_i + 0.013
        assert f.capture_times["tof"] == t_i
        items = f.hdf5_items()
        assert bool(items["/tof2/captured"][0]) == (f.index % 2 == 0)
        assert float(items["/tof2/time"][0]) == t_i + 0.013
        assert float(items["/tof/time"][0]) == t_i and bool(items["/tof/captured"][0])
        depth = items["/tof2/depth"][0]
        if f.index % 2:
            assert not np.any(depth) and depth.shape == items["/tof/depth"][0].shape
        else:
            assert f.buffers["tof2"].time_s == t_i + 0.013
            np.testing.assert_array_equal(depth, f.outputs["tof2"].depth_m)
            assert np.nanmedian(depth) > 1.9


def test_a_run_starting_in_a_non_capture_frame_writes_the_sensor_zeros() -> None:
    project = half_rate_project()
    with Simulator(project) as sim:
        f = sim.frame(3)
    assert "tof2" not in f.outputs
    items = f.hdf5_items()
    assert items["/tof2/depth"][0].shape == (project.rig.tof.height, project.rig.tof.width)
    assert not np.any(items["/tof2/depth"][0])


def test_a_trigger_offset_sees_a_moving_wall_where_it_is_then() -> None:
    """Wall approaching at 2 m/s: a camera triggered 30 ms late sees it 6 cm nearer."""
    v, dt = -2.0, 0.03
    base = wall_project(3.0)
    wall = base.objects[0].model_copy(update={"motion": Motion(velocity_mps=(v, 0.0, 0.0))})
    base = base.model_copy(update={"objects": [wall]})
    late = named_sensor(base.rig.tof.model_copy(update={"trigger_offset_s": dt}))
    late_radar = named_sensor(base.rig.radar.model_copy(update={"trigger_offset_s": dt}))
    project = with_rigs(base, sensors={"late": late, "late_radar": late_radar})
    with Simulator(project) as sim:
        f = sim.frame(2)
    t = f.time_s
    on_time = f.outputs["tof"].gt_range
    delayed = f.outputs["late"].gt_range
    seen = np.isfinite(on_time) & np.isfinite(delayed)
    assert seen.mean() > 0.9
    # Same rays, face at 3 + v t ahead of the camera: ranges scale as the face distances.
    ratio = (3.0 + v * (t + dt)) / (3.0 + v * t)
    np.testing.assert_allclose(delayed[seen] / on_time[seen], ratio, rtol=2e-5)
    # The late radar's object truth is for its capture time: the wall's centre then.
    items = f.hdf5_items()
    np.testing.assert_allclose(items["/late_radar/chirp_start_time"][0]
                               - items["/radar/chirp_start_time"][0], dt, rtol=0, atol=1e-12)
    assert f.outputs["late_radar"].raw.time_s == t + dt
    centre = np.array([3.1 + v * (t + dt), 0.0, 0.0])
    origin = (np.asarray(project.rig.pose.position_m)
              + np.asarray(project.rig.sensors["late_radar"].pose_on_rig.position_m))
    np.testing.assert_allclose(items["/objects/late_radar/range"][0][0],
                               np.linalg.norm(centre - origin), rtol=1e-12)
    np.testing.assert_allclose(items["/objects/late_radar/radial_velocity"][0][0],
                               v * (centre - origin)[0] / np.linalg.norm(centre - origin),
                               rtol=1e-9)


def two_rig_project(names: tuple[str, str]) -> Project:
    base = wall_project()
    base = base.model_copy(update={"timeline": base.timeline.model_copy(
        update={"duration_s": 0.2})})
    return with_rigs(base, Rig(name="cart", pose=Pose(position_m=(0.0, 0.5, 0.2)), sensors={
        names[0]: named_sensor(base.rig.tof), names[1]: named_sensor(base.rig.radar)}))


def _frame_items(frame: Frame) -> dict[str, Any]:
    return {**{k: v[0] for k, v in frame.hdf5_items().items()}, **frame.table_rows()}


def test_renaming_a_sensor_renames_its_outputs_and_nothing_else() -> None:
    a_project = two_rig_project(("cam", "rad"))
    b_project = two_rig_project(("eye", "ear"))
    names = {"/cam/": "/eye/", "/rad/": "/ear/", "/objects/rad/": "/objects/ear/"}

    def renamed(path: str) -> str:
        for old, new in names.items():
            if path.startswith(old):
                return new + path[len(old):]
        return path

    with Simulator(a_project) as sim:
        a = [_frame_items(f) for f in sim.frames(range(2))]
        a_static = sim.static_items()
    with Simulator(b_project) as sim:
        b = [_frame_items(f) for f in sim.frames(range(2))]
        b_static = sim.static_items()
    assert {renamed(p) for p in a_static} == set(b_static)
    for fa, fb in zip(a, b, strict=True):
        assert "/cam/depth" in fa and "/ear/adc" in fb and "/ear/detections" in fb
        assert {renamed(p) for p in fa} == set(fb)
        for path, value in fa.items():
            np.testing.assert_array_equal(value, fb[renamed(path)], err_msg=path)


def test_alike_sensors_share_one_render_and_keep_their_own_noise() -> None:
    """A second camera at the first one's pose: no extra render, its own noise stream."""
    base = wall_project()
    twin = with_rigs(base, sensors={"twin": named_sensor(base.rig.tof)})
    with Simulator(base) as sim:
        sim.frame(0)
        renders_alone = sim.render_count
    with Simulator(twin) as sim:
        f = sim.frame(0)
        assert sim.render_count == renders_alone
    assert f.buffers["twin"] is f.buffers["tof"]
    np.testing.assert_array_equal(f.outputs["twin"].gt_range, f.outputs["tof"].gt_range)
    assert not np.array_equal(f.outputs["twin"].depth_m, f.outputs["tof"].depth_m)
    # Alike radars behind a pane (a see-through pass) share both passes too.
    pane = SceneObject(id=2, name="pane", geometry=Box(size_m=(0.01, 1.0, 1.0)),
                       pose=Pose(position_m=(1.0, 0.0, 0.0)), material="glass")
    glazed = base.model_copy(update={"objects": [*base.objects, pane]})
    counts = []
    for project in (glazed, with_rigs(glazed, sensors={"radar_b": named_sensor(
            glazed.rig.radar)})):
        with Simulator(project) as sim:
            g = sim.frame(0)
            counts.append(sim.render_count)
    assert "radar" in g.see_through and g.see_through["radar_b"] is g.see_through["radar"]
    assert counts[0] == counts[1]
    streams = {s.name: s.rng_stream for s in active_sensors(twin)}
    assert streams == {"tof": 0, "radar": 1, "twin": sensor_rng_stream("tof", "twin", 0, 0)}
    assert len(set(streams.values())) == 3


def test_the_still_background_serves_only_the_sensors_of_still_rigs() -> None:
    """A moving second rig: its frames equal the plain path's bit for bit."""
    base = wall_project(4.0)
    mover = SceneObject(id=2, name="box", geometry=Box(size_m=(0.3, 0.3, 0.3)),
                        pose=Pose(position_m=(2.0, 0.0, 0.0)),
                        motion=Motion(velocity_mps=(0.0, 1.0, 0.0)))
    base = base.model_copy(update={"objects": [*base.objects, mover]})
    cart = Rig(name="cart", pose=Pose(position_m=(0.0, -0.5, 0.0)),
               motion=Motion(velocity_mps=(0.5, 0.0, 0.0)),
               sensors={"cart_tof": named_sensor(base.rig.tof)})
    project = with_rigs(base, cart)
    results = []
    for reuse in (True, False):
        with Simulator(project, reuse_static=reuse) as sim:
            results.append([f.outputs for f in sim.frames(range(3))])
            if reuse:
                misses = dict(sim.engine.cache.misses)
    assert misses.get("raster:tof:background", 0) >= 1
    assert "raster:cart_tof:background" not in misses
    for fast, plain in zip(*results, strict=True):
        for name in ("tof", "cart_tof"):
            np.testing.assert_array_equal(fast[name].depth_m, plain[name].depth_m)
            np.testing.assert_array_equal(fast[name].amplitude, plain[name].amplitude)


def test_rename_items_moves_only_the_kind_group() -> None:
    items = {"/radar/adc": 1, "/radar/x/y": 2, "/radarx/z": 3, "/objects/radar_range": 4}
    assert rename_items(items, "radar", "front") == {
        "/front/adc": 1, "/front/x/y": 2, "/radarx/z": 3, "/objects/radar_range": 4}
    assert rename_items(items, "radar", "radar") is items


# ---------------------------------------------------------------------- compatibility
@pytest.mark.parametrize("name", ["wall", "office_rgb", "point_targets", "person_walking"])
def test_version_2_files_and_their_version_3_resaves_give_the_same_frames(name: str,
                                                                          tmp_path: Path
                                                                          ) -> None:
    old_path = OLD / f"v2_{name}.json"
    assert json.loads(old_path.read_text())["format_version"] == 2
    old = load_project(old_path)
    save_project(old, tmp_path / "v3.json")
    assert json.loads((tmp_path / "v3.json").read_text())["format_version"] == 3
    new = load_project(tmp_path / "v3.json")
    assert new == old
    frames = []
    for project in (old, new):
        with Simulator(project) as sim:
            frames.append([_frame_items(f) for f in sim.frames(range(2))])
            static = sorted(sim.static_items())
    for fa, fb in zip(*frames, strict=True):
        assert set(fa) == set(fb)
        for path, value in fa.items():
            np.testing.assert_array_equal(value, fb[path], err_msg=path)
    # A one-ToF one-radar project keeps the dataset paths of before #30.
    paths = [p for p in frames[0][0] if not p.startswith(("/rgb/", "/people/"))
             and p not in ("/tof/gt_body_part", "/radar/detections")]
    assert sorted(paths) == ONE_RIG_PATHS
    assert [p for p in static if not p.startswith("/people/")] == ONE_RIG_STATIC


def test_every_old_fixture_and_example_loads_as_version_3(tmp_path: Path) -> None:
    """Every project file of earlier versions loads with the meaning of today's.

    The bundled examples were re-saved as version 3 from their version-2 files (kept in
    tests/data/old_projects): each old file loads into exactly today's example.
    """
    from simcore.resources import EXAMPLES_DIR

    examples = Path(EXAMPLES_DIR)
    for folder in examples.glob("*.meshes"):       # the glTF office's meshes, relative
        (tmp_path / folder.name).symlink_to(folder)
    old_examples = sorted(OLD.glob("v2_*.json"))
    # Multi-rig examples exist only in version 3 (a version-2 project has one rig).
    version_3_only = {"two_radars_facing.json", "robot_pair.json"}
    assert ({p.name.removeprefix("v2_") for p in old_examples}
            == {p.name for p in examples.glob("*.json")} - version_3_only)
    for path in old_examples:
        name = path.name.removeprefix("v2_")
        (tmp_path / name).write_text(path.read_text())
        old = load_project(tmp_path / name)
        assert old == load_project(examples / name), name
    for path in [*OLD.glob("v1_*.json"), *examples.glob("*.json")]:
        if path.name in version_3_only:
            continue
        project = load_project(path)
        assert project.format_version == 3, path
        assert list(project.sensor_configs())[:2] == ["tof", "radar"], path
        assert project.rigs == [] and project.rig.sensors == {}, path


def test_a_dataset_of_several_sensors_reads_back(tmp_path: Path) -> None:
    """HDF5 and Zarr: one frame axis, zeros and ``captured`` in non-capture frames."""
    from simcore.cli import main

    project = half_rate_project()
    project = with_rigs(project, Rig(name="cart", pose=Pose(position_m=(0.0, 0.4, 0.0)),
                                     sensors={"radar2": named_sensor(project.rig.radar)}))
    path = tmp_path / "multi.json"
    save_project(project, path)
    for out in (tmp_path / "multi.h5", tmp_path / "multi.zarr"):
        assert main(["run", str(path), "--out", str(out), "--frames", "4", "--quiet",
                     "--shard-frames", "2"]) == 0
        ds = open_dataset(out)
        try:
            np.testing.assert_array_equal(ds.tof2_captured.values, [True, False, True, False])
            np.testing.assert_allclose(ds.tof2_time.values, np.arange(4) / 10 + 0.013,
                                       rtol=0, atol=1e-15)
            assert ds.tof2_depth.dims == ("frame", "tof2_row", "tof2_col")
            assert not np.any(ds.tof2_depth.isel(frame=1).values)
            assert np.nanmedian(ds.tof2_depth.isel(frame=2).values) > 1.9
            assert ds.radar2_range_doppler.dims == ("frame", "radar2_velocity", "radar2_range")
            np.testing.assert_array_equal(ds.radar2_range.values, ds.range.values)
            assert ds.objects_radar2_range.dims == ("frame", "object")
            assert "radar2_detection_range" in ds and "detection_range" in ds
            assert ds.radar_range_doppler.dims == ("frame", "velocity", "range")
        finally:
            ds.close()


# ---------------------------------------------------------------------- field paths, checks
def test_field_paths_reach_named_sensors_and_further_rigs() -> None:
    from simcore.scene.fieldpath import FieldPathError, get, with_value

    project = two_rig_project(("cam", "rad"))
    edited = with_value(project, "rigs[0].sensors.rad.chirps_per_frame", 32)
    assert get(edited, "rigs[0].sensors.rad.chirps_per_frame") == 32
    assert get(edited.model_dump(), "rigs[0].sensors.rad.chirps_per_frame") == 32
    assert edited.sensor_config("rad").chirps_per_frame == 32  # type: ignore[attr-defined]
    assert get(edited, "rig.radar.chirps_per_frame") == project.rig.radar.chirps_per_frame
    edited = with_value(project, "rigs[0].pose.position_m[0]", 1.5)
    assert edited.rigs[0].pose.position_m[0] == 1.5
    with pytest.raises(FieldPathError, match=r"rigs\[0\]\.sensors\.nope does not exist"):
        with_value(project, "rigs[0].sensors.nope.fov_h_deg", 50.0)
    assert project.sensor_path("cam") == "rigs[0].sensors.cam"
    assert project.sensor_path("radar") == "rig.radar"


def test_preflight_counts_and_checks_every_sensor() -> None:
    from simcore.preflight import check, estimate_cost

    one = wall_project()
    two = two_rig_project(("cam", "rad"))
    c1, c2 = estimate_cost(one), estimate_cost(two)
    assert c2.render_pixels == 2 * c1.render_pixels
    assert c2.transforms == 2 * c1.transforms
    parts = dict(c2.memory_parts)
    assert parts["rigs[0].sensors.cam render (width × height × supersampling²)"] == \
        parts["rig.tof render (width × height × supersampling²)"]
    # Half the frames: half the camera's disk per frame.
    half = half_rate_project()
    tof = one.rig.tof
    assert estimate_cost(half).disk_bytes_per_frame - c1.disk_bytes_per_frame == \
        int(0.5 * tof.width * tof.height * 37)
    # A corner reflector at the second radar's antennas is refused, naming the object.
    from simcore.scene.geometry import CornerReflector

    at = np.asarray(two.rigs[0].pose.position_m) + np.asarray(
        two.rigs[0].sensors["rad"].pose_on_rig.position_m)
    target = SceneObject(id=7, name="cr", geometry=CornerReflector(edge_m=0.05),
                         pose=Pose(position_m=tuple(float(v) for v in at)))
    near = two.model_copy(update={"objects": [*two.objects, target]})
    problems = check(near)
    assert any("'cr' comes within" in p for p in problems), problems
    assert not any("'cr'" in p for p in check(one.model_copy(
        update={"objects": [*one.objects, target]})))


def test_bench_second_rig_is_a_copy_of_the_first_placed_beside_it() -> None:
    from simcore.bench import with_second_rig

    office = load_project(example_path("office"))
    two = with_second_rig(office, offset_m=(0.0, -1.0, 0.0), yaw_deg=30.0)
    rig = two.rigs[0]
    assert list(rig.sensors) == ["rig2_tof", "rig2_radar"]
    first = office.rig.pose.position_m
    np.testing.assert_allclose(rig.pose.position_m, (first[0], first[1] - 1.0, first[2]))
    assert rig.pose.rotation_deg[2] == office.rig.pose.rotation_deg[2] + 30.0
    tof = rig.sensors["rig2_tof"].model_dump()
    assert tof.pop("kind") == "tof" and tof == office.rig.tof.model_dump()


def test_generate_varies_named_sensors_and_further_rigs(tmp_path: Path) -> None:
    from simcore.cli import main

    save_project(two_rig_project(("cam", "rad")), tmp_path / "base.json")
    spec = {"format": "tofradar-scenario/1", "name": "carts", "base": "base.json",
            "vary": {"rigs[0].pose.position_m[0]": {"uniform": [1.0, 2.0]},
                     "rigs[0].sensors.rad.chirps_per_frame": {"choice": [16, 32]}}}
    (tmp_path / "spec.json").write_text(json.dumps(spec))
    assert main(["generate", str(tmp_path / "spec.json"), "--count", "4", "--out",
                 str(tmp_path / "scenes")]) == 0
    projects = [load_project(p) for p in sorted((tmp_path / "scenes").glob("*.json"))]
    assert len(projects) == 4
    for p in projects:
        assert 1.0 <= p.rigs[0].pose.position_m[0] <= 2.0
        assert p.sensor_config("rad").chirps_per_frame in (16, 32)  # type: ignore[attr-defined]
        assert p.rig.radar.chirps_per_frame == 16   # the built-in radar is not varied
    assert len({p.rigs[0].pose.position_m[0] for p in projects}) == 4


def test_validate_lists_every_sensor_with_its_rig_and_timing(tmp_path: Path,
                                                            capsys: pytest.CaptureFixture[str]
                                                            ) -> None:
    from simcore.cli import main

    project = with_rigs(half_rate_project(), Rig(name="cart", sensors={
        "rear": named_sensor(wall_project().rig.radar.model_copy(
            update={"trigger_offset_s": 0.02}))}))
    save_project(project, tmp_path / "p.json")
    assert main(["validate", str(tmp_path / "p.json")]) == 0
    out = capsys.readouterr().out
    assert "tof2: tof on rig 'rig', 5 frames/s (every 2 frames), 13 ms after the frame" in out
    assert "rear: radar on rig 'cart', 10 frames/s (every 1 frame), 20 ms after the frame" in out


def test_people_truth_per_radar_is_the_segments_geometry() -> None:
    base = load_project(example_path("person_walking"))
    project = with_rigs(base, Rig(name="cart", pose=SIDE_POSE,
                                  sensors={"side": named_sensor(base.rig.radar)}))
    with Simulator(project) as sim:
        f = sim.frame(3)
    items = f.hdf5_items()
    origin, axes = radar_frame_of(SIDE_POSE, project.rigs[0].sensors["side"].pose_on_rig)
    poses = items["/people/segments/pose"][0]
    expected = np.array([geometry(p[:3, 3], origin, axes) for p in poses])
    np.testing.assert_allclose(items["/people/segments/side/range"][0], expected[:, 0],
                               rtol=1e-12)
    np.testing.assert_allclose(items["/people/segments/side/azimuth"][0], expected[:, 1],
                               atol=1e-9)
    np.testing.assert_allclose(items["/people/segments/side/elevation"][0], expected[:, 2],
                               atol=1e-9)
    # The built-in radar's are unchanged beside them.
    assert not np.allclose(items["/people/segments/radar_range"][0], expected[:, 0])


def test_a_radar_scene_is_the_named_radar_and_its_own_rig() -> None:
    from simcore.scene.snapshot import take_snapshot
    from simcore.sensors.radar.scene import RadarScene

    base = load_project(example_path("point_targets"))
    project = with_rigs(base, Rig(name="cart", pose=SIDE_POSE,
                                  sensors={"side": named_sensor(base.rig.radar)}))
    snap = take_snapshot(project, 0.3)
    assert snap.sensor_rigs == {"tof": "rig", "radar": "rig", "side": "cart"}
    side = RadarScene.from_project(project, snap, "side")
    assert side.radar is snap.sensors["side"] and side.rig is snap.rigs["cart"]
    assert side.snapshot is snap and side.objects is project.objects
    builtin = RadarScene.from_project(project, snap)
    assert builtin.radar is snap.sensors["radar"] and builtin.rig is snap.rigs["rig"]
    with pytest.raises(KeyError, match="no sensor 'nothing'"):
        RadarScene.from_project(project, snap, "nothing")


def test_bench_rigs_reports_both_variants_from_one_run() -> None:
    from simcore.bench import rig_variants

    result = rig_variants(example_path("wall"), frames=1)
    assert result["one_rig"]["sensors"] == 2 and result["two_rigs"]["sensors"] == 4
    assert "tof" in result["two_rigs"]["stages_ms"]   # a still wall: no render is timed
    assert result["time_ratio"] == pytest.approx(
        result["two_rigs"]["frame_ms_median"] / result["one_rig"]["frame_ms_median"])
    assert result["plain_two_rigs"]["sensors"] == 4
    assert result["plain_time_ratio"] == pytest.approx(
        result["plain_two_rigs"]["frame_ms_median"]
        / result["plain_one_rig"]["frame_ms_median"])
