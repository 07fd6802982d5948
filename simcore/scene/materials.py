"""Materials: one reflectance parameter set per band, keyed by band name.

Each sensor renders in one band (:data:`BANDS`: the ToF camera's near infrared, the radar's
60 GHz, the RGB camera's visible light); a material holds one :class:`BandMaterial` per
band it sets and falls back to the default parameters for the others. A material may be
bright in one band and dark or transparent in another ("dual-band" materials).

The same reflectance model is used in both bands, evaluated per pixel in float precision
from the incidence angle (the sensors are monostatic, so the half-vector is the viewing
direction)::

    f(theta) = (1 - metallic) * reflectance * cos(theta)
             + specular * exp(-tan(theta)**2 / roughness**2) / (roughness**2 * cos(theta)**4)
             + retro_gain          (only for retroreflectors, angle independent)

For the ToF and visible bands ``f`` is the fraction of the illumination returned towards the camera
per unit solid angle times pi (a white Lambertian wall at normal incidence gives 1).
For the radar band ``f`` is the normalised radar cross-section per unit area sigma0 (m²/m²).
The specular term is the Beckmann/Kirchhoff rough-surface lobe with rms slope
``roughness``; ``metallic`` removes the diffuse part. ``opacity`` 0 removes the object
from that band's render pass entirely (the band sees through it).

Smooth interfaces (radar band, :mod:`simcore.sensors.radar.scatterers`): a band material
with a ``permittivity`` (or ``metallic`` = 1, a perfect conductor) also reflects
*coherently*, with the Fresnel reflection coefficient of its interface at normal incidence
(:func:`slab_coefficients`), reduced by its rms surface height ``height_rms_m`` as in the
Kirchhoff model (coherent power factor ``exp(-(2 k h cos θ)²)``); the rough-surface lobe above
then carries only the incoherent remainder ``1 − exp(-(2 k h cos θ)²)``. With a
``thickness_m`` the material is a slab that transmits: the band sees what lies behind it,
attenuated by the slab's transmission coefficient on the way in and out.
"""

from __future__ import annotations

import cmath
import json
import math
from pathlib import Path

import numpy as np
from numpy.typing import NDArray
from pydantic import Field, ValidationError, field_validator

from simcore.resources import MATERIALS_FILE
from simcore.scene.base import Fraction, Model, NonNegative

#: The bands materials describe: band name → what it is. A sensor renders in one of them.
BANDS: dict[str, str] = {
    "tof": "near infrared of the ToF camera's illumination (850–940 nm)",
    "radar": "the radar's carrier band (60 GHz)",
    "visible": "visible light, seen by the RGB camera",
}


class BandMaterial(Model):
    """Reflectance parameters of a material in one band."""

    reflectance: Fraction = 0.5
    specular: NonNegative = 0.0
    roughness: float = Field(0.3, ge=0.01, le=2.0, allow_inf_nan=False)
    metallic: Fraction = 0.0
    opacity: Fraction = 1.0
    retroreflector: bool = False
    retro_gain: NonNegative = 0.0
    permittivity: float | None = Field(
        None, ge=1.0, le=1000.0, allow_inf_nan=False,
        description="relative permittivity ε′ in this band; None: no smooth interface "
                    "(incoherent lobe only)")
    loss_tangent: float = Field(0.0, ge=0.0, le=100.0, allow_inf_nan=False,
                                description="dielectric loss tangent tan δ = ε″/ε′")
    thickness_m: float | None = Field(
        None, gt=0.0, le=1.0, allow_inf_nan=False,
        description="slab thickness (m); None: thick (nothing is transmitted)")
    height_rms_m: float = Field(0.0, ge=0.0, le=0.1, allow_inf_nan=False,
                                description="rms surface height (m): removes coherent "
                                            "reflection, 0 = smooth")

    def is_smooth_interface(self) -> bool:
        """Whether the material reflects coherently (a permittivity, or a metal)."""
        return self.permittivity is not None or self.metallic >= 1.0

    def coefficients(self, frequency_hz: float) -> tuple[complex, complex]:
        """(reflection Γ, one-way transmission T) at normal incidence, at ``frequency_hz``.

        A metal (``metallic`` = 1) gives (−1, 0); a material without a permittivity gives
        (0, 0) for a thick object and (0, 1) when ``thickness_m`` is set (no interface
        model: an invisible sheet); otherwise :func:`slab_coefficients`. T is relative to
        the same path through air (the phase of the extra electrical length included).
        """
        if self.metallic >= 1.0:
            return -1.0 + 0j, 0j
        if self.permittivity is None:
            return 0j, (1.0 + 0j) if self.thickness_m is not None else 0j
        return slab_coefficients(self.permittivity, self.loss_tangent, self.thickness_m,
                                 frequency_hz)

    def oblique_coefficients(self, frequency_hz: float, cos_theta: NDArray[np.floating]
                             ) -> tuple[NDArray[np.complex128], NDArray[np.complex128]]:
        """Reflection (Γ_TE, Γ_TM) at incidence angles θ (``cos_theta``), Born & Wolf signs.

        A metal gives (−1, +1); a material without a permittivity (0, 0); otherwise
        :func:`oblique_slab_coefficients` (the same slab as :meth:`coefficients`, at the
        angle). At normal incidence Γ_TE = :meth:`coefficients`' Γ = −Γ_TM.
        """
        c = np.asarray(cos_theta, dtype=np.float64)
        if self.metallic >= 1.0:
            return np.full(c.shape, -1.0 + 0j), np.full(c.shape, 1.0 + 0j)
        if self.permittivity is None:
            zero = np.zeros(c.shape, dtype=np.complex128)
            return zero, zero.copy()
        return oblique_slab_coefficients(self.permittivity, self.loss_tangent,
                                         self.thickness_m, frequency_hz, c)

    def coherent_factor(self, cos_theta: NDArray[np.floating], wavelength_m: float
                        ) -> NDArray[np.float64]:
        """Kirchhoff coherent power fraction ``exp(-(4π h cos θ / λ)²)`` of a rough interface."""
        g = (4.0 * math.pi * self.height_rms_m / wavelength_m
             * np.asarray(cos_theta, dtype=np.float64))
        return np.exp(-g * g)


