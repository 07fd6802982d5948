"""ToF optics and electronics switches, each against its own formula written out here.

wiggling (harmonic model), vignetting (cos⁴), Brown–Conrady distortion (projection of
known 3D points), stray light (PSF + phasor sum at one pixel), ambient light (shot-noise
formula, full well) and background suppression.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from simcore.render import RenderRequest, SceneRenderer
from simcore.render.buffers import RenderBuffers
from simcore.scene import Box, Pose, Project, SceneObject
from simcore.scene.model import SensorRig
from simcore.scene.snapshot import take_snapshot
from simcore.scene.tof_config import SPEED_OF_LIGHT, TofCameraConfig
from simcore.sensors.tof.camera import simulate_tof
from simcore.sensors.tof.optics import lens_focal_px

F_MOD = 20e6


def base(**changes: object) -> TofCameraConfig:
    cfg = TofCameraConfig(crosstalk_sigma_px=0.0, auto_exposure=False)
    return cfg.model_copy(update=changes)


def render(objects: list[SceneObject], cfg: TofCameraConfig) -> RenderBuffers:
    project = Project(objects=objects, rig=SensorRig(tof=cfg))
    renderer = SceneRenderer(project)
    try:
        return renderer.render(take_snapshot(project, 0.0),
                               RenderRequest("tof", "tof", cfg.render_intrinsics()))
    finally:
        renderer.close()


def wall(distance_m: float, *, oid: int = 1, size: float = 20.0,
         material: str = "white_paint", y: float = 0.0, z: float = 0.0) -> SceneObject:
    return SceneObject(id=oid, name=f"wall{oid}", geometry=Box(size_m=(0.02, size, size)),
                       pose=Pose(position_m=(distance_m + 0.01, y, z)), material=material)


@pytest.fixture(scope="module")
def wall_buffers() -> RenderBuffers:
    return render([wall(3.0)], base())


def cos_off_axis(cfg: TofCameraConfig) -> np.ndarray:
    intr = cfg.intrinsics()
    u = (np.arange(cfg.width) + 0.5 - intr.cx) / intr.fx
    v = (np.arange(cfg.height) + 0.5 - intr.cy) / intr.fy
    return 1.0 / np.sqrt(1.0 + u[None, :] ** 2 + v[:, None] ** 2)


def test_wiggling_follows_the_harmonic_model(wall_buffers: RenderBuffers) -> None:
    cfg = base(wiggling=True, wiggling_harmonics=(0.03, 0.008))
    # Every sensor column at its own range, 0.2 … 7.3 m (sub-pixels of a pixel alike).
    true = np.linspace(0.2, 7.3, cfg.width)
    rng_img = np.repeat(true, cfg.supersampling)[None, :].repeat(wall_buffers.shape[0], 0)
    buf = dataclasses.replace(wall_buffers, range_m=rng_img.astype(np.float32),
                              intensity=np.full(wall_buffers.shape, 4.0, np.float32)
                              * (rng_img.astype(np.float32) / 3.0) ** 2)
    out = simulate_tof(buf, cfg, rng=np.random.default_rng(0), noise=False)
    row = out.depth_m[cfg.height // 2]
    a3, a5 = cfg.wiggling_harmonics
    phi = 4 * np.pi * F_MOD * true / SPEED_OF_LIGHT
    # Four samples of cos φ + a3 cos 3φ + a5 cos 5φ at φ + iπ/2, demodulated.
    samples = [np.cos(phi + i * np.pi / 2) + a3 * np.cos(3 * (phi + i * np.pi / 2))
               + a5 * np.cos(5 * (phi + i * np.pi / 2)) for i in range(4)]
    est = np.mod(np.arctan2(samples[3] - samples[1], samples[0] - samples[2]), 2 * np.pi)
    predicted = est * SPEED_OF_LIGHT / (4 * np.pi * F_MOD)
    np.testing.assert_allclose(row, predicted, atol=5e-4)
    err = row - true
    amplitude = (a3 - a5) * SPEED_OF_LIGHT / (4 * np.pi * F_MOD)     # (a5 − a3) sin 4φ
    assert abs(np.abs(err).max() - amplitude) < 0.05 * amplitude
    # Period: a quarter of the unambiguous range (1.87 m at 20 MHz): sign changes every 0.94 m.
    crossings = true[1:][np.diff(np.sign(err)) != 0]
    np.testing.assert_allclose(np.diff(crossings), SPEED_OF_LIGHT / (2 * F_MOD) / 8, atol=0.05)
    off = simulate_tof(buf, base(), rng=np.random.default_rng(0), noise=False)
    assert np.abs(off.depth_m[cfg.height // 2] - true).max() < 1e-3


def test_vignetting_is_cos4(wall_buffers: RenderBuffers) -> None:
    cfg = base(ambient_light=False)
    off = simulate_tof(wall_buffers, cfg, rng=np.random.default_rng(0), noise=False)
    on = simulate_tof(wall_buffers, cfg.model_copy(update={"vignetting": True}),
                      rng=np.random.default_rng(0), noise=False)
    ratio = on.amplitude / off.amplitude
    np.testing.assert_allclose(ratio, cos_off_axis(cfg) ** 4, rtol=2e-3)
    np.testing.assert_allclose(on.depth_m, off.depth_m, atol=1e-5)


def test_distortion_moves_known_points_where_brown_conrady_projects_them() -> None:
    cfg = base(distortion=True, distortion_coefficients=(-0.37, 0.14, 0.002, -0.003, 0.0))
    k1, k2, p1, p2, k3 = cfg.distortion_coefficients
    intr = cfg.intrinsics()
    fx, fy = lens_focal_px(intr, cfg.distortion_coefficients)
    markers = [(2.0, -0.6, 0.0), (2.0, 0.6, 0.0), (2.0, -1.1, -0.6), (2.0, 1.1, 0.6)]
    objects = [wall(4.0)] + [
        SceneObject(id=10 + i, name=f"m{i}", geometry=Box(size_m=(0.02, 0.04, 0.04)),
                    pose=Pose(position_m=m), material="white_paint")
        for i, m in enumerate(markers)]
    out = simulate_tof(render(objects, cfg), cfg, rng=np.random.default_rng(0), noise=False)
    for i, (xw, yw, zw) in enumerate(markers):
        x, y = -yw / xw, -zw / xw                 # optical frame: x right, y down, z forward
        r2 = x * x + y * y
        g = 1 + k1 * r2 + k2 * r2**2 + k3 * r2**3
        xd = x * g + 2 * p1 * x * y + p2 * (r2 + 2 * x * x)
        yd = y * g + p1 * (r2 + 2 * y * y) + 2 * p2 * x * y
        col, row = int(xd * fx + intr.cx), int(yd * fy + intr.cy)
        pin_col, pin_row = int(x * intr.fx + intr.cx), int(y * intr.fy + intr.cy)
        assert abs(col - pin_col) + abs(row - pin_row) >= 4     # the lens moves it
        assert out.gt_object_id[row, col] == 10 + i
        assert out.gt_object_id[pin_row, pin_col] != 10 + i


def test_lens_focal_keeps_the_field_of_view_at_the_edge_centres() -> None:
    cfg = base()
    intr = cfg.intrinsics()
    coeffs = (-0.37, 0.14, 0.0, 0.0, 0.0)
    fx, fy = lens_focal_px(intr, coeffs)
    x = (intr.width - intr.cx) / intr.fx        # tan of the half field of view (pinhole)
    assert abs(x * (1 + coeffs[0] * x**2 + coeffs[1] * x**4) * fx - (intr.width - intr.cx)) < 1e-6


def test_stray_light_of_a_near_bright_object_shifts_the_far_wall_as_the_psf_predicts() -> None:
    s, r0 = 0.05, 6.0
    cfg = base(ambient_light=False, exposure_time_s=20e-6, min_amplitude_dn=0.0)
    objects = [wall(5.0, material="concrete"),
               SceneObject(id=2, name="card", geometry=Box(size_m=(0.01, 0.08, 0.08)),
                           pose=Pose(position_m=(0.3, 0.05, 0.0)), material="white_paint")]
    buf = render(objects, cfg)
    off = simulate_tof(buf, cfg, rng=np.random.default_rng(0), noise=False)
    assert not off.saturated.any()
    on = simulate_tof(buf, cfg.model_copy(update={"stray_light": True, "stray_light_fraction": s,
                                                  "stray_light_radius_px": r0}),
                      rng=np.random.default_rng(0), noise=False)
    c = off.correlation.astype(np.float64)
    z = (c[0] - c[2]) + 1j * (c[3] - c[1])          # phasor of each pixel without stray light
    h, w = z.shape
    yy, xx = np.mgrid[-(h - 1):h, -(w - 1):w]
    tail = (1 + (xx**2 + yy**2) / r0**2) ** -1.5
    tail /= tail.sum()
    card = off.gt_object_id == 2
    far = (off.gt_object_id == 1) & off.valid
    rows, cols = np.nonzero(far)
    dist = np.hypot(rows - np.nonzero(card)[0].mean(), cols - np.nonzero(card)[1].mean())
    checked = 0
    for p in np.argsort(dist)[::200][:12]:
        r, cl = rows[p], cols[p]
        # (1 − s) z_p + s Σ_j K(p − j) z_j
        kern = tail[(h - 1) - np.arange(h)[:, None] + r, (w - 1) - np.arange(w)[None, :] + cl]
        total = (1 - s) * z[r, cl] + s * np.sum(kern * z)
        predicted = np.mod(np.angle(total), 2 * np.pi) * SPEED_OF_LIGHT / (4 * np.pi * F_MOD)
        assert abs(on.depth_m[r, cl] - predicted) < 2e-3
        checked += 1
    shift = on.depth_m[far] - off.depth_m[far]
    assert checked == 12 and shift.min() < -0.05      # the far wall is pulled towards 0.3 m


def ambient_config(**changes: object) -> TofCameraConfig:
    return base(ambient_irradiance_w_m2=2.0, vignetting=False, **changes)


def test_ambient_light_shot_noise_and_full_well(wall_buffers: RenderBuffers) -> None:
    cfg = ambient_config(exposure_time_s=100e-6)
    ideal = simulate_tof(wall_buffers, cfg, rng=np.random.default_rng(0), noise=False)
    g = cfg.conversion_gain_dn_per_electron
    mean_e = ideal.correlation / g
    dark = simulate_tof(wall_buffers, cfg.model_copy(update={"ambient_light": False}),
                        rng=np.random.default_rng(0), noise=False)
    assert not ideal.saturated.any() and mean_e.mean() > 5 * dark.correlation.mean() / g
    noisy = [simulate_tof(wall_buffers, cfg, rng=np.random.default_rng(i)).correlation
             for i in range(2)]
    # Var(C_i) = (C_i + σ_read²) e⁻² → (·) g² DN² plus 1/12 DN² of quantisation.
    var_dn = (mean_e + cfg.read_noise_electrons**2) * g**2 + 1 / 12
    z = (noisy[0] - ideal.correlation) / np.sqrt(var_dn)
    assert abs(z.std() - 1.0) < 0.02
    # Saturation where the brightest sample (S + B)(1 + m)… reaches the full well.
    bright = ambient_config(exposure_time_s=400e-6)
    out = simulate_tof(wall_buffers, bright, rng=np.random.default_rng(0), noise=False)
    peak_e = mean_e.max(axis=0) * 4.0       # samples scale with exposure
    over, under = peak_e > 1.01 * cfg.full_well_electrons, peak_e < 0.99 * cfg.full_well_electrons
    assert over.any() and under.any()
    assert out.saturated[over].all() and not out.saturated[under].any()


def test_background_suppression_removes_ambient_charge_but_keeps_its_noise(
        wall_buffers: RenderBuffers) -> None:
    cfg = ambient_config(exposure_time_s=400e-6)
    sbi = cfg.model_copy(update={"background_suppression": True})
    plain = simulate_tof(wall_buffers, cfg, rng=np.random.default_rng(0), noise=False)
    assert plain.saturated.any()
    ideal = simulate_tof(wall_buffers, sbi, rng=np.random.default_rng(0), noise=False)
    assert not ideal.saturated.any()
    no_amb = simulate_tof(wall_buffers, sbi.model_copy(update={"ambient_light": False}),
                          rng=np.random.default_rng(0), noise=False)
    np.testing.assert_allclose(ideal.correlation, no_amb.correlation, rtol=1e-4, atol=0.05)
    with_amb = simulate_tof(wall_buffers, cfg.model_copy(update={"exposure_time_s": 100e-6}),
                            rng=np.random.default_rng(0), noise=False).correlation
    noisy = simulate_tof(wall_buffers, sbi, rng=np.random.default_rng(1)).correlation
    g = cfg.conversion_gain_dn_per_electron
    var_dn = (4.0 * with_amb / g + cfg.read_noise_electrons**2) * g**2 + 1 / 12
    z = (noisy - ideal.correlation) / np.sqrt(var_dn)
    assert abs(z.std() - 1.0) < 0.03


def test_switches_reach_cli_and_dataset_vignetting_sweep(tmp_path) -> None:  # type: ignore[no-untyped-def]
    """``tofradar sweep --vary rig.tof.vignetting=0,1``: each dataset records its switch in
    the stored project, and the amplitude ratio of the two is cos⁴ θ (shot noise averaged
    over a ring of pixels)."""
    import json

    import h5py

    from simcore.cli import main
    from simcore.scene import save_project

    cfg = base(width=64, height=48)
    project = Project(objects=[wall(3.0)], rig=SensorRig(tof=cfg))
    project.rig.radar.render_width, project.rig.radar.render_height = 240, 82
    path = tmp_path / "wall.json"
    save_project(project, path)
    out = tmp_path / "sweep"
    assert main(["sweep", str(path), "--vary", "rig.tof.vignetting=0,1", "--out", str(out),
                 "--frames", "1", "--seed", "1"]) == 0
    index = json.loads((out / "sweep.json").read_text())
    amplitude = {}
    for variant in index["variants"]:
        with h5py.File(out / variant["file"]) as f:
            stored = json.loads(f["meta"].attrs["project_json"])
            on = stored["rig"]["tof"]["vignetting"]
            assert on is bool(variant["parameters"]["rig.tof.vignetting"])
            amplitude[on] = f["tof/amplitude"][0].astype(np.float64)
    cos4 = cos_off_axis(cfg) ** 4
    ring = (cos4 > 0.7) & (cos4 < 0.75)
    assert ring.sum() > 100
    ratio = amplitude[True][ring].mean() / amplitude[False][ring].mean()
    assert ratio == pytest.approx(cos4[ring].mean(), rel=0.01)


def test_multipath_albedo_follows_the_lens(monkeypatch: pytest.MonkeyPatch) -> None:
    """With distortion, the diffuse albedo reaches multipath resampled like the buffers.

    Three walls of different albedo (known per object): every pixel of the distorted render
    must get its own object's albedo, also near the image edges where the lens moves
    pixels by many render pixels.
    """
    import simcore.sensors.tof.camera as camera

    cfg = base(distortion=True, multipath=True,
               distortion_coefficients=(-0.37, 0.14, 0.002, -0.003, 0.0))
    objects = [wall(4.0, oid=1, material="white_paint"),
               wall(2.5, oid=2, size=1.2, y=1.0, material="black_plastic"),
               wall(3.0, oid=3, size=1.0, y=-1.2, z=0.5, material="white_paint")]
    buffers = render(objects, cfg)
    per_object = np.array([0.8, 0.05, 0.5, 0.0], dtype=np.float32)   # index −1: nothing
    albedo = per_object[buffers.object_index]
    seen: dict[str, object] = {}

    def spy(buf: RenderBuffers, config: TofCameraConfig, alb: np.ndarray,
            **kwargs: int) -> np.ndarray:
        seen["buffers"], seen["albedo"] = buf, alb
        return original(buf, config, alb, **kwargs)

    original = camera._multipath_planes
    monkeypatch.setattr(camera, "_multipath_planes", spy)
    simulate_tof(buffers, cfg, rng=np.random.default_rng(0), noise=False, albedo=albedo)
    lensed = seen["buffers"]
    assert isinstance(lensed, RenderBuffers)
    moved = lensed.object_index != buffers.object_index
    assert moved.sum() > 100                          # the lens moves object boundaries
    np.testing.assert_array_equal(seen["albedo"], per_object[lensed.object_index])
