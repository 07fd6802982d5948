"""Multi-frequency ToF: a three-frequency (Kinect v2) camera unwraps over c / (2 gcd).

Known answers: the wall's distance along each pixel ray from the field of view; the
unambiguous ranges ``c / (2 f)``; unwrapping errors are whole wraps, so their rate is
counted as errors above half a metre.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose

from simcore.render import RenderRequest, render_once
from simcore.scene import Plane, Pose, Project, SceneObject
from simcore.scene.model import SensorRig
from simcore.scene.tof_config import SPEED_OF_LIGHT, TofCameraConfig, tof_preset
from simcore.sensors.tof.camera import simulate_tof, unwrap_frequencies, unwrap_two_frequencies

KINECT_HZ = (80e6, 16e6, 120e6)               # libfreenect2's three frequencies
WALL_M = 12.0                                 # beyond 1.87, 9.37 and 1.25 m


def ray_norms(cfg: TofCameraConfig) -> np.ndarray:
    """|(x/z, y/z, 1)| at every sensor pixel centre, from the field of view alone."""
    fx = 0.5 * cfg.width / math.tan(math.radians(cfg.fov_h_deg) / 2)
    fy = 0.5 * cfg.height / math.tan(math.radians(cfg.fov_v_deg) / 2)
    u = (np.arange(cfg.width) + 0.5 - cfg.width / 2) / fx
    v = (np.arange(cfg.height) + 0.5 - cfg.height / 2) / fy
    return np.sqrt(1.0 + u[None, :] ** 2 + v[:, None] ** 2)


@pytest.fixture(scope="module")
def far_wall():
    cfg = tof_preset("kinect_v2").model_copy(update={"illumination_power_w": 20.0})
    wall = SceneObject(id=1, name="wall", geometry=Plane(size_m=(40.0, 40.0)),
                       pose=Pose(position_m=(WALL_M, 0.0, 1.0), rotation_deg=(0.0, 90.0, 0.0)),
                       material="white_paint")
    project = Project(objects=[wall],
                      rig=SensorRig(pose=Pose(position_m=(0.0, 0.0, 1.0)), tof=cfg))
    buffers = render_once(project, RenderRequest("tof", "tof", cfg.render_intrinsics()))
    return cfg, buffers, WALL_M * ray_norms(cfg)


def test_three_frequency_camera_measures_a_wall_beyond_every_single_range(far_wall):
    cfg, buffers, truth = far_wall
    assert all(truth.min() > SPEED_OF_LIGHT / (2 * f) for f in KINECT_HZ)
    assert truth.max() < cfg.combined_unambiguous_range_m        # 18.74 m
    out = simulate_tof(buffers, cfg, rng=np.random.default_rng(0), noise=False)
    assert out.valid.mean() > 0.99
    assert np.abs(out.depth_m - truth)[out.valid].max() < 0.01
    # Each frequency alone reports the wall wrapped into its own range.
    for f in KINECT_HZ:
        one = simulate_tof(buffers, cfg.model_copy(update={"modulation_frequencies_hz": [f]}),
                           rng=np.random.default_rng(0), noise=False)
        r = SPEED_OF_LIGHT / (2 * f)
        centre = (slice(200, 224), slice(240, 272))
        assert_allclose(one.depth_m[centre], np.mod(truth[centre], r), atol=0.01)
    # With noise the unwrapping still picks the right wrap everywhere it is valid.
    noisy = simulate_tof(buffers, cfg, rng=np.random.default_rng(1), noise=True)
    assert noisy.valid.mean() > 0.95
    assert np.abs(noisy.depth_m - truth)[noisy.valid].max() < 0.5


def _wrap_errors(depth, truth) -> float:
    return float(np.mean(np.abs(depth - truth) > 0.5))


def test_camera_unwrapping_errors_rise_as_the_signal_falls(far_wall):
    cfg, buffers, truth = far_wall
    rates = []
    for power in (20.0, 0.5, 0.1):
        dim = cfg.model_copy(update={"illumination_power_w": power, "min_amplitude_dn": 0.0})
        out = simulate_tof(buffers, dim, rng=np.random.default_rng(2), noise=True)
        rates.append(_wrap_errors(out.depth_m, truth))
    assert rates[0] == 0.0
    assert rates[0] < rates[1] < rates[2]
    assert rates[2] > 0.05


def test_unwrap_frequencies_known_answers_and_error_rate_against_phase_noise():
    rng = np.random.default_rng(5)
    r_max = SPEED_OF_LIGHT / (2 * 8e6)                     # gcd 8 MHz: 18.74 m
    d = rng.uniform(0.0, r_max, size=(200, 200))
    ranges = [SPEED_OF_LIGHT / (2 * f) for f in KINECT_HZ]

    def unwrap(sigma_rad: float) -> np.ndarray:
        wrapped = [np.mod(d + rng.normal(0.0, sigma_rad, d.shape) * r / (2 * np.pi), r)
                   for r in ranges]
        return unwrap_frequencies(wrapped, KINECT_HZ)

    exact = unwrap(0.0)
    diff = np.abs(exact - d)
    assert np.minimum(diff, r_max - diff).max() < 1e-5
    rates = []
    for sigma in (0.01, 0.05, 0.15, 0.3, 0.6):
        out = unwrap(sigma)
        diff = np.abs(out - d)
        rates.append(float(np.mean(np.minimum(diff, r_max - diff) > 0.5)))
    assert rates[0] == 0.0 and rates[1] == 0.0
    assert all(b >= a for a, b in zip(rates, rates[1:], strict=False))
    assert rates[-1] > 0.1
    # Two frequencies: the same function gives the two-frequency unwrapping.
    two = [np.mod(d, ranges[0]), np.mod(d, ranges[1])]
    assert_allclose(unwrap_frequencies(two, KINECT_HZ[:2]),
                    unwrap_two_frequencies(*two, *KINECT_HZ[:2]))


def test_three_frequencies_are_validated():
    cfg = TofCameraConfig(modulation_frequencies_hz=list(KINECT_HZ))
    assert_allclose(cfg.combined_unambiguous_range_m, SPEED_OF_LIGHT / (2 * 8e6))
    with pytest.raises(ValueError, match="must differ"):
        TofCameraConfig(modulation_frequencies_hz=[80e6, 16e6, 80e6])
    with pytest.raises(ValueError, match="greatest common divisor"):
        TofCameraConfig(modulation_frequencies_hz=[80e6, 16e6, 120.001e6])
    with pytest.raises(ValueError):
        TofCameraConfig(modulation_frequencies_hz=[80e6, 16e6, 120e6, 40e6])
