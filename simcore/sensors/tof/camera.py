"""AMCW Time-of-Flight camera model: render buffers → correlation samples → depth.

The chain, per frame (equations and limits in ``docs/physics_tof.md``):

1. Per render sub-pixel, the mean signal electrons of one correlation sample
   ``S = S₁ f / R²`` (``S₁`` = :attr:`TofCameraConfig.signal_electrons_at_1m`, ``f`` the
   ToF-band material response including the incidence angle, ``R`` the range; the camera
   is the illuminator), the ambient electrons ``B = B₁ f`` and the phase
   ``φ = 4π f_mod R / c``.
2. Four correlation samples ``C_i = S (1 + m cos(φ + iπ/2)) + B`` — i.e.
   ``A/2 cos(φ + iπ/2) + offset`` with ``A = 2 m S`` — averaged over the sub-pixels of each
   sensor pixel *before* the phase is estimated (flying pixels at depth edges).
3. Cross-talk: a radially symmetric Gaussian of σ = ``crosstalk_sigma_px`` on the four
   correlation images.
4. Noise (optional): shot noise of variance ``C_i`` (e⁻), read noise, ADC quantisation.
5. Saturation: a sample at or above the full well (or the ADC's top code) makes the pixel
   invalid; samples are clipped there.
6. ``φ̂ = atan2(C3 − C1, C0 − C2)``, ``d̂ = c φ̂ / (4π f_mod)`` in ``[0, c/(2 f_mod))``,
   amplitude ``√((C3 − C1)² + (C0 − C2)²)``; too dark (amplitude below
   ``min_amplitude_dn``) or saturated → invalid, depth 0.
7. With two or three modulation frequencies, the wrapped depths are unwrapped jointly
   (:func:`unwrap_two_frequencies`, :func:`unwrap_frequencies`).

Partial transmission (optional, a ``see_through`` render): where the first surface of a
sub-pixel transmits (a glass pane, :func:`slab_transmittance`), the surface the
see-through render shows behind it adds its own return, times the two-way power
transmission ``T²``, to the pane's return as a phasor before the phase is estimated.

Dtype policy: sub-pixel phases are computed in float64 (cheap, and the phase of a 37 m
range needs more than float32's 7 digits to stay well under a millimetre); every
sensor-resolution image is float32, whose rounding (≤ 1e-7 relative) is far below the
1 cm depth budget.
"""

from __future__ import annotations

import cmath
import dataclasses
import math
import threading
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from math import gcd

import numpy as np
from numpy.typing import NDArray
from scipy.ndimage import gaussian_filter

from simcore.jit import kernel
from simcore.render.buffers import RenderBuffers, downsample_ground_truth
from simcore.scene.camera import PinholeIntrinsics
from simcore.scene.materials import BandMaterial
from simcore.scene.tof_config import SPEED_OF_LIGHT, TofCameraConfig
from simcore.sensors.tof.interference import Illuminator, interference_planes
from simcore.sensors.tof.multipath import (
    RECEIVER_STEP,
    OneBounceCache,
    one_bounce_image,
    senders_from_render,
)
from simcore.sensors.tof.optics import (
    distort_buffers,
    distort_image,
    stray_light,
    vignetting,
    wiggling_planes,
)
from simcore.sensors.tof.radiosity import Room
from simcore.sensors.tof.room_cache import room_indirect
from simcore.sensors.tof.specular import specular_paths

#: Float dtype of every sensor-resolution ToF image.
FLOAT = np.float32
#: Ranges below this are treated as this (m), to keep 1/R² finite.
MIN_RANGE_M = 1e-3


def as_float(values: NDArray[np.floating]) -> NDArray[np.float32]:
    """Cast to the ToF model's image dtype (float32, see the module docstring)."""
    return np.asarray(values, dtype=FLOAT)


def unambiguous_range_m(frequency_hz: float) -> float:
    """Unambiguous range ``c / (2 f)`` of one modulation frequency (m)."""
    return SPEED_OF_LIGHT / (2.0 * frequency_hz)


@dataclass(frozen=True)
class TofOutput:
    """One frame of the ToF camera, all images at sensor resolution (H, W).

    Attributes
    ----------
    depth_m : ndarray, shape (H, W), float32
        Measured radial distance along each pixel's ray (m); 0 where not ``valid``.
        Wrapped into ``[0, c/(2 f1))`` with one frequency, unwrapped into
        ``[0, c/(2 gcd(f1, f2)))`` with two.
    amplitude : ndarray, shape (H, W), float32
        Demodulated amplitude ``√((C3 − C1)² + (C0 − C2)²)`` of the first frequency (DN).
    intensity : ndarray, shape (H, W), float32
        Grey value: mean of the four correlation samples of the first frequency (DN),
        signal plus ambient light.
    valid : ndarray, shape (H, W), bool
        Neither saturated nor too dark (at every modulation frequency).
    saturated : ndarray, shape (H, W), bool
        A correlation sample reached the full well or the ADC's top code.
    correlation : ndarray, shape (4, H, W), float32
        The four raw correlation samples ``C0..C3`` of the first frequency (DN), axis 0
        is the phase step ``i`` of ``cos(φ + iπ/2)``.
    gt_range : ndarray, shape (H, W), float32
        Ground-truth range (m), NaN where no surface.
    gt_object_id : ndarray, shape (H, W), int32
        Ground-truth object id, −1 where no surface.
    gt_body_part : ndarray, shape (H, W), int32, or None
        Ground-truth body part (segment index of :data:`simcore.scene.people.SEGMENTS`)
        where a person is seen, −1 elsewhere; None in scenes without people.
    exposure_time_s : float
        Exposure time of each correlation sample in this frame (s): the configured one, or
        auto-exposure's choice.
    """

    depth_m: NDArray[np.float32]
    amplitude: NDArray[np.float32]
    intensity: NDArray[np.float32]
    valid: NDArray[np.bool_]
    saturated: NDArray[np.bool_]
    correlation: NDArray[np.float32]
    gt_range: NDArray[np.float32]
    gt_object_id: NDArray[np.int32]
    exposure_time_s: float = 0.0
    gt_body_part: NDArray[np.int32] | None = None

    def hdf5_items(self) -> dict[str, tuple[NDArray[np.generic], str]]:
        """Per-frame datasets of the HDF5 layout: path → (array without frame axis, unit)."""
        items: dict[str, tuple[NDArray[np.generic], str]] = {
            "/tof/depth": (self.depth_m, "m"),
            "/tof/amplitude": (self.amplitude, "DN"),
            "/tof/intensity": (self.intensity, "DN"),
            "/tof/valid": (self.valid, "1"),
            "/tof/correlation": (self.correlation, "DN"),
            "/tof/gt_range": (self.gt_range, "m"),
            "/tof/gt_object_id": (self.gt_object_id, "1"),
            "/tof/exposure_time": (np.asarray(self.exposure_time_s, dtype=np.float64), "s"),
        }
        if self.gt_body_part is not None:
            items["/tof/gt_body_part"] = (self.gt_body_part, "1")
        return items


def _block_mean(image: NDArray[np.floating], factor: int) -> NDArray[np.floating]:
    """Mean over ``factor × factor`` blocks: shape (H·k, W·k) → (H, W), same dtype."""
    if factor == 1:
        return image
    # Summing the k² strided views is several times faster than reshape(...).mean(axis).
    total = image[0::factor, 0::factor].copy()
    for i in range(factor):
        for j in range(factor):
            if i or j:
                total += image[i::factor, j::factor]
    total *= total.dtype.type(1.0 / factor**2)
    return total


