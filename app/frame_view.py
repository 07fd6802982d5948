"""What the GUI shows of one frame, extracted from a :class:`simcore.pipeline.Frame`.

:func:`build_frame_view` runs in the simulation worker thread: it pulls the arrays the
panels draw (ToF depth/amplitude/validity, range profile per Rx with the CFAR threshold,
range–Doppler and range–azimuth maps with their axes, detections, the radar point cloud in
world coordinates) out of the frame into plain numpy arrays, so the GUI thread only copies
them into plot items.

Nothing is computed here that the pipeline computes: ToF images come from
``frame.outputs["tof"]``, radar maps, CFAR threshold and detections from
``frame.outputs["radar"].dsp`` (:class:`simcore.dsp.RadarProducts`), the colour image from
``frame.outputs["rgb"]`` when the rig carries an RGB camera. This is the only module of
the GUI that reads a :class:`simcore.pipeline.Frame`.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np
from numpy.typing import NDArray

from simcore.scene import Project

F32 = NDArray[np.float32]
F64 = NDArray[np.float64]


@dataclass
class Detections:
    """Radar detections of one frame (all arrays shape (n,)).

    Attributes
    ----------
    range_m, velocity_mps, azimuth_deg, elevation_deg, snr_db : ndarray
        Polar measurements (velocity positive when moving away).
    xyz_radar_m : ndarray, shape (n, 3)
        Points in the radar optical frame (x right, y down, z forward).
    xyz_world_m : ndarray, shape (n, 3)
        The same points in the world frame.
    object_id : ndarray, shape (n,), int32, or None
        Ground-truth label: the id of the object contributing most power to each
        detection's cell, −1 for noise (None when the frame has no labels).
    """

    range_m: F64
    velocity_mps: F64
    azimuth_deg: F64
    elevation_deg: F64
    snr_db: F64
    xyz_radar_m: F64
    xyz_world_m: F64
    object_id: NDArray[np.int32] | None = None

    @classmethod
    def empty(cls) -> Detections:
        """No detections."""
        z = np.zeros(0)
        return cls(z, z, z, z, z, np.zeros((0, 3)), np.zeros((0, 3)))

    def __len__(self) -> int:
        return int(self.range_m.shape[0])


@dataclass
class RadarView:
    """Radar maps of one frame, in dB, with their axes.

    Attributes
    ----------
    range_axis_m : ndarray, shape (R,)
        Range of each range bin (m).
    profile_db : ndarray, shape (rx, R)
        Range-FFT magnitude per receive channel (dB), averaged over the chirps.
    threshold_db : ndarray, shape (R,) or None
        CFAR threshold along range (dB) on the same scale as ``profile_db``.
    velocity_axis_mps : ndarray, shape (D,)
    range_doppler_db : ndarray, shape (D, R)
    azimuth_axis_deg : ndarray, shape (A,)
    range_azimuth_db : ndarray, shape (A, R)
    detections : Detections
    channel_names : list of str
        One name per row of ``profile_db``.
    bev_db : ndarray, shape (nz, nx), optional
        Bird's-eye (Cartesian) range–azimuth image (dB, NaN outside the coverage) over
        ``bev_x_m`` (right) and ``bev_z_m`` (forward).
    """

    range_axis_m: F64
    profile_db: F32
    threshold_db: F32 | None
    velocity_axis_mps: F64
    range_doppler_db: F32
    azimuth_axis_deg: F64
    range_azimuth_db: F32
    detections: Detections
    channel_names: list[str]
    bev_db: F32 | None = None
    bev_x_m: F64 | None = None
    bev_z_m: F64 | None = None

    def profile_peak_range_m(self, *, min_range_m: float = 0.3) -> float:
        """Range (m) of the strongest bin of the channel-averaged profile beyond ``min_range_m``.

        NaN when no range bin lies beyond ``min_range_m`` (a waveform whose maximum range
        is shorter than that) or the profile is empty.
        """
        mean = 10 * np.log10(np.mean(10 ** (self.profile_db / 10), axis=0))
        mask = (self.range_axis_m >= min_range_m) & np.isfinite(mean)
        if not mask.any():
            return float("nan")
        return float(self.range_axis_m[mask][np.argmax(mean[mask])])


@dataclass
class TofView:
    """ToF camera images of one frame, shape (H, W), row 0 at the top.

    Attributes
    ----------
    depth_m : ndarray, float32
        Measured depth (m); NaN where invalid.
    amplitude : ndarray, float32
        Demodulated amplitude (DN).
    valid : ndarray, bool
        Neither saturated nor too dark.
    max_range_m : float
        Unambiguous range (upper end of the depth colour scale).
    """

    depth_m: F32
    amplitude: F32
    valid: NDArray[np.bool_]
    max_range_m: float
    amplitude_unit: str = "DN"
    # --- issue #17 (ground-truth overlays): id image for object outlines ---------------
    #: Ground-truth object id per pixel (−1 = no surface), shape (H, W); None if unknown.
    gt_object_id: NDArray[np.int32] | None = None
    # --- end issue #17 ---------------------------------------------------------------------


# --- issue #17 (ground-truth overlays) ---------------------------------------------------
@dataclass
class ObjectMarks:
    """Where each object of the frame truly is, seen from the radar (``K`` objects).

    Attributes
    ----------
    object_id : ndarray, shape (K,), int32
        Project ids (project order).
    range_m, radial_velocity_mps, azimuth_deg, elevation_deg : ndarray, shape (K,)
        Range (m), radial velocity (m/s, + = away), azimuth and elevation (deg) of each
        object's reference point in the radar frame (:mod:`simcore.scene.ground_truth`).
    nearest_range_m : ndarray, shape (K,), optional
        Range of each object's nearest surface point from the radar (m; issue #34): where
        the radar sees it begin. None when unknown.
    """

    object_id: NDArray[np.int32]
    range_m: F64
    radial_velocity_mps: F64
    azimuth_deg: F64
    elevation_deg: F64
    nearest_range_m: F64 | None = None


def object_marks(truth: Any, project: Project) -> ObjectMarks | None:
    """Adapt a frame's :class:`simcore.scene.ground_truth.ObjectTruth` (None → None)."""
    if truth is None or len(truth.radar_range_m) != len(project.objects):
        return None
    return ObjectMarks(np.array([o.id for o in project.objects], dtype=np.int32),
                       np.asarray(truth.radar_range_m, dtype=np.float64),
                       np.asarray(truth.radar_radial_velocity_mps, dtype=np.float64),
                       np.asarray(truth.radar_azimuth_deg, dtype=np.float64),
                       np.asarray(truth.radar_elevation_deg, dtype=np.float64),
                       _nearest(truth, len(project.objects)))


