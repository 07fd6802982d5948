"""FMCW IF synthesis: exact time-varying delays, NUFFT fast path and the direct sum.

Signal model (``docs/physics_radar.md``). For Tx ``t``, Rx ``r`` and scatterer ``k``, the
sample ``n`` of chirp ``m`` is taken at ``t = T_mt + t_n`` after the frame start
(``T_mt`` = ``config.chirp_start_times_s()``, ``t_n = n / f_s``); the scatterer is then at
``x_k(t)`` (its motion model ``x + v t + a t²/2``, or an exact ``trajectory``) and

    τ(t) = (|x_k(t) − p_t| + |x_k(t) − p_r|) / c              exact bistatic delay
    y[m, n] = Σ_k a_k · exp(j (2π (f_c + K t_n) τ(t) − π K τ(t)² + φ_k))

with ``a_k = A_k H(K τ_k)`` the radar-equation amplitude
(:func:`~simcore.sensors.radar.equation.if_amplitude_fs`) and the IF high-pass response at
the scatterer's frame-start position, held over the frame, and ``φ_k`` its scattering phase
(speckle). Because τ varies within each chirp, an up-chirp shifts a receding target's beat
frequency by its Doppler ``f_c τ'`` (range–Doppler coupling) and targets migrate in range
across the chirps. The real IF is ``Re y``; complex IQ is ``y``. Units: ADC full scale (FS).

:func:`synthesize_if` (fast path, finufft):

* scatterers that do not move relative to the radar: one 1-D type-1 transform per Tx–Rx
  pair over the samples, identical in every chirp;
* moving scatterers: per Tx–Rx pair one 2-D type-3 transform from the sources
  ``(τ_c, β)`` (delay at the frame centre, delay rate) to the targets
  ``(2π (f_inst(n) − f_r), 2π f_inst(n) (t − t_c))`` of all the pair's samples: with a
  delay linear in time the phase ``2π f_inst τ(t)`` is exactly bilinear in sources and
  targets, so range–Doppler coupling, range migration and the TDM chirp timing are exact.
  The curvature of the delay (acceleration, rotation, geometry) enters as a short Taylor
  series of extra transforms with the same points, whose length is chosen per scatterer
  from the tolerance; scatterers whose remaining model error exceeds it are synthesised
  over halves of the frame, quarters, … single chirps, and finally by the direct sum.

:func:`synthesize_if_direct` is the literal sum with exact positions at every sample, the
reference the fast path is tested against. Both are pure functions: the per-scatterer
arrays that do not depend on the radar (:func:`prepare`) are an explicit argument, so a
caller that synthesises one scatterer set several times (antenna edits) keeps them.
"""

from __future__ import annotations

import dataclasses
import os
import threading
from collections.abc import Callable, Iterator, Sequence
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field
from typing import Any, Literal

import finufft
import numpy as np
from numpy.typing import NDArray

from simcore.scene.radar_config import SPEED_OF_LIGHT, ElementPattern, RadarConfig
from simcore.sensors.radar.equation import (
    BOLTZMANN,
    R_REF_OHM,
    T0_K,
    amplitude_scale_fs,
    butterworth_poles,
    element_gain,
    highpass_response,
    if_amplitude_fs,
    if_filter_response,
    leakage_amplitude_fs,
    noise_std_fs,
    pattern_gains,
)
from simcore.sensors.radar.kinematics import Trajectory
from simcore.sensors.radar.path_kernel import path_lengths, path_lengths_rows
from simcore.sensors.radar.receiver import (
    leakage_if,
    quantize,
    receiver_chain,
    receiver_noise,
)
from simcore.sensors.radar.scatterers import Scatterers
from simcore.sensors.radar.synthesis_kernel import fit_delays, transform_points

ComplexCube = NDArray[np.complex128]
#: Tx positions (n_tx, 3) and Rx positions (n_rx, 3) of a synthesis (m), or one position per
#: prepared row, (n_tx, 3, M) and (n_rx, 3, M) (:func:`synthesize_if_sets`).
_Antennas = tuple[NDArray[np.float64], NDArray[np.float64]]
SynthesisMethod = Literal["nufft", "direct"]

#: Scatterers per NUFFT task: bounds the temporaries (≈ 1 MB per array) and balances the
#: tasks over the worker threads. The transforms of the blocks of a pair are summed.
BLOCK = 65536
#: ``nufft_tolerance`` at or above which finufft's single-precision (complex64) plans are
#: used for static scatterers: ≈ 2× faster, but the float32 points limit them to ≈ 3e-5
#: relative error (−90 dB on the office scene) whatever their own tolerance.
SINGLE_PRECISION_TOLERANCE = 1e-4
#: Default number of threads of :func:`synthesize_if` (numpy and finufft release the GIL).
DEFAULT_THREADS = max(1, min(2, os.cpu_count() or 1))
#: Smallest per-scatterer model error (rad of IF phase, ≈ relative amplitude error) the
#: moving-scatterer path aims at: below it the float32 weights' rounding (≈ 1e-7) and the
#: transforms dominate anyway. The budget is ``max(nufft_tolerance, MOTION_TOLERANCE_FLOOR)``.
MOTION_TOLERANCE_FLOOR = 1e-4
#: Relative L2 rounding of a single-precision (complex64) type-3 transform per radian of its
#: centred phase span ``P = max|s|·½ span(x) + max|t|·½ span(y)``: about 2 × 2⁻²⁴ measured
#: (point targets 0.7–5.7 m, P ≈ 310 rad: −88 dB), with a margin. Moving scatterers use
#: single precision where this times ``P`` is within half their budget (``docs/physics_radar.md``).
SINGLE_ROUNDING_PER_RAD = 2.5 * 2.0**-24
#: Longest curvature series (highest power) before a scatterer is split over shorter blocks.
MAX_SERIES_ORDER = 4
#: Scatterers × samples below which a fallback block is summed directly (a type-3
#: transform costs ≈ 0.5–4 ms whatever its size; the direct sum ≈ 30 ns per term).
DIRECT_MAX_TERMS = 32768
#: Scatterers up to which the series vectors share the main transform call.
MERGE_SERIES_POINTS = 32768
#: Loosest tolerance of the curvature-series transforms (their terms are small).
SERIES_NUFFT_TOLERANCE = 1e-3

_TWO_PI = 2.0 * np.pi


def check_wavelength(scatterers: Scatterers, config: RadarConfig) -> None:
    """Refuse scatterers computed for another wavelength (their corner-reflector RCS)."""
    if scatterers.wavelength_m and abs(scatterers.wavelength_m - config.wavelength_m) > (
            1e-9 * config.wavelength_m):
        raise ValueError(
            f"scatterers were computed for λ = {scatterers.wavelength_m * 1e3:.4f} mm but the "
            f"radar now uses λ = {config.wavelength_m * 1e3:.4f} mm; compute them again"
        )


