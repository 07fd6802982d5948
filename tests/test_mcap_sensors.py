"""MCAP topics, TF frames and stamps of several named sensors on several rigs (#30).

The frames here are built by hand in the layout the engine writes (``/<sensor>/...`` items,
``/<sensor>/captured`` and ``/<sensor>/time`` for a sensor slower than the timeline), so
the known answers are the configured poses and timing, not the simulator's output:

* rig ``robot_a`` (the project's first rig) at (1, 2, 0.5) m turned 90° about z, with the
  built-in ``tof`` and ``radar``;
* rig ``robot_b`` at (5, −1, 0) m turned −135° about z, moving at (0.4, 0, 0) m/s, with
  ``b_tof`` (trigger offset 20 ms) and ``b_radar`` (half the timeline's rate, 30 ms
  offset).
"""

from __future__ import annotations

import math
from collections import defaultdict
from pathlib import Path
from typing import Any

import h5py
import numpy as np
import pytest
from mcap.reader import make_reader
from mcap_ros2.decoder import DecoderFactory

from simcore.cli import main
from simcore.dsp.detections import DETECTION_DTYPE
from simcore.dsp.processing import static_axes_items
from simcore.io.mcap_writer import McapWriter
from simcore.io.ros2_messages import (
    TOPIC_TYPES,
    RigDescription,
    cloud_array,
    frame_messages,
    image_array,
    transform_matrix,
)
from simcore.scene.model import NamedRadar, NamedTof, Project, Rig, SensorRig, Timeline
from simcore.scene.motion import Motion, Pose
from simcore.scene.project_io import project_to_json
from simcore.scene.radar_config import RadarConfig
from simcore.scene.tof_config import TofCameraConfig

RATE_HZ = 10.0
N_FRAMES = 6
CHIRPS, SAMPLES = 4, 8
#: Optical frame (x right, y down, z forward) → sensor body frame (x forward, y left, z up).
OPTICAL = np.array([[0.0, 0.0, 1.0, 0.0], [-1.0, 0.0, 0.0, 0.0], [0.0, -1.0, 0.0, 0.0],
                    [0.0, 0.0, 0.0, 1.0]])
B_VELOCITY = np.array([0.4, 0.0, 0.0])
OFFSETS = {"tof": 0.0, "radar": 0.0, "b_tof": 0.02, "b_radar": 0.03}
DIVIDERS = {"tof": 1, "radar": 1, "b_tof": 1, "b_radar": 2}
RIG_OF = {"tof": "robot_a", "radar": "robot_a", "b_tof": "robot_b", "b_radar": "robot_b"}


def rot_z(deg: float) -> np.ndarray:
    c, s = math.cos(math.radians(deg)), math.sin(math.radians(deg))
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def rot_y(deg: float) -> np.ndarray:
    c, s = math.cos(math.radians(deg)), math.sin(math.radians(deg))
    return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])


def transform(r: np.ndarray, t: tuple[float, float, float]) -> np.ndarray:
    m = np.eye(4)
    m[:3, :3], m[:3, 3] = r, t
    return m


def world_from_rig(rig: str, t: float) -> np.ndarray:
    """The rigs' poses, written out from their configuration."""
    if rig == "robot_a":
        return transform(rot_z(90.0), (1.0, 2.0, 0.5))
    return transform(rot_z(-135.0), tuple(np.array([5.0, -1.0, 0.0]) + B_VELOCITY * t))


#: Each sensor's optical frame → its rig (pose on the rig, then optical → body).
RIG_FROM_OPTICAL = {
    "tof": transform(np.eye(3), (0.1, 0.0, 0.2)) @ OPTICAL,
    "radar": transform(rot_z(30.0), (0.1, 0.05, 0.2)) @ OPTICAL,
    "b_tof": transform(rot_y(10.0), (0.2, 0.1, 0.3)) @ OPTICAL,
    "b_radar": transform(rot_z(180.0), (-0.3, 0.0, 0.25)) @ OPTICAL,
}


