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
from simcore.sensors.radar.equation import (
    R_REF_OHM,
    element_gain,
    if_filter_response,
    noise_std_fs,
)
from simcore.sensors.radar.scatterers import Scatterers

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


@dataclass(frozen=True)
class PathSet:
    """Propagation paths from each aggressor Tx to each victim Rx.

    Attributes
    ----------
    amplitude_fs : ndarray, shape (aggressor tx, victim rx, P), complex128
        Peak IF amplitude at the victim's ADC of each path, before the IF filters (FS),
        with the path's scattering phase.
    delay_s : ndarray, shape (aggressor tx, victim rx, P), float64
        Propagation delay at the victim's frame start (s).
    delay_rate : ndarray, shape (aggressor tx, victim rx, P), float64
        Rate of change of the delay (s/s): the path's Doppler ``−f_c · delay_rate``.
    """

    amplitude_fs: NDArray[np.complex128]
    delay_s: NDArray[np.float64]
    delay_rate: NDArray[np.float64]

    @staticmethod
    def concatenate(sets: list[PathSet]) -> PathSet:
        """All paths of several sets (same antenna counts)."""
        return PathSet(*(np.concatenate([getattr(p, f) for p in sets], axis=-1)
                         for f in ("amplitude_fs", "delay_s", "delay_rate")))

    @property
    def n_paths(self) -> int:
        """Paths per (aggressor Tx, victim Rx)."""
        return int(self.delay_s.shape[-1])


def direct_paths(victim: RadarConfig, victim_pose: ArrayLike, aggressor: RadarConfig,
                 aggressor_pose: ArrayLike, *, victim_velocity_mps: ArrayLike = (0, 0, 0),
                 aggressor_velocity_mps: ArrayLike = (0, 0, 0)) -> PathSet:
    """The line of sight from every aggressor Tx to every victim Rx (one-way Friis).

    Both element patterns towards each other; the radars co-polarised (module docstring).
    Velocities: world velocities of the two radars (m/s), for the paths' Doppler.
    """
    pv, pa = np.asarray(victim_pose, np.float64), np.asarray(aggressor_pose, np.float64)
    rx_w = _world(pv, victim.rx_positions_m())
    tx_w = _world(pa, aggressor.tx_positions_m())
    dv = np.asarray(victim_velocity_mps, np.float64) - np.asarray(aggressor_velocity_mps,
                                                                   np.float64)
    n_a, n_r = len(tx_w), len(rx_w)
    amp = np.zeros((n_a, n_r, 1), np.complex128)
    delay = np.zeros((n_a, n_r, 1))
    rate = np.zeros((n_a, n_r, 1))
    for j in range(n_a):
        for r in range(n_r):
            d_vec = rx_w[r] - tx_w[j]
            dist = max(float(np.linalg.norm(d_vec)), 1e-3)
            g_t = element_gain(aggressor.element_pattern, (d_vec @ pa[:3, :3])[None, :])[0]
            g_r = element_gain(victim.element_pattern, (-d_vec @ pv[:3, :3])[None, :])[0]
            amp[j, r, 0] = friis_if_amplitude_fs(victim, aggressor, distance_m=dist,
                                                 gain_tx=float(g_t), gain_rx=float(g_r))
            delay[j, r, 0] = dist / SPEED_OF_LIGHT
            rate[j, r, 0] = float(d_vec @ dv) / dist / SPEED_OF_LIGHT
    return PathSet(amp, delay, rate)


#: Reflected paths kept per (aggressor Tx, victim Rx): the strongest, by amplitude.
MAX_REFLECTED_PATHS = 512


