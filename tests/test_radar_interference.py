"""Radar–radar interference over the direct path against its closed-form answers.

Two BGT60TR13C-like radars face each other 3 m apart (victim at the origin looking +z,
aggressor on its boresight looking back). Known answers, computed here from the chirps'
parameters and the geometry, not by the module: the burst's centre where the two
instantaneous frequencies cross, its duration ``2 f_AAF / |ΔK|``, its level from the
one-way Friis link, and the ghost range of an equal-slope aggressor.
"""

from __future__ import annotations

import numpy as np
import pytest

from simcore.scene.radar_config import SPEED_OF_LIGHT, RadarConfig
from simcore.scene.radar_presets import bgt60tr13c
from simcore.sensors.radar.interference import AggressorTiming, interference_if

DIST_M = 3.0
QUIET = {"noise_variance_adc": 0.0, "leakage_dbc": None, "adc_bits": None,
         "chirps_per_frame": 2}


def poses() -> tuple[np.ndarray, np.ndarray]:
    victim = np.eye(4)
    aggressor = np.diag([-1.0, 1.0, -1.0, 1.0])  # turned 180° about y: looks along −z
    aggressor[2, 3] = DIST_M
    return victim, aggressor


def one_way_delay_s(victim: RadarConfig, aggressor: RadarConfig) -> float:
    """Aggressor Tx1 → victim Rx1 (board positions; the aggressor's x is mirrored)."""
    rx = np.array([*victim.rx[0].position_mm, 0.0]) * 1e-3
    tx = np.array([-aggressor.tx[0].position_mm[0], aggressor.tx[0].position_mm[1], 0]) * 1e-3
    return float(np.linalg.norm(tx + [0, 0, DIST_M] - rx)) / SPEED_OF_LIGHT


def friis_amplitude_fs(victim: RadarConfig, aggressor: RadarConfig, d: float) -> float:
    """Boresight to boresight: P_r = P_t G_t G_r (λ/4πd)², V = √(2·50 Ω·P_r)·G_IF / V_fs."""
    p_r = (1e-3 * 10 ** (aggressor.tx_power_dbm / 10)
           * 10 ** ((aggressor.tx_gain_dbi + victim.rx_gain_dbi) / 10)
           * (aggressor.wavelength_m / (4 * np.pi * d)) ** 2)
    return float(np.sqrt(100.0 * p_r) * 10 ** (victim.if_gain_db / 20) / victim.adc_full_scale_v)


def test_different_slopes_give_a_burst_at_the_crossing_with_the_friis_level() -> None:
    victim = bgt60tr13c(**QUIET, if_highpass_hz=0.0)
    d_slope = 1e11  # Hz/s: a slow crossing, so the burst spans many samples
    k_a = victim.slope_hz_per_s - d_slope
    aggressor = bgt60tr13c(**QUIET, start_frequency_hz=60e9 + d_slope * 128e-6 + k_a * 2e-6,
                           bandwidth_hz=k_a * 256e-6)
    pv, pa = poses()
    x = interference_if(victim, pv, aggressor, pa, timing=AggressorTiming(2e-6))
    assert x.shape == (2, 3, 512)
    tau = one_way_delay_s(victim, aggressor)
    # f_v0 + K_v t = f_a0 + K_a (t − s − τ)  →  t× = (f_a0 − f_v0 − K_a (s + τ)) / ΔK
    t_cross = (aggressor.start_frequency_hz - victim.start_frequency_hz
               - k_a * (2e-6 + tau)) / d_slope
    duration = 2 * victim.if_lowpass_hz / d_slope
    env = np.abs(x[0, 0])
    t = np.arange(env.size) / victim.sample_rate_hz
    friis = friis_amplitude_fs(victim, aggressor, tau * SPEED_OF_LIGHT)
    inside = np.flatnonzero(env > friis / np.sqrt(2))  # Butterworth: −3 dB at f_AAF
    centre = 0.5 * (t[inside[0]] + t[inside[-1]])
    width = (inside[-1] - inside[0] + 1) / victim.sample_rate_hz
    # The low-pass delays the burst by its group delay at DC, Σ −Re(p_k) / (2π f_AAF)
    # over the Butterworth poles p_k on the unit circle (0.83 µs for order 4 at 500 kHz).
    n = victim.if_lowpass_order
    poles = np.exp(1j * np.pi * (2 * np.arange(1, n + 1) + n - 1) / (2 * n))
    t_cross += float(np.sum(-poles.real)) / (2 * np.pi * victim.if_lowpass_hz)
    level_db = 20 * np.log10(env.max() / friis)
    print(f"burst centre {centre * 1e6:.2f} µs (formula + group delay {t_cross * 1e6:.2f}), width "
          f"{width * 1e6:.2f} µs (formula {duration * 1e6:.2f}), level {level_db:+.2f} dB")
    assert abs(centre - t_cross) < 1.0 / victim.sample_rate_hz
    assert abs(width - duration) < 0.05 * duration + 1.0 / victim.sample_rate_hz
    assert abs(level_db) < 1.0
    # Outside the burst the IF is quiet: 40 dB down 3 burst lengths away (once the
    # aggressor's switch-on at s + τ, a step of a 12.6 MHz beat, has rung out).
    far = (np.abs(t - t_cross) > 3 * duration) & (t > 2e-6 + tau + 3e-6)
    assert env[far].max() < 0.01 * env.max()


@pytest.mark.parametrize("offset_s", [0.0, 5e-9])
def test_equal_slopes_give_a_ghost_at_the_lag_range(offset_s: float) -> None:
    victim = bgt60tr13c(**QUIET)
    aggressor = bgt60tr13c(**QUIET)
    pv, pa = poses()
    x = interference_if(victim, pv, aggressor, pa, timing=AggressorTiming(offset_s)).real
    ghost = SPEED_OF_LIGHT * (offset_s + one_way_delay_s(victim, aggressor)) / 2
    pad = 16
    w = np.hanning(x.shape[-1])
    spec = np.abs(np.fft.rfft(x[0, 0] * w, pad * x.shape[-1]))
    bin_m = SPEED_OF_LIGHT * victim.sample_rate_hz / (2 * victim.slope_hz_per_s * pad * 512)
    est = np.argmax(spec) * bin_m
    print(f"ghost at {est:.4f} m, formula {ghost:.4f} m")
    assert abs(est - ghost) < 0.25 * victim.range_resolution_m


def test_chirps_that_never_overlap_in_time_do_not_interfere() -> None:
    victim = bgt60tr13c(**QUIET)
    aggressor = bgt60tr13c(**QUIET)
    pv, pa = poses()
    x = interference_if(victim, pv, aggressor, pa, timing=AggressorTiming(10e-3))
    assert not np.any(x)
