"""Known-answer tests of the AMCW ToF camera model (issue 3), headless.

Scenes are built in code and rendered with the real renderer; every expected value comes
from geometry (ranges along the pixel rays, projected silhouettes) or from the radiometric
and noise formulas of docs/physics_tof.md, never from the model's own output.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose, assert_array_equal

from simcore.render import RenderBuffers, RenderRequest, render_once
from simcore.resources import example_path
from simcore.scene import Plane, Pose, Project, SceneObject, load_project
from simcore.scene.materials import band_response, load_material_library
from simcore.scene.model import SensorRig
from simcore.scene.snapshot import take_snapshot
from simcore.scene.tof_config import (
    SPEED_OF_LIGHT,
    TofCameraConfig,
    pmd_pico_flexx,
    tof_preset,
)
from simcore.sensors.tof.camera import simulate_tof, unwrap_two_frequencies

RIG_HEIGHT_M = 1.0
F1, F2 = 20e6, 16e6
R1 = SPEED_OF_LIGHT / (2 * F1)  # 7.4948 m


# --------------------------------------------------------------------------- helpers


def render(project: Project) -> RenderBuffers:
    """ToF-band render of ``project`` at t = 0 on the camera's supersampled grid."""
    return render_once(project, RenderRequest("tof", "tof", project.rig.tof.render_intrinsics()))


def ray_norms(cfg: TofCameraConfig) -> np.ndarray:
    """|(x/z, y/z, 1)| at every sensor pixel centre, from the field of view alone."""
    fx = 0.5 * cfg.width / math.tan(math.radians(cfg.fov_h_deg) / 2)
    fy = 0.5 * cfg.height / math.tan(math.radians(cfg.fov_v_deg) / 2)
    u = (np.arange(cfg.width) + 0.5 - cfg.width / 2) / fx
    v = (np.arange(cfg.height) + 0.5 - cfg.height / 2) / fy
    return np.sqrt(1.0 + u[None, :] ** 2 + v[:, None] ** 2)


def facing_plane(oid: int, name: str, distance_m: float, size_m: tuple[float, float],
                 material: str, *, left_m: float = 0.0, up_m: float = 0.0) -> SceneObject:
    """A rectangle facing the camera at ``distance_m``; size = (vertical, horizontal)."""
    return SceneObject(id=oid, name=name, geometry=Plane(size_m=size_m),
                       pose=Pose(position_m=(distance_m, left_m, RIG_HEIGHT_M + up_m),
                                 rotation_deg=(0.0, 90.0, 0.0)),
                       material=material)


def scene(objects: list[SceneObject], cfg: TofCameraConfig) -> Project:
    """Rig at (0, 0, 1 m) looking along world +x, camera at the rig origin."""
    return Project(objects=objects,
                   rig=SensorRig(pose=Pose(position_m=(0.0, 0.0, RIG_HEIGHT_M)), tof=cfg))


def coverage(cfg: TofCameraConfig, distance_m: float, size_m: tuple[float, float], *,
             left_m: float = 0.0, up_m: float = 0.0) -> np.ndarray:
    """Fraction of each sensor pixel's footprint covered by a facing rectangle, (H, W)."""
    fx = 0.5 * cfg.width / math.tan(math.radians(cfg.fov_h_deg) / 2)
    fy = 0.5 * cfg.height / math.tan(math.radians(cfg.fov_v_deg) / 2)
    # Optical frame: x right = −(world y), y down = −(world z − rig height).
    x0, x1 = -left_m - size_m[1] / 2, -left_m + size_m[1] / 2
    y0, y1 = -up_m - size_m[0] / 2, -up_m + size_m[0] / 2
    u0, u1 = cfg.width / 2 + fx * x0 / distance_m, cfg.width / 2 + fx * x1 / distance_m
    v0, v1 = cfg.height / 2 + fy * y0 / distance_m, cfg.height / 2 + fy * y1 / distance_m
    cols, rows = np.arange(cfg.width), np.arange(cfg.height)
    cov_u = np.clip(np.minimum(cols + 1, u1) - np.maximum(cols, u0), 0, 1)
    cov_v = np.clip(np.minimum(rows + 1, v1) - np.maximum(rows, v0), 0, 1)
    return cov_v[:, None] * cov_u[None, :]


