"""DSP stage time per frame at the preset configuration (512 samples × 16 chirps × 3 Rx).

The ADC cube is synthesised analytically (three point targets plus receiver noise), so the
benchmark needs neither the renderer nor the front-end model. Reports the median wall
time of ``process_frame`` and of its parts, and the same for the 2-Tx × 4-Rx TDM-MIMO
layout when ``--mimo`` is given.
"""

from __future__ import annotations

import argparse
import statistics
import time
from collections.abc import Callable

import numpy as np

from simcore.dsp import (
    DspConfig,
    array_layout,
    cfar_2d,
    doppler_fft,
    process_frame,
    radar_axes,
    range_azimuth_power,
    range_doppler_power,
    range_fft,
    virtual_array_positions_m,
)
from simcore.scene.radar_config import SPEED_OF_LIGHT, Antenna, RadarConfig


def point_target_cube(rc: RadarConfig, *, seed: int = 0) -> np.ndarray:
    """Three point targets (1.5/3.0/4.5 m, −20/0/+25°, middle one at +1 m/s) plus noise."""
    n_tx, n_rx = len(rc.tx), len(rc.rx)
    p_tx = np.array([[a.position_mm[0], a.position_mm[1], 0.0] for a in rc.tx]) * 1e-3
    p_rx = np.array([[a.position_mm[0], a.position_mm[1], 0.0] for a in rc.rx]) * 1e-3
    t_n = np.arange(rc.samples_per_chirp) / rc.sample_rate_hz
    k = np.arange(rc.chirps_per_frame)
    out = np.zeros((rc.chirps_per_frame, n_tx * n_rx, rc.samples_per_chirp),
                   dtype=complex if rc.complex_iq else float)
    for r, az_deg, v, amp in ((1.5, -20.0, 0.0, 1.0), (3.0, 0.0, 1.0, 0.25),
                              (4.5, 25.0, 0.0, 0.11)):
        u = np.array([np.sin(np.deg2rad(az_deg)), 0.0, np.cos(np.deg2rad(az_deg))])
        for j in range(n_tx):
            x = (r + v * (k * n_tx + j) * rc.chirp_repetition_time_s)[:, None] * u
            for i in range(n_rx):
                tau = (np.linalg.norm(x - p_tx[j], axis=1)
                       + np.linalg.norm(x - p_rx[i], axis=1))[:, None] / SPEED_OF_LIGHT
                ph = (2 * np.pi * rc.start_frequency_hz * tau
                      + 2 * np.pi * rc.slope_hz_per_s * tau * t_n - np.pi * rc.slope_hz_per_s
                      * tau**2)
                out[:, j * n_rx + i] += amp * (np.exp(1j * ph) if rc.complex_iq else np.cos(ph))
    rng = np.random.default_rng(seed)
    out = out + 0.3 * rng.standard_normal(out.shape)
    return out.astype(np.complex64 if rc.complex_iq else np.float32)


def median_ms(fn: Callable[[], object], repeats: int) -> float:
    fn()  # warm-up (threshold factors, FFT plans)
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        times.append((time.perf_counter() - t0) * 1e3)
    return statistics.median(times)


def bench(name: str, rc: RadarConfig, dc: DspConfig, repeats: int) -> None:
    cube = point_target_cube(rc)
    ax = radar_axes(rc, dc)
    rcube = range_fft(cube, fft_size=ax.range_fft_size)
    rd = doppler_fft(rcube, fft_size=ax.doppler_fft_size)
    power = range_doppler_power(rd)
    layout = array_layout(virtual_array_positions_m(rc))
    az = np.deg2rad(ax.azimuth_deg)
    total = median_ms(lambda: process_frame(cube, rc, dc), repeats)
    parts = {
        "range FFT": median_ms(lambda: range_fft(cube, fft_size=ax.range_fft_size), repeats),
        "Doppler FFT": median_ms(lambda: doppler_fft(rcube, fft_size=ax.doppler_fft_size),
                                 repeats),
        f"range-azimuth ({dc.angle_method})": median_ms(
            lambda: range_azimuth_power(rd, layout, wavelength_m=rc.wavelength_m,
                                        azimuth_rad=az, method=dc.angle_method), repeats),
        f"{dc.cfar_method.upper()}-CFAR 2-D": median_ms(
            lambda: cfar_2d(power, method=dc.cfar_method,
                            train=(dc.cfar_train_doppler, dc.cfar_train_range),
                            guard=(dc.cfar_guard_doppler, dc.cfar_guard_range),
                            pfa=dc.cfar_pfa, n_integrated=rd.shape[1]), repeats),
    }
    det = process_frame(cube, rc, dc).detections
    shape = "x".join(str(s) for s in cube.shape)
    print(f"{name}: cube {shape} ({cube.dtype}), maps {ax.velocity_mps.size} Doppler x "
          f"{ax.range_m.size} range x {ax.azimuth_deg.size} azimuth, {len(det)} detections")
    print(f"  process_frame  {total:7.1f} ms (median of {repeats})")
    for label, ms in parts.items():
        print(f"    {label:28s} {ms:7.1f} ms")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--repeats", type=int, default=30)
    parser.add_argument("--mimo", action="store_true", help="also the 2-Tx x 4-Rx TDM layout")
    args = parser.parse_args()
    bench("bgt60tr13c preset", RadarConfig(), DspConfig(), args.repeats)
    if args.mimo:
        half = 0.5 * RadarConfig().wavelength_m * 1e3
        rc = RadarConfig(
            complex_iq=True, chirps_per_frame=64, chirp_repetition_time_s=300e-6,
            tx=[Antenna(name="tx1"), Antenna(name="tx2", position_mm=(4 * half, 0.0))],
            rx=[Antenna(name=f"rx{i + 1}", position_mm=(i * half, 0.0)) for i in range(4)],
        )
        bench("2-Tx x 4-Rx TDM-MIMO, IQ, 64 chirps", rc, DspConfig(), args.repeats)


if __name__ == "__main__":
    main()