# --------------------------------------------------------------------------- prepared
@dataclass(frozen=True, eq=False)
class PreparedScatterers:
    """Per-scatterer arrays of a :class:`Scatterers` that do not depend on the radar.

    Made by :func:`prepare`; pass it to :func:`synthesize_if` to skip this work when the
    same scatterers are synthesised again (an antenna edit). Static scatterers come first,
    then moving ones; coordinates are stored one contiguous row per axis.

    Attributes
    ----------
    source : Scatterers
        The scatterers these arrays belong to.
    n_static : int
        Number of static scatterers (the first rows).
    order : ndarray of int, shape (M,)
        Index in ``source`` of each prepared row.
    accelerates : bool
        Whether any scatterer has a non-zero acceleration.
    positions : ndarray, shape (M, 3)
        Positions at the frame start, static first (m).
    pos, vel, acc : ndarray, shape (3, M)
        Positions (m), velocities (m/s), accelerations (m/s²), one row per axis.
    rcs : ndarray, shape (M,), float32
        RCS (m²).
    phase : ndarray, shape (M,), float64
        Scattering phases (rad).
    """

    source: Scatterers
    n_static: int
    order: NDArray[np.intp]
    accelerates: bool
    positions: NDArray[np.float64]
    pos: NDArray[np.float64]
    vel: NDArray[np.float64]
    acc: NDArray[np.float64]
    rcs: NDArray[np.float32]
    phase: NDArray[np.float64]
    _gains: dict[str, NDArray[np.float32]] = field(default_factory=dict, repr=False)
    _lock: threading.Lock = field(default_factory=threading.Lock, repr=False)

    def __len__(self) -> int:
        return int(self.rcs.shape[0])

    def gain(self, pattern: ElementPattern) -> NDArray[np.float32]:
        """Power gain ``g`` of an element pattern towards every scatterer, (M,) float32."""
        key = pattern.model_dump_json()
        with self._lock:
            if key not in self._gains:
                self._gains[key] = element_gain(pattern, self.positions).astype(np.float32)
            return self._gains[key]


def prepare(scatterers: Scatterers) -> PreparedScatterers:
    """Arrays of :func:`synthesize_if` that depend on the scatterers only (see the class)."""
    moving = scatterers.moving()
    n_moving = int(np.count_nonzero(moving))
    n_static = len(moving) - n_moving
    order = np.arange(len(moving))
    if n_moving and n_static:
        order = np.concatenate([np.flatnonzero(~moving), np.flatnonzero(moving)])
        sc = scatterers.subset(order)
    else:
        sc = scatterers                         # already in order: no gathers
    return PreparedScatterers(
        source=scatterers, n_static=n_static, order=order,
        accelerates=sc.accelerations_mps2 is not None and bool(
            np.any(sc.accelerations_mps2 != 0.0)),
        positions=sc.positions_m, pos=np.ascontiguousarray(sc.positions_m.T),
        vel=np.ascontiguousarray(sc.velocities_mps.T),
        acc=np.ascontiguousarray(sc.accelerations.T),
        rcs=sc.rcs_m2.astype(np.float32),
        phase=np.ascontiguousarray(sc.phase_rad, dtype=np.float64))


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
    lp_x_per_m: float = 0.0     # f_b / f_lowpass per metre of path (0: no low-pass)
    lp_poles: tuple[tuple[float, float], ...] = ()   # low-pass poles / (2π f_lowpass)

    @property
    def filtered(self) -> bool:
        """Whether the IF chain has a high-pass or an anti-aliasing low-pass."""
        return bool(self.poles or self.lp_poles)

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
            poles = tuple((float(z.real), float(z.imag)) for z in butterworth_poles(order))
        lp_cutoff, lp_order = config.if_lowpass_hz, config.if_lowpass_order
        lp_poles: tuple[tuple[float, float], ...] = ()
        if lp_cutoff > 0:
            lp_poles = tuple((float(z.real), float(z.imag))
                             for z in butterworth_poles(lp_order))
        return cls(
            n_s=n_s, eps=config.nufft_tolerance,
            single=config.nufft_tolerance >= SINGLE_PRECISION_TOLERANCE,
            theta_per_m=theta_per_tau / c, phase_per_m=phase_per_tau / c,
            quad_per_m2=np.pi * slope / c**2,
            x_per_m=slope / (c * cutoff) if cutoff > 0 else 0.0, poles=poles,
            lp_x_per_m=slope / (c * lp_cutoff) if lp_cutoff > 0 else 0.0, lp_poles=lp_poles)


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


def _plan3(n_trans: int, eps: float, *, single: bool) -> finufft.Plan:
    """2-D type-3 plan of the calling thread for ``n_trans`` vectors (complex64 if ``single``)."""
    plans: dict[tuple[int, float, bool], finufft.Plan] = getattr(_PLANS, "plans3", None) or {}
    _PLANS.plans3 = plans
    key = (n_trans, eps, single)
    if key not in plans:
        # Unsorted points: the fine grid (≈ 600 × 20 at the preset) stays in cache anyway.
        # upsampfac 2 (finufft picks 1.25 at some tolerances: wider kernels, 20 % slower).
        plans[key] = finufft.Plan(3, 2, n_trans=n_trans, eps=eps, isign=1, nthreads=1,
                                  spread_sort=0, upsampfac=2.0,
                                  dtype="complex64" if single else "complex128")
    return plans[key]


def _distance(pos: NDArray[np.float64], p: NDArray[np.float64]) -> NDArray[np.float64]:
    """``|X − p|`` for positions ``pos`` of shape (3, ...) (one row per coordinate)."""
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


def _lowpass_factor(x: NDArray[np.float32], pole: tuple[float, float]
                    ) -> tuple[NDArray[np.floating[Any]], NDArray[np.floating[Any]]]:
    """Real and imaginary parts of ``−p / (jx − p)`` for a pole ``p`` on the unit circle."""
    p_re, p_im = pole
    u = x - np.float32(p_im)
    den = u * u
    den += np.float32(p_re * p_re)
    re = (np.float32(p_re * p_re) - np.float32(p_im) * u) / den
    return re, x * np.float32(p_re) / den