def reflected_paths(victim: RadarConfig, victim_pose: ArrayLike, aggressor: RadarConfig,
                    aggressor_pose: ArrayLike, scatterers: Scatterers, *,
                    victim_velocity_mps: ArrayLike = (0, 0, 0),
                    aggressor_velocity_mps: ArrayLike = (0, 0, 0),
                    max_paths: int = MAX_REFLECTED_PATHS) -> PathSet:
    """Bistatic paths aggressor Tx → scatterer → victim Rx over the victim's scatterers.

    Bistatic radar equation ``P_r = P_t G_t g_t σ G_r g_r λ² / ((4π)³ R_a² R_v²)`` with the
    aggressor's power and Tx pattern towards the scatterer and the victim's Rx pattern;
    ``σ`` and the scattering phase are those the victim sees (its render's facets and
    analytic targets: the monostatic–bistatic equivalence, exact for small bistatic
    angles). Not modelled: whether the aggressor itself sees the scatterer (occlusion on
    the aggressor's side), only its pattern limits it. The ``max_paths`` strongest paths
    per (Tx, Rx) are kept.

    Parameters
    ----------
    scatterers : Scatterers
        The victim's scatterers, in the victim's optical frame.
    """
    pv, pa = np.asarray(victim_pose, np.float64), np.asarray(aggressor_pose, np.float64)
    n_a, n_r = len(aggressor.tx), len(victim.rx)
    if len(scatterers) == 0:
        z = np.zeros((n_a, n_r, 0))
        return PathSet(z.astype(np.complex128), z, z)
    x_v = scatterers.positions_m                       # victim optical frame
    x_w = _world(pv, x_v)
    v_w = scatterers.velocities_mps @ pv[:3, :3].T + np.asarray(victim_velocity_mps)
    rx_w = _world(pv, victim.rx_positions_m())
    tx_w = _world(pa, aggressor.tx_positions_m())
    va = np.asarray(aggressor_velocity_mps, np.float64)
    vv = np.asarray(victim_velocity_mps, np.float64)
    p_t = 1e-3 * 10.0 ** (aggressor.tx_power_dbm / 10.0)
    g0 = 10.0 ** ((aggressor.tx_gain_dbi + victim.rx_gain_dbi) / 10.0)
    lam = aggressor.wavelength_m
    volts_per = 10.0 ** (victim.if_gain_db / 20.0) / victim.adc_full_scale_v
    keep = min(max_paths, len(scatterers))
    amp = np.zeros((n_a, n_r, keep), np.complex128)
    delay = np.zeros((n_a, n_r, keep))
    rate = np.zeros((n_a, n_r, keep))
    g_r = element_gain(victim.element_pattern, x_v)          # victim sees from its origin
    for j in range(n_a):
        to_p = x_w - tx_w[j]
        r_a = np.maximum(np.linalg.norm(to_p, axis=1), 1e-3)
        g_t = element_gain(aggressor.element_pattern, to_p @ pa[:3, :3])
        rate_a = np.einsum("ij,ij->i", to_p, v_w - va) / r_a
        for r in range(n_r):
            from_p = x_w - rx_w[r]
            r_v = np.maximum(np.linalg.norm(from_p, axis=1), 1e-3)
            p_r = (p_t * g0 * g_t * g_r * scatterers.rcs_m2 * lam**2
                   / ((4 * np.pi) ** 3 * r_a**2 * r_v**2))
            a = np.sqrt(2.0 * R_REF_OHM * p_r) * volts_per
            top = np.argsort(-a, kind="stable")[:keep]
            amp[j, r] = a[top] * np.exp(1j * scatterers.phase_rad[top])
            delay[j, r] = (r_a[top] + r_v[top]) / SPEED_OF_LIGHT
            rate_v = np.einsum("ij,ij->i", from_p[top], v_w[top] - vv) / r_v[top]
            rate[j, r] = (rate_a[top] + rate_v) / SPEED_OF_LIGHT
    return PathSet(amp, delay, rate)


#: Where the gate's raised-cosine taper starts, as a fraction of the grid's rate: the
#: difference frequency fades out between it and :data:`GATE_FRACTION` (a hard cut would
#: ring into the passband).
TAPER_FRACTION = 0.25
#: Attenuation of the anti-aliasing filter where the gate's taper starts (dB): what the
#: taper changes is at least this far down.
GATE_ATTENUATION_DB = 60.0


