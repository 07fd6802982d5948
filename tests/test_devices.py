"""The device library: every preset number against its cited source, the vendor's own
formulas for its example configurations, presets by name in a project, limits refused.

The source values are written out here with their citations (``docs/devices.md`` lists
the same sources); the tests read the presets and compare.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from numpy.testing import assert_allclose

from simcore.cli import main
from simcore.io.ti_dca1000 import parse_cfg
from simcore.scene import device_cameras as cams
from simcore.scene import device_radars as rads
from simcore.scene.devices import DEVICES, device_figures, limit_problems, radar_figures
from simcore.scene.project_io import project_to_json
from simcore.scene.radar_config import RadarConfig
from simcore.scene.radar_presets import radar_preset, tdm_mimo_2tx4rx
from simcore.scene.tof_config import TofCameraConfig, tof_preset

# TI mmWave SDK 3.x demo configuration xwr68xx/profile_2d.cfg [SDK-CFG] (the chirp,
# channel, ADC and frame commands as shipped; the processing commands after them are
# kept too, to check they parse). The mmWave Demo Visualizer prints for this chirp:
# "Range Resolution(m):0.044", "Maximum Radial Velocity(m/s):1",
# "Radial velocity resolution(m/s):0.13".
XWR68XX_PROFILE_2D = """\
sensorStop
flushCfg
dfeDataOutputMode 1
channelCfg 15 7 0
adcCfg 2 1
adcbufCfg -1 0 1 1 1
profileCfg 0 60 359 7 57.14 0 0 70 1 256 5209 0 0 158
chirpCfg 0 0 0 0 0 0 0 1
chirpCfg 1 1 0 0 0 0 0 2
chirpCfg 2 2 0 0 0 0 0 4
frameCfg 0 2 16 0 100 1 0
lowPower 0 0
guiMonitor -1 1 1 0 0 0 1
cfarCfg -1 0 2 8 4 3 0 15 1
cfarCfg -1 1 0 4 2 3 1 15 1
multiObjBeamForming -1 1 0.5
clutterRemoval -1 0
calibDcRangeSig -1 0 -5 8 256
extendedMaxVelocity -1 0
lvdsStreamCfg -1 0 0 0
compRangeBiasAndRxChanPhase 0.0 1 0 -1 0 1 0 -1 0 1 0 -1 0 1 0 -1 0 1 0 -1 0 1 0 -1 0
measureRangeBiasAndRxChanPhase 0 1.5 0.2
CQRxSatMonitor 0 3 5 121 0
CQSigImgMonitor 0 127 4
analogMonitor 0 0
aoaFovCfg -1 -90 90 -90 90
cfarFovCfg -1 0 0 8.92
cfarFovCfg -1 1 -1 1.00
calibData 0 0 0
sensorStart
"""
# TI mmWave SDK 3.x demo configuration xwr18xx/profile_2d.cfg [SDK-CFG] (chirp part).
XWR18XX_PROFILE_2D = """\
sensorStop
flushCfg
dfeDataOutputMode 1
channelCfg 15 5 0
adcCfg 2 1
adcbufCfg -1 0 1 1 1
profileCfg 0 77 429 7 57.14 0 0 70 1 256 5209 0 0 30
chirpCfg 0 0 0 0 0 0 0 1
chirpCfg 1 1 0 0 0 0 0 4
frameCfg 0 1 16 0 100 1 0
lowPower 0 0
guiMonitor -1 1 1 0 0 0 1
lvdsStreamCfg -1 0 0 0
sensorStart
"""
C_TI = 3e8      # TI's tools compute with c = 3e8 m/s


def ti_formulas(start_ghz: float, idle_us: float, ramp_end_us: float, slope_mhz_us: float,
                samples: int, ksps: float, n_tx: int, loops: int) -> dict[str, float]:
    """TI's figures (SWRA553 "Programming Chirp Parameters in TI Radar Devices"; the mmWave
    Demo Visualizer): written out here independently of the package."""
    fs, slope = ksps * 1e3, slope_mhz_us * 1e12
    lam = C_TI / (start_ghz * 1e9)
    t_c = (idle_us + ramp_end_us) * 1e-6
    return {"range_resolution_m": C_TI * fs / (2 * slope * samples),
            "max_range_m": 0.9 * fs * C_TI / (2 * slope),           # complex 1x
            "velocity_resolution_mps": lam / (2 * loops * n_tx * t_c),
            "max_velocity_mps": lam / (4 * n_tx * t_c)}


# --------------------------------------------------------------------------- TI radars


def test_iwr6843isk_against_its_sources():
    cfg = radar_preset("ti_iwr6843isk")
    lim = DEVICES["ti_iwr6843isk"].limits
    # [IWR6843-DS]: 60–64 GHz, 3 Tx, 4 Rx, 10 MHz IF bandwidth, 12.5 Msps complex,
    # 12 dBm Tx power, 12 dB noise figure.
    assert lim.band_hz == (60e9, 64e9)
    assert (lim.max_tx, lim.max_rx) == (3, 4)
    assert lim.max_if_bandwidth_hz == 10e6
    assert lim.max_sample_rate_hz == 12.5e6
    assert (cfg.tx_power_dbm, cfg.noise_figure_db) == (12.0, 12.0)
    # [SDK-UG]: numLoops 1–255, up to 1024 ADC samples, framePeriodicity 0.1 ms–1342 ms,
    # numADCBits 12/14/16.
    assert lim.max_chirps_per_frame == 255
    assert lim.max_samples_per_chirp == 1024
    assert_allclose(lim.frame_rate_hz, (1 / 1.342, 1 / 0.1e-3))
    assert lim.adc_bits == (12, 14, 16)
    # [SDK-CFG] profile_2d.cfg: the preset is that chirp.
    s = parse_cfg(XWR68XX_PROFILE_2D)
    assert s == rads.IWR6843ISK_PROFILE_2D
    assert_allclose(cfg.start_frequency_hz, 60e9 + 70e12 * 7e-6)
    assert_allclose(cfg.chirp_time_s, (57.14 - 7) * 1e-6)
    assert_allclose(cfg.bandwidth_hz, 70e12 * (57.14 - 7) * 1e-6)
    assert_allclose(cfg.chirp_repetition_time_s, (359 + 57.14) * 1e-6)
    assert (cfg.samples_per_chirp, cfg.sample_rate_hz) == (256, 5209e3)
    assert (cfg.chirps_per_frame, cfg.complex_iq, cfg.adc_bits) == (16, True, 16)
    assert cfg.if_highpass_hz == 175e3          # [SDK-UG] hpfCornerFreq1 code 0


def test_iwr6843isk_antennas_form_the_isk_virtual_array():
    # [ISK-UG]: 4 Rx λ/2 apart; Tx1 and Tx3 2λ apart; Tx2 λ right of Tx1 and λ/2 above.
    cfg = radar_preset("ti_iwr6843isk")
    d = rads.ISK_HALF_WAVELENGTH_MM * 1e-3
    rx = cfg.rx_positions_m()
    assert_allclose(np.diff(rx[:, 0]), d)
    assert_allclose(rx[:, 1], 0.0)
    tx = {a.name: a.position_mm for a in cfg.tx}
    assert [a.name for a in cfg.tx] == ["tx1", "tx2", "tx3"]     # chirp order 1, 2, 4
    assert_allclose(np.subtract(tx["tx3"], tx["tx1"]), (4 * d * 1e3, 0.0))
    assert_allclose(np.subtract(tx["tx2"], tx["tx1"]), (2 * d * 1e3, -d * 1e3))
    virt = cfg.virtual_positions_m()
    row0 = np.sort(virt[np.isclose(virt[:, 1], 0.0), 0])
    row1 = np.sort(virt[np.isclose(virt[:, 1], -d), 0])
    assert_allclose(np.diff(row0), d)                   # 8-element λ/2 ULA in azimuth
    assert len(row0) == 8
    assert_allclose(row1, row0[2:6])                    # 4 elements one row up, shifted 2


def test_awr1843boost_against_its_sources():
    cfg = radar_preset("ti_awr1843boost")
    lim = DEVICES["ti_awr1843boost"].limits
    # [AWR1843-DS]: 76–81 GHz, 3 Tx, 4 Rx, 10 MHz IF, 12.5 Msps complex, 12 dBm,
    # noise figure 14 dB (76–77 GHz).
    assert lim.band_hz == (76e9, 81e9)
    assert (lim.max_tx, lim.max_rx, lim.max_if_bandwidth_hz) == (3, 4, 10e6)
    assert lim.max_sample_rate_hz == 12.5e6
    assert (cfg.tx_power_dbm, cfg.noise_figure_db) == (12.0, 14.0)
    s = parse_cfg(XWR18XX_PROFILE_2D)
    assert s == rads.AWR1843_PROFILE_2D
    assert s.tx_masks == (1, 4)                         # channelCfg 15 5 0: Tx1, Tx3
    assert [a.name for a in cfg.tx] == ["tx1", "tx3"]
    assert_allclose(cfg.start_frequency_hz, 77e9 + 70e12 * 7e-6)
    assert_allclose(cfg.chirp_repetition_time_s, (429 + 57.14) * 1e-6)


@pytest.mark.parametrize(("name", "text", "n_tx"), [
    ("ti_iwr6843isk", XWR68XX_PROFILE_2D, 3), ("ti_awr1843boost", XWR18XX_PROFILE_2D, 2)])
def test_ti_figures_follow_the_vendor_formulas(name, text, n_tx):
    s = parse_cfg(text)
    want = ti_formulas(s.start_freq_ghz, s.idle_time_us, s.ramp_end_time_us,
                       s.freq_slope_mhz_us, s.num_adc_samples, s.sample_rate_ksps, n_tx,
                       s.loops)
    got = device_figures(DEVICES[name])
    for key, value in want.items():
        assert_allclose(got[key], value, rtol=1e-12, err_msg=key)
    # The model's own range resolution is the same formula with the exact c.
    cfg = radar_preset(name)
    assert_allclose(cfg.range_resolution_m, want["range_resolution_m"] * 299_792_458 / 3e8,
                    rtol=1e-12)


def test_iwr6843_figures_match_the_visualizer_header():
    f = device_figures(DEVICES["ti_iwr6843isk"])
    assert round(f["range_resolution_m"], 3) == 0.044
    assert round(f["max_velocity_mps"], 1) == 1.0
    assert round(f["velocity_resolution_mps"], 2) == 0.13


# ----------------------------------------------------------------- Infineon radars


def test_infineon_presets_against_their_sources():
    # [BGT60UTR11-DS]: 58–63.5 GHz, 1 Tx, 1 Rx, 12-bit ADC, real IF.
    lim = DEVICES["infineon_bgt60utr11aip"].limits
    cfg = radar_preset("infineon_bgt60utr11aip")
    assert lim.band_hz == (58e9, 63.5e9)
    assert (lim.max_tx, lim.max_rx, lim.adc_bits, lim.complex_iq) == (1, 1, (12,), (False,))
    assert (len(cfg.tx), len(cfg.rx), cfg.adc_bits, cfg.complex_iq) == (1, 1, 12, False)
    # Infineon BGT60TR13C data sheet: 58–63.5 GHz, 1 Tx, 3 Rx.
    lim13 = DEVICES["bgt60tr13c"].limits
    assert (lim13.band_hz, lim13.max_tx, lim13.max_rx) == ((58e9, 63.5e9), 1, 3)
    # The preset keeps the reference paper's 60–66 GHz chirp: reported, not refused.
    old = radar_preset("bgt60tr13c")
    assert limit_problems(old) == []
    assert any("63.5 GHz" in p for p in limit_problems(old, enforced_only=False))


@pytest.mark.parametrize("name", ["bgt60tr13c", "infineon_bgt60utr11aip"])
def test_infineon_figures_follow_the_radar_sdk_metrics(name):
    # Infineon Radar SDK, Avian metrics ↔ device configuration: range_resolution = c / (2 B),
    # max_range = range_resolution · N_samples / 2 (real IF), speed_resolution =
    # λ / (2 N_chirps T_r), max_speed = λ / (4 T_r), λ at the chirp's centre frequency; the
    # SDK's chirp time is samples / sample rate, so B is the sampled bandwidth.
    cfg = radar_preset(name)
    c = 299_792_458.0
    lam = c / (cfg.start_frequency_hz + cfg.bandwidth_hz / 2)
    res = c / (2 * cfg.bandwidth_hz)
    f = radar_figures(cfg, device=DEVICES[name])
    assert_allclose(f["range_resolution_m"], res, rtol=1e-12)
    assert_allclose(f["max_range_m"], res * cfg.samples_per_chirp / 2, rtol=1e-12)
    assert_allclose(f["velocity_resolution_mps"],
                    lam / (2 * cfg.chirps_per_frame * cfg.chirp_repetition_time_s), rtol=1e-12)
    assert_allclose(f["max_velocity_mps"], lam / (4 * cfg.chirp_repetition_time_s), rtol=1e-12)


def test_model_figures_of_a_real_if_radar():
    cfg = radar_preset("infineon_bgt60utr11aip")
    f = radar_figures(cfg, device=DEVICES["infineon_bgt60utr11aip"])
    c = 299_792_458.0
    slope = 4e9 / 64e-6
    assert_allclose(f["range_resolution_m"], c / (2 * slope * 128 / 2e6))
    # Real IF: beat frequencies up to f_s / 2 = 1 MHz, the IF bandwidth limit.
    assert_allclose(f["max_range_m"], 1e6 * c / (2 * slope))


# --------------------------------------------------------------------------- cameras


def test_kinect_v2_against_its_sources():
    cfg = tof_preset("kinect_v2")
    assert (cfg.width, cfg.height) == (512, 424)                   # [K2]
    assert (cfg.fov_h_deg, cfg.fov_v_deg) == (70.6, 60.0)          # [K2]
    assert cfg.pixel_pitch_um == 10.0                              # [JSSC15]
    assert cfg.modulation_frequencies_hz == [80e6, 16e6, 120e6]    # [LIBFREENECT2]
    assert_allclose(cfg.combined_unambiguous_range_m, 18.75, atol=0.02)  # [LIBFREENECT2]
    assert cams.KINECT_V2_LIMITS.modes[0].max_frame_rate_hz == 30.0  # [K2]


def test_azure_kinect_against_its_sources():
    cfg = tof_preset("azure_kinect_wfov")
    assert (cfg.width, cfg.height, cfg.fov_h_deg, cfg.fov_v_deg) == (1024, 1024, 120, 120)
    assert cfg.wavelength_nm == 850.0                              # [AK]
    assert cfg.pixel_pitch_um == 3.5                               # [ISSCC18]
    modes = {(m.width, m.height): m for m in cams.AZURE_KINECT_LIMITS.modes}
    # [AK]: NFOV unbinned 640×576 and binned 320×288, WFOV binned 512×512 at 30 fps with
    # 12.8 ms exposure; WFOV unbinned 1024×1024 at 15 fps with 20.3 ms.
    assert set(modes) == {(640, 576), (320, 288), (512, 512), (1024, 1024)}
    assert modes[(1024, 1024)].max_frame_rate_hz == 15.0
    assert_allclose(modes[(1024, 1024)].max_exposure_s * 12, 20.3e-3)
    assert all(modes[k].max_frame_rate_hz == 30.0 for k in [(640, 576), (512, 512)])
    assert_allclose(modes[(640, 576)].max_exposure_s * 12, 12.8e-3)


def test_flexx2_and_pico_flexx_against_their_sources():
    f2 = tof_preset("pmd_flexx2")
    # [FLEXX2]: 224 × 172, 56° × 44°, 940 nm, up to 60 fps.
    assert (f2.width, f2.height, f2.fov_h_deg, f2.fov_v_deg) == (224, 172, 56.0, 44.0)
    assert f2.wavelength_nm == 940.0
    assert max(m.max_frame_rate_hz for m in cams.FLEXX2_LIMITS.modes) == 60.0
    pico = tof_preset("pmd_pico_flexx")
    # [ROYALE]: 224 × 171, 62° × 45°, 850 nm; use cases MODE_9_5FPS_2000 … MODE_5_45FPS_500.
    assert (pico.width, pico.height, pico.fov_h_deg, pico.fov_v_deg) == (224, 171, 62, 45)
    assert pico.wavelength_nm == 850.0
    names = {m.name: (m.max_frame_rate_hz, m.max_exposure_s)
             for m in cams.PICO_FLEXX_LIMITS.modes}
    assert names["MODE_9_5FPS_2000"] == (5.0, 2000e-6)
    assert names["MODE_5_45FPS_500"] == (45.0, 500e-6)


def test_every_device_cites_sources_and_is_listed(capsys):
    assert {d.kind for d in DEVICES.values()} == {"radar", "tof"}
    assert sum(d.kind == "radar" for d in DEVICES.values()) >= 4
    assert sum(d.kind == "tof" for d in DEVICES.values()) >= 4
    for d in DEVICES.values():
        assert d.sources, d.name
        cfg = d.factory()
        assert cfg.preset == d.name
    assert main(["devices"]) == 0
    out = capsys.readouterr().out
    for d in DEVICES.values():
        assert d.name in out
    # Figures shown: the IWR6843ISK's 4.36 cm and the Kinect v2's 18.74 m.
    assert "4.36 cm" in out and "18.74 m" in out


# ----------------------------------------------------------------- presets by name


def test_a_project_names_a_device_and_gets_its_fields():
    radar = RadarConfig.model_validate({"preset": "ti_iwr6843isk", "chirps_per_frame": 32})
    assert radar == radar_preset("ti_iwr6843isk", chirps_per_frame=32)
    cam = TofCameraConfig.model_validate({"preset": "kinect_v2", "exposure_time_s": 1e-4})
    assert cam.modulation_frequencies_hz == [80e6, 16e6, 120e6]
    assert cam.exposure_time_s == 1e-4


def test_older_preset_names_keep_the_class_defaults():
    # Old project files name "bgt60tr13c", "tdm_mimo_2tx4rx" or "pmd_pico_flexx" and rely
    # on the class defaults for the fields they leave out: nothing changes for them.
    assert RadarConfig.model_validate({"preset": "bgt60tr13c"}) == RadarConfig()
    tdm = RadarConfig.model_validate({"preset": "tdm_mimo_2tx4rx"})
    assert tdm.model_dump(exclude={"preset"}) == RadarConfig().model_dump(exclude={"preset"})
    assert tdm != tdm_mimo_2tx4rx()
    assert TofCameraConfig.model_validate({"preset": "pmd_pico_flexx"}) == TofCameraConfig()


def _project_file(tmp_path, *, radar=None, tof=None, rate=10.0):
    from scenes import wall_project

    project = wall_project()
    project.timeline.frame_rate_hz = rate
    data = json.loads(project_to_json(project))
    if radar is not None:
        data["rig"]["radar"] = radar
    if tof is not None:
        data["rig"]["tof"] = tof
    path = tmp_path / "p.json"
    path.write_text(json.dumps(data))
    return str(path)


@pytest.mark.parametrize(("radar", "tof", "rate", "needle"), [
    ({"preset": "ti_iwr6843isk", "samples_per_chirp": 2048, "chirp_time_s": 500e-6,
      "chirp_repetition_time_s": 600e-6}, None, 1.0,
     "samples_per_chirp: 2048 exceeds the TI IWR6843ISK's 1024 samples per chirp"),
    ({"preset": "ti_iwr6843isk", "sample_rate_hz": 20e6, "samples_per_chirp": 512}, None,
     10.0, "exceeds the TI IWR6843ISK's maximum sample rate 1.25e+07 Hz"),
    ({"preset": "ti_awr1843boost", "start_frequency_hz": 60e9}, None, 10.0,
     "leaves the TI AWR1843BOOST's band 76–81 GHz"),
    ({"preset": "ti_iwr6843isk"}, None, 100.0,
     "longer than a frame at 100 Hz"),
    (None, {"preset": "kinect_v2", "exposure_time_s": 5e-3, "exposure_range_s": [1e-6, 5e-3]},
     10.0, "outside the Microsoft Kinect v2's exposure range"),
    (None, {"preset": "kinect_v2", "width": 640, "height": 480}, 10.0,
     "is none of the Microsoft Kinect v2's modes"),
    (None, {"preset": "azure_kinect_wfov"}, 30.0,
     "exceeds the Microsoft Azure Kinect (WFOV, 1 MP)'s 15 frames/s"),
])
def test_validate_refuses_a_configuration_beyond_the_device(tmp_path, capsys, radar, tof,
                                                             rate, needle):
    path = _project_file(tmp_path, radar=radar, tof=tof, rate=rate)
    assert main(["validate", path]) == 2
    err = capsys.readouterr().err
    assert needle in err
    assert err.startswith("tofradar: error:") and "Traceback" not in err


def test_validate_accepts_the_presets_and_notes_older_limits(tmp_path, capsys):
    path = _project_file(tmp_path, radar={"preset": "ti_iwr6843isk"},
                         tof={"preset": "pmd_flexx2"})
    assert main(["validate", path]) == 0
    path = _project_file(tmp_path)        # bgt60tr13c: 60–66 GHz, beyond the data sheet
    assert main(["validate", path]) == 0
    out = capsys.readouterr().out
    assert "note: radar: outside the Infineon BGT60TR13C's limits" in out
    assert math.isfinite(device_figures(DEVICES["pmd_flexx2"])["unambiguous_range_m"])


def test_named_sensors_take_device_presets_too():
    from scenes import wall_project

    from simcore.scene.project_io import project_from_dict

    data = json.loads(project_to_json(wall_project()))
    data["rig"]["sensors"] = {"front": {"kind": "radar", "preset": "ti_awr1843boost"},
                              "depth": {"kind": "tof", "preset": "kinect_v2"}}
    configs = project_from_dict(data).sensor_configs()
    assert configs["front"].start_frequency_hz == radar_preset("ti_awr1843boost").start_frequency_hz
    assert [a.name for a in configs["front"].tx] == ["tx1", "tx3"]
    assert configs["depth"].modulation_frequencies_hz == [80e6, 16e6, 120e6]
