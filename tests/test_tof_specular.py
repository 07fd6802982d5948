"""Specular near-IR inter-reflections: a metal trihedral retroreflects, a metal plate does not.

The trihedral (``CornerReflector`` geometry, aluminium) faces the camera with its apex on
the optical axis at 1.5 m. Its triple-bounce rays leave antiparallel to the camera ray
``u``; unfolded, the three reflections are the point reflection ``X → 2A − X`` through
the apex A, whose closest approach to the camera is at the path length ``2 u·A``: the
pixel's measured range is ``u·A`` (the apex projected on its ray), not the facet's range.
"""

from __future__ import annotations

import numpy as np

from simcore.render import RenderRequest, SceneRenderer
from simcore.scene import Pose, Project, SceneObject
from simcore.scene.geometry import Box, CornerReflector
from simcore.scene.model import SensorRig
from simcore.scene.snapshot import take_snapshot
from simcore.scene.tof_config import TofCameraConfig
from simcore.sensors.tof.camera import simulate_tof, specular_factor
from simcore.sensors.tof.sensor import mirror_table, tof_bands

APEX_M = 1.5
EDGE_M = 0.1


def _render(project: Project, cfg: TofCameraConfig):  # type: ignore[no-untyped-def]
    renderer = SceneRenderer(project)
    try:
        return renderer.render(take_snapshot(project, 0.0),
                               RenderRequest("tof", "tof", cfg.render_intrinsics()))
    finally:
        renderer.close()


def trihedral(**tof: object) -> tuple[Project, TofCameraConfig]:
    # Local +z (the opening) turned to −x world: towards the camera at the origin.
    obj = SceneObject(id=1, name="trihedral", geometry=CornerReflector(edge_m=EDGE_M),
                      pose=Pose(position_m=(APEX_M, 0.0, 0.0), rotation_deg=(0.0, -90.0, 0.0)),
                      material="aluminium")
    cfg = TofCameraConfig(crosstalk_sigma_px=0.0, specular=True, **tof)  # type: ignore[arg-type]
    return Project(objects=[obj], rig=SensorRig(tof=cfg)), cfg


def test_metal_trihedral_returns_its_apex_range_with_auto_exposure() -> None:
    project, cfg = trihedral(auto_exposure=True)
    buf = _render(project, cfg)
    out = simulate_tof(buf, cfg, rng=np.random.default_rng(0), noise=True,
                       mirrors=mirror_table(tof_bands(project)))
    # Fully covered sensor pixels of the reflector.
    k = cfg.supersampling
    cover = (buf.object_index >= 0).reshape(cfg.height, k, cfg.width, k).all(axis=(1, 3))
    assert cover.sum() > 50
    valid = out.valid & cover
    print("valid fraction", valid.sum() / cover.sum())
    assert valid.sum() >= 0.55 * cover.sum()
    # Expected range: the apex projected on each pixel's ray, u·A.
    rays = cfg.intrinsics().ray_directions()
    u = rays / np.linalg.norm(rays, axis=-1, keepdims=True)
    expected = u[..., 2] * APEX_M       # apex on the optical axis: A = (0, 0, 1.5) optical
    ideal = simulate_tof(buf, cfg, rng=np.random.default_rng(0), noise=False,
                         mirrors=mirror_table(tof_bands(project)))
    valid = valid & ideal.valid
    err = ideal.depth_m[valid] - expected[valid]
    print("depth error median/max (mm)", np.median(np.abs(err)) * 1e3, np.abs(err).max() * 1e3)
    assert np.median(np.abs(err)) < 0.01
    assert np.percentile(np.abs(err), 95) < 0.02
    # The camera with shot and read noise: its valid pixels read the apex range too,
    # unbiased (mean within 5 mm: the standard error of ~80 pixels of σ ≈ 1 cm is ≈ 1 mm)
    # and the typical pixel within 2 cm (measured: mean 0.8 mm, σ 10 mm, 94 % < 2 cm).
    noisy = out.depth_m[valid] - expected[valid]
    print("noisy depth error mean/std/median|.| (mm)", noisy.mean() * 1e3,
          noisy.std() * 1e3, np.median(np.abs(noisy)) * 1e3)
    assert abs(noisy.mean()) < 0.005
    assert np.median(np.abs(noisy)) < 0.02
    # Not the facets' own depth: the facets lie nearer than the apex.
    facet = out.gt_range[valid]
    assert np.median(expected[valid] - facet) > 0.02 > 3 * np.median(np.abs(err))


def test_trihedral_saturates_at_fixed_exposure_where_its_signal_exceeds_the_full_well() -> None:
    project, cfg = trihedral(auto_exposure=False, exposure_time_s=1e-3)
    buf = _render(project, cfg)
    out = simulate_tof(buf, cfg, rng=np.random.default_rng(0), noise=False,
                       mirrors=mirror_table(tof_bands(project)))
    factor, _ = specular_factor(buf, mirror_table(tof_bands(project)), step=cfg.supersampling)
    # Computed irradiance → electrons of the brightest sample, per sensor pixel.
    k = cfg.supersampling
    direct = buf.intensity / np.maximum(buf.range_m, 1e-3) ** 2
    direct = np.where(buf.object_index >= 0, direct, 0.0)
    s = (factor.sum(axis=0) + direct).reshape(cfg.height, k, cfg.width, k).mean(axis=(1, 3))
    peak = s * cfg.signal_electrons_at_1m * (1 + cfg.demodulation_contrast)
    over = peak > cfg.full_well_electrons * 1.02
    under = peak < cfg.full_well_electrons * 0.98
    assert over.sum() > 50, "a 1 ms exposure saturates the retroreflection"
    assert out.saturated[over].all()
    assert not out.saturated[under].any()


def test_metal_plate_is_dark_except_near_normal_incidence() -> None:
    # A 1 m aluminium plate at 2 m, turned by yaw: no mirror path comes back (nothing to
    # bounce to), so only its direct lobe returns: bright at 0°, dark at 45°.
    valid_fraction = {}
    for yaw in (0.0, 45.0):
        plate = SceneObject(id=1, name="plate", geometry=Box(size_m=(0.01, 1.0, 1.0)),
                            pose=Pose(position_m=(2.0, 0.0, 0.0), rotation_deg=(0.0, 0.0, yaw)),
                            material="aluminium")
        cfg = TofCameraConfig(crosstalk_sigma_px=0.0, specular=True)
        project = Project(objects=[plate], rig=SensorRig(tof=cfg))
        buf = _render(project, cfg)
        out = simulate_tof(buf, cfg, rng=np.random.default_rng(0), noise=False,
                           mirrors=mirror_table(tof_bands(project)))
        seen = out.gt_object_id == 1
        valid_fraction[yaw] = out.valid[seen].mean()
    print(valid_fraction)
    assert valid_fraction[0.0] > 0.2
    assert valid_fraction[45.0] < 0.01