def two_rig_project() -> Project:
    small_tof = {"width": 8, "height": 6}
    radar = {"chirps_per_frame": CHIRPS, "samples_per_chirp": SAMPLES}
    rig_a = SensorRig(
        name="robot_a", pose=Pose(position_m=(1, 2, 0.5), rotation_deg=(0, 0, 90)),
        tof=TofCameraConfig(**small_tof, pose_on_rig=Pose(position_m=(0.1, 0, 0.2))),
        radar=RadarConfig(**radar, pose_on_rig=Pose(position_m=(0.1, 0.05, 0.2),
                                                    rotation_deg=(0, 0, 30))))
    rig_b = Rig(
        name="robot_b", pose=Pose(position_m=(5, -1, 0), rotation_deg=(0, 0, -135)),
        motion=Motion(velocity_mps=tuple(B_VELOCITY)),
        sensors={
            "b_tof": NamedTof(**small_tof, trigger_offset_s=0.02,
                              pose_on_rig=Pose(position_m=(0.2, 0.1, 0.3),
                                               rotation_deg=(0, 10, 0))),
            "b_radar": NamedRadar(**radar, frame_rate_hz=RATE_HZ / 2, trigger_offset_s=0.03,
                                  pose_on_rig=Pose(position_m=(-0.3, 0, 0.25),
                                                   rotation_deg=(0, 0, 180))),
        })
    return Project(timeline=Timeline(frame_rate_hz=RATE_HZ, duration_s=N_FRAMES / RATE_HZ),
                   rig=rig_a, rigs=[rig_b])


def capture_time(name: str, k: int) -> float | None:
    """When sensor ``name`` captures in frame ``k`` (None: it does not)."""
    return None if k % DIVIDERS[name] else k / RATE_HZ + OFFSETS[name]


def sensor_data(project: Project, name: str, k: int) -> dict[str, Any]:
    """Distinct, recognisable data of sensor ``name`` in frame ``k``."""
    cfg = project.sensor_config(name)
    seed = 100 * k + sum(map(ord, name))
    rng = np.random.default_rng(seed)
    if isinstance(cfg, TofCameraConfig):
        depth = rng.uniform(0.5, 4.0, (cfg.height, cfg.width)).astype(np.float32)
        depth[0, :3] = 0.0  # invalid pixels: not in the cloud
        return {"depth": (depth, "m"),
                "amplitude": (rng.uniform(0, 100, depth.shape).astype(np.float32), "DN")}
    assert isinstance(cfg, RadarConfig)
    axes = static_axes_items(cfg, project.dsp, group="radar")
    n_r = len(next(v for p, v in axes.items() if p.endswith("range_axis"))[0])
    n_v = len(next(v for p, v in axes.items() if p.endswith("velocity_axis"))[0])
    channels = len(cfg.tx) * len(cfg.rx)
    return {"adc": (rng.normal(size=(CHIRPS, channels, SAMPLES)).astype(np.float32), "V"),
            "chirp_start_time": (k / RATE_HZ + np.arange(CHIRPS * len(cfg.tx)).reshape(
                CHIRPS, len(cfg.tx)) * cfg.chirp_repetition_time_s, "s"),
            "range_doppler": (rng.normal(size=(n_v, n_r)).astype(np.float32), "dB")}


def detections(name: str, k: int) -> np.ndarray:
    rows = np.zeros(k % 3 + 1, dtype=DETECTION_DTYPE)
    rows["frame"] = k
    rows["x"] = np.arange(len(rows)) + 1.0
    rows["snr_db"] = 20.0 + len(name)
    return rows


