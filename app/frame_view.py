"""What the GUI shows of one frame, extracted from a :class:`simcore.pipeline.Frame`.

:func:`build_frame_view` runs in the simulation worker thread: it pulls the arrays the
panels draw (ToF depth/amplitude/validity, range profile per Rx with the CFAR threshold,
range–Doppler and range–azimuth maps with their axes, detections, the radar point cloud in
world coordinates) out of the frame into plain numpy arrays, so the GUI thread only copies
them into plot items.

The sensor and DSP stages of the pipeline are optional here: a frame without ``tof``
falls back to :func:`simcore.sensors.tof.simulate_tof` on the ToF render when that exists,
then to the ground-truth range; a frame without ``dsp`` falls back to the app's preview
radar chain (:mod:`app.preview_radar`), which the panels label as a preview.
"""

from __future__ import annotations

from dataclasses import dataclass, field
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
    """

    range_m: F64
    velocity_mps: F64
    azimuth_deg: F64
    elevation_deg: F64
    snr_db: F64
    xyz_radar_m: F64
    xyz_world_m: F64

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
    source : str
        "simcore" when computed by the pipeline's DSP, "preview" for the app's fallback.
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
    source: str = "simcore"

    def profile_peak_range_m(self, *, min_range_m: float = 0.3) -> float:
        """Range (m) of the strongest bin of the channel-averaged profile beyond ``min_range_m``."""
        mean = 10 * np.log10(np.mean(10 ** (self.profile_db / 10), axis=0))
        mask = self.range_axis_m >= min_range_m
        return float(self.range_axis_m[mask][np.argmax(mean[mask])])


@dataclass
class TofView:
    """ToF camera images of one frame, shape (H, W), row 0 at the top.

    Attributes
    ----------
    depth_m : ndarray, float32
        Measured depth (m); NaN where invalid.
    amplitude : ndarray, float32
        Demodulated amplitude (DN, or relative units for the ground-truth fallback).
    valid : ndarray, bool
    max_range_m : float
        Unambiguous range (upper end of the depth colour scale).
    source : str
        "simcore" (camera model) or "ground truth" (fallback).
    """

    depth_m: F32
    amplitude: F32
    valid: NDArray[np.bool_]
    max_range_m: float
    amplitude_unit: str = "DN"
    source: str = "simcore"


@dataclass
class FrameView:
    """Everything the GUI shows of one frame."""

    index: int
    time_s: float
    tof: TofView
    radar: RadarView | None
    object_poses: F64
    rig_pose: F64
    timings_ms: dict[str, float] = field(default_factory=dict)
    render_count: int = 0
    request_serial: int = 0
    latency_ms: float = 0.0
    notes: list[str] = field(default_factory=list)


# --------------------------------------------------------------------------------------
# ToF
# --------------------------------------------------------------------------------------


def _tof_view(frame: Any, project: Project, notes: list[str]) -> TofView:
    cfg = project.rig.tof
    tof = getattr(frame, "tof", None)
    if tof is None:
        try:
            from simcore.pipeline import frame_rng
            from simcore.sensors.tof import simulate_tof
        except ImportError:
            simulate_tof = None
        if simulate_tof is not None:
            tof = simulate_tof(frame.tof_buffers, cfg, rng=frame_rng(project.seed, frame.index))
    if tof is not None:
        valid = np.asarray(tof.valid, dtype=bool)
        depth = np.where(valid, tof.depth_m, np.nan).astype(np.float32)
        return TofView(depth, np.asarray(tof.amplitude, dtype=np.float32), valid,
                       float(cfg.combined_unambiguous_range_m))
    notes.append("ToF camera model not available: showing ground-truth range")
    gt = np.asarray(frame.tof_gt_range, dtype=np.float32)
    valid = np.isfinite(gt)
    amp = np.where(valid, 1.0 / np.maximum(gt, 0.05) ** 2, 0.0).astype(np.float32)
    return TofView(gt, amp, valid, float(cfg.unambiguous_range_m), amplitude_unit="1/m²",
                   source="ground truth")


# --------------------------------------------------------------------------------------
# Radar
# --------------------------------------------------------------------------------------


def _first(obj: Any, *names: str) -> Any:
    """The first attribute of ``obj`` among ``names`` that exists and is not None."""
    for name in names:
        value = getattr(obj, name, None)
        if value is not None:
            return value
    return None


def _db(x: Any, *, power: bool) -> F32:
    a = np.asarray(x)
    if np.iscomplexobj(a):
        a = np.abs(a) ** 2
        power = True
    a = np.maximum(np.asarray(a, dtype=np.float64), 1e-30)
    return (10 * np.log10(a) if power else 20 * np.log10(a)).astype(np.float32)


def radar_to_world(points_radar: F64, sensor_transform: F64) -> F64:
    """Radar optical-frame points, shape (n, 3), to world coordinates (n, 3)."""
    if len(points_radar) == 0:
        return np.zeros((0, 3))
    return points_radar @ sensor_transform[:3, :3].T + sensor_transform[:3, 3]


def _detections_from(dsp: Any, radar_transform: F64) -> Detections:
    det = _first(dsp, "detections", "point_cloud")
    if det is None:
        return Detections.empty()

    def col(*names: str) -> F64 | None:
        for n in names:
            if isinstance(det, np.ndarray) and det.dtype.names and n in det.dtype.names:
                return np.asarray(det[n], dtype=np.float64)
            v = getattr(det, n, None)
            if v is not None:
                return np.asarray(v, dtype=np.float64)
        return None

    rng = col("range", "range_m")
    if rng is None:
        return Detections.empty()
    n = len(rng)
    zeros = np.zeros(n)
    vel = col("velocity", "velocity_mps", "radial_velocity_mps")
    az = col("azimuth_deg")
    el = col("elevation_deg")
    snr = col("snr_db", "snr")
    x, y, z = col("x", "x_m"), col("y", "y_m"), col("z", "z_m")
    xyz = col("xyz", "xyz_m", "points_m")
    if xyz is None:
        if x is not None and y is not None and z is not None:
            xyz = np.stack([x, y, z], axis=1)
        else:
            a = np.deg2rad(az if az is not None else zeros)
            e = np.deg2rad(el if el is not None else zeros)
            xyz = np.stack([rng * np.cos(e) * np.sin(a), -rng * np.sin(e),
                            rng * np.cos(e) * np.cos(a)], axis=1)
    xyz = np.asarray(xyz, dtype=np.float64).reshape(n, 3)
    world = col("xyz_world", "xyz_world_m")
    world = (np.asarray(world).reshape(n, 3) if world is not None
             else radar_to_world(xyz, radar_transform))
    return Detections(rng, vel if vel is not None else zeros, az if az is not None else zeros,
                      el if el is not None else zeros, snr if snr is not None else zeros, xyz,
                      world)


def _radar_view_from_dsp(dsp: Any, project: Project, radar_transform: F64) -> RadarView:
    """Adapt :class:`simcore.dsp.RadarProducts` to :class:`RadarView`."""
    range_axis = np.asarray(_first(dsp, "range_axis_m", "range_axis"), dtype=np.float64)
    profile = _first(dsp, "range_profile_db", "range_profile")
    profile_db = (np.asarray(profile, dtype=np.float32) if getattr(dsp, "range_profile_db", None)
                  is not None else _db(profile, power=True))
    if profile_db.ndim == 1:
        profile_db = profile_db[None, :]
    threshold = _first(dsp, "range_threshold_db", "cfar_threshold_db", "profile_threshold_db")
    rd = _first(dsp, "range_doppler_db", "range_doppler")
    ra = _first(dsp, "range_azimuth_db", "range_azimuth")
    names = [a.name or f"rx{i + 1}" for i, a in enumerate(project.rig.radar.rx)]
    if profile_db.shape[0] != len(names):
        names = [f"ch{i + 1}" for i in range(profile_db.shape[0])]
    return RadarView(
        range_axis_m=range_axis,
        profile_db=profile_db,
        threshold_db=None if threshold is None else np.asarray(threshold, dtype=np.float32),
        velocity_axis_mps=np.asarray(_first(dsp, "velocity_axis_mps", "velocity_axis"),
                                     dtype=np.float64),
        range_doppler_db=np.asarray(rd, dtype=np.float32),
        azimuth_axis_deg=np.asarray(_first(dsp, "azimuth_axis_deg", "azimuth_axis"),
                                    dtype=np.float64),
        range_azimuth_db=np.asarray(ra, dtype=np.float32),
        detections=_detections_from(dsp, radar_transform),
        channel_names=names,
    )


def _radar_view(frame: Any, project: Project, notes: list[str]) -> RadarView | None:
    radar_transform = frame.radar_buffers.sensor.transform
    dsp = getattr(frame, "dsp", None)
    if dsp is not None:
        return _radar_view_from_dsp(dsp, project, radar_transform)
    from app.preview_radar import preview_radar_view

    notes.append("radar front end / DSP not in the pipeline yet: preview radar chain")
    return preview_radar_view(frame, project)


def build_frame_view(frame: Any, project: Project, *, render_count: int = 0) -> FrameView:
    """Extract what the panels draw from a pipeline frame (runs in the worker thread)."""
    notes: list[str] = []
    tof = _tof_view(frame, project, notes)
    radar = _radar_view(frame, project, notes)
    return FrameView(
        index=frame.index,
        time_s=float(frame.time_s),
        tof=tof,
        radar=radar,
        object_poses=np.asarray(frame.object_poses),
        rig_pose=np.asarray(frame.rig_pose),
        timings_ms=dict(frame.timings_ms),
        render_count=render_count,
        notes=notes,
    )
