"""Known-answer tests of the vital-sign estimator on raw FMCW cubes built with numpy.

A chest on the boresight at 1 m moves by ``A_b sin(2π f_b t) + A_h sin(2π f_h t + φ)``
(breathing and heartbeat); a strong static scatterer shares its range bin (clutter) and a
wall stands further away. The cubes come from :mod:`tests.fmcw_synth` (the FMCW model,
not the simulator); the estimator must find the configured rates and amplitudes.
"""

from __future__ import annotations

import numpy as np
import pytest
from numpy.testing import assert_allclose

from simcore.dsp import range_axis_m, range_fft
from simcore.dsp.vitals import (
    VitalSignsBuffer,
    estimate_vital_signs,
    frame_slow_time,
    kasa_circle_fit,
    phase_displacement_m,
    select_vital_bin,
    spectral_peak,
)
from simcore.scene.dsp_config import DspConfig
from simcore.scene.radar_config import Antenna, RadarConfig
from tests.fmcw_synth import synth_frames

FRAME_RATE_HZ = 20.0
DURATION_S = 40.0
CHEST_M = 1.0


def vitals_radar(*, complex_iq: bool) -> RadarConfig:
    """The preset's chirp (60–66 GHz in 256 µs), 128 samples, 2 chirps per frame, one Rx."""
    return RadarConfig(samples_per_chirp=128, sample_rate_hz=5e5, chirps_per_frame=2,
                       complex_iq=complex_iq, rx=[Antenna(name="rx1")])


def chest_cubes(rc: RadarConfig, *, breathing: tuple[float, float], heart: tuple[float, float],
                clutter: bool = True, noise_std: float = 0.03) -> np.ndarray:
    """Range spectra (frames, chirps, channels, range) of the chest scene.

    ``breathing`` and ``heart`` are (rate Hz, amplitude m).
    """
    (fb, ab), (fh, ah) = breathing, heart
    frames = np.arange(int(DURATION_S * FRAME_RATE_HZ)) / FRAME_RATE_HZ

    def chest(t: np.ndarray) -> np.ndarray:
        return (CHEST_M + ab * np.sin(2 * np.pi * fb * t)
                + ah * np.sin(2 * np.pi * fh * t + 0.7))

    scatterers = [(chest, 0.05)]
    if clutter:
        scatterers += [(lambda t: CHEST_M + 0.004 + 0 * t, 0.15),   # same bin, 3× stronger
                       (lambda t: 1.45 + 0 * t, 0.3)]               # a wall
    adc = synth_frames(rc, scatterers, frames, noise_std=noise_std, seed=3)
    return np.stack([range_fft(c) for c in adc])


def range_axis(rc: RadarConfig, n_bins: int) -> np.ndarray:
    return range_axis_m(n_bins=n_bins, fft_size=rc.samples_per_chirp,
                        sample_rate_hz=rc.sample_rate_hz, slope_hz_per_s=rc.slope_hz_per_s)


@pytest.mark.parametrize("complex_iq", [False, True])
def test_breathing_rate_and_amplitude_with_clutter(complex_iq: bool) -> None:
    rc = vitals_radar(complex_iq=complex_iq)
    rate, amp = 0.273, 4e-3
    cubes = chest_cubes(rc, breathing=(rate, amp), heart=(1.13, 0.2e-3))
    x = frame_slow_time(cubes)
    r = range_axis(rc, x.shape[1])
    k = select_vital_bin(x, range_axis_m=r, min_range_m=0.3, max_range_m=1.3)
    assert abs(r[k] - CHEST_M) <= 0.5 * (r[1] - r[0]) + 1e-9   # not the stronger wall
    vs = estimate_vital_signs(x[:, k], sample_rate_hz=FRAME_RATE_HZ,
                              wavelength_m=rc.wavelength_m, range_bin=k)
    print(f"IQ={complex_iq}: breathing {vs.breathing_rate_hz:.4f} Hz "
          f"{vs.breathing_amplitude_m * 1e3:.3f} mm, heart {vs.heart_rate_hz:.4f} Hz "
          f"{vs.heart_amplitude_m * 1e3:.3f} mm")
    assert abs(vs.breathing_rate_hz - rate) < 0.02
    assert abs(vs.breathing_amplitude_m - amp) < 0.2 * amp
    assert abs(vs.heart_rate_hz - 1.13) < 0.1                   # with breathing on, too
    # The displacement itself follows the chest (phase about the circle centre).
    t = np.arange(x.shape[0]) / FRAME_RATE_HZ
    truth = amp * np.sin(2 * np.pi * rate * t) + 0.2e-3 * np.sin(2 * np.pi * 1.13 * t + 0.7)
    assert np.std(vs.displacement_m - (truth - truth.mean())) < 0.1 * amp


