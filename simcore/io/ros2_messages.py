"""ROS 2 messages of a frame: standard types plus two documented tofradar messages.

One frame becomes one ``/tf`` message, stamped with the frame's simulation time, and one
message per topic of every sensor that captures in the frame, stamped with that sensor's
capture time (``header.stamp``; the MCAP log time is the same). A sensor named ``N`` of a
project's rigs publishes the topics of its kind (:data:`SENSOR_TOPICS`) under ``/N/``, its
messages in frame ``N``; the built-in sensors' topics are:

* ``/tf`` (``tf2_msgs/msg/TFMessage``): world → each rig (frame named after the rig,
  ``rig`` by default) → each of its sensors' optical frames (``tof``, ``radar``, ``rgb``);
  world → each object (frame named after the object).
* ``/tof/depth``, ``/tof/amplitude`` (``sensor_msgs/msg/Image``, 32FC1): distance along the
  pixel ray (m, 0 = invalid) and amplitude (DN), frame ``tof``.
* ``/tof/camera_info`` (``sensor_msgs/msg/CameraInfo``): pinhole, no distortion.
* ``/tof/points`` (``sensor_msgs/msg/PointCloud2``): the valid depth pixels back-projected,
  x, y, z (float32, m, frame ``tof``).
* ``/rgb/image`` (``sensor_msgs/msg/Image``, rgb8) and ``/rgb/camera_info`` when the rig
  has the RGB camera.
* ``/radar/detections`` (``sensor_msgs/msg/PointCloud2``): x, y, z (m), velocity (m/s),
  snr (dB), power_fraction (float32) and label (int32 object id, −1 = noise), frame
  ``radar``.
* ``/radar/adc`` (``tofradar_msgs/msg/RadarCube``): the raw ADC cube
  (``simcore/io/msg/tofradar_msgs/msg/RadarCube.msg``).
* ``/radar/range_doppler`` (``tofradar_msgs/msg/RangeDopplerMap``): the dB map
  (``simcore/io/msg/tofradar_msgs/msg/RangeDopplerMap.msg``).

Messages are built from the items a frame writes to HDF5 (``Frame.hdf5_items()``, its
detection rows and the run's static items), so a run, a conversion of an HDF5 file and the
live stream all produce the same messages. CDR encoding and decoding use
``mcap_ros2`` (no ROS installation).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from functools import cache
from importlib import resources
from typing import Any, NamedTuple

import numpy as np
from numpy.typing import NDArray
from scipy.spatial.transform import Rotation

from simcore.scene.camera import PinholeIntrinsics
from simcore.scene.model import Project, sensor_kind
from simcore.scene.motion import Motion, Pose, make_transform, rigid_state
from simcore.scene.project_io import ProjectError
from simcore.scene.radar_config import RadarConfig
from simcore.scene.snapshot import BODY_FROM_OPTICAL
from simcore.sensors.radar.interference import INR_NONE_DB
from simcore.sensors.schema import schemas

Items = Mapping[str, tuple[NDArray[Any], str]]

WORLD_FRAME = "world"

_STANDARD = {
    "builtin_interfaces/Time": "int32 sec\nuint32 nanosec\n",
    "std_msgs/Header": "builtin_interfaces/Time stamp\nstring frame_id\n",
    "sensor_msgs/Image": (
        "std_msgs/Header header\nuint32 height\nuint32 width\nstring encoding\n"
        "uint8 is_bigendian\nuint32 step\nuint8[] data\n"),
    "sensor_msgs/RegionOfInterest": (
        "uint32 x_offset\nuint32 y_offset\nuint32 height\nuint32 width\nbool do_rectify\n"),
    "sensor_msgs/CameraInfo": (
        "std_msgs/Header header\nuint32 height\nuint32 width\nstring distortion_model\n"
        "float64[] d\nfloat64[9] k\nfloat64[9] r\nfloat64[12] p\nuint32 binning_x\n"
        "uint32 binning_y\nsensor_msgs/RegionOfInterest roi\n"),
    "sensor_msgs/PointField": (
        "uint8 INT8=1\nuint8 UINT8=2\nuint8 INT16=3\nuint8 UINT16=4\nuint8 INT32=5\n"
        "uint8 UINT32=6\nuint8 FLOAT32=7\nuint8 FLOAT64=8\n"
        "string name\nuint32 offset\nuint8 datatype\nuint32 count\n"),
    "sensor_msgs/PointCloud2": (
        "std_msgs/Header header\nuint32 height\nuint32 width\n"
        "sensor_msgs/PointField[] fields\nbool is_bigendian\nuint32 point_step\n"
        "uint32 row_step\nuint8[] data\nbool is_dense\n"),
    "geometry_msgs/Vector3": "float64 x\nfloat64 y\nfloat64 z\n",
    "geometry_msgs/Quaternion": "float64 x\nfloat64 y\nfloat64 z\nfloat64 w\n",
    "geometry_msgs/Transform": (
        "geometry_msgs/Vector3 translation\ngeometry_msgs/Quaternion rotation\n"),
    "geometry_msgs/TransformStamped": (
        "std_msgs/Header header\nstring child_frame_id\ngeometry_msgs/Transform transform\n"),
    "tf2_msgs/TFMessage": "geometry_msgs/TransformStamped[] transforms\n",
}

#: Topics of each sensor kind (from its schema): a sensor named ``N`` publishes
#: ``/N/<suffix>``.
SENSOR_TOPICS: dict[str, dict[str, str]] = {
    kind: schema.topics() for kind, schema in schemas().items()}
TF_TOPIC = "/tf"
TF_TYPE = "tf2_msgs/msg/TFMessage"


def sensor_topics(name: str, kind: str) -> dict[str, str]:
    """Topic → ROS 2 type of the sensor ``name`` of kind ``kind`` (``"tof"``, ...)."""
    return {f"/{name}/{suffix}": datatype for suffix, datatype in SENSOR_TOPICS[kind].items()}


#: ROS 2 type of every topic of the built-in sensors (one of each kind, named after it); a
#: project's
#: own topics are :meth:`RigDescription.topics`.
TOPIC_TYPES = {TF_TOPIC: TF_TYPE, **{topic: datatype for kind in SENSOR_TOPICS
                                     for topic, datatype in sensor_topics(kind, kind).items()}}

_FLOAT32, _INT32 = 7, 5
#: Point layout of ``/radar/detections`` (little-endian, 28 bytes per point).
DETECTION_POINT_DTYPE = np.dtype([("x", "<f4"), ("y", "<f4"), ("z", "<f4"),
                                  ("velocity", "<f4"), ("snr", "<f4"),
                                  ("power_fraction", "<f4"), ("label", "<i4")])
#: Point layout of ``/tof/points`` (little-endian, 12 bytes per point).
TOF_POINT_DTYPE = np.dtype([("x", "<f4"), ("y", "<f4"), ("z", "<f4")])


def _short(datatype: str) -> str:
    """``pkg/msg/Name`` → ``pkg/Name``."""
    pkg, _, name = datatype.partition("/msg/")
    return f"{pkg}/{name}" if name else datatype


def _own_definition(name: str) -> str:
    if name in _STANDARD:
        return _STANDARD[name]
    pkg, msg = name.split("/")
    return (resources.files("simcore.io") / "msg" / pkg / "msg" / f"{msg}.msg").read_text()


def _dependencies(name: str, seen: list[str]) -> None:
    for line in _own_definition(name).splitlines():
        field_type = line.split("#")[0].split()
        if not field_type or "/" not in field_type[0]:
            continue
        dep = field_type[0].split("[")[0]
        if dep not in seen:
            seen.append(dep)
            _dependencies(dep, seen)


@cache
def message_definition(datatype: str) -> str:
    """Full ROS 2 message definition text (``.msg`` with its dependencies, MCAP style).

    Parameters
    ----------
    datatype : str
        ``pkg/msg/Name``, e.g. ``sensor_msgs/msg/Image`` or ``tofradar_msgs/msg/RadarCube``.
    """
    name = _short(datatype)
    deps: list[str] = []
    _dependencies(name, deps)
    parts = [_own_definition(name)]
    for dep in deps:
        parts.append("=" * 80 + f"\nMSG: {dep}\n" + _own_definition(dep))
    return "\n".join(parts)


@cache
def encoder(datatype: str) -> Callable[[Any], bytes]:
    """CDR encoder of a message type (message as nested dicts → bytes)."""
    from mcap_ros2._dynamic import serialize_dynamic

    fn: Callable[[Any], bytes] = serialize_dynamic(datatype, message_definition(datatype))[
        datatype]
    return fn


@cache
def decoder(datatype: str) -> Callable[[bytes], Any]:
    """CDR decoder of a message type (bytes → message object with attributes)."""
    from mcap_ros2._dynamic import generate_dynamic

    fn: Callable[[bytes], Any] = generate_dynamic(datatype, message_definition(datatype))[
        datatype]
    return fn


def stamp_ns(time_s: float) -> int:
    """Simulation time (s) as integer nanoseconds, the stamp of every message of a frame."""
    return int(round(float(time_s) * 1e9))


def _header(ns: int, frame_id: str) -> dict[str, Any]:
    return {"stamp": {"sec": ns // 1_000_000_000, "nanosec": ns % 1_000_000_000},
            "frame_id": frame_id}


def _transform(ns: int, parent: str, child: str, matrix: NDArray[np.float64]
               ) -> dict[str, Any]:
    x, y, z, w = Rotation.from_matrix(matrix[:3, :3]).as_quat()
    tx, ty, tz = (float(v) for v in matrix[:3, 3])
    return {"header": _header(ns, parent), "child_frame_id": child,
            "transform": {"translation": {"x": tx, "y": ty, "z": tz},
                          "rotation": {"x": float(x), "y": float(y), "z": float(z),
                                       "w": float(w)}}}


def transform_matrix(msg: Any) -> NDArray[np.float64]:
    """4×4 matrix (child → parent) of a decoded ``geometry_msgs/Transform``."""
    q, t = msg.rotation, msg.translation
    return make_transform(Rotation.from_quat([q.x, q.y, q.z, q.w]).as_matrix(),
                          np.array([t.x, t.y, t.z]))


def tof_points(depth_m: NDArray[np.floating], intrinsics: PinholeIntrinsics
               ) -> NDArray[np.float32]:
    """Back-project a ToF depth image to points in its optical frame.

    Parameters
    ----------
    depth_m : ndarray, shape (H, W)
        Distance along each pixel's ray (m); pixels with 0 (invalid) or NaN are dropped.
    intrinsics : PinholeIntrinsics
        The camera's pixel grid (H × W).

    Returns
    -------
    ndarray, shape (n, 3), float32
        Points (x right, y down, z forward; m), row-major pixel order.
    """
    d = np.asarray(depth_m, dtype=np.float64)
    rays = intrinsics.ray_directions()
    rays = rays / np.linalg.norm(rays, axis=-1, keepdims=True)
    keep = np.isfinite(d) & (d > 0)
    return (rays[keep] * d[keep][:, None]).astype(np.float32)


def _fields(dtype: np.dtype[Any]) -> list[dict[str, Any]]:
    assert dtype.fields is not None
    return [{"name": name, "offset": int(field[1]),
             "datatype": _INT32 if field[0].kind == "i" else _FLOAT32, "count": 1}
            for name, field in dtype.fields.items()]


def _cloud(ns: int, frame_id: str, points: NDArray[np.void]) -> dict[str, Any]:
    return {"header": _header(ns, frame_id), "height": 1, "width": len(points),
            "fields": _fields(points.dtype), "is_bigendian": False,
            "point_step": points.dtype.itemsize,
            "row_step": points.dtype.itemsize * len(points),
            "data": points.tobytes(), "is_dense": True}


def _image(ns: int, frame_id: str, array: NDArray[Any], encoding: str) -> dict[str, Any]:
    h, w = array.shape[:2]
    data = np.ascontiguousarray(array)
    return {"header": _header(ns, frame_id), "height": h, "width": w, "encoding": encoding,
            "is_bigendian": 0, "step": data.strides[0], "data": data.tobytes()}


def _camera_info(ns: int, frame_id: str, intr: PinholeIntrinsics) -> dict[str, Any]:
    # ROS puts the centre of pixel (0, 0) at (0, 0); tofradar at (0.5, 0.5).
    cx, cy = intr.cx - 0.5, intr.cy - 0.5
    return {"header": _header(ns, frame_id), "height": intr.height, "width": intr.width,
            "distortion_model": "plumb_bob", "d": [0.0] * 5,
            "k": [intr.fx, 0.0, cx, 0.0, intr.fy, cy, 0.0, 0.0, 1.0],
            "r": [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0],
            "p": [intr.fx, 0.0, cx, 0.0, 0.0, intr.fy, cy, 0.0, 0.0, 0.0, 1.0, 0.0],
            "binning_x": 0, "binning_y": 0,
            "roi": {"x_offset": 0, "y_offset": 0, "height": 0, "width": 0,
                    "do_rectify": False}}


def detection_points(rows: NDArray[np.void]) -> NDArray[np.void]:
    """``/radar/detections`` table rows → PointCloud2 points (:data:`DETECTION_POINT_DTYPE`)."""
    out = np.zeros(len(rows), dtype=DETECTION_POINT_DTYPE)
    for name in ("x", "y", "z", "velocity"):
        out[name] = rows[name]
    out["snr"] = rows["snr_db"]
    names = rows.dtype.names or ()
    out["power_fraction"] = rows["power_fraction"] if "power_fraction" in names else 0.0
    out["label"] = rows["object_id"] if "object_id" in names else -1
    return out


@dataclass(frozen=True)
class SensorDescription:
    """What the messages of one sensor need.

    Attributes
    ----------
    name : str
        Sensor name: its topics are ``/<name>/...`` and its optical frame is ``<name>``.
    kind : str
        ``"tof"``, ``"radar"`` or ``"rgb"``.
    rig : str
        Name (TF frame) of the rig that carries it.
    mount : ndarray, shape (4, 4)
        Its optical frame → its rig's body frame.
    divider : int
        It captures in every ``divider``-th frame of the timeline.
    trigger_offset_s : float
        Its capture time after the frame's time (s).
    intrinsics : PinholeIntrinsics or None
        Pixel grid of a camera.
    radar : dict
        Waveform fields of the ``RadarCube`` message (radars only).
    range_axis_m, velocity_axis_mps : ndarray or None
        Axes of a radar's range–Doppler map.
    """

    name: str
    kind: str
    rig: str
    mount: NDArray[np.float64]
    divider: int = 1
    trigger_offset_s: float = 0.0
    intrinsics: PinholeIntrinsics | None = None
    radar: dict[str, Any] = field(default_factory=dict)
    range_axis_m: NDArray[np.float64] | None = None
    velocity_axis_mps: NDArray[np.float64] | None = None

    def topics(self) -> dict[str, str]:
        """The topics of this sensor → their ROS 2 types."""
        return sensor_topics(self.name, self.kind)


@dataclass(frozen=True)
class RigDescription:
    """What the messages need from the project and the run's static items.

    Attributes
    ----------
    sensors : dict of str to SensorDescription
        Every sensor of every rig, by name (the project's order: the first rig's, then
        the other rigs').
    rigs : dict of str to (Pose, Motion)
        Every rig's pose and motion, by rig name (TF frame), the first rig first.
    frame_rate_hz : float
        The timeline's frame rate (which frames a slower sensor captures in).
    object_frames : list of str
        TF frame name of each object, project order (its name).
    segment_frames : tuple of str
        TF frame name of each person segment (``"<person>/<segment>"``), the order of
        ``/people/segments/pose``; empty without people.
    """

    sensors: dict[str, SensorDescription]
    rigs: dict[str, tuple[Pose, Motion]]
    frame_rate_hz: float
    object_frames: list[str]
    segment_frames: tuple[str, ...] = ()

    @classmethod
    def of(cls, project: Project, static_items: Items) -> RigDescription:
        """Describe a project's rigs and sensors (and the radar axes of ``static_items``).

        A radar's axes are ``/<name>/range_axis`` and ``/<name>/velocity_axis`` of
        ``static_items``, or else computed from its configuration and the project's DSP.
        :class:`~simcore.scene.project_io.ProjectError` when a rig or sensor name would be
        a second TF frame of that name (another rig's or sensor's, or ``world``).
        """
        from simcore.dsp.processing import static_axes_items

        optical = make_transform(BODY_FROM_OPTICAL, np.zeros(3))
        rate = project.timeline.frame_rate_hz
        sensors: dict[str, SensorDescription] = {}
        for rig in project.all_rigs():
            for name, cfg in rig.sensor_configs().items():
                kind = sensor_kind(cfg)
                extra: dict[str, Any] = {}
                if kind in ("tof", "rgb"):
                    extra["intrinsics"] = cfg.intrinsics()  # type: ignore[attr-defined]
                if isinstance(cfg, RadarConfig):
                    extra["radar"] = {
                        "n_tx": len(cfg.tx), "n_rx": len(cfg.rx), "complex_iq": cfg.complex_iq,
                        "start_frequency_hz": cfg.start_frequency_hz,
                        "bandwidth_hz": cfg.bandwidth_hz, "sample_rate_hz": cfg.sample_rate_hz,
                        "chirp_repetition_time_s": cfg.chirp_repetition_time_s}
                    axes = {k.rsplit("/", 1)[-1]: v for k, v in
                            static_axes_items(cfg, project.dsp, group=name).items()}
                    for key, attr in (("range_axis", "range_axis_m"),
                                      ("velocity_axis", "velocity_axis_mps")):
                        value = static_items.get(f"/{name}/{key}", axes.get(key))
                        extra[attr] = (None if value is None
                                       else np.asarray(value[0], dtype=np.float64))
                sensors[name] = SensorDescription(
                    name=name, kind=kind, rig=rig.name,
                    mount=cfg.pose_on_rig.matrix() @ optical,  # type: ignore[attr-defined]
                    divider=cfg.frame_divider(rate),  # type: ignore[attr-defined]
                    trigger_offset_s=float(cfg.trigger_offset_s),  # type: ignore[attr-defined]
                    **extra)
        owner: dict[str, str] = {WORLD_FRAME: "the world frame"}
        for what, names in (("rig", [r.name for r in project.all_rigs()]),
                            ("sensor", list(sensors))):
            for name in names:
                if name in owner:
                    raise ProjectError(f"project {project.name!r}", [
                        f"TF frame {name!r} would be both {owner[name]} and a {what}: "
                        f"rename the {what} (rig and sensor names are TF frames in MCAP "
                        "recordings and the live stream)"])
                owner[name] = f"a {what}"
        segments = static_items.get("/people/segments/names")
        return cls(sensors, {r.name: (r.pose, r.motion) for r in project.all_rigs()}, rate,
                   [o.name for o in project.objects],
                   tuple(str(n) for n in np.asarray(segments[0]).ravel()) if segments else ())

    def topics(self) -> dict[str, str]:
        """Every topic of the project → its ROS 2 type: ``/tf``, then each sensor's."""
        out = {TF_TOPIC: TF_TYPE}
        for sensor in self.sensors.values():
            out.update(sensor.topics())
        return out

    def rig_pose(self, rig: str, items: Items, time_s: float, *,
                 frame_time: bool = True) -> NDArray[np.float64]:
        """Rig body frame → world at ``time_s``.

        At the frame's time: the frame's item ``/poses/rigs`` (every rig, project order;
        a project with several rigs) or ``/poses/rig`` (the first rig) when the frame has
        it; otherwise (and at a sensor's capture time) the rig's pose and motion evaluated
        at ``time_s``.
        """
        if frame_time:
            order = list(self.rigs)
            if "/poses/rigs" in items:
                poses = np.asarray(items["/poses/rigs"][0], dtype=np.float64)
                if poses.shape[0] == len(order):
                    return poses[order.index(rig)]
            if rig == order[0] and "/poses/rig" in items:
                return np.asarray(items["/poses/rig"][0], dtype=np.float64)
        pose, motion = self.rigs[rig]
        return rigid_state(pose, motion, time_s).transform


class Message(NamedTuple):
    """One message: topic, ROS 2 type, the message (nested dicts) and its stamp (ns)."""

    topic: str
    datatype: str
    msg: dict[str, Any]
    stamp_ns: int


def _flag(items: Items, path: str) -> bool | None:
    return bool(np.asarray(items[path][0])) if path in items else None


def sensor_stamp_ns(rig: RigDescription, name: str, items: Items,
                    index: int | None = None) -> int | None:
    """Capture time (ns) of sensor ``name`` in a frame, or None if it does not capture.

    The frame's items ``/<name>/captured`` and ``/<name>/time`` when it has them;
    otherwise the sensor's timing: it captures in every ``divider``-th frame (``index``,
    or the frame's time × the timeline's rate), at the frame's time + its trigger offset.
    """
    sensor = rig.sensors[name]
    t = float(items["/time"][0])
    captured = _flag(items, f"/{name}/captured")
    if captured is None:
        k = int(round(t * rig.frame_rate_hz)) if index is None else index
        captured = k % sensor.divider == 0
    if not captured:
        return None
    path = f"/{name}/time"
    return stamp_ns(float(items[path][0]) if path in items else t + sensor.trigger_offset_s)


def frame_messages(rig: RigDescription, items: Items,
                   tables: Mapping[str, NDArray[np.void]] | None = None, *,
                   index: int | None = None) -> list[Message]:
    """Every message of one frame.

    Parameters
    ----------
    rig : RigDescription
        The rigs and sensors (mounts, intrinsics, radar axes, timing).
    items : mapping
        The frame's HDF5 items (``Frame.hdf5_items()``: path → (array without the frame
        axis, unit)).
    tables : mapping, optional
        The frame's table rows by path (``/<radar>/detections``, ``Frame.table_rows()``).
        A radar with ADC data and no rows publishes an empty detection cloud.
    index : int, optional
        The frame's number (default: its time × the timeline's rate): which frames a
        slower sensor captures in, when the items do not say (``/<name>/captured``).

    Returns
    -------
    list of Message
        ``/tf`` (stamped with the frame's time), then each sensor's topics in the order
        of :meth:`RigDescription.topics`, stamped with the sensor's capture time; a
        sensor that does not capture in this frame, and topics whose data the frame
        lacks, are left out.
    """
    t = float(items["/time"][0])
    ns = stamp_ns(t)
    tables = tables or {}
    stamps = {name: sensor_stamp_ns(rig, name, items, index) for name in rig.sensors}
    out: list[Message] = []

    tfs = [_transform(ns, WORLD_FRAME, name, rig.rig_pose(name, items, t)) for name in rig.rigs]
    # A rig carrying a sensor with a trigger offset: its pose at that capture time too,
    # so a TF lookup at the sensor's stamp is exact.
    for name in rig.rigs:
        for s in sorted({v for k, v in stamps.items()
                         if v is not None and v != ns and rig.sensors[k].rig == name}):
            tfs.append(_transform(s, WORLD_FRAME, name,
                                  rig.rig_pose(name, items, s * 1e-9, frame_time=False)))
    tfs += [_transform(ns, sensor.rig, name, sensor.mount)
            for name, sensor in rig.sensors.items()]
    poses = np.asarray(items["/poses/objects"][0])
    tfs += [_transform(ns, WORLD_FRAME, name, poses[i])
            for i, name in enumerate(rig.object_frames)]
    if rig.segment_frames and "/people/segments/pose" in items:  # people's body parts
        segments = np.asarray(items["/people/segments/pose"][0])
        tfs += [_transform(ns, WORLD_FRAME, name, segments[i])
                for i, name in enumerate(rig.segment_frames)]
    out.append(Message(TF_TOPIC, TF_TYPE, {"transforms": tfs}, ns))
    for name, sensor in rig.sensors.items():
        stamp = stamps[name]
        if stamp is not None:
            out += _SENSOR_MESSAGES[sensor.kind](sensor, items, tables, stamp)
    return out


def _tof_messages(sensor: SensorDescription, items: Items,
                  tables: Mapping[str, NDArray[np.void]], ns: int) -> list[Message]:
    n = sensor.name
    if f"/{n}/depth" not in items:
        return []
    assert sensor.intrinsics is not None
    topic = sensor.topics()
    depth = np.asarray(items[f"/{n}/depth"][0], dtype="<f4")
    pts = tof_points(depth, sensor.intrinsics)
    cloud = np.zeros(len(pts), dtype=TOF_POINT_DTYPE)
    cloud["x"], cloud["y"], cloud["z"] = pts.T
    msgs = [("depth", _image(ns, n, depth, "32FC1"))]
    if f"/{n}/amplitude" in items:
        msgs.append(("amplitude", _image(ns, n, np.asarray(items[f"/{n}/amplitude"][0], "<f4"),
                                         "32FC1")))
    msgs += [("camera_info", _camera_info(ns, n, sensor.intrinsics)),
             ("points", _cloud(ns, n, cloud))]
    return [Message(f"/{n}/{s}", topic[f"/{n}/{s}"], m, ns) for s, m in msgs]


def _rgb_messages(sensor: SensorDescription, items: Items,
                  tables: Mapping[str, NDArray[np.void]], ns: int) -> list[Message]:
    n = sensor.name
    if f"/{n}/image" not in items:
        return []
    assert sensor.intrinsics is not None
    topic = sensor.topics()
    msgs = [("image", _image(ns, n, np.asarray(items[f"/{n}/image"][0], np.uint8), "rgb8")),
            ("camera_info", _camera_info(ns, n, sensor.intrinsics))]
    return [Message(f"/{n}/{s}", topic[f"/{n}/{s}"], m, ns) for s, m in msgs]


def _radar_messages(sensor: SensorDescription, items: Items,
                    tables: Mapping[str, NDArray[np.void]], ns: int) -> list[Message]:
    n = sensor.name
    topic = sensor.topics()
    msgs: list[tuple[str, dict[str, Any]]] = []
    rows = tables.get(f"/{n}/detections")
    if rows is None and f"/{n}/adc" in items:
        from simcore.dsp.detections import DETECTION_DTYPE
        rows = np.zeros(0, dtype=DETECTION_DTYPE)
    if rows is not None:
        msgs.append(("detections", _cloud(ns, n, detection_points(rows))))
    if f"/{n}/adc" in items:
        adc = np.asarray(items[f"/{n}/adc"][0])
        data = adc.astype("<c8").view("<f4") if np.iscomplexobj(adc) else adc.astype("<f4")
        start = np.asarray(items[f"/{n}/chirp_start_time"][0], dtype=np.float64)
        chirps, channels, samples = adc.shape
        inr = items.get(f"/{n}/inr_db")
        msgs.append(("adc", {"header": _header(ns, n), "chirps": chirps,
                             "channels": channels, "samples": samples, **sensor.radar,
                             "chirp_start_time": start.ravel().tolist(),
                             "inr_db": INR_NONE_DB if inr is None else float(inr[0]),
                             "data": data.tobytes()}))
    if f"/{n}/range_doppler" in items and sensor.range_axis_m is not None:
        rd = np.asarray(items[f"/{n}/range_doppler"][0], dtype="<f4")
        assert sensor.velocity_axis_mps is not None
        msgs.append(("range_doppler", {
            "header": _header(ns, n), "doppler_bins": rd.shape[0],
            "range_bins": rd.shape[1], "range_axis": sensor.range_axis_m.tolist(),
            "velocity_axis": sensor.velocity_axis_mps.tolist(), "data": rd.tobytes()}))
    return [Message(f"/{n}/{s}", topic[f"/{n}/{s}"], m, ns) for s, m in msgs]


_SENSOR_MESSAGES: dict[str, Callable[[SensorDescription, Items,
                                      Mapping[str, NDArray[np.void]], int], list[Message]]] = {
    "tof": _tof_messages, "rgb": _rgb_messages, "radar": _radar_messages}


def cloud_array(msg: Any) -> NDArray[np.void]:
    """The points of a decoded ``sensor_msgs/PointCloud2`` as a structured array."""
    kinds = {_FLOAT32: "<f4", _INT32: "<i4", 8: "<f8", 2: "u1", 6: "<u4"}
    dtype = np.dtype({"names": [f.name for f in msg.fields],
                      "formats": [kinds[f.datatype] for f in msg.fields],
                      "offsets": [f.offset for f in msg.fields],
                      "itemsize": msg.point_step})
    return np.frombuffer(bytes(msg.data), dtype=dtype, count=msg.width * msg.height)


def image_array(msg: Any) -> NDArray[Any]:
    """The pixels of a decoded ``sensor_msgs/Image`` (32FC1 → float32 (H, W); rgb8 → (H, W, 3))."""
    if msg.encoding == "32FC1":
        return np.frombuffer(bytes(msg.data), "<f4").reshape(msg.height, msg.width)
    if msg.encoding == "rgb8":
        return np.frombuffer(bytes(msg.data), np.uint8).reshape(msg.height, msg.width, 3)
    raise ValueError(f"unsupported image encoding {msg.encoding!r}")