def _highpass32(wave: _Waveform, path: NDArray[np.float64]
                ) -> tuple[NDArray[np.floating[Any]], NDArray[np.floating[Any]]]:
    """Real and imaginary parts of the IF filters at the beat frequency of ``path`` (float32).

    High-pass ``Π_k jx / (jx − p_k)``, ``x = f_b / f_cut``, times the anti-aliasing low-pass
    ``Π_k (−p_k) / (jx' − p_k)``, ``x' = f_b / f_lowpass``, in float32 real arithmetic; call
    only when the waveform has a filter (``wave.filtered``).
    """
    x = path.astype(np.float32)
    h_re: NDArray[np.floating[Any]] = np.ones_like(x)
    h_im: NDArray[np.floating[Any]] = np.zeros_like(x)
    for poles, per_m, factor in ((wave.poles, wave.x_per_m, _highpass_factor),
                                 (wave.lp_poles, wave.lp_x_per_m, _lowpass_factor)):
        if not poles:
            continue
        xs = x * np.float32(per_m)
        for pole in poles:
            f_re, f_im = factor(xs, pole)
            h_re, h_im = h_re * f_re - h_im * f_im, h_re * f_im + h_im * f_re
    return h_re, h_im


def _pair_weights(wave: _Waveform, path: NDArray[np.float64], amp: NDArray[np.float32],
                  phase: NDArray[np.float64]
                  ) -> tuple[NDArray[np.floating], NDArray[np.complexfloating]]:
    """NUFFT points and weights of static scatterers for one Tx–Rx pair.

    ``amp`` is the radar-equation amplitude (float32); the high-pass, the phase and the
    point come from the path length ``path`` (m). Phases are reduced modulo 2π in float64
    before the float32 cos/sin (relative error ≈ 1e-7, −140 dB); points stay float64 for
    double plans.
    """
    theta = _wrap(path * wave.theta_per_m)
    arg = path * -wave.quad_per_m2
    arg += wave.phase_per_m
    arg *= path
    arg += phase
    arg32 = _wrap(arg).astype(np.float32)
    cos, sin = np.cos(arg32), np.sin(arg32)
    w = np.empty(path.shape, dtype=np.complex64 if wave.single else np.complex128)
    if wave.filtered:
        h_re, h_im = _highpass32(wave, path)
        a_re, a_im = amp * h_re, amp * h_im
        w.real = cos * a_re - sin * a_im
        w.imag = sin * a_re + cos * a_im
    else:
        w.real = cos * amp
        w.imag = sin * amp
    return (theta.astype(np.float32) if wave.single else theta), w


def _rows_of(p: NDArray[np.float64], rows: slice | NDArray[np.intp]) -> NDArray[np.float64]:
    """An antenna position (3,) as it is, or the ``rows`` of one per row, (3, M) → (3, B)."""
    return p if p.ndim == 1 else p[:, rows]


def _static_task(prep: PreparedScatterers, rows: slice, t: int, wave: _Waveform,
                 config: RadarConfig, antennas: _Antennas
                 ) -> list[NDArray[np.complexfloating]]:
    """One block of static scatterers, one Tx, every Rx: one transform each, shape (N,)."""
    pos = prep.pos[:, rows]
    d_t = _distance(pos, _rows_of(antennas[0][t], rows))
    rcs = prep.rcs[rows]
    g_t = prep.gain(config.tx[t].pattern or config.element_pattern)[rows]
    d_t32 = d_t.astype(np.float32)
    plan = _plan(wave)
    out = []
    for r, p_r in enumerate(antennas[1]):
        d_r = _distance(pos, _rows_of(p_r, rows))
        g_r = prep.gain(config.rx[r].pattern or config.element_pattern)[rows]
        amp = if_amplitude_fs(config, rcs, g_t, g_r, d_t32, d_r.astype(np.float32))
        theta, w = _pair_weights(wave, d_t + d_r, amp, prep.phase[rows])
        plan.setpts(theta)
        out.append(plan.execute(w))
    return out


# --------------------------------------------------------------------------- moving
@dataclass(frozen=True)
class _Sweep:
    """Timing and frequency constants of the moving-scatterer path for one configuration.

    ``f_inst(n) = f_c + K t_n`` is the instantaneous transmit frequency at sample ``n``;
    ``f_r`` its value at the centre of the sampled sweep.
    """

    t_n: NDArray[np.float64]          # (N,) sample times after the chirp start (s)
    starts: NDArray[np.float64]       # (chirps, tx) chirp start times (s)
    f_inst: NDArray[np.float64]       # (N,) Hz
    f_r: float
    f_max: float
    rel_df: float                     # max |f_inst − f_r| / f_r
    slope: float
    eps: float                        # per-scatterer budget, model + series (rad)
    eps_model: float                  # at most this much of it for the model's remainder
    eps_nufft: float                  # tolerance of the main transforms
    targets: dict[tuple[int, int, int], _Targets] = field(default_factory=dict, repr=False)
    lock: threading.Lock = field(default_factory=threading.Lock, repr=False)

    @classmethod
    def of(cls, config: RadarConfig) -> _Sweep:
        """The sweep of a configuration (the last few kept: their targets are re-used)."""
        key = config.model_dump_json()
        if config._chirp_delays_s is not None:   # one frame's chirp jitter
            key += config._chirp_delays_s.tobytes().hex()
        with _SWEEPS_LOCK:
            hit = _SWEEPS.get(key)
        if hit is None:
            hit = cls._make(config)
            with _SWEEPS_LOCK:
                if len(_SWEEPS) >= 8:
                    _SWEEPS.pop(next(iter(_SWEEPS)))
                _SWEEPS[key] = hit
        return hit

    @classmethod
    def _make(cls, config: RadarConfig) -> _Sweep:
        t_n = config.sample_times_s()
        slope = config.slope_hz_per_s
        f_inst = config.start_frequency_hz + slope * t_n
        f_r = float(config.start_frequency_hz + slope * 0.5 * (t_n[0] + t_n[-1]))
        eps = max(config.nufft_tolerance, MOTION_TOLERANCE_FLOOR)
        return cls(t_n=t_n, starts=config.chirp_start_times_s(), f_inst=f_inst, f_r=f_r,
                   f_max=float(f_inst[-1]), rel_df=float(np.abs(f_inst - f_r).max() / f_r),
                   slope=slope, eps=eps, eps_model=0.5 * eps,
                   eps_nufft=max(config.nufft_tolerance, 0.1 * eps))


#: The last few sweeps, by the configuration's JSON (their targets are re-used).
_SWEEPS: dict[str, _Sweep] = {}
_SWEEPS_LOCK = threading.Lock()