def dilate(mask: np.ndarray, steps: int = 1) -> np.ndarray:
    """Binary dilation with the 8-neighbourhood."""
    out = mask.copy()
    for _ in range(steps):
        grown = out.copy()
        for dr in (-1, 0, 1):
            for dc in (-1, 0, 1):
                grown |= np.roll(np.roll(out, dr, axis=0), dc, axis=1)
        out = grown
    return out


#: The preset's optics switched off (these tests check other parts of the chain).
OPTICS_OFF = {"multipath": False, "specular": False, "wiggling": False, "distortion": False,
              "vignetting": False, "stray_light": False}


def ideal(cfg: TofCameraConfig, **changes: object) -> TofCameraConfig:
    return cfg.model_copy(update={**OPTICS_OFF, **changes})


@pytest.fixture(scope="module")
def wall_json() -> Project:
    return load_project(example_path("wall"))


# --------------------------------------------------------------------------- config


def test_preset_and_intrinsics():
    cfg = tof_preset("pmd_pico_flexx")
    assert (cfg.width, cfg.height, cfg.fov_h_deg, cfg.fov_v_deg) == (224, 171, 62.0, 45.0)
    assert cfg.modulation_frequencies_hz == [20e6] and cfg.wavelength_nm == 850.0
    assert_allclose(cfg.unambiguous_range_m, 7.4948, atol=1e-4)
    sensor, sub = cfg.intrinsics(), cfg.render_intrinsics()
    assert (sub.width, sub.height) == (448, 342)
    # Sub-pixel k of pixel c has its centre at c + (k + 0.5)/2 in sensor pixel units.
    assert_allclose(sub.fx / 2, sensor.fx)
    assert_allclose((sub.cx - 0.5) / 2, sensor.cx - 0.25)
    cfg2 = TofCameraConfig(modulation_frequencies_hz=[F1, F2])
    assert_allclose(cfg2.combined_unambiguous_range_m, SPEED_OF_LIGHT / (2 * 4e6))
    with pytest.raises(ValueError, match="differ"):
        TofCameraConfig(modulation_frequencies_hz=[F1, F1])
    with pytest.raises(ValueError, match="common divisor"):
        TofCameraConfig(modulation_frequencies_hz=[20e6, 19_999_999.0])
    with pytest.raises(ValueError, match="unknown ToF preset"):
        tof_preset("nope")


# --------------------------------------------------------------------------- wall depth


def test_wall_depth_noise_off_within_1cm(wall_json):
    cfg = wall_json.rig.tof
    out = simulate_tof(render(wall_json), cfg, rng=np.random.default_rng(0), noise=False)
    # wall.json: front face 2.0 m ahead of the camera, normal to the boresight.
    expected = 2.0 * ray_norms(cfg)
    assert out.valid.all()
    err = np.abs(out.depth_m - expected)
    assert err.max() <= 0.01, err.max()
    assert_allclose(out.gt_range, expected, atol=1e-3)
    assert (out.gt_object_id == 1).all()
    assert out.depth_m.dtype == np.float32 and out.correlation.shape == (4, 171, 224)


