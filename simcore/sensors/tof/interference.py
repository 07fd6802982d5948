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

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from simcore.render.buffers import RenderBuffers
from simcore.scene.tof_config import PLANCK, SPEED_OF_LIGHT, TofCameraConfig


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


def hopped_config(config: TofCameraConfig, frame_number: int) -> TofCameraConfig:
    """The camera as it modulates in its frame ``frame_number`` (frequency hopping).

    Every modulation frequency raised by ``c × hop_step_hz``, ``c`` drawn from
    ``numpy.random.default_rng((hop_seed, frame_number))``; ``config`` itself without
    hopping.
    """
    if config.hop_channels <= 1 or config.hop_step_hz <= 0:
        return config
    rng = np.random.default_rng((int(config.hop_seed), int(frame_number) & 0x7FFFFFFF))
    shift = int(rng.integers(config.hop_channels)) * config.hop_step_hz
    return config.model_copy(update={"modulation_frequencies_hz": [
        f + shift for f in config.modulation_frequencies_hz]})


def light_windows_s(config: TofCameraConfig) -> NDArray[np.float64]:
    """The four correlation samples' exposures from the capture time, shape (4, 2) (s).

    Sample ``i`` is exposed from ``i × sample_interval_s`` for ``exposure_time_s`` (the
    camera's illumination is on then).
    """
    starts = np.arange(4) * config.sample_interval_s
    return np.stack([starts, starts + config.exposure_time_s], axis=1)


def overlap_fraction(victim: TofCameraConfig, aggressor: TofCameraConfig,
                     aggressor_start_s: float) -> float:
    """Part of the victim's exposure during which the aggressor's light is on.

    Mean over the victim's four correlation samples of the time its exposure overlaps
    any of the aggressor's (aggressor capture ``aggressor_start_s`` after the victim's),
    over the exposure time. 0: time multiplexed.
    """
    own = light_windows_s(victim)
    other = light_windows_s(aggressor) + aggressor_start_s
    total = 0.0
    for lo, hi in own:
        for a_lo, a_hi in other:
            total += max(0.0, min(hi, a_hi) - max(lo, a_lo))
    return float(min(1.0, total / (4.0 * victim.exposure_time_s)))


@dataclass(frozen=True)
class Illuminator:
    """Another camera's modulated light during a victim frame.

    Attributes
    ----------
    config : TofCameraConfig
        The other camera in that frame (its hopped frequencies, its exposure windows).
    pose : ndarray, shape (4, 4)
        Its optical frame (x right, y down, z forward) → world.
    start_s : float
        Its capture time minus the victim's (s).
    """

    config: TofCameraConfig
    pose: NDArray[np.float64]
    start_s: float

    def key(self) -> bytes:
        """Cache key."""
        return (self.config.model_dump_json().encode() + self.pose.tobytes()
                + np.float64(self.start_s).tobytes())