@pytest.mark.parametrize("complex_iq", [False, True])
def test_heart_rate_and_amplitude_when_breathing_is_off(complex_iq: bool) -> None:
    rc = vitals_radar(complex_iq=complex_iq)
    rate, amp = 1.37, 0.3e-3
    cubes = chest_cubes(rc, breathing=(0.25, 0.0), heart=(rate, amp))
    x = frame_slow_time(cubes)
    r = range_axis(rc, x.shape[1])
    k = select_vital_bin(x, range_axis_m=r, min_range_m=0.3, max_range_m=1.3)
    vs = estimate_vital_signs(x[:, k], sample_rate_hz=FRAME_RATE_HZ,
                              wavelength_m=rc.wavelength_m)
    print(f"IQ={complex_iq}: heart {vs.heart_rate_hz:.4f} Hz "
          f"{vs.heart_amplitude_m * 1e3:.4f} mm")
    assert abs(vs.heart_rate_hz - rate) < 0.1
    assert abs(vs.heart_amplitude_m - amp) < 0.2 * amp
    # The clutter phasor under the short arc is what the circle fit removes: without it
    # the phase swing (hence the amplitude) is far off.
    raw = estimate_vital_signs(x[:, k], sample_rate_hz=FRAME_RATE_HZ,
                               wavelength_m=rc.wavelength_m, static_offset="none")
    assert abs(raw.heart_amplitude_m - amp) > 0.3 * amp


def test_streaming_buffer_keeps_the_last_window_and_estimates() -> None:
    rc = vitals_radar(complex_iq=False)
    cubes = chest_cubes(rc, breathing=(0.31, 3e-3), heart=(1.2, 0.0))
    n_keep = int(30 * FRAME_RATE_HZ)
    buf = VitalSignsBuffer(cubes.shape[-1], capacity=n_keep)
    for c in cubes:
        buf.push_frame(c)
    assert buf.count == n_keep
    assert_allclose(buf.slow_time(), frame_slow_time(cubes[-n_keep:]), rtol=1e-6)
    r = range_axis(rc, cubes.shape[-1])
    vs = buf.estimate(sample_rate_hz=FRAME_RATE_HZ, wavelength_m=rc.wavelength_m,
                      range_axis_m=r, min_range_m=0.3, max_range_m=1.3)
    assert abs(vs.breathing_rate_hz - 0.31) < 0.02
    assert abs(vs.breathing_amplitude_m - 3e-3) < 0.6e-3


def test_kasa_circle_fit_recovers_a_noisy_short_arc() -> None:
    rng = np.random.default_rng(0)
    theta = np.linspace(1.0, 1.8, 400)
    z = (2 - 1j) + 0.5 * np.exp(1j * theta)
    z += 1e-3 * (rng.standard_normal(z.size) + 1j * rng.standard_normal(z.size))
    c, rad = kasa_circle_fit(z)
    assert abs(c - (2 - 1j)) < 0.02
    assert abs(rad - 0.5) < 0.02


def test_displacement_is_lambda_over_4pi_times_phase_and_positive_away() -> None:
    lam = 5e-3
    d_true = np.linspace(0.0, 3e-3, 200)          # moving away by 3 mm
    z = 0.8 * np.exp(1j * 4 * np.pi * d_true / lam) + (0.3 + 0.2j)
    d = phase_displacement_m(z, wavelength_m=lam)
    assert_allclose(d, d_true - d_true.mean(), atol=1e-7)


def test_spectral_peak_interpolates_between_bins_and_reports_nan_outside_nyquist() -> None:
    fs = 10.0
    t = np.arange(300) / fs                        # 30 s: bins 0.033 Hz apart
    for f0 in (0.2, 0.2167, 0.2333, 0.45):
        f, a = spectral_peak(2e-3 * np.cos(2 * np.pi * f0 * t + 1.0), sample_rate_hz=fs,
                             band_hz=(0.1, 0.6))
        assert abs(f - f0) < 2e-3
        assert abs(a - 2e-3) < 0.02 * 2e-3
    f, a = spectral_peak(np.sin(t), sample_rate_hz=fs, band_hz=(6.0, 7.0))
    assert np.isnan(f) and np.isnan(a)


def test_config_defaults_and_validation() -> None:
    cfg = DspConfig()
    assert cfg.vitals_breathing_band_hz == (0.1, 0.6)
    assert cfg.vitals_heart_band_hz == (0.8, 2.5)
    with pytest.raises(ValueError, match="vitals_heart_band_hz"):
        DspConfig(vitals_heart_band_hz=(2.0, 1.0))
    with pytest.raises(ValueError, match="vitals_static_offset"):
        DspConfig(vitals_static_offset="median")  # type: ignore[arg-type]