def _nearest(truth: Any, k: int) -> F64 | None:
    """The truth's nearest ranges (issue #34), or None from a core without them."""
    near = getattr(truth, "radar_nearest_range_m", None)
    return None if near is None or len(near) != k else np.asarray(near, dtype=np.float64)
# --- end issue #17 -----------------------------------------------------------------------


@dataclass
class FrameView:
    """Everything the GUI shows of one frame."""

    index: int
    time_s: float
    #: The first ToF camera's images (None: the project has no ToF camera).
    tof: TofView | None
    radar: RadarView | None
    object_poses: F64
    rig_pose: F64
    rgb: NDArray[np.uint8] | None = None
    timings_ms: dict[str, float] = field(default_factory=dict)
    render_count: int = 0
    request_serial: int = 0
    latency_ms: float = 0.0
    notes: list[str] = field(default_factory=list)
    #: Ground truth of every object from the radar (issue #17); None when unknown.
    objects: ObjectMarks | None = None
    #: Every sensor's images, maps and colour image of the frame, by sensor name (issue
    #: #30); a sensor that did not capture in this frame (a lower frame rate) is absent.
    #: ``tof``, ``radar`` and ``rgb`` above are the first sensor of each kind.
    tofs: dict[str, TofView] = field(default_factory=dict)
    radars: dict[str, RadarView] = field(default_factory=dict)
    rgbs: dict[str, NDArray[np.uint8]] = field(default_factory=dict)
    #: Ground truth of every object from each radar, by radar name.
    radar_objects: dict[str, ObjectMarks] = field(default_factory=dict)

    def for_sensor(self, kind: str, name: str) -> FrameView | None:
        """The frame with sensor ``name``'s data as its ``tof``, ``radar`` or ``rgb``.

        None when the sensor did not capture in this frame. A radar's view carries its
        own ground-truth marks (none when the frame has no truth for it).
        """
        # ``tof``, ``radar`` and ``rgb`` show the first sensor of each kind that captured
        # (or, in a view made without the per-sensor tables, the built-in one): the view
        # itself then, as it is (a panel keeps the very view; a test may edit ``radar``).
        if kind not in ("tof", "radar", "rgb"):
            raise ValueError(f"unknown sensor kind {kind!r}")
        table: dict[str, Any] = {"tof": self.tofs, "radar": self.radars, "rgb": self.rgbs}[kind]
        current = getattr(self, kind)
        if table.get(name) is current:
            return self
        # A view edited in place (or made without the tables) shows its first sensor.
        if not any(v is current for v in table.values()) and name == next(iter(table), kind):
            return self
        if name not in table:
            return None
        if kind == "tof":
            return replace(self, tof=table[name])
        if kind == "rgb":
            return replace(self, rgb=table[name])
        return replace(self, radar=table[name], objects=self.radar_objects.get(name))


