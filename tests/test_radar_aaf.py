"""The IF anti-aliasing low-pass: a target beyond the maximum range is attenuated by the
filter's response at its beat frequency instead of folding back at full level."""

from __future__ import annotations

import numpy as np
import pytest

from simcore.scene.radar_config import SPEED_OF_LIGHT
from simcore.scene.radar_presets import bgt60tr13c
from simcore.sensors.radar.scatterers import Scatterers
from simcore.sensors.radar.synthesis import synthesize_if, synthesize_if_direct


def butterworth_lowpass_db(f_hz: float, cutoff_hz: float, order: int) -> float:
    return -10 * np.log10(1 + (f_hz / cutoff_hz) ** (2 * order))


def target(range_m: float, az_deg: float = 0.0) -> Scatterers:
    az = np.deg2rad(az_deg)
    return Scatterers.from_arrays(range_m * np.array([[np.sin(az), 0.0, np.cos(az)]]), [1.0])


@pytest.mark.parametrize("range_m", [8.0, 11.0])
def test_a_target_beyond_the_maximum_range_is_attenuated_by_the_filter(range_m):
    cfg = bgt60tr13c(noise_variance_adc=0.0, if_highpass_hz=0.0, if_lowpass_hz=0.0)
    assert range_m > cfg.max_range_m
    cutoff, order = 0.8e6, 4
    filtered = cfg.model_copy(update={"if_lowpass_hz": cutoff, "if_lowpass_order": order})
    f_beat = 2 * range_m * cfg.slope_hz_per_s / SPEED_OF_LIGHT     # above f_s/2 = 1 MHz
    plain = synthesize_if(target(range_m), cfg)[0, 0].real
    aaf = synthesize_if(target(range_m), filtered)[0, 0].real
    w = np.hanning(len(plain))
    peak = [np.abs(np.fft.rfft(x * w)).max() for x in (plain, aaf)]
    measured = 20 * np.log10(peak[1] / peak[0])
    expected = butterworth_lowpass_db(f_beat, cutoff, order)
    print(f"{range_m} m: f_b = {f_beat / 1e6:.3f} MHz, {measured:.2f} dB vs {expected:.2f} dB")
    assert abs(measured - expected) < 1.0
    assert expected < -6.0


def test_fast_synthesis_with_the_filter_matches_the_direct_sum():
    rng = np.random.default_rng(1)
    cfg = bgt60tr13c(chirps_per_frame=4).model_copy(update={"if_lowpass_hz": 0.6e6})
    pos = rng.uniform([-2, -1, 0.5], [2, 1, 9], size=(200, 3))
    vel = np.where(rng.random((200, 1)) < 0.5, rng.normal(0, 1.0, (200, 3)), 0.0)
    sc = Scatterers.from_arrays(pos, rng.uniform(0.01, 1, 200), velocities_mps=vel)
    fast, ref = synthesize_if(sc, cfg), synthesize_if_direct(sc, cfg)
    err_db = 20 * np.log10(np.linalg.norm(fast - ref) / np.linalg.norm(ref))
    assert err_db < -60.0


def test_the_filter_must_lie_above_the_high_pass():
    from pydantic import ValidationError

    from simcore.scene.radar_config import RadarConfig

    with pytest.raises(ValidationError, match="if_lowpass_hz"):
        RadarConfig.model_validate(bgt60tr13c().model_dump() | {"if_lowpass_hz": 50e3})


def test_the_preset_and_its_bundled_examples_use_the_vendor_filters():
    """Infineon's Radar SDK defaults for the BGT60TR13C: HP 80 kHz, AAF 500 kHz; every
    bundled example on the preset keeps both (as loaded, so a migration cannot drop them)."""
    import json

    from simcore.resources import example_path
    from simcore.scene.project_io import load_project

    cfg = bgt60tr13c()
    assert (cfg.if_highpass_hz, cfg.if_lowpass_hz) == (80e3, 500e3)
    examples = sorted(example_path("wall").parent.glob("*.json"))
    using = [p for p in examples
             if json.loads(p.read_text()).get("rig", {}).get("radar", {}).get("preset")
             == "bgt60tr13c"]
    assert len(using) >= 10
    for path in using:
        radar = load_project(path).rig.radar
        assert radar.if_lowpass_hz == 500e3, path.name
        assert radar.if_highpass_hz == 80e3, path.name
