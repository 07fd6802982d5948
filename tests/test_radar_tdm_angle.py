"""TDM-MIMO angle through the whole simulator: two equal targets in one range–Doppler cell.

Two equal point targets at 2 m, 10° left and 10° right of boresight, both static, fall into
the same range–Doppler cell of the 2 Tx × 4 Rx TDM radar; the 8-element λ/2 virtual ULA
resolves them in angle (Rayleigh limit ``2 / N = 0.25`` in ``sin az``; they are
``2 sin 10° = 0.35`` apart). Known answer: one detection at (2 m, −10°) and one at
(2 m, +10°) (body y left is optical x negative: azimuth = −bearing), nothing else above
15 dB SNR.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import pytest

from simcore.dsp import DspConfig, process_frame
from simcore.render import RenderRequest, SceneRenderer
from simcore.scene import PointTarget, Pose, Project, SceneObject
from simcore.scene.model import SensorRig
from simcore.scene.radar_presets import tdm_mimo_2tx4rx
from simcore.scene.snapshot import take_snapshot
from simcore.sensors.radar import radar_scatterers, simulate_radar
from simcore.sensors.radar.scene import RadarScene

RANGE_M, BEARING_DEG = 2.0, 10.0


def test_two_targets_in_one_cell_both_detected_without_spurious(
        make_renderer: Callable[..., SceneRenderer]) -> None:
    cfg = tdm_mimo_2tx4rx()
    objects = [
        SceneObject(id=i + 1, name=f"target{i}", geometry=PointTarget(rcs_m2=1.0),
                    pose=Pose(position_m=(RANGE_M * np.cos(np.deg2rad(b)),
                                          RANGE_M * np.sin(np.deg2rad(b)), 0.0)))
        for i, b in enumerate((BEARING_DEG, -BEARING_DEG))]
    project = Project(objects=objects, rig=SensorRig().model_copy(update={"radar": cfg}))
    renderer = make_renderer(project)
    snap = take_snapshot(project, 0.0)
    buffers = renderer.render(snap, RenderRequest("radar", "radar", cfg.render_intrinsics()))
    out = simulate_radar(radar_scatterers(RadarScene.from_project(project, snap), buffers,
                                          config=cfg), cfg,
                         rng=np.random.default_rng(3))
    det = process_frame(out.adc, cfg, DspConfig()).detections
    for i in range(len(det)):
        print(f"R {det.range_m[i]:.3f} m, az {det.azimuth_deg[i]:+.2f}°, "
              f"v {det.velocity_mps[i]:+.3f} m/s, SNR {det.snr_db[i]:.1f} dB")
    strong = det.snr_db > 15.0
    near = np.abs(det.range_m - RANGE_M) < 2 * cfg.range_resolution_m
    for az_true in (-BEARING_DEG, BEARING_DEG):
        hit = near & (np.abs(det.azimuth_deg - az_true) < 2.0) & strong
        assert hit.sum() == 1, f"target at {az_true:+.0f}° detected {hit.sum()} times"
    target = near & (np.minimum(np.abs(det.azimuth_deg - BEARING_DEG),
                                np.abs(det.azimuth_deg + BEARING_DEG)) < 2.0)
    assert not np.any(strong & ~target), "spurious detection above 15 dB SNR"


@pytest.mark.parametrize("az_true", [-25.0, 0.0, 30.0])
def test_a_single_target_still_gives_one_detection(az_true: float) -> None:
    """A lone target: the angle spectrum's sidelobes (−13 dB) add no second detection."""
    from tests.test_dsp import optical_point, synth_cube, ula_config
    rc = ula_config(4, n_tx=2, chirps=16)
    cube = synth_cube(rc, [(optical_point(2.0, az_true), np.zeros(3), 1.0)], noise_std=0.05,
                      seed=2)
    det = process_frame(cube, rc, DspConfig()).detections
    assert len(det) == 1 and abs(det.azimuth_deg[0] - az_true) < 1.0