def frame_items(project: Project, k: int, *, flags: bool) -> dict[str, Any]:
    """Frame ``k`` as the engine gives it: a sensor that does not capture has no data.

    ``flags``: also ``/poses/rigs`` and the ``/<sensor>/captured`` and ``/<sensor>/time``
    items of the sensors with their own timing (otherwise the writer finds the rigs' poses
    and the timing from the project).
    """
    items: dict[str, Any] = {"/time": (np.float64(k / RATE_HZ), "s"),
                             "/poses/rig": (world_from_rig("robot_a", k / RATE_HZ), "m"),
                             "/poses/objects": (np.zeros((0, 4, 4)), "m")}
    if flags:  # the engine's: every rig's pose, project order
        items["/poses/rigs"] = (np.stack([world_from_rig(r, k / RATE_HZ)
                                          for r in ("robot_a", "robot_b")]), "m")
    for name in OFFSETS:
        t = capture_time(name, k)
        if flags and (DIVIDERS[name] > 1 or OFFSETS[name]):
            items[f"/{name}/captured"] = (np.bool_(t is not None), "1")
            items[f"/{name}/time"] = (np.float64(np.nan if t is None else t), "s")
        if t is not None:
            items.update({f"/{name}/{key}": v for key, v in sensor_data(project, name,
                                                                         k).items()})
        elif flags:  # the engine keeps one frame axis: zeros where it did not capture
            items.update({f"/{name}/{key}": (np.zeros_like(a), unit) for key, (a, unit)
                          in sensor_data(project, name, k).items()})
    return items


def frame_tables(k: int, *, flags: bool = False) -> dict[str, np.ndarray]:
    """The radars' detection rows (with ``flags``, the engine's: none where it did not
    capture)."""
    return {f"/{n}/detections": detections(n, k) if capture_time(n, k) is not None
            else detections(n, k)[:0] for n in ("radar", "b_radar")
            if flags or capture_time(n, k) is not None}


def read_mcap(path: Path) -> dict[str, list[tuple[int, Any]]]:
    """topic → [(log time ns, decoded message)], in file order."""
    out: dict[str, list[tuple[int, Any]]] = defaultdict(list)
    with open(path, "rb") as f:
        reader = make_reader(f, decoder_factories=[DecoderFactory()])
        for _, channel, message, msg in reader.iter_decoded_messages():
            out[channel.topic].append((message.log_time, msg))
    return out


def _stamp(msg: Any) -> int:
    return msg.header.stamp.sec * 10**9 + msg.header.stamp.nanosec


def ns(t: float) -> int:
    return int(round(t * 1e9))


def write_mcap(path: Path, *, flags: bool) -> Project:
    project = two_rig_project()
    with McapWriter(path, project_json=project_to_json(project), seed=1) as writer:
        static: dict[str, Any] = {}
        for name in ("radar", "b_radar"):
            cfg = project.sensor_config(name)
            assert isinstance(cfg, RadarConfig)
            for p, v in static_axes_items(cfg, project.dsp, group="radar").items():
                static[f"/{name}/{p.rsplit('/', 1)[-1]}"] = v
        writer.write_static(static)
        for k in range(N_FRAMES):
            writer.write_frame(k, frame_items(project, k, flags=flags),
                               frame_tables(k, flags=flags))
    return project


Recording = tuple[Project, dict[str, list[tuple[int, Any]]]]


@pytest.fixture(scope="module", params=[True, False], ids=["captured-items", "from-timing"])
def recording(request: pytest.FixtureRequest, tmp_path_factory: pytest.TempPathFactory
              ) -> Recording:
    path = tmp_path_factory.mktemp("sensors") / "two_rigs.mcap"
    project = write_mcap(path, flags=request.param)
    return project, read_mcap(path)


def test_topics_per_sensor_built_in_names_unchanged(recording: Recording) -> None:
    _, topics = recording
    expected = {"/tf", *(t for t in TOPIC_TYPES if t.startswith(("/tof/", "/radar/")))}
    for name, suffixes in (("b_tof", ("depth", "amplitude", "camera_info", "points")),
                           ("b_radar", ("detections", "adc", "range_doppler"))):
        expected |= {f"/{name}/{s}" for s in suffixes}
    assert set(topics) == expected


