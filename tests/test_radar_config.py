"""Radar configuration: presets, validation, warnings, array layouts, element patterns."""

from __future__ import annotations

import numpy as np
import pytest
from numpy.testing import assert_allclose
from pydantic import ValidationError

from simcore.scene.radar_arrays import circular, custom_array, l_shape, ula, ura
from simcore.scene.radar_config import (
    SPEED_OF_LIGHT,
    Antenna,
    CosinePattern,
    RadarConfig,
    TablePattern,
    aliasing_warnings,
)
from simcore.scene.radar_presets import bgt60tr13c, radar_preset, tdm_mimo_2tx4rx
from simcore.sensors.radar.scatterers import trihedral_effective_area
from simcore.sensors.radar.synthesis import element_gain, highpass_response


def positions(antennas: list[Antenna]) -> np.ndarray:
    return np.array([a.position_mm for a in antennas])


def test_bgt60tr13c_preset_matches_the_datasheet_numbers() -> None:
    cfg = radar_preset("bgt60tr13c")
    assert cfg.start_frequency_hz == 60e9 and cfg.bandwidth_hz == 6e9
    assert cfg.sample_rate_hz == 2e6 and cfg.samples_per_chirp == 512
    assert cfg.chirps_per_frame == 16 and not cfg.complex_iq
    assert len(cfg.tx) == 1 and len(cfg.rx) == 3
    half_lambda_mm = 0.5 * SPEED_OF_LIGHT / 60e9 * 1e3
    assert_allclose(positions(cfg.rx), [[half_lambda_mm, 0], [0, 0], [0, -half_lambda_mm]])
    assert_allclose(cfg.max_range_m, 512 * SPEED_OF_LIGHT / (4 * 6e9), rtol=1e-12)  # 6.4 m
    assert_allclose(cfg.range_resolution_m, SPEED_OF_LIGHT / (2 * 6e9), rtol=1e-12)
    assert aliasing_warnings(cfg) == []


def test_mimo_preset_forms_a_half_wavelength_virtual_ula() -> None:
    cfg = tdm_mimo_2tx4rx()
    assert len(cfg.tx) == 2 and len(cfg.rx) == 4 and cfg.complex_iq
    virt = cfg.virtual_positions_m()
    assert virt.shape == (8, 3)
    x = np.sort(virt[:, 0])
    lam = SPEED_OF_LIGHT / 62e9
    assert_allclose(np.diff(x), lam / 2, rtol=1e-9)
    assert_allclose(virt[:, 1:], 0.0)
    # TDM: Tx1, Tx2, Tx1, … one chirp repetition time apart.
    starts = cfg.chirp_start_times_s()
    assert starts.shape == (64, 2)
    assert_allclose(starts.ravel(), np.arange(128) * cfg.chirp_repetition_time_s)
    assert aliasing_warnings(cfg) == []


def test_unknown_preset_is_a_clear_error() -> None:
    with pytest.raises(ValueError, match="unknown radar preset 'nope'.*bgt60tr13c"):
        radar_preset("nope")


@pytest.mark.parametrize(
    ("update", "message"),
    [
        ({"sample_rate_hz": 0.0}, "sample_rate_hz"),
        ({"sample_rate_hz": -2e6}, "sample_rate_hz"),
        ({"chirp_time_s": 100e-6}, "exceeds chirp_time_s"),
        ({"chirp_repetition_time_s": 200e-6}, "shorter than chirp_time_s"),
        ({"if_highpass_hz": 1.5e6}, "below the IF bandwidth"),
        ({"adc_bits": 0}, "adc_bits"),
        ({"leakage_dbc": 3.0}, "leakage_dbc"),
        ({"rx": [Antenna(name="a"), Antenna(name="a", position_mm=(1, 0))]}, "duplicate"),
        ({"tx": []}, "tx"),
    ],
)
def test_impossible_configs_are_rejected_with_the_field_named(update: dict, message: str
                                                              ) -> None:
    values = bgt60tr13c().model_dump()
    values.update(update)
    with pytest.raises(ValidationError, match=message):
        RadarConfig(**values)


def test_aliasing_warnings_name_the_problem() -> None:
    cfg = bgt60tr13c()
    assert aliasing_warnings(cfg, ranges_m=np.array([1.0, 5.0, np.nan])) == []
    msgs = aliasing_warnings(cfg, ranges_m=np.array([1.0, 7.5, 9.0]))
    assert len(msgs) == 1 and "2 scene points" in msgs[0] and "6.40 m" in msgs[0]
    msgs = aliasing_warnings(cfg, radial_velocities_mps=np.array([0.5, -30.0]))
    assert len(msgs) == 1 and "unambiguous velocity" in msgs[0]
    wide = cfg.model_copy(update={"rx": ula(3, 6.0)})
    assert any("grating lobes" in m for m in aliasing_warnings(wide))
    same = cfg.model_copy(update={"rx": custom_array([(0, 0), (0, 0)])})
    assert any("same position" in m for m in aliasing_warnings(same))


