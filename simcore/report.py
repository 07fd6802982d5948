"""Validation report: the reference simulator's experiments, regenerated as figures.

:func:`generate_report` runs the bundled example scenes through the whole pipeline, measures
each phenomenon against an independent answer (scene geometry, the radar equation written
out here from its constants, the exact direct-sum IF synthesis), draws one PNG per
experiment and writes ``README.md`` with a paragraph and the numbers for each. The numbers
are returned too, so that tests can hold them to the bars of the earlier issues.
"""

from __future__ import annotations

import copy
import json
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy import ndimage

from simcore.dsp import process_frame
from simcore.pipeline import Frame, Simulator
from simcore.render import RenderRequest, SceneRenderer
from simcore.report_multipath import multipath_section, tof_multipath_figure
from simcore.report_products import products_section
from simcore.resources import example_path
from simcore.scene.geometry import Box, CornerReflector, Cylinder, Plane, Sphere
from simcore.scene.model import Project, SceneObject, SensorRig
from simcore.scene.motion import Motion, Pose
from simcore.scene.people.expand import expand_people
from simcore.scene.project_io import load_project
from simcore.scene.radar_config import COVERAGE_LEVEL_DB, SPEED_OF_LIGHT, CosinePattern, RadarConfig
from simcore.scene.snapshot import take_snapshot
from simcore.sensors.radar import radar_scatterers, simulate_radar
from simcore.sensors.radar.scene import RadarScene
from simcore.sensors.radar.sensor import RadarSensor
from simcore.sensors.radar.synthesis import synthesize_if, synthesize_if_direct

#: The reference simulator's bars (from the issues): range ¼ bin, velocity 1 bin, angle 2°,
#: power 0.5 dB, IF error −60 dB, resolution change 1 dB.
BARS = {"range_bins": 0.25, "velocity_bins": 1.0, "angle_deg": 2.0, "power_db": 0.5,
        "if_error_db": -60.0, "resolution_db": 1.0}

R_REF_OHM = 50.0   # receiver reference impedance of the documented calibration


@dataclass
class Figure:
    """One figure of the report: file, title, reading paragraph."""

    file: str
    title: str
    text: str
    section: str | None = None   # figures of one section share a heading


@dataclass
class ReportResult:
    """Numbers and figures of a generated report."""

    out_dir: Path
    numbers: dict[str, Any] = field(default_factory=dict)
    figures: list[Figure] = field(default_factory=list)


def _plt() -> Any:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def _save(fig: Any, path: Path) -> None:
    """Write a figure as PNG and release it."""
    fig.savefig(path, dpi=110)
    _plt().close(fig)


def _object_id(project: Project, name: str) -> int:
    return project.object_by_name(name).id


# --------------------------------------------------------------------------- analytic truth


def expected_corner_amplitude_fs(config: RadarConfig, *, edge_m: float, range_m: float
                                 ) -> float:
    """IF amplitude (FS) of a boresight trihedral from the radar equation.

    ``P_r = P_t G_t G_r λ² σ / ((4π)³ R⁴)`` with ``σ = 4πa⁴/(3λ²)``; the receiver makes a
    tone of peak voltage ``√(2 R_ref P_r)`` times the IF voltage gain, seen through the
    first-order (or n-th order Butterworth) IF high-pass at the beat frequency, divided by
    the ADC full-scale voltage. The range FFT is normalised so that a tone of amplitude
    ``A`` reads ``A`` (docs/dsp.md).
    """
    lam = config.wavelength_m
    p_t = 1e-3 * 10 ** (config.tx_power_dbm / 10)
    g = 10 ** ((config.tx_gain_dbi + config.rx_gain_dbi) / 10)
    sigma = 4 * np.pi * edge_m**4 / (3 * lam**2)
    p_r = p_t * g * lam**2 * sigma / ((4 * np.pi) ** 3 * range_m**4)
    volts = np.sqrt(2 * R_REF_OHM * p_r) * 10 ** (config.if_gain_db / 20)
    f_b = 2 * config.slope_hz_per_s * range_m / SPEED_OF_LIGHT
    if config.if_highpass_hz > 0:
        ratio = f_b / config.if_highpass_hz
        order = config.if_highpass_order
        volts *= ratio**order / np.sqrt(1 + ratio ** (2 * order))
    if config.if_lowpass_hz > 0:  # Butterworth anti-aliasing low-pass magnitude
        volts /= np.sqrt(1 + (f_b / config.if_lowpass_hz) ** (2 * config.if_lowpass_order))
    return float(volts / config.adc_full_scale_v)


def corner_truth(project: Project, t: float) -> list[dict[str, Any]]:
    """Range, azimuth and radial velocity of every corner apex as the radar sees it."""
    snap = take_snapshot(project, t)
    radar = snap.sensors["radar"]
    out = []
    for obj, state in zip(project.objects, snap.objects, strict=True):
        if not isinstance(obj.geometry, CornerReflector):
            continue
        rel = state.origin - radar.position
        opt = radar.rotation.T @ rel
        rng = float(np.linalg.norm(rel))
        vel = float((state.velocity_mps - radar.velocity_mps) @ rel / rng)
        out.append({"name": obj.name, "range": rng, "velocity": vel,
                    "azimuth_deg": float(np.degrees(np.arctan2(opt[0], opt[2]))),
                    "world": state.origin.tolist()})
    return out


def _nearest(det: NDArray[Any], rng: float) -> int | None:
    if len(det) == 0:
        return None
    return int(np.argmin(np.abs(det["range"] - rng)))


# ------------------------------------------------------------------------------ experiments


def office_tof(frame: Frame, project: Project, out: Path) -> tuple[Figure, dict[str, Any]]:
    """Figure 1: ToF depth and amplitude of the office; retroreflector, chair, plate."""
    plt = _plt()
    tof = frame.outputs["tof"]
    gt_id, gt = tof.gt_object_id, tof.gt_range
    retro = gt_id == _object_id(project, "ir_retroreflector")
    backrest = gt_id == _object_id(project, "chair_backrest")
    plate = gt_id == _object_id(project, "metal_plate")
    wall = gt_id == _object_id(project, "back_wall")
    retro_range = float(np.nanmedian(gt[retro]))
    ring = ndimage.binary_dilation(retro, iterations=2) & ~retro & tof.valid
    err_ring = tof.depth_m[ring] - gt[ring]
    toward = np.sign(retro_range - gt[ring])
    pulled = float(np.mean(err_ring * toward > 0.01)) if ring.any() else 0.0
    far = wall & tof.valid & ~ndimage.binary_dilation(retro, iterations=6)
    numbers = {
        "retro_pixels": int(retro.sum()),
        "retro_invalid_fraction": float(np.mean(~tof.valid[retro])),
        "retro_depth_zero_fraction": float(np.mean(tof.depth_m[retro] == 0)),
        "ring_pixels": int(ring.sum()),
        "ring_pulled_fraction": pulled,
        "ring_median_abs_error_m": float(np.median(np.abs(err_ring))) if ring.any() else 0.0,
        "wall_median_abs_error_m": float(np.median(np.abs(tof.depth_m[far] - gt[far]))),
        "backrest_amplitude_dn": float(np.median(tof.amplitude[backrest])),
        "backrest_valid_fraction": float(np.mean(tof.valid[backrest])),
        "plate_amplitude_dn": float(np.median(tof.amplitude[plate])),
        "wall_amplitude_dn": float(np.median(tof.amplitude[wall])),
    }
    fig, axes = plt.subplots(1, 2, figsize=(13, 4.6), constrained_layout=True)
    depth = np.where(tof.valid, tof.depth_m, np.nan)
    cmap = plt.get_cmap("viridis").with_extremes(bad="0.55")
    im = axes[0].imshow(depth, cmap=cmap, vmin=0, vmax=6)
    fig.colorbar(im, ax=axes[0], label="depth (m); grey = invalid")
    amp = np.maximum(tof.amplitude, 1e-3)
    im = axes[1].imshow(np.log10(amp), cmap="gray", vmin=0, vmax=np.log10(amp.max()))
    fig.colorbar(im, ax=axes[1], label="log10 amplitude (DN)")
    for ax, title in zip(axes, ("ToF depth", "ToF amplitude"), strict=True):
        ax.set_title(f"{title} — office.json, t = {frame.time_s:.2f} s")
        ax.set_xlabel("column (px)")
        ax.set_ylabel("row (px)")
        for mask, label, colour in ((retro, "IR retroreflector", "red"),
                                    (backrest, "chair backrest", "orange"),
                                    (plate, "metal plate", "cyan")):
            rows, cols = np.nonzero(mask)
            if len(rows):
                ax.add_patch(plt.Rectangle((cols.min() - 1.5, rows.min() - 1.5),
                                           cols.max() - cols.min() + 3,
                                           rows.max() - rows.min() + 3, fill=False,
                                           ec=colour, lw=1.2))
                ax.text(cols.min(), rows.min() - 3, label, color=colour, fontsize=8)
    name = "fig1_office_tof.png"
    _save(fig, out / name)
    text = (
        f"The near-IR retroreflector saturates the camera: {numbers['retro_invalid_fraction']:.0%}"
        f" of its {numbers['retro_pixels']} pixels are invalid and report depth 0 "
        f"({numbers['retro_depth_zero_fraction']:.0%}), as a real pico flexx does. Cross-talk "
        f"(Gaussian, σ = {project.rig.tof.crosstalk_sigma_px} px, on the correlation images) "
        f"bleeds its signal into the {numbers['ring_pixels']} valid pixels around it, "
        f"{numbers['ring_pulled_fraction']:.0%} of which are pulled by more than 1 cm towards "
        f"the reflector's range (median error {numbers['ring_median_abs_error_m'] * 100:.1f} cm"
        f" against {numbers['wall_median_abs_error_m'] * 100:.1f} cm on the back wall away "
        f"from it). The chair's black backrest is barely visible: median amplitude "
        f"{numbers['backrest_amplitude_dn']:.0f} DN, {numbers['backrest_valid_fraction']:.0%} "
        f"valid, against {numbers['wall_amplitude_dn']:.0f} DN on the white back wall; the "
        f"metal plate on that wall returns {numbers['plate_amplitude_dn']:.0f} DN through "
        f"its specular lobe."
    )
    return Figure(name, "Office scene, ToF camera", text), numbers


