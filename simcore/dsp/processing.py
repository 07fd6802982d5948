"""One radar frame through the whole processing chain: ADC cube → maps → point cloud."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from simcore.dsp.angle import (
    ArrayLayout,
    array_layout,
    estimate_angles,
    secondary_azimuth_peaks,
    spatial_covariance,
    virtual_array_positions_m,
)
from simcore.dsp.cfar import CfarResult, cfar_1d, cfar_2d, group_peaks, suppress_sidelobes
from simcore.dsp.detections import (
    Detections,
    spherical_to_radar_xyz,
    transform_points,
)
from simcore.dsp.interference import mitigate_interference
from simcore.dsp.maps import (
    bird_eye_axes,
    bird_eye_image,
    range_azimuth_power,
    range_doppler_power,
    range_profile_power,
)
from simcore.dsp.peaks import parabolic_peak_offset
from simcore.dsp.spectrum import (
    compensate_tdm_doppler,
    doppler_fft,
    doppler_fft_size,
    range_axis_m,
    range_bin_count,
    range_fft,
    range_fft_size,
    velocity_axis_mps,
)
from simcore.dsp.windows import make_window, peak_sidelobe_db, power_to_db
from simcore.scene.dsp_config import DspConfig
from simcore.scene.radar_config import RadarConfig

H5Items = dict[str, tuple[NDArray[np.generic], str]]


@dataclass(frozen=True)
class RadarAxes:
    """Axes of the frame products; they depend only on the radar and DSP configurations.

    Attributes
    ----------
    range_m : ndarray, shape (n_range,), float64
        Range of each kept range bin (m).
    velocity_mps : ndarray, shape (n_doppler,), float64
        Radial velocity of each (fft-shifted) Doppler bin (m/s, positive = moving away).
    azimuth_deg : ndarray, shape (n_az,), float64
        Azimuth grid of the range–azimuth map (deg, positive right).
    elevation_deg : ndarray, shape (n_el,), float64
        Elevation search grid (deg, positive up).
    bev_x_m, bev_z_m : ndarray, shapes (nx,), (nz,), float64
        Pixel centres of the bird's-eye image: lateral x (right) and forward z (m).
    range_fft_size, doppler_fft_size : int
        FFT lengths.
    """

    range_m: NDArray[np.float64]
    velocity_mps: NDArray[np.float64]
    azimuth_deg: NDArray[np.float64]
    elevation_deg: NDArray[np.float64]
    bev_x_m: NDArray[np.float64]
    bev_z_m: NDArray[np.float64]
    range_fft_size: int
    doppler_fft_size: int


def _grid(lo: float, hi: float, step: float) -> NDArray[np.float64]:
    n = int(np.floor((hi - lo) / step + 1e-9)) + 1
    return lo + np.arange(n, dtype=np.float64) * step


def radar_axes(radar_config: RadarConfig, dsp_config: DspConfig) -> RadarAxes:
    """Compute every axis of the frame products.

    Parameters
    ----------
    radar_config : RadarConfig
        Waveform and antennas.
    dsp_config : DspConfig
        Processing options.

    Returns
    -------
    RadarAxes
    """
    rc, dc = radar_config, dsp_config
    n_fft = range_fft_size(rc.samples_per_chirp, dc.range_fft_size)
    n_bins = range_bin_count(n_fft, complex_iq=rc.complex_iq)
    r = range_axis_m(n_bins=n_bins, fft_size=n_fft, sample_rate_hz=rc.sample_rate_hz,
                     slope_hz_per_s=rc.slope_hz_per_s)
    if dc.max_range_m is not None:
        r = r[r <= dc.max_range_m]
        if r.size < 2:
            raise ValueError(f"max_range_m = {dc.max_range_m} keeps fewer than 2 range bins")
    n_dop = doppler_fft_size(rc.chirps_per_frame, dc.doppler_fft_size)
    v = velocity_axis_mps(fft_size=n_dop,
                          chirp_interval_s=len(rc.tx) * rc.chirp_repetition_time_s,
                          wavelength_m=rc.wavelength_m)
    az = _grid(dc.azimuth_min_deg, dc.azimuth_max_deg, dc.azimuth_step_deg)
    el = _grid(dc.elevation_min_deg, dc.elevation_max_deg, dc.elevation_step_deg)
    max_az = np.deg2rad(max(abs(az[0]), abs(az[-1])))
    bx, bz = bird_eye_axes(max_range_m=float(r[-1]), max_azimuth_rad=float(max_az),
                           resolution_m=dc.bev_resolution_m)
    return RadarAxes(r, v, az, el, bx, bz, n_fft, n_dop)


def static_axes_items(radar_config: RadarConfig, dsp_config: DspConfig, *,
                      group: str) -> H5Items:
    """Run-constant HDF5 datasets of the radar products: path → (array, unit).

    Parameters
    ----------
    radar_config : RadarConfig
        Waveform and antennas.
    dsp_config : DspConfig
        Processing options.

    Returns
    -------
    dict
        ``/<group>/range_axis`` (n_range,) m, ``velocity_axis`` (n_doppler,) m/s,
        ``azimuth_axis`` (n_az,) deg, ``bird_eye_x_axis`` (nx,) m and
        ``bird_eye_z_axis`` (nz,) m, all float64; they label the axes of the
        per-frame items of :meth:`RadarProducts.hdf5_items`.
    """
    ax = radar_axes(radar_config, dsp_config)
    return {
        f"/{group}/range_axis": (ax.range_m, "m"),
        f"/{group}/velocity_axis": (ax.velocity_mps, "m/s"),
        f"/{group}/azimuth_axis": (ax.azimuth_deg, "deg"),
        f"/{group}/bird_eye_x_axis": (ax.bev_x_m, "m"),
        f"/{group}/bird_eye_z_axis": (ax.bev_z_m, "m"),
    }


@dataclass(frozen=True)
class RadarProducts:
    """Every DSP product of one frame.

    Attributes
    ----------
    axes : RadarAxes
        Axes of all maps.
    range_cube : ndarray, shape (chirps, channels, range), complex64
        Range spectra (amplitude-normalised; :mod:`simcore.dsp.spectrum`).
    range_doppler_cube : ndarray, shape (doppler, channels, range), complex64
        Range–Doppler spectra, TDM Doppler phase compensated when enabled.
    range_profile_db : ndarray, shape (channels, range), float32
        Range profile of each (virtual) channel, mean power over chirps (dB).
    range_profile_integrated_db : ndarray, shape (range,), float32
        The same averaged over channels (dB).
    range_doppler_db : ndarray, shape (doppler, range), float32
        Range–Doppler map, mean power over channels (dB).
    range_azimuth_db : ndarray, shape (azimuth, range), float32
        Range–azimuth map at zero elevation, mean over Doppler bins (dB).
    bird_eye_db : ndarray, shape (nz, nx), float32
        Range–azimuth map resampled to Cartesian x (right) × z (forward) pixels (dB, NaN
        outside the coverage).
    cfar : CfarResult
        Detector output on the range–Doppler power map, shape (doppler, range).
    peaks : ndarray, shape (doppler, range), bool
        CFAR hits left after peak grouping, Doppler sidelobe suppression and the dynamic
        range floor (before the range limits and ``max_detections``).
    detections : Detections
        Point cloud of the frame.
    """

    axes: RadarAxes
    range_cube: NDArray[np.complex64]
    range_doppler_cube: NDArray[np.complex64]
    range_profile_db: NDArray[np.float32]
    range_profile_integrated_db: NDArray[np.float32]
    range_doppler_db: NDArray[np.float32]
    range_azimuth_db: NDArray[np.float32]
    bird_eye_db: NDArray[np.float32]
    cfar: CfarResult
    peaks: NDArray[np.bool_]
    detections: Detections

    def hdf5_items(self, *, group: str) -> H5Items:
        """Per-frame HDF5 datasets: path → (array without the frame axis, unit).

        Parameters
        ----------
        group : str
            The radar's dataset group (its name).

        Returns
        -------
        dict
            ``/<group>/range_profile`` (channels, range), ``range_profile_integrated``
            (range,), ``range_doppler`` (doppler, range), ``range_azimuth``
            (azimuth, range), ``bird_eye`` (nz, nx); all float32 dB, under the radar's
            group (its name). The detections go to its ``detections`` table via
            :meth:`detection_records`.
        """
        return {
            f"/{group}/range_profile": (self.range_profile_db, "dB"),
            f"/{group}/range_profile_integrated": (self.range_profile_integrated_db, "dB"),
            f"/{group}/range_doppler": (self.range_doppler_db, "dB"),
            f"/{group}/range_azimuth": (self.range_azimuth_db, "dB"),
            f"/{group}/bird_eye": (self.bird_eye_db, "dB"),
        }

    def detection_records(self, frame: int) -> NDArray[np.void]:
        """Return this frame's detections as rows of :data:`~simcore.dsp.DETECTION_DTYPE`."""
        return self.detections.records(frame)