def test_array_layouts() -> None:
    assert_allclose(positions(ula(4, 2.5)), [[0, 0], [2.5, 0], [5, 0], [7.5, 0]])
    assert_allclose(positions(ula(3, -2.0, axis="y", origin_mm=(1, 1))),
                    [[1, 1], [1, -1], [1, -3]])
    assert_allclose(positions(ura(2, 3, 2.0, 1.0)),
                    [[0, 0], [2, 0], [0, 1], [2, 1], [0, 2], [2, 2]])
    assert_allclose(positions(l_shape(2, 2, 2.5)), positions(RadarConfig().rx))
    assert_allclose(positions(l_shape(3, 2, 1.0)), [[2, 0], [1, 0], [0, 0], [0, -1]])
    ring = positions(circular(6, 5.0, start_deg=90))
    assert_allclose(np.hypot(ring[:, 0], ring[:, 1]), 5.0)
    assert_allclose(ring[0], [0, 5], atol=1e-12)
    names = [a.name for a in ula(3, 1.0, prefix="tx")]
    assert names == ["tx1", "tx2", "tx3"]
    with pytest.raises(ValueError, match="axis"):
        ula(2, 1.0, axis="z")


def test_cosine_pattern_is_half_power_at_forty_degrees() -> None:
    pattern = CosinePattern()
    az = np.deg2rad([0.0, 40.0, -40.0, 95.0])
    dirs = np.stack([np.sin(az), np.zeros(4), np.cos(az)], axis=1)
    assert_allclose(element_gain(pattern, dirs), [1.0, 0.5, 0.5, 0.0], atol=2e-3)
    up = np.array([[0.0, -np.sin(np.deg2rad(40)), np.cos(np.deg2rad(40))]])
    assert_allclose(element_gain(pattern, up), 0.5, atol=2e-3)
    assert_allclose(element_gain(CosinePattern(exponent_az=0, exponent_el=0), dirs[:3]), 1.0)


def test_table_pattern_interpolates_in_db_and_holds_its_edges() -> None:
    table = TablePattern(azimuth_deg=[-60, 0, 60], elevation_deg=[-30, 30],
                         gain_db=[[-12, 0, -6], [-12, 0, -6]])
    az = np.deg2rad([0.0, 30.0, -30.0, 80.0])
    dirs = np.stack([np.sin(az), np.zeros(4), np.cos(az)], axis=1)
    assert_allclose(10 * np.log10(element_gain(table, dirs)), [0, -3, -6, -6], atol=1e-9)
    with pytest.raises(ValidationError, match="shape"):
        TablePattern(azimuth_deg=[0, 1], elevation_deg=[0, 1], gain_db=[[0, 0]])
    with pytest.raises(ValidationError, match="increasing"):
        TablePattern(azimuth_deg=[1, 0], elevation_deg=[0, 1], gain_db=[[0, 0], [0, 0]])


def test_trihedral_effective_area_known_values() -> None:
    a = 0.1
    axis = np.ones(3) / np.sqrt(3)
    assert_allclose(trihedral_effective_area(axis, a), a**2 / np.sqrt(3), rtol=1e-12)
    lam = 5e-3
    rcs = 4 * np.pi * trihedral_effective_area(axis, a) ** 2 / lam**2
    assert_allclose(rcs, 4 * np.pi * a**4 / (3 * lam**2), rtol=1e-12)
    # Along an edge or outside the octant nothing comes back.
    assert trihedral_effective_area(np.array([1.0, 0, 0]), a) == 0
    assert trihedral_effective_area(np.array([-0.1, 0.7, 0.7]), a) == 0
    # The two branches meet where l + m = n, at (1, 1, 2)/√6; the area falls off off-axis.
    def unit(v: list[float]) -> np.ndarray:
        return np.array(v) / np.linalg.norm(v)

    just_outer = trihedral_effective_area(unit([1, 1, 2 + 1e-7]), a)
    just_inner = trihedral_effective_area(unit([1, 1, 2 - 1e-7]), a)
    assert_allclose(just_outer, just_inner, rtol=1e-5)
    assert_allclose(just_outer, a**2 * (4 / 6) / (4 / np.sqrt(6)), rtol=1e-5)
    assert trihedral_effective_area(unit([0.5, 0.6, 0.9]), a) < a**2 / np.sqrt(3)


def test_butterworth_highpass_magnitude() -> None:
    f = np.array([0.0, 40e3, 80e3, 160e3, 1e6])
    for order in (1, 2, 4):
        h = highpass_response(f, 80e3, order)
        x = f / 80e3
        assert_allclose(np.abs(h) ** 2, x ** (2 * order) / (1 + x ** (2 * order)), atol=1e-12)
        assert_allclose(highpass_response(-f, 80e3, order), np.conj(h))
    assert_allclose(highpass_response(f, 0.0, 1), 1.0)
