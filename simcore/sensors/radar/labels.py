"""Ground-truth labels of radar detections: which object put the power into a detection's cell.

For every detection (a range–Doppler cell with an estimated direction) the expected power
of every scatterer of the frame in that cell is

    P_k = A_k² · |W_r(δr_k)|² · |W_d(δv_k)|² · S(f_k) · B_k

with ``A_k = C √(σ_k ḡ_k) / R_k² · |H(f_b)|`` the scatterer's IF amplitude (radar equation
of :func:`~simcore.sensors.radar.synthesis.amplitude_scale_fs`, ``ḡ`` the element pattern
gains averaged over the Tx–Rx pairs, ``H`` the IF high-pass), ``W_r`` and ``W_d`` the
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
noise power the detection is noise (``object_id = −1``). The model ignores real-IF image
frequencies, range–Doppler coupling and motion within the frame (each a fraction of a bin).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np
from numpy.typing import NDArray

from simcore.dsp.angle import direction_vectors, virtual_array_positions_m
from simcore.dsp.detections import Detections
from simcore.dsp.processing import RadarAxes
from simcore.dsp.windows import make_window
from simcore.scene.dsp_config import DspConfig
from simcore.scene.radar_config import SPEED_OF_LIGHT, Antenna, RadarConfig
from simcore.sensors.radar.scatterers import Scatterers
from simcore.sensors.radar.synthesis import (
    amplitude_scale_fs,
    element_gain,
    highpass_response,
    noise_std_fs,
)

#: Oversampling of the tabulated window responses (table points per FFT bin).
OVERSAMPLING = 32
#: Scatterers per block of the (scatterers × detections) power matrix (bounds memory).
BLOCK = 16384


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
        Multipath ghost (always False: the simulator has no multipath yet).
    """

    object_id: NDArray[np.int32]
    power_fraction: NDArray[np.float32]
    ghost: NDArray[np.bool_]

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


def _noise_gain(name: str, length: int, sidelobe_db: float) -> float:
    """``Σw² / (Σw)²`` of a window: the noise power of an amplitude-normalised bin."""
    w = make_window(name, length, sidelobe_db=sidelobe_db).astype(np.float64)  # type: ignore[arg-type]
    return float(np.sum(w**2) / np.sum(w) ** 2)


def _mean_pair_gain(config: RadarConfig, directions: NDArray[np.float64]) -> NDArray[np.float64]:
    """Element power gain ``g_t g_r`` averaged over the Tx–Rx pairs, shape (M,)."""
    def gains(antennas: list[Antenna]) -> NDArray[np.float64]:
        return np.mean([element_gain(a.pattern or config.element_pattern, directions)
                        for a in antennas], axis=0)
    return np.asarray(gains(config.tx) * gains(config.rx), dtype=np.float64)


