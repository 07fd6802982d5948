"""Receiver chain: Tx→Rx leakage, receiver noise, IF high-pass on the noise, ADC.

See ``docs/physics_radar.md`` section 4. All values in FS (fractions of the ADC full scale).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from simcore.scene.radar_config import SPEED_OF_LIGHT, RadarConfig
from simcore.sensors.radar.equation import (
    highpass_response,
    leakage_amplitude_fs,
    noise_std_fs,
)

ComplexCube = NDArray[np.complex128]


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


__all__ = ["leakage_if", "quantize", "receiver_chain", "receiver_noise"]
