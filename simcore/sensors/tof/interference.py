"""ToF–ToF interference of continuous-wave (AMCW) cameras: the correlation term, pure.

A pixel of the victim camera correlates the light it receives with its own reference at
modulation frequency ``f_v`` over the exposure ``T``; four phase steps ``ψ_k = kπ/2``
give the phasor ``Σ_k I_k e^{j ψ_k}``. An aggressor camera's light, modulated at ``f_a``
and lagging the victim's clock by ``θ`` (``1 + cos(2π f_a (t − L/c) − θ)``), arriving over
a path of length ``L`` (its emitter → scene → this pixel, or straight into the lens when
the cameras face each other) adds

    ``A_a · e^{j (2π f_a L / c + θ)} · (1/T) ∫_overlap e^{j 2π (f_v − f_a) t} dt``

to the victim's phasor ``A_v e^{j 4π f_v d / c}``:

* same frequency (``f_a = f_v``): the phasors add, ``A_v e^{jφ_v} + A_a e^{jφ_a}``, so the
  measured phase, and the depth, are biased toward the aggressor's path;
* different frequencies: the cross term is scaled by the average of ``e^{-j 2π Δf t}``
  (``Δf = f_a − f_v``) over the overlap, ``|·| ≤ 1 / (π |Δf| T)`` (zero when ``Δf T`` is
  an integer); the aggressor's photons still add shot noise;
* time multiplexing (exposures that do not overlap): no cross term and no photons.

The sum-frequency term ``f_a + f_v`` (at most ``A_a / (π (f_a + f_v) T)``, negligible for
exposures of many modulation periods) is dropped. ``overlap_fraction`` is the part of
the victim's exposure the aggressor illuminates.
Radar (60 GHz) and ToF (850 nm, MHz modulation) do not disturb each other: neither
detector responds to the other's carrier (docs/interference.md).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from simcore.scene.tof_config import SPEED_OF_LIGHT


def cross_correlation_factor(victim_frequency_hz: float, aggressor_frequency_hz: float, *,
                             exposure_s: float, overlap_fraction: float = 1.0) -> complex:
    """Average of ``e^{-j 2π Δf t}``, ``Δf = f_a − f_v``, over the overlapping exposure.

    ``(1/T) ∫_0^{ρT} e^{-j 2π Δf t} dt`` with ``ρ = overlap_fraction``: ``ρ`` for equal
    frequencies, ``ρ e^{-jπΔfρT} sinc(Δf ρ T)`` otherwise (``sinc(x) = sin(πx)/(πx)``).
    """
    if not 0.0 <= overlap_fraction <= 1.0:
        raise ValueError(f"overlap_fraction = {overlap_fraction}; allowed [0, 1]")
    span = overlap_fraction * exposure_s
    x = (aggressor_frequency_hz - victim_frequency_hz) * span
    return complex(overlap_fraction * np.exp(-1j * np.pi * x) * np.sinc(x))


def path_phase_rad(frequency_hz: ArrayLike, path_m: ArrayLike) -> NDArray[np.float64]:
    """Modulation phase accumulated over a light path, ``2π f L / c`` (rad)."""
    return np.asarray(2.0 * np.pi * np.asarray(frequency_hz) * np.asarray(path_m)
                      / SPEED_OF_LIGHT, dtype=np.float64)


def interfered_phasor(own_amplitude: ArrayLike, own_path_m: ArrayLike,
                      aggressor_amplitude: ArrayLike, aggressor_path_m: ArrayLike, *,
                      victim_frequency_hz: float, aggressor_frequency_hz: float,
                      exposure_s: float, aggressor_phase_rad: float = 0.0,
                      overlap_fraction: float = 1.0) -> NDArray[np.complex128]:
    """The victim pixel's correlation phasor with an aggressor's light added.

    Parameters
    ----------
    own_amplitude, aggressor_amplitude : array_like, broadcastable
        Correlation amplitudes the two lights would give alone at equal frequencies.
    own_path_m, aggressor_path_m : array_like, broadcastable
        Light path lengths: victim emitter → scene → pixel (twice the depth when
        co-located), aggressor emitter → (scene →) pixel (m).
    victim_frequency_hz, aggressor_frequency_hz : float, keyword-only
        Modulation frequencies (Hz).
    exposure_s : float, keyword-only
        Victim exposure time (s).
    aggressor_phase_rad : float, keyword-only
        How far the aggressor's modulation lags the victim's clock (rad).
    overlap_fraction : float, keyword-only
        Part of the exposure the aggressor is on (0 with time multiplexing).

    Returns
    -------
    ndarray, complex128
        ``A_v e^{j 2π f_v L_v / c} + A_a e^{j (2π f_a L_a / c + θ)} · c(Δf, T, ρ)``.
    """
    own = np.asarray(own_amplitude) * np.exp(1j * path_phase_rad(victim_frequency_hz,
                                                                 own_path_m))
    c = cross_correlation_factor(victim_frequency_hz, aggressor_frequency_hz,
                                 exposure_s=exposure_s, overlap_fraction=overlap_fraction)
    agg = (np.asarray(aggressor_amplitude) * c
           * np.exp(1j * (path_phase_rad(aggressor_frequency_hz, aggressor_path_m)
                          + aggressor_phase_rad)))
    return np.asarray(own + agg, dtype=np.complex128)


def phasor_depth_m(phasor: ArrayLike, frequency_hz: float) -> NDArray[np.float64]:
    """Depth from a correlation phasor, ``c · arg / (4π f)`` wrapped to ``[0, c / 2f)`` (m)."""
    phase = np.mod(np.angle(np.asarray(phasor)), 2.0 * np.pi)
    return np.asarray(SPEED_OF_LIGHT * phase / (4.0 * np.pi * frequency_hz), dtype=np.float64)


def extra_shot_noise_variance(aggressor_intensity: ArrayLike, *, overlap_fraction: float = 1.0
                              ) -> NDArray[np.float64]:
    """Shot-noise variance the aggressor's photons add (in the units of the intensity).

    Poisson: each of the four phase images gains the aggressor's mean intensity (its
    DC part, whatever its frequency) over the overlap, and the variance equals the mean.
    """
    return np.asarray(overlap_fraction * np.asarray(aggressor_intensity), dtype=np.float64)


__all__ = [
    "cross_correlation_factor",
    "extra_shot_noise_variance",
    "interfered_phasor",
    "path_phase_rad",
    "phasor_depth_m",
]