@dataclass(frozen=True)
class _FrameConstants:
    """What the chain derives from the configurations alone (read-only arrays)."""

    axes: RadarAxes
    layout: ArrayLayout
    azimuth_rad: NDArray[np.float64]
    n_eff: float                  # (Σw)² / Σw² of the Doppler window
    doppler_sidelobe_db: float    # its peak sidelobe level


_FRAME_CONSTANTS: dict[str, _FrameConstants] = {}


def _frame_constants(rc: RadarConfig, dc: DspConfig) -> _FrameConstants:
    """Axes, array layout and Doppler-window figures, cached per pair of configurations."""
    key = rc.model_dump_json() + dc.model_dump_json()
    const = _FRAME_CONSTANTS.get(key)
    if const is None:
        axes = radar_axes(rc, dc)
        layout = array_layout(virtual_array_positions_m(rc))
        w_d = make_window(dc.doppler_window, rc.chirps_per_frame,
                          sidelobe_db=dc.doppler_window_sidelobe_db).astype(np.float64)
        const = _FrameConstants(axes, layout, np.deg2rad(axes.azimuth_deg),
                                float(np.sum(w_d) ** 2 / np.sum(w_d ** 2)),
                                peak_sidelobe_db(w_d))
        for arr in (*vars(axes).values(), *vars(layout).values(), const.azimuth_rad):
            if isinstance(arr, np.ndarray):
                arr.setflags(write=False)
        if len(_FRAME_CONSTANTS) > 8:
            _FRAME_CONSTANTS.clear()
        _FRAME_CONSTANTS[key] = const
    return const