def _gate_taper(f_rel: NDArray[np.float64]) -> NDArray[np.float64]:
    """1 below :data:`TAPER_FRACTION` of the rate, raised cosine to 0 at the gate."""
    x = np.clip((f_rel - TAPER_FRACTION) / (GATE_FRACTION - TAPER_FRACTION), 0.0, 1.0)
    return np.asarray(0.5 * (1.0 + np.cos(np.pi * x)), dtype=np.float64)


def default_oversample(victim: RadarConfig) -> int:
    """The simulation grid's rate over the ADC rate (at least 2, at most 16).

    Without an anti-aliasing filter, 16 (components up to 3.6× the ADC's rate fold back
    as on the chip). With one of order ``n`` at ``f_AAF``, the smallest grid whose gate
    taper starts (:data:`TAPER_FRACTION` of its rate) where the filter is
    :data:`GATE_ATTENUATION_DB` down: ``(f_taper / f_AAF)^n`` ≥ 10^(60/20).
    """
    if victim.if_lowpass_hz <= 0:
        return 16
    ratio = 10.0 ** (GATE_ATTENUATION_DB / (20.0 * victim.if_lowpass_order))
    need = ratio * victim.if_lowpass_hz / (TAPER_FRACTION * victim.sample_rate_hz)
    return int(min(16, max(2, np.ceil(need))))


def mix_paths(victim: RadarConfig, aggressor: RadarConfig, paths: PathSet, *,
              aggressor_starts_s: ArrayLike, victim_starts_s: ArrayLike | None = None,
              oversample: int | None = None) -> NDArray[np.complex128]:
    """The aggressor's chirps over ``paths``, mixed with the victim's, after its IF filters.

    Parameters
    ----------
    victim, aggressor : RadarConfig
        The two radars as they transmit in this frame (start frequencies hopped:
        :func:`simcore.sensors.radar.transmit.frame_transmit_config`).
    paths : PathSet
        Aggressor Tx → victim Rx paths.
    aggressor_starts_s : array_like, shape (aggressor chirps, aggressor tx)
        Send time of every aggressor chirp (TDM order) relative to the victim's frame
        start (s).
    victim_starts_s : array_like, shape (victim chirps, victim tx), optional
        Start of every victim chirp from its frame start (s); default
        ``victim.chirp_start_times_s()`` (with the frame's jitter, if any).
    oversample : int, optional
        Simulation grid rate over the victim's ADC rate; default
        :func:`default_oversample`.

    Returns
    -------
    ndarray, shape (victim chirps, victim tx*rx, victim samples), complex128
        Complex IF in FS, noise-free; the real part is the real-IF signal.

    Notes
    -----
    Per path the delay is ``τ₀ + τ' t_k`` at the victim chirp's start ``t_k``: its
    Doppler phase is exact chirp to chirp, the range migration within the frame (a few
    picoseconds of delay) is left out. The gate of each pair of chirps is taken at the
    shortest delay of the pair's paths (the paths' delays differ by nanoseconds).
    """
    v_starts = (victim.chirp_start_times_s() if victim_starts_s is None
                else np.asarray(victim_starts_s, np.float64))
    a_starts = np.asarray(aggressor_starts_s, np.float64)
    n_v_tx, n_rx = len(victim.tx), len(victim.rx)
    if oversample is None:
        oversample = default_oversample(victim)
    grid = _mix_grid(victim, aggressor, oversample)
    out = np.zeros((victim.chirps_per_frame, n_v_tx * n_rx, grid.t_n.size),
                   dtype=np.complex128)
    if paths.n_paths == 0:
        return np.ascontiguousarray(out[..., ::oversample])
    for j in range(len(aggressor.tx)):
        for r in range(n_rx):
            amp, tau0, tau_dot = (paths.amplitude_fs[j, r], paths.delay_s[j, r],
                                  paths.delay_rate[j, r])
            live = np.abs(amp) > 0
            if not live.any():
                continue
            amp, tau0, tau_dot = amp[live], tau0[live], tau_dot[live]
            lo, hi = float(tau0.min()), float(tau0.max())
            pairs = _chirp_pairs(grid, v_starts, n_v_tx, a_starts[:, j], lo, hi)
            if not pairs:
                continue
            burst = _pair_bursts(grid, pairs, amp, tau0, tau_dot, lo)
            if burst is None:
                continue
            cols, sig = burst
            for q, (k, t, _, _) in enumerate(pairs):
                out[k, t * n_rx + r, cols] += sig[q]
    filtered = _filtered(out, grid.rate, victim)
    return np.ascontiguousarray(filtered[..., ::oversample])