def office_radar_profile(frame: Frame, project: Project, out: Path
                         ) -> tuple[Figure, dict[str, Any]]:
    """Figure 2: range-FFT spectrum per Rx with leakage roll-off, noise floor, corner peak."""
    plt = _plt()
    dsp = frame.outputs["radar"].dsp
    r = dsp.axes.range_m
    cr = corner_truth(project, frame.time_s)[0]
    k = int(np.argmin(np.abs(r - cr["range"])))
    profile = dsp.range_profile_db
    integrated = dsp.range_profile_integrated_db
    window = slice(max(k - 2, 0), k + 3)
    peak_db = float(integrated[window].max())
    around = np.r_[max(k - 40, 0):max(k - 6, 0), k + 6:min(k + 40, len(r))]
    clutter_db = float(np.median(integrated[around]))
    # Noise floor: the same receiver and DSP with no scatterers at all (noise, leakage).
    scat = _office_scatterers(frame, project)
    noise_profile = _receiver_profile_db(project, scat.subset(np.zeros(len(scat), bool)), 12)
    noise_db = float(np.median(noise_profile[r > 0.5]))
    nearest_surface = float(np.nanmin(frame.buffers["radar"].range_m))
    rise = integrated - noise_profile
    above = np.nonzero((r > 0.3) & (rise >= 6.0))[0]
    clutter_start = float(r[above[0]]) if len(above) else float("nan")
    band = (r >= 1.5) & (r <= 2.3)
    band_over = float(10 * np.log10(np.mean(10 ** (integrated[band] / 10))
                                    / np.mean(10 ** (noise_profile[band] / 10))))
    height = float(frame.snapshot.sensors["radar"].position[2])
    half_fov = project.rig.radar.render_fov_h_deg / 2
    near = r < 0.1
    numbers = {"corner_range_m": cr["range"], "corner_peak_db": peak_db,
               "nearest_surface_m": nearest_surface, "clutter_start_m": clutter_start,
               "clutter_1p5_2p3_over_noise_db": band_over, "radar_height_m": height,
               "corner_over_clutter_db": peak_db - clutter_db, "noise_floor_db": noise_db,
               "near_zero_db": float(integrated[near].min()) if near.any() else float("nan"),
               "leakage_peak_db": float(integrated[r < 0.15].max()),
               "max_scene_db": float(integrated.max())}
    fig, ax = plt.subplots(figsize=(11, 4.6), constrained_layout=True)
    for ch in range(profile.shape[0]):
        ax.plot(r, profile[ch], lw=0.9, label=f"Rx channel {ch + 1}")
    ax.axvline(cr["range"], color="k", ls="--", lw=0.8)
    ax.annotate("corner reflector behind the\nradar-transparent paper box",
                xy=(cr["range"], peak_db), xytext=(cr["range"] - 2.2, peak_db - 4),
                arrowprops={"arrowstyle": "->"}, fontsize=9)
    ax.plot(r, noise_profile, color="0.5", lw=0.8,
            label=f"receiver alone: noise floor {noise_db:.0f} dBFS (and leakage)")
    ax.axvspan(1.5, 2.3, color="tab:green", alpha=0.12,
               label=f"floor clutter 1.5–2.3 m ({band_over:.0f} dB over the noise)")
    ax.axvspan(0, 0.2, color="orange", alpha=0.15, label="IF high-pass / leakage roll-off")
    ax.set_xlabel("range (m)")
    ax.set_ylabel("power (dBFS)")
    ax.set_ylim(top=peak_db + 8)
    ax.set_title(f"Range-FFT spectrum per Rx — office.json, t = {frame.time_s:.2f} s "
                 "(Hann window, chirp-averaged)")
    ax.set_xlim(0, r[-1])
    ax.legend(loc="upper right", fontsize=8)
    ax.grid(alpha=0.3)
    name = "fig2_office_range_profile.png"
    _save(fig, out / name)
    text = (
        f"Every Rx channel shows the same features as the measured BGT60TR13C spectrum: the "
        f"80 kHz IF high-pass rolls the spectrum off towards 0 m (down to "
        f"{numbers['near_zero_db']:.0f} dBFS) and attenuates the Tx→Rx leakage tone to "
        f"{numbers['leakage_peak_db']:.0f} dBFS, and the receiver noise floor (the same "
        f"receiver and DSP without any scatterer) sits at {noise_db:.0f} dBFS. The radar "
        f"render covers the antennas' field of view (±{half_fov:.0f}°, the two-way element "
        f"pattern down to {COVERAGE_LEVEL_DB:.0f} dB), so the floor {height:.2f} m below "
        f"the radar is in the "
        f"scene from {nearest_surface:.2f} m, where the render's lower edge meets it: its "
        f"grazing clutter lifts the spectrum 6 dB over the noise from {clutter_start:.2f} m "
        f"and by {band_over:.0f} dB on average between 1.5 and 2.3 m (section 7.2 separates "
        f"the floor's own contribution), so no stretch of bare noise precedes the room's "
        f"objects; the "
        f"desks, chair, walls and the walking person add their returns beyond, and the "
        f"corner reflector hidden behind the paper box (paper transmits most of the 60 GHz "
        f"wave, and is opaque in near-IR) stands "
        f"{numbers['corner_over_clutter_db']:.1f} dB over the surrounding clutter at "
        f"{cr['range']:.2f} m ({peak_db:.1f} dBFS)."
    )
    return Figure(name, "Office scene, radar range spectrum", text), numbers


def _footprint(obj: Any, transform: NDArray[np.float64]) -> NDArray[np.float64] | None:
    """World x–y outline (closed polygon) of an object's bounding box."""
    g = obj.geometry
    if isinstance(g, Box):
        half = np.array(g.size_m) / 2
    elif isinstance(g, Cylinder):
        half = np.array([g.radius_m, g.radius_m, g.height_m / 2])
    elif isinstance(g, Sphere):
        half = np.full(3, g.radius_m)
    elif isinstance(g, Plane):
        half = np.array([g.size_m[0] / 2, g.size_m[1] / 2, 0.0])
    elif isinstance(g, CornerReflector):
        half = np.full(3, g.edge_m / 2)
    else:
        return None
    corners = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)])
    world = (corners * half) @ transform[:3, :3].T + transform[:3, 3]
    xy = world[:, :2]
    from scipy.spatial import ConvexHull

    hull = ConvexHull(xy)
    return np.vstack([xy[hull.vertices], xy[hull.vertices[:1]]])