def test_amplitude_follows_inverse_square_and_radiometry(wall_json):
    cfg = wall_json.rig.tof
    amps = {}
    for distance in (1.0, 2.0):
        project = wall_json.model_copy(deep=True)
        project.objects[0].pose = Pose(position_m=(distance + 0.1, 0.0, RIG_HEIGHT_M))
        out = simulate_tof(render(project), cfg, rng=np.random.default_rng(0), noise=False)
        assert not out.saturated.any()
        amps[distance] = out.amplitude.astype(np.float64)
    ratio = amps[1.0] / amps[2.0]
    assert np.abs(ratio / 4.0 - 1.0).max() <= 0.02, np.abs(ratio / 4.0 - 1.0).max()
    # Absolute level at the image centre: A = 2 m S1 f(θ) / R² · gain, θ from geometry.
    concrete = load_material_library()["concrete"].band("tof")
    norms = ray_norms(cfg)
    cos_theta = 1.0 / norms
    f = band_response(cos_theta, reflectance=concrete.reflectance, specular=concrete.specular,
                      roughness=concrete.roughness, metallic=concrete.metallic)
    expected = (2 * cfg.demodulation_contrast * cfg.signal_electrons_at_1m * f
                / (2.0 * norms) ** 2 * cfg.conversion_gain_dn_per_electron)
    centre = (slice(60, 110), slice(80, 144))
    assert_allclose(amps[2.0][centre], expected[centre], rtol=0.01)


# --------------------------------------------------------------------------- wrapping


@pytest.fixture(scope="module")
def far_wall(wall_json) -> tuple[Project, RenderBuffers]:
    project = wall_json.model_copy(deep=True)
    project.objects[0].pose = Pose(position_m=(9.1, 0.0, RIG_HEIGHT_M))
    project.objects[0].material = "white_paint"
    return project, render(project)


def test_wall_at_9m_wraps_with_one_frequency(far_wall):
    project, buffers = far_wall
    cfg = ideal(project.rig.tof, illumination_power_w=4.0)
    out = simulate_tof(buffers, cfg, rng=np.random.default_rng(0), noise=False)
    truth = 9.0 * ray_norms(cfg)
    assert out.valid.mean() > 0.99
    assert_allclose(out.gt_range[out.valid], truth[out.valid], atol=2e-3)
    centre = out.depth_m[84:87, 110:114]
    assert_allclose(centre, 9.0 - R1, atol=0.01)          # ≈ 1.505 m
    err = np.abs(out.depth_m - np.mod(truth, R1))[out.valid]
    assert err.max() <= 0.01


def test_wall_at_9m_unwrapped_with_two_frequencies(far_wall):
    project, buffers = far_wall
    cfg = ideal(project.rig.tof, illumination_power_w=4.0, modulation_frequencies_hz=[F1, F2])
    truth = 9.0 * ray_norms(cfg)
    out = simulate_tof(buffers, cfg, rng=np.random.default_rng(0), noise=False)
    assert out.valid.mean() > 0.99
    assert np.abs(out.depth_m - truth)[out.valid].max() <= 0.01
    # With noise the unwrapping still picks the right wrap count everywhere it is valid.
    noisy = simulate_tof(buffers, cfg, rng=np.random.default_rng(1), noise=True)
    assert noisy.valid.mean() > 0.95
    assert np.abs(noisy.depth_m - truth)[noisy.valid].max() < 0.5


def test_unwrap_two_frequencies_known_answers():
    rng = np.random.default_rng(3)
    r_max = SPEED_OF_LIGHT / (2 * 4e6)                     # 37.47 m for 20 / 16 MHz
    d = rng.uniform(0.0, r_max, size=(50, 40))
    r2 = SPEED_OF_LIGHT / (2 * F2)
    e1 = rng.uniform(-0.3, 0.3, size=d.shape)              # |e1 − e2| < 0.94 m limit
    e2 = rng.uniform(-0.3, 0.3, size=d.shape)
    out = unwrap_two_frequencies(np.mod(d + e1, R1), np.mod(d + e2, r2), F1, F2)
    diff = np.abs(out - d)
    diff = np.minimum(diff, r_max - diff)                  # distance on the circle [0, R)
    assert diff.max() < 0.31
    # Beyond the combined range the result aliases back into [0, R).
    far = unwrap_two_frequencies(np.array([np.mod(r_max + 2.0, R1)]),
                                 np.array([np.mod(r_max + 2.0, r2)]), F1, F2)
    assert_allclose(far, [2.0], atol=1e-4)


# --------------------------------------------------------------------------- flying pixels


FG_DIST, WALL_DIST = 1.5, 4.0


