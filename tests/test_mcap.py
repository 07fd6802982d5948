"""MCAP recordings: every topic read back with the mcap reader and ROS 2 (CDR) decoding."""

from __future__ import annotations

from collections import defaultdict
from pathlib import Path

import h5py
import numpy as np
import pytest
from mcap.reader import make_reader
from mcap_ros2.decoder import DecoderFactory

from simcore.cli import main
from simcore.io.ros2_messages import TOPIC_TYPES, cloud_array, image_array, transform_matrix
from simcore.resources import example_path
from simcore.scene import load_project
from simcore.scene.snapshot import take_snapshot

N_FRAMES = 3


def read_mcap(path: Path) -> dict[str, list[tuple[int, object]]]:
    """topic → [(log time ns, decoded message)], in file order."""
    out: dict[str, list[tuple[int, object]]] = defaultdict(list)
    with open(path, "rb") as f:
        reader = make_reader(f, decoder_factories=[DecoderFactory()])
        for schema, channel, message, msg in reader.iter_decoded_messages():
            assert schema.encoding == "ros2msg" and channel.message_encoding == "cdr"
            assert schema.name == TOPIC_TYPES[channel.topic]
            out[channel.topic].append((message.log_time, msg))
    return out


def _stamp(msg) -> int:
    return msg.header.stamp.sec * 10**9 + msg.header.stamp.nanosec


@pytest.fixture(scope="module")
def office_rgb(tmp_path_factory) -> tuple[Path, Path]:
    tmp = tmp_path_factory.mktemp("mcap")
    h5, mcap = tmp / "run.h5", tmp / "run.mcap"
    assert main(["run", str(example_path("office_rgb")), "--out", str(h5), "--frames",
                 str(N_FRAMES), "--quiet"]) == 0
    assert main(["convert", str(h5), "--to", str(mcap)]) == 0
    return h5, mcap


def test_every_topic_has_one_message_per_frame_all_stamped_with_the_frame_time(office_rgb):
    h5, mcap = office_rgb
    topics = read_mcap(mcap)
    assert set(topics) == set(TOPIC_TYPES)
    with h5py.File(h5) as f:
        times_ns = np.round(f["time"][:] * 1e9).astype(np.int64)
    for topic, messages in topics.items():
        assert len(messages) == N_FRAMES, topic
        log_times = [t for t, _ in messages]
        np.testing.assert_array_equal(log_times, times_ns, err_msg=topic)
        if topic != "/tf":
            np.testing.assert_array_equal([_stamp(m) for _, m in messages], times_ns)
    for _, msg in topics["/tf"]:
        assert {_stamp(t) for t in msg.transforms} <= set(times_ns.tolist())