# --------------------------------------------------------------------------------------
# ToF
# --------------------------------------------------------------------------------------


def _tof_view(frame: Any, project: Project, name: str = "tof") -> TofView:
    cfg = project.sensor_config(name)
    tof = frame.outputs[name]
    valid = np.asarray(tof.valid, dtype=bool)
    depth = np.where(valid, tof.depth_m, np.nan).astype(np.float32)
    gt_id = getattr(tof, "gt_object_id", None)  # issue #17: object outlines
    return TofView(depth, np.asarray(tof.amplitude, dtype=np.float32), valid,
                   float(cfg.combined_unambiguous_range_m),
                   gt_object_id=None if gt_id is None else np.asarray(gt_id, dtype=np.int32))


# --------------------------------------------------------------------------------------
# Radar
# --------------------------------------------------------------------------------------


def radar_to_world(points_radar: F64, sensor_transform: F64) -> F64:
    """Radar optical-frame points, shape (n, 3), to world coordinates (n, 3)."""
    if len(points_radar) == 0:
        return np.zeros((0, 3))
    return points_radar @ sensor_transform[:3, :3].T + sensor_transform[:3, 3]


def channel_names(project: Project, name: str = "radar") -> list[str]:
    """Names of radar ``name``'s virtual channels, Tx-major (``rx1`` … with one Tx)."""
    radar: Any = project.sensor_config(name)
    rx = [a.name or f"rx{i + 1}" for i, a in enumerate(radar.rx)]
    if len(radar.tx) == 1:
        return rx
    tx = [a.name or f"tx{i + 1}" for i, a in enumerate(radar.tx)]
    return [f"{t}·{r}" for t in tx for r in rx]


def radar_view_from_products(dsp: Any, project: Project, radar_transform: F64, *,
                             labels: Any = None, name: str = "radar") -> RadarView:
    """Adapt :class:`simcore.dsp.RadarProducts` to a :class:`RadarView`."""
    ax = dsp.axes
    velocity = np.asarray(ax.velocity_mps, dtype=np.float64)
    threshold_db = None
    cfar = getattr(dsp, "cfar", None)
    if cfar is not None and np.ndim(cfar.threshold) == 2:
        # Zero-Doppler row: static targets have the same (amplitude-normalised) power in
        # the range profile and at 0 m/s in the range–Doppler map.
        d0 = int(np.argmin(np.abs(velocity)))
        threshold_db = (10 * np.log10(np.maximum(cfar.threshold[d0], 1e-30))).astype(
            np.float32)
    det = dsp.detections
    xyz = np.asarray(det.xyz_radar_m, dtype=np.float64).reshape(-1, 3)
    world = det.xyz_world_m
    world = (np.asarray(world, dtype=np.float64).reshape(-1, 3) if world is not None
             else radar_to_world(xyz, radar_transform))
    detections = Detections(
        np.asarray(det.range_m, dtype=np.float64), np.asarray(det.velocity_mps, dtype=float),
        np.asarray(det.azimuth_deg, dtype=float), np.asarray(det.elevation_deg, dtype=float),
        np.asarray(det.snr_db, dtype=float), xyz, world,
        None if labels is None or len(labels.object_id) != len(xyz)
        else np.asarray(labels.object_id, dtype=np.int32))
    profile = np.asarray(dsp.range_profile_db, dtype=np.float32)
    names = channel_names(project, name)
    if len(names) != profile.shape[0]:
        names = [f"ch{i + 1}" for i in range(profile.shape[0])]
    bev = getattr(dsp, "bird_eye_db", None)
    return RadarView(
        range_axis_m=np.asarray(ax.range_m, dtype=np.float64),
        profile_db=profile,
        threshold_db=threshold_db,
        velocity_axis_mps=velocity,
        range_doppler_db=np.asarray(dsp.range_doppler_db, dtype=np.float32),
        azimuth_axis_deg=np.asarray(ax.azimuth_deg, dtype=np.float64),
        range_azimuth_db=np.asarray(dsp.range_azimuth_db, dtype=np.float32),
        detections=detections,
        channel_names=names,
        bev_db=None if bev is None else np.asarray(bev, dtype=np.float32),
        bev_x_m=None if bev is None else np.asarray(ax.bev_x_m, dtype=np.float64),
        bev_z_m=None if bev is None else np.asarray(ax.bev_z_m, dtype=np.float64),
    )


