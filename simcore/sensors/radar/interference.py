"""Radar–radar interference over the direct path: the aggressor's chirps in the victim's IF.

Pure functions (no scene, no rig): a victim radar and an aggressor radar, each with its
configuration and the pose of its optical frame in the world, and the aggressor's timing
relative to the victim. The aggressor's transmitted chirp reaches each victim Rx over the
line of sight after the one-way delay ``τ = d / c``; the victim's mixer multiplies it by
its own chirp, and the difference signal passes the victim's IF filters (high-pass,
anti-aliasing low-pass: :func:`simcore.sensors.radar.equation.if_filter_response`)
before the ADC samples it. Add the result to the victim's noise-free IF cube before
:func:`simcore.sensors.radar.receiver.receiver_chain` (noise, quantization).

Physics (``docs/interference.md``)
    Instantaneous frequencies ``f_v(t) = f_v0 + K_v (t − t_k)`` (victim chirp ``k``
    started at ``t_k``) and ``f_a(t) = f_a0 + K_a (t − s_m − τ)`` (aggressor chirp ``m``
    sent at ``s_m``). The IF is ``A exp(j(φ_v(t) − φ_a(t)))`` while both chirps are on.

    * Different slopes: the difference frequency sweeps at ``K_v − K_a`` through zero at
      ``t× = t_k + (f_a0 − f_v0 − K_a (s_m + τ − t_k)) / (K_v − K_a)`` and lies inside the
      passband ``|f| < f_AAF`` (real IF) for ``2 f_AAF / |K_v − K_a|``: a short chirped
      burst (never shorter than the filter's response, about ``1 / f_AAF``).
    * Equal slopes: a constant beat ``K (s_m + τ − t_k) + f_v0 − f_a0``, i.e. a ghost
      target at range ``c (s_m + τ − t_k + (f_v0 − f_a0) / K) / 2``.

    Level: one-way Friis, ``P_r = P_t G_t g_t G_r g_r (λ / (4π d))²`` with both element
    patterns towards each other, turned into the IF amplitude like the radar equation
    (``√(2 R_ref P_r) · 10^(G_IF/20) / V_fs``). Polarisation: the two radars are assumed
    co-polarised (identical boards, same orientation about the line of sight), the
    worst case; a rotated aggressor would add ``cos² ψ`` of the rotation ``ψ``, which is
    not modelled (polarisation-independent as documented).

Without an anti-aliasing filter (``if_lowpass_hz = 0``) the interference is simulated on
a grid ``oversample`` times the ADC rate and sampled, so components above the ADC's
Nyquist frequency fold back as they would on the real chip; components beyond the grid's
own band are dropped (gated where ``|f_v − f_a|`` exceeds 45 % of the grid's rate).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from simcore.scene.radar_config import SPEED_OF_LIGHT, RadarConfig
from simcore.sensors.radar.equation import R_REF_OHM, element_gain, if_filter_response

GATE_FRACTION = 0.45  # of the simulation grid's rate: beyond it the signal is dropped


@dataclass(frozen=True)
class AggressorTiming:
    """When the aggressor's chirps start, relative to the victim's first chirp.

    Attributes
    ----------
    start_offset_s : float
        Start of the aggressor's first chirp minus the start of the victim's first chirp
        (s): frame offset plus chirp start offset.
    chirp_jitter_s : tuple of float
        Extra start delay of each aggressor chirp (s); empty: none (see transmit-side
        jitter mitigation).
    """

    start_offset_s: float = 0.0
    chirp_jitter_s: tuple[float, ...] = ()


def friis_if_amplitude_fs(victim: RadarConfig, aggressor: RadarConfig, *, distance_m: float,
                          gain_tx: float = 1.0, gain_rx: float = 1.0) -> float:
    """Peak IF amplitude at the victim's ADC of the aggressor's direct signal (FS).

    One-way Friis ``P_r = P_t G_t g_t G_r g_r (λ / (4π d))²`` with ``P_t``, ``G_t`` the
    aggressor's ``tx_power_dbm``, ``tx_gain_dbi``, ``G_r`` the victim's ``rx_gain_dbi``,
    λ the aggressor's centre wavelength; ``√(2 R_ref P_r) · 10^(G_IF/20) / V_fs`` with the
    victim's IF gain and full scale. Filters not included.

    Parameters
    ----------
    victim, aggressor : RadarConfig
        The two radars.
    distance_m : float, keyword-only
        Aggressor Tx to victim Rx (m).
    gain_tx, gain_rx : float, keyword-only
        Element power patterns relative to boresight towards each other.

    Returns
    -------
    float
    """
    p_t = 1e-3 * 10.0 ** (aggressor.tx_power_dbm / 10.0)
    g = 10.0 ** ((aggressor.tx_gain_dbi + victim.rx_gain_dbi) / 10.0) * gain_tx * gain_rx
    p_r = p_t * g * (aggressor.wavelength_m / (4.0 * np.pi * distance_m)) ** 2
    volts = np.sqrt(2.0 * R_REF_OHM * p_r) * 10.0 ** (victim.if_gain_db / 20.0)
    return float(volts / victim.adc_full_scale_v)


def _world(pose: NDArray[np.float64], points: NDArray[np.float64]) -> NDArray[np.float64]:
    return points @ pose[:3, :3].T + pose[:3, 3]


def _filtered(x: NDArray[np.complex128], rate_hz: float, victim: RadarConfig
              ) -> NDArray[np.complex128]:
    """The victim's IF filters applied to rows of a complex signal (zero-padded FFT)."""
    n = x.shape[-1]
    n_fft = 1 << int(np.ceil(np.log2(2 * n)))
    f = np.fft.fftfreq(n_fft, 1.0 / rate_hz)
    h = if_filter_response(f, victim)
    return np.fft.ifft(np.fft.fft(x, n_fft, axis=-1) * h, axis=-1)[..., :n]


