"""FMCW IF synthesis: the radar equation, the exact per-pair delay, NUFFT and direct sums.

Signal model (``docs/physics_radar.md``). For Tx ``t``, Rx ``r``, chirp ``m`` starting at
``T_mt`` after the frame start and scatterer ``k`` at ``X_k + v_k T_mt``::

    τ   = (|X − p_t| + |X − p_r|) / c                     exact bistatic delay
    f_b = K τ                                             beat frequency
    a   = C √(σ g_t(u) g_r(u)) / (|X − p_t| |X − p_r|) · H(f_b)
    y[n] = Σ_k a · exp(j (2π f_c τ + 2π f_b n / f_s − π K τ² + φ_k))

with ``C`` the radar-equation calibration of :func:`amplitude_scale_fs`, ``g`` the element
power patterns in the direction ``u`` of ``X_k`` from the array origin, ``H`` the IF
high-pass's frequency response and ``φ_k`` the scatterer's extra phase (speckle). The real
IF is ``Re y``; complex IQ is ``y``. Units: ADC full scale (FS).

:func:`synthesize_if` evaluates ``y`` with finufft: for every (chirp, Tx, Rx) one 1-D type-1
transform over the scatterers, whose non-uniform points are the per-sample phase
increments ``2π f_b / f_s`` (exact: nothing is assumed constant across chirps or
antennas). Scatterers that do not move relative to the radar give identical chirps; they
are transformed once per pair. :func:`synthesize_if_direct` is the literal sum, the
reference the fast path is tested against.
"""

from __future__ import annotations

import os
import threading
import weakref
from collections.abc import Iterator
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from typing import Any, Literal

import finufft
import numpy as np
from numpy.typing import NDArray
from scipy.interpolate import RegularGridInterpolator

from simcore.scene.radar_config import (
    SPEED_OF_LIGHT,
    CosinePattern,
    ElementPattern,
    RadarConfig,
    TablePattern,
)
from simcore.sensors.radar.scatterers import Scatterers

BOLTZMANN = 1.380649e-23
#: Reference noise temperature of the noise figure (K).
T0_K = 290.0
#: Reference impedance of the power → voltage conversion at the Rx port (Ω).
R_REF_OHM = 50.0

ComplexCube = NDArray[np.complex128]


# --------------------------------------------------------------------------- calibration
def amplitude_scale_fs(config: RadarConfig) -> float:
    """Calibration constant ``C`` of the IF amplitude (FS · m / √m², see module docstring).

    A scatterer of RCS σ at distances ``R_t`` (from the Tx) and ``R_r`` (from the Rx)
    receives the power ``P_r = P_t G_t g_t G_r g_r λ² σ / ((4π)³ R_t² R_r²)`` (radar
    equation); its IF tone has the peak voltage ``√(2 R_ref P_r) · 10^(if_gain_db/20)`` at
    the ADC input, i.e. the amplitude ``C √(σ g_t g_r) / (R_t R_r)`` in FS with

        C = √(2 R_ref P_t G_t G_r λ² / (4π)³) · 10^(if_gain_db/20) / V_fs.
    """
    p_t = 1e-3 * 10.0 ** (config.tx_power_dbm / 10.0)
    g = 10.0 ** ((config.tx_gain_dbi + config.rx_gain_dbi) / 10.0)
    lam = config.wavelength_m
    volts = np.sqrt(2.0 * R_REF_OHM * p_t * g * lam**2 / (4.0 * np.pi) ** 3)
    return float(volts * 10.0 ** (config.if_gain_db / 20.0) / config.adc_full_scale_v)


def noise_std_fs(config: RadarConfig) -> float:
    """Receiver noise standard deviation per real channel (I or Q) at the ADC (FS).

    ``noise_variance_adc`` when set; otherwise thermal noise ``k T0 F B R_ref`` in the
    Nyquist band ``B = f_s / 2`` of each real channel, referred to the ADC input through
    the IF gain.
    """
    if config.noise_variance_adc is not None:
        return float(np.sqrt(config.noise_variance_adc))
    f = 10.0 ** (config.noise_figure_db / 10.0)
    power = BOLTZMANN * T0_K * f * 0.5 * config.sample_rate_hz
    volts = np.sqrt(power * R_REF_OHM) * 10.0 ** (config.if_gain_db / 20.0)
    return float(volts / config.adc_full_scale_v)


