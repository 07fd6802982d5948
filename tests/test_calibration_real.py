"""The BGT60TR13C preset against the shared real recording (issue #35).

The recording (``../shared/real/bgt60tr13c_breathing``, or ``$TOFRADAR_REAL_RECORDING``)
read through the project's code gives the figures of its README; the project made from it,
simulated with an empty scene, meets the calibration targets (within 3 dB)."""

from __future__ import annotations

import numpy as np
import pytest

from simcore.cli import main
from simcore.io.recordings import read_recording, recording_levels
from simcore.pipeline import Simulator
from simcore.report.real import empty_scene_frames, shared_recording
from simcore.scene import load_project

RECORDING = shared_recording()
pytestmark = pytest.mark.skipif(RECORDING is None, reason="shared real recording absent")

#: The README's figures (dBFS).
README = {"leakage": (-20.0, -17.8, -25.8), "target": -35.9, "beyond_aaf": (-76.4, -75.0),
          "per_sample": -65.1}


@pytest.fixture(scope="module")
def real():
    assert RECORDING is not None
    rec = read_recording(RECORDING)
    return rec, recording_levels(rec.adc(), rec.config)


def test_the_readme_figures_through_the_project_code(real):
    _, lv = real
    print(lv.table())
    assert np.max(np.abs(np.subtract(lv.leakage_dbfs, README["leakage"]))) <= 0.5
    assert abs(lv.target_dbfs - README["target"]) <= 0.5
    assert np.max(np.abs(np.subtract(lv.floor_beyond_aaf_dbfs, README["beyond_aaf"]))) <= 0.5
    assert abs(lv.per_sample_noise_dbfs - README["per_sample"]) <= 0.5


def test_the_project_made_from_it_meets_the_calibration_targets(real, tmp_path):
    """``tofradar convert --project``, then that project through the whole simulator."""
    rec, lv = real
    project_path = tmp_path / "from_recording.json"
    assert main(["convert", str(RECORDING), "--to", str(tmp_path / "real.h5"), "--project",
                 str(project_path)]) == 0
    project = load_project(project_path)
    assert not project.objects and project.rig.radar == rec.config
    with Simulator(project) as sim:
        adc = np.stack([sim.frame(i).outputs["radar"].raw.adc for i in range(24)])
    sim = recording_levels(adc, project.rig.radar)
    print("real", lv.table())
    print("sim ", sim.table())
    assert np.max(np.abs(np.subtract(sim.leakage_dbfs, lv.leakage_dbfs))) <= 3.0
    assert abs(sim.floor_beyond_aaf_mean_dbfs - lv.floor_beyond_aaf_mean_dbfs) <= 3.0
    assert abs(sim.floor_in_band_dbfs - lv.floor_in_band_dbfs) <= 3.0
    assert abs(sim.per_sample_noise_dbfs - lv.per_sample_noise_dbfs) <= 3.0


def test_the_receiver_alone_gives_the_same_levels(real):
    """The report's shortcut (the receiver on an empty scene) equals the pipeline's levels."""
    rec, lv = real
    sim = recording_levels(empty_scene_frames(rec.config, frames=64, seed=3), rec.config)
    assert np.max(np.abs(np.subtract(sim.leakage_dbfs, lv.leakage_dbfs))) <= 3.0
    assert abs(sim.per_sample_noise_dbfs - lv.per_sample_noise_dbfs) <= 3.0


def test_the_report_section_on_the_real_recording(real, tmp_path):
    """The section's numbers: the calibrated rows within 3 dB, the README's target, the
    breathing through the vital-sign estimator at the README's ≈ 0.24 Hz near 0.33 m, and
    the torso and the person simulated there (their levels beside the real one)."""
    from simcore.report.real import real_section

    file, title, text, nums = real_section(tmp_path, quick=True)
    assert (tmp_path / file).stat().st_size > 20_000 and title.endswith("BGT60TR13C")
    for name, measured, _before, after in nums["rows"]:
        assert abs(after - measured) <= 3.0, name
    assert abs(nums["target_real_dbfs"] - README["target"]) <= 0.5
    assert abs(nums["breathing_rate_hz"] - 0.24) <= 0.02
    assert abs(nums["breathing_range_m"] - 0.33) <= 0.03
    assert 0.5 <= nums["breathing_amplitude_mm"] <= 10.0      # a chest, not noise nor steps
    for body in ("torso", "person"):
        lv = nums[body]
        if lv is None:           # no OpenGL on this machine
            continue
        assert lv["min_dbfs"] <= lv["mean_dbfs"] <= lv["max_dbfs"] < 0.0   # no clipping
        assert lv["min_dbfs"] > nums["rows"][-1][1] + 20        # well above the noise
        assert f"{lv['mean_dbfs']:.1f} dBFS" in text