@dataclass(frozen=True)
class _Targets:
    """Type-3 targets of the samples of chirps ``m0 … m1−1`` of one Tx (flattened)."""

    t_c: float                        # block centre time (s)
    half: float                       # half the block's duration U (s)
    s: NDArray[np.float64]            # 2π (f_inst − f_r), (J,)
    t: NDArray[np.float64]            # 2π f_inst (t − t_c), (J,)
    b: NDArray[np.float64]            # 2π f_inst ((t − t_c)² − q̄), (J,)
    b2: NDArray[np.float64]           # 2π (t − t_c)(f_inst − f_r), (J,)
    q_mean: float                     # q̄ = mean of (t − t_c)² over the block (s²)
    b_max: float
    b2_max: float
    s_max: float
    t_max: float
    s32: NDArray[np.float32]          # s and t in single precision, for complex64 transforms
    t32: NDArray[np.float32]

    @classmethod
    def of(cls, sweep: _Sweep, tx: int, m0: int, m1: int) -> _Targets:
        """The targets, computed once per sweep, Tx and block (every pair and frame)."""
        key = (tx, m0, m1)
        with sweep.lock:
            hit = sweep.targets.get(key)
        if hit is None:
            hit = cls._make(sweep, tx, m0, m1)
            with sweep.lock:
                if len(sweep.targets) > 64:
                    sweep.targets.clear()
                sweep.targets[key] = hit
        return hit

    @classmethod
    def _make(cls, sweep: _Sweep, tx: int, m0: int, m1: int) -> _Targets:
        times = sweep.starts[m0:m1, tx][:, None] + sweep.t_n[None, :]
        t_c = 0.5 * float(times[0, 0] + times[-1, -1])
        u = times - t_c
        q = u * u
        q_mean = float(q.mean())
        f = np.broadcast_to(sweep.f_inst, u.shape)
        b = (_TWO_PI * f * (q - q_mean)).ravel()
        b2 = (_TWO_PI * u * (f - sweep.f_r)).ravel()
        s, t = (_TWO_PI * (f - sweep.f_r)).ravel(), (_TWO_PI * f * u).ravel()
        out = cls(t_c=t_c, half=0.5 * float(times[-1, -1] - times[0, 0]), s=s, t=t,
                  b=b, b2=b2, q_mean=q_mean, b_max=float(np.abs(b).max()),
                  b2_max=float(np.abs(b2).max()), s_max=float(np.abs(s).max()),
                  t_max=float(np.abs(t).max()), s32=s.astype(np.float32),
                  t32=t.astype(np.float32))
        for arr in (out.s, out.t, out.b, out.b2, out.s32, out.t32):
            arr.setflags(write=False)
        return out


#: Fit nodes of a block, in units of its half-duration U from its centre: the parabola goes
#: through nodes 0, 2, 4; the others measure the model's error.
_NODES = np.array([-1.0, -0.5, 0.0, 0.5, 1.0])
#: With an exact trajectory (possibly with kinks): four more check nodes.
_NODES_FINE = np.array([-1.0, -0.5, 0.0, 0.5, 1.0, -0.75, -0.25, 0.25, 0.75])


@dataclass(frozen=True)
class _Motion:
    """Where the moving scatterers are: their motion model, or an exact trajectory."""

    prep: PreparedScatterers
    trajectory: Trajectory | None = None

    @property
    def nodes(self) -> NDArray[np.float64]:
        return _NODES if self.trajectory is None else _NODES_FINE

    def positions(self, idx: NDArray[np.intp], times: NDArray[np.float64]
                  ) -> NDArray[np.float64]:
        """Positions of prepared rows ``idx`` at ``times``, shape (3, T, len(idx)) (m)."""
        prep = self.prep
        if self.trajectory is not None:
            pos = np.asarray(self.trajectory(times), dtype=np.float64)      # (M, T, 3)
            return np.ascontiguousarray(pos[prep.order[idx]].transpose(2, 1, 0))
        t = times[None, :, None]
        out = prep.pos[:, None, idx] + prep.vel[:, None, idx] * t
        if prep.accelerates:
            out += 0.5 * prep.acc[:, None, idx] * (t * t)
        return out


def _series_order(a: NDArray[np.float64], eps: NDArray[np.float64] | float
                  ) -> NDArray[np.int8]:
    """Smallest ``P`` with ``a^(P+1) / (P+1)! ≤ eps`` (MAX_SERIES_ORDER + 1 if none)."""
    order = np.zeros(a.shape, dtype=np.int8)
    term = a.copy()
    for p in range(1, MAX_SERIES_ORDER + 2):
        above = term > eps
        if not above.any():
            break
        order += above
        term *= a
        term /= p + 1
    return order


def _direct_chirp(sweep: _Sweep, positions: NDArray[np.float64], p_t: NDArray[np.float64],
                  p_r: NDArray[np.float64], weights: NDArray[np.complex128]
                  ) -> NDArray[np.complex128]:
    """Literal sum over scatterers for one chirp: ``Σ_k w_k e^{j(2π f_inst τ − πKτ²)}``.

    ``positions`` has shape (3, N, B) (one row per axis, then samples, then scatterers).
    """
    tau = (_distance(positions, p_t) + _distance(positions, p_r)) / SPEED_OF_LIGHT
    phase = _TWO_PI * sweep.f_inst[:, None] * tau - np.pi * sweep.slope * tau * tau
    return np.asarray(np.exp(1j * phase) @ weights, dtype=np.complex128)


@dataclass(frozen=True)
class _Fit:
    """Delay model of scatterers over one block (module docstring); arrays of shape (B,)."""

    tau: NDArray[np.float64]          # delay at the block centre (s)
    beta: NDArray[np.float64]         # delay rate (s/s)
    alpha: NDArray[np.float64]        # curvature coefficient of 2π f_inst u² (s/s²)
    gamma: NDArray[np.float64]        # coefficient Kτβ/f_r of b2 (s)
    cross: NDArray[np.bool_]          # the first-order γ term is added
    order: NDArray[np.int8]           # series length P
    ok: NDArray[np.bool_]             # model within the budget


def _fit(path: NDArray[np.float64], nodes: NDArray[np.float64], tg: _Targets, sweep: _Sweep
         ) -> _Fit:
    """Fit ``L(t_c + u) ≈ L₀ + L₁ u + L₂ u²/2`` to path lengths at ``t_c + U·nodes``.

    The parabola goes through the block's ends and centre; its largest deviation at the
    other nodes (±U/2, and ±U/4, ±3U/4 for a trajectory), ×1.5, which bounds a cubic or
    quartic remainder over the whole block, is the geometric model error. Added to it: the
    terms of ``−πKτ²`` folded approximately into the sources (``docs/physics_radar.md``).
    A scatterer is within the model when that error is at most ``eps_model`` and a series
    of at most :data:`MAX_SERIES_ORDER` terms brings the curvature within what is left of
    ``eps``.
    """
    n = path.shape[1]
    tau, beta, alpha, gamma = (np.empty(n) for _ in range(4))
    cross, ok = np.empty(n, dtype=bool), np.empty(n, dtype=bool)
    order = np.empty(n, dtype=np.int8)
    fit_delays(np.ascontiguousarray(path), nodes, tg.half, SPEED_OF_LIGHT, sweep.slope,
               sweep.f_r, sweep.f_max, sweep.rel_df, sweep.eps, sweep.eps_model, tg.b_max,
               tg.b2_max, MAX_SERIES_ORDER, tau, beta, alpha, gamma, cross, order, ok)
    return _Fit(tau=tau, beta=beta, alpha=alpha, gamma=gamma, cross=cross, order=order, ok=ok)


