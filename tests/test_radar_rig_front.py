"""The rig's own front as a multipath reflector: radar → plate → rig front → plate → radar.

A flat aluminium plate faces the radar at range R. By the image method the real array sees
the plate's mirror image of the rig front (a flat plate a × b in the board plane) at 2R;
its amplitude is the radar equation at 2R for the monostatic flat-plate RCS
σ = 4π (a b)² / λ² (Knott, *Radar Cross Section*, normal incidence) × |Γ_plate|⁴ |Γ_front|²
(two reflections on the plate, one on the rig front). Tilting the plate by α about the
vertical: a point x along the rig front's width then has the unfolded round trip
2|x'| ≈ 4R + 2 x sin α (its image x' moves by sin α per unit x along the line of sight),
so the front's phase across its width runs as 2k x sin α and σ scales by
cos²α · sinc²(k a sin α), with its first null at sin α = λ / (2a).
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import pytest

from simcore.render import RenderRequest, SceneRenderer
from simcore.scene import Box, Pose, Project, SceneObject
from simcore.scene.materials import load_material_library
from simcore.scene.model import SensorRig
from simcore.scene.radar_config import SPEED_OF_LIGHT, RadarConfig
from simcore.scene.radar_presets import bgt60tr13c
from simcore.scene.snapshot import take_snapshot
from simcore.sensors.radar import radar_scatterers
from simcore.sensors.radar.equation import if_amplitude_fs
from simcore.sensors.radar.multipath import GhostSet, ghost_scatterers, synthesize_ghosts
from simcore.sensors.radar.scatterers import KIND_POINT_TARGET
from simcore.sensors.radar.scene import RadarScene

Renderer = Callable[..., SceneRenderer]

R, Z = 1.5, 1.0
THICK = 0.01


def scene(cfg: RadarConfig, *, tilt_deg: float = 0.0, lateral_m: float = 0.0) -> Project:
    """An aluminium plate 1 m × 1 m whose front face is R ahead of the radar (world +x),
    its centre ``lateral_m`` to the side."""
    plate = SceneObject(id=1, name="plate", geometry=Box(size_m=(THICK, 1.0, 1.0)),
                        pose=Pose(position_m=(R + THICK / 2, lateral_m, Z),
                                  rotation_deg=(0.0, 0.0, tilt_deg)),
                        material="aluminium")
    return Project(objects=[plate], rig=SensorRig(pose=Pose(position_m=(0.0, 0.0, Z)),
                                                   radar=cfg))


def ideal(**kw: object) -> RadarConfig:
    base: dict[str, object] = {
        "noise_variance_adc": 0.0, "leakage_dbc": None, "adc_bits": None,
        "if_highpass_hz": 0.0, "if_lowpass_hz": 0.0, "speckle": False,
        "multipath_order": 1, "render_width": 128, "render_height": 128}
    base.update(kw)
    return bgt60tr13c(**base)


def beat_range(cfg: RadarConfig, f_hz: np.ndarray) -> np.ndarray:
    """Range of a beat frequency: R = c f / (2 S)."""
    return SPEED_OF_LIGHT * f_hz / (2 * cfg.slope_hz_per_s)


def gamma_aluminium(cfg: RadarConfig) -> complex:
    """Normal-incidence Γ of aluminium × its Kirchhoff coherent factor exp(−(4πh/λ)²/2)."""
    band = load_material_library()["aluminium"].band("radar")
    g = 4 * np.pi * band.height_rms_m / cfg.wavelength_m
    return complex(band.coefficients(SPEED_OF_LIGHT / cfg.wavelength_m)[0]) * np.exp(-g * g / 2)


def rig_front_sets(make_renderer: Renderer, project: Project) -> list[GhostSet]:
    cfg = project.rig.radar
    snap = take_snapshot(project, 0.0)
    buf = make_renderer(project).render(
        snap, RenderRequest("radar", "radar", cfg.render_intrinsics()))
    sc = radar_scatterers(RadarScene.from_project(project, snap), buf, config=project.rig.radar)
    sets = ghost_scatterers(RadarScene.from_project(project, snap), sc, cfg, buffers=buf)
    return [g for g in sets if g.order == 2 and np.all(g.scatterers.kind == KIND_POINT_TARGET)]


def test_the_double_bounce_is_the_rig_front_image_at_twice_the_range(
        make_renderer: Renderer) -> None:
    cfg = ideal()
    sets = rig_front_sets(make_renderer, scene(cfg))
    assert len(sets) == 1 and len(sets[0].scatterers) == 1
    ghost = sets[0].scatterers
    assert float(np.linalg.norm(ghost.positions_m[0])) == pytest.approx(2 * R, abs=1e-9)
    a, b, lam = cfg.rig_front_width_m, cfg.rig_front_height_m, cfg.wavelength_m
    sigma = 4 * np.pi * (a * b) ** 2 / lam**2 * abs(gamma_aluminium(cfg)) ** 6
    assert ghost.rcs_m2[0] == pytest.approx(sigma, rel=1e-9)
    assert sets[0].reflector == 0                       # a ghost of the plate

    # Its IF: a tone at 2R, at the radar equation's amplitude for σ at 2R.
    y = synthesize_ghosts(sets, cfg)[0, 0]
    n, pad = cfg.samples_per_chirp, 16
    w = np.hanning(n)
    spec = np.abs(np.fft.rfft(y.real * w, n=pad * n)) / w.sum() * 2   # a tone of peak A → A
    ranges = beat_range(cfg, np.fft.rfftfreq(pad * n, 1 / cfg.sample_rate_hz))
    i = int(np.argmax(spec))
    print(f"peak at {ranges[i]:.4f} m (2R = {2 * R} m, bin {cfg.range_resolution_m:.4f} m)")
    assert abs(ranges[i] - 2 * R) < cfg.range_resolution_m
    expected = if_amplitude_fs(cfg, sigma, 1.0, 1.0, 2 * R, 2 * R)
    level_db = 20 * np.log10(spec[i] / expected)
    print(f"level {level_db:+.2f} dB from the radar equation")
    assert abs(level_db) < 1.0


def test_no_rig_front_no_double_bounce(make_renderer: Renderer) -> None:
    assert rig_front_sets(make_renderer, scene(ideal(rig_front_width_m=0.0))) == []
    # An absorbing rig front (a radome of absorber) returns nothing either.
    absorber = ideal(rig_front_material="radar_absorber")
    assert rig_front_sets(make_renderer, scene(absorber)) == []


def test_the_reflection_point_must_lie_on_the_plate(make_renderer: Renderer) -> None:
    """The foot of the perpendicular from the radar must be on the plate: shifted 0.4 m
    sideways (edge 0.1 m from it) the echo stays, 0.6 m (edge 0.1 m past it) it goes."""
    cfg = ideal()
    assert len(rig_front_sets(make_renderer, scene(cfg, lateral_m=0.4))) == 1
    assert rig_front_sets(make_renderer, scene(cfg, lateral_m=0.6)) == []


def test_a_tilted_plate_puts_the_rig_front_into_its_pattern_null(make_renderer: Renderer) -> None:
    """Tilt α about the vertical (module docstring): σ × cos²α sinc²(k a sin α)."""
    cfg = ideal()
    lam, a = cfg.wavelength_m, cfg.rig_front_width_m
    straight = rig_front_sets(make_renderer, scene(cfg))[0].scatterers.rcs_m2[0]
    null = np.degrees(np.arcsin(lam / (2 * a)))
    for alpha in (null, 0.5 * null, 0.25 * null):
        s = np.sin(np.radians(alpha))
        expected = (np.cos(np.radians(alpha)) * np.sin(2 * np.pi / lam * a * s)
                    / (2 * np.pi / lam * a * s)) ** 2
        sets = rig_front_sets(make_renderer, scene(cfg, tilt_deg=alpha))
        got = sets[0].scatterers.rcs_m2[0] / straight if sets else 0.0
        print(f"tilt {alpha:.3f}°: σ ratio {got:.4g} (expected {expected:.4g})")
        assert got == pytest.approx(expected, abs=1e-6)


def test_aluminium_plate_at_1_5_m_double_bounce_over_the_noise() -> None:
    """The full chain (thermal noise, leakage, IF filters, 12-bit ADC): the echo at 2R
    stands ≥ 10 dB over the noise floor with the rig front, and ≥ 20 dB lower without it."""
    from simcore.pipeline import Simulator

    snr = {}
    for front in (True, False):
        cfg = bgt60tr13c(multipath_order=1, render_width=128, render_height=128,
                         **({} if front else {"rig_front_width_m": 0.0}))
        with Simulator(scene(cfg)) as sim:
            adc = np.asarray(sim.frame(0).outputs["radar"].raw.adc, dtype=np.float64)
        n = adc.shape[-1]
        w = np.hanning(n)
        x = adc - adc.mean(axis=-1, keepdims=True)
        power = np.mean(np.abs(np.fft.rfft(x * w, axis=-1)) ** 2, axis=(0, 1))
        ranges = beat_range(cfg, np.fft.rfftfreq(n, 1 / cfg.sample_rate_hz))
        floor = np.median(power[(ranges > 3.5) & (ranges < 6.0)])
        near = np.abs(ranges - 2 * R) <= cfg.range_resolution_m
        snr[front] = 10 * np.log10(power[near].max() / floor)
        at = ranges[near][np.argmax(power[near])]
        print(f"rig front {front}: {snr[front]:.1f} dB over the noise at {at:.3f} m")
        if front:
            assert abs(at - 2 * R) <= cfg.range_resolution_m
    assert snr[True] >= 10.0
    assert snr[True] - snr[False] >= 20.0


def test_older_projects_get_the_rig_front_by_default() -> None:
    """A version-1 project (written before the field existed) migrates to the default
    rig front, the 25 mm × 25 mm aluminium board front."""
    from pathlib import Path

    from simcore.scene.project_io import load_project

    old = load_project(Path(__file__).parent / "data" / "old_projects" / "v1_office.json")
    radar = old.rig.radar
    assert (radar.rig_front_width_m, radar.rig_front_height_m) == (0.025, 0.025)
    assert radar.rig_front_material == "aluminium"