RGB = tuple[Fraction, Fraction, Fraction]


class DualBandMaterial(Model):
    """A material: independent parameters per band, and its colour in visible light.

    ``bands`` maps band names (:data:`BANDS`) to parameters; a band left out uses the
    default :class:`BandMaterial` (opaque, reflectance 0.5). ``color_rgb`` is the linear
    RGB albedo that tints the visible band (the RGB camera's colour).
    """

    name: str = Field(min_length=1)
    description: str = ""
    color_rgb: RGB = (0.6, 0.6, 0.6)
    bands: dict[str, BandMaterial] = Field(default_factory=dict)

    @field_validator("bands")
    @classmethod
    def _known_bands(cls, bands: dict[str, BandMaterial]) -> dict[str, BandMaterial]:
        unknown = sorted(set(bands) - set(BANDS))
        if unknown:
            raise ValueError(f"unknown band {unknown[0]!r}; known bands: {', '.join(BANDS)}")
        return bands

    def band(self, band: str) -> BandMaterial:
        """Parameters of ``band`` (the defaults where the material does not set it)."""
        if band not in BANDS:
            raise ValueError(f"unknown band {band!r}; known bands: {', '.join(BANDS)}")
        return self.bands.get(band, _DEFAULT_BAND)


_DEFAULT_BAND = BandMaterial()


class MaterialLibraryError(ValueError):
    """The material library file is unreadable or invalid."""


_LIBRARY_CACHE: dict[tuple[str, int, int], dict[str, DualBandMaterial]] = {}


def load_material_library(path: Path = MATERIALS_FILE, *, copy: bool = True
                          ) -> dict[str, DualBandMaterial]:
    """Load a material library JSON file (``{"materials": [...]}``) keyed by name.

    The parsed file is cached until it changes on disk; each call returns fresh copies,
    so callers may edit what they get; ``copy=False`` returns the cached models themselves
    (for readers only: a frame reads the table several times, a deep copy costs ≈ 2 ms).
    """
    try:
        stat = Path(path).stat()
        key = (str(path), stat.st_mtime_ns, stat.st_size)
        if key not in _LIBRARY_CACHE:
            data = json.loads(Path(path).read_text(encoding="utf-8"))
            materials = [DualBandMaterial.model_validate(m) for m in data["materials"]]
            _LIBRARY_CACHE.clear()
            _LIBRARY_CACHE[key] = {m.name: m for m in materials}
    except (OSError, json.JSONDecodeError, KeyError, TypeError, ValidationError) as exc:
        raise MaterialLibraryError(f"material library {path}: {exc}") from exc
    if not copy:
        return dict(_LIBRARY_CACHE[key])
    return {name: m.model_copy(deep=True) for name, m in _LIBRARY_CACHE[key].items()}


