"""Fresnel TE/TM reflection at oblique incidence against published values.

Glass (n = 1.5, lossless) in air: at 45° the reflectances are R_s = 9.20 % and
R_p = 0.85 %, at normal incidence 4 % for both, zero for p at Brewster's angle
arctan 1.5 = 56.31° (Hecht, *Optics*, 5th ed., §4.6.2 and Fig. 4.50; Born & Wolf,
*Principles of Optics*, §1.5.2). The slab at normal incidence is
:func:`~simcore.scene.materials.slab_coefficients`.
"""

from __future__ import annotations

import numpy as np
import pytest

from simcore.scene.materials import BandMaterial, oblique_slab_coefficients, slab_coefficients
from simcore.sensors.radar.multipath import Reflector, polarised_reflection

F = 60e9


def test_glass_reflectances_are_the_published_ones() -> None:
    cos = np.cos(np.radians([0.0, 45.0, np.degrees(np.arctan(1.5)), 89.999]))
    r_te, r_tm = oblique_slab_coefficients(2.25, 0.0, None, F, cos)
    np.testing.assert_allclose(np.abs(r_te[:2]) ** 2, [0.0400, 0.0920], atol=5e-5)
    np.testing.assert_allclose(np.abs(r_tm[:2]) ** 2, [0.0400, 0.0085], atol=5e-5)
    assert abs(r_tm[2]) < 1e-12                                    # Brewster
    np.testing.assert_allclose([r_te[3], r_tm[3]], [-1.0, -1.0], atol=1e-3)   # grazing
    # Signs (Born & Wolf): r_TE = (1 − n)/(1 + n) = −r_TM at normal incidence.
    assert r_te[0] == pytest.approx(-0.2) and r_tm[0] == pytest.approx(0.2)


@pytest.mark.parametrize("thickness", [None, 0.004, 0.018])
def test_the_oblique_slab_at_normal_incidence_is_the_slab(thickness: float | None) -> None:
    r_te, r_tm = oblique_slab_coefficients(6.31, 0.041, thickness, F, np.array([1.0]))
    gamma, _ = slab_coefficients(6.31, 0.041, thickness, F)
    assert complex(r_te[0]) == pytest.approx(gamma, abs=1e-12)
    assert complex(r_tm[0]) == pytest.approx(-gamma, abs=1e-12)


def test_a_thin_slab_is_transparent_where_its_round_trip_is_a_whole_wavelength() -> None:
    """Half-wave slab: Γ = 0 when 2 k₀ d √(n² − sin²θ) = 2π, for both polarisations."""
    n2, theta = 4.0, np.radians(30.0)
    kappa = np.sqrt(n2 - np.sin(theta) ** 2)
    d = 299_792_458.0 / F / (2.0 * kappa)
    r_te, r_tm = oblique_slab_coefficients(n2, 0.0, d, F, np.array([np.cos(theta)]))
    assert abs(r_te[0]) < 1e-12 and abs(r_tm[0]) < 1e-12


def _wall(normal: np.ndarray, band: BandMaterial) -> Reflector:
    return Reflector(0, np.zeros(3), np.eye(3)[:2], np.ones(2), normal, False, -1.0 + 0j, 0.0,
                     0.0, band=band, frequency_hz=F)


def test_co_polar_reflection_of_metal_and_dielectric_faces() -> None:
    """Radar frame (y down): E along y (V) or x (H); a side wall x = const, a floor y = const."""
    metal = BandMaterial(metallic=1.0)
    v, h = np.array([0.0, 1.0, 0.0]), np.array([1.0, 0.0, 0.0])
    side = _wall(np.array([-1.0, 0.0, 0.0]), metal)
    floor = _wall(np.array([0.0, -1.0, 0.0]), metal)
    grazing_side = np.array([[np.sin(0.01), 0.0, np.cos(0.01)]])
    grazing_floor = np.array([[0.0, np.sin(0.01), np.cos(0.01)]])
    # E parallel to the metal (V on a side wall, H over a floor): the image dipole is −p.
    assert polarised_reflection(side, grazing_side, v)[0] == pytest.approx(-1.0)
    assert polarised_reflection(floor, grazing_floor, h)[0] == pytest.approx(-1.0)
    # E normal to the metal (V over a floor at grazing): the image dipole is +p.
    assert polarised_reflection(floor, grazing_floor, v)[0] == pytest.approx(1.0, abs=1e-3)
    # Normal incidence: the material's Γ for either polarisation.
    concrete = BandMaterial(permittivity=5.24, loss_tangent=0.065)
    front = _wall(np.array([0.0, 0.0, -1.0]), concrete)
    gamma, _ = concrete.coefficients(F)
    for pol in (v, h):
        assert complex(polarised_reflection(front, np.array([[0.0, 0.0, 1.0]]), pol)[0]) \
            == pytest.approx(gamma)
    # A dielectric floor at grazing cancels both polarisations (Γ → −1).
    for pol in (v, h):
        floor_c = _wall(np.array([0.0, -1.0, 0.0]), concrete)
        assert polarised_reflection(floor_c, grazing_floor, pol)[0] == pytest.approx(-1, abs=0.05)


@pytest.mark.parametrize("cos_theta", [1.0, 0.8, 0.4, 0.1])
def test_a_lossless_slab_conserves_energy_at_every_angle(cos_theta: float) -> None:
    """|Γ|² + |T|² = 1 for a lossless slab, TE and TM, at any angle (glass 4 mm, 63 GHz);
    at normal incidence T is the normal-incidence slab's."""
    from simcore.scene.materials import (
        oblique_slab_coefficients,
        oblique_slab_transmission,
        slab_coefficients,
    )

    c = np.array([cos_theta])
    gammas = oblique_slab_coefficients(2.25, 0.0, 0.004, 63e9, c)
    trans = oblique_slab_transmission(2.25, 0.0, 0.004, 63e9, c)
    for g, t in zip(gammas, trans, strict=True):
        np.testing.assert_allclose(abs(g[0]) ** 2 + abs(t[0]) ** 2, 1.0, atol=1e-12)
    if cos_theta == 1.0:
        np.testing.assert_allclose(trans[0][0], slab_coefficients(2.25, 0.0, 0.004, 63e9)[1],
                                   atol=1e-12)