def mid_pixel_rectangle(cfg: TofCameraConfig, distance_m: float
                        ) -> tuple[tuple[float, float], float, float]:
    """Size and offsets (m) of a facing rectangle whose four edges project to mid-pixel.

    It spans 60 × 40 sensor pixels centred on image point (119.5, 90.5), so its edges lie at
    u = 89.5, 149.5 and v = 70.5, 110.5: every silhouette pixel is half box, half wall.
    """
    fx = 0.5 * cfg.width / math.tan(math.radians(cfg.fov_h_deg) / 2)
    fy = 0.5 * cfg.height / math.tan(math.radians(cfg.fov_v_deg) / 2)
    size = (40 * distance_m / fy, 60 * distance_m / fx)
    left = -(119.5 - cfg.width / 2) * distance_m / fx
    up = -(90.5 - cfg.height / 2) * distance_m / fy
    return size, left, up


@pytest.mark.parametrize("supersampling", [2, 4, 1])
def test_flying_pixels_only_on_silhouette(supersampling):
    cfg = ideal(pmd_pico_flexx(), supersampling=supersampling, crosstalk_sigma_px=0.0)
    size, left, up = mid_pixel_rectangle(cfg, FG_DIST)
    project = scene([
        facing_plane(1, "wall", WALL_DIST, (20.0, 20.0), "concrete"),
        facing_plane(2, "box", FG_DIST, size, "white_paint", left_m=left, up_m=up),
    ], cfg)
    out = simulate_tof(render(project), cfg, rng=np.random.default_rng(0), noise=False)
    norms = ray_norms(cfg)
    r_fg, r_wall = FG_DIST * norms, WALL_DIST * norms
    cov = coverage(cfg, FG_DIST, size, left_m=left, up_m=up)
    silhouette = (cov > 0) & (cov < 1)
    assert out.valid.all()
    flying = (out.depth_m > r_fg + 0.02) & (out.depth_m < r_wall - 0.02)
    # Away from the silhouette every pixel sees one surface, within 1 cm.
    inside, outside = cov == 1, cov == 0
    assert np.abs(out.depth_m - r_fg)[inside].max() < 0.01
    assert np.abs(out.depth_m - r_wall)[outside].max() < 0.01
    if supersampling == 1:
        assert not flying.any()
        near = np.minimum(np.abs(out.depth_m - r_fg), np.abs(out.depth_m - r_wall))
        assert near.max() < 0.01
    else:
        assert silhouette.sum() == 2 * (60 + 40)
        assert not (flying & ~silhouette).any()
        # Every silhouette pixel mixes box and wall sub-pixels.
        assert flying[silhouette].all()


# --------------------------------------------------------------------------- retroreflector


RETRO_DIST, RETRO_WALL = 3.0, 4.5
RETRO_SIZE, RETRO_LEFT, RETRO_UP = (0.2, 0.2), 0.3117, 0.0523


@pytest.fixture(scope="module")
def retro_scene() -> tuple[Project, RenderBuffers]:
    # A fixed exposure: the saturation level is what is tested (auto-exposure would move it).
    cfg = pmd_pico_flexx().model_copy(update={**OPTICS_OFF, "auto_exposure": False})
    project = scene([
        facing_plane(1, "wall", RETRO_WALL, (20.0, 20.0), "concrete"),
        facing_plane(2, "tape", RETRO_DIST, RETRO_SIZE, "ir_retroreflector_tape",
                     left_m=RETRO_LEFT, up_m=RETRO_UP),
    ], cfg)
    return project, render(project)