def _check_cube(cube: NDArray[np.generic], rc: RadarConfig) -> None:
    expected = (rc.chirps_per_frame, len(rc.tx) * len(rc.rx), rc.samples_per_chirp)
    if cube.shape != expected:
        raise ValueError(
            f"ADC cube has shape {cube.shape}, expected (chirps, tx*rx channels, samples) = "
            f"{expected} for this radar configuration"
        )


def process_frame(
    cube: ArrayLike,
    radar_config: RadarConfig,
    dsp_config: DspConfig | None = None,
    *,
    radar_to_world: ArrayLike | None = None,
) -> RadarProducts:
    """Run the processing chain on one ADC cube.

    Chain: range FFT (DC removal, window, zero padding) → Doppler FFT (optional static
    clutter removal, window, zero padding, fft-shift) → TDM-MIMO Doppler phase
    compensation → maps (range profiles, range–Doppler, range–azimuth, bird's eye) →
    CFAR on the channel-averaged range–Doppler power → peak grouping → range/velocity
    refinement, angle estimation, point cloud.

    Parameters
    ----------
    cube : array_like, shape (chirps, channels, samples)
        ADC samples, float (real IF) or complex (IQ); channels are the ``n_tx * n_rx``
        virtual channels, tx-major.
    radar_config : RadarConfig
        Waveform and antenna layout the cube was recorded with.
    dsp_config : DspConfig, optional
        Processing options (defaults: ``DspConfig()``).
    radar_to_world : array_like, shape (4, 4), keyword-only, optional
        Radar optical frame → world transform; when given, the detections also carry
        world coordinates.

    Returns
    -------
    RadarProducts
    """
    rc = radar_config
    dc = DspConfig() if dsp_config is None else dsp_config
    x = np.asarray(cube)
    _check_cube(x, rc)
    const = _frame_constants(rc, dc)
    range_cube, rd = _spectra(x, const.axes, rc, dc)
    profile = range_profile_power(range_cube)
    rd_power = range_doppler_power(rd)
    ra_db, bev = _range_azimuth_maps(rd, const, rc, dc)
    cfar, peaks = _detect_peaks(rd_power, const, dc, n_integrated=rd.shape[1])
    detections = _detections(rd, rd_power, cfar, peaks, const.axes, const.layout, rc, dc,
                             radar_to_world)
    return RadarProducts(
        axes=const.axes,
        range_cube=range_cube,
        range_doppler_cube=rd,
        range_profile_db=power_to_db(profile),
        range_profile_integrated_db=power_to_db(profile.mean(axis=0)),
        range_doppler_db=power_to_db(rd_power),
        range_azimuth_db=ra_db,
        bird_eye_db=bev,
        cfar=cfar,
        peaks=peaks,
        detections=detections,
    )