def _transform(fit: _Fit, sel: NDArray[np.intp], w0: NDArray[np.complex128], tg: _Targets,
               sweep: _Sweep) -> NDArray[np.complex128]:
    """IF of the scatterers ``sel`` of a fit at the block's targets, shape (J,).

    One type-3 transform of ``w e^{j(s x + t y)}`` with ``x = τ + α q̄``,
    ``y = β (1 − Kτ/f_r)``, ``w = a e^{j(φ + 2π f_r x − πKτ²)}``, plus the curvature series
    ``Σ_q (jα)^q/q! b^q`` (q = 1 … P) and, where needed, ``jγ b2``: extra vectors with the
    same points, in the main call when most scatterers need them or they are few (a call
    has a fixed cost of ≈ 5 ms), else in one more call over those that do, at the looser
    tolerance their small size allows.
    """
    x, y, phase = np.empty(len(sel)), np.empty(len(sel)), np.empty(len(sel))
    transform_points(fit.tau, fit.alpha, fit.beta, sel.astype(np.int64, copy=False),
                     tg.q_mean, sweep.slope, sweep.f_r, x, y, phase)
    points = _Points.of(x, y, tg, sweep)
    w = w0[sel] * _phasors(phase, single=points.single)
    alpha = fit.alpha[sel]
    order, cross = fit.order[sel], fit.cross[sel]
    needs = (order > 0) | cross
    n_needs = int(np.count_nonzero(needs))
    if not n_needs:
        return points.transform(w, sweep.eps_nufft, tg)
    merge = len(sel) <= MERGE_SERIES_POINTS or n_needs > 0.7 * len(sel)
    part = np.arange(len(sel)) if merge else np.flatnonzero(needs)
    # Rows 0 … P−1: the curvature series, term q+1 at most a^(q+1)/(q+1)! of the main one;
    # row P: the first-order γ term. A tolerance of (eps/2) / max(a, g) does for all.
    p_max = int(order.max())
    n_cross = int(cross.any())
    ia = 1j * alpha[part]
    coef = np.zeros((p_max + n_cross, len(part)), dtype=np.complex128)
    if p_max:
        coef[0] = w[part] * ia
        for q in range(1, p_max):
            coef[q] = coef[q - 1] * ia / (q + 1)
    size = float(np.abs(alpha[part]).max()) * tg.b_max
    if n_cross:
        gamma = np.where(cross[part], fit.gamma[sel[part]], 0.0)
        coef[p_max] = w[part] * 1j * gamma
        size = max(size, float(np.abs(gamma).max()) * tg.b2_max)
    if merge:
        f = points.transform(np.concatenate([w[None], coef]), sweep.eps_nufft, tg)
        blk, f = f[0], f[1:]
    else:
        blk = points.transform(w, sweep.eps_nufft, tg)
        eps = min(max(sweep.eps_nufft, 0.5 * sweep.eps / max(size, 1e-300)),
                  SERIES_NUFFT_TOLERANCE)
        eps = 10.0 ** np.floor(np.log10(eps))           # few distinct plans per thread
        f = points.transform(coef if len(coef) > 1 else coef[0], eps, tg,
                             part=part).reshape(len(coef), -1)
    corr = np.zeros_like(blk)
    for q in range(p_max - 1, -1, -1):                  # Horner in b
        corr = (corr + f[q]) * tg.b
    if n_cross:
        corr += f[p_max] * tg.b2
    return blk + corr


def _phasors(phase: NDArray[np.float64], *, single: bool) -> NDArray[np.complexfloating]:
    """``e^{j phase}`` for phases in [−π, π]; in float32 for single-precision transforms.

    numpy's float32 sine and cosine are vectorised (≈ 10× faster than float64 here); their
    error, a few 1e-8 at these arguments, is that of the complex64 weights themselves.
    """
    p = phase.astype(np.float32) if single else phase
    out: NDArray[np.complexfloating] = np.empty(len(p), dtype=np.complex64 if single
                                                else np.complex128)
    np.cos(p, out=out.real)
    np.sin(p, out=out.imag)
    return out


@dataclass(frozen=True)
class _Points:
    """The sources of a block's type-3 calls, in the precision its budget allows.

    Single precision (complex64, ≈ 2× faster) where its rounding,
    :data:`SINGLE_ROUNDING_PER_RAD` × the phase span of the centred points, is within half
    the per-scatterer budget ``ε``; double precision otherwise. Single-precision points are
    centred in double precision first, and the centre's phase ``e^{j(s x_c + t y_c)}`` is
    put back on the outputs in double precision: the rounding scales with the points'
    spread (the range bins they span), not with their distance.
    """

    x: NDArray[np.float64] | NDArray[np.float32]
    y: NDArray[np.float64] | NDArray[np.float32]
    single: bool
    shift: NDArray[np.complex128] | None

    @classmethod
    def of(cls, x: NDArray[np.float64], y: NDArray[np.float64], tg: _Targets,
           sweep: _Sweep) -> _Points:
        x_lo, x_hi, y_lo, y_hi = float(x.min()), float(x.max()), float(y.min()), float(y.max())
        span = 0.5 * (tg.s_max * (x_hi - x_lo) + tg.t_max * (y_hi - y_lo))
        if SINGLE_ROUNDING_PER_RAD * span > 0.5 * sweep.eps:
            return cls(x=x, y=y, single=False, shift=None)
        x_c, y_c = 0.5 * (x_lo + x_hi), 0.5 * (y_lo + y_hi)
        return cls(x=(x - x_c).astype(np.float32), y=(y - y_c).astype(np.float32),
                   single=True, shift=np.exp(1j * (tg.s * x_c + tg.t * y_c)))

    def transform(self, weights: NDArray[np.complex128], eps: float, tg: _Targets,
                  part: NDArray[np.intp] | None = None) -> NDArray[np.complex128]:
        """Type-3 transform of ``weights`` ((J,) or (n, J) out) from the points ``part``."""
        plan = _plan3(1 if weights.ndim == 1 else len(weights), eps, single=self.single)
        x, y = (self.x, self.y) if part is None else (self.x[part], self.y[part])
        if self.single:
            plan.setpts(x, y, None, tg.s32, tg.t32)
            out = plan.execute(weights.astype(np.complex64)).astype(np.complex128)
        else:
            plan.setpts(x, y, None, tg.s, tg.t)
            out = np.asarray(plan.execute(weights), dtype=np.complex128)
        if self.shift is not None:
            out *= self.shift
        return out