def test_retroreflector_saturates_and_bleeds(retro_scene):
    project, buffers = retro_scene
    cfg = project.rig.tof
    assert cfg.crosstalk_sigma_px > 0
    norms = ray_norms(cfg)
    r_tape, r_wall = RETRO_DIST * norms, RETRO_WALL * norms
    cov = coverage(cfg, RETRO_DIST, RETRO_SIZE, left_m=RETRO_LEFT, up_m=RETRO_UP)
    core = cov == 1
    touched = cov > 0
    ring = dilate(touched, 1) & ~touched       # fully on the wall, adjacent to the tape
    assert core.sum() > 50 and ring.sum() > 40

    out = simulate_tof(buffers, cfg, rng=np.random.default_rng(0), noise=False)
    assert out.saturated[core].all()
    assert not out.valid[core].any()
    assert_array_equal(out.depth_m[core], 0.0)
    # Cross-talk pulls the wall pixels next to the tape toward the tape's range.
    pull = (r_wall - out.depth_m)[ring & out.valid]
    span = (r_wall - r_tape)[ring & out.valid]
    assert (ring & out.valid).sum() >= 0.8 * ring.sum()
    assert np.median(pull) > 0.10, np.median(pull)
    assert (pull > 0.02).mean() > 0.8
    assert (pull <= span + 0.01).all() and (pull > -0.01).all()
    # Far from the tape the wall is untouched.
    far = ~dilate(touched, 4)
    assert np.abs(out.depth_m - r_wall)[far].max() < 0.01

    clean = simulate_tof(buffers, ideal(cfg, crosstalk_sigma_px=0.0),
                         rng=np.random.default_rng(0), noise=False)
    assert clean.saturated[core].all() and not clean.valid[core].any()
    assert clean.valid[ring].all()
    assert np.abs(clean.depth_m - r_wall)[ring].max() < 0.01


# --------------------------------------------------------------------------- noise


def test_depth_noise_falls_with_illumination_power(wall_json):
    buffers = render(wall_json)
    base = wall_json.rig.tof
    centre = (slice(65, 105), slice(92, 132))
    stds, predicted = [], []
    for power in (0.25, 1.0, 4.0):
        cfg = ideal(base, illumination_power_w=power)
        frames = np.stack([
            simulate_tof(buffers, cfg, rng=np.random.default_rng([7, i]), noise=True).depth_m
            for i in range(30)])
        assert (frames[:, centre[0], centre[1]] > 0).all()
        stds.append(float(np.median(frames.std(axis=0, ddof=1)[centre])))
        # Four-bucket phase noise: σ_φ² = Σ var(C_i) / A² = 2 (offset + σ_read² + q²) / A²
        # (e⁻), with the noise-free offset and amplitude of the same pixels.
        clean = simulate_tof(buffers, cfg, rng=np.random.default_rng(0), noise=False)
        gain = cfg.conversion_gain_dn_per_electron
        offset_e = clean.intensity[centre] / gain
        amp_e = clean.amplitude[centre] / gain
        var = 2 * (offset_e + cfg.read_noise_electrons**2 + 1 / (12 * gain**2))
        predicted.append(float(np.median(R1 / (2 * np.pi) * np.sqrt(var) / amp_e)))
    assert stds[0] > stds[1] > stds[2], stds
    assert stds[0] > 2.5 * stds[2]
    assert_allclose(stds, predicted, rtol=0.1)


def test_seeded_frames_are_reproducible(wall_json):
    buffers = render(wall_json)
    cfg = wall_json.rig.tof
    a = simulate_tof(buffers, cfg, rng=np.random.default_rng(5))
    b = simulate_tof(buffers, cfg, rng=np.random.default_rng(5))
    c = simulate_tof(buffers, cfg, rng=np.random.default_rng(6))
    assert_array_equal(a.correlation, b.correlation)
    assert not np.array_equal(a.correlation, c.correlation)
    items = a.hdf5_items()
    assert set(items) == {"/tof/depth", "/tof/amplitude", "/tof/valid", "/tof/correlation",
                          "/tof/gt_range", "/tof/gt_object_id", "/tof/intensity",
                          "/tof/exposure_time"}
    assert items["/tof/depth"][1] == "m" and items["/tof/valid"][0].dtype == np.bool_
    assert items["/tof/correlation"][0].shape == (4, 171, 224)
    assert items["/tof/gt_object_id"][0].dtype == np.int32
    for key in ("/tof/depth", "/tof/amplitude", "/tof/intensity", "/tof/correlation",
                "/tof/gt_range"):
        assert items[key][0].dtype == np.float32, key
    with pytest.raises(ValueError, match="supersampling"):
        simulate_tof(buffers, ideal(cfg, supersampling=1), rng=np.random.default_rng(0))