def _spectra(x: NDArray[np.generic], axes: RadarAxes, rc: RadarConfig, dc: DspConfig
             ) -> tuple[NDArray[np.complex64], NDArray[np.complex64]]:
    """Interference mitigation, range FFT, Doppler FFT, TDM phase compensation."""
    if dc.interference_mitigation != "off":
        x = mitigate_interference(x, method=dc.interference_mitigation,
                                  threshold=dc.interference_threshold)
    range_cube = range_fft(x, window=dc.range_window, sidelobe_db=dc.range_window_sidelobe_db,
                           fft_size=axes.range_fft_size, remove_dc=dc.remove_dc,
                           n_bins=axes.range_m.size)
    rd = doppler_fft(range_cube, window=dc.doppler_window,
                     sidelobe_db=dc.doppler_window_sidelobe_db, fft_size=axes.doppler_fft_size,
                     static_clutter_removal=dc.static_clutter_removal)
    n_tx = len(rc.tx)
    if n_tx > 1 and dc.tdm_doppler_compensation:
        rd = compensate_tdm_doppler(rd, velocity_axis_mps=axes.velocity_mps, n_tx=n_tx,
                                    chirp_repetition_time_s=rc.chirp_repetition_time_s,
                                    wavelength_m=rc.wavelength_m)
    return range_cube, rd


def _range_azimuth_maps(rd: NDArray[np.complex64], const: _FrameConstants, rc: RadarConfig,
                        dc: DspConfig) -> tuple[NDArray[np.float32], NDArray[np.float32]]:
    """Range–azimuth map (dB) and its bird's-eye resampling."""
    axes, az_rad = const.axes, const.azimuth_rad
    # Doppler bins as snapshots, Parseval-scaled to per-chirp power.
    ra_method = "bartlett" if dc.angle_method == "monopulse" else dc.angle_method
    ra_power = range_azimuth_power(rd, const.layout, wavelength_m=rc.wavelength_m,
                                   azimuth_rad=az_rad, method=ra_method,
                                   diagonal_loading=dc.capon_diagonal_loading,
                                   fft_size=dc.angle_fft_size) * np.float32(const.n_eff)
    ra_db = power_to_db(ra_power)
    bev = bird_eye_image(ra_db, range_axis_m=axes.range_m, azimuth_axis_rad=az_rad,
                         x_axis_m=axes.bev_x_m, z_axis_m=axes.bev_z_m)
    return ra_db, bev


