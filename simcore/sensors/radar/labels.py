"""Ground-truth labels of radar detections: which object put the power into a detection's cell.

For every detection (a range–Doppler cell with an estimated direction) the expected power
of every scatterer of the frame in that cell is

    P_k = A_k² · |W_r(δr_k)|² · |W_d(δv_k)|² · S(f_k) · B_k

with ``A_k = C √(σ_k ḡ_k) / R_k² · |H(f_b)|`` the scatterer's IF amplitude (radar equation
of :func:`~simcore.sensors.radar.equation.amplitude_scale_fs`, ``ḡ`` the element pattern
gains averaged over the Tx–Rx pairs, ``|H|² = x/(1+x)``, ``x = (f_b/f_c)^(2n)``, the
receiver's order-n Butterworth IF high-pass), ``W_r`` and ``W_d`` the
range- and Doppler-window responses (normalised to 1 at their peak, as the DSP's
amplitude-normalised spectra) at the scatterer's offset from the cell's centre in FFT bins
(Doppler offsets wrap), ``S`` the static-clutter filter (``1 − |D_N(f)|²``, ``D_N`` the
normalised Dirichlet kernel of ``N`` chirps at the Doppler frequency ``f`` in cycles per
chirp; 1 when the filter is off) and ``B_k = |a(u_det)ᴴ a(u_k)|² / N_ch²`` the Bartlett beam
response of the virtual array towards the detection's direction. The expected noise power of
the beam-formed cell is ``P_n = κ σ_n² (Σw_r²/(Σw_r)²) (Σw_d²/(Σw_d)²) / N_ch`` (``κ = 4`` for
real IF, ``2`` for IQ, ``σ_n`` the receiver noise per real channel).

A detection is labelled with the object whose scatterers sum to the most power, and
``power_fraction = P_object / (Σ_k P_k + P_n)``; when even that object's power is below the
noise power the detection is noise (``object_id = −1``). Multipath ghosts
(``ghosts=``) enter as further candidates: each object's ghost power (its scatterers at the
half bistatic path of the ghost's unfolded path, :func:`prepare_scatterers` with mirrored
antennas) competes with every object's direct power, and a detection won by a ghost is
labelled with that object's id and ``ghost`` True. The model ignores real-IF image
frequencies, range–Doppler coupling and motion within the frame (each a fraction of a bin),
and scatterers whose range offset from the cell puts them below ``RANGE_FLOOR`` of the
range window's peak (or more than ``MAX_RANGE_OFFSET_BINS`` bins away): the scatterers are
sorted by range once (:func:`prepare_scatterers`, kept across frames for a still
background), and each detection sums only those near its range.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from functools import lru_cache

import numpy as np
from numpy.typing import NDArray

from simcore.dsp.angle import direction_vectors, virtual_array_positions_m
from simcore.dsp.detections import Detections
from simcore.dsp.processing import RadarAxes
from simcore.dsp.windows import make_window
from simcore.jit import kernel
from simcore.scene.dsp_config import DspConfig
from simcore.scene.radar_config import SPEED_OF_LIGHT, Antenna, CosinePattern, RadarConfig
from simcore.sensors.radar.equation import (
    adc_noise_std_fs,
    amplitude_scale_fs,
    element_gain,
    noise_std_fs,
)
from simcore.sensors.radar.scatterers import Scatterers

#: Oversampling of the tabulated window responses (table points per FFT bin).
OVERSAMPLING = 32
#: Window power below which a scatterer's range offset from a cell is ignored (−70 dB).
RANGE_FLOOR = 1e-7
#: ... or beyond this many range-FFT bins, for windows whose sidelobes stay above it.
MAX_RANGE_OFFSET_BINS = 64


@dataclass(frozen=True)
class DetectionLabels:
    """Ground-truth labels of one frame's detections (same order as the detections).

    Attributes
    ----------
    object_id : ndarray, shape (n,), int32
        Project id of the object contributing most power to the detection's cell; −1 for
        noise (no object above the noise power).
    power_fraction : ndarray, shape (n,), float32
        That object's share of the cell's expected power (scatterers + noise), in [0, 1].
    ghost : ndarray, shape (n,), bool
        The power is that of the object's multipath ghost (a path via a specular
        reflector, :mod:`simcore.sensors.radar.multipath`), not of its direct return.
    object_index : ndarray, shape (n,), int32, or None
        Index of that object in the (engine's) project objects, −1 for noise; a person's
        segments are objects of their own there (its body part).
    """

    object_id: NDArray[np.int32]
    power_fraction: NDArray[np.float32]
    ghost: NDArray[np.bool_]
    object_index: NDArray[np.int32] | None = None

    def __len__(self) -> int:
        return int(self.object_id.size)

    @classmethod
    def unlabelled(cls, n: int) -> DetectionLabels:
        """``n`` detections labelled as noise."""
        return cls(np.full(n, -1, dtype=np.int32), np.zeros(n, dtype=np.float32),
                   np.zeros(n, dtype=bool))


@lru_cache(maxsize=16)
def _window_power_table(name: str, length: int, sidelobe_db: float, fft_size: int
                        ) -> NDArray[np.float64]:
    """``|W(δ)|²`` on ``fft_size * OVERSAMPLING`` offsets δ of one bin / OVERSAMPLING (peak 1)."""
    w = make_window(name, length, sidelobe_db=sidelobe_db).astype(np.float64)  # type: ignore[arg-type]
    spec = np.fft.fft(w, n=fft_size * OVERSAMPLING)
    table = np.abs(spec) ** 2 / float(np.sum(w)) ** 2
    table.setflags(write=False)
    return table


def _lookup(table: NDArray[np.float64], offset_bins: NDArray[np.float64]) -> NDArray[np.float64]:
    """Tabulated window power at offsets in FFT bins (periodic in the FFT length)."""
    idx = np.rint(offset_bins * OVERSAMPLING).astype(np.int64) % table.size
    return table[idx]


@lru_cache(maxsize=16)
def _noise_gain(name: str, length: int, sidelobe_db: float) -> float:
    """``Σw² / (Σw)²`` of a window: the noise power of an amplitude-normalised bin."""
    w = make_window(name, length, sidelobe_db=sidelobe_db).astype(np.float64)  # type: ignore[arg-type]
    return float(np.sum(w**2) / np.sum(w) ** 2)


def _mean_pair_gain(config: RadarConfig, directions: NDArray[np.float64]) -> NDArray[np.float64]:
    """Element power gain ``g_t g_r`` averaged over the Tx–Rx pairs, shape (M,)."""
    patterns = [a.pattern or config.element_pattern for a in (*config.tx, *config.rx)]
    if all(isinstance(p, CosinePattern) for p in patterns):
        exponents = np.array([(p.exponent_az, p.exponent_el) for p in patterns],  # type: ignore[union-attr]
                             dtype=np.float64)
        out = np.empty(len(directions))
        _cosine_pair_gain(np.ascontiguousarray(directions, dtype=np.float64), exponents,
                          len(config.tx), out)
        return out
    cache: dict[str, NDArray[np.float64]] = {}

    def gain(antenna: Antenna) -> NDArray[np.float64]:
        pattern = antenna.pattern or config.element_pattern
        key = pattern.model_dump_json()
        if key not in cache:
            cache[key] = element_gain(pattern, directions)
        return cache[key]

    g_tx = np.mean([gain(a) for a in config.tx], axis=0)
    g_rx = np.mean([gain(a) for a in config.rx], axis=0)
    return np.asarray(g_tx * g_rx, dtype=np.float64)


@kernel
def _cosine_pair_gain(d: NDArray[np.float64], exponents: NDArray[np.float64], n_tx: int,
                      out: NDArray[np.float64]) -> None:
    """:func:`_mean_pair_gain` for cosine patterns, one pass over the directions.

    ``exponents`` (n_tx + n_rx, 2): (az, el) exponents of the Tx, then the Rx elements.
    The gain of each element is :func:`~simcore.sensors.radar.equation.element_gain`'s
    ``max(cos az, 0)^a · max(cos el, 0)^b``, with ``cos az = z / √(x² + z²)`` and
    ``cos el = √(x² + z²) / |d|``; for ``a = b`` it is ``max(z / |d|, 0)^a``, one power
    instead of two (the same to a few ulp). Elements with the exponents of the one
    before share its value.
    """
    n_el = exponents.shape[0]
    n_rx = n_el - n_tx
    for i in range(out.size):
        x, y, z = d[i, 0], d[i, 1], d[i, 2]
        horiz_sq = x * x + z * z
        norm_sq = horiz_sq + y * y
        g_tx = 0.0
        g_rx = 0.0
        g = 0.0
        for e in range(n_el):
            a, b = exponents[e, 0], exponents[e, 1]
            if e == 0 or a != exponents[e - 1, 0] or b != exponents[e - 1, 1]:
                if a == b:
                    cos_both = z / math.sqrt(norm_sq) if norm_sq > 0 else 1.0
                    g = max(cos_both, 0.0) ** a
                else:
                    horiz = math.sqrt(horiz_sq)
                    cos_az = z / horiz if horiz > 0 else 1.0
                    cos_el = horiz / math.sqrt(norm_sq) if norm_sq > 0 else 1.0
                    g = max(cos_az, 0.0) ** a * cos_el ** b
            if e < n_tx:
                g_tx += g
            else:
                g_rx += g
        out[i] = (g_tx / n_tx) * (g_rx / n_rx)


@dataclass(frozen=True)
class LabelScatterers:
    """What each scatterer of a set brings to any detection cell, sorted by range.

    Depends only on the scatterers and the radar configuration, so the stage cache keeps it
    for a still background across frames. Built by :func:`prepare_scatterers`.

    Attributes
    ----------
    range_m : ndarray, shape (M,), float64
        Distance from the radar (m), ascending.
    velocity_mps : ndarray, shape (M,), float64
        Radial velocity (m/s, + = moving away).
    power : ndarray, shape (M,), float64
        Peak power in its own cell, ``A²`` (FS²; module docstring).
    steering : ndarray, shape (M, channels), complex64
        Virtual-array response towards the scatterer.
    object_index : ndarray, shape (M,), intp
        Index of its object in the project (−1: none).
    doppler_cycles : ndarray, shape (M,), float64
        Doppler frequency in cycles per chirp interval (for the static-clutter filter).
    """

    range_m: NDArray[np.float64]
    velocity_mps: NDArray[np.float64]
    power: NDArray[np.float64]
    steering: NDArray[np.complex64]
    object_index: NDArray[np.intp]
    doppler_cycles: NDArray[np.float64]

    def __len__(self) -> int:
        return int(self.range_m.size)


def prepare_scatterers(scatterers: Scatterers, radar_config: RadarConfig, *,
                       tx_positions_m: NDArray[np.floating] | None = None,
                       rx_positions_m: NDArray[np.floating] | None = None) -> LabelScatterers:
    """Per-scatterer terms of the cell power (radar equation, high-pass, array response).

    Parameters
    ----------
    scatterers : Scatterers
        Scatterers in the radar optical frame (m, m/s, m²).
    radar_config : RadarConfig
        Waveform, antennas and receiver.
    tx_positions_m, rx_positions_m : ndarray, shape (n, 3), optional
        Antenna positions that replace the configuration's, as in
        :func:`~simcore.sensors.radar.synthesis.synthesize_if` (the mirrored antennas of a
        multipath path). A scatterer's range is then half its bistatic path length from the
        antennas' centroids, its radial velocity the rate of that half length, the spreading
        ``1 / (R_t R_r)²`` and its array response the exact per-channel path phases.

    Returns
    -------
    LabelScatterers
        The scatterers sorted by range.
    """
    rc = radar_config
    if tx_positions_m is not None or rx_positions_m is not None:
        return _prepare_bistatic(scatterers, rc, tx_positions_m, rx_positions_m)
    pos = np.ascontiguousarray(scatterers.positions_m, dtype=np.float64)
    r = np.empty(len(pos))
    _ranges(pos, r)
    rank = np.empty(len(pos), dtype=np.int64)
    rank[_range_order(r)] = np.arange(len(pos))
    gain = _mean_pair_gain(rc, pos)
    n_ch = len(rc.tx) * len(rc.rx)
    out = LabelScatterers(np.empty(len(pos)), np.empty(len(pos)), np.empty(len(pos)),
                          np.empty((len(pos), n_ch), dtype=np.complex64),
                          np.empty(len(pos), dtype=np.intp), np.empty(len(pos)))
    _monostatic_terms(
        pos, np.ascontiguousarray(scatterers.velocities_mps, dtype=np.float64),
        np.ascontiguousarray(scatterers.rcs_m2, dtype=np.float64),
        np.ascontiguousarray(scatterers.object_index), gain, r, rank,
        np.ascontiguousarray(-2.0 * np.pi / rc.wavelength_m * virtual_array_positions_m(rc).T),
        amplitude_scale_fs(rc) ** 2, _filter_terms(rc),
        2.0 * len(rc.tx) * rc.chirp_repetition_time_s, rc.wavelength_m,
        out.range_m, out.velocity_mps, out.power, out.steering, out.object_index,
        out.doppler_cycles)
    return out


def _filter_terms(rc: RadarConfig) -> NDArray[np.float64]:
    """The IF filters for :func:`_filter_power`: (2K/c, f_hp, 2 n_hp, f_lp, 2 n_lp)."""
    return np.array([2.0 * rc.slope_hz_per_s, rc.if_highpass_hz, 2 * rc.if_highpass_order,
                     rc.if_lowpass_hz, 2 * rc.if_lowpass_order], dtype=np.float64)


@kernel
def _filter_power(r: float, terms: NDArray[np.float64]) -> float:
    """:func:`_receiver_response` of one range (``terms`` from :func:`_filter_terms`)."""
    out = 1.0
    if terms[1] > 0:
        x = _integer_power(terms[0] * r / SPEED_OF_LIGHT / terms[1], int(terms[2]))
        out *= x / (1.0 + x)
    if terms[3] > 0:
        x = _integer_power(terms[0] * r / SPEED_OF_LIGHT / terms[3], int(terms[4]))
        out /= 1.0 + x
    return out


@kernel
def _integer_power(x: float, n: int) -> float:
    """``x ** n`` for ``n >= 1`` by squaring (``x * x`` for ``n = 2``, as numpy's square)."""
    result = 1.0
    first = True
    while n > 0:
        if n & 1:
            result = x if first else result * x
            first = False
        n >>= 1
        if n:
            x = x * x
    return result


@kernel
def _ranges(pos: NDArray[np.float64], out: NDArray[np.float64]) -> None:
    """Distance of each position from the origin, at least 1 nm."""
    for i in range(out.size):
        x, y, z = pos[i, 0], pos[i, 1], pos[i, 2]
        # The order of numpy's einsum("ij,ij->i") over three columns: the same bits.
        out[i] = max(math.sqrt((x * x + z * z) + y * y), 1e-9)


@kernel
def _range_order(r: NDArray[np.float64]) -> NDArray[np.int64]:
    """Stable ascending order of ``r`` (as ``argsort(kind="stable")``) by a bucket sort.

    Scatterers spread over the ranges, so buckets of two on average need only insertion
    sorts; a crowded bucket (or non-finite ranges) falls back to a merge sort.
    """
    n = r.size
    lo = np.inf
    hi = -np.inf
    for i in range(n):
        lo = min(lo, r[i])
        hi = max(hi, r[i])
    if n < 2 or not (np.isfinite(lo) and np.isfinite(hi)) or hi == lo:
        return np.argsort(r, kind="mergesort")
    n_buckets = max(1, n // 2)
    scale = n_buckets / (hi - lo)
    bucket = np.empty(n, dtype=np.int64)
    start = np.zeros(n_buckets + 1, dtype=np.int64)
    for i in range(n):
        b = min(int((r[i] - lo) * scale), n_buckets - 1)
        bucket[i] = b
        start[b + 1] += 1
    for b in range(n_buckets):
        start[b + 1] += start[b]
    fill = start[:-1].copy()
    order = np.empty(n, dtype=np.int64)
    for i in range(n):
        b = bucket[i]
        order[fill[b]] = i
        fill[b] += 1
    for b in range(n_buckets):
        first, end = start[b], start[b + 1]
        if end - first > 32:
            seg = order[first:end].copy()
            order[first:end] = seg[np.argsort(r[seg], kind="mergesort")]
            continue
        for j in range(first + 1, end):
            item = order[j]
            key = r[item]
            t = j
            while t > first and r[order[t - 1]] > key:
                order[t] = order[t - 1]
                t -= 1
            order[t] = item
    return order


@kernel
def _monostatic_terms(pos: NDArray[np.float64], vel: NDArray[np.float64],
                      rcs: NDArray[np.float64], object_index: NDArray[np.integer],
                      gain: NDArray[np.float64], r: NDArray[np.float64],
                      rank: NDArray[np.int64], phase_per_m: NDArray[np.float64],
                      scale_sq: float, filters: NDArray[np.float64], cycle_time_s: float,
                      wavelength_m: float, out_range: NDArray[np.float64],
                      out_velocity: NDArray[np.float64], out_power: NDArray[np.float64],
                      out_steering: NDArray[np.complex64], out_object: NDArray[np.intp],
                      out_cycles: NDArray[np.float64]) -> None:
    """Fill the fields of :class:`LabelScatterers`, scatterer ``k`` into row ``rank[k]``.

    The formulas of the module docstring, in the order of operations of the numpy
    reference in ``tests/test_labels.py`` (the same numbers to a few ulp). The inputs are
    read in order and the rows written by rank: scattered writes cost less than
    scattered reads.
    """
    for k in range(rank.size):
        i = rank[k]
        rk = r[k]
        ux, uy, uz = pos[k, 0] / rk, pos[k, 1] / rk, pos[k, 2] / rk
        v = (vel[k, 0] * ux + vel[k, 2] * uz) + vel[k, 1] * uy
        out_range[i] = rk
        out_velocity[i] = v
        r_sq = rk * rk
        out_power[i] = scale_sq * rcs[k] * gain[k] / (r_sq * r_sq) * _filter_power(rk, filters)
        for c in range(out_steering.shape[1]):
            ph = np.float32(ux * phase_per_m[0, c] + uy * phase_per_m[1, c]
                            + uz * phase_per_m[2, c])
            out_steering[i, c] = complex(math.cos(ph), math.sin(ph))
        out_object[i] = object_index[k]
        out_cycles[i] = v * cycle_time_s / wavelength_m


def _receiver_response(rc: RadarConfig, r: NDArray[np.float64]) -> NDArray[np.float64]:
    """Power response of the IF filters at the beat frequency of (half path) range ``r``."""
    out = np.ones_like(r)
    if rc.if_highpass_hz > 0:
        # |H|² of the order-n Butterworth IF high-pass at the beat frequency.
        x = (2.0 * rc.slope_hz_per_s * r / SPEED_OF_LIGHT / rc.if_highpass_hz) ** (
            2 * rc.if_highpass_order)
        out *= x / (1.0 + x)
    if rc.if_lowpass_hz > 0:
        # |H|² of the anti-aliasing low-pass: 1 / (1 + (f_b / f_lp)^{2n}).
        x = (2.0 * rc.slope_hz_per_s * r / SPEED_OF_LIGHT / rc.if_lowpass_hz) ** (
            2 * rc.if_lowpass_order)
        out /= 1.0 + x
    return out


def _prepare_bistatic(scatterers: Scatterers, rc: RadarConfig,
                      tx_positions_m: NDArray[np.floating] | None,
                      rx_positions_m: NDArray[np.floating] | None) -> LabelScatterers:
    """:func:`prepare_scatterers` with antenna positions other than the configuration's."""
    p_tx = rc.tx_positions_m() if tx_positions_m is None else np.asarray(tx_positions_m,
                                                                          dtype=np.float64)
    p_rx = rc.rx_positions_m() if rx_positions_m is None else np.asarray(rx_positions_m,
                                                                          dtype=np.float64)
    m = len(scatterers)
    return _prepare_rows(scatterers, rc, *(
        (np.broadcast_to(p, (m, *p.shape)), np.broadcast_to(np.mean(p, axis=0), (m, 3)))
        for p in (p_tx, p_rx)))


def _prepare_rows(scatterers: Scatterers, rc: RadarConfig,
                  tx: tuple[NDArray[np.float64], NDArray[np.float64]],
                  rx: tuple[NDArray[np.float64], NDArray[np.float64]]) -> LabelScatterers:
    """:func:`_prepare_bistatic` with each row's own antennas.

    ``tx`` and ``rx``: the antenna positions of each row, (M, n, 3), and their centroid,
    (M, 3) (m).
    """
    pos = scatterers.positions_m
    legs = [pos - centroid for _, centroid in (tx, rx)]
    r_t, r_r = (np.maximum(np.linalg.norm(leg, axis=1), 1e-9) for leg in legs)
    r = 0.5 * (r_t + r_r)
    order = np.argsort(r, kind="stable")
    pos, r, r_t, r_r = pos[order], r[order], r_t[order], r_r[order]
    u_sum = legs[0][order] / r_t[:, None] + legs[1][order] / r_r[:, None]
    v_radial = 0.5 * np.einsum("ij,ij->i", scatterers.velocities_mps[order], u_sum)
    # The element patterns are those of the direct direction: a multipath set folds the
    # pattern ratio of its mirrored leg into its RCS (simcore.sensors.radar.multipath).
    power = amplitude_scale_fs(rc) ** 2 * scatterers.rcs_m2[order] * _mean_pair_gain(rc, pos)
    power /= (r_t * r_r) ** 2
    power *= _receiver_response(rc, r)
    d_tx = np.linalg.norm(pos[:, None, :] - tx[0][order], axis=2)          # (M, n_tx)
    d_rx = np.linalg.norm(pos[:, None, :] - rx[0][order], axis=2)          # (M, n_rx)
    path = (d_tx[:, :, None] + d_rx[:, None, :]).reshape(len(pos), -1) - 2.0 * r[:, None]
    # The IF phase is +2π f_c τ (synthesis), so the steering is exp(+j 2π/λ · Δpath).
    steering = np.exp(2j * np.pi / rc.wavelength_m * path).astype(np.complex64)
    cycles = v_radial * 2.0 * len(rc.tx) * rc.chirp_repetition_time_s / rc.wavelength_m
    return LabelScatterers(r, v_radial, power, steering,
                           scatterers.object_index[order].astype(np.intp), cycles)


def prepare_scatterer_sets(sets: Sequence[tuple[Scatterers, NDArray[np.floating] | None,
                                                NDArray[np.floating] | None]],
                           radar_config: RadarConfig) -> list[LabelScatterers]:
    """:func:`prepare_scatterers` of several sets, each with its antennas, as few as possible.

    ``sets`` holds ``(scatterers, tx_positions_m, rx_positions_m)`` (None: the
    configuration's). A detection cell's power is a sum over scatterers
    (:func:`cell_power_by_object`), so the sets with the configuration's antennas are
    prepared as one, and those with antennas of their own as another, each row with its
    set's antennas (the same terms row by row as one call per set; the multipath ghosts'
    dozens of small sets cost one call each otherwise).

    Returns
    -------
    list of LabelScatterers
        At most two.
    """
    sets = [s for s in sets if len(s[0])]
    own = [s for s in sets if s[1] is not None or s[2] is not None]
    plain = [s[0] for s in sets if s[1] is None and s[2] is None]
    out = [prepare_scatterers(Scatterers.concatenate(plain), radar_config)] if plain else []
    if len(own) == 1:
        out.append(prepare_scatterers(own[0][0], radar_config, tx_positions_m=own[0][1],
                                      rx_positions_m=own[0][2]))
    elif own:
        rows = []
        for k, default in ((1, radar_config.tx_positions_m()), (2, radar_config.rx_positions_m())):
            given = [default if s[k] is None else np.asarray(s[k], dtype=np.float64) for s in own]
            sizes = [len(s[0]) for s in own]
            rows.append((np.concatenate([np.broadcast_to(p, (n, *p.shape))
                                         for p, n in zip(given, sizes, strict=True)]),
                         np.concatenate([np.broadcast_to(np.mean(p, axis=0), (n, 3))
                                         for p, n in zip(given, sizes, strict=True)])))
        out.append(_prepare_rows(Scatterers.concatenate([s[0] for s in own]), radar_config,
                                 rows[0], rows[1]))
    return out


def cell_power_by_object(prepared: LabelScatterers, detections: Detections, n_objects: int,
                         radar_config: RadarConfig, dsp_config: DspConfig, axes: RadarAxes
                         ) -> NDArray[np.float64]:
    """Expected power of each object's scatterers in each detection's cell.

    Parameters
    ----------
    prepared : LabelScatterers
        The scatterers (:func:`prepare_scatterers`).
    detections : Detections
        The detections (cells and directions).
    n_objects : int
        Number of project objects.
    radar_config, dsp_config : RadarConfig, DspConfig
        The configurations the detections were made with.
    axes : RadarAxes
        Axes of the range–Doppler map.

    Returns
    -------
    ndarray, shape (n, n_objects + 1), float64
        Power (FS², beam-formed cell) per detection and object; the last column holds the
        scatterers of no object.
    """
    return _DetectionCells.of(detections, radar_config, dsp_config, axes).power_by_object(
        prepared, n_objects)


@dataclass(frozen=True)
class _DetectionCells:
    """What :func:`cell_power_by_object` needs of the detections, for any scatterer set."""

    cell_range: NDArray[np.float64]
    cell_velocity: NDArray[np.float64]
    a_det_conj: NDArray[np.complex64]         # (n, ch): conjugated beam steering
    range_table: NDArray[np.float64]
    doppler_table: NDArray[np.float64]
    dr: float
    dv: float
    reach_m: float
    n_chirps: int
    clutter_filter: bool

    @classmethod
    def of(cls, detections: Detections, rc: RadarConfig, dc: DspConfig, axes: RadarAxes
           ) -> _DetectionCells:
        """The cells, beams and window tables of ``detections``."""
        range_table = _window_power_table(dc.range_window, rc.samples_per_chirp,
                                          dc.range_window_sidelobe_db, axes.range_fft_size)
        doppler_table = _window_power_table(dc.doppler_window, rc.chirps_per_frame,
                                            dc.doppler_window_sidelobe_db,
                                            axes.doppler_fft_size)
        dr = SPEED_OF_LIGHT * rc.sample_rate_hz / (2.0 * rc.slope_hz_per_s
                                                   * axes.range_fft_size)
        dv = (float(axes.velocity_mps[1] - axes.velocity_mps[0])
              if axes.velocity_mps.size > 1 else 1.0)
        reach_m = _range_window_reach_bins(dc.range_window, rc.samples_per_chirp,
                                           dc.range_window_sidelobe_db,
                                           axes.range_fft_size) * dr
        a_det = np.exp(-2j * np.pi * (direction_vectors(
            np.deg2rad(detections.azimuth_deg), np.deg2rad(detections.elevation_deg))
            @ virtual_array_positions_m(rc).T) / rc.wavelength_m).astype(np.complex64)
        return cls(axes.range_m[detections.range_index],
                   axes.velocity_mps[detections.doppler_index],
                   np.ascontiguousarray(a_det.conj()), range_table, doppler_table, dr, dv,
                   reach_m, rc.chirps_per_frame, dc.static_clutter_removal)

    def power_by_object(self, prepared: LabelScatterers, n_objects: int
                        ) -> NDArray[np.float64]:
        """:func:`cell_power_by_object` of one scatterer set."""
        n = self.cell_range.size
        out = np.zeros((n, n_objects + 1))
        if n == 0 or len(prepared) == 0:
            return out
        keep = (_clutter_filter(prepared.doppler_cycles, self.n_chirps)
                if self.clutter_filter else np.zeros(0))
        bounds = np.empty((n, 2), dtype=np.int64)
        bounds[:, 0] = np.searchsorted(prepared.range_m, self.cell_range - self.reach_m)
        bounds[:, 1] = np.searchsorted(prepared.range_m, self.cell_range + self.reach_m)
        n_ch = self.a_det_conj.shape[1]
        _cell_powers(prepared.range_m, prepared.velocity_mps, prepared.power,
                     np.ascontiguousarray(prepared.steering), prepared.object_index, keep,
                     bounds, self.cell_range, self.cell_velocity, self.a_det_conj,
                     self.range_table, self.doppler_table, self.dr, self.dv,
                     float(n_ch**2), out)
        return out


@kernel
def _wrap(i: int, n: int) -> int:
    """``i % n`` (non-negative), without a division for ``-n <= i < n``."""
    if i < 0:
        i += n
    if 0 <= i < n:
        return i
    return i % n


@kernel
def _cell_powers(range_m: NDArray[np.float64], velocity_mps: NDArray[np.float64],
                 power: NDArray[np.float64], steering: NDArray[np.complex64],
                 object_index: NDArray[np.intp], keep: NDArray[np.float64],
                 bounds: NDArray[np.int64], cell_range: NDArray[np.float64],
                 cell_velocity: NDArray[np.float64], a_det_conj: NDArray[np.complex64],
                 range_table: NDArray[np.float64], doppler_table: NDArray[np.float64],
                 dr: float, dv: float, n_ch_sq: float, out: NDArray[np.float64]) -> None:
    """Add each near scatterer's power in each detection's cell to its object's column.

    The column is the scatterer's ``object_index``; the last one (``out.shape[1] − 1``)
    takes those of no object (−1, or beyond the project's objects).

    Detection ``j`` sums the scatterers ``bounds[j, 0] <= k < bounds[j, 1]``: power ×
    range- and Doppler-window power (tabulated, :func:`_lookup`) × beam response
    ``|a_k · conj(a_det)|² / N_ch²`` × ``keep[k]`` (the clutter filter; none when
    ``keep`` is empty), in the order of ``k``, as the ``bincount`` of the numpy reference
    in ``tests/test_labels.py``.
    """
    n_r = range_table.size
    n_d = doppler_table.size
    n_objects = out.shape[1] - 1
    for j in range(bounds.shape[0]):
        for k in range(bounds[j, 0], bounds[j, 1]):
            i_r = _wrap(int(np.rint((range_m[k] - cell_range[j]) / dr * OVERSAMPLING)), n_r)
            i_d = _wrap(int(np.rint((velocity_mps[k] - cell_velocity[j]) / dv * OVERSAMPLING)),
                        n_d)
            beam = np.complex64(0)
            for c in range(steering.shape[1]):
                beam += steering[k, c] * a_det_conj[j, c]
            p = power[k] * range_table[i_r]
            p *= doppler_table[i_d]
            p *= (float(beam.real) ** 2 + float(beam.imag) ** 2) / n_ch_sq
            if keep.size:
                p *= keep[k]
            obj = object_index[k]
            out[j, obj if 0 <= obj < n_objects else n_objects] += p


def _clutter_filter(cycles: NDArray[np.float64], n_chirps: int) -> NDArray[np.float64]:
    """Power kept by mean removal over ``n_chirps`` chirps: ``1 − |D_N(f)|²``."""
    sin_f = np.sin(np.pi * cycles)
    small = np.abs(sin_f) < 1e-12
    d = np.where(small, 1.0, np.sin(np.pi * n_chirps * cycles)
                 / (n_chirps * np.where(small, 1.0, sin_f)))
    return np.asarray(1.0 - d**2, dtype=np.float64)


def label_detections(detections: Detections, scatterers: Scatterers | Sequence[
        tuple[LabelScatterers, float]], object_ids: NDArray[np.integer],
                     radar_config: RadarConfig, dsp_config: DspConfig, axes: RadarAxes,
                     ghosts: Sequence[LabelScatterers] = ()) -> DetectionLabels:
    """Attribute each detection to the object contributing most power to its cell.

    Parameters
    ----------
    detections : Detections
        The frame's detections (cells ``doppler_index``, ``range_index``; directions
        ``azimuth_deg``, ``elevation_deg``).
    scatterers : Scatterers, or sequence of (LabelScatterers, float)
        Every scatterer of the frame (radar optical frame, m and m/s; ``object_index``
        into the project's objects); or prepared sets with signs whose signed sum is the
        frame's (a still background + the frame's facets − the background's hidden ones).
    object_ids : ndarray, shape (objects,), int
        Project id of each object, in project order.
    radar_config : RadarConfig
        Waveform, antennas and receiver the cube was synthesised with.
    dsp_config : DspConfig
        The processing the detections come from (windows, FFT sizes, clutter filter).
    axes : RadarAxes
        Axes of the range–Doppler map (bin centres: m, m/s).
    ghosts : sequence of LabelScatterers
        The frame's multipath ghosts (:func:`prepare_scatterers` of each path set, with its
        mirrored antennas). The power of an object's ghosts competes with the direct power
        of every object; a detection whose largest share is a ghost's gets that object's
        id and ``ghost`` True.

    Returns
    -------
    DetectionLabels
        One label per detection (module docstring for the model).
    """
    n = len(detections)
    rc, dc = radar_config, dsp_config
    parts = ([(prepare_scatterers(scatterers, rc), 1.0)] if isinstance(scatterers, Scatterers)
             else list(scatterers))
    if n == 0:
        return DetectionLabels.unlabelled(n)
    n_objects = len(object_ids)
    cells = _DetectionCells.of(detections, rc, dc, axes)
    per_object = np.zeros((n, n_objects + 1))
    for prepared, sign in parts:
        per_object += sign * cells.power_by_object(prepared, n_objects)
    per_object = np.maximum(per_object, 0.0)
    per_ghost = np.zeros_like(per_object)
    for prepared in ghosts:
        per_ghost += cells.power_by_object(prepared, n_objects)

    n_ch = len(rc.tx) * len(rc.rx)
    sigma2 = noise_std_fs(rc) ** 2 + adc_noise_std_fs(rc) ** 2   # + noise after the filters
    noise = (4.0 if not rc.complex_iq else 2.0) * sigma2 / n_ch
    noise *= _noise_gain(dc.range_window, rc.samples_per_chirp, dc.range_window_sidelobe_db)
    noise *= _noise_gain(dc.doppler_window, rc.chirps_per_frame, dc.doppler_window_sidelobe_db)
    total = per_object.sum(axis=1) + per_ghost.sum(axis=1) + noise
    ids = np.asarray(object_ids, dtype=np.int32)
    if n_objects == 0:
        return DetectionLabels.unlabelled(n)
    # Columns: each object's direct power, then each object's ghost power.
    candidates = np.concatenate([per_object[:, :n_objects], per_ghost[:, :n_objects]], axis=1)
    best = np.argmax(candidates, axis=1)
    best_power = candidates[np.arange(n), best]
    is_object = best_power > noise
    object_id = np.where(is_object, ids[best % n_objects], -1).astype(np.int32)
    fraction = np.divide(best_power, total, out=np.zeros(n), where=is_object & (total > 0))
    fraction = fraction.astype(np.float32)
    index = np.where(is_object, best % n_objects, -1).astype(np.int32)
    return DetectionLabels(object_id, fraction, is_object & (best >= n_objects), index)


def _range_reach_bins(range_table: NDArray[np.float64]) -> float:
    """Largest range offset (FFT bins) where the window power reaches ``RANGE_FLOOR``."""
    half = range_table[: range_table.size // 2]
    above = np.flatnonzero(half >= RANGE_FLOOR)
    reach = (above.max() + 1) / OVERSAMPLING if above.size else 1.0
    return float(min(reach, MAX_RANGE_OFFSET_BINS))


@lru_cache(maxsize=16)
def _range_window_reach_bins(name: str, length: int, sidelobe_db: float, fft_size: int
                             ) -> float:
    """:func:`_range_reach_bins` of :func:`_window_power_table` ``(name, length, …)``."""
    return _range_reach_bins(_window_power_table(name, length, sidelobe_db, fft_size))