def test_motion_artifacts_follow_the_four_sample_formula(make_renderer):
    """A wall receding along the axis: each correlation sample sees its own range."""
    from scenes import wall_project

    from simcore.scene import Motion
    from simcore.sensors.tof.camera import simulate_tof

    v, d0 = 30.0, 2.0                         # fast, so the artefact is centimetres
    project = wall_project(d0, material="white_paint")
    project.objects[0].motion = Motion(velocity_mps=(v, 0.0, 0.0))
    cfg = project.rig.tof.model_copy(update={"crosstalk_sigma_px": 0.0, "supersampling": 1,
                                             "motion_artifacts": True})
    renderer = make_renderer(project)
    intr = cfg.render_intrinsics()
    dt = cfg.sample_interval_s
    samples = [renderer.render(take_snapshot(project, i * dt), RenderRequest("tof", "tof", intr))
               for i in range(4)]
    out = simulate_tof(samples[0], cfg, rng=np.random.default_rng(0), noise=False,
                       sample_buffers=samples)
    still = simulate_tof(samples[0], cfg, rng=np.random.default_rng(0), noise=False)

    # Centre pixel, by hand: C_i = S_i + B + m S_i cos(phi_i + i pi/2) with S_i ∝ f/R_i²
    # and the ambient B independent of range (the common response factor cancels).
    row, col = cfg.height // 2, cfg.width // 2
    f = cfg.modulation_frequencies_hz[0]
    c = 299_792_458.0
    r = np.array([s.range_m[row, col] for s in samples], dtype=float)
    sig = cfg.signal_electrons_at_1m / r**2
    corr = sig + cfg.ambient_electrons + cfg.demodulation_contrast * sig * np.cos(
        4 * np.pi * f * r / c + np.arange(4) * np.pi / 2)
    phase = np.arctan2(corr[3] - corr[1], corr[0] - corr[2]) % (2 * np.pi)
    expected = phase * c / (4 * np.pi * f)
    assert abs(out.depth_m[row, col] - expected) < 2e-3
    # The artefact is real: millimetres away from the still-scene depth (float error is µm).
    assert abs(out.depth_m[row, col] - still.depth_m[row, col]) > 0.003
    np.testing.assert_allclose(r, r[0] + v * dt * np.arange(4) * samples[0].range_m[row, col]
                               / samples[0].points_m[row, col, 2], atol=1e-4)


def test_auto_exposure_keeps_a_near_grey_wall_valid():
    """A grey wall at 0.1 m saturates at the fixed 250 µs exposure (it does from ≈ 0.6 m);
    auto-exposure shortens the exposure so that it reads right (the pico flexx stays valid
    down to 0.1 m)."""
    from scenes import wall_project

    from simcore.sensors.tof.camera import auto_exposure_s

    project = wall_project(0.1, material="concrete")
    fixed = project.rig.tof.model_copy(update={"crosstalk_sigma_px": 0.0})
    auto = fixed.model_copy(update={"auto_exposure": True})
    buf = render_once(project, RenderRequest("tof", "tof", fixed.render_intrinsics()))
    out_fixed = simulate_tof(buf, fixed, rng=np.random.default_rng(0))
    out_auto = simulate_tof(buf, auto, rng=np.random.default_rng(0))
    assert out_fixed.saturated.mean() > 0.9 and out_fixed.exposure_time_s == 250e-6
    assert out_auto.valid.mean() > 0.95
    centre = out_auto.depth_m[60:110, 80:140]
    assert abs(float(np.median(centre)) - float(np.median(out_auto.gt_range[60:110, 80:140]))
               ) < 0.01
    # The chosen exposure puts the brightest 1 % at the target: check it from the formula,
    # peak electrons ∝ exposure, computed here from the configured radiometry.
    f = np.percentile(buf.intensity[buf.object_index >= 0], 99.9)
    r = float(np.nanmin(buf.range_m))
    peak_at_config = (f * fixed.signal_electrons_at_1m / r**2 + f * fixed.ambient_electrons) * (
        1 + fixed.demodulation_contrast)
    expected = fixed.exposure_time_s * fixed.auto_exposure_target * (
        fixed.full_well_electrons / peak_at_config)
    assert auto_exposure_s(buf, auto) == pytest.approx(expected, rel=0.1)
    assert out_auto.exposure_time_s == auto_exposure_s(buf, auto)


