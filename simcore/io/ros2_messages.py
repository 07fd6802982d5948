"""ROS 2 messages of a frame: standard types plus two documented tofradar messages.

One frame becomes one message per topic, all stamped with the frame's simulation time
(``header.stamp`` and the MCAP log time are equal for every sensor of a frame):

* ``/tf`` (``tf2_msgs/msg/TFMessage``): world → rig → each sensor's optical frame
  (``tof``, ``radar``, ``rgb``); world → each object (frame named after the object).
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
from dataclasses import dataclass
from functools import cache
from importlib import resources
from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy.spatial.transform import Rotation

from simcore.scene.camera import PinholeIntrinsics
from simcore.scene.model import Project
from simcore.scene.motion import make_transform
from simcore.scene.snapshot import BODY_FROM_OPTICAL

Items = Mapping[str, tuple[NDArray[Any], str]]
#: One message: (topic, ROS 2 type name, message as nested dicts).
Message = tuple[str, str, dict[str, Any]]

WORLD_FRAME = "world"
RIG_FRAME = "rig"

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

#: ROS 2 type of every topic.
TOPIC_TYPES = {
    "/tf": "tf2_msgs/msg/TFMessage",
    "/tof/depth": "sensor_msgs/msg/Image",
    "/tof/amplitude": "sensor_msgs/msg/Image",
    "/tof/camera_info": "sensor_msgs/msg/CameraInfo",
    "/tof/points": "sensor_msgs/msg/PointCloud2",
    "/rgb/image": "sensor_msgs/msg/Image",
    "/rgb/camera_info": "sensor_msgs/msg/CameraInfo",
    "/radar/detections": "sensor_msgs/msg/PointCloud2",
    "/radar/adc": "tofradar_msgs/msg/RadarCube",
    "/radar/range_doppler": "tofradar_msgs/msg/RangeDopplerMap",
}

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
class RigDescription:
    """What the messages need from the project and the run's static items.

    Attributes
    ----------
    sensors : dict of str to ndarray, shape (4, 4)
        Each sensor's optical frame → rig body frame.
    intrinsics : dict of str to PinholeIntrinsics
        Pixel grids of the cameras (``tof``, ``rgb``).
    object_frames : list of str
        TF frame name of each object, project order (its name).
    radar : dict
        Waveform fields of the ``RadarCube`` message (empty without a radar).
    range_axis_m, velocity_axis_mps : ndarray or None
        Axes of the range–Doppler map.
    segment_frames : tuple of str
        TF frame name of each person segment (``"<person>/<segment>"``), the order of
        ``/people/segments/pose``; empty without people.
    """

    sensors: dict[str, NDArray[np.float64]]
    intrinsics: dict[str, PinholeIntrinsics]
    object_frames: list[str]
    radar: dict[str, Any]
    range_axis_m: NDArray[np.float64] | None
    velocity_axis_mps: NDArray[np.float64] | None
    segment_frames: tuple[str, ...] = ()

    @classmethod
    def of(cls, project: Project, static_items: Items) -> RigDescription:
        """Describe a project's rig (and the radar axes of ``static_items``)."""
        optical = make_transform(BODY_FROM_OPTICAL, np.zeros(3))
        configs = project.rig.sensor_configs()
        sensors = {name: cfg.pose_on_rig.matrix() @ optical  # type: ignore[attr-defined]
                   for name, cfg in configs.items()}
        intrinsics = {name: cfg.intrinsics() for name, cfg in configs.items()  # type: ignore
                      if name in ("tof", "rgb")}
        radar: dict[str, Any] = {}
        rc = project.rig.radar
        if rc is not None:
            radar = {"n_tx": len(rc.tx), "n_rx": len(rc.rx), "complex_iq": rc.complex_iq,
                     "start_frequency_hz": rc.start_frequency_hz,
                     "bandwidth_hz": rc.bandwidth_hz, "sample_rate_hz": rc.sample_rate_hz,
                     "chirp_repetition_time_s": rc.chirp_repetition_time_s}

        def axis(path: str) -> NDArray[np.float64] | None:
            return None if path not in static_items else np.asarray(static_items[path][0],
                                                                    dtype=np.float64)

        segments = static_items.get("/people/segments/names")
        return cls(sensors, intrinsics, [o.name for o in project.objects], radar,
                   axis("/radar/range_axis"), axis("/radar/velocity_axis"),
                   tuple(str(n) for n in np.asarray(segments[0]).ravel()) if segments else ())