def test_each_sensor_stamped_at_its_capture_time_half_rate_has_half(recording: Recording) -> None:
    _, topics = recording
    for topic, messages in topics.items():
        if topic == "/tf":
            assert [t for t, _ in messages] == [ns(k / RATE_HZ) for k in range(N_FRAMES)]
            continue
        name = topic.split("/")[1]
        expected = [ns(t) for k in range(N_FRAMES) if (t := capture_time(name, k)) is not None]
        assert [t for t, _ in messages] == expected, topic
        assert [_stamp(m) for _, m in messages] == expected, topic
        assert all(m.header.frame_id == name for _, m in messages), topic
    assert len(topics["/b_radar/adc"]) == N_FRAMES // 2
    assert len(topics["/radar/adc"]) == N_FRAMES


def test_tf_tree_equals_the_configured_poses(recording: Recording) -> None:
    _, topics = recording
    for k, (_, msg) in enumerate(topics["/tf"]):
        tf: dict[tuple[str, str, int], np.ndarray] = {
            (t.header.frame_id, t.child_frame_id, _stamp(t)): transform_matrix(t.transform)
            for t in msg.transforms}
        t_k = k / RATE_HZ
        for rig in ("robot_a", "robot_b"):
            np.testing.assert_allclose(tf[("world", rig, ns(t_k))], world_from_rig(rig, t_k),
                                       atol=1e-9)
        for name, expected in RIG_FROM_OPTICAL.items():
            np.testing.assert_allclose(tf[(RIG_OF[name], name, ns(t_k))], expected, atol=1e-9)
        # The moving rig also at its sensors' capture times (exact TF lookups there).
        for name in ("b_tof", "b_radar"):
            t = capture_time(name, k)
            if t is not None:
                np.testing.assert_allclose(tf[("world", "robot_b", ns(t))],
                                           world_from_rig("robot_b", t), atol=1e-9)
        assert len(tf) == 2 + 4 + (2 if k % 2 == 0 else 1)


def test_payloads_are_each_sensors_own_data(recording: Recording) -> None:
    project, topics = recording
    for name in ("tof", "b_tof"):
        intr = project.sensor_config(name).intrinsics()  # type: ignore[attr-defined]
        for k, (_, msg) in enumerate(topics[f"/{name}/depth"]):
            depth = sensor_data(project, name, k)["depth"][0]
            np.testing.assert_array_equal(image_array(msg), depth)
            info = topics[f"/{name}/camera_info"][k][1]
            assert (info.width, info.height) == (8, 6)
            assert info.k[0] == pytest.approx(intr.fx) and info.k[2] == pytest.approx(
                intr.cx - 0.5)
            assert cloud_array(topics[f"/{name}/points"][k][1]).size == np.count_nonzero(depth)
    for name in ("radar", "b_radar"):
        captured = [k for k in range(N_FRAMES) if capture_time(name, k) is not None]
        cfg = project.sensor_config(name)
        assert isinstance(cfg, RadarConfig)
        for (_, cube), (_, cloud), (_, rd), k in zip(
                topics[f"/{name}/adc"], topics[f"/{name}/detections"],
                topics[f"/{name}/range_doppler"], captured, strict=True):
            data = sensor_data(project, name, k)
            np.testing.assert_array_equal(
                np.frombuffer(bytes(cube.data), "<f4").reshape(cube.chirps, cube.channels,
                                                               cube.samples), data["adc"][0])
            assert cube.n_rx == len(cfg.rx) and cube.bandwidth_hz == cfg.bandwidth_hz
            rows = detections(name, k)
            points = cloud_array(cloud)
            np.testing.assert_array_equal(points["x"], rows["x"])
            np.testing.assert_array_equal(points["snr"], rows["snr_db"])
            np.testing.assert_array_equal(
                np.frombuffer(bytes(rd.data), "<f4").reshape(rd.doppler_bins, rd.range_bins),
                data["range_doppler"][0])
            assert len(rd.range_axis) == rd.range_bins


