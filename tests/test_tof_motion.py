"""Motion artefacts by reprojection: each correlation sample at its own time, no extra renders.

A wall facing the camera recedes along the optical axis at v; pixel ray d (unit, optical
frame) meets it at R_i = R_0 + v t_i / d_z at sample time t_i = i Δt. The four samples
C_i = S_i + B + m S_i cos(4π f R_i / c + iπ/2), S_i ∝ 1/R_i², give the depth written out
here; the reprojected frame must match it at every pixel and match the four-render frame.
"""

from __future__ import annotations

import numpy as np
from scenes import wall_project

from simcore.render import RenderRequest
from simcore.scene import Motion
from simcore.scene.snapshot import take_snapshot
from simcore.scene.tof_config import SPEED_OF_LIGHT
from simcore.sensors.tof.camera import simulate_tof


def test_receding_wall_per_sample_phase_error_by_reprojection(make_renderer) -> None:  # type: ignore[no-untyped-def]
    v, d0 = 30.0, 2.0
    project = wall_project(d0, material="white_paint")
    project.objects[0].motion = Motion(velocity_mps=(v, 0.0, 0.0))
    cfg = project.rig.tof.model_copy(update={
        "crosstalk_sigma_px": 0.0, "supersampling": 1, "motion_artifacts": True,
        "motion_sampling": "reprojection", "auto_exposure": False})
    renderer = make_renderer(project)
    intr = cfg.render_intrinsics()
    dt = cfg.sample_interval_s
    frame = renderer.render(take_snapshot(project, 0.0), RenderRequest("tof", "tof", intr))
    out = simulate_tof(frame, cfg, rng=np.random.default_rng(0), noise=False)
    still = simulate_tof(frame, cfg.model_copy(update={"motion_artifacts": False}),
                         rng=np.random.default_rng(0), noise=False)
    f = cfg.modulation_frequencies_hz[0]
    rows = np.arange(20, cfg.height - 20, 30)
    cols = np.arange(20, cfg.width - 20, 40)
    artefact = []
    for row in rows:
        for col in cols:
            r0 = float(frame.range_m[row, col])
            dz = float(frame.points_m[row, col, 2]) / r0
            r = r0 + v * dt * np.arange(4) / dz
            sig = cfg.signal_electrons_at_1m * float(frame.intensity[row, col]) / r**2
            amb = cfg.ambient_electrons * float(frame.intensity[row, col])
            corr = sig + amb + cfg.demodulation_contrast * sig * np.cos(
                4 * np.pi * f * r / SPEED_OF_LIGHT + np.arange(4) * np.pi / 2)
            phase = np.arctan2(corr[3] - corr[1], corr[0] - corr[2]) % (2 * np.pi)
            expected = phase * SPEED_OF_LIGHT / (4 * np.pi * f)
            assert abs(out.depth_m[row, col] - expected) < 1e-3
            artefact.append(abs(out.depth_m[row, col] - still.depth_m[row, col]))
    assert max(artefact) > 3e-3        # real: millimetres (float error is micrometres)
    # The same as four renders at the samples' times (away from the wall's edges).
    samples = [frame] + [renderer.render(take_snapshot(project, i * dt),
                                         RenderRequest("tof", "tof", intr)) for i in (1, 2, 3)]
    rendered = simulate_tof(frame, cfg.model_copy(update={"motion_sampling": "renders"}),
                            rng=np.random.default_rng(0), noise=False, sample_buffers=samples)
    inner = (slice(10, -10), slice(10, -10))
    np.testing.assert_allclose(out.depth_m[inner], rendered.depth_m[inner], atol=1e-3)
