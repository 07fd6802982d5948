"""ToF partial transmission (issue 15): a camera looking through a glass pane.

Scene: a white wall 2 m ahead of the camera and a pane 1 m ahead, both facing it. The
expected values come from the incoherent slab formula written out here (interface
reflectance R = ((n − 1)/(n + 1))², one-pass transmittance T = (1 − R)²/(1 − R²)), from the
geometry (ranges along the pixel rays) and from the phasor sum of the two returns.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from simcore.render import RenderBuffers, SceneRenderer
from simcore.scene import Box, Plane, Pose, Project, SceneObject
from simcore.scene.materials import BandMaterial, DualBandMaterial, load_material_library
from simcore.scene.model import SensorRig
from simcore.scene.snapshot import take_snapshot
from simcore.scene.tof_config import SPEED_OF_LIGHT, TofCameraConfig
from simcore.sensors.radar.sensor import RadarSensor
from simcore.sensors.radar.surfaces import transmission_coefficients
from simcore.sensors.tof.camera import TofOutput, simulate_tof
from simcore.sensors.tof.sensor import TofSensor, transmittance

RIG_HEIGHT_M = 1.0
WALL_M, PANE_M = 2.0, 1.0
CFG = TofCameraConfig(crosstalk_sigma_px=0.0, modulation_frequencies_hz=(20e6,))


def glass_t() -> float:
    """One-pass near-IR power transmittance of the library's glass, from its index."""
    band = load_material_library()["glass"].band("tof")
    assert band.permittivity is not None
    n = math.sqrt(band.permittivity)
    r = ((n - 1) / (n + 1)) ** 2
    return (1 - r) ** 2 / (1 - r * r)


def facing(oid: int, name: str, distance_m: float, size_m: float, material: str) -> SceneObject:
    return SceneObject(id=oid, name=name, geometry=Plane(size_m=(size_m, size_m)),
                       pose=Pose(position_m=(distance_m, 0.0, RIG_HEIGHT_M),
                                 rotation_deg=(0.0, 90.0, 0.0)), material=material)


def project_with(pane: str | None, materials: list[DualBandMaterial] | None = None) -> Project:
    objects = [facing(1, "wall", WALL_M, 20.0, "white_paint")]
    if pane is not None:
        objects.append(SceneObject(id=2, name="pane", geometry=Box(size_m=(0.004, 8.0, 8.0)),
                                   pose=Pose(position_m=(PANE_M + 0.002, 0.0, RIG_HEIGHT_M)),
                                   material=pane))
    return Project(objects=objects, materials=materials or [],
                   rig=SensorRig(pose=Pose(position_m=(0.0, 0.0, RIG_HEIGHT_M)), tof=CFG))


def run(project: Project) -> tuple[TofOutput, RenderBuffers]:
    """The ToF frame the sensor plug-in would compute (render, see-through render)."""
    sensor = TofSensor()
    renderer = SceneRenderer(project)
    try:
        snap = take_snapshot(project, 0.0)
        request = sensor.render_request(project)
        buffers = renderer.render(snap, request)
        hide = sensor.see_through(project)
        through = None if hide is None else renderer.render(snap, request, hide=hide)
    finally:
        renderer.close()
    out = simulate_tof(buffers, project.rig.tof, rng=np.random.default_rng(0), noise=False,
                       see_through=through,
                       transmittance=None if through is None else transmittance(project))
    return out, buffers


def ray_geometry(cfg: TofCameraConfig) -> tuple[np.ndarray, np.ndarray]:
    """|(x/z, y/z, 1)| and tan of the off-axis angle at every sensor pixel centre."""
    fx = 0.5 * cfg.width / math.tan(math.radians(cfg.fov_h_deg) / 2)
    fy = 0.5 * cfg.height / math.tan(math.radians(cfg.fov_v_deg) / 2)
    u = (np.arange(cfg.width) + 0.5 - cfg.width / 2) / fx
    v = (np.arange(cfg.height) + 0.5 - cfg.height / 2) / fy
    tan2 = u[None, :] ** 2 + v[:, None] ** 2
    return np.sqrt(1.0 + tan2), np.sqrt(tan2)