def office_range_azimuth(frame: Frame, project: Project, out: Path
                         ) -> tuple[Figure, dict[str, Any]]:
    """Figure 3: range–azimuth map with OS-CFAR detections; point cloud on a top view."""
    plt = _plt()
    dsp = frame.outputs["radar"].dsp
    det = dsp.detections
    cr = corner_truth(project, frame.time_s)[0]
    # The corner's detection: the one its cell's power labels as the corner, nearest its
    # range (a cell can hold a detection per azimuth peak; others may share the range).
    records = dsp.detection_records(frame.index)
    mine = np.flatnonzero(frame.outputs["radar"].labels.object_id
                          == _object_id(project, cr["name"]))
    k = _nearest(records, cr["range"]) if not len(mine) else int(
        mine[np.argmin(np.abs(records["range"][mine] - cr["range"]))])
    cr_err = (float(np.linalg.norm(det.xyz_world_m[k] - np.array(cr["world"])))
              if k is not None and det.xyz_world_m is not None else float("nan"))
    # Ground-truth labels: the object giving most of each detection's cell power.
    floor_det = frame.outputs["radar"].labels.object_id == _object_id(project, "floor")
    numbers: dict[str, Any] = {"detections": int(len(det.range_m)),
                               "corner_detected_error_m": cr_err,
                               "cfar": project.dsp.cfar_method,
                               "floor_detections": int(floor_det.sum())}
    height = float(frame.snapshot.sensors["radar"].position[2])   # floor top at z = 0
    if floor_det.any():
        below = np.degrees(np.arcsin(np.minimum(height / det.range_m[floor_det], 1.0)))
        numbers["floor_detection_ranges_m"] = [float(det.range_m[floor_det].min()),
                                               float(det.range_m[floor_det].max())]
        numbers["floor_detection_depression_deg"] = [float(below.min()), float(below.max())]
    fig, axes = plt.subplots(1, 2, figsize=(14, 5.4), constrained_layout=True)
    ax = axes[0]
    ra = dsp.range_azimuth_db
    top = float(np.max(ra))
    az = np.deg2rad(dsp.axes.azimuth_deg)
    rr, aa = np.meshgrid(dsp.axes.range_m, az)
    im = ax.pcolormesh(rr * np.sin(aa), rr * np.cos(aa), ra, vmin=top - 45, vmax=top,
                       cmap="magma", shading="gouraud")
    fig.colorbar(im, ax=ax, label="power (dB)")
    da = np.deg2rad(det.azimuth_deg)
    ax.scatter(det.range_m * np.sin(da), det.range_m * np.cos(da), s=28, facecolors="none",
               edgecolors="cyan", lw=1.2,
               label=f"{project.dsp.cfar_method.upper()}-CFAR detections")
    ax.set_xlabel("cross-range x (m, radar frame, + = right)")
    ax.set_ylabel("down-range z (m)")
    ax.set_aspect("equal")
    ax.set_xlim(-5, 5)
    ax.set_ylim(0, dsp.axes.range_m[-1])
    ax.set_title("Range–azimuth map as a fan (Bartlett, actual antenna positions)")
    ax.legend(loc="upper right", fontsize=8)
    ax = axes[1]
    snap = frame.snapshot
    # The project's objects' poses (a person's placement; the snapshot holds its segments).
    for obj, pose in zip(project.objects, frame.object_poses, strict=True):
        poly = _footprint(obj, pose)
        if poly is not None and obj.name not in ("floor", "ceiling"):
            ax.fill(poly[:, 0], poly[:, 1], color="0.85", ec="0.4", lw=0.7)
    if det.xyz_world_m is not None and len(det.range_m):
        sc = ax.scatter(det.xyz_world_m[:, 0], det.xyz_world_m[:, 1], c=det.velocity_mps,
                        cmap="coolwarm", vmin=-1.5, vmax=1.5, s=18 + 2 * np.clip(det.snr_db, 0, 40),
                        ec="k", lw=0.4, zorder=3)
        fig.colorbar(sc, ax=ax, label="radial velocity (m/s, + = away)")
    rp = snap.sensors["radar"].position
    ax.plot(*rp[:2], marker="^", color="k", ms=9)
    for edge_deg in (-50.0, 50.0):
        a = np.deg2rad(edge_deg)
        d = snap.sensors["radar"].rotation @ np.array([np.sin(a), 0.0, np.cos(a)])
        ax.plot([rp[0], rp[0] + 7 * d[0]], [rp[1], rp[1] + 7 * d[1]], "k:", lw=0.8)
    ax.plot(*np.array(cr["world"][:2]), marker="x", color="red", ms=10, mew=2,
            label="corner reflector (truth)")
    ax.set_xlim(-0.5, 6)
    ax.set_ylim(-2.9, 2.9)
    ax.set_aspect("equal")
    ax.set_xlabel("world x (m)")
    ax.set_ylabel("world y (m)")
    ax.set_title("Radar point cloud on a top view of the office")
    ax.legend(loc="lower right", fontsize=8)
    name = "fig3_office_range_azimuth.png"
    _save(fig, out / name)
    text = (
        f"{project.dsp.cfar_method.upper()}-CFAR on the range–Doppler map gives "
        f"{numbers['detections']} detections in this frame; each one's azimuth comes from "
        f"the angle spectrum of its cell and its world position from the radar pose. The "
        f"corner reflector behind the paper box is detected {cr_err * 100:.1f} cm from its "
        f"true apex. With only two elements across (the BGT60TR13C's L of three Rx), the "
        f"azimuth beam is about 60° wide: a range cell that holds several reflectors at "
        f"different angles gets one blended azimuth, so clutter points from the walls, "
        f"desks and the person (coloured by radial velocity) scatter around their objects on "
        f"the top view, as in measured point clouds of this radar. "
        + (f"{numbers['floor_detections']} detections are labelled floor clutter by the "
           f"ground truth (the object giving most of the cell's power), at "
           f"{numbers['floor_detection_ranges_m'][0]:.2f}–"
           f"{numbers['floor_detection_ranges_m'][1]:.2f} m, "
           f"{numbers['floor_detection_depression_deg'][0]:.0f}–"
           f"{numbers['floor_detection_depression_deg'][1]:.0f}° below the radar's horizon "
           f"(section 7.2): the floor now inside the rendered field of view."
           if numbers["floor_detections"] else "No detection comes from the floor.")
    )
    return Figure(name, "Office scene, range–azimuth and point cloud", text), numbers


def doppler_experiment(project: Project, out: Path, *, frames: int,
                       progress: Callable[[str], None]) -> tuple[Figure, dict[str, Any]]:
    """Figure 4: estimated radial velocity over time against ground truth."""
    plt = _plt()
    bin_v = project.rig.radar.velocity_resolution_mps
    times, est, true = [], [], []
    with Simulator(project) as sim:
        for i in range(frames):
            frame = sim.frame(i)
            truth = corner_truth(project, frame.time_s)[0]
            rows = frame.outputs["radar"].dsp.detection_records(i)
            k = _nearest(rows, truth["range"])
            times.append(frame.time_s)
            true.append(truth["velocity"])
            est.append(float(rows["velocity"][k]) if k is not None else np.nan)
            if i % 20 == 0:
                progress(f"doppler frame {i}/{frames}")
    t, e, g = np.array(times), np.array(est), np.array(true)
    err = e - g
    ok = np.isfinite(err)
    numbers = {"frames": frames, "detected_fraction": float(np.mean(ok)),
               "mean_error_mps": float(np.mean(err[ok])), "std_error_mps": float(np.std(err[ok])),
               "max_abs_error_mps": float(np.max(np.abs(err[ok]))),
               "within_one_bin_fraction": float(np.mean(np.abs(err[ok]) < bin_v)),
               "velocity_bin_mps": bin_v, "max_speed_mps": float(np.max(np.abs(g)))}
    fig, axes = plt.subplots(2, 1, figsize=(11, 6), sharex=True, constrained_layout=True,
                             gridspec_kw={"height_ratios": [3, 1.3]})
    axes[0].plot(t, g, "k-", lw=1.5, label="ground truth (range rate of the corner apex)")
    axes[0].plot(t, e, "o", ms=3.5, color="tab:red", label="estimated (CFAR peak, refined)")
    axes[0].set_ylabel("radial velocity (m/s, + = away)")
    axes[0].legend(fontsize=8, loc="upper right")
    axes[0].grid(alpha=0.3)
    axes[0].set_title(f"Doppler experiment — rig moving back and forth, "
                      f"{project.rig.radar.chirps_per_frame} chirps, Chebyshev "
                      f"{project.dsp.doppler_window_sidelobe_db:.0f} dB window, 2× zero padding")
    axes[1].plot(t, err * 1000, ".", color="tab:blue",
                 label=f"estimate − truth (one Doppler bin = {bin_v * 1000:.0f} mm/s)")
    lim = max(5.0, 3 * float(np.nanmax(np.abs(err))) * 1000)
    axes[1].set_ylim(-lim, lim)
    axes[1].set_ylabel("error (mm/s)")
    axes[1].set_xlabel("time (s)")
    axes[1].legend(fontsize=8, loc="upper right")
    axes[1].grid(alpha=0.3)
    name = "fig4_doppler.png"
    _save(fig, out / name)
    text = (
        f"The rig moves sinusoidally towards and away from one corner reflector (up to "
        f"{numbers['max_speed_mps']:.2f} m/s). Over {frames} frames the target is detected in "
        f"{numbers['detected_fraction']:.0%} of them; the estimated radial velocity follows "
        f"the exact range rate with mean error {numbers['mean_error_mps'] * 100:+.2f} cm/s, "
        f"standard deviation {numbers['std_error_mps'] * 100:.2f} cm/s and worst case "
        f"{numbers['max_abs_error_mps'] * 100:.2f} cm/s; "
        f"{numbers['within_one_bin_fraction']:.0%} of the estimates lie within one Doppler bin "
        f"({bin_v * 100:.1f} cm/s). Ground truth here is exact (the keyframed rigid motion), "
        f"not a finite difference of range maps."
    )
    return Figure(name, "Doppler experiment", text), numbers


