"""`tofradar report` runs headless and its numbers meet the bars of the earlier issues."""

from __future__ import annotations

import json

from simcore.cli import main
from simcore.report.real import shared_recording


def test_quick_report_figures_and_numbers(tmp_path):
    out = tmp_path / "validation"
    assert main(["report", "--out", str(out), "--quick", "--quiet"]) == 0
    figures = sorted(p.name for p in out.glob("fig*.png"))
    assert len(figures) == 17 + (shared_recording() is not None)   # 17th: Sionna office
    assert all((out / f).stat().st_size > 20_000 for f in figures)   # real plots, not blanks
    readme = (out / "README.md").read_text()
    assert all(f in readme for f in figures)
    n = json.loads((out / "numbers.json").read_text())

    tof = n["office_tof"]
    assert tof["retro_invalid_fraction"] == 1.0 and tof["retro_depth_zero_fraction"] == 1.0
    assert tof["ring_pulled_fraction"] > 0.5                 # cross-talk toward the reflector
    assert tof["backrest_amplitude_dn"] < 0.5 * tof["wall_amplitude_dn"]
    assert tof["plate_amplitude_dn"] > tof["wall_amplitude_dn"]

    radar = n["office_radar"]
    assert radar["corner_over_clutter_db"] > 10             # seen through the paper box
    assert radar["noise_floor_db"] < radar["corner_peak_db"] - 30
    assert radar["near_zero_db"] < radar["noise_floor_db"]   # high-pass roll-off
    assert radar["clutter_1p5_2p3_over_noise_db"] >= 12      # the floor, not empty space
    assert "in the empty space before" not in readme           # the old ±22° artefact
    # The corner sits in the walls' diffuse clutter, whose speckle follows the facets: a
    # 3-Rx L array at its ≈ 3.5 m places it within ≈ 3° (0.2 m) across tessellations.
    assert n["office_range_azimuth"]["corner_detected_error_m"] < 0.2

    dop = n["doppler"]
    assert dop["detected_fraction"] == 1.0
    assert dop["within_one_bin_fraction"] == 1.0

    cal = n["calibration"]
    assert cal["power_vs_range"]["max_abs_error_db"] < 0.5
    pt = cal["point_targets"]
    assert pt["all_detected"]
    assert pt["max_range_err_bins"] < 0.25
    assert pt["max_velocity_err_bins"] < 1.0
    assert pt["max_azimuth_err_deg"] < 2.0
    assert cal["if_synthesis"]["error_db"] < -60
    assert abs(cal["resolution"]["change_db"]) < 1.0

    side = n["side_by_side"]
    assert side["time_s"] == side["radar_time_s"]
    assert side["tof_points"] > 10_000 and side["radar_detections"] > 0

    real = n["real_bgt60tr13c"]
    if shared_recording() is None:
        assert real["recording"] is None and "is not present" in readme
    else:   # issue #35: the calibrated front end within 3 dB of the real device
        assert "Simulation and a real BGT60TR13C" in readme
        for name, measured, _before, after in real["rows"]:
            assert abs(after - measured) <= 3.0, name
        assert 0.1 <= real["breathing_rate_hz"] <= 0.5

    # Surfaces (#15): the bars of the issue, measured by the report itself.
    surf = n["surfaces"]
    assert "## 7. Surfaces" in readme
    plate = surf["plate"]
    assert abs(plate["normal_incidence_error_db"]) <= 1.0       # 4πA²/λ²
    assert plate["main_lobe_max_abs_error_db"] <= 1.0           # the PO sinc, main lobe
    assert plate["at_first_null_db"] < -20
    assert max(plate["angles_deg"]) > plate["first_null_deg"]  # swept beyond the null
    assert surf["sphere"]["max_abs_error_db"] <= 1.5            # πr²
    assert surf["office_floor"]["floor_over_noise_db"] >= 12    # 1.5–2.3 m
    rig = surf["moving_rig"]
    assert rig["frames"] == 20 and rig["step_m"] == 0.02
    assert rig["max_step_beyond_model_db"] <= 1.0

    ghost = n["multipath"]["radar"]
    assert isinstance(ghost, dict) and ghost                   # the radar multipath section
    # Interference (#30): bursts buried the weak target, interpolation brings it back with
    # a floor ≥ 10 dB lower; jitter and hopping remove the equal-slope ghost.
    inter = n["interference"]
    assert inter["clean"]["target_found"] and not inter["bursts, off"]["target_found"]
    assert inter["bursts, interpolation"]["target_found"]
    assert inter["bursts, off"]["floor_db"] - inter["bursts, interpolation"]["floor_db"] >= 10
    assert inter["ghost, off"]["inr_db"] > 20
    assert inter["ghost, chirp jitter"]["inr_db"] < inter["ghost, off"]["inr_db"] - 10
    assert inter["ghost, hopping"]["inr_db"] < inter["ghost, off"]["inr_db"] - 10
    # ToF MPI (#16, #42): without it the ideal camera measures the rendered range (0 off the
    # depth edges); with it the room's surfaces read long. (Not every object: light bounced
    # several times can come more than half the 15 m modulation wavelength late, and its
    # phasor then pulls a near object's phase short — the chair seat by a few cm; the
    # office against the path tracer, pixel by pixel, is tests/test_tof_mitransient.py.)
    mpi = n["multipath"]["tof"]
    assert mpi["median_abs_error_off_mm"] < 1.0
    assert mpi["median_shift_mm"] > 5.0
    objs = mpi["per_object"]
    assert all(objs[w]["median_mm"] > 10.0 for w in ("floor", "back_wall", "left_wall",
                                                       "right_wall", "ceiling")), objs
