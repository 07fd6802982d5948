"""The physical-optics return of a flat plate against the exact PO integral and the image.

A square perfectly conducting plate of side ``L`` faces the radar at distance ``d`` on
boresight. Its PO return, in the radar equation's terms (the sum of the facets'
``a e^{j 2k r} / r²``, the IF phasor of each facet at the carrier, without antenna gains),
must equal the exact PO integral over the plate,

    S = ∫∫ j (2√π / λ) (−Γ) cos θ e^{j 2k r} / r² dA,     r = √(x² + y² + d²),

(here by quadrature on a 0.5 mm grid) within 1 dB, and its phase must be the image
method's: an infinite plane returns ``Γ √π d e^{j 2k d} / d²`` (the image of the radar at
``2d``, radar cross-section ``π d²``), which the plate approaches once it spans several
Fresnel zones (``√(λ d / 2)`` ≈ 0.05–0.1 m here).
"""

from __future__ import annotations

import numpy as np
import pytest

from simcore.render import RenderRequest, SceneRenderer
from simcore.scene import Box, Pose, Project, SceneObject
from simcore.scene.materials import BandMaterial, DualBandMaterial
from simcore.scene.model import SensorRig
from simcore.scene.snapshot import take_snapshot
from simcore.sensors.radar.scatterers import _object_meshes
from simcore.sensors.radar.scene import RadarScene
from simcore.sensors.radar.surfaces import facet_returns

SIDE_M = 1.2
#: A perfect conductor with no diffuse part: the return is PO alone.
PEC = DualBandMaterial(name="pec", bands={"radar": BandMaterial(
    reflectance=0.0, specular=0.0, metallic=1.0)})


def plate_return(d: float) -> tuple[complex, float]:
    """The facets' summed return of the plate at ``d`` (m), and the wavelength."""
    project = Project(
        objects=[SceneObject(id=1, name="plate", geometry=Box(size_m=(0.002, SIDE_M, SIDE_M)),
                             material="pec", pose=Pose(position_m=(d + 0.001, 0.0, 0.0)))],
        materials=[PEC], rig=SensorRig())
    cfg = project.rig.radar
    snap = take_snapshot(project, 0.0)
    renderer = SceneRenderer(project)
    try:
        buffers = renderer.render(snap, RenderRequest("radar", "radar", cfg.render_intrinsics(),
                                                      geometry_only=True))
    finally:
        renderer.close()
    lam = cfg.wavelength_m
    found = facet_returns(RadarScene.from_project(project, snap), buffers,
                          _object_meshes(project.objects, buffers), wavelength_m=lam,
                          speckle=False)
    r = np.linalg.norm(found.positions_m, axis=1)
    k = 2.0 * np.pi / lam
    return complex(np.sum(found.amplitude * np.exp(2j * k * r) / r**2)), lam


def exact_po(d: float, lam: float, *, step_m: float = 5e-4) -> complex:
    """The PO integral over the plate (Γ = −1) by the midpoint rule."""
    k = 2.0 * np.pi / lam
    n = round(SIDE_M / step_m)
    x = (np.arange(n) + 0.5) / n * SIDE_M - SIDE_M / 2
    total = 0j
    for xs in np.array_split(x, 40):
        gx, gy = np.meshgrid(xs, x, indexing="ij")
        r = np.sqrt(gx**2 + gy**2 + d**2)
        total += np.sum((d / r) * np.exp(2j * k * r) / r**2)
    return complex(1j * 2.0 * np.sqrt(np.pi) / lam * total * (SIDE_M / n) ** 2)


def image_return(d: float, lam: float) -> complex:
    """An infinite metal plane's return (Γ = −1): the image of the radar at ``2d``."""
    k = 2.0 * np.pi / lam
    return complex(-np.sqrt(np.pi) * d * np.exp(2j * k * d) / d**2)


@pytest.mark.parametrize("d", [1.0, 2.0, 3.0, 4.0])
def test_plate_po_level_is_the_exact_integral_and_its_phase_the_image(d: float) -> None:
    facets, lam = plate_return(d)
    exact = exact_po(d, lam)
    image = image_return(d, lam)
    level_db = 20.0 * np.log10(abs(facets) / abs(exact))
    phase_deg = np.degrees(np.angle(facets / image))
    print(f"d = {d} m: facets − exact PO {level_db:+.2f} dB, phase − image {phase_deg:+.1f}°, "
          f"exact − image {np.degrees(np.angle(exact / image)):+.1f}°")
    assert abs(level_db) < 1.0
    assert abs(phase_deg) < 10.0


def test_the_exact_po_integral_of_a_large_plate_is_its_image() -> None:
    """The reference itself: the stationary-phase limit of PO is the image (the factor j)."""
    lam = 299_792_458.0 / 60e9
    for d in (1.0, 2.0):
        ratio = exact_po(d, lam) / image_return(d, lam)
        assert abs(20 * np.log10(abs(ratio))) < 1.0
        assert abs(np.degrees(np.angle(ratio))) < 5.0