def frame_messages(rig: RigDescription, items: Items,
                   detections: NDArray[np.void] | None = None) -> list[Message]:
    """Every message of one frame.

    Parameters
    ----------
    rig : RigDescription
        The rig (sensor mounts, intrinsics, radar axes).
    items : mapping
        The frame's HDF5 items (``Frame.hdf5_items()``: path → (array without the frame
        axis, unit)).
    detections : ndarray of DETECTION_DTYPE, optional
        The frame's rows of the ``/radar/detections`` table.

    Returns
    -------
    list of (topic, type, message)
        In the order of :data:`TOPIC_TYPES`; topics whose data the frame lacks are left out.
    """
    ns = stamp_ns(float(items["/time"][0]))
    out: list[Message] = []

    def add(topic: str, msg: dict[str, Any]) -> None:
        out.append((topic, TOPIC_TYPES[topic], msg))

    tfs = [_transform(ns, WORLD_FRAME, RIG_FRAME, np.asarray(items["/poses/rig"][0]))]
    tfs += [_transform(ns, RIG_FRAME, name, m) for name, m in rig.sensors.items()]
    poses = np.asarray(items["/poses/objects"][0])
    tfs += [_transform(ns, WORLD_FRAME, name, poses[i])
            for i, name in enumerate(rig.object_frames)]
    if rig.segment_frames and "/people/segments/pose" in items:  # people's body parts
        segments = np.asarray(items["/people/segments/pose"][0])
        tfs += [_transform(ns, WORLD_FRAME, name, segments[i])
                for i, name in enumerate(rig.segment_frames)]
    add("/tf", {"transforms": tfs})
    if "/tof/depth" in items:
        depth = np.asarray(items["/tof/depth"][0], dtype="<f4")
        add("/tof/depth", _image(ns, "tof", depth, "32FC1"))
        add("/tof/amplitude", _image(ns, "tof", np.asarray(items["/tof/amplitude"][0], "<f4"),
                                     "32FC1"))
        add("/tof/camera_info", _camera_info(ns, "tof", rig.intrinsics["tof"]))
        pts = tof_points(depth, rig.intrinsics["tof"])
        cloud = np.zeros(len(pts), dtype=TOF_POINT_DTYPE)
        cloud["x"], cloud["y"], cloud["z"] = pts.T
        add("/tof/points", _cloud(ns, "tof", cloud))
    if "/rgb/image" in items:
        add("/rgb/image", _image(ns, "rgb", np.asarray(items["/rgb/image"][0], np.uint8),
                                 "rgb8"))
        add("/rgb/camera_info", _camera_info(ns, "rgb", rig.intrinsics["rgb"]))
    if detections is not None:
        add("/radar/detections", _cloud(ns, "radar", detection_points(detections)))
    if "/radar/adc" in items:
        adc = np.asarray(items["/radar/adc"][0])
        data = adc.astype("<c8").view("<f4") if np.iscomplexobj(adc) else adc.astype("<f4")
        start = np.asarray(items["/radar/chirp_start_time"][0], dtype=np.float64)
        chirps, channels, samples = adc.shape
        add("/radar/adc", {"header": _header(ns, "radar"), "chirps": chirps,
                           "channels": channels, "samples": samples, **rig.radar,
                           "chirp_start_time": start.ravel().tolist(),
                           "data": data.tobytes()})
    if "/radar/range_doppler" in items and rig.range_axis_m is not None:
        rd = np.asarray(items["/radar/range_doppler"][0], dtype="<f4")
        assert rig.velocity_axis_mps is not None
        add("/radar/range_doppler", {
            "header": _header(ns, "radar"), "doppler_bins": rd.shape[0],
            "range_bins": rd.shape[1], "range_axis": rig.range_axis_m.tolist(),
            "velocity_axis": rig.velocity_axis_mps.tolist(), "data": rd.tobytes()})
    return out


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