def calibration(out: Path, *, quick: bool, progress: Callable[[str], None]
                ) -> tuple[Figure, dict[str, Any]]:
    """Figure 5: power vs range against the radar equation; error tables; IF error; grid."""
    plt = _plt()
    base = load_project(example_path("point_targets"))
    numbers: dict[str, Any] = {}

    # (a) received power of one boresight corner vs range, noise off, zero-padded range FFT.
    ranges = np.linspace(1.0, 6.0, 6 if quick else 11)
    measured, expected = [], []
    proj = copy.deepcopy(base)
    proj.objects = [proj.objects[1]]
    proj.objects[0].motion = type(proj.objects[0].motion)()
    proj.rig.radar.noise_variance_adc = 0.0
    proj.rig.radar.leakage_dbc = None
    proj.rig.radar.adc_bits = None
    proj.dsp.range_fft_size = 8 * proj.rig.radar.samples_per_chirp
    radar_y = proj.rig.pose.position_m[1] + proj.rig.radar.pose_on_rig.position_m[1]
    geometry = proj.objects[0].geometry
    assert isinstance(geometry, CornerReflector)
    edge = geometry.edge_m
    for rng in ranges:
        variant = proj.model_copy(deep=True)
        p = variant.objects[0].pose
        variant.objects[0].pose = p.model_copy(update={"position_m": (float(rng), radar_y,
                                                                      p.position_m[2])})
        with Simulator(variant) as sim:
            frame = sim.frame(0)
        radar_pos = frame.snapshot.sensors["radar"].position
        true_r = float(np.linalg.norm(frame.snapshot.objects[0].origin - radar_pos))
        measured.append(float(frame.outputs["radar"].dsp.range_profile_integrated_db.max()))
        expected.append(20 * np.log10(expected_corner_amplitude_fs(
            variant.rig.radar, edge_m=edge, range_m=true_r)))
    power_err = np.array(measured) - np.array(expected)
    numbers["power_vs_range"] = {"ranges_m": ranges.tolist(), "measured_dbfs": measured,
                                 "expected_dbfs": expected,
                                 "max_abs_error_db": float(np.max(np.abs(power_err)))}
    progress("calibration: power vs range done")

    # (b) range / velocity / angle errors on point_targets.json.
    rows_out = []
    bin_r = base.rig.radar.range_resolution_m
    bin_v = base.rig.radar.velocity_resolution_mps
    with Simulator(base) as sim:
        for i in range(3 if quick else 10):
            frame = sim.frame(i)
            det = frame.outputs["radar"].dsp.detection_records(i)
            for truth in corner_truth(base, frame.time_s):
                k = _nearest(det, truth["range"])
                if k is None:
                    rows_out.append({"frame": i, "target": truth["name"], "detected": False})
                    continue
                rows_out.append({
                    "frame": i, "target": truth["name"], "detected": True,
                    "range_err_bins": float(abs(det["range"][k] - truth["range"]) / bin_r),
                    "velocity_err_bins": float(abs(det["velocity"][k] - truth["velocity"]) / bin_v),
                    "azimuth_err_deg": float(abs(det["azimuth_deg"][k] - truth["azimuth_deg"])),
                })
            numbers.setdefault("detections_per_frame", []).append(int(len(det)))
    found = [r for r in rows_out if r["detected"]]
    numbers["point_targets"] = {
        "frames": len(numbers["detections_per_frame"]),
        "all_detected": len(found) == len(rows_out),
        "max_range_err_bins": max(r["range_err_bins"] for r in found),
        "max_velocity_err_bins": max(r["velocity_err_bins"] for r in found),
        "max_azimuth_err_deg": max(r["azimuth_err_deg"] for r in found),
        "per_target": {name: {k: max(r[k] for r in found if r["target"] == name)
                              for k in ("range_err_bins", "velocity_err_bins", "azimuth_err_deg")}
                       for name in sorted({r["target"] for r in found})},
    }
    progress("calibration: point targets done")

    # (c) IF synthesis error against the exact direct sum on a subset of the office scene.
    office = load_project(example_path("office"))
    with Simulator(office) as sim:
        frame = sim.frame(0)
        sc = radar_scatterers(RadarScene.from_project(expand_people(office), frame.snapshot),
                              frame.buffers["radar"], config=office.rig.radar,
                              seed=sim.seed,
                              see_through=frame.see_through.get("radar"))
        rng = np.random.default_rng(0)
        subset = sc.subset(np.sort(rng.choice(len(sc), size=min(len(sc), 800 if quick
                                                                 else 2000), replace=False)))
        t0 = time.perf_counter()
        fast = synthesize_if(subset, office.rig.radar)
        t_fast = time.perf_counter() - t0
        t0 = time.perf_counter()
        ref = synthesize_if_direct(subset, office.rig.radar)
        t_direct = time.perf_counter() - t0
        t0 = time.perf_counter()
        synthesize_if(sc, office.rig.radar)
        t_full = time.perf_counter() - t0
    if_err = 20 * np.log10(np.linalg.norm(fast - ref) / np.linalg.norm(ref))
    numbers["if_synthesis"] = {
        "subset_scatterers": len(subset), "scene_scatterers": len(sc),
        "error_db": float(if_err),
        "direct_s_extrapolated": t_direct * len(sc) / len(subset), "nufft_s": t_full,
        "speedup": t_direct * len(sc) / len(subset) / t_full, "subset_nufft_s": t_fast,
    }
    progress("calibration: IF synthesis error done")

    # (d) extended-surface return vs render resolution (wall.json, 1× and 2× grid).
    wall = load_project(example_path("wall"))
    peaks = {}
    for factor in (1, 2):
        variant = wall.model_copy(deep=True)
        variant.rig.radar.render_supersampling = factor
        variant.rig.radar.noise_variance_adc = 0.0
        with Simulator(variant) as sim:
            peaks[factor] = float(
                sim.frame(0).outputs["radar"].dsp.range_profile_integrated_db.max())
    numbers["resolution"] = {"peak_db_1x": peaks[1], "peak_db_2x": peaks[2],
                             "change_db": peaks[2] - peaks[1]}

    fig = plt.figure(figsize=(13, 5.2), constrained_layout=True)
    grid = fig.add_gridspec(1, 2, width_ratios=[1.1, 1])
    ax = fig.add_subplot(grid[0])
    ax.plot(ranges, expected, "k-", label="radar equation (4πa⁴/3λ² trihedral)")
    ax.plot(ranges, measured, "o", color="tab:red", label="simulated range-FFT peak")
    ax.set_xlabel("range (m)")
    ax.set_ylabel("received power (dBFS)")
    ax.set_title(f"Point target power vs range (a = {edge * 100:.0f} cm trihedral, boresight)")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    ax2 = ax.twinx()
    ax2.plot(ranges, power_err, "s", color="tab:blue", ms=4)
    ax2.set_ylabel("simulated − equation (dB)", color="tab:blue")
    ax2.set_ylim(-1, 1)
    ax = fig.add_subplot(grid[1])
    ax.axis("off")
    pt = numbers["point_targets"]
    ifs = numbers["if_synthesis"]
    table = [
        ["quantity", "measured", "bar"],
        ["range error (point targets)", f"{pt['max_range_err_bins']:.3f} bin", "≤ 0.25 bin"],
        ["velocity error", f"{pt['max_velocity_err_bins']:.3f} bin", "≤ 1 bin"],
        ["azimuth error", f"{pt['max_azimuth_err_deg']:.2f}°", "≤ 2°"],
        ["power vs radar equation", f"{numbers['power_vs_range']['max_abs_error_db']:.3f} dB",
         "≤ 0.5 dB"],
        ["IF synthesis vs direct sum", f"{ifs['error_db']:.0f} dB", "≤ −60 dB"],
        ["NUFFT speed-up (office)", f"{ifs['speedup']:.0f}×", ""],
        ["wall peak, 2× vs 1× grid", f"{numbers['resolution']['change_db']:+.3f} dB", "< 1 dB"],
    ]
    tab = ax.table(cellText=table[1:], colLabels=table[0], loc="center", cellLoc="left",
                   colWidths=[0.5, 0.27, 0.23])
    tab.auto_set_font_size(False)
    tab.set_fontsize(9)
    tab.scale(1, 1.6)
    ax.set_title("Calibration and accuracy (worst case over targets and frames)")
    name = "fig5_calibration.png"
    _save(fig, out / name)
    text = (
        f"Left: the peak of the simulated range spectrum of a {edge * 100:.0f} cm trihedral on "
        f"boresight follows the radar equation (P_t G_t G_r λ² σ/((4π)³R⁴), the documented "
        f"receiver gain and the IF high-pass, computed independently here) within "
        f"{numbers['power_vs_range']['max_abs_error_db']:.3f} dB from 1 to 6 m. Right: on "
        f"point_targets.json over {pt['frames']} frames every target is detected, with worst "
        f"errors {pt['max_range_err_bins']:.3f} range bin, {pt['max_velocity_err_bins']:.3f} "
        f"Doppler bin and {pt['max_azimuth_err_deg']:.2f}°; the NUFFT IF synthesis differs from "
        f"the exact direct sum by {ifs['error_db']:.0f} dB on {ifs['subset_scatterers']} office "
        f"scatterers and is {ifs['speedup']:.0f}× faster than the direct sum extrapolated to the "
        f"whole scene ({ifs['scene_scatterers']} scatterers); doubling the render grid changes "
        f"the wall's peak by {numbers['resolution']['change_db']:+.3f} dB."
    )
    return Figure(name, "Calibration", text), numbers


