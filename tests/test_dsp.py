"""Known-answer tests of the radar processing chain on analytically built ADC cubes.

Every cube here is synthesised in this file from the FMCW model of DESIGN.md — the exact
two-way delay ``tau = (|X - p_tx| + |X - p_rx|) / c`` with ``X`` moved by its velocity to
each chirp's start time ``(k * n_tx + j) * T_r`` and the IF sample
``a cos(2 pi f_c tau + 2 pi K tau t_n - pi K tau^2)`` (``a exp(j ...)`` for IQ) — never by the
simulator, so that the processing's sign conventions are checked against the physics and
not against themselves.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from numpy.testing import assert_allclose, assert_array_equal

from simcore.dsp import (
    DETECTION_DTYPE,
    DspConfig,
    array_layout,
    bartlett_spectrum,
    capon_spectrum,
    doppler_fft,
    make_window,
    monopulse_azimuth_rad,
    process_frame,
    radar_axes,
    range_axis_m,
    range_fft,
    spatial_covariance,
    static_axes_items,
    steering_vectors,
    velocity_axis_mps,
    virtual_array_positions_m,
)
from simcore.dsp.windows import peak_sidelobe_db
from simcore.scene.radar_config import SPEED_OF_LIGHT, Antenna, RadarConfig

ROOT = Path(__file__).resolve().parents[1]


# --------------------------------------------------------------------------------------
# Analytic cube synthesis (independent of simcore.dsp)
# --------------------------------------------------------------------------------------


def optical_point(range_m: float, az_deg: float, el_deg: float = 0.0) -> np.ndarray:
    """Point at range/azimuth/elevation in the radar optical frame (x right, y down, z fwd)."""
    az, el = np.deg2rad(az_deg), np.deg2rad(el_deg)
    return range_m * np.array([np.sin(az) * np.cos(el), -np.sin(el), np.cos(az) * np.cos(el)])


def synth_cube(rc: RadarConfig, targets: list[tuple[np.ndarray, np.ndarray, float]], *,
               noise_std: float = 0.0, seed: int = 0) -> np.ndarray:
    """ADC cube (chirps, tx*rx, samples) of point targets (position, velocity, amplitude).

    Positions/velocities in the radar optical frame (m, m/s). Noise: real N(0, noise_std²)
    per sample, or complex with E|n|² = noise_std² for IQ.
    """
    n_tx, n_rx = len(rc.tx), len(rc.rx)
    p_tx = np.array([[a.position_mm[0] * 1e-3, a.position_mm[1] * 1e-3, 0.0] for a in rc.tx])
    p_rx = np.array([[a.position_mm[0] * 1e-3, a.position_mm[1] * 1e-3, 0.0] for a in rc.rx])
    t_n = np.arange(rc.samples_per_chirp) / rc.sample_rate_hz
    slope, f_c = rc.bandwidth_hz / rc.chirp_time_s, rc.start_frequency_hz
    k = np.arange(rc.chirps_per_frame)
    dtype = complex if rc.complex_iq else float
    out = np.zeros((rc.chirps_per_frame, n_tx * n_rx, rc.samples_per_chirp), dtype=dtype)
    for pos, vel, amp in targets:
        for j in range(n_tx):
            t0 = (k * n_tx + j) * rc.chirp_repetition_time_s
            x = np.asarray(pos)[None, :] + np.asarray(vel)[None, :] * t0[:, None]
            d_tx = np.linalg.norm(x - p_tx[j], axis=1)
            for i in range(n_rx):
                tau = ((d_tx + np.linalg.norm(x - p_rx[i], axis=1)) / SPEED_OF_LIGHT)[:, None]
                phase = (2 * np.pi * f_c * tau + 2 * np.pi * slope * tau * t_n[None, :]
                         - np.pi * slope * tau**2)
                out[:, j * n_rx + i, :] += amp * (np.exp(1j * phase) if rc.complex_iq
                                                  else np.cos(phase))
    if noise_std:
        rng = np.random.default_rng(seed)
        if rc.complex_iq:
            out += noise_std / np.sqrt(2) * (rng.standard_normal(out.shape)
                                             + 1j * rng.standard_normal(out.shape))
        else:
            out += noise_std * rng.standard_normal(out.shape)
    return out.astype(np.complex64 if rc.complex_iq else np.float32)


def ula_config(n_rx: int, *, n_tx: int = 1, chirps: int = 16, complex_iq: bool = True,
               samples: int = 256) -> RadarConfig:
    """Radar with an ``n_rx`` λ/2 ULA along x (λ at the chirp centre); Tx ``n_rx·λ/2`` apart."""
    base = RadarConfig()
    half_mm = 0.5 * base.wavelength_m * 1e3
    return RadarConfig(
        samples_per_chirp=samples, chirp_time_s=samples / 2e6 + 1e-6, sample_rate_hz=2e6,
        chirps_per_frame=chirps, complex_iq=complex_iq,
        tx=[Antenna(name=f"tx{j + 1}", position_mm=(j * n_rx * half_mm, 0.0))
            for j in range(n_tx)],
        rx=[Antenna(name=f"rx{i + 1}", position_mm=(i * half_mm, 0.0)) for i in range(n_rx)],
    )


def local_maxima(y: np.ndarray, *, within_db: float = 30.0) -> np.ndarray:
    """Indices of local maxima of a dB curve that are within ``within_db`` of its maximum."""
    idx = np.flatnonzero((y[1:-1] > y[:-2]) & (y[1:-1] >= y[2:])) + 1
    return idx[y[idx] > y.max() - within_db]


# --------------------------------------------------------------------------------------
# Windows, range and Doppler FFTs
# --------------------------------------------------------------------------------------


def test_windows_come_from_scipy_and_have_the_expected_sidelobes() -> None:
    assert peak_sidelobe_db(make_window("hann", 64)) == pytest.approx(-31.5, abs=0.3)
    assert peak_sidelobe_db(make_window("chebyshev", 16, sidelobe_db=60)) == pytest.approx(
        -60.0, abs=0.05)
    assert peak_sidelobe_db(make_window("none", 64)) == pytest.approx(-13.3, abs=0.2)
    for name in ("hamming", "blackman", "blackmanharris"):
        w = make_window(name, 32)
        assert w.dtype == np.float32 and w.max() == pytest.approx(1.0)


@pytest.mark.parametrize("complex_iq", [False, True])
@pytest.mark.parametrize("bin_position", [77.0, 123.4])
def test_tone_lands_in_the_predicted_range_bin(complex_iq: bool, bin_position: float) -> None:
    rc = RadarConfig(complex_iq=complex_iq)
    n = rc.samples_per_chirp
    f_b = bin_position * rc.sample_rate_hz / n  # beat frequency of the target
    expected_range = f_b * SPEED_OF_LIGHT / (2 * rc.slope_hz_per_s)
    t = np.arange(n) / rc.sample_rate_hz
    amp = 0.25
    tone = amp * (np.exp(2j * np.pi * f_b * t + 0.3j) if complex_iq
                  else np.cos(2 * np.pi * f_b * t + 0.3))
    cube = np.broadcast_to(tone, (rc.chirps_per_frame, 3, n))
    spec = range_fft(cube, window="hann")
    assert spec.shape == (16, 3, n if complex_iq else n // 2) and spec.dtype == np.complex64
    axis = range_axis_m(n_bins=spec.shape[-1], fft_size=n, sample_rate_hz=rc.sample_rate_hz,
                        slope_hz_per_s=rc.slope_hz_per_s)
    peak = int(np.argmax(np.abs(spec[0, 0])))
    assert peak == round(bin_position)
    assert abs(axis[peak] - expected_range) <= 0.5 * rc.range_resolution_m
    if bin_position == round(bin_position):  # on-bin: amplitude normalisation reads A
        assert abs(spec[0, 0, peak]) == pytest.approx(amp, rel=1e-4)
    # process_frame's refined range is within 2 % of a bin (2.5 cm bins here).
    prod = process_frame(cube, rc, DspConfig(cfar_pfa=1e-3))
    assert len(prod.detections) >= 1
    assert abs(prod.detections.range_m[0] - expected_range) < 0.05 * rc.range_resolution_m


@pytest.mark.parametrize("velocity", [1.3, -0.8])
def test_doppler_phase_ramp_lands_in_the_right_velocity_bin(velocity: float) -> None:
    rc = RadarConfig(complex_iq=True)
    lam, t_r = rc.wavelength_m, rc.chirp_repetition_time_s
    k = np.arange(rc.chirps_per_frame)
    # Range bin 40 tone whose carrier phase advances 4π v T_r / λ per chirp.
    n = rc.samples_per_chirp
    t = np.arange(n) / rc.sample_rate_hz
    f_b = 40 * rc.sample_rate_hz / n
    phase_k = 4 * np.pi * velocity * k * t_r / lam
    cube = np.exp(1j * (2 * np.pi * f_b * t[None, :] + phase_k[:, None]))[:, None, :]
    cube = np.repeat(cube, 3, axis=1)
    rd = doppler_fft(range_fft(cube), fft_size=16)
    v_axis = velocity_axis_mps(fft_size=16, chirp_interval_s=t_r, wavelength_m=lam)
    assert_allclose(np.diff(v_axis), rc.velocity_resolution_mps)
    d = int(np.argmax(np.abs(rd[:, 0, 40])))
    assert abs(v_axis[d] - velocity) <= 0.5 * rc.velocity_resolution_mps + 1e-9
    assert np.sign(v_axis[d]) == np.sign(velocity)  # positive = moving away
    # Through the whole chain (2x zero-padded Doppler, parabolic refinement).
    prod = process_frame(cube.astype(np.complex64), rc, DspConfig(min_range_m=0.0))
    assert abs(prod.detections.velocity_mps[0] - velocity) < 0.1 * rc.velocity_resolution_mps


def test_two_targets_two_range_bins_apart_are_resolved_with_hann() -> None:
    rc = RadarConfig(complex_iq=True, chirps_per_frame=16)
    dr = rc.range_resolution_m
    r1 = 60 * dr
    r2 = r1 + 2 * dr
    # (a) one chirp, targets' carrier phases in quadrature at the window centre.
    n = rc.samples_per_chirp
    t = np.arange(n) / rc.sample_rate_hz
    f1, f2 = (2 * rc.slope_hz_per_s * r / SPEED_OF_LIGHT for r in (r1, r2))
    tc = t - t[n // 2]
    one = np.exp(2j * np.pi * f1 * tc) + np.exp(2j * np.pi * f2 * tc + 0.5j * np.pi)
    prof = 20 * np.log10(np.abs(range_fft(one[None, None, :], window="hann")[0, 0]) + 1e-12)
    peaks = local_maxima(prof[50:75]) + 50
    assert_array_equal(peaks, [60, 62])
    dip_a = min(prof[60], prof[62]) - prof[61]
    assert dip_a > 2.5
    # (b) whole frame, targets 3 velocity bins apart: their relative phase turns through
    # three full cycles over the frame, so the chirp-averaged range profile of
    # process_frame adds their powers and resolves them.
    v1, v2 = 0.5 * rc.velocity_resolution_mps, -0.5 * rc.velocity_resolution_mps
    targets = [(optical_point(r1, 0.0), optical_point(v1, 0.0), 1.0),
               (optical_point(r2, 0.0), optical_point(v2, 0.0), 1.0)]
    cube = synth_cube(rc, targets, noise_std=0.01)
    prod = process_frame(cube, rc, DspConfig(range_window="hann"))
    prof = prod.range_profile_integrated_db
    peaks = local_maxima(prof[50:75]) + 50
    assert_array_equal(peaks, [60, 62])
    dip_b = min(prof[60], prof[62]) - prof[61]
    print(f"dip_a={dip_a:.2f} dB dip_b={dip_b:.2f} dB")
    assert dip_b > 2.5
    # And a second sanity check: 2-D detection finds both, at their ranges and velocities.
    d = prod.detections
    assert len(d) == 2
    order = np.argsort(d.range_m)
    assert_allclose(d.range_m[order], [r1, r2], atol=0.2 * dr)
    assert_allclose(d.velocity_mps[order], [v1, v2], atol=rc.velocity_resolution_mps / 2)


# --------------------------------------------------------------------------------------
# Angle estimation
# --------------------------------------------------------------------------------------


def test_monopulse_azimuth_two_rx() -> None:
    rc = ula_config(2, complex_iq=False, samples=512)
    for az in (-35.0, -7.5, 0.0, 17.0, 48.0):
        cube = synth_cube(rc, [(optical_point(2.2, az), np.zeros(3), 1.0)],
                          noise_std=0.05, seed=3)
        prod = process_frame(cube, rc, DspConfig(angle_method="monopulse"))
        assert len(prod.detections) == 1
        print(f"monopulse: true {az:+.1f}°, estimated {prod.detections.azimuth_deg[0]:+.2f}°")
        assert prod.detections.azimuth_deg[0] == pytest.approx(az, abs=0.5)
        assert prod.detections.elevation_deg[0] == 0.0  # no vertical extent
    # The bare function: phase difference of a known plane wave.
    lam = rc.wavelength_m
    d = 0.5 * lam
    a = steering_vectors([[d, 0, 0], [0, 0, 0]], wavelength_m=lam,
                         azimuth_rad=np.deg2rad(23.0))
    assert np.rad2deg(monopulse_azimuth_rad(a[0], a[1], baseline_m=d, wavelength_m=lam)) == (
        pytest.approx(23.0, abs=1e-9))


@pytest.mark.parametrize("method", ["monopulse", "bartlett", "capon", "fft"])
def test_elevation_from_the_l_array(method: str) -> None:
    rc = RadarConfig()  # default: 3 Rx in an L (rx1 right of rx2, rx3 above rx2)
    assert array_layout(virtual_array_positions_m(rc)).has_vertical_extent
    for az, el in ((10.0, 12.0), (-25.0, -8.0)):
        cube = synth_cube(rc, [(optical_point(2.0, az, el), np.zeros(3), 1.0)],
                          noise_std=0.05, seed=4)
        prod = process_frame(cube, rc, DspConfig(angle_method=method))
        assert len(prod.detections) == 1
        det = prod.detections
        print(f"{method}: true ({az:+.1f}°, {el:+.1f}°), estimated "
              f"({det.azimuth_deg[0]:+.2f}°, {det.elevation_deg[0]:+.2f}°)")
        assert det.azimuth_deg[0] == pytest.approx(az, abs=1.0)
        assert det.elevation_deg[0] == pytest.approx(el, abs=1.0)
        assert_allclose(det.xyz_radar_m[0], optical_point(det.range_m[0], az, el), atol=0.05)
        assert det.xyz_radar_m[0, 1] * np.sign(el) < 0  # up = -y


def test_capon_resolves_two_targets_20_degrees_apart_where_bartlett_does_not() -> None:
    # 4-Rx λ/2 ULA, complex IQ, 64 chirps; two equal targets at the same range (2.0 m)
    # at -10° and +10°, moving at -1.0 and +1.3 m/s so that their returns decorrelate
    # over the chirps. SNR: amplitude 1 and complex noise of variance 1 per ADC sample
    # (0 dB), i.e. 10 log10(256 * 0.375) = 19.8 dB per target, chirp and element after the
    # Hann range FFT.
    rc = ula_config(4, chirps=64)
    targets = [(optical_point(2.0, -10.0), optical_point(-1.0, -10.0), 1.0),
               (optical_point(2.0, 10.0), optical_point(1.3, 10.0), 1.0)]
    cube = synth_cube(rc, targets, noise_std=1.0, seed=7)
    spec = range_fft(cube, window="hann")
    r_bin = int(round(2.0 / rc.range_resolution_m))
    cov = spatial_covariance(spec[:, :, r_bin])  # snapshots = chirps
    az = np.deg2rad(np.arange(-60.0, 60.01, 0.25))
    a = steering_vectors(virtual_array_positions_m(rc), wavelength_m=rc.wavelength_m,
                         azimuth_rad=az)
    bart = 10 * np.log10(bartlett_spectrum(cov, a))
    capon = 10 * np.log10(capon_spectrum(cov, a, diagonal_loading=1e-3))
    az_deg = np.rad2deg(az)
    b_peaks = az_deg[local_maxima(bart)]
    c_peaks = az_deg[local_maxima(capon)]
    assert len(b_peaks[np.abs(b_peaks) < 30]) == 1  # one merged lobe near 0°
    c_main = np.sort(c_peaks[np.argsort(capon[local_maxima(capon)])[-2:]])
    assert_allclose(c_main, [-10.0, 10.0], atol=2.0)
    dip = min(np.interp(c_main, az_deg, capon)) - np.interp(0.0, az_deg, capon)
    print(f"Bartlett peaks {b_peaks[np.abs(b_peaks) < 30]}°, Capon peaks {c_main}°, "
          f"Capon dip at 0° {dip:.1f} dB")
    assert dip > 3.0


def test_tdm_mimo_virtual_array_needs_doppler_phase_compensation() -> None:
    # 2 Tx (4·λ/2 apart) × 4 Rx (λ/2 ULA) = 8-element λ/2 virtual ULA; a target moving at
    # 1.5 m/s picks up 4π v T_r / λ ≈ 1.19 rad between the Tx slots.
    rc = ula_config(4, n_tx=2, chirps=16)
    layout = array_layout(virtual_array_positions_m(rc))
    assert layout.row_channels.size == 8 and layout.row_spacing_m == pytest.approx(
        0.5 * rc.wavelength_m)
    az_true, v_true = 20.0, 1.5
    cube = synth_cube(rc, [(optical_point(2.0, az_true), optical_point(v_true, az_true), 1.0)],
                      noise_std=0.1, seed=5)
    errors = {}
    for compensate in (True, False):
        for method in ("fft", "bartlett"):
            dc = DspConfig(angle_method=method, tdm_doppler_compensation=compensate)
            det = process_frame(cube, rc, dc).detections
            assert len(det) == 1
            assert det.velocity_mps[0] == pytest.approx(v_true, abs=rc.velocity_resolution_mps)
            errors[(compensate, method)] = abs(det.azimuth_deg[0] - az_true)
    print("TDM azimuth errors (deg):", {k: round(float(v), 2) for k, v in errors.items()})
    assert errors[(True, "fft")] < 0.5 and errors[(True, "bartlett")] < 0.5
    assert errors[(False, "fft")] > 3.0 and errors[(False, "bartlett")] > 3.0


# --------------------------------------------------------------------------------------
# End to end (analytic cube of resources/examples/point_targets.json)
# --------------------------------------------------------------------------------------


def _point_targets_scene() -> tuple[RadarConfig, list[tuple[np.ndarray, np.ndarray, float]],
                                    np.ndarray, list[tuple[float, float, float]]]:
    """Radar config, targets (optical frame), radar→world transform, truth (R, az, v)."""
    project = json.loads((ROOT / "resources/examples/point_targets.json").read_text())
    radar = project["rig"]["radar"]
    rc = RadarConfig(**{k: radar[k] for k in (
        "start_frequency_hz", "bandwidth_hz", "chirp_time_s", "sample_rate_hz",
        "samples_per_chirp", "chirps_per_frame", "chirp_repetition_time_s", "complex_iq")},
        tx=[Antenna(**a) for a in radar["tx"]], rx=[Antenna(**a) for a in radar["rx"]])
    # Rig at its position with no rotation; radar offset on the rig (body: x fwd, y left,
    # z up); optical frame: x right = -y_body, y down = -z_body, z fwd = x_body.
    rig = np.asarray(project["rig"]["pose"]["position_m"])
    radar_origin = rig + np.asarray(radar["pose_on_rig"]["position_m"])
    body_from_opt = np.array([[0.0, 0.0, 1.0], [-1.0, 0.0, 0.0], [0.0, -1.0, 0.0]])
    to_world = np.eye(4)
    to_world[:3, :3] = body_from_opt
    to_world[:3, 3] = radar_origin
    targets, truth = [], []
    for obj in project["objects"]:
        pos_w = np.asarray(obj["pose"]["position_m"])
        vel_w = np.asarray(obj["motion"]["velocity_mps"])
        pos = body_from_opt.T @ (pos_w - radar_origin)
        vel = body_from_opt.T @ vel_w
        r = float(np.linalg.norm(pos))
        amp = (1.5 / r) ** 2  # radar equation: amplitude ∝ 1/R²
        targets.append((pos, vel, amp))
        truth.append((r, float(np.rad2deg(np.arctan2(pos[0], pos[2]))),
                      float(vel @ pos / r)))
    return rc, targets, to_world, truth


@pytest.mark.parametrize("noise_std", [0.3, 1e-4])
def test_end_to_end_three_point_targets(noise_std: float) -> None:
    rc, targets, to_world, truth = _point_targets_scene()
    assert_allclose([t[0] for t in truth], [1.5, 3.0, 4.5], atol=1e-5)
    assert_allclose([t[1] for t in truth], [-20.0, 0.0, 25.0], atol=1e-3)
    assert_allclose([t[2] for t in truth], [0.0, 1.0, 0.0], atol=1e-9)
    cube = synth_cube(rc, targets, noise_std=noise_std, seed=11)
    prod = process_frame(cube, rc, DspConfig(), radar_to_world=to_world)
    det = prod.detections
    assert len(det) == 3
    order = np.argsort(det.range_m)
    v_bin = prod.axes.velocity_mps[1] - prod.axes.velocity_mps[0]
    for i, (r, az, v) in zip(order, truth, strict=True):
        print(f"noise {noise_std:g}: range {det.range_m[i] - r:+.4f} m, azimuth "
              f"{det.azimuth_deg[i] - az:+.2f}°, velocity {det.velocity_mps[i] - v:+.3f} m/s "
              f"(bin {v_bin:.3f}), elevation {det.elevation_deg[i]:+.2f}°, "
              f"SNR {det.snr_db[i]:.1f} dB")
        assert abs(det.range_m[i] - r) < 0.02
        assert abs(det.azimuth_deg[i] - az) < 3.0
        assert abs(det.velocity_mps[i] - v) < v_bin
        assert abs(det.elevation_deg[i]) < 3.0
    # World coordinates: the targets' project positions (within the angle/range errors).
    project = json.loads((ROOT / "resources/examples/point_targets.json").read_text())
    world_truth = np.array([o["pose"]["position_m"] for o in project["objects"]])
    assert det.xyz_world_m is not None
    assert_allclose(det.xyz_world_m[order], world_truth, atol=0.15)
    rec = prod.detection_records(7)
    assert rec.dtype == DETECTION_DTYPE and len(rec) == 3
    assert_array_equal(rec["frame"], 7)
    assert_allclose(rec["x"], det.xyz_radar_m[:, 0], rtol=1e-6)


# --------------------------------------------------------------------------------------
# Products, axes, HDF5 items
# --------------------------------------------------------------------------------------


def test_products_shapes_axes_and_hdf5_items() -> None:
    rc = RadarConfig()
    dc = DspConfig(max_range_m=5.0)
    cube = synth_cube(rc, [(optical_point(2.0, 15.0), np.zeros(3), 1.0)], noise_std=0.1)
    prod = process_frame(cube, rc, dc)
    ax = radar_axes(rc, dc)
    n_r, n_d, n_az = ax.range_m.size, ax.velocity_mps.size, ax.azimuth_deg.size
    assert ax.range_m[-1] <= 5.0 and n_r == 201
    assert n_d == 32 and n_az == 161
    items = prod.hdf5_items(group="radar")
    assert items["/radar/range_doppler"][0].shape == (n_d, n_r)
    assert items["/radar/range_azimuth"][0].shape == (n_az, n_r)
    assert items["/radar/range_profile"][0].shape == (3, n_r)
    assert items["/radar/range_profile_integrated"][0].shape == (n_r,)
    assert items["/radar/bird_eye"][0].shape == (ax.bev_z_m.size, ax.bev_x_m.size)
    for arr, unit in items.values():
        assert arr.dtype == np.float32 and unit == "dB"
    static = static_axes_items(rc, dc, group="radar")
    assert_array_equal(static["/radar/range_axis"][0], prod.axes.range_m)
    assert_array_equal(static["/radar/velocity_axis"][0], prod.axes.velocity_mps)
    assert_array_equal(static["/radar/azimuth_axis"][0], prod.axes.azimuth_deg)
    assert [static[k][1] for k in ("/radar/range_axis", "/radar/velocity_axis",
                                   "/radar/azimuth_axis")] == ["m", "m/s", "deg"]
    # The target shows up where it is in the range–azimuth map and the bird's-eye image.
    ra = prod.range_azimuth_db
    i_az, i_r = np.unravel_index(np.argmax(ra), ra.shape)
    assert abs(ax.azimuth_deg[i_az] - 15.0) <= 2.0 and abs(ax.range_m[i_r] - 2.0) < 0.03
    assert ra.max() == pytest.approx(0.0, abs=1.5)  # unit amplitude reads ≈ 0 dB
    bev = prod.bird_eye_db
    i_z, i_x = np.unravel_index(np.nanargmax(bev), bev.shape)
    assert abs(ax.bev_x_m[i_x] - 2.0 * np.sin(np.deg2rad(15))) < 0.1
    assert abs(ax.bev_z_m[i_z] - 2.0 * np.cos(np.deg2rad(15))) < 0.1
    assert np.isnan(bev[0, 0])  # outside the azimuth coverage
    empty = prod.detections.records(0)[:0]
    assert empty.dtype.names == ("frame", "range", "velocity", "azimuth_deg", "elevation_deg",
                                 "x", "y", "z", "snr_db", "object_id", "power_fraction",
                                 "ghost", "body_part")


def test_static_clutter_removal_keeps_only_movers() -> None:
    rc = RadarConfig()
    targets = [(optical_point(1.5, 0.0), np.zeros(3), 1.0),
               (optical_point(3.0, 10.0), optical_point(-0.9, 10.0), 0.3)]
    cube = synth_cube(rc, targets, noise_std=0.05)
    assert len(process_frame(cube, rc, DspConfig()).detections) == 2
    det = process_frame(cube, rc, DspConfig(static_clutter_removal=True)).detections
    assert len(det) == 1
    assert det.range_m[0] == pytest.approx(3.0, abs=0.02)
    assert det.velocity_mps[0] == pytest.approx(-0.9, abs=0.1)


def test_cube_shape_is_checked_and_config_validated() -> None:
    rc = RadarConfig()
    with pytest.raises(ValueError, match="expected"):
        process_frame(np.zeros((16, 2, 512), np.float32), rc)
    with pytest.raises(ValueError, match="azimuth_max_deg"):
        DspConfig(azimuth_min_deg=10, azimuth_max_deg=-10)
    with pytest.raises(ValueError):
        DspConfig(cfar_method="xx")  # type: ignore[arg-type]
    with pytest.raises(ValueError):
        DspConfig(unknown_option=1)  # type: ignore[call-arg]


def test_false_alarm_rate_through_the_whole_chain() -> None:
    # Real-IF noise frames at the preset: windowed, zero-padded (correlated) cells averaged
    # over 3 channels; the 2-D OS-CFAR rate stays within a factor 2 of the request.
    rc = RadarConfig()
    rng = np.random.default_rng(21)
    dc = DspConfig(cfar_pfa=1e-3)
    hits = cells = 0
    for _ in range(60):
        cube = rng.standard_normal((16, 3, 512)).astype(np.float32)
        res = process_frame(cube, rc, dc).cfar
        hits += int(res.detections.sum())
        cells += res.detections.size
    rate = hits / cells
    print(f"chain false-alarm rate {rate:.2e} over {cells} cells (requested 1e-3)")
    assert cells > 400_000
    assert 0.5e-3 <= rate <= 2e-3