@dataclass(frozen=True)
class _MixGrid:
    """The simulation grid of one victim chirp and the two radars' chirp parameters."""

    rate: float                     # grid rate (Hz)
    t_n: NDArray[np.float64]        # (N,) grid times from the victim chirp's start (s)
    own: NDArray[np.float64]        # (N,) the victim chirp's phase on the grid (rad)
    k_v: float                      # victim slope (Hz/s)
    k_a: float                      # aggressor slope (Hz/s)
    f_v0: float                     # victim start frequency (Hz)
    f_a0: float                     # aggressor start frequency (Hz)
    t_a: float                      # aggressor chirp duration (s)


def _mix_grid(victim: RadarConfig, aggressor: RadarConfig, oversample: int) -> _MixGrid:
    """The grid ``oversample`` times the victim's ADC rate, and the chirp parameters."""
    rate = victim.sample_rate_hz * oversample
    t_n = np.arange(victim.samples_per_chirp * oversample) / rate
    k_v, f_v0 = victim.slope_hz_per_s, victim.start_frequency_hz
    own = 2 * np.pi * (f_v0 * t_n + 0.5 * k_v * t_n**2)
    return _MixGrid(rate, t_n, own, k_v, aggressor.slope_hz_per_s, f_v0,
                    aggressor.start_frequency_hz, aggressor.chirp_time_s)


def _chirp_pairs(grid: _MixGrid, v_starts: NDArray[np.float64], n_v_tx: int,
                 a_starts: NDArray[np.float64], lo: float, hi: float
                 ) -> list[tuple[int, int, float, float]]:
    """(victim chirp, victim tx, its start, aggressor chirp start) of the overlapping pairs.

    Pairs whose chirps overlap for some path delay in ``[lo, hi]`` and whose beat enters
    the gate somewhere along the victim chirp.
    """
    k_v, k_a, f_v0, f_a0 = grid.k_v, grid.k_a, grid.f_v0, grid.f_a0
    span = grid.t_n[-1]
    pairs = []
    for k in range(v_starts.shape[0]):
        for t in range(n_v_tx):
            t_k = v_starts[k, t]
            for s in a_starts:
                if s + lo <= t_k + span and s + hi + grid.t_a >= t_k:
                    # The difference frequency is linear over the chirp: skip
                    # pairs whose beat stays beyond the gate all along.
                    f0 = f_v0 - f_a0 - k_a * (t_k - s - lo)
                    f1 = f0 + (k_v - k_a) * span
                    if f0 * f1 > 0 and min(abs(f0), abs(f1)) >= GATE_FRACTION * grid.rate:
                        continue
                    pairs.append((k, t, t_k, s))
    return pairs