def _downsample_reference(ids: np.ndarray, rng: np.ndarray, factor: int
                          ) -> tuple[np.ndarray, np.ndarray]:
    """The numpy ``downsample_ground_truth`` the compiled kernel replaced, verbatim."""
    h, w = ids.shape
    hs, ws = h // factor, w // factor
    ids = (ids[: hs * factor, : ws * factor].reshape(hs, factor, ws, factor)
           .transpose(0, 2, 1, 3).reshape(hs, ws, -1))
    rng = (rng[: hs * factor, : ws * factor].reshape(hs, factor, ws, factor)
           .transpose(0, 2, 1, 3).reshape(hs, ws, -1))
    gt_id = ids[..., 0].copy()
    uniform = np.all(ids == gt_id[..., None], axis=-1)
    with np.errstate(invalid="ignore"):
        gt_range = np.nansum(rng, axis=-1) / np.float64(ids.shape[-1])
    mixed = np.flatnonzero(~uniform)
    if mixed.size:
        m_ids = ids.reshape(-1, ids.shape[-1])[mixed]
        m_rng = rng.reshape(-1, rng.shape[-1])[mixed]
        counts = (m_ids[..., :, None] == m_ids[..., None, :]).sum(axis=-1)
        key = counts * 1e6 - np.nan_to_num(m_rng, nan=1e5)
        best = np.argmax(key, axis=-1)
        m_id = np.take_along_axis(m_ids, best[..., None], axis=-1)[..., 0]
        same = m_ids == m_id[..., None]
        with np.errstate(invalid="ignore"):
            m_range = np.nansum(np.where(same, m_rng, 0.0), axis=-1) / same.sum(axis=-1)
        gt_id.reshape(-1)[mixed] = m_id
        gt_range.reshape(-1)[mixed] = m_range
    gt_range = np.where(gt_id >= 0, gt_range, np.nan).astype(np.float32)
    return gt_range, gt_id.astype(np.int32)


@pytest.mark.parametrize("factor", [1, 2, 3])
def test_ground_truth_downsampling_matches_the_numpy_reference(factor: int) -> None:
    """Votes (most frequent id, ties to the nearer surface, background NaN) and means."""
    from types import SimpleNamespace

    from simcore.render.buffers import downsample_ground_truth

    gen = np.random.default_rng(factor)
    h, w = 7 * factor + 1, 9 * factor + 2            # rows and columns left over
    # Blocks of few ids (-1 = background) so that uniform, mixed and tied pixels occur.
    ids = gen.integers(-1, 3, (h, w)).astype(np.int32)
    ids[: 3 * factor] = ids[0, 0]
    rng = gen.uniform(0.5, 5.0, (h, w)).astype(np.float32)
    rng[ids < 0] = np.nan
    rng[1, 1] = rng[1, 0] if factor > 1 else rng[1, 1]   # an exact range tie
    buffers = SimpleNamespace(shape=(h, w), object_id=ids, range_m=rng)
    gt_range, gt_id = downsample_ground_truth(buffers, factor)  # type: ignore[arg-type]
    ref_range, ref_id = _downsample_reference(ids, rng, factor)
    assert_array_equal(gt_id, ref_id)
    assert_allclose(gt_range, ref_range, rtol=2e-7, equal_nan=True)
    assert gt_range.dtype == np.float32 and gt_id.dtype == np.int32