def _crosstalk(images: NDArray[np.float32], sigma_px: float) -> NDArray[np.float32]:
    """Gaussian cross-talk over the last two axes of ``images`` (…, H, W)."""
    if sigma_px <= 0:
        return images
    sigma = (0.0,) * (images.ndim - 2) + (sigma_px, sigma_px)
    return as_float(gaussian_filter(images, sigma=sigma, mode="reflect"))


def _read_out(correlation_e: NDArray[np.float32], config: TofCameraConfig, *,
              rng: np.random.Generator, noise: bool,
              suppressed: NDArray[np.float32] | None = None
              ) -> tuple[NDArray[np.float32], NDArray[np.bool_]]:
    """Noise, saturation and ADC of the correlation samples.

    Parameters
    ----------
    correlation_e : ndarray, shape (4, H, W), float32
        Noise-free correlation samples (e⁻).
    suppressed : ndarray, shape (H, W), optional
        Background suppression: ambient electrons removed from every sample after the
        noise (:attr:`TofCameraConfig.background_suppression`).

    Returns
    -------
    correlation_dn : ndarray, shape (4, H, W), float32
        Read-out samples (DN), clipped to ``[0, adc_max_dn]``; quantised when ``noise``.
    saturated : ndarray, shape (H, W), bool
        Some sample reached the full well or the ADC's top code.
    """
    c = correlation_e
    if noise:
        # Shot noise (Poisson, Gaussian approximation: variance = mean e⁻) and read noise.
        std = np.sqrt(np.maximum(c, 0.0) + FLOAT(config.read_noise_electrons) ** 2)
        c = as_float(c + std * rng.standard_normal(c.shape, dtype=FLOAT))
    if suppressed is not None:
        # SBI: the pixel drains the mean ambient charge before it fills the well; the
        # ambient light's shot noise (added above) stays.
        c = as_float(c - suppressed)
    full_well = FLOAT(config.full_well_electrons)
    saturated = np.any(c >= full_well, axis=0)
    dn = np.minimum(c, full_well) * FLOAT(config.conversion_gain_dn_per_electron)
    if noise:
        dn = np.round(dn)
    adc_max = FLOAT(config.adc_max_dn)
    saturated |= np.any(dn >= adc_max, axis=0)
    return as_float(np.clip(dn, 0.0, adc_max)), saturated


def _demodulate(correlation: NDArray[np.float32], frequency_hz: float
                ) -> tuple[NDArray[np.float32], NDArray[np.float32]]:
    """Four-phase demodulation.

    Parameters
    ----------
    correlation : ndarray, shape (4, H, W)
        ``C_i = A/2 cos(φ + iπ/2) + offset``.
    frequency_hz : float
        Modulation frequency.

    Returns
    -------
    depth : ndarray, shape (H, W), float32
        ``c φ̂ / (4π f)`` wrapped into ``[0, c/(2f))`` (m).
    amplitude : ndarray, shape (H, W), float32
        ``√((C3 − C1)² + (C0 − C2)²)`` (= A, units of ``correlation``).
    """
    num = correlation[3] - correlation[1]      # A sin φ
    den = correlation[0] - correlation[2]      # A cos φ
    phase = np.mod(np.arctan2(num, den), FLOAT(2 * np.pi))
    max_range = unambiguous_range_m(frequency_hz)
    depth = phase * FLOAT(max_range / (2 * np.pi))
    depth = np.where(depth >= FLOAT(max_range), FLOAT(0.0), depth)
    return as_float(depth), as_float(np.hypot(num, den))


