"""Radar front end on rendered scenes: the example projects' known answers (headless)."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import pytest
from numpy.testing import assert_allclose

from simcore.render import PinholeIntrinsics, RenderBuffers, RenderRequest, SceneRenderer
from simcore.resources import example_path
from simcore.scene import Box, PointTarget, Pose, Project, SceneObject, load_project
from simcore.scene.model import SensorRig
from simcore.scene.project_io import material_table
from simcore.scene.radar_config import SPEED_OF_LIGHT, RadarConfig
from simcore.scene.snapshot import SceneSnapshot, take_snapshot
from simcore.sensors.radar import radar_scatterers, simulate_radar
from simcore.sensors.radar.scatterers import KIND_CORNER_REFLECTOR, KIND_POINT_TARGET
from simcore.sensors.radar.scene import RadarScene

IDEAL = {"noise_variance_adc": 0.0, "leakage_dbc": None, "adc_bits": None,
         "if_highpass_hz": 0.0, "if_lowpass_hz": 0.0}

Renderer = Callable[..., SceneRenderer]


def radar_render(renderer: SceneRenderer, project: Project, config: RadarConfig, t: float = 0.0
                 ) -> tuple[SceneSnapshot, RenderBuffers]:
    snap = take_snapshot(project, t)
    return snap, renderer.render(snap, RenderRequest("radar", "radar", config.render_intrinsics()))


def transfer_matrix_transmission(eps_r: float, loss_tangent: float, thickness_m: float,
                                 frequency_hz: float, cos_theta: float = 1.0,
                                 polarization: str = "TE") -> complex:
    """One-way transmission of a slab in air at incidence ``θ`` (transfer matrices).

    The ABCD matrix of a line section of wave impedance Z and length d,
    ``[[cos δ, j Z sin δ], [j sin δ / Z, cos δ]]`` with δ = k₀ d √(n² − sin²θ), between two
    air half spaces of impedance Z₀ gives ``T = 2 / (A + B/Z₀ + C Z₀ + D)`` (TE: Z = η/cos θ
    in each medium, TM: Z = η cos θ, θ the medium's own angle); relative to the same
    straight path through air it is multiplied by e^{+j k₀ d cos θ}. (Independent of the
    Airy-sum form in the code.)
    """
    n = np.sqrt(eps_r * (1 - 1j * loss_tangent))
    k0 = 2 * np.pi * frequency_hz / SPEED_OF_LIGHT
    sin2 = 1 - cos_theta**2
    cos_t = np.sqrt(n * n - sin2) / n
    delta = k0 * n * cos_t * thickness_m
    eta0 = 376.730313668
    eta = eta0 / n
    if polarization == "TE":
        z0, z = eta0 / cos_theta, eta / cos_t
    else:
        z0, z = eta0 * cos_theta, eta * cos_t
    a, b = np.cos(delta), 1j * z * np.sin(delta)
    c, d = 1j * np.sin(delta) / z, np.cos(delta)
    return complex(2 / (a + b / z0 + c * z0 + d) * np.exp(1j * k0 * thickness_m * cos_theta))


def box_crossings(start: np.ndarray, end: np.ndarray, center: np.ndarray, size: np.ndarray
                  ) -> list[np.ndarray]:
    """Outward normals of an axis-aligned box's faces that the segment start → end crosses,
    in order (the slab method: entry and exit per axis)."""
    d = end - start
    lo, hi = center - size / 2, center + size / 2
    t_in, t_out, n_in, n_out = 0.0, 1.0, None, None
    for k in range(3):
        t1, t2 = (lo[k] - start[k]) / d[k], (hi[k] - start[k]) / d[k]
        s1, s2 = -1.0, 1.0
        if t1 > t2:
            t1, t2, s1, s2 = t2, t1, s2, s1
        if t1 > t_in:
            t_in, n_in = t1, s1 * np.eye(3)[k]
        if t2 < t_out:
            t_out, n_out = t2, s2 * np.eye(3)[k]
    return [n for n, t in ((n_in, t_in), (n_out, t_out)) if n is not None and 0 < t < 1]


def radar_position(project: Project) -> np.ndarray:
    """Radar origin in the world for an unrotated rig (positions add)."""
    return (np.asarray(project.rig.pose.position_m)
            + np.asarray(project.rig.radar.pose_on_rig.position_m))


def range_spectrum(x: np.ndarray, pad: int = 16) -> np.ndarray:
    """Hann-windowed, zero-padded real FFT scaled so a real tone of amplitude A peaks at A."""
    n = x.shape[-1]
    w = np.hanning(n)
    return np.fft.rfft(x * w, n=pad * n, axis=-1) / (w.sum() / 2)


def radar_equation_amplitude(cfg: RadarConfig, rcs: float, r: float, gain: float) -> float:
    """IF amplitude (FS) of a monostatic target from the radar equation, independently."""
    p_t = 1e-3 * 10 ** (cfg.tx_power_dbm / 10)
    g = 10 ** ((cfg.tx_gain_dbi + cfg.rx_gain_dbi) / 10) * gain
    p_r = p_t * g * cfg.wavelength_m**2 * rcs / ((4 * np.pi) ** 3 * r**4)
    return float(np.sqrt(2 * 50.0 * p_r) * 10 ** (cfg.if_gain_db / 20) / cfg.adc_full_scale_v)


def test_point_targets_range_and_power(make_renderer: Renderer) -> None:
    """Acceptance: peaks within ¼ range bin; trihedral power vs radar equation ≤ 0.5 dB."""
    project = load_project(example_path("point_targets"))
    cfg = project.rig.radar.model_copy(update=IDEAL)
    renderer = make_renderer(project)
    snap, buffers = radar_render(renderer, project, cfg)
    scat = radar_scatterers(RadarScene.from_project(project, snap), buffers, config=cfg)
    assert (scat.kind == KIND_CORNER_REFLECTOR).sum() == 3 and len(scat) == 3
    out = simulate_radar(scat, cfg, rng=np.random.default_rng(0))
    # Channel 1 is the Rx at the Tx position: the round trip is exactly 2R.
    pad = 16
    spec = range_spectrum(out.adc[0, 1].astype(np.float64), pad)
    bin_m = SPEED_OF_LIGHT * cfg.sample_rate_hz / (2 * cfg.slope_hz_per_s * pad
                                                   * cfg.samples_per_chirp)
    radar = radar_position(project)
    edge = 0.06
    sigma = 4 * np.pi * edge**4 / (3 * cfg.wavelength_m**2)
    q = cfg.element_pattern.exponent_az
    for obj in project.objects:
        offset = np.asarray(obj.pose.position_m) - radar
        r_true = float(np.linalg.norm(offset))
        az = np.arctan2(-offset[1], offset[0])
        guess = int(round(r_true / bin_m))
        window = np.abs(spec[guess - 3 * pad: guess + 3 * pad])
        peak = guess - 3 * pad + int(np.argmax(window))
        r_est = peak * bin_m
        err_bins = abs(r_est - r_true) / cfg.range_resolution_m
        amp_expected = radar_equation_amplitude(cfg, sigma, r_true, np.cos(az) ** (2 * q))
        power_err_db = 20 * np.log10(abs(spec[peak]) / amp_expected)
        print(f"{obj.name}: R {r_true:.4f} m, est {r_est:.4f} m ({err_bins:.3f} bin), "
              f"power {power_err_db:+.3f} dB")
        assert err_bins <= 0.25
        assert abs(power_err_db) <= 0.5


def test_wall_peak_power_does_not_depend_on_render_supersampling(make_renderer: Renderer
                                                                  ) -> None:
    """Supersampling the radar render (480² → 960² pixels) leaves the data unchanged: the
    scatterers are surface facets, the render only decides which are seen (the render
    grid doubled is checked in ``test_radar_surfaces``)."""
    project = load_project(example_path("wall"))
    renderer = make_renderer(project)
    base = project.rig.radar.model_copy(update={**IDEAL, "if_highpass_hz": 80e3})
    fine = base.model_copy(update={"render_supersampling": 2})
    snap, coarse_buf = radar_render(renderer, project, base)
    _, fine_buf = radar_render(renderer, project, fine)
    assert fine_buf.shape == (2 * coarse_buf.shape[0], 2 * coarse_buf.shape[1])
    peaks = []
    for cfg, buf in ((base, coarse_buf), (fine, fine_buf)):
        out = simulate_radar(radar_scatterers(RadarScene.from_project(project, snap), buf,
                                              config=cfg), cfg,
                             rng=np.random.default_rng(0))
        spec = range_spectrum(out.adc[0, 1].astype(np.float64), pad=1)
        peaks.append(20 * np.log10(np.abs(spec).max()))
    print(f"wall peak: {peaks[0]:.3f} dBFS at 1×, {peaks[1]:.3f} dBFS at 2× render")
    assert abs(peaks[1] - peaks[0]) < 0.5


def test_corner_reflector_behind_paper_box_appears_in_radar_data(make_renderer: Renderer
                                                                  ) -> None:
    """Acceptance: the paper box hides the corner reflector from the ToF camera only."""
    project = load_project(example_path("office"))
    renderer = make_renderer(project)
    cfg = project.rig.radar
    snap, buffers = radar_render(renderer, project, cfg)
    names = [o.name for o in project.objects]
    cr, box = names.index("corner_reflector"), names.index("paper_box")
    apex_world = snap.objects[cr].origin

    # ToF: the ray to the apex ends on the paper box.
    tof = project.rig.tof
    tof_intr = PinholeIntrinsics.from_fov(tof.width, tof.height, tof.fov_h_deg, tof.fov_v_deg)
    tof_buf = renderer.render(snap, RenderRequest("tof", "tof", tof_intr))
    t = snap.sensors["tof"].transform
    u, v = tof_intr.project((apex_world - t[:3, 3]) @ t[:3, :3])
    assert tof_buf.object_index[int(v), int(u)] == box

    # Radar: the paper box is drawn but transmits; seen through it (the second pass
    # without it), the reflector is its analytic scatterer, attenuated by the box's paper
    # walls that the ray crosses (each a slab at the ray's angle, TE and TM, computed here
    # by the transfer-matrix method), in and out.
    assert np.any(buffers.object_index == box)
    hide = tuple(i == box for i in range(len(names)))
    through = renderer.render(snap, RenderRequest("radar", "radar", cfg.render_intrinsics()),
                              hide=hide)
    alone = radar_scatterers(RadarScene.from_project(project, snap), buffers,
                             config=project.rig.radar)
    assert not np.any(alone.kind == KIND_CORNER_REFLECTOR)      # opaque without the pass
    scat = radar_scatterers(RadarScene.from_project(project, snap), buffers, see_through=through,
                            config=project.rig.radar)
    is_cr = scat.kind == KIND_CORNER_REFLECTOR
    assert is_cr.sum() == 1 and scat.object_index[is_cr][0] == cr
    r_cr = float(np.linalg.norm(scat.positions_m[is_cr][0]))
    assert_allclose(r_cr, np.linalg.norm(apex_world - snap.sensors["radar"].position), rtol=1e-9)
    paper = material_table(project)["paper"].band("radar")
    t_slab = transfer_matrix_transmission(paper.permittivity, paper.loss_tangent,
                                          paper.thickness_m, SPEED_OF_LIGHT / cfg.wavelength_m)
    # The same reflector with nothing in front (the pass without the box, used as the
    # frame's render) has the unattenuated RCS.
    open_view = radar_scatterers(RadarScene.from_project(project, snap), through,
                                 config=project.rig.radar)
    sigma_open = open_view.rcs_m2[open_view.kind == KIND_CORNER_REFLECTOR][0]
    # The ray to the apex enters the box's side and leaves through its back; the radar's
    # V field (world z made transverse to the ray) split at each wall into TE (along
    # n × d) and TM; the trihedral returns the field itself, back through the same walls.
    radar = snap.sensors["radar"].position
    obj = project.objects[box]
    walls = box_crossings(radar, apex_world, np.asarray(obj.pose.position_m),
                          np.asarray(obj.geometry.size_m))
    assert len(walls) == 2
    d = (apex_world - radar) / np.linalg.norm(apex_world - radar)
    field = np.array([0.0, 0.0, 1.0]) - d[2] * d
    field = (field / np.linalg.norm(field)).astype(complex)
    freq = SPEED_OF_LIGHT / cfg.wavelength_m
    for n in walls:
        te = np.cross(n, d) / np.linalg.norm(np.cross(n, d))
        cos = abs(float(n @ d))
        t_te, t_tm = (transfer_matrix_transmission(paper.permittivity, paper.loss_tangent,
                                                   paper.thickness_m, freq, cos, p)
                      for p in ("TE", "TM"))
        part = (field @ te) * te
        field = t_te * part + t_tm * (field - part)
    two_way = abs(field @ field) ** 2
    print(f"paper |T|² = {abs(t_slab) ** 2:.4f} at normal incidence; reflector RCS "
          f"{sigma_open:.4g} m² open, {scat.rcs_m2[is_cr][0]:.4g} m² behind the box "
          f"({10 * np.log10(two_way):.2f} dB: two walls crossed obliquely, each way)")
    assert_allclose(scat.rcs_m2[is_cr][0], sigma_open * two_way, rtol=1e-6)
    assert two_way < abs(t_slab) ** 8              # more than two walls at normal incidence

    # … and its return stands out of the office clutter in the noisy ADC data.
    rng_seed = 11
    with_cr = simulate_radar(scat, cfg, rng=np.random.default_rng(rng_seed))
    without = simulate_radar(scat.subset(~is_cr), cfg, rng=np.random.default_rng(rng_seed))
    pad = 4
    spec_with = np.abs(range_spectrum(with_cr.adc.astype(np.float64), pad)).mean(axis=(0, 1))
    spec_without = np.abs(range_spectrum(without.adc.astype(np.float64), pad)).mean(axis=(0, 1))
    bin_m = cfg.range_resolution_m / pad
    k = int(round(r_cr / bin_m))
    near = slice(k - pad, k + pad + 1)
    rise_db = 20 * np.log10(spec_with[near].max() / spec_without[near].max())
    local_peak = k - pad + int(np.argmax(spec_with[near]))
    print(f"corner reflector at {r_cr:.3f} m: +{rise_db:.1f} dB over the clutter, "
          f"peak at {local_peak * bin_m:.3f} m")
    assert rise_db > 10.0
    assert abs(local_peak * bin_m - r_cr) <= 0.25 * cfg.range_resolution_m


def test_point_target_is_hidden_by_a_wall_in_front(make_renderer: Renderer) -> None:
    target = SceneObject(id=1, name="target", geometry=PointTarget(rcs_m2=2.0),
                         pose=Pose(position_m=(4.0, 0.3, 0.0)))
    wall = SceneObject(id=2, name="wall", geometry=Box(size_m=(0.1, 4.0, 4.0)),
                       pose=Pose(position_m=(2.0, 0.0, 0.0)))
    open_project = Project(objects=[target], rig=SensorRig())
    hidden_project = Project(objects=[target, wall], rig=SensorRig())
    behind_project = Project(objects=[target.model_copy(update={"pose": Pose(
        position_m=(1.0, 0.3, 0.0))}), wall], rig=SensorRig())
    for project, visible in ((open_project, True), (hidden_project, False),
                             (behind_project, True)):
        renderer = make_renderer(project)
        cfg = project.rig.radar
        snap, buffers = radar_render(renderer, project, cfg)
        scat = radar_scatterers(RadarScene.from_project(project, snap), buffers,
                                config=project.rig.radar)
        found = scat.kind == KIND_POINT_TARGET
        assert found.sum() == int(visible)
        if visible:
            assert scat.rcs_m2[found][0] == 2.0


@pytest.mark.parametrize("band", ["tof"])
def test_scatterers_need_the_radar_band(make_renderer: Renderer, band: str) -> None:
    project = load_project(example_path("wall"))
    renderer = make_renderer(project)
    snap = take_snapshot(project, 0.0)
    buf = renderer.render(snap, RenderRequest(band, band,
                                             PinholeIntrinsics.from_fov(64, 48, 60.0)))
    with pytest.raises(ValueError, match="radar render"):
        radar_scatterers(RadarScene.from_project(project, snap), buf, config=project.rig.radar)