def _moving_block(motion: _Motion, idx: NDArray[np.intp], w0: NDArray[np.complex128],
                  pair: tuple[int, NDArray[np.float64], NDArray[np.float64]],
                  m0: int, m1: int, sweep: _Sweep, out: NDArray[np.complex128],
                  path: NDArray[np.float64] | None = None) -> None:
    """Add the IF of moving scatterers ``idx`` over chirps ``m0 … m1−1`` of one pair to ``out``.

    The scatterers within the delay model of the block (:func:`_fit`) are transformed
    (:func:`_transform`); the others go to the two halves of the block, or to the direct
    sum when they are few (:data:`DIRECT_MAX_TERMS`) or the block is a single chirp.

    Parameters
    ----------
    idx : ndarray of int, shape (B,)
        Prepared rows.
    w0 : ndarray, shape (B,), complex128
        Frame-constant amplitudes ``a_k e^{jφ_k}`` for this pair (FS).
    pair : (int, ndarray (3,), ndarray (3,))
        Tx index, Tx position and Rx position (m); or each (3, B), one per scatterer.
    out : ndarray, shape (chirps, samples), complex128
        This pair's IF, added to.
    path : ndarray, shape (5, B), optional
        Path lengths at the block's fit nodes, if the caller has them (m).
    """
    if not len(idx):
        return
    tx, p_t, p_r = pair
    tg = _Targets.of(sweep, tx, m0, m1)
    if path is None:
        pos = motion.positions(idx, tg.t_c + tg.half * motion.nodes)
        path = _distance(pos, p_t) + _distance(pos, p_r)
    fit = _fit(path, motion.nodes, tg, sweep)
    sel = np.flatnonzero(fit.ok)
    n_blk = m1 - m0
    if len(sel):
        out[m0:m1] += _transform(fit, sel, w0, tg, sweep).reshape(n_blk, -1)
    rest = np.flatnonzero(~fit.ok)
    if not len(rest):
        return
    p_t, p_r = _rows_of(p_t, rest), _rows_of(p_r, rest)
    if n_blk > 1 and len(rest) * tg.s.size > DIRECT_MAX_TERMS:
        mid = (m0 + m1) // 2
        _moving_block(motion, idx[rest], w0[rest], (tx, p_t, p_r), m0, mid, sweep, out)
        _moving_block(motion, idx[rest], w0[rest], (tx, p_t, p_r), mid, m1, sweep, out)
        return
    for m in range(m0, m1):
        times = sweep.starts[m, tx] + sweep.t_n
        out[m] += _direct_chirp(sweep, motion.positions(idx[rest], times), p_t, p_r,
                                w0[rest])


def _frame_amplitudes(prep: PreparedScatterers, rows: slice, t: int, r: int,
                      config: RadarConfig, wave: _Waveform, d_t: NDArray[np.float64],
                      d_r: NDArray[np.float64]) -> NDArray[np.complex128]:
    """``a_k e^{jφ_k}`` of one pair: radar equation × high-pass at the frame start (FS).

    ``d_t``, ``d_r`` are the distances to the Tx and the Rx at the frame start (m); float32
    arithmetic as for static scatterers.
    """
    g_t = prep.gain(config.tx[t].pattern or config.element_pattern)[rows]
    g_r = prep.gain(config.rx[r].pattern or config.element_pattern)[rows]
    amp = if_amplitude_fs(config, prep.rcs[rows], g_t, g_r, d_t.astype(np.float32),
                          d_r.astype(np.float32))
    ph = prep.phase[rows].astype(np.float32)
    cos, sin = np.cos(ph), np.sin(ph)
    out = np.empty(len(amp), dtype=np.complex128)
    if wave.filtered:
        h_re, h_im = _highpass32(wave, d_t + d_r)
        a_re, a_im = amp * h_re, amp * h_im
        out.real = cos * a_re - sin * a_im
        out.imag = sin * a_re + cos * a_im
    else:
        out.real = cos * amp
        out.imag = sin * amp
    return out


def _moving_task(motion: _Motion, rows: slice, t: int, rxs: Sequence[int], sweep: _Sweep,
                 wave: _Waveform, config: RadarConfig, antennas: _Antennas
                 ) -> list[NDArray[np.complex128]]:
    """One block of moving scatterers, one Tx, the Rx ``rxs``: the IF over all chirps.

    The path lengths at the frame's fit nodes come from one compiled pass per Rx
    (:func:`~simcore.sensors.radar.path_kernel.path_lengths`), or, for a trajectory, from
    positions computed once for all Rx in cache-sized chunks; the transforms then take the
    whole block at once (their fixed cost is paid once per block and pair).

    Returns
    -------
    list of ndarray, shape (chirps, samples)
        One per Rx of ``rxs``.
    """
    n_c = config.chirps_per_frame
    idx = np.arange(rows.start, rows.stop)
    tg = _Targets.of(sweep, t, 0, n_c)
    times = np.concatenate([[0.0], tg.t_c + tg.half * motion.nodes])
    p_t, p_rx = _rows_of(antennas[0][t], rows), [_rows_of(p, rows) for p in antennas[1]]
    per_row = p_t.ndim == 2
    d0_t = np.empty(len(idx))
    d0_r = np.empty((len(rxs), len(idx)))
    path = np.empty((len(rxs), len(times) - 1, len(idx)))
    if motion.trajectory is None:
        prep = motion.prep
        for j, r in enumerate(rxs):
            if per_row:     # the rows' own antennas, indexed from row 0
                path_lengths_rows(prep.pos, prep.vel, prep.acc, prep.accelerates,
                                  rows.start, rows.stop, times, antennas[0][t],
                                  antennas[1][r], path[j], d0_t, d0_r[j])
            else:
                path_lengths(prep.pos, prep.vel, prep.acc, prep.accelerates, rows.start,
                             rows.stop, times, np.ascontiguousarray(p_t),
                             np.ascontiguousarray(p_rx[r]), path[j], d0_t, d0_r[j])
    else:
        # A trajectory returns every scatterer at each call: call it once per block.
        pos = motion.positions(idx, times)                             # (3, T, b)
        d_t = _distance(pos, p_t)
        d0_t[:] = d_t[0]
        for j, r in enumerate(rxs):
            d_r = _distance(pos, p_rx[r])
            d0_r[j] = d_r[0]
            np.add(d_t[1:], d_r[1:], out=path[j])
    outs = []
    for j, r in enumerate(rxs):
        out = np.zeros((n_c, config.samples_per_chirp), dtype=np.complex128)
        w0 = _frame_amplitudes(motion.prep, rows, t, r, config, wave, d0_t, d0_r[j])
        _moving_block(motion, idx, w0, (t, p_t, p_rx[r]), 0, n_c, sweep, out, path=path[j])
        outs.append(out)
    return outs