def interference_if(
    victim: RadarConfig,
    victim_pose: ArrayLike,
    aggressor: RadarConfig,
    aggressor_pose: ArrayLike,
    *,
    timing: AggressorTiming | None = None,
    oversample: int = 16,
) -> NDArray[np.complex128]:
    """The aggressor's direct signal in the victim's ADC cube, after the IF filters (FS).

    Parameters
    ----------
    victim, aggressor : RadarConfig
        The two radars (waveforms, antennas, powers, gains, patterns, receiver).
    victim_pose, aggressor_pose : array_like, shape (4, 4)
        Each radar's optical frame (x right, y down, z boresight) → world.
    timing : AggressorTiming, keyword-only, optional
        Aggressor chirp start times relative to the victim's first chirp.
    oversample : int, keyword-only
        Simulation grid rate over the victim's ADC rate.

    Returns
    -------
    ndarray, shape (victim chirps, victim tx*rx, victim samples), complex128
        Complex IF in FS, noise-free; the real part is the real-IF signal. The same on
        every victim Tx slot of a chirp (the victim's own Tx does not matter).
    """
    timing = AggressorTiming() if timing is None else timing
    pv, pa = np.asarray(victim_pose, np.float64), np.asarray(aggressor_pose, np.float64)
    rx_w = _world(pv, victim.rx_positions_m())
    tx_w = _world(pa, aggressor.tx_positions_m())
    n_v_tx, n_rx = len(victim.tx), len(victim.rx)
    n_a_tx = len(aggressor.tx)
    rate = victim.sample_rate_hz * oversample
    t_n = np.arange(victim.samples_per_chirp * oversample) / rate  # since the chirp start
    k_v, k_a = victim.slope_hz_per_s, aggressor.slope_hz_per_s
    f_v0, f_a0 = victim.start_frequency_hz, aggressor.start_frequency_hz
    jitter = np.zeros(aggressor.chirps_per_frame)
    jitter[:len(timing.chirp_jitter_s)] = timing.chirp_jitter_s[:aggressor.chirps_per_frame]
    starts = (timing.start_offset_s + np.arange(aggressor.chirps_per_frame)
              * aggressor.chirp_repetition_time_s + jitter)
    out = np.zeros((victim.chirps_per_frame, n_v_tx * n_rx, t_n.size), dtype=np.complex128)
    for r in range(n_rx):
        for j in range(n_a_tx):
            d_vec = rx_w[r] - tx_w[j]
            dist = float(np.linalg.norm(d_vec))
            g_t = element_gain(aggressor.element_pattern, (d_vec @ pa[:3, :3])[None, :])[0]
            g_r = element_gain(victim.element_pattern, (-d_vec @ pv[:3, :3])[None, :])[0]
            amp = friis_if_amplitude_fs(victim, aggressor, distance_m=dist,
                                        gain_tx=float(g_t), gain_rx=float(g_r))
            tau = dist / SPEED_OF_LIGHT
            for m in range(j, aggressor.chirps_per_frame, n_a_tx):
                for k in range(victim.chirps_per_frame):
                    t_k = k * victim.chirp_repetition_time_s
                    ta = t_n + t_k - starts[m] - tau  # time since the aggressor chirp began
                    on = (ta >= 0) & (ta <= aggressor.chirp_time_s)
                    if not on.any():
                        continue
                    f_diff = f_v0 + k_v * t_n - (f_a0 + k_a * ta)
                    on &= np.abs(f_diff) < GATE_FRACTION * rate
                    phase = 2 * np.pi * ((f_v0 * t_n + 0.5 * k_v * t_n**2)
                                         - (f_a0 * ta + 0.5 * k_a * ta**2))
                    sig = np.where(on, amp * np.exp(1j * phase), 0.0)
                    out[k, r::n_rx][:] += sig[None, :]
    filtered = _filtered(out, rate, victim)
    return np.ascontiguousarray(filtered[..., ::oversample])