def slab_coefficients(permittivity: float, loss_tangent: float, thickness_m: float | None,
                      frequency_hz: float) -> tuple[complex, complex]:
    """Reflection and transmission of a dielectric half-space or slab at normal incidence.

    With the complex refractive index ``n = √(ε′ (1 − j tan δ))``, the single interface
    reflects ``r = (1 − n) / (1 + n)``. A slab of thickness ``d`` (one-way phase
    ``δ = k₀ n d``) reflects and transmits, summing its internal reflections
    (Born & Wolf §1.6; Orfanidis, *Electromagnetic Waves and Antennas*, §6.1)::

        Γ = r (1 − e^{−2jδ}) / (1 − r² e^{−2jδ})
        T = (1 − r²) e^{−jδ} / (1 − r² e^{−2jδ}) · e^{+j k₀ d}

    (T relative to the same path through air). A half-space (``thickness_m`` None)
    transmits nothing.

    Parameters
    ----------
    permittivity : float
        Real relative permittivity ε′ (≥ 1).
    loss_tangent : float
        tan δ = ε″ / ε′ (≥ 0).
    thickness_m : float or None
        Slab thickness d (m), or None for a half-space.
    frequency_hz : float
        Frequency (Hz).

    Returns
    -------
    (complex, complex)
        Γ and T (amplitude ratios; e^{+jωt} convention).
    """
    n = cmath.sqrt(permittivity * (1.0 - 1j * loss_tangent))
    r = (1.0 - n) / (1.0 + n)
    if thickness_m is None:
        return r, 0j
    k0 = 2.0 * math.pi * frequency_hz / 299_792_458.0
    e1 = cmath.exp(-1j * k0 * n * thickness_m)
    e2 = e1 * e1
    den = 1.0 - r * r * e2
    gamma = r * (1.0 - e2) / den
    trans = (1.0 - r * r) * e1 / den * cmath.exp(1j * k0 * thickness_m)
    return gamma, trans


def oblique_slab_coefficients(permittivity: float, loss_tangent: float,
                              thickness_m: float | None, frequency_hz: float,
                              cos_theta: NDArray[np.floating]
                              ) -> tuple[NDArray[np.complex128], NDArray[np.complex128]]:
    """Fresnel reflection of a dielectric half-space or slab at oblique incidence, TE and TM.

    With ``n = √(ε′ (1 − j tan δ))`` and ``κ = √(n² − sin²θ)`` (n cos θ_t), the interface
    reflects (Born & Wolf, *Principles of Optics*, §1.5.2, eqs. 21a–b; field amplitudes,
    the TM reflected field's reference direction mirrored)::

        r_TE = (cos θ − κ) / (cos θ + κ)        r_TM = (n² cos θ − κ) / (n² cos θ + κ)

    and a slab of thickness ``d`` (one-way phase ``δ = k₀ κ d``) sums its internal
    reflections as at normal incidence (Orfanidis, *Electromagnetic Waves and Antennas*,
    §7.6): ``Γ = r (1 − e^{−2jδ}) / (1 − r² e^{−2jδ})`` for each polarisation. At θ = 0
    r_TE = (1 − n)/(1 + n) (:func:`slab_coefficients`) and r_TM = −r_TE; r_TM vanishes at
    Brewster's angle ``tan θ_B = n`` (lossless).

    Parameters
    ----------
    permittivity, loss_tangent : float
        ε′ and tan δ.
    thickness_m : float or None
        Slab thickness (m); None: a half-space.
    frequency_hz : float
        Frequency (Hz).
    cos_theta : ndarray
        Cosines of the incidence angles (from the normal), any shape.

    Returns
    -------
    (ndarray, ndarray), complex128, the shape of ``cos_theta``
        Γ_TE and Γ_TM.
    """
    c = np.clip(np.asarray(cos_theta, dtype=np.float64), 0.0, 1.0)
    n2 = permittivity * (1.0 - 1j * loss_tangent)
    kappa = np.sqrt(n2 - (1.0 - c * c) + 0j)
    r_te = (c - kappa) / (c + kappa)
    r_tm = (n2 * c - kappa) / (n2 * c + kappa)
    if thickness_m is None:
        return r_te, r_tm
    k0 = 2.0 * math.pi * frequency_hz / 299_792_458.0
    e2 = np.exp(-2j * k0 * kappa * thickness_m)
    return (r_te * (1.0 - e2) / (1.0 - r_te * r_te * e2),
            r_tm * (1.0 - e2) / (1.0 - r_tm * r_tm * e2))