# --------------------------------------------------------------------------- entry points
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


#: One task: (moving?, scatterer rows, Tx, its Rx).
_Task = tuple[bool, slice, int, tuple[int, ...]]


def antenna_positions(config: RadarConfig, tx_positions_m: NDArray[np.floating] | None,
                      rx_positions_m: NDArray[np.floating] | None) -> _Antennas:
    """Tx and Rx positions of a synthesis: the config's, or the caller's overrides.

    An override must have one row per Tx (Rx) of ``config``, shape (n, 3), radar optical
    frame (m); the image method of :mod:`simcore.sensors.radar.multipath` passes mirrored
    antennas. Anything else than finite numbers of that shape is refused.
    """
    out = []
    for name, given, default in (("tx_positions_m", tx_positions_m, config.tx_positions_m),
                                 ("rx_positions_m", rx_positions_m, config.rx_positions_m)):
        want = default()
        if given is None:
            out.append(want)
            continue
        arr = np.asarray(given, dtype=np.float64)
        if arr.shape != want.shape or not np.all(np.isfinite(arr)):
            raise ValueError(f"{name} must be finite with shape {want.shape}, got "
                             f"shape {arr.shape}")
        out.append(arr)
    return out[0], out[1]


def synthesize_if(scatterers: Scatterers, config: RadarConfig, *, threads: int | None = None,
                  prepared: PreparedScatterers | None = None,
                  trajectory: Trajectory | None = None,
                  tx_positions_m: NDArray[np.floating] | None = None,
                  rx_positions_m: NDArray[np.floating] | None = None) -> ComplexCube:
    """Noise-free complex IF of all scatterers with finufft (fast path).

    Static scatterers (no velocity or acceleration relative to the radar) are transformed
    once per Tx–Rx pair and broadcast over the chirps; moving ones by one 2-D type-3
    transform per pair over all its chirps and samples, with the exact linear-delay model,
    a curvature series and a per-scatterer fallback to shorter blocks (module docstring,
    ``docs/physics_radar.md``). Blocks of :data:`BLOCK` scatterers run as independent
    tasks on ``threads`` threads; their results are summed in a fixed order, so the output
    does not depend on ``threads``.

    Parameters
    ----------
    scatterers : Scatterers
        Point scatterers in the radar frame, with their motion over the frame.
    config : RadarConfig
        Waveform, antennas, gains, IF high-pass and ``nufft_tolerance``: the transforms'
        tolerance and, at least :data:`MOTION_TOLERANCE_FLOOR`, the per-scatterer budget
        of the moving-scatterer model.
    threads : int, optional
        Worker threads (default :data:`DEFAULT_THREADS`; 1 runs on the calling thread).
    prepared : PreparedScatterers, optional
        ``prepare(scatterers)``, when the caller keeps it (otherwise made here).
    trajectory : callable, optional
        ``times_s (T,) → positions (M, T, 3)``: exact radar-frame positions of all the
        scatterers at times after the frame start (m), when their motion over the frame is
        not the model ``x + v t + a t²/2`` (a keyframed path that turns a corner within the
        frame). Every scatterer is then treated as moving, the model is fitted to the
        trajectory block by block and checked at more nodes; it is called with a few times
        per block and returns all the scatterers each time, so it suits small sets.
    tx_positions_m, rx_positions_m : ndarray, shape (n_tx, 3) and (n_rx, 3), optional
        Antenna positions used for the path lengths (delays and spreading) instead of
        ``config.tx_positions_m()`` / ``rx_positions_m()``, radar optical frame (m): the
        image method's mirrored antennas. The element patterns are still evaluated in the
        direction of each scatterer from the array origin.

    Returns
    -------
    ndarray, shape (chirps, tx*rx, samples), complex128
        ``y`` of the module docstring in FS; the real IF is its real part. Channel
        ``t * n_rx + r`` is Tx ``t`` with Rx ``r``.
    """
    check_wavelength(scatterers, config)
    antennas = antenna_positions(config, tx_positions_m, rx_positions_m)
    if len(scatterers) == 0:
        return _zeros(config)
    if prepared is None:
        prepared = prepare(scatterers)
    elif prepared.source is not scatterers:
        raise ValueError("prepared belongs to another Scatterers object; use prepare(scatterers)")
    return _synthesize(prepared, config, antennas, threads, trajectory)


def _zeros(config: RadarConfig) -> ComplexCube:
    return np.zeros((config.chirps_per_frame, len(config.tx) * len(config.rx),
                     config.samples_per_chirp), dtype=np.complex128)


def synthesize_if_sets(sets: Sequence[tuple[Scatterers, NDArray[np.floating] | None,
                                            NDArray[np.floating] | None]],
                       config: RadarConfig, *, threads: int | None = None) -> ComplexCube:
    """The sum of :func:`synthesize_if` over scatterer sets, each with its own antennas.

    ``sets`` holds ``(scatterers, tx_positions_m, rx_positions_m)`` (the overrides of
    :func:`synthesize_if`, None for the configuration's). Every set's rows keep their own
    antenna positions (path lengths, spreading and delay model row by row, as in their own
    call), and all the sets share one transform per Tx–Rx pair: a type-3 transform costs
    ≈ 1–2 ms at the frame's 8192 targets whatever its number of points, so the image
    method's dozens of small ghost sets (one per reflector and path) cost about one. The
    result equals the sum of the separate calls within the transforms' tolerance (their
    rounding: the points share one grid, in one precision).

    Returns
    -------
    ndarray, shape (chirps, tx*rx, samples), complex128
        As :func:`synthesize_if`; zeros when the sets are empty.
    """
    sets = [s for s in sets if len(s[0])]
    if not sets:
        return _zeros(config)
    for sc, _, _ in sets:
        check_wavelength(sc, config)
    if len(sets) == 1:
        sc, tx, rx = sets[0]
        return synthesize_if(sc, config, threads=threads, tx_positions_m=tx,
                             rx_positions_m=rx)
    merged = Scatterers.concatenate([sc for sc, _, _ in sets])
    prep = prepare(merged)
    sizes = np.array([len(sc) for sc, _, _ in sets])
    tx0, rx0 = antenna_positions(config, None, None)
    given = ([tx0 if tx is None else antenna_positions(config, tx, None)[0] for _, tx, _ in sets],
             [rx0 if rx is None else antenna_positions(config, None, rx)[1] for _, _, rx in sets])
    # (n, 3, M): each set's antennas repeated over its rows, in prepared order.
    per_row = [np.ascontiguousarray(np.repeat(np.stack(g, axis=2), sizes, axis=2)[:, :, prep.order])
               for g in given]
    return _synthesize(prep, config, (per_row[0], per_row[1]), threads, None)


