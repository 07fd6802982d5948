"""Radar surfaces (issue #15): physical-optics facets against the PO and optics formulas.

Every expected value is computed here from textbook formulas (Knott, *Radar Cross
Section*): a flat plate of area A at normal incidence has σ = 4πA²/λ², its pattern in one
plane is σ(θ) = σ₀ [cos θ · sinc(k a sin θ)]² (first null at sin θ = λ/(2a)); a large
sphere has σ = πr². The power of a target at range R comes from the radar equation
(``radar_equation_amplitude``, written independently in ``test_radar_scene``).
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import pytest
from test_radar_scene import (
    IDEAL,
    radar_equation_amplitude,
    range_spectrum,
    transfer_matrix_transmission,
)

from simcore.render import RenderRequest, SceneRenderer
from simcore.resources import example_path
from simcore.scene import Box, Pose, Project, SceneObject, Sphere, load_project
from simcore.scene.geometry import CornerReflector
from simcore.scene.model import SensorRig
from simcore.scene.motion import Motion
from simcore.scene.project_io import material_table
from simcore.scene.radar_config import SPEED_OF_LIGHT, RadarConfig
from simcore.scene.snapshot import take_snapshot
from simcore.sensors.radar import radar_scatterers, simulate_radar
from simcore.sensors.radar.scatterers import KIND_CORNER_REFLECTOR
from simcore.sensors.radar.scene import RadarScene
from simcore.sensors.radar.sensor import RadarSensor

Renderer = Callable[..., SceneRenderer]


def one_object(geometry: object, distance_m: float, *, material: str = "aluminium",
               yaw_deg: float = 0.0) -> Project:
    return Project(objects=[SceneObject(
        id=1, name="target", geometry=geometry, material=material,
        pose=Pose(position_m=(distance_m, 0.0, 0.0), rotation_deg=(0.0, 0.0, yaw_deg)))],
        rig=SensorRig())


def peak_dbfs(make_renderer: Renderer, project: Project, cfg: RadarConfig, *, seed: int = 0,
              t: float = 0.0) -> float:
    """Largest range-FFT magnitude of chirp 0, channel 1 (Rx at the Tx) in dBFS."""
    renderer = make_renderer(project)
    snap = take_snapshot(project, t)
    sensor = RadarSensor()
    request = RenderRequest("radar", "radar", cfg.render_intrinsics(), geometry_only=True)
    buffers = renderer.render(snap, request)
    hide = sensor.see_through(project)
    through = None if hide is None else renderer.render(snap, request, hide=hide)
    scat = radar_scatterers(RadarScene.from_project(project, snap), buffers, config=cfg, seed=seed,
                            see_through=through)
    out = simulate_radar(scat, cfg, rng=np.random.default_rng(0))
    spec = range_spectrum(out.adc[0, 1].astype(np.float64), 16)
    return float(20 * np.log10(np.abs(spec).max()))


def highpass_db(cfg: RadarConfig, r: float) -> float:
    """First-order high-pass |H| at the beat frequency of range r (dB)."""
    x = (cfg.slope_hz_per_s * 2 * r / SPEED_OF_LIGHT) / cfg.if_highpass_hz
    return float(10 * np.log10(x**2 / (1 + x**2)))


@pytest.mark.parametrize(("side", "distance"), [(0.05, 3.0), (0.10, 6.0)])
def test_plate_at_normal_incidence_gives_4_pi_a2_over_lambda2(make_renderer: Renderer,
                                                               side: float,
                                                               distance: float) -> None:
    project = one_object(Box(size_m=(0.002, side, side)), distance)
    cfg = project.rig.radar.model_copy(update={**IDEAL, "if_highpass_hz": 80e3,
                                               "if_highpass_order": 1})
    r = distance - 0.001                                   # the plate's front face
    sigma = 4 * np.pi * side**4 / cfg.wavelength_m**2
    expected = 20 * np.log10(radar_equation_amplitude(cfg, sigma, r, 1.0)) + highpass_db(cfg, r)
    peaks = [peak_dbfs(make_renderer, project, cfg, seed=s) for s in range(4)]
    print(f"{side * 100:.0f} cm plate at {distance} m: {np.round(np.array(peaks) - expected, 3)}"
          " dB from 4πA²/λ²")
    assert max(abs(p - expected) for p in peaks) <= 1.0
    assert max(peaks) - min(peaks) <= 1.0


def test_plate_pattern_follows_the_po_sinc_to_its_first_null(make_renderer: Renderer) -> None:
    """A 5 cm plate at 3 m (beyond its far-field distance 2a²/λ = 1 m) turned about z."""
    side, distance = 0.05, 3.0
    base = one_object(Box(size_m=(0.002, side, side)), distance)
    cfg = base.rig.radar.model_copy(update=IDEAL)
    k = 2 * np.pi / cfg.wavelength_m
    null = np.degrees(np.arcsin(cfg.wavelength_m / (2 * side)))
    ref = peak_dbfs(make_renderer, base, cfg)
    for frac in (0.25, 0.5, 0.7):
        theta = frac * null
        x = k * side * np.sin(np.radians(theta))
        expected = 20 * np.log10(np.cos(np.radians(theta)) * np.sin(x) / x)
        got = peak_dbfs(make_renderer, one_object(Box(size_m=(0.002, side, side)), distance,
                                                  yaw_deg=theta), cfg) - ref
        print(f"{theta:.2f}°: {got:+.2f} dB (PO {expected:+.2f} dB)")
        assert abs(got - expected) <= 1.0
    at_null = peak_dbfs(make_renderer, one_object(Box(size_m=(0.002, side, side)), distance,
                                                  yaw_deg=null), cfg) - ref
    print(f"first null {null:.2f}°: {at_null:+.1f} dB")
    assert at_null < -20.0


def test_metal_sphere_gives_pi_r2(make_renderer: Renderer) -> None:
    radius, distance = 0.10, 3.0
    project = one_object(Sphere(radius_m=radius), distance)
    cfg = project.rig.radar.model_copy(update=IDEAL)
    r = distance - radius
    expected = 20 * np.log10(radar_equation_amplitude(cfg, np.pi * radius**2, r, 1.0))
    peaks = [peak_dbfs(make_renderer, project, cfg, seed=s) for s in range(3)]
    print(f"sphere: {np.round(np.array(peaks) - expected, 3)} dB from πr²")
    assert max(abs(p - expected) for p in peaks) <= 1.5


@pytest.mark.parametrize("which", ["wall", "plate"])
def test_doubling_the_render_grid_changes_nothing(make_renderer: Renderer, which: str) -> None:
    if which == "wall":
        project = load_project(example_path("wall"))
    else:
        project = one_object(Box(size_m=(0.002, 0.1, 0.1)), 3.0)
    cfg = project.rig.radar.model_copy(update={**IDEAL, "speckle": True})
    fine = cfg.model_copy(update={"render_width": 2 * cfg.render_width,
                                  "render_height": 2 * cfg.render_height})
    coarse_db, fine_db = (peak_dbfs(make_renderer, project, c) for c in (cfg, fine))
    print(f"{which}: {coarse_db:.3f} dBFS at {cfg.render_width} px, {fine_db:.3f} at "
          f"{fine.render_width} px")
    assert abs(fine_db - coarse_db) <= 0.5


def test_static_sphere_keeps_its_power_under_a_moving_rig(make_renderer: Renderer) -> None:
    """20 frames of a rig moving 2 cm per frame sideways: only R⁻⁴ and the pattern change."""
    radius, distance, step = 0.10, 3.0, 0.02
    sphere = SceneObject(id=1, name="sphere", geometry=Sphere(radius_m=radius),
                         pose=Pose(position_m=(distance, 0.0, 0.0)), material="aluminium")
    rig = SensorRig(motion=Motion(velocity_mps=(0.0, step / 0.1, 0.0)))
    project = Project(objects=[sphere], rig=rig)
    cfg = project.rig.radar.model_copy(update=IDEAL)
    q = cfg.element_pattern.exponent_az
    corrected = []
    for frame in range(20):
        t = 0.1 * frame
        offset = np.array([distance, -step * frame, 0.0])
        r = float(np.linalg.norm(offset)) - radius
        az = np.arctan2(offset[1], offset[0])
        model = 20 * np.log10(radar_equation_amplitude(cfg, np.pi * radius**2, r,
                                                       np.cos(az) ** (2 * q)))
        corrected.append(peak_dbfs(make_renderer, project, cfg, t=t) - model)
    steps = np.abs(np.diff(corrected))
    print(f"frame-to-frame change beyond R⁻⁴ and pattern: max {steps.max():.3f} dB")
    assert steps.max() <= 1.0


def test_office_floor_clutter_stands_above_the_noise(make_renderer: Renderer) -> None:
    """The floor between 1.5 and 2.3 m is inside the antennas' field of view: its clutter
    must be well above the receiver noise (≥ 12 dB), not cut off by the render."""
    project = load_project(example_path("office"))
    cfg = project.rig.radar
    renderer = make_renderer(project)
    snap = take_snapshot(project, 0.0)
    request = RadarSensor().render_request(project)
    buffers = renderer.render(snap, request)
    through = renderer.render(snap, request, hide=RadarSensor().see_through(project))
    names = [o.name for o in project.objects]
    scat = radar_scatterers(RadarScene.from_project(project, snap), buffers, see_through=through,
                            config=project.rig.radar)
    floor = scat.subset(scat.object_index == names.index("floor"))
    with_floor = simulate_radar(floor, cfg, rng=np.random.default_rng(1))
    noise_only = simulate_radar(floor.subset(np.zeros(len(floor), bool)), cfg,
                                rng=np.random.default_rng(2))
    pad = 1
    bins = np.fft.rfftfreq(cfg.samples_per_chirp * pad, 1 / cfg.sample_rate_hz) * (
        SPEED_OF_LIGHT / (2 * cfg.slope_hz_per_s))
    band = (bins >= 1.5) & (bins <= 2.3)

    def profile(out: object) -> np.ndarray:
        spec = range_spectrum(out.adc.astype(np.float64), pad)   # type: ignore[attr-defined]
        return (np.abs(spec) ** 2).mean(axis=(0, 1))

    rise = 10 * np.log10(profile(with_floor)[band].mean() / profile(noise_only)[band].mean())
    print(f"floor clutter 1.5–2.3 m: {rise:.1f} dB over the noise")
    assert rise >= 12.0


@pytest.mark.parametrize(("material", "max_loss_db"), [("glass", 10.0), ("aluminium", None)])
def test_pane_in_front_of_a_corner_reflector(make_renderer: Renderer, material: str,
                                             max_loss_db: float | None) -> None:
    """A glass pane costs its computed two-way transmission (≤ 10 dB); metal ≥ 30 dB."""
    reflector = SceneObject(id=1, name="cr", geometry=CornerReflector(edge_m=0.06),
                            pose=Pose(position_m=(3.0, 0.0, 0.0), rotation_deg=(0, -90, 0)),
                            material="radar_retroreflector")
    pane = SceneObject(id=2, name="pane", geometry=Box(size_m=(0.004, 1.0, 1.0)),
                       pose=Pose(position_m=(1.5, 0.0, 0.0)), material=material)
    open_project = Project(objects=[reflector], rig=SensorRig())
    cfg = open_project.rig.radar.model_copy(update=IDEAL)

    def reflector_power(project: Project) -> float:
        renderer = make_renderer(project)
        snap = take_snapshot(project, 0.0)
        request = RadarSensor().render_request(project)
        buffers = renderer.render(snap, request)
        hide = RadarSensor().see_through(project)
        through = None if hide is None else renderer.render(snap, request, hide=hide)
        scat = radar_scatterers(RadarScene.from_project(project, snap), buffers, config=cfg,
                                see_through=through)
        return float(scat.rcs_m2[scat.kind == KIND_CORNER_REFLECTOR].sum())

    open_rcs = reflector_power(open_project)
    assert open_rcs > 0
    behind = reflector_power(Project(objects=[reflector, pane], rig=SensorRig()))
    loss_db = 10 * np.log10(open_rcs / behind) if behind > 0 else np.inf
    print(f"{material}: two-way loss {loss_db:.2f} dB")
    if max_loss_db is None:
        assert loss_db >= 30.0
        return
    band = material_table(open_project)[material].band("radar")
    t = transfer_matrix_transmission(band.permittivity, band.loss_tangent, band.thickness_m,
                                     SPEED_OF_LIGHT / cfg.wavelength_m)
    expected = -40 * np.log10(abs(t))
    assert abs(loss_db - expected) <= 1.0
    assert loss_db <= max_loss_db
