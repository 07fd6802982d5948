"""Dual-band materials: one parameter set for the ToF near-infrared band, one for radar.

The same reflectance model is used in both bands, evaluated per pixel in float precision
from the incidence angle (the sensors are monostatic, so the half-vector is the viewing
direction)::

    f(theta) = (1 - metallic) * reflectance * cos(theta)
             + specular * exp(-tan(theta)**2 / roughness**2) / (roughness**2 * cos(theta)**4)
             + retro_gain          (only for retroreflectors, angle independent)

For the ToF band ``f`` is the fraction of the illumination returned towards the camera
per unit solid angle times pi (a white Lambertian wall at normal incidence gives 1).
For the radar band ``f`` is the normalised radar cross-section per unit area sigma0 (m²/m²).
The specular term is the Beckmann/Kirchhoff rough-surface lobe with rms slope
``roughness``; ``metallic`` removes the diffuse part. ``opacity`` 0 removes the object
from that band's render pass entirely (the band sees through it).
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
from numpy.typing import NDArray
from pydantic import Field, ValidationError

from simcore.resources import MATERIALS_FILE
from simcore.scene.base import Fraction, Model, NonNegative


class BandMaterial(Model):
    """Reflectance parameters of a material in one band (ToF near-IR or radar)."""

    reflectance: Fraction = 0.5
    specular: NonNegative = 0.0
    roughness: float = Field(0.3, ge=0.01, le=2.0, allow_inf_nan=False)
    metallic: Fraction = 0.0
    opacity: Fraction = 1.0
    retroreflector: bool = False
    retro_gain: NonNegative = 0.0


class DualBandMaterial(Model):
    """A material with independent ToF and radar parameters."""

    name: str = Field(min_length=1)
    description: str = ""
    tof: BandMaterial = BandMaterial()
    radar: BandMaterial = BandMaterial()

    def band(self, band: str) -> BandMaterial:
        """Return the parameters of ``band`` ("tof" or "radar")."""
        if band == "tof":
            return self.tof
        if band == "radar":
            return self.radar
        raise ValueError(f"unknown band {band!r}; expected 'tof' or 'radar'")


class MaterialLibraryError(ValueError):
    """The material library file is unreadable or invalid."""


_LIBRARY_CACHE: dict[tuple[str, int, int], dict[str, DualBandMaterial]] = {}


def load_material_library(path: Path = MATERIALS_FILE) -> dict[str, DualBandMaterial]:
    """Load a material library JSON file (``{"materials": [...]}``) keyed by name.

    The parsed file is cached until it changes on disk; each call returns fresh copies,
    so callers may edit what they get.
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
    return {name: m.model_copy(deep=True) for name, m in _LIBRARY_CACHE[key].items()}


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