def _synthesize(prep: PreparedScatterers, config: RadarConfig, antennas: _Antennas,
                threads: int | None, trajectory: Trajectory | None) -> ComplexCube:
    """:func:`synthesize_if` of prepared scatterers with the antennas of the synthesis."""
    n_tx, n_rx = len(config.tx), len(config.rx)
    out = _zeros(config)
    if trajectory is not None:
        prep = dataclasses.replace(prep, n_static=0)
    motion = _Motion(prep, trajectory)
    wave = _Waveform.of(config)
    sweep = _Sweep.of(config)

    all_rx = tuple(range(n_rx))
    tasks: list[_Task] = []
    for lo in range(0, prep.n_static, BLOCK):
        rows = slice(lo, min(lo + BLOCK, prep.n_static))
        tasks.extend((False, rows, t, all_rx) for t in range(n_tx))
    n_threads = DEFAULT_THREADS if threads is None else max(1, int(threads))
    # Moving scatterers: as few tasks as keep the threads busy (each type-3 transform has a
    # fixed cost of ≈ 2 ms at its 8192 targets, whatever its number of points): one per
    # block of rows and Tx–Rx pair (a trajectory: per Tx, its positions serve every Rx).
    step = max(BLOCK, -(-(len(prep) - prep.n_static) // n_threads))
    rx_groups = [all_rx] if trajectory is not None else [(r,) for r in all_rx]
    for lo in range(prep.n_static, len(prep), step):
        rows = slice(lo, min(lo + step, len(prep)))
        tasks.extend((True, rows, t, rxs) for t in range(n_tx) for rxs in rx_groups)

    def run(task: _Task) -> list[NDArray[np.complexfloating]]:
        moves, rows, t, rxs = task
        if moves:
            return list(_moving_task(motion, rows, t, rxs, sweep, wave, config, antennas))
        return _static_task(prep, rows, t, wave, config, antennas)

    results: Iterator[list[NDArray[np.complexfloating]]]
    if n_threads == 1 or len(tasks) == 1:
        results = map(run, tasks)
    else:
        results = _pool(n_threads).map(run, tasks)
    for (_, _, t, rxs), ys in zip(tasks, results, strict=True):
        for r, y in zip(rxs, ys, strict=True):
            out[:, t * n_rx + r] += y   # (N,) broadcasts over the chirps
    return out


def synthesize_if_direct(scatterers: Scatterers, config: RadarConfig, *,
                         chirps: NDArray[np.integer] | None = None, chunk: int = 512,
                         trajectory: Trajectory | None = None,
                         tx_positions_m: NDArray[np.floating] | None = None,
                         rx_positions_m: NDArray[np.floating] | None = None) -> ComplexCube:
    """Noise-free complex IF by the literal sum over scatterers and samples (reference).

    Every sample of every chirp and Tx–Rx pair takes the scatterers' exact positions at its
    own time ``t = T_mt + t_n`` and sums ``a_k exp(j (2π (f_c + K t_n) τ(t) − π K τ(t)²
    + φ_k))``; the amplitudes ``a_k`` (radar equation, element patterns, high-pass) are
    those of the positions at the frame start. Costs O(chirps · tx · rx · M · samples);
    use it on small scenes or a few chirps.

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
    trajectory : callable, optional
        ``times_s (T,) → positions (M, T, 3)``: exact radar-frame positions at times after
        the frame start (m); default the scatterers' motion model
        (:meth:`Scatterers.positions_at`).
    tx_positions_m, rx_positions_m : ndarray, optional
        Antenna position overrides, as in :func:`synthesize_if`.

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
    traj: Callable[[NDArray[np.floating]], NDArray[np.float64]] = (
        scatterers.positions_at if trajectory is None else trajectory)
    x0 = scatterers.positions_m
    p_tx, p_rx = antenna_positions(config, tx_positions_m, rx_positions_m)
    g_tx, g_rx = pattern_gains(config, x0)
    f_inst = config.start_frequency_hz + config.slope_hz_per_s * t_n
    slope = config.slope_hz_per_s
    starts = config.chirp_start_times_s()
    amp = np.empty((n_tx, n_rx, len(x0)), dtype=np.complex128)
    for t in range(n_tx):
        for r in range(n_rx):
            r_t = np.linalg.norm(x0 - p_tx[t], axis=1)
            r_r = np.linalg.norm(x0 - p_rx[r], axis=1)
            h = if_filter_response(slope * (r_t + r_r) / SPEED_OF_LIGHT, config)
            amp[t, r] = (if_amplitude_fs(config, scatterers.rcs_m2, g_tx[t], g_rx[r], r_t, r_r)
                         * h * np.exp(1j * scatterers.phase_rad))
    for i, m in enumerate(idx):
        for t in range(n_tx):
            x = np.asarray(traj(starts[m, t] + t_n), dtype=np.float64)   # (M, N, 3)
            for r in range(n_rx):
                acc = np.zeros(len(t_n), dtype=np.complex128)
                for lo in range(0, len(x0), chunk):
                    k = slice(lo, lo + chunk)
                    r_t = np.sqrt(np.sum((x[k] - p_tx[t]) ** 2, axis=-1))
                    r_r = np.sqrt(np.sum((x[k] - p_rx[r]) ** 2, axis=-1))
                    tau = (r_t + r_r) / SPEED_OF_LIGHT                      # (chunk, N)
                    ph = 2 * np.pi * f_inst[None, :] * tau - np.pi * slope * tau**2
                    acc += amp[t, r, k] @ np.exp(1j * ph)
                out[i, t * n_rx + r] = acc
    return out


__all__ = [
    "BLOCK", "BOLTZMANN", "DEFAULT_THREADS", "MAX_SERIES_ORDER", "MOTION_TOLERANCE_FLOOR",
    "R_REF_OHM", "SINGLE_PRECISION_TOLERANCE", "T0_K", "ComplexCube", "PreparedScatterers",
    "SynthesisMethod", "amplitude_scale_fs", "antenna_positions", "check_wavelength",
    "element_gain", "highpass_response", "if_amplitude_fs", "leakage_amplitude_fs", "leakage_if",
    "noise_std_fs", "prepare", "quantize", "receiver_chain", "receiver_noise",
    "synthesize_if", "synthesize_if_direct", "synthesize_if_sets",
]