def label_detections(detections: Detections, scatterers: Scatterers, object_ids: NDArray[
        np.integer], radar_config: RadarConfig, dsp_config: DspConfig, axes: RadarAxes
                     ) -> DetectionLabels:
    """Attribute each detection to the object contributing most power to its cell.

    Parameters
    ----------
    detections : Detections
        The frame's detections (cells ``doppler_index``, ``range_index``; directions
        ``azimuth_deg``, ``elevation_deg``).
    scatterers : Scatterers
        Every scatterer of the frame (radar optical frame, m and m/s; ``object_index``
        into the project's objects).
    object_ids : ndarray, shape (objects,), int
        Project id of each object, in project order.
    radar_config : RadarConfig
        Waveform, antennas and receiver the cube was synthesised with.
    dsp_config : DspConfig
        The processing the detections come from (windows, FFT sizes, clutter filter).
    axes : RadarAxes
        Axes of the range–Doppler map (bin centres: m, m/s).

    Returns
    -------
    DetectionLabels
        One label per detection (module docstring for the model).
    """
    n = len(detections)
    if n == 0 or len(scatterers) == 0:
        return DetectionLabels.unlabelled(n)
    rc, dc = radar_config, dsp_config
    n_ch = len(rc.tx) * len(rc.rx)
    range_table = _window_power_table(dc.range_window, rc.samples_per_chirp,
                                      dc.range_window_sidelobe_db, axes.range_fft_size)
    doppler_table = _window_power_table(dc.doppler_window, rc.chirps_per_frame,
                                        dc.doppler_window_sidelobe_db, axes.doppler_fft_size)
    dr = SPEED_OF_LIGHT * rc.sample_rate_hz / (2.0 * rc.slope_hz_per_s * axes.range_fft_size)
    dv = float(axes.velocity_mps[1] - axes.velocity_mps[0]) if axes.velocity_mps.size > 1 else 1.0
    cell_range = axes.range_m[detections.range_index]
    cell_velocity = axes.velocity_mps[detections.doppler_index]
    a_det = np.exp(-2j * np.pi * (direction_vectors(
        np.deg2rad(detections.azimuth_deg), np.deg2rad(detections.elevation_deg))
        @ virtual_array_positions_m(rc).T) / rc.wavelength_m)  # (n, ch)

    noise = (4.0 if not rc.complex_iq else 2.0) * noise_std_fs(rc) ** 2 / n_ch
    noise *= _noise_gain(dc.range_window, rc.samples_per_chirp, dc.range_window_sidelobe_db)
    noise *= _noise_gain(dc.doppler_window, rc.chirps_per_frame, dc.doppler_window_sidelobe_db)

    n_objects = len(object_ids)
    per_object = np.zeros((n, n_objects + 1))  # last column: scatterers of no object
    for start in range(0, len(scatterers), BLOCK):
        s = scatterers.subset(slice(start, start + BLOCK))
        power = _cell_power(s, rc, dc, cell_range, cell_velocity, a_det, range_table,
                            doppler_table, dr, dv)  # (m, n)
        obj = np.where((s.object_index >= 0) & (s.object_index < n_objects),
                       s.object_index, n_objects)
        np.add.at(per_object.T, obj, power)
    total = per_object.sum(axis=1) + noise
    best = np.argmax(per_object[:, :n_objects], axis=1) if n_objects else np.zeros(n, int)
    best_power = per_object[np.arange(n), best] if n_objects else np.zeros(n)
    is_object = best_power > noise
    ids = np.asarray(object_ids, dtype=np.int32)
    object_id = np.where(is_object, ids[best] if n_objects else -1, -1).astype(np.int32)
    fraction = np.where(is_object, best_power / total, 0.0).astype(np.float32)
    return DetectionLabels(object_id, fraction, np.zeros(n, dtype=bool))


def _cell_power(s: Scatterers, rc: RadarConfig, dc: DspConfig,
                cell_range: NDArray[np.float64], cell_velocity: NDArray[np.float64],
                a_det: NDArray[np.complex128], range_table: NDArray[np.float64],
                doppler_table: NDArray[np.float64], dr: float, dv: float
                ) -> NDArray[np.float64]:
    """Expected power of scatterers ``s`` in each detection's cell, shape (M, n), FS²."""
    pos = s.positions_m
    r = np.maximum(np.linalg.norm(pos, axis=1), 1e-9)
    u = pos / r[:, None]
    v_radial = np.einsum("ij,ij->i", s.velocities_mps, u)
    beat_hz = 2.0 * rc.slope_hz_per_s * r / SPEED_OF_LIGHT
    hp = np.abs(highpass_response(beat_hz, rc.if_highpass_hz, rc.if_highpass_order)) ** 2 \
        if rc.if_highpass_hz else np.ones_like(r)
    amp2 = amplitude_scale_fs(rc) ** 2 * s.rcs_m2 * _mean_pair_gain(rc, pos) / r**4 * hp
    w_r = _lookup(range_table, (r[:, None] - cell_range[None, :]) / dr)
    w_d = _lookup(doppler_table, (v_radial[:, None] - cell_velocity[None, :]) / dv)
    if dc.static_clutter_removal:
        # Mean removal over the chirps: a tone at f cycles/chirp keeps 1 − |D_N(f)|².
        n_chirps = rc.chirps_per_frame
        f = v_radial * 2.0 * len(rc.tx) * rc.chirp_repetition_time_s / rc.wavelength_m
        with np.errstate(divide="ignore", invalid="ignore"):
            d = np.where(np.abs(np.sin(np.pi * f)) < 1e-12, 1.0,
                         np.sin(np.pi * n_chirps * f) / (n_chirps * np.sin(np.pi * f)))
        w_d = w_d * (1.0 - d**2)[:, None]
    a_s = np.exp(-2j * np.pi * (u @ virtual_array_positions_m(rc).T) / rc.wavelength_m)
    beam = np.abs(a_s @ a_det.conj().T) ** 2 / a_det.shape[1] ** 2  # (M, n)
    return np.asarray(amp2[:, None] * w_r * w_d * beam, dtype=np.float64)