def test_point_clouds_images_and_radar_data_equal_the_hdf5_dataset(office_rgb):
    h5, mcap = office_rgb
    topics = read_mcap(mcap)
    with h5py.File(h5) as f:
        det = f["radar/detections"][:]
        for k in range(N_FRAMES):
            rows = det[det["frame"] == k]
            points = cloud_array(topics["/radar/detections"][k][1])
            assert len(rows) > 0
            for field, column in (("x", "x"), ("y", "y"), ("z", "z"), ("velocity", "velocity"),
                                  ("snr", "snr_db"), ("label", "object_id"),
                                  ("power_fraction", "power_fraction")):
                np.testing.assert_array_equal(points[field], rows[column])
            assert 22 in set(points["label"])  # the corner reflector behind the paper box

            depth = f["tof/depth"][k]
            np.testing.assert_array_equal(image_array(topics["/tof/depth"][k][1]), depth)
            np.testing.assert_array_equal(image_array(topics["/tof/amplitude"][k][1]),
                                          f["tof/amplitude"][k])
            np.testing.assert_array_equal(image_array(topics["/rgb/image"][k][1]),
                                          f["rgb/image"][k])
            # Back-project the depth with the CameraInfo's K (ROS pixel centres).
            info = topics["/tof/camera_info"][k][1]
            fx, cx, fy, cy = info.k[0], info.k[2], info.k[4], info.k[5]
            rows_i, cols_i = np.nonzero(depth > 0)
            rays = np.stack([(cols_i - cx) / fx, (rows_i - cy) / fy, np.ones(cols_i.size)], 1)
            expected = rays / np.linalg.norm(rays, axis=1, keepdims=True) * depth[
                rows_i, cols_i][:, None]
            cloud = cloud_array(topics["/tof/points"][k][1])
            got = np.stack([cloud["x"], cloud["y"], cloud["z"]], 1)
            np.testing.assert_allclose(got, expected, atol=1e-5)

            cube = topics["/radar/adc"][k][1]
            adc = f["radar/adc"][k]
            assert (cube.chirps, cube.channels, cube.samples) == adc.shape
            assert cube.complex_iq == np.iscomplexobj(adc)
            data = np.frombuffer(bytes(cube.data), "<f4")
            if cube.complex_iq:
                data = data.view("<c8")
            np.testing.assert_array_equal(data.reshape(adc.shape), adc)
            np.testing.assert_array_equal(np.reshape(cube.chirp_start_time, (cube.chirps, -1)),
                                          f["radar/chirp_start_time"][k])
            rd = topics["/radar/range_doppler"][k][1]
            np.testing.assert_array_equal(
                np.frombuffer(bytes(rd.data), "<f4").reshape(rd.doppler_bins, rd.range_bins),
                f["radar/range_doppler"][k])
            np.testing.assert_array_equal(rd.range_axis, f["radar/range_axis"][:])
            np.testing.assert_array_equal(rd.velocity_axis, f["radar/velocity_axis"][:])


def test_tf_chain_reproduces_the_poses(office_rgb):
    h5, mcap = office_rgb
    topics = read_mcap(mcap)
    with h5py.File(h5) as f:
        project = load_project(example_path("office_rgb"))
        names = list(f["objects/names"].asstr()[:])
        for k in range(N_FRAMES):
            tf = {(t.header.frame_id, t.child_frame_id): transform_matrix(t.transform)
                  for t in topics["/tf"][k][1].transforms}
            world_rig = tf[("world", "rig")]
            np.testing.assert_allclose(world_rig, f["poses/rig"][k], atol=1e-9)
            for i, name in enumerate(names):
                np.testing.assert_allclose(tf[("world", name)], f["poses/objects"][k, i],
                                           atol=1e-9)
            snap = take_snapshot(project, float(f["time"][k]))
            for sensor in ("tof", "radar", "rgb"):
                np.testing.assert_allclose(world_rig @ tf[("rig", sensor)],
                                           snap.sensors[sensor].transform, atol=1e-9)


def test_run_writes_mcap_by_suffix_and_refuses_to_resume_it(tmp_path):
    out = tmp_path / "targets.mcap"
    assert main(["run", str(example_path("point_targets")), "--out", str(out), "--frames", "2",
                 "--quiet"]) == 0
    topics = read_mcap(out)
    assert "/rgb/image" not in topics  # no RGB camera on this rig
    assert all(len(m) == 2 for m in topics.values())
    for _, msg in topics["/radar/detections"]:
        assert sorted(cloud_array(msg)["label"]) == [1, 2, 3]
    assert main(["run", str(example_path("point_targets")), "--out", str(out), "--frames", "2",
                 "--resume", "--quiet"]) == 2


def test_the_reading_example_in_robotics_md_runs(office_rgb, monkeypatch, capsys):
    text = (Path(__file__).resolve().parents[1] / "docs" / "robotics.md").read_text()
    section = text[text.index("### Reading a recording in Python"):]
    code = section[section.index("```python\n") + 10:section.index("```\n", 10)]
    monkeypatch.chdir(office_rgb[1].parent)  # the example reads run.mcap
    exec(compile(code, "robotics.md", "exec"), {})
    assert len(capsys.readouterr().out.splitlines()) == N_FRAMES