def side_by_side(frame: Frame, project: Project, out: Path) -> tuple[Figure, dict[str, Any]]:
    """Figure 6: ToF and radar point clouds of the same frame in one 3D view."""
    plt = _plt()
    tof = frame.outputs["tof"]
    intr = project.rig.tof.intrinsics()
    rays = intr.ray_directions()
    rays /= np.linalg.norm(rays, axis=-1, keepdims=True)
    pts = (tof.depth_m[..., None] * rays)[tof.valid]
    world = pts @ frame.snapshot.sensors["tof"].rotation.T + frame.snapshot.sensors["tof"].position
    world = world[:: max(1, len(world) // 12000)]
    det = frame.outputs["radar"].dsp.detections
    fig = plt.figure(figsize=(11, 7), constrained_layout=True)
    ax = fig.add_subplot(projection="3d")
    ax.scatter(world[:, 0], world[:, 1], world[:, 2], s=0.6, c=world[:, 2], cmap="viridis",
               alpha=0.5, label=f"ToF point cloud ({int(tof.valid.sum())} valid pixels)")
    if det.xyz_world_m is not None and len(det.range_m):
        ax.scatter(det.xyz_world_m[:, 0], det.xyz_world_m[:, 1], det.xyz_world_m[:, 2], s=40,
                   c="red", depthshade=False, label=f"radar detections ({len(det.range_m)})")
    rig = frame.snapshot.rig.origin
    ax.scatter(*rig, marker="^", s=80, c="k", label="sensor rig")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.set_zlabel("z (m)")
    ax.set_xlim(0, 6)
    ax.set_ylim(-3, 3)
    ax.set_zlim(0, 3)
    ax.view_init(elev=28, azim=-130)
    ax.set_title(f"ToF and radar of one frame, same timestamp t = {frame.time_s:.2f} s")
    ax.legend(loc="upper left", fontsize=8)
    name = "fig6_side_by_side.png"
    _save(fig, out / name)
    numbers = {"time_s": frame.time_s, "tof_points": int(tof.valid.sum()),
               "radar_detections": int(len(det.range_m)),
               "radar_time_s": float(frame.outputs["radar"].raw.time_s)}
    radar_start = frame.outputs["radar"].raw.time_s
    text = (
        f"Both sensors of one frame come from one scene snapshot at t = {frame.time_s:.2f} s "
        f"(the radar's first chirp starts at {radar_start:.2f} s): the dense ToF point "
        f"cloud ({numbers['tof_points']} valid pixels) and the sparse radar point cloud "
        f"({numbers['radar_detections']} detections) in the same world frame. The radar sees "
        f"the corner reflector that the paper box hides from the ToF camera."
    )
    return Figure(name, "ToF and radar side by side", text), numbers


# ----------------------------------------------------------------------------------- driver


def generate_report(out_dir: str | Path, *, quick: bool = False,
                    progress: Callable[[str], None] | None = None) -> ReportResult:
    """Run every experiment, write the figures and ``README.md`` into ``out_dir``.

    ``quick`` uses fewer frames and calibration points (for tests); the figures and numbers
    are the same kind.
    """
    say = progress or (lambda message: None)
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    result = ReportResult(out)
    office = load_project(example_path("office"))
    with Simulator(office) as sim:
        frame = sim.frame(0)
    say("office frame done")
    for name, fn in (("office_tof", office_tof), ("office_radar", office_radar_profile),
                     ("office_range_azimuth", office_range_azimuth),
                     ("side_by_side", side_by_side)):
        fig, nums = fn(frame, office, out)
        result.figures.append(fig)
        result.numbers[name] = nums
        say(f"{name} done")
    doppler = load_project(example_path("doppler_back_and_forth"))
    n = 24 if quick else doppler.timeline.n_frames
    fig, nums = doppler_experiment(doppler, out, frames=n, progress=say)
    result.figures.insert(3, fig)
    result.numbers["doppler"] = nums
    fig, nums = calibration(out, quick=quick, progress=say)
    result.figures.insert(4, fig)
    result.numbers["calibration"] = nums
    surfaces: dict[str, Any] = {}
    fig, nums = surfaces_plate_sphere(out, progress=say)
    result.figures.append(fig)
    surfaces.update(nums)
    fig, nums = surfaces_office_floor(frame, office, out)
    result.figures.append(fig)
    surfaces["office_floor"] = nums
    say("surfaces: office floor done")
    fig, nums = surfaces_moving_rig(out, progress=say)
    result.figures.append(fig)
    surfaces["moving_rig"] = nums
    result.numbers["surfaces"] = surfaces
    figures, nums = multipath_section(out, quick=quick)
    for file, title, text in figures:
        result.figures.append(Figure(file, title, text, section="Multipath"))
    fig_tof, nums_tof = tof_multipath_figure(out)
    result.figures.append(Figure(*fig_tof, section="Multipath"))
    from simcore.report_sionna import sionna_section

    figures, nums_sionna = sionna_section(out)
    for file, title, text in figures:
        result.figures.append(Figure(file, title, text, section="Multipath"))
    result.numbers["multipath"] = {"radar": nums, "tof": nums_tof, "sionna": nums_sionna}
    say("multipath done")
    from simcore.report_interference import interference_section

    figures, nums = interference_section(out, quick=quick)
    for file, title, text in figures:
        result.figures.append(Figure(file, title, text, section="Interference"))
    result.numbers["interference"] = nums
    say("interference done")
    figures, nums = products_section(out, quick=quick)
    for file, title, text in figures:
        result.figures.append(Figure(file, title, text, section="Radar products"))
    result.numbers["products"] = nums
    say("radar products done")
    real_bgt60tr13c(result, out, quick=quick)
    say("real BGT60TR13C done")
    _write_readme(result, quick=quick)
    (out / "numbers.json").write_text(json.dumps(result.numbers, indent=2, default=float) + "\n")
    return result


def real_bgt60tr13c(result: ReportResult, out: Path, *, quick: bool) -> None:
    """Section "simulation and a real BGT60TR13C" (:mod:`simcore.report_real`).

    Uses the shared real recording when present; otherwise the section says it is absent.
    """
    from simcore.report_real import real_section

    file, title, text, numbers = real_section(out, quick=quick)
    result.figures.append(Figure(file, title, text))
    result.numbers["real_bgt60tr13c"] = numbers


def _write_readme(result: ReportResult, *, quick: bool) -> None:
    lines = [
        "# Validation report",
        "",
        "Regenerated by `tofradar report` (or `make report`) from the bundled example "
        "scenes; every number below is measured by that run against an independent answer "
        "(scene geometry and exact rigid motion, the radar equation, the direct-sum IF "
        "synthesis). The raw numbers are in [numbers.json](numbers.json)."
        + (" *Quick mode: fewer frames and calibration points.*" if quick else ""),
        "",
    ]
    number, sub, section = 0, 0, None
    for fig in result.figures:
        if fig.section is None:
            number += 1
            lines += [f"## {number}. {fig.title}", ""]
        else:
            if fig.section != section:
                number += 1
                sub = 0
                lines += [f"## {number}. {fig.section}", ""]
            sub += 1
            title = fig.title.removeprefix(fig.section + ": ")
            lines += [f"### {number}.{sub} {title[:1].upper()}{title[1:]}", ""]
        section = fig.section
        lines += ([f"![{fig.title}]({fig.file})", ""] if fig.file else []) + [fig.text, ""]
    (result.out_dir / "README.md").write_text("\n".join(lines))


# ----------------------------------------------------------------------------------- surfaces

#: Receiver without noise, leakage, quantisation or IF high-pass: the single-object
#: experiments compare the scattered power itself with the radar equation.
_IDEAL_RECEIVER = {"noise_variance_adc": 0.0, "leakage_dbc": None, "adc_bits": None,
                   "if_highpass_hz": 0.0}


def radar_equation_amplitude(config: RadarConfig, rcs_m2: float, range_m: float,
                             pattern_gain: float = 1.0) -> float:
    """IF amplitude (FS) of a monostatic target of RCS ``rcs_m2`` from the radar equation.

    ``P_r = P_t G_t G_r g λ² σ / ((4π)³ R⁴)`` (``g``: the two-way element pattern at the
    target's direction), a tone of peak voltage ``√(2 R_ref P_r)`` times the IF voltage gain
    over the ADC full scale; no IF high-pass (the experiments that use it switch it off).
    """
    p_t = 1e-3 * 10 ** (config.tx_power_dbm / 10)
    g = 10 ** ((config.tx_gain_dbi + config.rx_gain_dbi) / 10) * pattern_gain
    p_r = p_t * g * config.wavelength_m**2 * rcs_m2 / ((4 * np.pi) ** 3 * range_m**4)
    return float(np.sqrt(2 * R_REF_OHM * p_r) * 10 ** (config.if_gain_db / 20)
                 / config.adc_full_scale_v)


def _range_spectrum(x: NDArray[np.float64], pad: int = 16) -> NDArray[np.complex128]:
    """Hann-windowed, zero-padded real FFT scaled so a tone of amplitude A peaks at A."""
    n = x.shape[-1]
    w = np.hanning(n)
    return np.asarray(np.fft.rfft(x * w, n=pad * n, axis=-1) / (w.sum() / 2))


class _SingleObjectRadar:
    """Renders small single-object scenes for the radar (one offscreen window, re-used)."""

    def __init__(self) -> None:
        self._renderer: SceneRenderer | None = None

    def scatterers(self, project: Project, config: RadarConfig, *, seed: int = 0,
                   t: float = 0.0) -> Any:
        project = expand_people(project)
        if self._renderer is None:
            self._renderer = SceneRenderer(project)
        else:
            self._renderer.set_project(project)
        snap = take_snapshot(project, t)
        request = RenderRequest("radar", "radar", config.render_intrinsics(), geometry_only=True)
        buffers = self._renderer.render(snap, request)
        hide = RadarSensor().see_through(project)
        through = None if hide is None else self._renderer.render(snap, request, hide=hide)
        return radar_scatterers(RadarScene.from_project(project, snap), buffers,
                                config=config, seed=seed,
                                see_through=through)

    def peak_dbfs(self, project: Project, config: RadarConfig, *, seed: int = 0,
                  t: float = 0.0) -> float:
        """Largest range-FFT magnitude (dBFS) of chirp 0 on the Rx at the Tx (channel 2)."""
        scat = self.scatterers(project, config, seed=seed, t=t)
        adc = simulate_radar(scat, config, rng=np.random.default_rng(0)).adc
        spec = _range_spectrum(adc[0, 1].astype(np.float64))
        return float(20 * np.log10(np.abs(spec).max()))

    def close(self) -> None:
        if self._renderer is not None:
            self._renderer.close()


def _one_object(geometry: Any, distance_m: float, *, rotation_deg: tuple[float, float, float]
                = (0.0, 0.0, 0.0), rig: SensorRig | None = None) -> Project:
    return Project(objects=[SceneObject(
        id=1, name="target", geometry=geometry, material="aluminium",
        pose=Pose(position_m=(distance_m, 0.0, 0.0), rotation_deg=rotation_deg))],
        rig=rig or SensorRig())


def _radar_to_origin(project: Project, t: float) -> tuple[float, float]:
    """Distance and azimuth (rad) from the radar to the first object's origin at ``t``."""
    snap = take_snapshot(project, t)
    radar = snap.sensors["radar"]
    rel = snap.objects[0].origin - radar.position
    opt = radar.rotation.T @ rel
    return float(np.linalg.norm(rel)), float(np.arctan2(opt[0], opt[2]))


def _receiver_profile_db(project: Project, scatterers: Any, seed: int) -> NDArray[np.float64]:
    """Chirp- and channel-averaged range profile (dBFS) of ``scatterers``.

    Through the project's whole receiver (noise, leakage, IF chain, ADC) and DSP, as the
    frame's own profile.
    """
    cfg = project.rig.radar
    adc = simulate_radar(scatterers, cfg, rng=np.random.default_rng(seed)).adc
    return np.asarray(process_frame(adc, cfg, project.dsp).range_profile_integrated_db,
                      dtype=np.float64)


def _office_scatterers(frame: Frame, project: Project) -> Any:
    return radar_scatterers(RadarScene.from_project(expand_people(project), frame.snapshot),
                            frame.buffers["radar"], config=project.rig.radar,
                            seed=0,
                            see_through=frame.see_through.get("radar"))


def surfaces_plate_sphere(out: Path, *, progress: Callable[[str], None]
                          ) -> tuple[Figure, dict[str, Any]]:
    """Surfaces (a, b): a plate's pattern against PO; a sphere's RCS against πr².

    A few dozen small renders (about two seconds): the same in quick mode.
    """
    plt = _plt()
    cfg = RadarConfig().model_copy(update=_IDEAL_RECEIVER)
    lam = cfg.wavelength_m
    k = 2 * np.pi / lam
    side, distance = 0.05, 3.0
    null_deg = float(np.degrees(np.arcsin(lam / (2 * side))))
    radar = _SingleObjectRadar()
    numbers: dict[str, Any] = {}
    try:
        # (a) plate: power vs yaw, normalised to normal incidence, against PO.
        angles = np.linspace(0.0, 2.2 * null_deg, 34)
        plate = Box(size_m=(0.002, side, side))
        peaks = np.array([radar.peak_dbfs(_one_object(plate, distance,
                                                      rotation_deg=(0.0, 0.0, float(a))), cfg)
                          for a in angles])
        r_front, _ = _radar_to_origin(_one_object(plate, distance), 0.0)
        r_front -= 0.001
        sigma0 = 4 * np.pi * side**4 / lam**2
        expected0 = 20 * np.log10(radar_equation_amplitude(cfg, sigma0, r_front))

        def po_db(theta_deg: NDArray[np.float64]) -> NDArray[np.float64]:
            th = np.radians(theta_deg)
            x = k * side * np.sin(th)
            pattern = np.cos(th) * np.sinc(x / np.pi)
            return np.asarray(20 * np.log10(np.maximum(np.abs(pattern), 1e-6)))

        rel = peaks - peaks[0]
        po = po_db(angles)
        lobe = po >= -10.0                      # the main lobe down to −10 dB
        numbers["plate"] = {
            "side_m": side, "range_m": r_front, "first_null_deg": null_deg,
            "angles_deg": angles.tolist(), "relative_db": rel.tolist(), "po_db": po.tolist(),
            "normal_incidence_error_db": float(peaks[0] - expected0),
            "rcs_normal_dbsm": float(10 * np.log10(sigma0) + peaks[0] - expected0),
            "po_rcs_normal_dbsm": float(10 * np.log10(sigma0)),
            "main_lobe_max_abs_error_db": float(np.max(np.abs(rel[lobe] - po[lobe]))),
            "main_lobe_to_deg": float(angles[lobe].max()),
            "at_first_null_db": float(np.interp(null_deg, angles, rel)),
        }
        progress("surfaces: plate pattern done")

        # (b) sphere: RCS over aspect angles (the object turned) and speckle seeds.
        radius = 0.10
        sphere = Sphere(radius_m=radius)
        aspects = [(0.0, 0.0, 0.0), (0.0, 20.0, 35.0), (0.0, -30.0, 80.0), (10.0, 45.0, 10.0),
                   (0.0, 0.0, 135.0), (30.0, 60.0, 200.0), (0.0, -70.0, 290.0)]
        seeds = (0, 1, 2)
        r_sphere = _radar_to_origin(_one_object(sphere, distance), 0.0)[0] - radius
        sigma_opt = np.pi * radius**2
        ref_db = 20 * np.log10(radar_equation_amplitude(cfg, sigma_opt, r_sphere))
        rcs = np.array([[10 * np.log10(sigma_opt) + radar.peak_dbfs(
            _one_object(sphere, distance, rotation_deg=rot), cfg, seed=s) - ref_db
            for s in seeds] for rot in aspects])
        numbers["sphere"] = {
            "radius_m": radius, "range_m": r_sphere, "optics_rcs_dbsm": float(
                10 * np.log10(sigma_opt)), "aspects_deg": [list(a) for a in aspects],
            "seeds": list(seeds), "rcs_dbsm": rcs.tolist(),
            "max_abs_error_db": float(np.max(np.abs(rcs - 10 * np.log10(sigma_opt)))),
            "spread_db": float(rcs.max() - rcs.min()),
        }
        progress("surfaces: sphere done")
    finally:
        radar.close()

    fig, axes = plt.subplots(1, 2, figsize=(13, 4.8), constrained_layout=True)
    ax = axes[0]
    fine = np.linspace(0.0, angles[-1], 600)
    ax.plot(fine, po_db(fine), "k-", lw=1, label="PO: σ₀[cos θ · sinc(ka sin θ)]²")
    ax.plot(angles, rel, "o", color="tab:red", ms=5, label="simulated (range-FFT peak)")
    ax.axvline(null_deg, color="0.5", ls=":", lw=1,
               label=f"first null sin θ = λ/2a ({null_deg:.2f}°)")
    ax.set_ylim(-45, 3)
    ax.set_xlabel("aspect angle θ, plate turned about the vertical axis (°)")
    ax.set_ylabel("power relative to normal incidence (dB)")
    pl = numbers["plate"]
    ax.set_title(f"{side * 100:.0f}×{side * 100:.0f} cm aluminium plate at {distance:.0f} m: "
                 f"normal incidence {pl['normal_incidence_error_db']:+.2f} dB from 4πA²/λ²",
                 fontsize=10)
    ax.legend(fontsize=8, loc="lower left")
    ax.grid(alpha=0.3)
    ax = axes[1]
    sp = numbers["sphere"]
    labels = [f"({a[0]:.0f}, {a[1]:.0f}, {a[2]:.0f})" for a in aspects]
    xs = np.arange(len(aspects))
    for j, s in enumerate(seeds):
        ax.plot(xs + (j - (len(seeds) - 1) / 2) * 0.12, rcs[:, j], "o", ms=6,
                label=f"simulated, speckle seed {s}")
    ax.axhline(sp["optics_rcs_dbsm"], color="k", lw=1,
               label=f"optics πr² = {sp['optics_rcs_dbsm']:.1f} dBsm")
    ax.axhspan(sp["optics_rcs_dbsm"] - 1.5, sp["optics_rcs_dbsm"] + 1.5, color="0.85",
               label="± 1.5 dB", zorder=0)
    ax.set_xticks(xs, labels, fontsize=8, rotation=20)
    ax.set_xlabel("sphere orientation (roll, pitch, yaw) (°): its facets seen from another side")
    ax.set_ylabel("RCS (dBsm)")
    ax.set_ylim(sp["optics_rcs_dbsm"] - 4, sp["optics_rcs_dbsm"] + 4)
    ax.set_title(f"Aluminium sphere r = {radius * 100:.0f} cm at {distance:.0f} m", fontsize=10)
    ax.legend(fontsize=8, loc="lower right")
    ax.grid(alpha=0.3)
    name = "fig7_surfaces_rcs.png"
    _save(fig, out / name)
    text = (
        f"Surfaces are physical-optics facets fixed to the objects (docs/physics_radar.md §1); "
        f"here each object is alone in front of the radar, with an ideal receiver, and its "
        f"range-FFT peak is converted to RCS with the radar equation written out in this "
        f"module. Left: a {side * 100:.0f}×{side * 100:.0f} cm aluminium plate at "
        f"{distance:.0f} m (beyond its far-field distance 2a²/λ) returns "
        f"{pl['rcs_normal_dbsm']:.1f} dBsm at normal incidence, "
        f"{pl['normal_incidence_error_db']:+.2f} dB from 4πA²/λ² "
        f"({pl['po_rcs_normal_dbsm']:.1f} dBsm); turned about the vertical axis it follows "
        f"the PO pattern [cos θ · sinc(ka sin θ)]² within "
        f"{pl['main_lobe_max_abs_error_db']:.2f} dB over the main lobe (to "
        f"{pl['main_lobe_to_deg']:.1f}°, −10 dB) and falls to {pl['at_first_null_db']:.0f} dB "
        f"at the first null ({null_deg:.2f}°), with the side lobe beyond it. Right: a "
        f"{radius * 100:.0f} cm aluminium sphere at {distance:.0f} m, turned to "
        f"{len(aspects)} orientations and rendered with {len(seeds)} speckle seeds, gives "
        f"{rcs.min():.2f} to {rcs.max():.2f} dBsm against πr² = "
        f"{sp['optics_rcs_dbsm']:.2f} dBsm (worst {sp['max_abs_error_db']:.2f} dB): its return "
        f"is the coherent sum of the facets around the specular point, not of random phases."
    )
    return Figure(name, "Surfaces: plate and sphere against physical optics", text,
                  section="Surfaces"), numbers


def surfaces_office_floor(frame: Frame, project: Project, out: Path
                          ) -> tuple[Figure, dict[str, Any]]:
    """Surfaces (c): the office range profile with the floor's own contribution."""
    plt = _plt()
    scat = _office_scatterers(frame, project)
    floor = scat.subset(scat.object_index == [o.name for o in project.objects].index("floor"))
    scene_db = np.asarray(frame.outputs["radar"].dsp.range_profile_integrated_db,
                          dtype=np.float64)
    floor_db = _receiver_profile_db(project, floor, 11)
    noise_db = _receiver_profile_db(project, floor.subset(np.zeros(len(floor), bool)), 12)
    r = np.asarray(frame.outputs["radar"].dsp.axes.range_m, dtype=np.float64)
    band = (r >= 1.5) & (r <= 2.3)

    def mean_db(p: NDArray[np.float64], sel: NDArray[np.bool_]) -> float:
        return float(10 * np.log10(np.mean(10 ** (p[sel] / 10))))

    floor_over = mean_db(floor_db, band) - mean_db(noise_db, band)
    scene_over = mean_db(scene_db, band) - mean_db(noise_db, band)
    rise = floor_db - noise_db
    above = np.nonzero((r > 0.3) & (rise >= 6.0))[0]
    floor_start = float(r[above[0]]) if len(above) else float("nan")
    radar = frame.snapshot.sensors["radar"]
    height = float(radar.position[2])      # the floor's top is z = 0 in office.json
    half_fov = project.rig.radar.render_fov_h_deg / 2
    edge_m = height / np.sin(np.radians(half_fov))
    grazing = np.degrees(np.arcsin(np.minimum(height / np.array([1.5, 2.3]), 1.0)))
    numbers = {"floor_over_noise_db": floor_over, "scene_over_noise_db": scene_over,
               "floor_first_range_m": floor_start, "radar_height_m": height,
               "noise_floor_db": float(np.median(noise_db[r > 0.5])),
               "floor_scatterers": len(floor),
               "render_half_fov_deg": half_fov, "render_floor_edge_m": edge_m,
               "band_m": [1.5, 2.3]}
    fig, ax = plt.subplots(figsize=(11, 4.6), constrained_layout=True)
    ax.plot(r, scene_db, color="tab:blue", lw=1.1, label="whole scene (the frame)")
    ax.plot(r, floor_db, color="tab:brown", lw=1.0,
            label=f"floor alone ({numbers['floor_scatterers']} facets) + receiver")
    ax.plot(r, noise_db, color="0.45", lw=0.9, label="receiver alone (noise, leakage)")
    ax.axvspan(1.5, 2.3, color="tab:green", alpha=0.12,
               label=f"1.5–2.3 m: floor {floor_over:.1f} dB over the noise")
    ax.axvline(edge_m, color="k", ls=":", lw=0.8)
    ax.text(edge_m - 0.03, numbers["noise_floor_db"] + 10,
            f"render's lower edge (−{half_fov:.0f}°)\nmeets the floor {height:.2f} m below:"
            f"\n{height:.2f} m / sin {half_fov:.0f}° = {edge_m:.2f} m", fontsize=8, ha="right")
    ax.set_xlim(0, r[-1])
    ax.set_xlabel("range (m)")
    ax.set_ylabel("power (dBFS, chirp- and channel-averaged)")
    ax.set_title(f"Office range profile and the floor's clutter — office.json, "
                 f"t = {frame.time_s:.2f} s (Hann window)")
    ax.legend(fontsize=8, loc="upper right")
    ax.grid(alpha=0.3)
    name = "fig8_surfaces_office_floor.png"
    _save(fig, out / name)
    text = (
        f"The radar render covers the antennas' field of view (±{half_fov:.0f}° in azimuth "
        f"and elevation, the two-way element pattern down to {COVERAGE_LEVEL_DB:.0f} dB), so "
        f"the floor under the "
        f"radar ({height:.2f} m below it) is in the scene from where the render's lower edge "
        f"meets it, {height:.2f} m / sin {half_fov:.0f}° = {edge_m:.2f} m, outwards (the floor "
        f"nearer than that lies beyond the pattern's {COVERAGE_LEVEL_DB:.0f} dB edge and is left "
        f"out). The "
        f"floor's {numbers['floor_scatterers']} facets alone, through the same receiver and "
        f"DSP, rise 6 dB above the receiver noise from {floor_start:.2f} m and stand "
        f"{floor_over:.1f} dB over it on average between 1.5 and 2.3 m; the whole scene is "
        f"{scene_over:.1f} dB over the noise there, so that band is the floor's grazing "
        f"clutter (the concrete's diffuse σ⁰ seen {grazing[1]:.0f}–{grazing[0]:.0f}° below "
        f"boresight). Beyond 2.3 m the "
        f"desks, chair, person, walls and the corner reflector rise above it; before "
        f"{edge_m:.2f} m the profile is the receiver's noise and the leakage tone's "
        f"high-passed skirt."
    )
    return Figure(name, "Surfaces: office floor clutter", text, section="Surfaces"), numbers


def surfaces_moving_rig(out: Path, *, progress: Callable[[str], None]
                        ) -> tuple[Figure, dict[str, Any]]:
    """Surfaces (d): a static sphere's power over 20 frames of a rig moving 2 cm/frame."""
    plt = _plt()
    radius, distance, step, dt, frames = 0.10, 3.0, 0.02, 0.1, 20
    rig = SensorRig(motion=Motion(velocity_mps=(0.0, step / dt, 0.0)))
    project = _one_object(Sphere(radius_m=radius), distance, rig=rig)
    cfg = project.rig.radar.model_copy(update=_IDEAL_RECEIVER)
    project.rig.radar = cfg
    pattern = cfg.element_pattern
    assert isinstance(pattern, CosinePattern)     # the default: cos^q in azimuth
    q_az = pattern.exponent_az
    radar = _SingleObjectRadar()
    measured, model, ranges, az = [], [], [], []
    try:
        for i in range(frames):
            t = dt * i
            centre, a = _radar_to_origin(project, t)
            rng = centre - radius
            gain = max(np.cos(a), 0.0) ** (2 * q_az)
            measured.append(radar.peak_dbfs(project, cfg, t=t))
            model.append(20 * np.log10(radar_equation_amplitude(
                cfg, np.pi * radius**2, rng, gain)))
            ranges.append(rng)
            az.append(np.degrees(a))
    finally:
        radar.close()
    progress("surfaces: moving rig done")
    meas, mod = np.array(measured), np.array(model)
    resid = meas - mod
    numbers = {"frames": frames, "step_m": step, "ranges_m": ranges, "azimuth_deg": az,
               "measured_dbfs": measured, "model_dbfs": model,
               "max_step_beyond_model_db": float(np.max(np.abs(np.diff(resid)))),
               "max_step_raw_db": float(np.max(np.abs(np.diff(meas)))),
               "model_change_db": float(mod.max() - mod.min()),
               "max_abs_error_db": float(np.max(np.abs(resid)))}
    fig, axes = plt.subplots(2, 1, figsize=(10, 6), sharex=True, constrained_layout=True,
                             gridspec_kw={"height_ratios": [2, 1]})
    idx = np.arange(frames)
    axes[0].plot(idx, mod, "k-", lw=1, label="radar equation πr², R⁻⁴ and element pattern")
    axes[0].plot(idx, meas, "o", color="tab:red", ms=5, label="simulated range-FFT peak")
    axes[0].set_ylabel("peak power (dBFS)")
    axes[0].set_ylim(float(mod.mean()) - 3, float(mod.mean()) + 2)
    axes[0].set_title(f"Static aluminium sphere (r = {radius * 100:.0f} cm, {distance:.0f} m "
                      f"ahead) seen by a rig moving {step * 100:.0f} cm per frame sideways")
    axes[0].legend(fontsize=8)
    axes[0].grid(alpha=0.3)
    axes[1].plot(idx, resid, "s-", color="tab:blue", ms=4, lw=0.8)
    axes[1].axhline(0, color="k", lw=0.6)
    axes[1].set_ylim(min(-1.5, resid.min() - 0.3), max(1.5, resid.max() + 0.3))
    axes[1].set_ylabel("simulated − model (dB)")
    axes[1].set_xticks(idx[::2])
    axes[1].set_xlabel(f"frame (Δt = {dt:.1f} s; azimuth 0° → {az[-1]:.1f}°)")
    axes[1].grid(alpha=0.3)
    name = "fig9_surfaces_moving_rig.png"
    _save(fig, out / name)
    text = (
        f"The sphere's speckle is a fixed function of the surface point in object "
        f"coordinates, so a static object seen from a moving rig decorrelates only with the "
        f"aspect angle. Over {frames} frames of a rig moving {step * 100:.0f} cm per frame "
        f"sideways (azimuth 0° to {az[-1]:.1f}°) the peak follows the radar equation with "
        f"πr², R⁻⁴ and the element pattern within {numbers['max_abs_error_db']:.2f} dB; the "
        f"largest frame-to-frame change beyond that model is "
        f"{numbers['max_step_beyond_model_db']:.3f} dB (raw: "
        f"{numbers['max_step_raw_db']:.3f} dB, the model itself changes by "
        f"{numbers['model_change_db']:.2f} dB over the sequence)."
    )
    return Figure(name, "Surfaces: a static sphere under a moving rig", text,
                  section="Surfaces"), numbers