def test_frame_messages_with_and_without_timing_items_agree() -> None:
    project = two_rig_project()
    rig = RigDescription.of(project, {})
    for k in range(N_FRAMES):
        a = frame_messages(rig, frame_items(project, k, flags=True),
                           frame_tables(k, flags=True))
        b = frame_messages(rig, frame_items(project, k, flags=False), frame_tables(k),
                           index=k)
        assert [(m.topic, m.stamp_ns) for m in a] == [(m.topic, m.stamp_ns) for m in b]


def write_hdf5(path: Path, project: Project, *, per_capture: bool) -> None:
    """A dataset in the layout of several sensors: a row per frame (zeros where a sensor
    did not capture, as the engine writes), or b_radar's arrays a row per capture."""
    with h5py.File(path, "w") as f:
        meta = f.create_group("meta")
        meta.attrs.update({"project_json": project_to_json(project), "n_frames": N_FRAMES,
                           "seed": 1})
        frames = [frame_items(project, k, flags=True) for k in range(N_FRAMES)]
        paths = sorted({p for items in frames for p in items})
        for p in paths:
            rows = [items[p][0] for k, items in enumerate(frames) if p in items and not (
                per_capture and p.startswith("/b_radar/") and not p.endswith(
                    ("/captured", "/time")) and capture_time("b_radar", k) is None)]
            ds = f.create_dataset(p, data=np.stack(rows))
            ds.attrs.update({"per_frame": True, "unit": frames[0].get(p, ("", ""))[1]})
        for name in ("radar", "b_radar"):
            cfg = project.sensor_config(name)
            assert isinstance(cfg, RadarConfig)
            for p, (v, unit) in static_axes_items(cfg, project.dsp, group="radar").items():
                f.create_dataset(f"/{name}/{p.rsplit('/', 1)[-1]}", data=v).attrs["unit"] = unit
            table = np.concatenate([detections(name, k) for k in range(N_FRAMES)
                                    if capture_time(name, k) is not None])
            f.create_dataset(f"/{name}/detections", data=table).attrs["table"] = True


