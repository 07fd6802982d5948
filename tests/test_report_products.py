"""The radar-products figures of the validation report, against the motion put in."""

from __future__ import annotations

import numpy as np

from simcore.report.products import (
    BREATHING,
    HEARTBEAT,
    chest_vital_signs,
    products_section,
    walker_radial_velocities,
)


def test_products_section_measures_the_synthesised_motion(tmp_path):
    figures, nums = products_section(tmp_path, quick=True)
    assert [f[0] for f in figures] == ["fig12_microdoppler.png", "fig13_vital_signs.png"]
    assert all((tmp_path / f[0]).stat().st_size > 20_000 for f in figures)
    assert nums["torso_peak_within_one_bin_fraction"] >= 0.8
    assert abs(nums["step_frequency_hz"] - nums["true_step_frequency_hz"]) < 0.1
    assert abs(nums["breathing_rate_error_hz"]) < 0.02
    assert abs(nums["breathing_amplitude_error"]) < 0.2
    assert abs(nums["heart_rate_error_hz"]) < 0.1


def test_walker_caricature_follows_boulic_cycle_and_heart_alone_is_found():
    t = np.linspace(0.0, 3.0, 3001)
    v = walker_radial_velocities(t, speed_mps=1.15)
    # Boulic's cycle duration 1.346 / sqrt(v / leg length): 1.18 s at 1.15 m/s, 0.9 m legs.
    leg = v["left_leg"] - v["torso"]
    up = t[1:][(leg[:-1] < 0) & (leg[1:] >= 0)]
    assert np.allclose(np.diff(up), 1.346 / np.sqrt(1.15 / 0.9), atol=2e-3)
    assert np.allclose(v["torso"], -1.15)
    vs, _ = chest_vital_signs(duration_s=30.0, breathing_on=False)
    assert abs(vs.heart_rate_hz - HEARTBEAT[0]) < 0.1
    assert abs(vs.heart_amplitude_m - HEARTBEAT[1]) < 0.2 * HEARTBEAT[1]
    assert BREATHING[0] < 0.6