def test_the_sensor_sees_through_glass_only() -> None:
    assert TofSensor().see_through(project_with("glass")) == (False, True)
    assert TofSensor().see_through(project_with("white_paint")) is None
    assert TofSensor().see_through(project_with(None)) is None


def test_through_a_glass_pane_the_camera_measures_the_wall() -> None:
    norm, tan = ray_geometry(CFG)
    open_out, _ = run(project_with(None))
    out, buffers = run(project_with("glass"))
    # Ground truth: the first surface hit, the pane.
    assert np.nanmax(np.abs(out.gt_range - PANE_M * norm)) < 5e-3
    assert np.all(out.gt_object_id == 2)
    # Off the pane's specular spot (> 12° off its normal, where its smooth-glass lobe is
    # < 1e-4 of the wall's return) the camera measures the wall at 2 m ...
    away = (tan > math.tan(math.radians(12))) & open_out.valid
    assert away.sum() > 1000
    assert out.valid[away].all()
    err = out.depth_m[away] - WALL_M * norm[away]
    print(f"depth error through glass: max {np.abs(err).max() * 1e3:.2f} mm")
    assert np.abs(err).max() < 2e-3
    # ... at the wall's amplitude times the two-way transmission T².
    ratio = out.amplitude[away] / open_out.amplitude[away]
    expected = glass_t() ** 2
    print(f"amplitude ratio {ratio.mean():.4f} (T² = {expected:.4f})")
    assert np.allclose(ratio, expected, rtol=2e-3)
    # Near normal incidence the pane reflects the illuminator: the pane's own return
    # dominates there (saturated, or a depth pulled towards the pane).
    centre = tan < math.tan(math.radians(1))
    pulled = ~out.valid[centre] | (out.depth_m[centre] < 1.5 * norm[centre])
    assert pulled.all()


def test_an_opaque_pane_hides_the_wall() -> None:
    norm, _ = ray_geometry(CFG)
    out, _ = run(project_with("white_paint"))
    ok = out.valid
    assert ok.sum() > 0.9 * ok.size
    assert np.abs(out.depth_m[ok] - PANE_M * norm[ok]).max() < 2e-3


def test_a_mixed_pixel_has_the_phase_of_the_phasor_sum() -> None:
    """A frosted pane (diffuse near-IR reflectance 0.1, transmitting like glass): each
    pixel measures the phase of the pane's and the wall's returns added as phasors."""
    frosted = DualBandMaterial(name="frosted", bands={"tof": BandMaterial(
        reflectance=0.1, roughness=1.0, permittivity=2.3, thickness_m=0.004)})
    norm, tan = ray_geometry(CFG)
    out, _ = run(project_with("frosted", [frosted]))
    n = math.sqrt(2.3)
    r = ((n - 1) / (n + 1)) ** 2
    t2 = ((1 - r) ** 2 / (1 - r * r)) ** 2
    cos = 1.0 / norm

    def response(rho: float, spec: float, m: float) -> np.ndarray:
        tan2 = tan**2
        return rho * cos + spec * np.exp(-tan2 / m**2) / (m**2 * cos**4)

    r1, r2 = PANE_M * norm, WALL_M * norm
    pane = response(0.1, 0.0, 1.0) / r1**2
    wall = response(0.85, 0.01, 0.6) * t2 / r2**2
    k = 4 * np.pi * CFG.modulation_frequencies_hz[0] / SPEED_OF_LIGHT
    phasor = pane * np.exp(1j * k * r1) + wall * np.exp(1j * k * r2)
    expected = np.mod(np.angle(phasor), 2 * np.pi) / k
    ok = out.valid
    assert ok.sum() > 0.9 * ok.size
    err = out.depth_m[ok] - expected[ok]
    print(f"mixed depth {out.depth_m[ok].min():.3f}..{out.depth_m[ok].max():.3f} m, "
          f"max error {np.abs(err).max() * 1e3:.2f} mm")
    # Strictly between the two surfaces, as the phasor sum says (sub-pixel averaging
    # of the slowly varying geometry inside a pixel: well under a millimetre).
    assert np.all(out.depth_m[ok] > r1[ok] + 0.1) and np.all(out.depth_m[ok] < r2[ok] - 0.1)
    assert np.abs(err).max() < 1e-3