@pytest.mark.parametrize("per_capture", [False, True])
def test_convert_hdf5_of_several_sensors(tmp_path: Path, per_capture: bool) -> None:
    project = two_rig_project()
    h5, mcap = tmp_path / "run.h5", tmp_path / "run.mcap"
    write_hdf5(h5, project, per_capture=per_capture)
    with h5py.File(h5) as f:
        assert f["b_radar/adc"].shape[0] == (N_FRAMES // 2 if per_capture else N_FRAMES)
    assert main(["convert", str(h5), "--to", str(mcap)]) == 0
    direct = tmp_path / "direct.mcap"
    write_mcap(direct, flags=True)
    got, want = read_mcap(mcap), read_mcap(direct)
    assert set(got) == set(want)
    for topic in want:
        assert [t for t, _ in got[topic]] == [t for t, _ in want[topic]], topic
    for (_, a), (_, b) in zip(got["/b_radar/adc"], want["/b_radar/adc"], strict=True):
        assert bytes(a.data) == bytes(b.data)
    for (_, a), (_, b) in zip(got["/b_radar/detections"], want["/b_radar/detections"],
                              strict=True):
        assert bytes(a.data) == bytes(b.data)


class _FakeFrame:
    def __init__(self, project: Project, k: int):
        self.index, self.time_s = k, k / RATE_HZ
        self._items = frame_items(project, k, flags=True)
        self._tables = frame_tables(k, flags=True)

    def hdf5_items(self) -> dict[str, Any]:
        return self._items

    def table_rows(self) -> dict[str, np.ndarray]:
        return self._tables


class _FakeSimulator:
    """The engine's frames of the two-rig project, built by hand (see frame_items)."""

    def __init__(self, project: Project, **_: Any):
        self.project, self.n_frames = project, N_FRAMES

    def __enter__(self) -> _FakeSimulator:
        return self

    def __exit__(self, *exc: object) -> None:
        pass

    def static_items(self) -> dict[str, Any]:
        return {}

    def frame(self, k: int) -> _FakeFrame:
        return _FakeFrame(self.project, k)


def record_channels(monkeypatch: pytest.MonkeyPatch
                    ) -> tuple[list[tuple[str, str, int]], dict[str, str]]:
    """Replace the Foxglove SDK's channels by recorders: (topic, type, log time) of every
    message logged, and the type of every topic advertised."""
    foxglove = pytest.importorskip("foxglove")
    logged: list[tuple[str, str, int]] = []
    advertised: dict[str, str] = {}

    class RecordingChannel:
        def __init__(self, topic: str, *, message_encoding: str, schema: Any):
            assert message_encoding == "cdr" and schema.encoding == "ros2msg"
            self.topic = topic
            advertised[topic] = schema.name

        def log(self, data: bytes, *, log_time: int) -> None:
            logged.append((self.topic, advertised[self.topic], log_time))

        def close(self) -> None:
            pass

    monkeypatch.setattr(foxglove, "Channel", RecordingChannel)
    return logged, advertised


def test_foxglove_stream_publishes_every_sensor_at_its_capture_time(
        monkeypatch: pytest.MonkeyPatch) -> None:
    from simcore.io import live

    logged, advertised = record_channels(monkeypatch)
    monkeypatch.setattr(live, "Simulator", _FakeSimulator)
    project = two_rig_project()
    report = live.serve(project, port=0, wait_for_client=False, realtime=False, linger_s=0.0)
    assert report.frames_published == N_FRAMES
    assert advertised == RigDescription.of(project, {}).topics()
    by_topic: dict[str, list[int]] = defaultdict(list)
    for topic, _, log_time in logged:
        by_topic[topic].append(log_time)
    assert by_topic["/tf"] == [ns(k / RATE_HZ) for k in range(N_FRAMES)]
    for topic in advertised:
        if topic != "/tf":
            name = topic.split("/")[1]
            assert by_topic[topic] == [ns(t) for k in range(N_FRAMES)
                                       if (t := capture_time(name, k)) is not None], topic
    assert len(by_topic["/b_radar/adc"]) == N_FRAMES // 2


# --- The real engine: a run of two rigs to HDF5 and to MCAP --------------------------------

E_FRAMES = 4


def engine_project() -> Project:
    """The wall example with a second, moving rig: b_tof 20 ms late, b_radar at half rate
    30 ms late; small ToF cameras keep the run short."""
    from simcore.resources import example_path
    from simcore.scene import load_project

    base = load_project(example_path("wall"))
    tof = {"width": 32, "height": 24}
    radar = {k: v for k, v in base.rig.radar.model_dump().items()
             if k not in ("kind", "frame_rate_hz", "trigger_offset_s")}
    rig_a = base.rig.model_copy(update={"tof": base.rig.tof.model_copy(update=tof)})
    rig_b = Rig(name="robot_b",
                pose=Pose(position_m=(0.5, 1.0, 1.0), rotation_deg=(0, 0, -20)),
                motion=Motion(velocity_mps=(0.3, 0.0, 0.0)),
                sensors={"b_tof": NamedTof(**tof, trigger_offset_s=0.02,
                                           pose_on_rig=Pose(position_m=(0.1, 0.0, 0.0))),
                         "b_radar": NamedRadar(**radar, frame_rate_hz=RATE_HZ / 2,
                                               trigger_offset_s=0.03)})
    return Project.model_validate({
        **base.model_dump(), "rig": rig_a.model_dump(), "rigs": [rig_b.model_dump()],
        "timeline": {"frame_rate_hz": RATE_HZ, "duration_s": E_FRAMES / RATE_HZ}})


@pytest.fixture(scope="module")
def engine_run(tmp_path_factory: pytest.TempPathFactory) -> tuple[Project, Path, Path, Path]:
    from simcore.scene.project_io import save_project

    tmp = tmp_path_factory.mktemp("engine")
    project = engine_project()
    save_project(project, tmp / "two.json")
    h5, converted, direct = tmp / "run.h5", tmp / "conv.mcap", tmp / "run.mcap"
    for out in (h5, direct):
        assert main(["run", str(tmp / "two.json"), "--out", str(out), "--quiet"]) == 0
    assert main(["convert", str(h5), "--to", str(converted)]) == 0
    return project, h5, converted, direct


def test_engine_run_topics_stamps_and_tf(engine_run: tuple[Project, Path, Path, Path]
                                         ) -> None:
    project, h5, converted, direct = engine_run
    topics = read_mcap(converted)
    with h5py.File(h5) as f:
        times = f["time"][()]
        assert {t.split("/")[1] for t in topics if t != "/tf"} == {
            "tof", "radar", "b_tof", "b_radar"}
        for name, n_expected in (("tof", 4), ("radar", 4), ("b_tof", 4), ("b_radar", 2)):
            expected = [ns(k / RATE_HZ + (0.03 if name == "b_radar" else
                                           0.02 if name == "b_tof" else 0.0))
                        for k in range(E_FRAMES) if name != "b_radar" or k % 2 == 0]
            assert len(expected) == n_expected
            for topic in (t for t in topics if t.startswith(f"/{name}/")):
                assert [t for t, _ in topics[topic]] == expected, topic
                assert [_stamp(m) for _, m in topics[topic]] == expected, topic
            if name in ("b_tof", "b_radar"):  # the dataset's capture times agree
                cap = f[f"{name}/captured"][()]
                assert [ns(t) for t in f[f"{name}/time"][()][cap]] == expected
        captured = np.flatnonzero(f["b_radar/captured"][()])
        for (_, cube), k in zip(topics["/b_radar/adc"], captured, strict=True):
            np.testing.assert_array_equal(
                np.frombuffer(bytes(cube.data), "<f4").reshape(f["b_radar/adc"].shape[1:]),
                f["b_radar/adc"][k])
        rigs = f["poses/rigs"][()]
        for k, (_, msg) in enumerate(topics["/tf"]):
            assert _stamp(msg.transforms[0]) == ns(times[k])
            tf = {(t.header.frame_id, t.child_frame_id): transform_matrix(t.transform)
                  for t in msg.transforms if _stamp(t) == ns(times[k])}
            b = transform(rot_z(-20.0), (0.5 + 0.3 * times[k], 1.0, 1.0))  # configured
            np.testing.assert_allclose(tf[("world", "robot_b")], b, atol=1e-9)
            np.testing.assert_allclose(tf[("world", "robot_b")], rigs[k, 1], atol=1e-9)
            np.testing.assert_allclose(tf[("world", "rig")], rigs[k, 0], atol=1e-9)
            np.testing.assert_allclose(tf[("robot_b", "b_tof")],
                                       transform(np.eye(3), (0.1, 0.0, 0.0)) @ OPTICAL,
                                       atol=1e-9)
            np.testing.assert_allclose(tf[("rig", "radar")],
                                       project.rig.radar.pose_on_rig.matrix() @ OPTICAL,
                                       atol=1e-9)
    # A run straight to MCAP writes the same messages as the conversion of its HDF5 file.
    again = read_mcap(direct)
    assert set(again) == set(topics)
    for topic in topics:
        assert [t for t, _ in again[topic]] == [t for t, _ in topics[topic]], topic
    for (_, a), (_, b) in zip(again["/b_radar/adc"], topics["/b_radar/adc"], strict=True):
        assert bytes(a.data) == bytes(b.data)


def test_engine_run_products_per_radar(engine_run: tuple[Project, Path, Path, Path]) -> None:
    _, h5, _, _ = engine_run
    assert main(["products", str(h5)]) == 0
    with h5py.File(h5) as f:
        for name, frames in (("radar", np.arange(E_FRAMES)), ("b_radar", np.arange(0, 4, 2))):
            t = f[f"{name}/vitals/time"][()]  # one per frame, NaN where it did not capture
            np.testing.assert_array_equal(np.flatnonzero(np.isfinite(t)), frames)
            np.testing.assert_allclose(t[frames], f[f"{name}/chirp_start_time"][()][
                frames, :, 0].mean(axis=1))
            assert f[f"{name}/spectrogram/power"].shape[0] == len(frames)
    from simcore.io.reader import open_dataset

    ds = open_dataset(h5)  # the reader puts the per-radar products on the frame axis
    try:
        assert ds["b_radar_vitals_time"].shape == (E_FRAMES,)
    finally:
        ds.close()


def test_engine_live_stream_equals_the_recording(
        engine_run: tuple[Project, Path, Path, Path], monkeypatch: pytest.MonkeyPatch) -> None:
    from simcore.io import live

    project, _, converted, _ = engine_run
    logged, advertised = record_channels(monkeypatch)
    report = live.serve(project, port=0, wait_for_client=False, realtime=False, linger_s=0.0)
    assert report.frames_published == E_FRAMES
    recording = read_mcap(converted)
    assert set(advertised) == set(recording)
    by_topic: dict[str, list[int]] = defaultdict(list)
    for topic, _, log_time in logged:
        by_topic[topic].append(log_time)
    assert by_topic == {topic: [t for t, _ in msgs] for topic, msgs in recording.items()}


@pytest.mark.parametrize(("rig_name", "sensor_name"), [("front", "front"), ("world", "b_tof"),
                                                       ("robot_b", "world")])
def test_colliding_tf_frames_are_one_line_errors(
        tmp_path: Path, capsys: pytest.CaptureFixture[str], rig_name: str,
        sensor_name: str) -> None:
    """A rig and a sensor of one name, or either named ``world``, is refused on loading."""
    import json

    from simcore.resources import example_path
    from simcore.scene import load_project

    tof = NamedTof(width=8, height=6).model_dump()
    rigs = [{"name": rig_name, "sensors": {"b_tof": tof}}]
    if sensor_name != "b_tof":
        rigs.append({"name": "b", "sensors": {sensor_name: tof}})
    data = {**load_project(example_path("wall")).model_dump(mode="json"), "rigs": rigs}
    (tmp_path / "p.json").write_text(json.dumps(data))
    out = tmp_path / "p.mcap"
    assert main(["run", str(tmp_path / "p.json"), "--out", str(out), "--frames", "1",
                 "--quiet"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("tofradar: error: ") and "frame" in err[0]
    assert repr(rig_name if rig_name != "robot_b" else sensor_name) in err[0]
    assert not out.exists()


def test_each_radars_interference_to_noise_ratio_reaches_its_adc_message(
        tmp_path: Path) -> None:
    """The two facing radars: every RadarCube carries the frame's ``/<radar>/inr_db``."""
    import h5py

    from simcore.resources import example_path
    from simcore.sensors.radar.interference import INR_NONE_DB

    example = example_path("two_radars_facing")
    h5, mcap = tmp_path / "r.h5", tmp_path / "r.mcap"
    for out in (h5, mcap):
        assert main(["run", str(example), "--out", str(out), "--frames", "2",
                     "--quiet"]) == 0
    with h5py.File(h5, "r") as f:
        expected = {name: f[f"/{name}/inr_db"][:] for name in ("radar", "radar_b")}
    recording = read_mcap(mcap)
    for name, inr in expected.items():
        got = [m.inr_db for _, m in recording[f"/{name}/adc"]]
        np.testing.assert_allclose(got, inr, rtol=0, atol=1e-9)
        assert np.all(inr > INR_NONE_DB)      # the other radar is heard in every frame