def _radar_view(frame: Any, project: Project, notes: list[str]) -> RadarView | None:
    radar = frame.outputs.get("radar")
    if radar is None or "radar" not in frame.buffers:
        if project.sensors_of_kind("radar"):
            notes.append("no radar captured in this frame")
        return None
    return radar_view_from_products(radar.dsp, project, frame.buffers["radar"].sensor.transform,
                                    labels=getattr(radar, "labels", None))


def radar_object_marks(frame: Any, project: Project) -> dict[str, ObjectMarks]:
    """Each further radar's object truth (``/objects/<name>/range`` … of the frame)."""
    items = getattr(frame, "sensor_truth", None) or {}
    ids = np.array([o.id for o in project.objects], dtype=np.int32)
    out: dict[str, ObjectMarks] = {}
    for name in project.sensors_of_kind("radar"):
        keys = [f"/objects/{name}/{q}" for q in ("range", "radial_velocity", "azimuth",
                                                  "elevation")]
        if name == "radar" or not all(k in items for k in keys):
            continue
        arrays = [np.asarray(items[k][0], dtype=np.float64) for k in keys]
        if any(len(a) != len(ids) for a in arrays):
            continue
        out[name] = ObjectMarks(ids, *arrays)
    return out


def _no_tof(project: Project, notes: list[str]) -> TofView | None:
    """An all-invalid image of the first camera's size: no ToF camera captured.

    None when the project has no ToF camera (a radar-only project).
    """
    cfg: Any = next(iter(project.sensors_of_kind("tof").values()), None)
    if cfg is None:
        return None
    notes.append("no ToF camera captured in this frame")
    shape = (cfg.height, cfg.width)
    return TofView(np.full(shape, np.nan, np.float32), np.zeros(shape, np.float32),
                   np.zeros(shape, bool), float(cfg.combined_unambiguous_range_m))


def _sensor_transform(frame: Any, project: Project, name: str) -> F64:
    """Sensor ``name``'s world transform in this frame (its buffer's, else its pose)."""
    buffer = getattr(frame, "buffers", {}).get(name)
    if buffer is not None:
        return np.asarray(buffer.sensor.transform, dtype=np.float64)
    from app.document.sensors import (
        sensor_states,  # the GUI's rigs: only for a sensor without buffer
    )

    return sensor_states(project, float(frame.time_s))[name].transform


def build_frame_view(frame: Any, project: Project, *, render_count: int = 0) -> FrameView:
    """Extract what the panels draw from a pipeline frame (runs in the worker thread)."""
    notes: list[str] = []
    timings = dict(frame.timings_ms)
    outputs = frame.outputs
    tofs = {n: _tof_view(frame, project, n) for n in project.sensors_of_kind("tof")
            if n in outputs}
    radars = {n: radar_view_from_products(outputs[n].dsp, project,
                                          _sensor_transform(frame, project, n),
                                          labels=getattr(outputs[n], "labels", None), name=n)
              for n in project.sensors_of_kind("radar")
              if n in outputs and getattr(outputs[n], "dsp", None) is not None}
    rgbs = {n: np.asarray(outputs[n].image) for n in project.sensors_of_kind("rgb")
            if n in outputs}
    # The first sensor of each kind that captured (the built-in one when it did).
    tof = next(iter(tofs.values()), None) or _no_tof(project, notes)
    radar = next(iter(radars.values()), None) or _radar_view(frame, project, notes)
    marks = radar_object_marks(frame, project)
    objects = object_marks(getattr(frame, "objects", None), project)  # issue #17
    if objects is not None:
        marks = {"radar": objects, **marks}  # every radar's truth, the built-in's too
    first_radar = next(iter(radars), "radar")
    if first_radar != "radar":
        objects = marks.get(first_radar)
    rgb = next(iter(rgbs.values()), None)
    return FrameView(
        index=frame.index,
        time_s=float(frame.time_s),
        tof=tof,
        radar=radar,
        rgb=rgb,
        object_poses=np.asarray(frame.object_poses),
        rig_pose=np.asarray(frame.rig_pose),
        timings_ms=timings,
        render_count=render_count,
        notes=notes,
        objects=objects,
        tofs=tofs,
        radars=radars,
        rgbs=rgbs,
        radar_objects=marks,
    )