def leakage_amplitude_fs(config: RadarConfig) -> float:
    """Peak amplitude of the Tx→Rx leakage tone at the ADC, before the high-pass (FS)."""
    if config.leakage_dbc is None:
        return 0.0
    p = 1e-3 * 10.0 ** ((config.tx_power_dbm + config.leakage_dbc) / 10.0)
    volts = np.sqrt(2.0 * R_REF_OHM * p) * 10.0 ** (config.if_gain_db / 20.0)
    return float(volts / config.adc_full_scale_v)


def highpass_response(freq_hz: NDArray[np.floating] | float, cutoff_hz: float, order: int
                      ) -> NDArray[np.complex128]:
    """Frequency response of an analog Butterworth high-pass, ``H(j 2π f)``.

    ``H(s) = Π_k s / (s − p_k)`` with the ``order`` Butterworth poles ``p_k`` on the circle of
    radius ``2π cutoff_hz`` in the left half plane; ``|H|² = x^{2n} / (1 + x^{2n})`` with
    ``x = f / cutoff``. ``cutoff_hz = 0`` gives ``H = 1``. Negative frequencies (complex IQ)
    get ``H(−f) = conj H(f)``.
    """
    f = np.asarray(freq_hz, dtype=np.float64)
    if cutoff_hz <= 0:
        return np.ones(f.shape, dtype=np.complex128)
    k = np.arange(1, order + 1)
    poles = 2 * np.pi * cutoff_hz * np.exp(1j * np.pi * (2 * k + order - 1) / (2 * order))
    s = 2j * np.pi * f
    h = np.ones(f.shape, dtype=np.complex128)
    for p in poles:
        h *= s / (s - p)
    return h


def element_gain(pattern: ElementPattern, directions: NDArray[np.floating]
                 ) -> NDArray[np.float64]:
    """Power gain of an element pattern relative to its boresight peak.

    Parameters
    ----------
    pattern : CosinePattern or TablePattern
        The element pattern.
    directions : ndarray, shape (M, 3)
        Directions in the radar optical frame (need not be unit vectors).

    Returns
    -------
    ndarray, shape (M,)
        Linear power gain (1 on boresight for a cosine pattern).
    """
    d = np.asarray(directions, dtype=np.float64)
    horiz = np.hypot(d[:, 0], d[:, 2])
    if isinstance(pattern, CosinePattern):
        # cos az = z / √(x² + z²), cos el = √(x² + z²) / |d|: no trigonometric calls.
        norm = np.hypot(horiz, d[:, 1])
        with np.errstate(divide="ignore", invalid="ignore"):
            cos_az = np.where(horiz > 0, d[:, 2] / horiz, 1.0)
            cos_el = np.where(norm > 0, horiz / norm, 1.0)
            g = (np.maximum(cos_az, 0.0) ** pattern.exponent_az
                 * np.maximum(cos_el, 0.0) ** pattern.exponent_el)
        return np.asarray(g, dtype=np.float64)
    az = np.arctan2(d[:, 0], d[:, 2])
    el = np.arctan2(-d[:, 1], horiz)
    if isinstance(pattern, TablePattern):
        az_t = np.asarray(pattern.azimuth_deg)
        el_t = np.asarray(pattern.elevation_deg)
        interp = RegularGridInterpolator((el_t, az_t), np.asarray(pattern.gain_db))
        pts = np.stack([np.clip(np.degrees(el), el_t[0], el_t[-1]),
                        np.clip(np.degrees(az), az_t[0], az_t[-1])], axis=-1)
        return np.asarray(10.0 ** (interp(pts) / 10.0), dtype=np.float64)
    raise TypeError(f"unknown element pattern {pattern!r}")