def _detect_peaks(rd_power: NDArray[np.float32], const: _FrameConstants, dc: DspConfig, *,
                  n_integrated: int) -> tuple[CfarResult, NDArray[np.bool_]]:
    """CFAR, peak grouping, Doppler sidelobe suppression and the dynamic-range floor."""
    if dc.cfar_dimensions == 2:
        cfar = cfar_2d(rd_power, method=dc.cfar_method,
                       train=(dc.cfar_train_doppler, dc.cfar_train_range),
                       guard=(dc.cfar_guard_doppler, dc.cfar_guard_range), pfa=dc.cfar_pfa,
                       rank=dc.cfar_os_rank, n_integrated=n_integrated,
                       circular=(True, False))
    else:
        cfar = cfar_1d(rd_power, method=dc.cfar_method, train=dc.cfar_train_range,
                       guard=dc.cfar_guard_range, pfa=dc.cfar_pfa, rank=dc.cfar_os_rank,
                       n_integrated=n_integrated, axis=-1, circular=False)
    peaks = group_peaks(rd_power, cfar.detections, method=dc.peak_grouping,
                        neighbourhood=dc.peak_neighbourhood, circular=(True, False))
    if dc.doppler_sidelobe_margin_db is not None:
        peaks = suppress_sidelobes(rd_power, peaks, axis=0, sidelobe_db=const.doppler_sidelobe_db,
                                   margin_db=dc.doppler_sidelobe_margin_db,
                                   spread=dc.peak_neighbourhood[1] // 2)
    if dc.max_dynamic_range_db is not None:
        floor = float(np.max(rd_power)) * 10.0 ** (-dc.max_dynamic_range_db / 10.0)
        peaks = peaks & (rd_power > floor)
    return cfar, peaks


def _detections(
    rd: NDArray[np.complex64],
    rd_power: NDArray[np.float32],
    cfar: CfarResult,
    peaks: NDArray[np.bool_],
    axes: RadarAxes,
    layout: ArrayLayout,
    rc: RadarConfig,
    dc: DspConfig,
    radar_to_world: ArrayLike | None,
) -> Detections:
    """Point cloud of the peak cells: refined range and velocity, angles, SNR."""
    i_d, i_r, p = _detection_cells(peaks, rd_power, axes, rc, dc)
    if i_d.size == 0:
        return Detections.empty(with_world=radar_to_world is not None)
    rng, vel = _refined_range_velocity(rd_power, i_d, i_r, axes, dc)
    snapshots = _cell_snapshots(rd, i_d, i_r, vel, axes, rc, dc)
    cov = None
    if dc.angle_method == "capon":
        cov = spatial_covariance(rd[:, :, i_r])  # (n, ch, ch)
    az, el = estimate_angles(
        snapshots, layout, wavelength_m=rc.wavelength_m, method=dc.angle_method,
        azimuth_grid_rad=np.deg2rad(axes.azimuth_deg),
        elevation_grid_rad=np.deg2rad(axes.elevation_deg), covariances=cov,
        diagonal_loading=dc.capon_diagonal_loading, fft_size=dc.angle_fft_size)
    noise = cfar.noise[i_d, i_r].astype(np.float64)
    if dc.angle_peaks_within_db is not None and layout.has_horizontal_extent:
        idx, az2, p2 = _shared_cell_peaks(snapshots, p, i_d, i_r, el, cfar, axes, layout,
                                          rc, within_db=dc.angle_peaks_within_db)
        sel = np.concatenate([np.arange(i_d.size), idx])
        i_d, i_r, rng, vel, el, noise = (a[sel] for a in (i_d, i_r, rng, vel, el, noise))
        p = p[sel] * p2
        az = np.concatenate([az, az2])
    return _detections_table(i_d, i_r, rng, vel, az, el, p, noise, radar_to_world)


def _detection_cells(peaks: NDArray[np.bool_], rd_power: NDArray[np.float32],
                     axes: RadarAxes, rc: RadarConfig, dc: DspConfig) -> tuple[
        NDArray[np.intp], NDArray[np.intp], NDArray[np.float64]]:
    """Peak cells (Doppler, range index, power) inside the range limits, strongest first."""
    i_d, i_r = np.nonzero(peaks)
    keep = axes.range_m[i_r] >= dc.min_range_m
    if rc.complex_iq:
        # IQ bins past the middle of the FFT hold negative beat frequencies: the last bins
        # are the near-DC zone (leakage, the high-pass's skirt, the window's main lobe
        # around DC) wrapped around, not far targets; min_range_m applies to them too.
        span_m = axes.range_fft_size * float(axes.range_m[1] - axes.range_m[0])
        keep &= span_m - axes.range_m[i_r] >= dc.min_range_m
    i_d, i_r = i_d[keep], i_r[keep]
    p = rd_power[i_d, i_r].astype(np.float64)
    order = np.argsort(-p, kind="stable")[: dc.max_detections]
    return i_d[order], i_r[order], p[order]


def _refined_range_velocity(rd_power: NDArray[np.float32], i_d: NDArray[np.intp],
                            i_r: NDArray[np.intp], axes: RadarAxes, dc: DspConfig) -> tuple[
        NDArray[np.float64], NDArray[np.float64]]:
    """Range and velocity of the cells, parabolically interpolated when asked."""
    n_dop, n_rng = rd_power.shape
    rng = axes.range_m[i_r].astype(np.float64)
    vel = axes.velocity_mps[i_d].astype(np.float64)
    if not dc.interpolate_peaks:
        return rng, vel

    def pdb(rows: NDArray[np.intp], cols: NDArray[np.intp]) -> NDArray[np.float64]:
        """The map in dB at some cells (only those the refinement reads)."""
        return 10.0 * np.log10(np.maximum(rd_power[rows, cols].astype(np.float64), 1e-30))

    dr = axes.range_m[1] - axes.range_m[0]
    inner = (i_r > 0) & (i_r < n_rng - 1)
    r_l, r_r = np.clip(i_r - 1, 0, n_rng - 1), np.clip(i_r + 1, 0, n_rng - 1)
    mid = pdb(i_d, i_r)
    off_r = np.where(
        inner, parabolic_peak_offset(pdb(i_d, r_l), mid, pdb(i_d, r_r)), 0.0)
    rng = rng + off_r * dr
    if n_dop >= 3:
        dv = axes.velocity_mps[1] - axes.velocity_mps[0]
        off_v = parabolic_peak_offset(pdb((i_d - 1) % n_dop, i_r), mid,
                                      pdb((i_d + 1) % n_dop, i_r))
        vel = vel + off_v * dv
    return rng, vel


def _cell_snapshots(rd: NDArray[np.complex64], i_d: NDArray[np.intp], i_r: NDArray[np.intp],
                    vel: NDArray[np.float64], axes: RadarAxes, rc: RadarConfig,
                    dc: DspConfig) -> NDArray[np.complex128]:
    """Channel responses of the cells, shape (n, channels), TDM phase finished."""
    snapshots = np.asarray(rd[i_d, :, i_r]).astype(np.complex128)  # (n, channels)
    n_tx = len(rc.tx)
    if n_tx > 1 and dc.tdm_doppler_compensation:
        # The cube was de-rotated with each bin's velocity; finish with the refined one.
        tx_index = np.repeat(np.arange(n_tx), len(rc.rx))
        dv = vel - axes.velocity_mps[i_d]
        snapshots *= np.exp(-4j * np.pi * dv[:, None] * tx_index[None, :]
                            * rc.chirp_repetition_time_s / rc.wavelength_m)
    return snapshots


def _shared_cell_peaks(snapshots: NDArray[np.complex128], p: NDArray[np.float64],
                       i_d: NDArray[np.intp], i_r: NDArray[np.intp], el: NDArray[np.float64],
                       cfar: CfarResult, axes: RadarAxes, layout: ArrayLayout,
                       rc: RadarConfig, *, within_db: float) -> tuple[
        NDArray[np.int64], NDArray[np.float64], NDArray[np.float64]]:
    """Targets sharing a range–Doppler cell: one further detection per azimuth peak.

    Returns the cell of each further peak, its azimuth (rad), and the power factor of
    every detection, the main ones (1) followed by the further ones.
    """
    idx, az2, rel_db = secondary_azimuth_peaks(
        snapshots, layout.positions_m, wavelength_m=rc.wavelength_m,
        azimuth_grid_rad=np.deg2rad(axes.azimuth_deg), elevation_rad=el,
        within_db=within_db)
    # A further peak must pass the CFAR threshold on its own share of the power.
    strong = p[idx] * 10.0 ** (rel_db / 10.0) > cfar.threshold[i_d[idx], i_r[idx]]
    idx, az2, rel_db = idx[strong], az2[strong], rel_db[strong]
    factor = 10.0 ** (np.concatenate([np.zeros(i_d.size), rel_db]) / 10.0)
    return idx, az2, factor


def _detections_table(i_d: NDArray[np.intp], i_r: NDArray[np.intp], rng: NDArray[np.float64],
                      vel: NDArray[np.float64], az: NDArray[np.float64],
                      el: NDArray[np.float64], p: NDArray[np.float64],
                      noise: NDArray[np.float64], radar_to_world: ArrayLike | None
                      ) -> Detections:
    """The point cloud: positions, SNR and power of every detection."""
    snr_db = 10.0 * np.log10(np.maximum(p, 1e-30) / np.maximum(noise, 1e-30))
    xyz = spherical_to_radar_xyz(rng, az, el)
    world = None if radar_to_world is None else transform_points(xyz, radar_to_world)
    return Detections(
        doppler_index=i_d.astype(np.int64),
        range_index=i_r.astype(np.int64),
        range_m=rng,
        velocity_mps=vel,
        azimuth_deg=np.rad2deg(az),
        elevation_deg=np.rad2deg(el),
        snr_db=snr_db,
        power_db=10.0 * np.log10(np.maximum(p, 1e-30)),
        xyz_radar_m=xyz,
        xyz_world_m=world,
    )


__all__ = [
    "H5Items",
    "RadarAxes",
    "RadarProducts",
    "process_frame",
    "radar_axes",
    "static_axes_items",
]
