"""Preflight: everything a run needs checked before any frame is computed.

:func:`check` lists every problem of a validated :class:`~simcore.scene.model.Project` that
its schema cannot see: rules across the radar, ToF and DSP configurations, derived
quantities (wavelength, beat frequencies, étendue, velocities, delays) that must be finite
and in range, mesh files (path policy, type, size, indices, finiteness) and the memory a
frame would need against a budget. :func:`estimate_cost` gives the numbers behind the
memory and disk check. ``tofradar validate`` prints the problems, ``tofradar run`` and the
GUI refuse to start while there are any. Every message is one line naming the field, the
value and the allowed range.

The estimate is an upper bound built from array sizes (render buffers, radar cube, DSP maps,
meshes) plus the interpreter's own footprint; it is not a measurement.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from simcore.scene.base import MAX_COORDINATE_M, MAX_SPEED_MPS, MAX_TIME_S, check_name
from simcore.scene.files import reference_path, reference_problem
from simcore.scene.geometry import Box, Cylinder, Mesh, Plane, Sphere
from simcore.scene.mesh_files import (
    MAX_MESH_FILE_BYTES,
    MESH_SUFFIXES,
    MeshError,
    read_mesh_arrays,
)
from simcore.scene.model import Project
from simcore.scene.motion import Motion, Pose
from simcore.scene.radar_config import SPEED_OF_LIGHT, RadarConfig
from simcore.scene.tof_config import TofCameraConfig

#: Longest run accepted (frames) and largest seed (HDF5 stores it as a signed 64-bit int).
MAX_FRAMES = 10_000_000
MAX_SEED = 2**63 - 1
#: Closest approach of a point target or corner reflector to a radar antenna (m).
MIN_CLEARANCE_M = 0.01
#: Most pixels of the bird's-eye image.
MAX_BEV_PIXELS = 16_000_000
#: Python, numpy, VTK and finufft loaded, before any frame (bytes).
BASE_MEMORY_BYTES = 400 * 2**20
#: Bytes per render pixel: float buffers (range, points, normals, velocities, …), the
#: raster and the ray directions, with temporaries.
BYTES_PER_RENDER_PIXEL = 200
#: Bytes per radar scatterer (positions, weights, phases, per-task NUFFT strengths).
BYTES_PER_SCATTERER = 400
#: Bytes per mesh triangle (points, normals, indices, VTK's copies).
BYTES_PER_TRIANGLE = 400
#: Fraction of the available memory a run may plan to use by default.
MEMORY_BUDGET_FRACTION = 0.8
#: Rough frame-time model (s per unit); calibrated on office.json, 2-core machine.
SECONDS_PER_RENDER_PIXEL = 6e-8
SECONDS_PER_NUFFT_POINT = 2e-9
SECONDS_PER_DSP_CELL = 5e-9


class RunError(RuntimeError):
    """A run cannot go on, for a reason explained in one line (no traceback needed)."""


def _size(n: float) -> str:
    """Bytes as text with a binary prefix (B … EiB)."""
    for unit in ("B", "KiB", "MiB", "GiB", "TiB", "PiB"):
        if abs(n) < 1024:
            return f"{n:.1f} {unit}" if unit != "B" else f"{int(n)} B"
        n /= 1024
    return f"{n:.1f} EiB"


@dataclass(frozen=True)
class CostEstimate:
    """Upper-bound resources of one frame of a project.

    Attributes
    ----------
    render_pixels : int
        Pixels rendered per frame (ToF and radar passes, supersampling included).
    scatterers : int
        Most radar scatterers per frame (one per radar facet and per point target).
    transforms : int
        NUFFTs per frame (one per chirp, Tx and Rx).
    memory_bytes : int
        Peak memory of one worker process (bytes).
    disk_bytes_per_frame : int
        Uncompressed bytes one frame adds to the dataset.
    seconds_per_frame : float
        Rough compute time of one frame on one core pair (s).
    mesh_triangles : int
        Triangles of the scene's meshes (an upper bound from file sizes when not parsed).
    memory_parts : tuple of (str, int)
        Where the memory goes: (field or stage, bytes), largest first.
    """

    render_pixels: int
    scatterers: int
    transforms: int
    memory_bytes: int
    disk_bytes_per_frame: int
    seconds_per_frame: float
    mesh_triangles: int = 0
    memory_parts: tuple[tuple[str, int], ...] = ()

    def describe(self) -> str:
        """One line: pixels, scatterers, NUFFTs, memory, disk and time per frame."""
        return (f"{self.render_pixels:,} render pixels, ≤ {self.scatterers:,} scatterers, "
                f"{self.transforms:,} NUFFTs per frame; memory ≈ {_size(self.memory_bytes)}, "
                f"disk ≤ {_size(self.disk_bytes_per_frame)} per frame, "
                f"≈ {self.seconds_per_frame:.2g} s per frame")


def _radar_sizes(project: Project, rc: RadarConfig) -> dict[str, int]:
    """Sizes of a radar's products.

    Without building any axis (fields may be huge).
    """
    dc = project.dsp
    n_fft = dc.range_fft_size or 1 << max(0, (rc.samples_per_chirp - 1).bit_length())
    n_bins = n_fft if rc.complex_iq else n_fft // 2
    bin_m = rc.sample_rate_hz / n_fft * SPEED_OF_LIGHT / (2.0 * rc.slope_hz_per_s)
    if dc.max_range_m is not None and math.isfinite(bin_m) and bin_m > 0:
        n_bins = min(n_bins, int(dc.max_range_m / bin_m) + 1)
    n_dop = dc.doppler_fft_size or 2 * (1 << max(0, (rc.chirps_per_frame - 1).bit_length()))
    n_az = int(math.floor((dc.azimuth_max_deg - dc.azimuth_min_deg) / dc.azimuth_step_deg
                          + 1e-9)) + 1
    n_el = int(math.floor((dc.elevation_max_deg - dc.elevation_min_deg)
                          / dc.elevation_step_deg + 1e-9)) + 1
    r_max = max(n_bins - 1, 1) * bin_m if math.isfinite(bin_m) else math.inf
    max_az = math.radians(max(abs(dc.azimuth_min_deg), abs(dc.azimuth_max_deg)))
    half = r_max * min(1.0, math.sin(min(max_az, math.pi / 2)))
    bev = (2 * half / dc.bev_resolution_m + 1) * (r_max / dc.bev_resolution_m + 1)
    return {"n_fft": n_fft, "n_bins": max(n_bins, 0), "n_dop": n_dop, "n_az": n_az,
            "n_el": n_el, "bev_pixels": int(min(bev, 2**62)) if math.isfinite(bev) else 2**62}


def _mesh_triangle_bound(project: Project, base_dir: Path | None) -> int:
    """Upper bound on mesh triangles from the file sizes (≥ 12 bytes per triangle)."""
    total = 0
    for obj in project.objects:
        if isinstance(obj.geometry, Mesh):
            path = _mesh_path(base_dir, obj.geometry.path)
            try:
                size = path.stat().st_size if path.is_file() else 0
            except OSError:
                size = 0
            total += min(size, MAX_MESH_FILE_BYTES) // 12
    return total


def estimate_cost(project: Project, *, base_dir: Path | None = None,
                  mesh_triangles: int | None = None,
                  mesh_area_m2: float = 0.0) -> CostEstimate:
    """Estimate the memory, disk and time one frame of ``project`` needs.

    Parameters
    ----------
    project : Project
        A validated project.
    base_dir : Path, optional
        The project's folder (for mesh file sizes).
    mesh_triangles : int, optional
        Triangles of the scene's meshes when known (else bounded from file sizes).
    mesh_area_m2 : float
        Surface of the scene's meshes, scaled, when known (m²): split into 10 cm facets.

    Returns
    -------
    CostEstimate
    """
    if mesh_triangles is None:
        mesh_triangles = _mesh_triangle_bound(project, base_dir)
    n_point = sum(1 for o in project.objects if o.geometry.kind in ("point_target",
                                                                    "corner_reflector"))
    # Surface facets (at most 10 cm, fixed to the objects): about half face the radar.
    scatterers = (int(0.5 * _surface_facets(project, mesh_triangles, mesh_area_m2)) + n_point
                  if project.sensors_of_kind("radar") else 0)
    parts: dict[str, int] = {}
    render_px = transforms = disk = 0
    seconds = 0.0
    rate = project.timeline.frame_rate_hz
    # Every sensor: memory while it runs, disk and time per frame scaled by the share of
    # frames it captures in.
    for name, tof in project.sensors_of_kind("tof").items():
        assert isinstance(tof, TofCameraConfig)
        share = 1.0 / tof.frame_divider(rate)
        where = project.sensor_path(name)
        tof_px = tof.width * tof.height * tof.supersampling**2
        tof_bytes = tof_px * BYTES_PER_RENDER_PIXEL
        if tof.motion_artifacts and tof.motion_sampling == "renders":
            tof_px *= 4                     # four renders at the samples' times
            tof_bytes *= 4
        elif tof.motion_artifacts:          # reprojection: the four samples' range and points
            tof_bytes += tof_px * 4 * 16
        parts[f"{where} render (width × height × supersampling²)"] = tof_bytes
        render_px += tof_px
        seconds += share * SECONDS_PER_RENDER_PIXEL * tof_px
        disk += int(share * tof.height * tof.width * 37)
    ffts_all = angle_all = 0
    for name, rc in project.sensors_of_kind("radar").items():
        assert isinstance(rc, RadarConfig)
        share = 1.0 / rc.frame_divider(rate)
        where = project.sensor_path(name)
        radar_px = rc.render_width * rc.render_height * rc.render_supersampling**2
        n_ch = len(rc.tx) * len(rc.rx)
        n_nufft = rc.chirps_per_frame * n_ch
        s = _radar_sizes(project, rc)
        cube = rc.chirps_per_frame * n_ch * rc.samples_per_chirp * 16 * 4
        ffts_all += (rc.chirps_per_frame * n_ch * s["n_fft"]
                     + s["n_dop"] * n_ch * s["n_bins"]) * 8 * 3
        el = s["n_el"] if any(a.position_mm[1] for a in (*rc.tx, *rc.rx)) else 1
        angle_all += (s["n_bins"] * s["n_az"] * el * 8 + s["n_az"] * el * n_ch * 32
                      + s["bev_pixels"] * 4 * 3)
        parts[f"{where} render (render_width × render_height × render_supersampling²)"] = (
            radar_px * BYTES_PER_RENDER_PIXEL)
        parts[f"{where} scatterers (surface facets of the objects)"] = (
            scatterers * BYTES_PER_SCATTERER * 2)
        parts[f"{where} ADC cube (chirps_per_frame × tx × rx × samples_per_chirp)"] = cube
        render_px += radar_px
        transforms += n_nufft
        sample = 8 if rc.complex_iq else 4
        disk += int(share * (n_ch * rc.chirps_per_frame * rc.samples_per_chirp * sample
                             + rc.chirps_per_frame * len(rc.tx) * 8
                             + (n_ch + 1) * s["n_bins"] * 4 + s["n_dop"] * s["n_bins"] * 4
                             + s["n_az"] * s["n_bins"] * 4 + s["bev_pixels"] * 4
                             + project.dsp.max_detections * 36))
        seconds += share * (SECONDS_PER_RENDER_PIXEL * radar_px
                            + SECONDS_PER_NUFFT_POINT * n_nufft
                            * (scatterers + rc.samples_per_chirp)
                            + SECONDS_PER_DSP_CELL * (n_ch * s["n_dop"] * s["n_bins"]
                                                      + s["n_bins"] * s["n_az"] * el))
    parts["dsp FFTs (range_fft_size, doppler_fft_size)"] = ffts_all
    parts["dsp angle maps (azimuth/elevation steps, bev_resolution_m)"] = angle_all
    parts["mesh triangles"] = mesh_triangles * BYTES_PER_TRIANGLE
    memory = BASE_MEMORY_BYTES + sum(parts.values())
    disk += 8 + 128 * (1 + len(project.objects))
    ordered = tuple(sorted(parts.items(), key=lambda kv: -kv[1]))
    return CostEstimate(render_pixels=render_px, scatterers=scatterers,
                        transforms=transforms, memory_bytes=int(memory),
                        disk_bytes_per_frame=int(disk), seconds_per_frame=float(seconds),
                        mesh_triangles=int(mesh_triangles), memory_parts=ordered)


def _surface_facets(project: Project, mesh_triangles: int, mesh_area_m2: float) -> float:
    """Surface facets of every object (10 cm facets; tessellations' own triangles)."""
    facet_area = 0.5 * 0.1 * 0.1 * 0.5           # a facet is about half a 10 cm square
    total = float(mesh_triangles) + mesh_area_m2 / facet_area
    for o in project.objects:
        g = o.geometry
        if isinstance(g, Box):
            a, b, c = g.size_m
            total += 2 * (a * b + b * c + c * a) / facet_area + 12
        elif isinstance(g, Plane):
            total += g.size_m[0] * g.size_m[1] / facet_area + 2
        elif isinstance(g, Sphere):
            total += max(4 * math.pi * g.radius_m**2 / facet_area, 25_600)
        elif isinstance(g, Cylinder):
            r, h = g.radius_m, g.height_m
            total += max((2 * math.pi * r * h + 2 * math.pi * r * r) / facet_area, 508)
        elif g.kind == "person":  # 17 ellipsoid segments of 28 × 14 tessellation
            total += 17 * 2 * 28 * 13
    return total


def available_memory_bytes() -> int:
    """Memory the system can give a new process now (MemAvailable; else physical RAM)."""
    try:
        with open("/proc/meminfo", encoding="ascii") as fh:
            for line in fh:
                if line.startswith("MemAvailable:"):
                    return int(line.split()[1]) * 1024
    except (OSError, ValueError, IndexError):
        pass
    try:
        return int(os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES"))
    except (ValueError, OSError, AttributeError):
        return 8 * 2**30


def default_memory_budget() -> int:
    """Default memory budget of one run: 80 % of the available memory."""
    return int(available_memory_bytes() * MEMORY_BUDGET_FRACTION)


def _mesh_path(base_dir: Path | None, mesh_path: str) -> Path:
    return reference_path(base_dir, mesh_path)


def mesh_path_problem(base_dir: Path | None, mesh_path: str, *,
                      allow_outside_paths: bool = False) -> str | None:
    """Why a mesh path breaks the path policy (None if it does not).

    Inside the project folder (after resolving ``..`` and symlinks) unless
    ``allow_outside_paths``; a regular file with a mesh suffix, not a device, FIFO,
    socket, directory or symlink loop (:func:`simcore.scene.files.reference_problem`).
    """
    return reference_problem(base_dir, mesh_path, what="mesh", suffixes=MESH_SUFFIXES,
                             max_bytes=MAX_MESH_FILE_BYTES,
                             allow_outside_paths=allow_outside_paths)


def _reach(pose: Pose, motion: Motion, t_end: float) -> tuple[float, float]:
    """Largest distance from the origin and largest speed of a body over [0, t_end]."""
    base = np.asarray(pose.position_m, dtype=np.float64)
    if motion.keyframes:
        offsets = np.array([k.position_m for k in motion.keyframes], dtype=np.float64)
        reach = float(np.linalg.norm(base + offsets, axis=1).max())
        times = np.array([k.time_s for k in motion.keyframes])
        steps = np.linalg.norm(np.diff(offsets, axis=0), axis=1) / np.maximum(
            np.diff(times), 1e-300) if len(times) > 1 else np.zeros(1)
        return max(reach, float(np.linalg.norm(base))), float(steps.max())
    v = np.asarray(motion.velocity_mps, dtype=np.float64)
    reach = max(float(np.linalg.norm(base)), float(np.linalg.norm(base + v * t_end)))
    return reach, float(np.linalg.norm(v))


def timeline_frames(project: Project) -> float:
    """Frames of the project's timeline (as ``Timeline.n_frames``, without overflowing)."""
    frames = project.timeline.duration_s * project.timeline.frame_rate_hz
    return float(max(1, round(frames))) if math.isfinite(frames) else math.inf


def _physics_problems(project: Project, n_frames: int) -> list[str]:
    """Derived quantities that must be finite and in range."""
    out: list[str] = []
    radars = {project.sensor_path(n): c for n, c in project.sensors_of_kind("radar").items()}
    tofs = {project.sensor_path(n): c for n, c in project.sensors_of_kind("tof").items()}
    for where, rc in radars.items():
        assert isinstance(rc, RadarConfig)
        out += _radar_problems(project, where, rc)
    for where, tof in tofs.items():
        assert isinstance(tof, TofCameraConfig)
        out += _finite({
            f"{where} electrons per radiance": tof.electrons_per_radiance,
            f"{where} signal electrons at 1 m": tof.signal_electrons_at_1m,
            f"{where} unambiguous range (m)": tof.unambiguous_range_m,
        })
    # Motion: every body stays within the world and below the speed limit; delays finite.
    offsets = [float(c.trigger_offset_s)  # type: ignore[attr-defined]
               for c in project.sensor_configs().values()]
    t_end = (n_frames / project.timeline.frame_rate_hz + max(offsets, default=0.0)
             + max((c.frame_duration_s for c in radars.values()  # type: ignore[attr-defined]
                    ), default=0.0)
             + 4 * max((c.sample_interval_s for c in tofs.values()  # type: ignore[attr-defined]
                        ), default=0.0))
    rig_reach = rig_speed = 0.0
    for i, rig in enumerate(project.all_rigs()):
        reach, speed = _reach(rig.pose, rig.motion, t_end)
        where = "rig" if i == 0 else f"rigs[{i - 1}]"
        if reach > MAX_COORDINATE_M:
            out.append(f"{where}.motion: the rig reaches {reach:.3g} m from the origin within "
                       f"{t_end:.3g} s; allowed ±{MAX_COORDINATE_M:g} m")
        rig_reach, rig_speed = max(rig_reach, reach), max(rig_speed, speed)
    for i, obj in enumerate(project.objects):
        reach, speed = _reach(obj.pose, obj.motion, t_end)
        if reach > MAX_COORDINATE_M:
            out.append(f"objects[{i}].motion: {obj.name!r} reaches {reach:.3g} m from the "
                       f"origin within {t_end:.3g} s; allowed ±{MAX_COORDINATE_M:g} m")
        elif speed + rig_speed > MAX_SPEED_MPS:
            out.append(f"objects[{i}].motion: relative speed {speed + rig_speed:.3g} m/s to "
                       f"the rig; allowed at most {MAX_SPEED_MPS:g} m/s")
        delay = 2 * (reach + rig_reach) / SPEED_OF_LIGHT
        if not math.isfinite(delay):
            out.append(f"objects[{i}].pose: round-trip delay {delay!r} s is not finite")
    out += _clearance_problems(project, n_frames)
    return out


def _finite(derived: dict[str, float]) -> list[str]:
    """Derived quantities that must be finite and in range, one line each."""
    # float32 carries the images and the IF cube: stay well inside its range.
    return [f"{name}: derived value {value:.3g} is out of range; allowed (1e-30, 1e30)"
            for name, value in derived.items()
            if not (math.isfinite(value) and 1e-30 < value < 1e30)]


def _radar_problems(project: Project, where: str, rc: RadarConfig) -> list[str]:
    """A radar's derived quantities and FFT sizes against the DSP settings."""
    dc = project.dsp
    out = _finite({
        f"{where} wavelength (m)": rc.wavelength_m,
        f"{where} chirp slope (Hz/s)": rc.slope_hz_per_s,
        f"{where} range resolution (m)": rc.range_resolution_m,
        f"{where} unambiguous range (m)": rc.max_range_m,
        f"{where} velocity resolution (m/s)": rc.velocity_resolution_mps,
        f"{where} unambiguous velocity (m/s)": rc.max_velocity_mps,
        f"{where} frame duration (s)": rc.frame_duration_s,
    })
    s = _radar_sizes(project, rc)
    if dc.range_fft_size is not None and dc.range_fft_size < rc.samples_per_chirp:
        out.append(f"dsp.range_fft_size: {dc.range_fft_size} is below "
                   f"{where}.samples_per_chirp = {rc.samples_per_chirp}; allowed "
                   f"[{rc.samples_per_chirp}, 65536]")
    if dc.doppler_fft_size is not None and dc.doppler_fft_size < rc.chirps_per_frame:
        out.append(f"dsp.doppler_fft_size: {dc.doppler_fft_size} is below "
                   f"{where}.chirps_per_frame = {rc.chirps_per_frame}; allowed "
                   f"[{rc.chirps_per_frame}, 65536]")
    n_fft = max(s["n_fft"], 1)
    bin_m = rc.sample_rate_hz / n_fft * SPEED_OF_LIGHT / (2.0 * rc.slope_hz_per_s)
    if dc.max_range_m is not None and dc.max_range_m < bin_m:
        out.append(f"dsp.max_range_m: {dc.max_range_m:g} m keeps fewer than 2 range bins "
                   f"(bin spacing {bin_m:.4g} m); allowed [{bin_m:.4g}, 1e5] m or null")
    if dc.min_range_m >= rc.max_range_m:
        out.append(f"dsp.min_range_m: {dc.min_range_m:g} m is beyond the radar's unambiguous "
                   f"range {rc.max_range_m:.4g} m; allowed [0, {rc.max_range_m:.4g}) m")
    if s["bev_pixels"] > MAX_BEV_PIXELS:
        out.append(f"dsp.bev_resolution_m: {dc.bev_resolution_m:g} m gives a bird's-eye image "
                   f"of {s['bev_pixels']:.3g} pixels; at most {MAX_BEV_PIXELS} (coarser "
                   "resolution or a smaller max_range_m)")
    return out


def _clearance_problems(project: Project, n_frames: int) -> list[str]:
    """Point targets and corner reflectors must stay clear of the radar's antennas.

    Their scatterers are placed analytically (not through the render, whose near plane
    keeps surfaces away), so one at an antenna would divide by a zero distance. Checked at
    up to 128 frame times spread over the run.
    """
    from simcore.scene.motion import rigid_state
    from simcore.scene.snapshot import _sensor_state

    analytic = [i for i, o in enumerate(project.objects)
                if o.geometry.kind in ("point_target", "corner_reflector")]
    radars = project.sensors_of_kind("radar")
    if not analytic or not radars:
        return []
    elements = {n: np.concatenate([rc.tx_positions_m(), rc.rx_positions_m()])  # type: ignore[attr-defined]
                for n, rc in radars.items()}
    frames = np.unique(np.linspace(0, max(n_frames - 1, 0), min(n_frames, 128)).astype(int))
    worst: dict[int, tuple[float, float]] = {}
    for k in frames:
        t = project.timeline.frame_time(int(k))
        # Only the radars and the analytic objects (as take_snapshot places them).
        placed = []
        for n, rc in radars.items():
            rig = project.sensor_rig(n)
            pose = _sensor_state(rigid_state(rig.pose, rig.motion, t),
                                 rc.pose_on_rig.matrix()).transform  # type: ignore[attr-defined]
            placed.append(elements[n] @ pose[:3, :3].T + pose[:3, 3])
        ants = np.concatenate(placed)
        for i in analytic:
            obj = project.objects[i]
            origin = rigid_state(obj.pose, obj.motion, t).transform[:3, 3]
            d = float(np.linalg.norm(ants - origin, axis=1).min())
            if d < worst.get(i, (math.inf, 0.0))[0]:
                worst[i] = (d, t)
    return [f"objects[{i}].pose: {project.objects[i].name!r} comes within {d:.3g} m of a radar "
            f"antenna at t = {t:.3g} s; allowed at least {MIN_CLEARANCE_M} m"
            for i, (d, t) in sorted(worst.items()) if d < MIN_CLEARANCE_M]


def check(project: Project, *, base_dir: Path | None = None,
          memory_budget_bytes: int | None = None, n_frames: int | None = None,
          seed: int | None = None, allow_outside_paths: bool = False,
          parse_meshes: bool = True) -> list[str]:
    """Every problem that would stop or spoil a run of ``project``, one line each.

    Parameters
    ----------
    project : Project
        A project that passed schema validation.
    base_dir : Path, optional
        The project's folder (mesh paths are relative to it); default: the working folder.
    memory_budget_bytes : int, optional
        Largest memory one frame may need (default: 80 % of the available memory).
    n_frames : int, optional
        Frames of the run (default: the project's timeline).
    seed : int, optional
        Seed of the run (default: the project's).
    allow_outside_paths : bool
        Accept mesh files outside the project folder.
    parse_meshes : bool
        Parse every mesh file (counts, indices, finiteness), not just its path and size.

    Returns
    -------
    list of str
        One line per problem, naming the field, the value and the allowed range; empty
        when the project can run.
    """
    out: list[str] = []
    if not project.objects:
        out.append("objects: the scene has no objects; add at least one (allowed 1 or more)")
    for i, obj in enumerate(project.objects):
        try:
            check_name(obj.name)
        except ValueError as exc:
            out.append(f"objects[{i}].name: {exc}")
    for i, mat in enumerate(project.materials):
        try:
            check_name(mat.name)
        except ValueError as exc:
            out.append(f"materials[{i}].name: {exc}")
    for field in ("name", "description"):
        text = getattr(project, field)
        if "\x00" in text or len(text) > 100_000:
            out.append(f"{field}: must have no NUL character and at most 100000 characters")
    run_seed = project.seed if seed is None else seed
    if not 0 <= run_seed <= MAX_SEED:
        out.append(f"seed: {run_seed} is out of range; allowed [0, {MAX_SEED}]")
    frames = timeline_frames(project) if n_frames is None else n_frames
    if frames > MAX_FRAMES:
        source = "timeline.duration_s × frame_rate_hz" if n_frames is None else "--frames"
        out.append(f"{source}: {frames:.3g} frames; allowed at most {MAX_FRAMES}")
        frames = MAX_FRAMES
    span = frames / project.timeline.frame_rate_hz
    if not span <= MAX_TIME_S:
        out.append(f"timeline.frame_rate_hz: {frames:.3g} frames at "
                   f"{project.timeline.frame_rate_hz:.3g} Hz span {span:.3g} s of simulated "
                   f"time; allowed at most {MAX_TIME_S:g} s")
        return out
    out += _physics_problems(project, int(frames))
    out += _clip_problems(project, base_dir, allow_outside_paths=allow_outside_paths)
    # Meshes: path policy and file type first (cheap), then the cost, then parsing.
    mesh_ok: list[tuple[int, Path, Mesh]] = []
    for i, obj in enumerate(project.objects):
        if isinstance(obj.geometry, Mesh):
            problem = mesh_path_problem(base_dir, obj.geometry.path,
                                        allow_outside_paths=allow_outside_paths)
            if problem:
                out.append(f"objects[{i}].geometry.path: {problem}")
            else:
                mesh_ok.append((i, _mesh_path(base_dir, obj.geometry.path), obj.geometry))
    cost = estimate_cost(project, base_dir=base_dir)
    budget = default_memory_budget() if memory_budget_bytes is None else memory_budget_bytes
    if cost.memory_bytes > budget:
        out.append(_over_budget(cost, budget))
        return out   # parsing huge meshes would only take long
    if parse_meshes:
        out += _mesh_problems(project, mesh_ok, base_dir, budget)
    return out


def _clip_problems(project: Project, base_dir: Path | None, *,
                   allow_outside_paths: bool) -> list[str]:
    """Every person's BVH clip: the path policy of meshes, then what it does to the person."""
    from simcore.scene.limits import MAX_BVH_BYTES
    from simcore.scene.people.bvh import BvhError, clip_motion_problems, load_bvh
    from simcore.scene.people.config import Person
    from simcore.scene.people.skeleton import build_skeleton

    out: list[str] = []
    for i, obj in enumerate(project.objects):
        geom = obj.geometry
        if not isinstance(geom, Person) or geom.motion.bvh is None:
            continue
        clip, where = geom.motion.bvh, f"objects[{i}].geometry.motion.bvh.path"
        problem = reference_problem(base_dir, clip.path, what="BVH clip",
                                    max_bytes=MAX_BVH_BYTES,
                                    allow_outside_paths=allow_outside_paths)
        if problem:
            out.append(f"{where}: {problem}")
            continue
        path = reference_path(base_dir, clip.path)
        try:
            motion = load_bvh(path)
            out += [f"{where}: {p}" for p in clip_motion_problems(
                motion, source=path.name, play_rate=clip.play_rate,
                leg_length_m=build_skeleton(geom.height_m, geom.build).leg_length_m,
                origin_m=float(np.linalg.norm(obj.pose.position_m)))]
        except BvhError as exc:
            out.append(f"{where}: {exc}")
    return out


def _over_budget(cost: CostEstimate, budget: int) -> str:
    field, part = cost.memory_parts[0]
    return (f"memory: a frame would need ≈ {_size(cost.memory_bytes)}, over the budget "
            f"of {_size(budget)}; most of it ({_size(part)}) for {field}")


def _mesh_problems(project: Project, mesh_ok: list[tuple[int, Path, Mesh]],
                   base_dir: Path | None, budget: int) -> list[str]:
    """Parse every mesh: its errors, its extent, and the memory of its facets (by area)."""
    out: list[str] = []
    area = 0.0
    for i, path, geom in mesh_ok:
        try:
            points, triangles = read_mesh_arrays(path)
        except MeshError as exc:
            out.append(f"objects[{i}].geometry.path: {exc}")
            continue
        extent = float(np.abs(points).max()) * geom.scale
        if extent > MAX_COORDINATE_M:
            out.append(f"objects[{i}].geometry.scale: mesh extent {extent:.3g} m; "
                       f"allowed at most {MAX_COORDINATE_M:g} m")
            continue
        tri = points[triangles]
        area += 0.5 * float(np.linalg.norm(np.cross(tri[:, 1] - tri[:, 0], tri[:, 2]
                                                    - tri[:, 0]), axis=1).sum()) \
            * geom.scale**2
    # Mesh facets are 10 cm like the primitives' (a scaled-up mesh has many more).
    cost = estimate_cost(project, base_dir=base_dir, mesh_area_m2=area)
    if area and cost.memory_bytes > budget:
        out.append(_over_budget(cost, budget).replace(
            "surface facets of the objects", "surface facets of the objects, meshes by "
            f"their {area:.3g} m² scaled by geometry.scale"))
    return out


__all__ = ["CostEstimate", "RunError", "available_memory_bytes", "check",
           "default_memory_budget", "estimate_cost", "mesh_path_problem", "timeline_frames"]