def _pattern_gains(config: RadarConfig, directions: NDArray[np.float64]
                   ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Per-element pattern gains, shapes (tx, M) and (rx, M); shared patterns computed once."""
    cache: dict[str, NDArray[np.float64]] = {}

    def gain(pattern: ElementPattern) -> NDArray[np.float64]:
        key = pattern.model_dump_json()
        if key not in cache:
            cache[key] = element_gain(pattern, directions)
        return cache[key]

    g_tx = np.array([gain(a.pattern or config.element_pattern) for a in config.tx])
    g_rx = np.array([gain(a.pattern or config.element_pattern) for a in config.rx])
    return g_tx.reshape(len(config.tx), -1), g_rx.reshape(len(config.rx), -1)


def _scatterer_weights(scatterers: Scatterers, config: RadarConfig
                       ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """``C √(σ g_t g_r)`` per pair and the scatterers' phases; shape (tx, rx, M) and (M,)."""
    g_tx, g_rx = _pattern_gains(config, scatterers.positions_m)
    base = amplitude_scale_fs(config) * np.sqrt(scatterers.rcs_m2)
    amp = base[None, None, :] * np.sqrt(g_tx[:, None, :] * g_rx[None, :, :])
    return amp, scatterers.phase_rad


def check_wavelength(scatterers: Scatterers, config: RadarConfig) -> None:
    """Refuse scatterers computed for another wavelength (their corner-reflector RCS)."""
    if scatterers.wavelength_m and abs(scatterers.wavelength_m - config.wavelength_m) > (
            1e-9 * config.wavelength_m):
        raise ValueError(
            f"scatterers were computed for λ = {scatterers.wavelength_m * 1e3:.4f} mm but the "
            f"radar now uses λ = {config.wavelength_m * 1e3:.4f} mm; compute them again"
        )


# --------------------------------------------------------------------------- synthesis
#: Scatterers per NUFFT task: bounds the temporaries (≈ 1 MB per array) and balances the
#: tasks over the worker threads. The transforms of the blocks of a pair are summed.
BLOCK = 65536
#: ``nufft_tolerance`` at or above which finufft's single-precision (complex64) plans are
#: used: ≈ 2× faster, but the float32 points limit them to ≈ 3e-5 relative error (−90 dB
#: on the office scene) whatever their own tolerance.
SINGLE_PRECISION_TOLERANCE = 1e-4
#: Default number of threads of :func:`synthesize_if` (numpy and finufft release the GIL).
DEFAULT_THREADS = max(1, min(2, os.cpu_count() or 1))

_TWO_PI = 2.0 * np.pi


class _Prepared:
    """Per-scatterer arrays that do not depend on the antennas or the waveform.

    Kept for the latest :class:`Scatterers` object (by identity), so that re-synthesising
    the same scatterers with other antennas (an antenna drag in the GUI) skips them.
    """

    def __init__(self, scatterers: Scatterers):
        self.ref = weakref.ref(scatterers)
        vel = scatterers.velocities_mps
        moving = (vel[:, 0] != 0.0) | (vel[:, 1] != 0.0) | (vel[:, 2] != 0.0)
        n_moving = int(np.count_nonzero(moving))
        n_static = len(moving) - n_moving
        self.groups = {False: slice(0, n_static), True: slice(n_static, len(moving))}
        # Static scatterers first, then moving ones; each group a contiguous slice.
        order: NDArray[np.intp] | slice = slice(None)
        if n_moving and n_static:
            order = np.concatenate([np.flatnonzero(~moving), np.flatnonzero(moving)])
        self.positions = scatterers.positions_m[order]
        # Structure of arrays: one contiguous row per coordinate.
        self.pos = np.ascontiguousarray(self.positions.T)
        self.vel = (np.ascontiguousarray(vel[order].T) if n_moving
                    else np.zeros((3, len(moving))))
        self.sqrt_rcs = np.sqrt(scatterers.rcs_m2[order]).astype(np.float32)
        self.phase = np.ascontiguousarray(scatterers.phase_rad[order], dtype=np.float64)
        self._gains: dict[str, NDArray[np.float32]] = {}
        self._lock = threading.Lock()

    def amplitude_gain(self, pattern: ElementPattern) -> NDArray[np.float32]:
        """``√g`` of an element pattern towards every scatterer, shape (M,), float32."""
        key = pattern.model_dump_json()
        with self._lock:
            if key not in self._gains:
                g = element_gain(pattern, self.positions)
                self._gains[key] = np.sqrt(g).astype(np.float32)
            return self._gains[key]


_PREPARED: list[_Prepared] = []
_PREPARED_LOCK = threading.Lock()


#: Scatterer sets whose prepared arrays are kept (least recently used dropped first): a
#: static background, a frame and its small subsets.
_PREPARED_KEEP = 4


def _prepared(scatterers: Scatterers) -> _Prepared:
    with _PREPARED_LOCK:
        live = [q for q in _PREPARED if q.ref() is not None]
        for p in live:
            if p.ref() is scatterers:
                _PREPARED[:] = [q for q in live if q is not p] + [p]
                return p
        p = _Prepared(scatterers)
        _PREPARED[:] = live[-(_PREPARED_KEEP - 1):] + [p]
        return p


@dataclass(frozen=True)
class _Waveform:
    """Constants of the weights and points, per metre of Tx→scatterer→Rx path."""

    n_s: int
    eps: float
    single: bool
    theta_per_m: float          # θ = 2π f_b / f_s per metre of path
    phase_per_m: float          # (2π f_c + (N/2) θ_per_τ) / c
    quad_per_m2: float          # π K / c²
    x_per_m: float              # f_b / f_cut per metre of path (0: no high-pass)
    poles: tuple[tuple[float, float], ...]   # high-pass poles / (2π f_cut)

    @classmethod
    def of(cls, config: RadarConfig) -> _Waveform:
        c = SPEED_OF_LIGHT
        n_s, slope = config.samples_per_chirp, config.slope_hz_per_s
        theta_per_tau = _TWO_PI * slope / config.sample_rate_hz
        # y[n] = Σ c e^{i n θ} for n = 0…N−1 is finufft's type-1 sum over modes
        # k = n − N//2 with the weights c e^{i (N//2) θ}.
        phase_per_tau = _TWO_PI * config.start_frequency_hz + (n_s // 2) * theta_per_tau
        cutoff, order = config.if_highpass_hz, config.if_highpass_order
        poles: tuple[tuple[float, float], ...] = ()
        if cutoff > 0:
            k = np.arange(1, order + 1)
            p = np.exp(1j * np.pi * (2 * k + order - 1) / (2 * order))
            poles = tuple((float(z.real), float(z.imag)) for z in p)
        return cls(
            n_s=n_s, eps=config.nufft_tolerance,
            single=config.nufft_tolerance >= SINGLE_PRECISION_TOLERANCE,
            theta_per_m=theta_per_tau / c, phase_per_m=phase_per_tau / c,
            quad_per_m2=np.pi * slope / c**2,
            x_per_m=slope / (c * cutoff) if cutoff > 0 else 0.0, poles=poles)


_PLANS = threading.local()


def _plan(wave: _Waveform) -> finufft.Plan:
    """Type-1 plan of the calling thread for the waveform's size, tolerance and precision."""
    plans: dict[tuple[int, float, bool], finufft.Plan] = getattr(_PLANS, "plans", None) or {}
    _PLANS.plans = plans
    key = (wave.n_s, wave.eps, wave.single)
    if key not in plans:
        # One thread per plan: on few cores finufft's own threading costs more than it gains
        # at 1-D sizes; the tasks run in parallel instead. Sorting the points buys nothing
        # here: the whole fine grid (2N points) stays in L1 cache.
        plans[key] = finufft.Plan(1, (wave.n_s,), eps=wave.eps, isign=1,
                                  dtype="complex64" if wave.single else "complex128",
                                  nthreads=1, spread_sort=0)
    return plans[key]


def _distance(pos: NDArray[np.float64], p: NDArray[np.float64]) -> NDArray[np.float64]:
    """``|X − p|`` for positions ``pos`` of shape (3, B) (one row per coordinate)."""
    d = pos[0] - p[0]
    d *= d
    tmp = pos[1] - p[1]
    tmp *= tmp
    d += tmp
    np.subtract(pos[2], p[2], out=tmp)
    tmp *= tmp
    d += tmp
    return np.sqrt(d, out=d)


def _wrap(x: NDArray[np.float64]) -> NDArray[np.float64]:
    """``x`` minus the nearest multiple of 2π, in place (result in [−π, π])."""
    q = x * (1.0 / _TWO_PI)
    np.rint(q, out=q)
    q *= _TWO_PI
    x -= q
    return x


def _highpass_factor(x: NDArray[np.float32], pole: tuple[float, float]
                     ) -> tuple[NDArray[np.floating[Any]], NDArray[np.floating[Any]]]:
    """Real and imaginary parts of ``jx / (jx − p)`` for a pole ``p`` on the unit circle."""
    p_re, p_im = pole
    u = x - np.float32(p_im)
    den = u * u
    den += np.float32(p_re * p_re)
    return x * u / den, x * np.float32(-p_re) / den


def _pair_weights(wave: _Waveform, d_t: NDArray[np.float64], d_r: NDArray[np.float64],
                  amp: NDArray[np.float32], phase: NDArray[np.float64]
                  ) -> tuple[NDArray[np.floating], NDArray[np.complexfloating]]:
    """NUFFT points and weights of scatterers for one Tx–Rx pair.

    ``amp`` is ``C √(σ g_t g_r) / R_t`` (float32); the rest of the amplitude, the phase and
    the point come from the path length. Phases are reduced modulo 2π in float64 before
    the float32 cos/sin (relative error ≈ 1e-7, −140 dB); points stay float64 for double
    plans.
    """
    path = d_t + d_r
    theta = _wrap(path * wave.theta_per_m)
    arg = path * -wave.quad_per_m2
    arg += wave.phase_per_m
    arg *= path
    arg += phase
    arg32 = _wrap(arg).astype(np.float32)
    a = amp / d_r.astype(np.float32)
    cos, sin = np.cos(arg32), np.sin(arg32)
    w = np.empty(path.shape, dtype=np.complex64 if wave.single else np.complex128)
    if wave.poles:
        # H(f_b) = Π_k jx / (jx − p_k), x = f_b / f_cut, in float32 real arithmetic.
        x = path.astype(np.float32)
        x *= np.float32(wave.x_per_m)
        h_re, h_im = _highpass_factor(x, wave.poles[0])
        for pole in wave.poles[1:]:
            f_re, f_im = _highpass_factor(x, pole)
            h_re, h_im = h_re * f_re - h_im * f_im, h_re * f_im + h_im * f_re
        a_re, a_im = a * h_re, a * h_im
        w.real = cos * a_re - sin * a_im
        w.imag = sin * a_re + cos * a_im
    else:
        w.real = cos * a
        w.imag = sin * a
    return (theta.astype(np.float32) if wave.single else theta), w


#: One task: chirps (None: static scatterers, the same in every chirp), Tx, block.
_Task = tuple[tuple[int, ...] | None, int, slice]


def _run_task(task: _Task, prep: _Prepared, wave: _Waveform, config: RadarConfig,
              amp_tx: list[NDArray[np.float32]], amp_rx: list[NDArray[np.float32]]
              ) -> list[NDArray[np.complexfloating]]:
    """One block of scatterers, one Tx, some chirps (one row for static ones): every Rx.

    The weights of all the task's chirps are computed together (one set of numpy calls);
    each chirp is its own type-1 transform.

    Returns
    -------
    list of ndarray, shape (chirps or 1, samples)
        One per Rx.
    """
    chirps, t, rows = task
    pos = prep.pos[:, rows]
    n = pos.shape[1]
    reps = 1
    if chirps is not None:
        reps = len(chirps)
        starts = config.chirp_start_times_s()[list(chirps), t]
        pos = (pos[:, None, :] + prep.vel[:, rows][:, None, :] * starts[None, :, None]
               ).reshape(3, reps * n)
    d_t = _distance(pos, config.tx_positions_m()[t])
    base = np.tile(prep.sqrt_rcs[rows] * amp_tx[t][rows], reps)
    base /= d_t.astype(np.float32)
    base *= np.float32(amplitude_scale_fs(config))
    phase = np.tile(prep.phase[rows], reps)
    plan = _plan(wave)
    out = []
    for r, p_r in enumerate(config.rx_positions_m()):
        theta, w = _pair_weights(wave, d_t, _distance(pos, p_r),
                                 base * np.tile(amp_rx[r][rows], reps), phase)
        y = np.empty((reps, wave.n_s), dtype=w.dtype)
        for k in range(reps):
            plan.setpts(theta[k * n:(k + 1) * n])
            y[k] = plan.execute(w[k * n:(k + 1) * n])
        out.append(y)
    return out


_POOLS: dict[int, ThreadPoolExecutor] = {}
_POOLS_LOCK = threading.Lock()


def _forget_pools() -> None:
    # A forked child inherits the pools but not their threads: start new ones there.
    _POOLS.clear()


if hasattr(os, "register_at_fork"):
    os.register_at_fork(after_in_child=_forget_pools)


def _pool(threads: int) -> ThreadPoolExecutor:
    with _POOLS_LOCK:
        if threads not in _POOLS:
            _POOLS[threads] = ThreadPoolExecutor(max_workers=threads,
                                                 thread_name_prefix="if-synthesis")
        return _POOLS[threads]


def synthesize_if(scatterers: Scatterers, config: RadarConfig, *, threads: int | None = None
                  ) -> ComplexCube:
    """Noise-free complex IF of all scatterers with finufft (fast path).

    Static scatterers (zero relative velocity) are transformed once per Tx–Rx pair and
    broadcast over the chirps; moving ones once per pair and chirp. Blocks of
    :data:`BLOCK` scatterers run as independent tasks on ``threads`` threads; their
    results are summed in a fixed order, so the output does not depend on ``threads``.

    Parameters
    ----------
    scatterers : Scatterers
        Point scatterers in the radar frame.
    config : RadarConfig
        Waveform, antennas, gains, IF high-pass and ``nufft_tolerance`` (below
        :data:`SINGLE_PRECISION_TOLERANCE`: double-precision transforms).
    threads : int, optional
        Worker threads (default :data:`DEFAULT_THREADS`; 1 runs on the calling thread).

    Returns
    -------
    ndarray, shape (chirps, tx*rx, samples), complex128
        ``y`` of the module docstring in FS; the real IF is its real part. Channel
        ``t * n_rx + r`` is Tx ``t`` with Rx ``r``.
    """
    check_wavelength(scatterers, config)
    n_c, n_s = config.chirps_per_frame, config.samples_per_chirp
    n_tx, n_rx = len(config.tx), len(config.rx)
    out = np.zeros((n_c, n_tx * n_rx, n_s), dtype=np.complex128)
    if len(scatterers) == 0:
        return out
    prep = _prepared(scatterers)
    wave = _Waveform.of(config)
    amp_tx = [prep.amplitude_gain(a.pattern or config.element_pattern) for a in config.tx]
    amp_rx = [prep.amplitude_gain(a.pattern or config.element_pattern) for a in config.rx]

    tasks: list[_Task] = []
    for moves, group in prep.groups.items():
        for lo in range(group.start, group.stop, BLOCK):
            rows = slice(lo, min(lo + BLOCK, group.stop))
            # Moving scatterers: chirps in chunks of about BLOCK points per task.
            per_task = max(1, BLOCK // (rows.stop - rows.start))
            chunks = ([tuple(range(c, min(c + per_task, n_c))) for c in range(0, n_c, per_task)]
                      if moves else [None])
            for t in range(n_tx):
                for chirps in chunks:
                    tasks.append((chirps, t, rows))

    def run(task: _Task) -> list[NDArray[np.complexfloating]]:
        return _run_task(task, prep, wave, config, amp_tx, amp_rx)

    n_threads = DEFAULT_THREADS if threads is None else max(1, int(threads))
    results: Iterator[list[NDArray[np.complexfloating]]]
    if n_threads == 1 or len(tasks) == 1:
        results = map(run, tasks)
    else:
        results = _pool(n_threads).map(run, tasks)
    for (chirps, t, _), ys in zip(tasks, results, strict=True):
        for r, y in enumerate(ys):
            if chirps is None:
                out[:, t * n_rx + r] += y
            else:
                out[chirps[0]:chirps[-1] + 1, t * n_rx + r] += y
    return out


def synthesize_if_direct(scatterers: Scatterers, config: RadarConfig, *,
                         chirps: NDArray[np.integer] | None = None, chunk: int = 2048
                         ) -> ComplexCube:
    """Noise-free complex IF by the literal sum over scatterers and samples (reference).

    Costs O(chirps · tx · rx · M · samples); use it on small scenes or a few chirps.

    Parameters
    ----------
    scatterers : Scatterers
        Point scatterers in the radar frame.
    config : RadarConfig
        The radar.
    chirps : ndarray of int, optional
        Chirp indices to compute (default all).
    chunk : int
        Scatterers per vectorised block.

    Returns
    -------
    ndarray, shape (len(chirps), tx*rx, samples), complex128
        Same quantity as :func:`synthesize_if`.
    """
    check_wavelength(scatterers, config)
    idx = np.arange(config.chirps_per_frame) if chirps is None else np.asarray(chirps)
    n_tx, n_rx = len(config.tx), len(config.rx)
    t_n = config.sample_times_s()
    out = np.zeros((len(idx), n_tx * n_rx, len(t_n)), dtype=np.complex128)
    if len(scatterers) == 0:
        return out
    amp, phase = _scatterer_weights(scatterers, config)
    p_tx, p_rx = config.tx_positions_m(), config.rx_positions_m()
    starts = config.chirp_start_times_s()
    f_c, slope = config.start_frequency_hz, config.slope_hz_per_s
    for i, m in enumerate(idx):
        for t in range(n_tx):
            for r in range(n_rx):
                acc = np.zeros(len(t_n), dtype=np.complex128)
                for lo in range(0, len(scatterers), chunk):
                    k = slice(lo, lo + chunk)
                    x = scatterers.positions_m[k] + scatterers.velocities_mps[k] * starts[m, t]
                    r_t = np.sqrt(np.sum((x - p_tx[t]) ** 2, axis=1))
                    r_r = np.sqrt(np.sum((x - p_rx[r]) ** 2, axis=1))
                    tau = ((r_t + r_r) / SPEED_OF_LIGHT)[:, None]
                    h = highpass_response(slope * tau[:, 0], config.if_highpass_hz,
                                          config.if_highpass_order)
                    a = amp[t, r, k] / (r_t * r_r) * h
                    ph = (2 * np.pi * f_c * tau + 2 * np.pi * slope * tau * t_n[None, :]
                          - np.pi * slope * tau**2 + phase[k, None])
                    acc += a @ np.exp(1j * ph)
                out[i, t * n_rx + r] = acc
    return out


# --------------------------------------------------------------------------- receiver
def leakage_if(config: RadarConfig) -> ComplexCube:
    """Tx→Rx leakage of every pair: one tone over the direct board path, all chirps equal.

    Returns
    -------
    ndarray, shape (1, tx*rx, samples), complex128
        Complex IF in FS (broadcasts over chirps), high-pass applied.
    """
    n_tx, n_rx = len(config.tx), len(config.rx)
    t_n = config.sample_times_s()
    out = np.zeros((1, n_tx * n_rx, len(t_n)), dtype=np.complex128)
    amp = leakage_amplitude_fs(config)
    if amp == 0.0:
        return out
    p_tx, p_rx = config.tx_positions_m(), config.rx_positions_m()
    f_c, slope = config.start_frequency_hz, config.slope_hz_per_s
    for t in range(n_tx):
        for r in range(n_rx):
            tau = float(np.linalg.norm(p_tx[t] - p_rx[r])) / SPEED_OF_LIGHT
            h = highpass_response(slope * tau, config.if_highpass_hz, config.if_highpass_order)
            out[0, t * n_rx + r] = amp * h * np.exp(1j * (
                2 * np.pi * f_c * tau + 2 * np.pi * slope * tau * t_n - np.pi * slope * tau**2))
    return out


def receiver_noise(config: RadarConfig, shape: tuple[int, ...], rng: np.random.Generator
                   ) -> NDArray[np.float64] | NDArray[np.complex128]:
    """White receiver noise shaped by the IF high-pass, real or complex per ``complex_iq``.

    Parameters
    ----------
    config : RadarConfig
        The radar (noise level, high-pass, IQ).
    shape : tuple
        Output shape; the last axis is fast time (samples).
    rng : numpy.random.Generator
        Source of randomness.

    Returns
    -------
    ndarray
        Noise in FS, variance ``noise_std_fs(config)**2`` per real channel before the
        high-pass (the high-pass removes the part of it below its cutoff).
    """
    sigma = noise_std_fs(config)
    noise: NDArray[np.float64] | NDArray[np.complex128]
    if config.complex_iq:
        noise = sigma * (rng.standard_normal(shape) + 1j * rng.standard_normal(shape))
    else:
        noise = sigma * rng.standard_normal(shape)
    if config.if_highpass_hz > 0 and sigma > 0:
        n = shape[-1]
        if config.complex_iq:
            f = np.fft.fftfreq(n, 1.0 / config.sample_rate_hz)
            h = highpass_response(f, config.if_highpass_hz, config.if_highpass_order)
            noise = np.fft.ifft(np.fft.fft(noise, axis=-1) * h, axis=-1)
        else:
            f = np.fft.rfftfreq(n, 1.0 / config.sample_rate_hz)
            h = highpass_response(f, config.if_highpass_hz, config.if_highpass_order)
            noise = np.fft.irfft(np.fft.rfft(noise, axis=-1) * h, n=n, axis=-1)
    return noise


def quantize(x: NDArray[np.float64], bits: int | None) -> tuple[NDArray[np.float64], int]:
    """Round to the ADC grid and clip at full scale (FS units).

    The LSB is ``2 / 2**bits``; codes run from ``-2**(bits-1)`` to ``2**(bits-1) - 1``.

    Returns
    -------
    quantized : ndarray, same shape as ``x``
        Quantized values (FS).
    clipped : int
        Number of values that exceeded full scale.
    """
    if bits is None:
        return x, 0
    half = 2 ** (bits - 1)
    codes = np.rint(x * half)
    clipped = int(np.count_nonzero((codes < -half) | (codes > half - 1)))
    return np.clip(codes, -half, half - 1) / half, clipped


def receiver_chain(ideal: ComplexCube, config: RadarConfig, rng: np.random.Generator
                   ) -> tuple[NDArray[np.float32] | NDArray[np.complex64], int]:
    """Leakage, noise, quantization: the ADC cube from the noise-free complex IF.

    Parameters
    ----------
    ideal : ndarray, shape (chirps, tx*rx, samples), complex128
        Output of :func:`synthesize_if` (FS).
    config : RadarConfig
        Receiver settings.
    rng : numpy.random.Generator
        Source of the noise.

    Returns
    -------
    adc : ndarray, shape (chirps, tx*rx, samples)
        float32 (real IF) or complex64 (IQ), FS.
    clipped : int
        Number of real values (I and Q counted separately) clipped at full scale.
    """
    x = ideal + leakage_if(config)
    noise = receiver_noise(config, x.shape, rng)
    if config.complex_iq:
        z = x + noise
        i_q, c_i = quantize(z.real, config.adc_bits)
        q_q, c_q = quantize(z.imag, config.adc_bits)
        return (i_q + 1j * q_q).astype(np.complex64), c_i + c_q
    real, clipped = quantize(x.real + noise.real, config.adc_bits)
    return real.astype(np.float32), clipped


SynthesisMethod = Literal["nufft", "direct"]