def burst_centre_s(victim: RadarConfig, aggressor: RadarConfig, *, chirp_start_s: float,
                   aggressor_start_s: float, delay_s: float) -> float:
    """Time the two instantaneous frequencies cross, since the victim chirp's start (s).

    ``(f_a0 − f_v0 − K_a (s + τ − t_k)) / (K_v − K_a)`` for a victim chirp starting at
    ``t_k = chirp_start_s`` and an aggressor chirp sent at ``s = aggressor_start_s``,
    received ``τ = delay_s`` later. Different slopes only.
    """
    k_v, k_a = victim.slope_hz_per_s, aggressor.slope_hz_per_s
    if k_v == k_a:
        raise ValueError("equal slopes never cross: the interference is a ghost tone")
    lag = aggressor_start_s + delay_s - chirp_start_s
    return float((aggressor.start_frequency_hz - victim.start_frequency_hz - k_a * lag)
                 / (k_v - k_a))


def burst_duration_s(victim: RadarConfig, aggressor: RadarConfig) -> float:
    """Time the difference frequency spends inside the victim's passband (s).

    ``2 f_AAF / |K_v − K_a|``: the beat sweeps from ``−f_AAF`` to ``+f_AAF`` (both signs
    pass, for a real IF and for IQ); ``f_AAF`` is the anti-aliasing cutoff, or the ADC's
    Nyquist frequency ``f_s / 2`` when there is none. The filters' response time (about
    ``1 / f_AAF``) sets a lower bound this formula does not include.
    """
    f_aaf = victim.if_lowpass_hz or 0.5 * victim.sample_rate_hz
    return float(2.0 * f_aaf / abs(victim.slope_hz_per_s - aggressor.slope_hz_per_s))


def ghost_range_m(victim: RadarConfig, aggressor: RadarConfig, *, lag_s: float) -> float:
    """Range of the ghost target an equal-slope aggressor makes (m).

    ``c (lag + (f_v0 − f_a0) / K) / 2`` with ``lag = s + τ − t_k`` the aggressor chirp's
    arrival after the victim chirp's start.
    """
    k = victim.slope_hz_per_s
    return float(SPEED_OF_LIGHT * (lag_s + (victim.start_frequency_hz
                                            - aggressor.start_frequency_hz) / k) / 2.0)


__all__ = [
    "AggressorTiming",
    "burst_centre_s",
    "burst_duration_s",
    "friis_if_amplitude_fs",
    "ghost_range_m",
    "interference_if",
]