@pytest.mark.parametrize("material", ["glass", "white_paint"])
def test_the_radar_band_is_unchanged(material: str) -> None:
    """The radar's see-through objects and transmission do not read the ToF band."""
    project = project_with(material)
    table = load_material_library()
    stripped = {name: m.model_copy(update={"bands": {b: v for b, v in m.bands.items()
                                                      if b != "tof"}})
                for name, m in table.items()}
    wavelength = project.rig.radar.wavelength_m
    np.testing.assert_array_equal(transmission_coefficients(project.objects, table, wavelength),
                                  transmission_coefficients(project.objects, stripped, wavelength))
    expected = (False, True) if material == "glass" else None
    assert RadarSensor().see_through(project) == expected


def test_the_engine_gives_the_sensor_its_see_through_pass() -> None:
    """Through the engine (plug-in, see-through render): the same frame as by hand."""
    from simcore.pipeline import Simulator

    project = project_with("glass")
    by_hand, _ = run(project)
    with Simulator(project) as sim:
        frame = sim.frame(0)
    assert "tof" in frame.see_through
    out = frame.outputs["tof"]
    assert isinstance(out, TofOutput)
    norm, tan = ray_geometry(CFG)
    away = (tan > math.tan(math.radians(12))) & out.valid & by_hand.valid
    assert away.sum() > 1000
    # The engine's camera is noisy: compare means (shot noise averages out over the pixels).
    ratio = out.amplitude[away].mean() / by_hand.amplitude[away].mean()
    assert abs(ratio - 1.0) < 0.01
    assert np.median(np.abs(out.depth_m[away] - WALL_M * norm[away])) < 0.02


def test_float_glass_glint_is_narrow_as_its_beckmann_lobe_predicts() -> None:
    """The pane's own return is the lobe ``F exp(−tan²θ/m²) / (m² cos⁴θ)`` of the library's
    roughness m, which for smooth float glass confines the glint to within 1° of the pane's
    normal (its 1/e² half-width is ``atan(m √2)``)."""
    band = load_material_library()["glass"].band("tof")
    m = band.roughness
    half_width_deg = math.degrees(math.atan(m * math.sqrt(2)))
    assert half_width_deg < 1.0
    project = project_with("glass")
    sensor = TofSensor()
    renderer = SceneRenderer(project)
    try:
        buffers = renderer.render(take_snapshot(project, 0.0), sensor.render_request(project))
    finally:
        renderer.close()
    pane = buffers.object_index == 1            # index of the pane (second object)
    assert pane.all()
    pts = buffers.points_m
    cos = np.abs(pts[..., 2]) / np.linalg.norm(pts, axis=-1)   # the pane faces the camera
    tan2 = (1 - cos**2) / cos**2
    lobe = band.specular * np.exp(-tan2 / m**2) / (m**2 * cos**4)
    # The exponent tan²θ/m² magnifies the float32 cosine's rounding (1e-7 / m² ≈ 1e-3).
    np.testing.assert_allclose(buffers.intensity, lobe, rtol=1e-2, atol=1e-6 * lobe.max())
    glint = buffers.intensity > buffers.intensity.max() * math.exp(-2)
    tilt = np.degrees(np.arccos(cos[glint]))
    print(f"glint: {glint.sum()} render px, up to {tilt.max():.2f}° "
          f"(1/e² half-width {half_width_deg:.2f}°)")
    assert 0 < glint.sum() and tilt.max() <= half_width_deg
