"""The ideal-sensor switch of the radar: no receiver noise, no ADC quantisation."""

from __future__ import annotations

import json

import numpy as np

from simcore.resources import example_path
from simcore.scene import load_project
from simcore.scene.radar_config import RadarConfig
from simcore.sensors.radar.frontend import radar_output
from simcore.sensors.radar.receiver import leakage_if


def test_the_ideal_radar_outputs_its_noise_free_if_plus_leakage() -> None:
    cfg = RadarConfig(adc_bits=8, ideal=True)            # the default noise is on
    rng = np.random.default_rng(0)
    shape = (cfg.chirps_per_frame, len(cfg.tx) * len(cfg.rx), cfg.samples_per_chirp)
    ideal = 0.3 * np.exp(2j * np.pi * rng.random(shape))
    out = radar_output(ideal, cfg, rng=np.random.default_rng(1), time_s=0.0, n_scatterers=1)
    expected = (ideal + leakage_if(cfg)).real.astype(np.float32)
    np.testing.assert_array_equal(out.adc, expected)
    assert out.clipped_samples == 0
    # The same radar, not ideal: noise and an 8-bit grid (256 levels).
    real = radar_output(ideal, cfg.model_copy(update={"ideal": False}),
                        rng=np.random.default_rng(1), time_s=0.0, n_scatterers=1)
    assert np.unique(real.adc).size <= 256 < np.unique(out.adc).size


def test_the_switch_is_a_project_field(tmp_path) -> None:
    data = json.loads(open(example_path("wall")).read())
    assert load_project(example_path("wall")).rig.radar.ideal is False      # old files: off
    data["rig"]["radar"]["ideal"] = True
    path = tmp_path / "ideal.json"
    path.write_text(json.dumps(data))
    assert load_project(path).rig.radar.ideal is True