def interference_planes(buffers: RenderBuffers, config: TofCameraConfig,
                        illuminators: Sequence[Illuminator]) -> NDArray[np.float32]:
    """Other cameras' light in the victim's pixels, as offset and phasor planes (e⁻).

    For each illuminator and each victim pixel that shows a surface point ``P`` (one
    render sub-pixel per pixel, the one at ``(k//2, k//2)`` of its block: the foreign
    light varies slowly, and this is ``k²`` times cheaper than every sub-pixel): the
    point is lit if it lies in the illuminator's field of view (its emitter fills it, like
    the victim's own) and faces it; its irradiance
    ``E = I_a cos θ_a / d_a²`` (``I_a`` = power / illuminated solid angle) makes a
    Lambertian radiance ``ρ E / π``, with ``ρ cos θ_v`` the render's response ``f`` seen
    from the victim (``ρ = f / cos θ_v``). Electrons per correlation sample
    ``S_a = f (cos θ_a / cos θ_v) (I_a / π) · electrons_per_radiance / d_a²``, path
    ``L = d_a + R``. The victim's phasor gains
    ``m S_a c(Δf, T, ρ) e^{j (2π f_a L / c + θ)}`` (``c`` =
    :func:`cross_correlation_factor` of the frequencies and the exposure overlap ``ρ``,
    ``θ = −2π f_a · start_s``, the aggressor's modulation starting later) and its offset
    ``ρ S_a`` (the photons: shot noise at any frequency).

    Direct light: when the illuminator's emitter is in the victim's view, unoccluded, and
    the victim in the illuminator's field, the emitter adds to the pixel it images
    ``I_a / d² × aperture area`` (a point source through the lens:
    ``π (f / 2N)²``, ``f`` the focal length) times exposure, quantum efficiency and
    photons per joule, over the path ``d``.

    Not modelled: whether the illuminator itself sees ``P`` (occlusion on its side);
    multipath of the foreign light; the sum-frequency term.

    Parameters
    ----------
    buffers : RenderBuffers
        The victim's supersampled render (``points_m``, ``normals``, ``cos_incidence``,
        ``intensity``, ``range_m``, ``sensor``).
    config : TofCameraConfig
        The victim in this frame (hopped frequencies, this frame's exposure).
    illuminators : sequence of Illuminator
        The other cameras whose light falls in the frame.

    Returns
    -------
    ndarray, shape (1 + 2F, H, W), float32
        Offset, then (re, im) per modulation frequency, at sensor resolution.
    """
    freqs = config.modulation_frequencies_hz
    h, w_px = config.height, config.width
    victim = _victim_pixels(buffers, config.supersampling)
    planes = np.zeros((1 + 2 * len(freqs), h * w_px), np.float64)
    for ill in illuminators:
        rho = overlap_fraction(config, ill.config, ill.start_s)
        if rho <= 0:
            continue
        view = _emitter_view(ill, buffers.sensor.transform)
        cs = [cross_correlation_factor(f_v, _paired(ill.config, j),
                                       exposure_s=config.exposure_time_s,
                                       overlap_fraction=rho) for j, f_v in enumerate(freqs)]
        light = _Light(ill, cs, config.demodulation_contrast, rho)
        _add_lit_surfaces(planes, victim, view, light, config)
        _add_direct_light(planes, buffers, victim.hit_full, view, light, config)
    return planes.reshape(-1, h, w_px).astype(np.float32)


@dataclass(frozen=True)
class _VictimPixels:
    """The victim's pixels that show a surface, one render sub-pixel each, optical frame."""

    hit_full: NDArray[np.bool_]     # (Hs, Ws) render sub-pixels that show a surface
    idx: NDArray[np.intp]           # (n,) flat sensor pixels that do
    points: NDArray[np.float32]     # (n, 3) their surface points (m)
    normals: NDArray[np.float32]    # (n, 3)
    range_m: NDArray[np.float32]    # (n,)
    response: NDArray[np.float32]   # (n,) the render's response ``f``
    cos_v: NDArray[np.float32]      # (n,) cosine of incidence from the victim, ≥ 0.05


def _victim_pixels(buffers: RenderBuffers, k: int) -> _VictimPixels:
    """The sub-pixel at ``(k//2, k//2)`` of each sensor pixel's block that shows a surface.

    The foreign light varies slowly over the scene, and this is k² times cheaper than
    every sub-pixel.
    """
    o = k // 2
    hit_full = (buffers.object_index >= 0) & np.isfinite(buffers.range_m)
    hit = hit_full[o::k, o::k].reshape(-1)
    idx = np.flatnonzero(hit)

    def pick(a: NDArray[np.generic], last: int | None = None) -> NDArray[np.float32]:
        """The chosen sub-pixels' values of a render buffer."""
        v = np.asarray(a, np.float32)[o::k, o::k]
        return v.reshape(-1, last)[idx] if last else v.reshape(-1)[idx]

    return _VictimPixels(hit_full, idx, pick(buffers.points_m, 3), pick(buffers.normals, 3),
                         pick(buffers.range_m), pick(buffers.intensity),
                         np.maximum(pick(buffers.cos_incidence), np.float32(0.05)))


@dataclass(frozen=True)
class _EmitterView:
    """An illuminator's emitter seen from the victim's optical frame."""

    position: NDArray[np.float64]   # (3,) emitter position (m)
    rotation: NDArray[np.float64]   # (3, 3) its axes
    intensity_w_sr: float           # radiant intensity I_a (W/sr)
    tan_h: float                    # tangent of its half field of view, horizontal
    tan_v: float                    # and vertical


def _emitter_view(ill: Illuminator, victim_pose: NDArray[np.float64]) -> _EmitterView:
    """Illuminator ``ill``'s emitter in the frame of the victim at ``victim_pose``."""
    rot, origin = victim_pose[:3, :3], victim_pose[:3, 3]
    return _EmitterView(
        (ill.pose[:3, 3] - origin) @ rot, rot.T @ ill.pose[:3, :3],
        ill.config.illumination_power_w / ill.config.illumination_solid_angle_sr,
        np.tan(np.radians(ill.config.fov_h_deg) / 2),
        np.tan(np.radians(ill.config.fov_v_deg) / 2))


