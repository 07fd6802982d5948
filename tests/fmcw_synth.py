"""Raw FMCW ADC cubes of moving point scatterers, built with numpy alone (no simcore.dsp).

The model is the one of DESIGN.md and ``tests/test_dsp.py``: for Tx ``j`` and Rx ``i`` the
exact two-way delay ``tau = (|X - p_tx| + |X - p_rx|) / c`` with the scatterer at ``X(t)``
at each chirp's true start time ``t = frame_time + (k n_tx + j) T_r``, and the IF sample
``a cos(2 pi f_c tau + 2 pi K tau t_n - pi K tau^2)`` (real IF) or ``a exp(j ...)`` (IQ).
Scatterers sit on the radar's boresight (optical +z) and move along it, so their range
``r(t)`` is all a test states: ``X(t) = (0, 0, r(t))``.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

import numpy as np

from simcore.scene.radar_config import SPEED_OF_LIGHT, RadarConfig

#: A scatterer: range over time (vectorised, m) and its IF amplitude (FS).
Scatterer = tuple[Callable[[np.ndarray], np.ndarray], float]


def synth_frames(rc: RadarConfig, scatterers: Sequence[Scatterer], frame_times_s: np.ndarray,
                 *, noise_std: float = 0.0, seed: int = 0) -> np.ndarray:
    """ADC cubes, shape (frames, chirps, tx*rx, samples), float32 (real IF) or complex64."""
    n_tx, n_rx = len(rc.tx), len(rc.rx)
    p_tx = np.array([[a.position_mm[0] * 1e-3, a.position_mm[1] * 1e-3, 0.0] for a in rc.tx])
    p_rx = np.array([[a.position_mm[0] * 1e-3, a.position_mm[1] * 1e-3, 0.0] for a in rc.rx])
    t_n = np.arange(rc.samples_per_chirp) / rc.sample_rate_hz
    slope, f_c = rc.bandwidth_hz / rc.chirp_time_s, rc.start_frequency_hz
    k = np.arange(rc.chirps_per_frame)
    frames = np.asarray(frame_times_s, dtype=np.float64)
    shape = (frames.size, rc.chirps_per_frame, n_tx * n_rx, rc.samples_per_chirp)
    out = np.zeros(shape, dtype=complex if rc.complex_iq else float)
    for range_of_t, amp in scatterers:
        for j in range(n_tx):
            t = frames[:, None] + ((k * n_tx + j) * rc.chirp_repetition_time_s)[None, :]
            r = range_of_t(t)                                    # (frames, chirps)
            x = np.stack([np.zeros_like(r), np.zeros_like(r), r], axis=-1)
            d_tx = np.linalg.norm(x - p_tx[j], axis=-1)
            for i in range(n_rx):
                tau = ((d_tx + np.linalg.norm(x - p_rx[i], axis=-1)) / SPEED_OF_LIGHT)[..., None]
                phase = (2 * np.pi * f_c * tau + 2 * np.pi * slope * tau * t_n
                         - np.pi * slope * tau**2)
                out[:, :, j * n_rx + i, :] += amp * (np.exp(1j * phase) if rc.complex_iq
                                                     else np.cos(phase))
    if noise_std:
        rng = np.random.default_rng(seed)
        if rc.complex_iq:
            out += noise_std / np.sqrt(2) * (rng.standard_normal(shape)
                                             + 1j * rng.standard_normal(shape))
        else:
            out += noise_std * rng.standard_normal(shape)
    return out.astype(np.complex64 if rc.complex_iq else np.float32)


def chirp_times(rc: RadarConfig, frame_times_s: np.ndarray) -> np.ndarray:
    """Start time of every chirp of Tx 0, shape (frames, chirps), s."""
    k = np.arange(rc.chirps_per_frame) * len(rc.tx) * rc.chirp_repetition_time_s
    return np.asarray(frame_times_s, dtype=np.float64)[:, None] + k[None, :]