def unwrap_two_frequencies(depth1_m: NDArray[np.floating], depth2_m: NDArray[np.floating],
                           frequency1_hz: float, frequency2_hz: float) -> NDArray[np.float32]:
    """Unwrap two wrapped depth images measured at two modulation frequencies.

    The true distance ``d`` satisfies ``d = d1 + n1 R1 = d2 + n2 R2`` with
    ``R_k = c / (2 f_k)``. Over the combined unambiguous range
    ``R = c / (2 g)``, ``g = gcd(f1, f2)`` (frequencies rounded to whole Hz), there are
    ``f1 / g`` candidates ``n1``. For each, ``n2`` is the nearest integer making the two
    estimates agree; the candidate with the smallest disagreement wins, and its two
    estimates are averaged with inverse-variance weights ``f_k²`` (equal phase noise gives
    depth noise ∝ 1/f_k). The result is wrapped into ``[0, R)``.

    Limit: a wrong candidate disagrees by at least ``c g / (2 f1 f2)``, so unwrapping is
    exact while ``|e1 − e2| < c g / (4 f1 f2)`` (e_k the depth errors; 0.94 m for 20 and
    16 MHz); distances beyond ``R`` alias back into ``[0, R)``.

    Parameters
    ----------
    depth1_m, depth2_m : ndarray, shape (H, W)
        Wrapped depths in ``[0, R1)`` and ``[0, R2)`` (m).
    frequency1_hz, frequency2_hz : float
        The two modulation frequencies (Hz).

    Returns
    -------
    ndarray, shape (H, W), float32
        Unwrapped depth in ``[0, c / (2 gcd(f1, f2)))`` (m).
    """
    f1, f2 = round(frequency1_hz), round(frequency2_hz)
    common = gcd(f1, f2)
    r1, r2 = unambiguous_range_m(frequency1_hz), unambiguous_range_m(frequency2_hz)
    r_max = SPEED_OF_LIGHT / (2.0 * common)
    d1 = np.asarray(depth1_m, dtype=np.float64)
    d2 = np.asarray(depth2_m, dtype=np.float64)
    w1, w2 = f1**2 / (f1**2 + f2**2), f2**2 / (f1**2 + f2**2)
    best_err = np.full(d1.shape, np.inf)
    best = np.zeros(d1.shape)
    for n1 in range(f1 // common):
        cand1 = d1 + n1 * r1
        cand2 = d2 + np.round((cand1 - d2) / r2) * r2
        err = np.abs(cand1 - cand2)
        better = err < best_err
        best_err = np.where(better, err, best_err)
        best = np.where(better, w1 * cand1 + w2 * cand2, best)
    return as_float(np.mod(best, r_max))


def unwrap_frequencies(depths_m: Sequence[NDArray[np.floating]],
                       frequencies_hz: Sequence[float]) -> NDArray[np.float32]:
    """Unwrap wrapped depth images measured at several modulation frequencies.

    The generalisation of :func:`unwrap_two_frequencies` to any number of frequencies
    (Kinect v2: 80, 16 and 120 MHz). The true distance ``d`` satisfies
    ``d = d_k + n_k R_k`` for every frequency (``R_k = c / (2 f_k)``). Over the combined
    unambiguous range ``R = c / (2 g)``, ``g = gcd(f_1, …, f_K)`` (frequencies rounded to
    whole Hz), each of the ``f_1 / g`` candidates ``n_1`` of the first frequency fixes
    every other ``n_k`` as the nearest integer making ``d_k + n_k R_k`` agree with it; the
    candidate with the smallest sum of squared disagreements wins (a maximum-likelihood
    search over the wrap counts, as the Kinect v2 decoders do with a table of the allowed
    ``(n_1, n_2, n_3)``), and its estimates are averaged with inverse-variance weights
    ``f_k²``. The result is wrapped into ``[0, R)``.

    Failure mode: with phase noise σ_φ at each frequency the depth errors are
    ``e_k ≈ σ_φ R_k / (2π)``; once two estimates differ by half the smallest distance
    between candidates the search picks a wrong ``n``, an error of a whole wrap (metres,
    not millimetres). The rate of such errors rises steeply as the amplitude SNR falls
    (``docs/devices.md``, "Multi-frequency unwrapping").

    Parameters
    ----------
    depths_m : sequence of ndarray, shape (H, W)
        Wrapped depth ``d_k`` in ``[0, R_k)`` per frequency (m).
    frequencies_hz : sequence of float
        The modulation frequencies (Hz), same order.

    Returns
    -------
    ndarray, shape (H, W), float32
        Unwrapped depth in ``[0, c / (2 gcd(f_1, …)))`` (m).
    """
    if len(depths_m) == 1:
        return as_float(np.asarray(depths_m[0]))
    if len(depths_m) == 2:
        return unwrap_two_frequencies(depths_m[0], depths_m[1], frequencies_hz[0],
                                      frequencies_hz[1])
    whole = [round(f) for f in frequencies_hz]
    common = whole[0]
    for f in whole[1:]:
        common = gcd(common, f)
    ranges = [unambiguous_range_m(f) for f in frequencies_hz]
    r_max = SPEED_OF_LIGHT / (2.0 * common)
    depths = [np.asarray(d, dtype=np.float64) for d in depths_m]
    weights = np.array([f**2 for f in whole], dtype=np.float64)
    weights /= weights.sum()
    best_err = np.full(depths[0].shape, np.inf)
    best = np.zeros(depths[0].shape)
    for n1 in range(whole[0] // common):
        cand1 = depths[0] + n1 * ranges[0]
        err = np.zeros_like(cand1)
        mean = weights[0] * cand1
        for d, r, w in zip(depths[1:], ranges[1:], weights[1:], strict=True):
            cand = d + np.round((cand1 - d) / r) * r
            err += (cand1 - cand) ** 2
            mean += w * cand
        better = err < best_err
        best_err = np.where(better, err, best_err)
        best = np.where(better, mean, best)
    return as_float(np.mod(best, r_max))


def incoherent_slab(permittivity: float, loss_tangent: float, thickness_m: float | None,
                    wavelength_m: float) -> tuple[float, float]:
    """Power reflectance and transmittance of a slab at normal incidence, summed incoherently.

    For light whose coherence length is far below the slab's thickness (an LED or VCSEL
    illuminator and a window pane) the internal reflections add in power, not in
    amplitude: with the interface reflectance ``R = |(1 − n)/(1 + n)|²`` of the complex
    index ``n = √(ε′ (1 − j tan δ))`` and the single-pass power attenuation
    ``a = exp(−4π κ d / λ)`` (``κ = −Im n``)::

        T = (1 − R)² a / (1 − R² a²),   R_slab = R + R (1 − R)² a² / (1 − R² a²)

    (lossless: ``T = (1 − R)/(1 + R)``, ``R_slab = 2R/(1 + R)``). A half-space
    (``thickness_m`` None) transmits nothing.

    Returns
    -------
    (float, float)
        ``R_slab`` and the one-pass power transmittance ``T``.
    """
    n = cmath.sqrt(permittivity * (1.0 - 1j * loss_tangent))
    refl = abs((1.0 - n) / (1.0 + n)) ** 2
    if thickness_m is None:
        return refl, 0.0
    a = math.exp(-4.0 * math.pi * abs(n.imag) * thickness_m / wavelength_m)
    den = 1.0 - refl * refl * a * a
    return (refl + refl * (1.0 - refl) ** 2 * a * a / den,
            (1.0 - refl) ** 2 * a / den)


def slab_transmittance(band: BandMaterial, wavelength_m: float) -> float:
    """One-pass power transmittance of a ToF-band material (0: opaque).

    Not drawn (opacity 0) or a metal: 0; no permittivity: 1 with a ``thickness_m`` (an
    invisible sheet, as :meth:`BandMaterial.coefficients`) else 0; otherwise
    :func:`incoherent_slab`.
    """
    if band.opacity <= 0 or band.metallic >= 1.0:
        return 0.0
    if band.permittivity is None:
        return 1.0 if band.thickness_m is not None else 0.0
    return incoherent_slab(band.permittivity, band.loss_tangent, band.thickness_m,
                           wavelength_m)[1]


def _sample_signal(buffers: RenderBuffers, config: TofCameraConfig
                   ) -> tuple[NDArray[np.float32], NDArray[np.float32], NDArray[np.float32]]:
    """Per sub-pixel range, signal and ambient electrons of one render."""
    hit = (buffers.object_index >= 0) & np.isfinite(buffers.range_m)
    r = np.where(hit, np.maximum(buffers.range_m, FLOAT(MIN_RANGE_M)), FLOAT(1.0))
    response = np.where(hit, buffers.intensity, FLOAT(0.0))
    signal = response * FLOAT(config.signal_electrons_at_1m)
    signal /= r * r
    ambient = response * FLOAT(config.ambient_electrons if config.ambient_light else 0.0)
    return r, signal, ambient


def reprojected_samples(buffers: RenderBuffers, config: TofCameraConfig
                        ) -> list[RenderBuffers]:
    """The render at the four correlation samples' times, from its per-pixel motion.

    Each pixel's surface is its tangent plane ``n·X = n·P`` moving with the point's
    velocity ``v`` relative to the camera (``velocity_mps``); at time ``t`` the same ray
    ``X = s d`` meets it at ``s(t) = R + (n·v) t / (n·d)``. Exact for translating planar
    surfaces (and to first order in ``t`` for curved or rotating ones); a pixel keeps its
    surface, so silhouettes that cross pixels during the ~3 ms are not moved (the four
    renders of ``motion_sampling = "renders"`` do that).

    Returns
    -------
    list of 4 RenderBuffers
        Sample ``i`` at ``i · sample_interval_s``; only ``range_m`` and ``points_m`` change.
    """
    ranges, d = _reprojected_ranges(buffers, config)
    return [buffers] + [dataclasses.replace(buffers, range_m=r, points_m=as_float(d * r[..., None]))
                        for r in ranges[1:]]


def _reprojected_ranges(buffers: RenderBuffers, config: TofCameraConfig
                        ) -> tuple[list[NDArray[np.float32]], NDArray[np.float32]]:
    """The ranges of :func:`reprojected_samples` (sample 0 is ``buffers.range_m`` itself).

    Returns
    -------
    ranges : list of 4 ndarray, shape (H, W), float32
    d : ndarray, shape (H, W, 3), float32
        Each pixel's unit ray (where it sees a surface).
    """
    ranges, d = _reprojection(np.ascontiguousarray(buffers.range_m, dtype=np.float32),
                              np.ascontiguousarray(buffers.object_index, dtype=np.int32),
                              np.ascontiguousarray(buffers.points_m, dtype=np.float32),
                              np.ascontiguousarray(buffers.normals, dtype=np.float32),
                              np.ascontiguousarray(buffers.velocity_mps, dtype=np.float32),
                              float(config.sample_interval_s))
    return [buffers.range_m, ranges[0], ranges[1], ranges[2]], d


@kernel
def _reprojection(range_m: NDArray[np.float32], index: NDArray[np.int32],
                  points: NDArray[np.float32], normals: NDArray[np.float32],
                  velocity: NDArray[np.float32], interval: float
                  ) -> tuple[NDArray[np.float32], NDArray[np.float32]]:
    """:func:`_reprojected_ranges` in one pass: samples 1–3's ranges (3, H, W) and the rays.

    Float32 throughout, in numpy's order: ``d = P / R``, ``rate = (n·v) / (n·d)`` where the
    pixel sees a surface and ``|n·d| > 1e-6``, else 0; ``R_i = R + rate · (i Δt)``.
    """
    h, w = range_m.shape
    ranges = np.empty((3, h, w), dtype=np.float32)
    d = np.empty((h, w, 3), dtype=np.float32)
    one, zero, tiny = np.float32(1.0), np.float32(0.0), np.float32(1e-6)
    steps = np.empty(3, dtype=np.float32)
    for i in range(3):
        steps[i] = np.float32((i + 1) * interval)
    for y in range(h):
        for x in range(w):
            r = range_m[y, x]
            hit = index[y, x] >= 0 and math.isfinite(r)
            safe = r if hit else one
            d0, d1, d2 = points[y, x, 0] / safe, points[y, x, 1] / safe, points[y, x, 2] / safe
            d[y, x, 0], d[y, x, 1], d[y, x, 2] = d0, d1, d2
            n0, n1, n2 = normals[y, x, 0], normals[y, x, 1], normals[y, x, 2]
            n_dot_d = n0 * d0 + n1 * d1 + n2 * d2
            n_dot_v = n0 * velocity[y, x, 0] + n1 * velocity[y, x, 1] + n2 * velocity[y, x, 2]
            rate = zero
            if hit and abs(n_dot_d) > tiny:
                rate = n_dot_v / n_dot_d
            for i in range(3):
                ranges[i, y, x] = r + rate * steps[i]
    return ranges, d


def _moved_samples(buffers: RenderBuffers, config: TofCameraConfig) -> list[RenderBuffers]:
    """:func:`reprojected_samples` as :func:`_correlation_from_samples` reads them.

    Only ``range_m`` is replaced (the correlation samples read ``range_m``, ``intensity``
    and ``object_index``): the moved points of the other buffers are not built.
    """
    ranges, _ = _reprojected_ranges(buffers, config)
    return [buffers] + [dataclasses.replace(buffers, range_m=r) for r in ranges[1:]]


def _correlation_from_samples(sample_buffers: Sequence[RenderBuffers], config: TofCameraConfig,
                              f_mod: float) -> NDArray[np.float32]:
    """Correlation images (4, H, W) in electrons, sample ``i`` from render ``i``.

    Each of the four samples integrates the scene as it is during its own exposure, so a
    moving edge lands at different pixels in C0..C3 (the motion artefact of real AMCW
    cameras). The optics and cross-talk are applied afterwards (:func:`_optics`) like for
    a still scene. With wiggling each sample also sees the correlation's harmonics
    ``a3 cos 3(φ + iπ/2) + a5 cos 5(φ + iπ/2)``.
    """
    k = config.supersampling
    a3, a5 = (FLOAT(a) for a in config.wiggling_harmonics)
    # Wiggling: cos 3x = 4c³ − 3c and cos 5x = 16c⁵ − 20c³ + 5c with c = cos x, so
    # c + a3 cos 3x + a5 cos 5x is a polynomial in c (one cosine instead of three).
    p1, p3, p5 = FLOAT(1 - 3 * a3 + 5 * a5), FLOAT(4 * a3 - 20 * a5), FLOAT(16 * a5)
    if not config.wiggling:          # c (1 + c² (0 + c² 0)) = c exactly
        p1, p3, p5 = FLOAT(1.0), FLOAT(0.0), FLOAT(0.0)
    contrast = FLOAT(config.demodulation_contrast)
    signal_1m = FLOAT(config.signal_electrons_at_1m)
    ambient_e = FLOAT(config.ambient_electrons if config.ambient_light else 0.0)
    planes = []
    for i, buf in enumerate(sample_buffers):
        # Two compiled passes around numpy's float32 cosine (the same numbers as the
        # numpy steps of _sample_signal and _block_mean, in their order).
        phase, signal, ambient = _sample_terms(
            np.ascontiguousarray(buf.range_m, dtype=np.float32),
            np.ascontiguousarray(buf.intensity, dtype=np.float32),
            np.ascontiguousarray(buf.object_index, dtype=np.int32), signal_1m, ambient_e,
            FLOAT(4.0 * np.pi * f_mod / SPEED_OF_LIGHT), FLOAT(i * np.pi / 2))
        wave = np.cos(phase, out=phase)
        planes.append(_sample_plane(signal, ambient, wave, k, contrast, p1, p3, p5))
    return as_float(np.stack(planes))


@kernel
def _sample_terms(range_m: NDArray[np.float32], intensity: NDArray[np.float32],
                  index: NDArray[np.int32], signal_1m: np.float32, ambient_e: np.float32,
                  k_phase: np.float32, phase0: np.float32
                  ) -> tuple[NDArray[np.float32], NDArray[np.float32], NDArray[np.float32]]:
    """Per sub-pixel phase ``k R + φ0``, signal and ambient electrons (:func:`_sample_signal`)."""
    h, w = range_m.shape
    phase = np.empty((h, w), dtype=np.float32)
    signal = np.empty((h, w), dtype=np.float32)
    ambient = np.empty((h, w), dtype=np.float32)
    near = np.float32(MIN_RANGE_M)
    for y in range(h):
        for x in range(w):
            r = range_m[y, x]
            if index[y, x] >= 0 and math.isfinite(r):
                r = max(r, near)
                response = intensity[y, x]
            else:
                r = np.float32(1.0)
                response = np.float32(0.0)
            signal[y, x] = response * signal_1m / (r * r)
            ambient[y, x] = response * ambient_e
            phase[y, x] = r * k_phase + phase0
    return phase, signal, ambient


@kernel
def _sample_plane(signal: NDArray[np.float32], ambient: NDArray[np.float32],
                  wave: NDArray[np.float32], k: int, contrast: np.float32,
                  p1: np.float32, p3: np.float32, p5: np.float32) -> NDArray[np.float32]:
    """One correlation sample per sensor pixel, float32.

    The block mean of ``S + B`` plus that of ``m S w``, ``w = c (p1 + c² (p3 + c² p5))`` of
    the wave ``c`` (wiggling; ``p = (1, 0, 0)``: the plain cosine).
    """
    h, w = signal.shape[0] // k, signal.shape[1] // k
    inv = np.float32(1.0 / (k * k))
    out = np.empty((h, w), dtype=np.float32)
    for y in range(h):
        for x in range(w):
            total = np.float32(0.0)
            modulated = np.float32(0.0)
            for i in range(k):
                for j in range(k):
                    yy, xx = y * k + i, x * k + j
                    c = wave[yy, xx]
                    c2 = c * c
                    c = c * (p1 + c2 * (p3 + c2 * p5))
                    a = signal[yy, xx] + ambient[yy, xx]
                    m = signal[yy, xx] * contrast * c
                    if i == 0 and j == 0:
                        total, modulated = a, m
                    else:
                        total += a
                        modulated += m
            out[y, x] = total * inv + modulated * inv
    return out


_SOLID_ANGLE: dict[tuple[float, ...], NDArray[np.float32]] = {}


def _solid_angle(intrinsics: PinholeIntrinsics) -> NDArray[np.float32]:
    """:meth:`PinholeIntrinsics.pixel_solid_angle` as float32, computed once per grid."""
    key = (intrinsics.width, intrinsics.height, intrinsics.fx, intrinsics.fy,
           intrinsics.cx, intrinsics.cy)
    if key not in _SOLID_ANGLE:
        if len(_SOLID_ANGLE) > 8:
            _SOLID_ANGLE.clear()
        _SOLID_ANGLE[key] = as_float(intrinsics.pixel_solid_angle())
    return _SOLID_ANGLE[key]


#: The last frame's exact one-bounce sums per receiver: a frame in which only part of the
#: render changed (a person walking past a still camera) sums only what changed.
_ONE_BOUNCE_REUSE = OneBounceCache()
#: The last one-bounce results with copies of their inputs (still scenes reuse them): one
#: per camera for up to this many cameras (least recently used dropped).
_ONE_BOUNCE_KEEP = 8
_ONE_BOUNCE_CACHE: list[tuple[bytes, tuple[NDArray[np.generic], ...], tuple[
    NDArray[np.float32], list[tuple[NDArray[np.float32], NDArray[np.float32]]]]]] = []
_ONE_BOUNCE_LOCK = threading.Lock()


def _cached_one_bounce(arrays: tuple[NDArray[np.generic], ...], params: tuple[object, ...],
                       compute: Callable[[], tuple[NDArray[np.float32],
                                                   list[tuple[NDArray[np.float32],
                                                              NDArray[np.float32]]]]]
                       ) -> tuple[NDArray[np.float32],
                                  list[tuple[NDArray[np.float32], NDArray[np.float32]]]]:
    """``compute()``, or its previous result when the render's geometry is byte-identical.

    The one-bounce sums depend only on the receivers' points and normals and on the senders
    (not on the exposure), so a still camera looking at a still scene reuses them frame
    after frame. The inputs are compared byte for byte with the last call's (a compiled
    comparison that stops at the first difference: a moving scene costs little).
    """
    key = repr(params).encode()
    with _ONE_BOUNCE_LOCK:
        for i, (k, inputs, value) in enumerate(_ONE_BOUNCE_CACHE):
            if k == key and len(inputs) == len(arrays) and all(
                    _same_bytes(a, b) for a, b in zip(arrays, inputs, strict=True)):
                _ONE_BOUNCE_CACHE.append(_ONE_BOUNCE_CACHE.pop(i))   # most recent last
                return value
    result = compute()
    with _ONE_BOUNCE_LOCK:
        _ONE_BOUNCE_CACHE.append((key, tuple(np.array(a, copy=True) for a in arrays), result))
        del _ONE_BOUNCE_CACHE[:-_ONE_BOUNCE_KEEP]
    return result


def _same_bytes(a: NDArray[np.generic], b: NDArray[np.generic]) -> bool:
    """Whether two arrays have the same dtype, shape and bytes."""
    if a.dtype != b.dtype or a.shape != b.shape:
        return False
    word = np.uint64 if a.nbytes % 8 == 0 else np.uint8
    return bool(_equal_words(np.ascontiguousarray(a).reshape(-1).view(word),
                             np.ascontiguousarray(b).reshape(-1).view(word)))


@kernel
def _equal_words(a: NDArray[np.unsignedinteger], b: NDArray[np.unsignedinteger]) -> bool:
    """Word-wise equality, stopping at the first difference."""
    for i in range(a.shape[0]):
        if a[i] != b[i]:
            return False
    return True


@kernel
def _receivers(points: NDArray[np.float32], normals: NDArray[np.float32],
               hit: NDArray[np.bool_], albedo: NDArray[np.float32], k: int
               ) -> tuple[NDArray[np.float32], NDArray[np.float32], NDArray[np.float32],
                          NDArray[np.float32]]:
    """Each sensor pixel's mean surface point, unit normal and albedo over its hit sub-pixels.

    As :func:`_block_mean` of the hit sub-pixels' values (0 elsewhere) divided by the hit
    fraction ``coverage`` (at least 1e-12), in float32 and in the same order, the normal then
    scaled to unit length.

    Returns
    -------
    points, normals : ndarray, shape (H, W, 3), float32
    albedo, coverage : ndarray, shape (H, W), float32
    """
    h, w = hit.shape[0] // k, hit.shape[1] // k
    inv = np.float32(1.0 / (k * k))
    pts = np.empty((h, w, 3), dtype=np.float32)
    nrm = np.empty((h, w, 3), dtype=np.float32)
    rho = np.empty((h, w), dtype=np.float32)
    coverage = np.empty((h, w), dtype=np.float32)
    zero = np.float32(0.0)
    sp = np.empty(3, dtype=np.float32)
    sn = np.empty(3, dtype=np.float32)
    for y in range(h):
        for x in range(w):
            cov, sa = zero, zero
            for i in range(k):
                for j in range(k):
                    yy, xx = y * k + i, x * k + j
                    on = hit[yy, xx]
                    a = albedo[yy, xx]
                    if i == 0 and j == 0:
                        cov = np.float32(1.0) if on else zero
                        sa = a
                        for c in range(3):
                            sp[c] = points[yy, xx, c] if on else zero
                            sn[c] = normals[yy, xx, c] if on else zero
                    else:
                        cov += np.float32(1.0) if on else zero
                        sa += a
                        for c in range(3):
                            sp[c] += points[yy, xx, c] if on else zero
                            sn[c] += normals[yy, xx, c] if on else zero
            cov *= inv
            count = max(cov, np.float32(1e-12))
            coverage[y, x] = cov
            rho[y, x] = (sa * inv) / count
            for c in range(3):
                pts[y, x, c] = (sp[c] * inv) / count
                sn[c] = (sn[c] * inv) / count
            norm = max(np.float32(math.sqrt(sn[0] * sn[0] + sn[1] * sn[1] + sn[2] * sn[2])),
                       np.float32(1e-12))
            for c in range(3):
                nrm[y, x, c] = sn[c] / norm
    return pts, nrm, rho, coverage


def _multipath_planes(buffers: RenderBuffers, config: TofCameraConfig,
                      albedo: NDArray[np.float32], *, receiver_step: int = RECEIVER_STEP,
                      room: Room | None = None, shadow_map: RenderBuffers | None = None
                      ) -> NDArray[np.float32]:
    """Indirect diffuse light per sensor pixel: offset and phasor planes (electrons).

    One bounce from the surfaces the camera sees (:func:`one_bounce_image`;
    ``receiver_step`` is its node spacing, 1: the exact sum at every pixel), or, given the
    scene's ``room``, every bounce from every surface (:func:`room_indirect`; the light
    reaches what the pinhole render ``shadow_map`` sees, default ``buffers``).

    Returns
    -------
    ndarray, shape (1 + 2·F, H, W), float32
        ``S_ind`` and, per modulation frequency, ``m Re(S_ind e^{iφ})``,
        ``m Im(S_ind e^{iφ})`` — laid out like the direct planes of :func:`simulate_tof`.
    """
    k = config.supersampling
    hit = (buffers.object_index >= 0) & np.isfinite(buffers.range_m)
    lit_albedo = np.where(hit, albedo, FLOAT(0.0))
    # Receivers: each sensor pixel's mean surface point, normal and albedo.
    pts, nrm, rho, coverage = _receivers(
        np.ascontiguousarray(buffers.points_m, dtype=np.float32),
        np.ascontiguousarray(buffers.normals, dtype=np.float32), np.ascontiguousarray(hit),
        np.ascontiguousarray(lit_albedo, dtype=np.float32), k)
    seen = coverage > 0
    h, w = seen.shape
    if room is not None:     # every bounce from the whole scene (surfel radiosity)
        # A still camera in a still scene reuses the last frame's result (same bytes in).
        light = buffers if shadow_map is None else shadow_map
        range_m = np.ascontiguousarray(light.range_m, dtype=np.float32)
        transform = np.ascontiguousarray(buffers.sensor.transform, dtype=np.float64)
        magnitude, phasors = _cached_one_bounce(
            (pts, nrm, seen, range_m, transform),
            (h, w, tuple(config.modulation_frequencies_hz), receiver_step, room.key(),
             config.multipath_surfel_m, config.multipath_bounces, config.multipath_moving),
            lambda: room_indirect(
                room, camera=transform, intrinsics=light.intrinsics, range_m=range_m,
                points_m=pts, normals=nrm, seen=seen,
                frequencies_hz=list(config.modulation_frequencies_hz),
                patch_m=config.multipath_surfel_m, bounces=config.multipath_bounces,
                step=receiver_step, moving=config.multipath_moving))
    else:
        senders = senders_from_render(
            buffers.points_m, buffers.normals, lit_albedo,
            _solid_angle(buffers.intrinsics), hit,
            stride=config.multipath_patch_px * k)
        # Keyed by what the sums read (sensor-resolution receivers and the senders): a
        # quarter of the render's bytes to digest.
        magnitude, phasors = _cached_one_bounce(
            (pts, nrm, seen, senders.points_m, senders.normals, senders.weight),
            (h, w, tuple(config.modulation_frequencies_hz), receiver_step),
            lambda: one_bounce_image(
                pts, nrm, seen, senders, list(config.modulation_frequencies_hz),
                step=receiver_step, cache=_ONE_BOUNCE_REUSE,
                camera=np.ascontiguousarray(buffers.sensor.transform).tobytes()))
    scale = as_float(rho * FLOAT(config.signal_electrons_at_1m) * coverage)
    scale[~seen] = 0.0
    planes = np.zeros((1 + 2 * len(phasors), h, w), dtype=np.float32)
    planes[0] = magnitude * scale
    contrast = FLOAT(config.demodulation_contrast)
    for j, (re, im) in enumerate(phasors):
        planes[1 + 2 * j] = re * scale * contrast
        planes[2 + 2 * j] = im * scale * contrast
    return planes


def specular_factor(buffers: RenderBuffers, mirrors: tuple[NDArray[np.float32],
                                                         NDArray[np.bool_]],
                    *, max_bounces: int = 3, step: int = 1
                    ) -> tuple[NDArray[np.float32], NDArray[np.float32]]:
    """Mirror-path signal factors and optical paths of a render (:mod:`.specular`).

    Parameters
    ----------
    buffers : RenderBuffers
        The ToF render.
    mirrors : (ndarray, ndarray)
        :func:`simcore.sensors.tof.specular.material_columns` and
        :func:`~simcore.sensors.tof.specular.is_mirror` of the project's objects.
    max_bounces, step : int, keyword-only
        Surfaces per path; one traced path per ``step × step`` block of render pixels
        (:func:`simcore.sensors.tof.specular.specular_paths`).

    Returns
    -------
    factor, path : ndarray, shape (max_bounces − 1, H·k, W·k), float32
        Signal per ``signal_electrons_at_1m`` (1/m²) and round-trip path (m).
    """
    columns, mirror = mirrors
    intr = buffers.intrinsics
    index = np.ascontiguousarray(np.where(np.isfinite(buffers.range_m),
                                          buffers.object_index, -1).astype(np.int32))
    if not mirror[index[index >= 0]].any():
        shape = (max(max_bounces - 1, 1), *index.shape)
        return np.zeros(shape, dtype=np.float32), np.zeros(shape, dtype=np.float32)
    return specular_paths(
        np.ascontiguousarray(buffers.points_m, dtype=np.float32),
        np.ascontiguousarray(buffers.normals, dtype=np.float32), index,
        np.ascontiguousarray(columns, dtype=np.float32), np.ascontiguousarray(mirror),
        np.array([intr.fx, intr.fy, intr.cx, intr.cy], dtype=np.float64), max_bounces, step)


def _specular_planes(factor: NDArray[np.float32], path: NDArray[np.float32],
                     config: TofCameraConfig) -> NDArray[np.float32]:
    """Offset and phasor planes (e⁻) of the mirror paths, laid out like the direct planes."""
    k = config.supersampling
    signal = factor * FLOAT(config.signal_electrons_at_1m)
    planes = [_block_mean(signal.sum(axis=0), k)]
    m_signal = signal * FLOAT(config.demodulation_contrast)
    for f_mod in config.modulation_frequencies_hz:
        phase = path * FLOAT(2.0 * np.pi * f_mod / SPEED_OF_LIGHT)
        planes += [_block_mean((m_signal * np.cos(phase)).sum(axis=0), k),
                   _block_mean((m_signal * np.sin(phase)).sum(axis=0), k)]
    return as_float(np.stack(planes))


def _transmitted_planes(buffers: RenderBuffers, see_through: RenderBuffers,
                        transmittance: NDArray[np.floating], config: TofCameraConfig
                        ) -> NDArray[np.float32]:
    """The returns seen through transmissive surfaces: offset and phasor planes (e⁻).

    A sub-pixel whose first surface transmits (one-pass power ``T`` of its object in
    ``transmittance``) and whose see-through render shows a surface no nearer adds that
    surface's signal and ambient electrons times ``T²`` (in and out).

    Returns
    -------
    ndarray, shape (1 + 2·F, H, W), float32
        Laid out like the direct planes of :func:`simulate_tof`.
    """
    k = config.supersampling
    front = buffers.object_index
    hit = (front >= 0) & np.isfinite(buffers.range_m)
    table = np.append(np.asarray(transmittance, dtype=np.float32), FLOAT(0.0))
    t = table[np.where(hit, front, -1)]
    r2, signal, ambient = _sample_signal(see_through, config)
    behind = ((t > 0) & (see_through.object_index >= 0) & np.isfinite(see_through.range_m)
              & (see_through.range_m >= np.where(hit, buffers.range_m, np.inf)
                 - FLOAT(1e-4)))
    two_way = np.where(behind, t * t, FLOAT(0.0))
    signal = signal * two_way
    planes = [_block_mean(signal + ambient * two_way, k)]
    m_signal = signal * FLOAT(config.demodulation_contrast)
    for f_mod in config.modulation_frequencies_hz:
        phase = r2 * FLOAT(4.0 * np.pi * f_mod / SPEED_OF_LIGHT)
        planes += [_block_mean(m_signal * np.cos(phase), k),
                   _block_mean(m_signal * np.sin(phase), k)]
    return as_float(np.stack(planes))


def auto_exposure_s(reference: RenderBuffers, config: TofCameraConfig, *,
                    extra_response: NDArray[np.float32] | None = None) -> float:
    """The exposure that puts the brightest 1 % of pixels at the target level (s).

    From a noise-free look at ``reference`` (the previous frame's render): the largest
    correlation sample of a pixel is at most ``(S + B)(1 + m)``; its 99th percentile over
    the pixels that see a surface, at the configured exposure, scales linearly with the
    exposure time. The result is clipped to ``config.exposure_range_s``. ``extra_response``
    (render shape, 1/m²) adds light that does not come straight back (the mirror paths of
    :func:`specular_factor`) as ``signal_electrons_at_1m ×`` it.
    """
    k = config.supersampling
    _, signal, ambient = _sample_signal(reference, config)
    if extra_response is not None:
        signal = signal + extra_response * FLOAT(config.signal_electrons_at_1m)
    offset = _block_mean(signal + ambient, k)
    seen = _block_mean((reference.object_index >= 0).astype(np.float32), k) > 0
    low, high = config.exposure_range_s
    if not seen.any():
        return float(high)
    peak = float(np.percentile(offset[seen], 99)) * (1.0 + config.demodulation_contrast)
    if peak <= 0:
        return float(high)
    wanted = config.exposure_time_s * config.auto_exposure_target * (
        config.full_well_electrons / peak)
    return float(min(max(wanted, low), high))


def _direct_planes(buffers: RenderBuffers, config: TofCameraConfig) -> NDArray[np.float32]:
    """Offset ``S + B`` and per frequency the phasor ``m S e^{iφ}`` (re, im) per sensor pixel.

    ``C_i = offset + m S cos(φ + iπ/2)``: C0 = o + mSc, C1 = o − mSs, C2 = o − mSc,
    C3 = o + mSs. With wiggling, the harmonics' phasor (:func:`.optics.wiggling_planes`) is
    added to the fundamental's. In float32 like the buffers (relative rounding 6e-8; the
    phase of a 10 m range is accurate to 1e-6 rad, 1 µm of depth at 20 MHz).

    Returns
    -------
    ndarray, shape (1 + 2F, H, W), float32
    """
    k = config.supersampling
    r, signal, ambient = _sample_signal(buffers, config)
    m_signal = signal * FLOAT(config.demodulation_contrast)
    planes = [_block_mean(signal + ambient, k)]
    for f_mod in config.modulation_frequencies_hz:
        phase = r * FLOAT(4.0 * np.pi * f_mod / SPEED_OF_LIGHT)
        re, im = m_signal * np.cos(phase), m_signal * np.sin(phase)
        if config.wiggling:
            w_re, w_im = wiggling_planes(m_signal, phase, config.wiggling_harmonics)
            re, im = re + w_re, im + w_im
        planes += [_block_mean(re, k), _block_mean(im, k)]
    return as_float(np.stack(planes))


def _optics(planes: NDArray[np.float32], config: TofCameraConfig) -> NDArray[np.float32]:
    """Vignetting, lens stray light and cross-talk on the planes (…, H, W) (all linear)."""
    if config.vignetting:
        planes = planes * vignetting(config.intrinsics())
    if config.stray_light:
        planes = stray_light(planes, config.stray_light_fraction, config.stray_light_radius_px)
    return _crosstalk(as_float(planes), config.crosstalk_sigma_px)


def _ambient_plane(buffers: RenderBuffers, config: TofCameraConfig) -> NDArray[np.float32]:
    """Ambient electrons per sample and sensor pixel, after the optics (for SBI)."""
    _, _, ambient = _sample_signal(buffers, config)
    return _optics(_block_mean(ambient, config.supersampling)[None], config)[0]


_Images = tuple[NDArray[np.float32], NDArray[np.float32], NDArray[np.bool_],
                NDArray[np.bool_], NDArray[np.float32]]


def _read_and_demodulate(mixed: NDArray[np.float32] | None, indirect: NDArray[np.float32] | None,
                         sample_buffers: Sequence[RenderBuffers] | None,
                         config: TofCameraConfig, *, rng: np.random.Generator, noise: bool,
                         ambient: NDArray[np.float32] | None
                         ) -> tuple[NDArray[np.float32], _Images]:
    """Steps 4.–7.: correlation samples, read-out, demodulation, validity, unwrapping.

    Returns
    -------
    depth : ndarray, shape (H, W), float32
    (amplitude, intensity, valid, saturated, correlation)
        Of the first modulation frequency (validity over all).
    """
    depths, amplitude, correlation, intensity = [], None, None, None
    valid = np.ones((config.height, config.width), dtype=bool)
    saturated = np.zeros_like(valid)
    for j, f_mod in enumerate(config.modulation_frequencies_hz):
        if sample_buffers is not None:
            corr_e = _correlation_from_samples(sample_buffers, config, f_mod)
            if indirect is not None:
                o, re, im = indirect[[0, 1 + 2 * j, 2 + 2 * j]]
                corr_e = corr_e + np.stack([o + re, o - im, o - re, o + im])
            corr_e = _optics(corr_e, config)      # linear: once on the four samples
        else:
            assert mixed is not None
            o, re, im = mixed[0], mixed[1 + 2 * j], mixed[2 + 2 * j]
            corr_e = np.stack([o + re, o - im, o - re, o + im])
        # 4.–5. Noise, saturation, ADC.
        corr_dn, sat = _read_out(corr_e, config, rng=rng, noise=noise, suppressed=ambient)
        # 6. Phase, depth, amplitude, validity.
        depth, amp = _demodulate(corr_dn, f_mod)
        saturated |= sat
        valid &= ~sat & (amp >= FLOAT(config.min_amplitude_dn))
        depths.append(depth)
        if j == 0:
            amplitude, correlation = amp, corr_dn
            intensity = as_float(corr_dn.mean(axis=0))
    assert amplitude is not None and correlation is not None and intensity is not None
    # 7. Multi-frequency unwrapping.
    depth_m = unwrap_frequencies(depths, config.modulation_frequencies_hz)
    depth_m = as_float(np.where(valid, depth_m, 0.0))
    return depth_m, (amplitude, intensity, valid, saturated, correlation)


def simulate_tof(buffers: RenderBuffers, config: TofCameraConfig, *,
                 rng: np.random.Generator, noise: bool = True,
                 sample_buffers: Sequence[RenderBuffers] | None = None,
                 albedo: NDArray[np.float32] | None = None,
                 exposure_reference: RenderBuffers | None = None,
                 see_through: RenderBuffers | None = None,
                 transmittance: NDArray[np.floating] | None = None,
                 mirrors: tuple[NDArray[np.float32], NDArray[np.bool_]] | None = None,
                 illuminators: Sequence[Illuminator] = (),
                 room: Room | None = None) -> TofOutput:
    """Simulate one AMCW ToF frame from the ToF band's supersampled render.

    Parameters
    ----------
    buffers : RenderBuffers
        ToF-band render on :meth:`TofCameraConfig.render_intrinsics`, shape
        (H·k, W·k) with ``k = config.supersampling``; uses ``range_m`` (m),
        ``intensity`` (material response f(θ)) and ``object_id``.
    config : TofCameraConfig
        Camera parameters.
    rng : numpy.random.Generator
        Source of the shot and read noise (seed it for reproducible frames).
    noise : bool, optional
        False gives the ideal camera: no shot/read noise and no ADC quantisation
        (saturation, cross-talk and ambient offset remain); so does ``config.ideal``.
    sample_buffers : sequence of 4 RenderBuffers, optional
        Renders at the four correlation samples' own exposure times (motion artefacts):
        sample ``i`` is taken from ``sample_buffers[i]``; ``buffers`` still gives the ground
        truth at the frame time. ``None`` takes all four from ``buffers``.
    albedo : ndarray, shape (H·k, W·k), optional
        Diffuse albedo of the ToF band per render pixel (``(1 − metallic) reflectance``);
        needed when ``config.multipath`` is on (:mod:`simcore.sensors.tof.multipath`).
    exposure_reference : RenderBuffers, optional
        With ``config.auto_exposure``: the render auto-exposure looks at (the previous
        frame's, like a real camera's; default ``buffers``) — :func:`auto_exposure_s`.
    see_through : RenderBuffers, optional
        The same pass with the transmissive objects hidden (:meth:`TofSensor.see_through`):
        what lies behind a pane adds its return × ``T²`` to the pane's own return, as
        phasors before the phase is estimated. Ground truth stays the first surface.
    transmittance : ndarray, shape (N,), optional
        One-pass power transmittance of each object (index as ``object_index``;
        :func:`slab_transmittance`); needed with ``see_through``.
    mirrors : (ndarray, ndarray), optional
        Per-object material columns and mirror flags
        (:func:`simcore.sensors.tof.specular.material_columns`, ``is_mirror``); needed when
        ``config.specular`` is on: light reaching pixels via glossy surfaces
        (:mod:`simcore.sensors.tof.specular`), also counted by auto-exposure.
    illuminators : sequence of Illuminator, optional
        Other cameras whose modulated light falls on the scene (and into the lens)
        during the frame: ToF–ToF interference
        (:func:`simcore.sensors.tof.interference.interference_planes`).
    room : Room, optional
        Every surface of the scene (:mod:`simcore.sensors.tof.radiosity`); needed when
        ``config.multipath_model`` is ``"room"``.

    Returns
    -------
    TofOutput
        Depth, amplitude, grey value, validity, correlation samples and ground truth at
        sensor resolution (H, W).

    Raises
    ------
    ValueError
        If the render's shape is not the supersampled sensor grid.
    """
    k = config.supersampling
    noise = noise and not config.ideal
    _check_render(buffers, config, sample_buffers)
    pinhole = buffers      # the light's shadow map for room multipath: the undistorted render
    if config.distortion:
        buffers, sample_buffers, see_through, exposure_reference, albedo = _through_the_lens(
            config, buffers, sample_buffers, see_through, exposure_reference, albedo)
    if (sample_buffers is None and config.motion_artifacts
            and config.motion_sampling == "reprojection"):
        sample_buffers = _moved_samples(buffers, config)   # after the lens: cheaper
    spec = None
    if config.specular:
        if mirrors is None:
            raise ValueError("specular needs the objects' mirror table (mirrors=...)")
        spec = specular_factor(buffers, mirrors, step=config.supersampling)
    if config.auto_exposure:
        # The previous frame's mirror paths are taken as this frame's (cheaper).
        exposure = auto_exposure_s(buffers if exposure_reference is None
                                   else exposure_reference, config,
                                   extra_response=None if spec is None
                                   else spec[0].sum(axis=0))
        config = config.model_copy(update={"exposure_time_s": exposure})
    indirect = _indirect_light(buffers, config, albedo=albedo, pinhole=pinhole, room=room,
                               spec=spec, see_through=see_through,
                               transmittance=transmittance, illuminators=illuminators)
    mixed = None
    if sample_buffers is None:
        # 1.–2. Per sub-pixel signal/ambient electrons, range and phase, summed per sensor
        #    pixel as the offset S + B and the phasor m S e^{iφ} per frequency.
        planes = _direct_planes(buffers, config)
        if indirect is not None:
            planes = planes + indirect
        # 3. Optics on the collected light (vignetting, lens stray light) and cross-talk —
        #    all linear, so they act on offset and phasor planes alike.
        mixed = _optics(planes, config)
    ambient = _ambient_plane(buffers, config) if config.background_suppression else None
    depth_m, out = _read_and_demodulate(mixed, indirect, sample_buffers, config, rng=rng,
                                        noise=noise, ambient=ambient)
    gt_range, gt_id = downsample_ground_truth(buffers, k)
    amplitude, intensity, valid, saturated, correlation = out
    return TofOutput(
        depth_m=depth_m,
        amplitude=amplitude,
        intensity=intensity,
        valid=valid,
        saturated=saturated,
        correlation=correlation,
        gt_range=gt_range,
        gt_object_id=gt_id,
        exposure_time_s=float(config.exposure_time_s),
    )


def _check_render(buffers: RenderBuffers, config: TofCameraConfig,
                  sample_buffers: Sequence[RenderBuffers] | None) -> None:
    """The render is the supersampled sensor grid; four sample renders when given."""
    k = config.supersampling
    expected = (config.height * k, config.width * k)
    if buffers.shape != expected:
        raise ValueError(
            f"ToF render is {buffers.shape[1]}×{buffers.shape[0]} px; the camera needs "
            f"{expected[1]}×{expected[0]} (sensor {config.width}×{config.height} × "
            f"supersampling {k})")
    if sample_buffers is not None and len(sample_buffers) != 4:
        raise ValueError(f"sample_buffers needs the 4 correlation samples' renders, "
                         f"got {len(sample_buffers)}")


def _through_the_lens(config: TofCameraConfig, buffers: RenderBuffers,
                      sample_buffers: Sequence[RenderBuffers] | None,
                      see_through: RenderBuffers | None,
                      exposure_reference: RenderBuffers | None,
                      albedo: NDArray[np.float32] | None
                      ) -> tuple[RenderBuffers, Sequence[RenderBuffers] | None,
                                 RenderBuffers | None, RenderBuffers | None,
                                 NDArray[np.float32] | None]:
    """The renders (and the albedo) as the distorting lens maps them onto the sensor."""
    # The albedo is per render pixel like the buffers: it follows the lens with them.
    albedo = None if albedo is None else np.asarray(distort_image(
        albedo, buffers.intrinsics, config.distortion_coefficients), dtype=FLOAT)
    # Buffers the camera model never reads stay as rendered (the distorted render
    # does not leave this function); the velocities only for motion reprojection.
    skip: tuple[str, ...] = ("cos_incidence", "radial_velocity_mps")
    if not (config.motion_artifacts and config.motion_sampling == "reprojection"):
        skip += ("velocity_mps",)
    buffers = distort_buffers(buffers, config, skip=skip)
    sample_buffers = (None if sample_buffers is None
                      else [distort_buffers(b, config, skip=skip) for b in sample_buffers])
    see_through = (None if see_through is None
                   else distort_buffers(see_through, config, skip=skip))
    if exposure_reference is not None:
        # Auto-exposure reads only these three (auto_exposure_s): the reference never
        # leaves this function, so its other buffers are not resampled.
        ref, lens = exposure_reference, config.distortion_coefficients
        exposure_reference = dataclasses.replace(
            ref, range_m=distort_image(ref.range_m, ref.intrinsics, lens, np.nan),
            intensity=distort_image(ref.intensity, ref.intrinsics, lens, 0),
            object_index=distort_image(ref.object_index, ref.intrinsics, lens, -1))
    return buffers, sample_buffers, see_through, exposure_reference, albedo


def _indirect_light(buffers: RenderBuffers, config: TofCameraConfig, *,
                    albedo: NDArray[np.float32] | None, pinhole: RenderBuffers,
                    room: Room | None,
                    spec: tuple[NDArray[np.float32], NDArray[np.float32]] | None,
                    see_through: RenderBuffers | None,
                    transmittance: NDArray[np.floating] | None,
                    illuminators: Sequence[Illuminator]) -> NDArray[np.float32] | None:
    """Multipath, mirror paths, returns through panes and other cameras' light, as planes.

    Added as phasors before read-out; None when there is none.
    """
    indirect = None
    if config.multipath:
        if albedo is None:
            raise ValueError("multipath needs the diffuse albedo of the render (albedo=...)")
        if config.multipath_model == "room" and room is None:
            raise ValueError("'room' multipath needs the scene's surfaces (room=...)")
        indirect = _multipath_planes(buffers, config, albedo, shadow_map=pinhole,
                                     room=room if config.multipath_model == "room" else None)
    if spec is not None:
        mirrored = _specular_planes(spec[0], spec[1], config)
        indirect = mirrored if indirect is None else indirect + mirrored
    if see_through is not None:
        if transmittance is None:
            raise ValueError("see_through needs the objects' transmittance (transmittance=...)")
        if see_through.shape != buffers.shape:
            raise ValueError("the see-through render must have the render's shape")
        through = _transmitted_planes(buffers, see_through, transmittance, config)
        indirect = through if indirect is None else indirect + through
    if illuminators:
        foreign = interference_planes(buffers, config, illuminators)
        indirect = foreign if indirect is None else indirect + foreign
    return indirect