def _pair_bursts(grid: _MixGrid, pairs: list[tuple[int, int, float, float]],
                 amp: NDArray[np.complex128], tau0: NDArray[np.float64],
                 tau_dot: NDArray[np.float64], lo: float
                 ) -> tuple[NDArray[np.intp], NDArray[np.complex128]] | None:
    """Grid columns inside any pair's gate and each pair's signal there, shape (Q, C).

    None when no pair's beat enters the gate.
    """
    k_v, k_a, f_v0, f_a0, t_n = grid.k_v, grid.k_a, grid.f_v0, grid.f_a0, grid.t_n
    t_k_arr = np.array([p[2] for p in pairs])
    s_arr = np.array([p[3] for p in pairs])
    lag = t_k_arr - s_arr                                 # (Q,)
    tau = tau0[None, :] + tau_dot[None, :] * t_k_arr[:, None]   # (Q, P)
    weights = amp[None, :] * np.exp(2j * np.pi * (
        tau * (f_a0 + k_a * lag[:, None]) - 0.5 * k_a * tau**2))
    # The gate first (real arithmetic), then the signal on the grid's columns
    # that any pair has inside it (the bursts: a small part of the chirp).
    u = t_n[None, :] + lag[:, None]             # since the aggressor chirp's send
    ta = u - lo
    on = (ta >= 0) & (ta <= grid.t_a)
    f_diff = f_v0 + k_v * t_n[None, :] - (f_a0 + k_a * ta)
    taper = _gate_taper(np.abs(f_diff) / grid.rate)
    on &= taper > 0
    cols = np.flatnonzero(on.any(axis=0))
    if cols.size == 0:
        return None
    t_c = t_n[cols]
    tones = np.exp(2j * np.pi * k_a * tau0[:, None] * t_c[None, :])   # (P, C)
    summed = weights @ tones                                          # (Q, C)
    u_c = u[:, cols]
    phase = grid.own[None, cols] - 2 * np.pi * (f_a0 * u_c + 0.5 * k_a * u_c**2)
    sig = np.where(on[:, cols], taper[:, cols] * summed * np.exp(1j * phase), 0.0)
    return cols, sig


def interference_if(
    victim: RadarConfig,
    victim_pose: ArrayLike,
    aggressor: RadarConfig,
    aggressor_pose: ArrayLike,
    *,
    timing: AggressorTiming | None = None,
    oversample: int | None = None,
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
        Complex IF in FS, noise-free; the real part is the real-IF signal.
    """
    timing = AggressorTiming() if timing is None else timing
    starts = aggressor.chirp_start_times_s() + timing.start_offset_s
    flat = starts.reshape(-1)
    n = min(len(timing.chirp_jitter_s), flat.size)
    flat[:n] += np.asarray(timing.chirp_jitter_s[:n])
    paths = direct_paths(victim, victim_pose, aggressor, aggressor_pose)
    return mix_paths(victim, aggressor, paths, aggressor_starts_s=flat.reshape(starts.shape),
                     oversample=oversample)


#: ``inr_db`` of a frame whose interference did not reach the passband (dB): finite, so
#: datasets stay finite.
INR_NONE_DB = -300.0
#: ``inr_db`` of a noise-free receiver (``noise_variance_adc = 0``) with interference (dB).
INR_NOISE_FREE_DB = 300.0


def interference_to_noise_db(interference: NDArray[np.complex128], victim: RadarConfig
                             ) -> float:
    """Interference-to-noise ratio of a frame (dB).

    Mean interference power over the cube (the real part for a real IF, I and Q for IQ)
    over the receiver noise variance per real channel
    (:func:`simcore.sensors.radar.equation.noise_std_fs`), within
    [:data:`INR_NONE_DB`, :data:`INR_NOISE_FREE_DB`]: the floor without interference, the
    ceiling for a noise-free receiver with interference.
    """
    x = interference if victim.complex_iq else interference.real
    power = float(np.mean(np.abs(x) ** 2) / (2.0 if victim.complex_iq else 1.0))
    noise = noise_std_fs(victim) ** 2
    if power <= 0:
        return INR_NONE_DB
    if noise <= 0:
        return INR_NOISE_FREE_DB
    return float(np.clip(10.0 * np.log10(power / noise), INR_NONE_DB, INR_NOISE_FREE_DB))


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
    "INR_NOISE_FREE_DB",
    "INR_NONE_DB",
    "MAX_REFLECTED_PATHS",
    "AggressorTiming",
    "PathSet",
    "burst_centre_s",
    "direct_paths",
    "burst_duration_s",
    "friis_if_amplitude_fs",
    "ghost_range_m",
    "interference_if",
    "interference_to_noise_db",
    "mix_paths",
    "reflected_paths",
]
