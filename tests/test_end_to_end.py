"""The whole chain on point_targets.json against the scene's geometric truth."""

from __future__ import annotations

import h5py
import numpy as np

from simcore.cli import main
from simcore.pipeline import Simulator
from simcore.resources import example_path
from simcore.scene import load_project
from simcore.scene.snapshot import take_snapshot


def truth(project, t: float) -> list[tuple[float, float, float]]:
    """(range m, azimuth deg, radial velocity m/s) of every corner apex seen by the radar."""
    snap = take_snapshot(project, t)
    radar = snap.sensors["radar"]
    out = []
    for state in snap.objects:
        rel = state.origin - radar.position
        opt = radar.rotation.T @ rel
        rng = float(np.linalg.norm(rel))
        vel = float((state.velocity_mps - radar.velocity_mps) @ rel / rng)
        out.append((rng, float(np.degrees(np.arctan2(opt[0], opt[2]))), vel))
    return out


def test_point_targets_three_detections_at_truth():
    project = load_project(example_path("point_targets"))
    bin_v = project.rig.radar.velocity_resolution_mps
    with Simulator(project) as sim:
        for index in (0, 4):
            frame = sim.frame(index)
            det = frame.outputs["radar"].dsp.detection_records(index)
            assert len(det) == 3, det
            for rng, az, vel in truth(project, frame.time_s):
                k = int(np.argmin(np.abs(det["range"] - rng)))
                assert abs(det["range"][k] - rng) < 0.02
                assert abs(det["azimuth_deg"][k] - az) < 3.0
                assert abs(det["velocity"][k] - vel) < bin_v
    # The scene is what the example promises: the middle corner recedes at 1.0 m/s.
    assert abs(truth(project, 0.0)[1][2] - 1.0) < 1e-9


def test_ten_frame_dataset_layout_units_and_moving_target(tmp_path):
    out = tmp_path / "pt.h5"
    assert main(["run", str(example_path("point_targets")), "--out", str(out), "--frames",
                 "10", "--quiet"]) == 0
    project = load_project(example_path("point_targets"))
    radar, tof = project.rig.radar, project.rig.tof
    n_ch = len(radar.tx) * len(radar.rx)
    expected = {
        "time": ((10,), "s"),
        "poses/rig": ((10, 4, 4), "m"),
        "poses/objects": ((10, 3, 4, 4), "m"),
        "tof/depth": ((10, tof.height, tof.width), "m"),
        "tof/amplitude": ((10, tof.height, tof.width), "DN"),
        "tof/valid": ((10, tof.height, tof.width), "1"),
        "tof/correlation": ((10, 4, tof.height, tof.width), "DN"),
        "tof/gt_range": ((10, tof.height, tof.width), "m"),
        "tof/gt_object_id": ((10, tof.height, tof.width), "1"),
        "radar/adc": ((10, radar.chirps_per_frame, n_ch, radar.samples_per_chirp), "FS"),
    }
    with h5py.File(out) as f:
        for path, (shape, unit) in expected.items():
            assert f[path].shape == shape, path
            assert f[path].attrs["unit"] == unit, path
        assert f["radar/adc"].dtype == np.float32
        assert f["tof/valid"].dtype == bool
        n_r, n_d = f["radar/range_axis"].shape[0], f["radar/velocity_axis"].shape[0]
        n_az = f["radar/azimuth_axis"].shape[0]
        assert f["radar/range_doppler"].shape == (10, n_d, n_r)
        assert f["radar/range_azimuth"].shape == (10, n_az, n_r)
        assert f["radar/range_axis"].attrs["unit"] == "m"
        assert f["radar/velocity_axis"].attrs["unit"] == "m/s"
        assert f["radar/azimuth_axis"].attrs["unit"] == "deg"
        for key in ("format_version", "project_json", "created", "tofradar_version", "seed"):
            assert key in f["meta"].attrs
        det = f["radar/detections"][:]
        times = f["time"][:]
    assert set(det.dtype.names) >= {"frame", "range", "velocity", "azimuth_deg",
                                    "elevation_deg", "x", "y", "z", "snr_db"}
    # The moving corner (middle one, boresight) follows 3.0 m + 1.0 m/s · t frame by frame.
    for index, t in enumerate(times):
        rows = det[det["frame"] == index]
        true_range = truth(project, t)[1][0]
        k = int(np.argmin(np.abs(rows["range"] - true_range)))
        assert abs(rows["range"][k] - true_range) < 0.02, (index, rows["range"], true_range)
        assert abs(rows["velocity"][k] - 1.0) < radar.velocity_resolution_mps


def test_tof_motion_artifacts_switch_in_the_pipeline():
    project = load_project(example_path("office"))
    project.rig.tof.motion_artifacts = False
    with Simulator(project) as sim:
        still = sim.frame(3)
        renders = sim.render_count
        project.rig.tof.motion_artifacts = True
        project.rig.tof.motion_sampling = "renders"
        sim.set_project(project)
        moving = sim.frame(3)
        assert sim.render_count - renders == 3  # three sample renders; the frame's is re-used
    person = moving.outputs["tof"].gt_object_id == project.object_by_name("person").id
    edge = person ^ np.roll(person, 1, axis=1)
    # The walking person's silhouette changes between samples; the still back wall doesn't.
    differs = still.outputs["tof"].depth_m != moving.outputs["tof"].depth_m
    assert differs[edge].mean() > differs[~edge & ~person].mean()