def oblique_slab_transmission(permittivity: float, loss_tangent: float, thickness_m: float,
                              frequency_hz: float, cos_theta: NDArray[np.floating]
                              ) -> tuple[NDArray[np.complex128], NDArray[np.complex128]]:
    """One-way transmission of a slab at oblique incidence, TE and TM, relative to air.

    The slab of :func:`oblique_slab_coefficients` (interface ``r`` per polarisation,
    one-way phase ``δ = k₀ κ d``) transmits, summing its internal reflections (Airy;
    Stokes: ``t t′ = 1 − r²``)::

        T = (1 − r²) e^{−jδ} / (1 − r² e^{−2jδ}) · e^{+j k₀ d cos θ}

    the last factor the phase of the same straight path through air (the ray is not
    displaced: a thin sheet). At θ = 0 both equal :func:`slab_coefficients`' T.

    Returns
    -------
    (ndarray, ndarray), complex128, the shape of ``cos_theta``
        T_TE and T_TM.
    """
    c = np.clip(np.asarray(cos_theta, dtype=np.float64), 0.0, 1.0)
    n2 = permittivity * (1.0 - 1j * loss_tangent)
    kappa = np.sqrt(n2 - (1.0 - c * c) + 0j)
    k0 = 2.0 * math.pi * frequency_hz / 299_792_458.0
    e1 = np.exp(-1j * k0 * kappa * thickness_m)
    air = np.exp(1j * k0 * thickness_m * c)
    out = []
    for r in ((c - kappa) / (c + kappa), (n2 * c - kappa) / (n2 * c + kappa)):
        out.append((1.0 - r * r) * e1 / (1.0 - r * r * e1 * e1) * air)
    return out[0], out[1]


def summarize_band(band: str, m: BandMaterial, radar_frequency_hz: float = 60e9) -> str:
    """One phrase on what ``m`` does in ``band``, computed from its values (not prose).

    The radar band names the normal-incidence reflection |Γ| and the two-way transmission
    of :meth:`BandMaterial.coefficients` at ``radar_frequency_hz``.
    """
    if m.opacity == 0.0:
        return "invisible"
    parts = []
    if m.metallic >= 1.0:
        parts.append("metal")
    elif (1.0 - m.metallic) * m.reflectance >= 0.005:
        parts.append(f"diffuse {(1.0 - m.metallic) * m.reflectance:.2f}")
    if m.specular > 0:
        parts.append(f"specular {m.specular:.2f} (roughness {m.roughness:.2f})")
    if m.retroreflector or m.retro_gain > 0:
        parts.append("retro-reflector" + (f" (gain {m.retro_gain:g})" if m.retro_gain else ""))
    if band == "radar":
        gamma, trans = m.coefficients(radar_frequency_hz)
        if abs(gamma) >= 1e-3:                   # −60 dB: below that, no reflection
            parts.append(f"|Γ| {abs(gamma):.2f} ({20 * math.log10(abs(gamma)):.1f} dB)")
        if abs(trans) > 0:
            loss = max(-40 * math.log10(abs(trans)), 0.0) + 0.0      # no "−0.0"
            parts.append(f"transmits, {loss:.1f} dB two-way loss")
    if m.opacity < 1.0:
        parts.append(f"opacity {m.opacity:.2f}")
    return ", ".join(parts) or "black (no return)"


def summarize_material(material: DualBandMaterial, radar_frequency_hz: float = 60e9) -> str:
    """What the material does in each band, from its current values (:func:`summarize_band`)."""
    names = {"tof": "ToF", "radar": "radar", "visible": "visible"}
    return "; ".join(f"{names[b]}: {summarize_band(b, material.band(b), radar_frequency_hz)}"
                     for b in BANDS)


def band_response(
    cos_theta: NDArray[np.floating],
    *,
    reflectance: NDArray[np.floating] | float,
    specular: NDArray[np.floating] | float,
    roughness: NDArray[np.floating] | float,
    metallic: NDArray[np.floating] | float,
    retro_gain: NDArray[np.floating] | float = 0.0,
) -> NDArray[np.float32]:
    """Evaluate the monostatic reflectance model of the module docstring.

    Parameters
    ----------
    cos_theta : ndarray, shape (...)
        Cosine of the incidence angle (between surface normal and the direction back to
        the sensor), in [0, 1].
    reflectance, specular, roughness, metallic, retro_gain : ndarray or float
        Material parameters, broadcastable to ``cos_theta``.

    Returns
    -------
    ndarray, shape (...), float32
        Band response ``f(theta)`` (dimensionless).
    """
    c = np.clip(np.asarray(cos_theta, dtype=np.float64), 1e-6, 1.0)
    m2 = np.asarray(roughness, dtype=np.float64) ** 2
    tan2 = (1.0 - c * c) / (c * c)
    diffuse = (1.0 - np.asarray(metallic)) * np.asarray(reflectance) * c
    lobe = np.asarray(specular) * np.exp(-tan2 / m2) / (m2 * c**4)
    return (diffuse + lobe + np.asarray(retro_gain)).astype(np.float32)