@dataclass(frozen=True)
class _Light:
    """What a pixel's phasor gains per electron of an illuminator's light."""

    ill: Illuminator
    cs: list[complex]               # cross-correlation factor per victim frequency
    contrast: float                 # the victim's demodulation contrast m
    rho: float                      # exposure overlap fraction

    def add(self, planes: NDArray[np.float64], where: NDArray[np.intp] | int,
            electrons: NDArray[np.float64] | float, path_m: NDArray[np.float64] | float
            ) -> None:
        """Add ``electrons`` over paths ``path_m`` to the offset and phasor planes."""
        planes[0, where] += self.rho * electrons
        for j in range(len(self.cs)):
            f_a = _paired(self.ill.config, j)
            phase = 2 * np.pi * f_a * (path_m / SPEED_OF_LIGHT - self.ill.start_s)
            ph = self.contrast * electrons * self.cs[j] * np.exp(1j * phase)
            planes[1 + 2 * j, where] += ph.real
            planes[2 + 2 * j, where] += ph.imag


def _add_lit_surfaces(planes: NDArray[np.float64], victim: _VictimPixels, view: _EmitterView,
                      light: _Light, config: TofCameraConfig) -> None:
    """The emitter's light scattered by the surfaces in its field that face it."""
    w = victim.points - view.position.astype(np.float32)
    d_a = np.maximum(np.sqrt(np.einsum("ij,ij->i", w, w)), np.float32(1e-3))
    loc = w @ view.rotation.astype(np.float32)
    z = loc[:, 2]
    lit = (z > 0) & (np.abs(loc[:, 0]) <= view.tan_h * z) & (np.abs(loc[:, 1]) <= view.tan_v * z)
    cos_a = -np.einsum("ij,ij->i", victim.normals, w) / d_a
    lit &= cos_a > 0
    sel = np.flatnonzero(lit)
    if not sel.size:
        return
    da = d_a[sel].astype(np.float64)
    s_a = (victim.response[sel] * cos_a[sel] / victim.cos_v[sel]).astype(np.float64) * (
        view.intensity_w_sr / np.pi * config.electrons_per_radiance) / da**2
    light.add(planes, victim.idx[sel], s_a, da + victim.range_m[sel])


def _add_direct_light(planes: NDArray[np.float64], buffers: RenderBuffers,
                      hit_full: NDArray[np.bool_], view: _EmitterView, light: _Light,
                      config: TofCameraConfig) -> None:
    """The emitter itself in the victim's view, unoccluded, the victim in its field."""
    a_pos = view.position
    d = float(np.linalg.norm(a_pos))
    b_loc = -a_pos @ view.rotation                    # victim in the emitter's frame
    if not (a_pos[2] > 0 and b_loc[2] > 0 and abs(b_loc[0]) <= view.tan_h * b_loc[2]
            and abs(b_loc[1]) <= view.tan_v * b_loc[2]):
        return
    hs, ws = buffers.shape
    intr = buffers.intrinsics
    col = int(np.floor(intr.fx * a_pos[0] / a_pos[2] + intr.cx))
    row = int(np.floor(intr.fy * a_pos[1] / a_pos[2] + intr.cy))
    if not (0 <= row < hs and 0 <= col < ws) or (
            hit_full[row, col] and buffers.range_m[row, col] < d - 1e-3):
        return
    k = config.supersampling
    focal = config.intrinsics().fx * config.pixel_pitch_um * 1e-6
    aperture = np.pi * (focal / (2 * config.f_number)) ** 2
    photons = config.wavelength_nm * 1e-9 / (PLANCK * SPEED_OF_LIGHT)
    e = (view.intensity_w_sr / d**2 * aperture * config.exposure_time_s
         * config.quantum_efficiency * photons)
    light.add(planes, (row // k) * config.width + col // k, e, d)


def _paired(aggressor: TofCameraConfig, j: int) -> float:
    """The aggressor's modulation frequency met by the victim's ``j``-th."""
    freqs = aggressor.modulation_frequencies_hz
    return float(freqs[min(j, len(freqs) - 1)])


__all__ = [
    "Illuminator",
    "cross_correlation_factor",
    "extra_shot_noise_variance",
    "hopped_config",
    "interference_planes",
    "light_windows_s",
    "overlap_fraction",
    "interfered_phasor",
    "path_phase_rad",
    "phasor_depth_m",
]
