"""Real-recording input (issue #35): the Radar Fusion GUI / ifxdaq format, written here with
known tones and noise, read back, converted; malformed recordings give one clear error."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from numpy.testing import assert_allclose, assert_array_equal

from simcore.cli import main
from simcore.io import open_dataset
from simcore.io.recordings import (
    RecordingError,
    codes_to_fs,
    read_recording,
    recording_levels,
)
from simcore.scene import load_project
from simcore.scene.radar_config import SPEED_OF_LIGHT
from simcore.scene.radar_presets import (
    RF_CONVERSION_GAIN_DB,
    TX_POWER_MAX_DBM,
    baseband_gain_db,
)

SETTINGS: dict[str, Any] = {
    "aaf_cutoff_Hz": 500000, "chirp_repetition_time_s": 0.0005911249900236726,
    "end_frequency_Hz": 63500000000, "frame_repetition_time_s": 0.07726884633302689,
    "hp_cutoff_Hz": 80000, "if_gain_dB": 23, "mimo_mode": "off", "num_chirps_per_frame": 4,
    "num_samples_per_chirp": 64, "rx_antennas": [1, 2, 3], "sample_rate_Hz": 2000000,
    "start_frequency_Hz": 58000000000, "tx_antennas": [1], "tx_power_level": 31,
}


def write_recording(root: Path, codes: np.ndarray, settings: dict[str, Any] | None = None,
                    *, bits: int = 12) -> Path:
    """A recording folder as the Radar Fusion GUI writes it."""
    stream = root / "rec" / "RadarIfxAvian_00"
    stream.mkdir(parents=True)
    np.save(stream / "radar.npy", codes)
    (stream / "config.json").write_text(json.dumps(
        {"device_config": {"fmcw_single_shape": settings or SETTINGS}}, indent=4))
    (stream / "meta.json").write_text(json.dumps({"adc_resolution": bits,
                                                  "description": "test"}))
    (root / "rec" / "meta.json").write_text(json.dumps({"date_captured": "2026-01-06"}))
    return root / "rec"


def bin_range_m(settings: dict[str, Any]) -> float:
    slope = (settings["end_frequency_Hz"] - settings["start_frequency_Hz"]) / (
        settings["num_samples_per_chirp"] / settings["sample_rate_Hz"])
    return settings["sample_rate_Hz"] / settings["num_samples_per_chirp"] * SPEED_OF_LIGHT / (
        2 * slope)


def tone_codes(settings: dict[str, Any], *, frames: int, tones: list[tuple[int, float]],
               noise_lsb: float, seed: int = 0) -> np.ndarray:
    """Codes of tones (range bin, amplitude FS) on bin centres, plus Gaussian noise."""
    rng = np.random.default_rng(seed)
    n = settings["num_samples_per_chirp"]
    shape = (frames, len(settings["rx_antennas"]), settings["num_chirps_per_frame"], n)
    x = np.zeros(shape)
    t = np.arange(n)
    for k, amp in tones:
        phase = rng.uniform(0, 2 * np.pi, shape[:-1])[..., None]
        x += amp * np.cos(2 * np.pi * k * t / n + phase)
    codes = np.rint(2048 + 2048 * x + noise_lsb * rng.standard_normal(shape))
    return np.clip(codes, 0, 4095).astype(np.uint16)


def test_codes_become_fractions_of_full_scale_exactly(tmp_path):
    codes = tone_codes(SETTINGS, frames=3, tones=[(12, 0.1)], noise_lsb=2.0)
    rec = read_recording(write_recording(tmp_path, codes))
    assert rec.n_frames == 3 and rec.adc_bits == 12
    expected = (codes.astype(np.float64) - 2048) / 2048
    assert_array_equal(rec.frame_adc(1), expected[1].transpose(1, 0, 2).astype(np.float32))
    assert_array_equal(rec.adc(), expected.transpose(0, 2, 1, 3).astype(np.float32))
    assert_allclose(rec.frame_times_s(), np.arange(3) * SETTINGS["frame_repetition_time_s"])
    assert codes_to_fs(np.array([0, 4095], dtype=np.uint16), 12).tolist() == [-1.0, 4095 / 2048 - 1]


#: Recordings other than the shared one's configuration: other sample, chirp and antenna
#: counts, sample rates, bandwidths, gains, filters and the TDM mode with its one Tx.
OTHER_SETTINGS: dict[str, dict[str, Any]] = {
    "shared": SETTINGS,
    "128 samples, 1 Rx, 16 chirps": dict(
        SETTINGS, num_samples_per_chirp=128, sample_rate_Hz=1000000, rx_antennas=[2],
        num_chirps_per_frame=16, if_gain_dB=40, hp_cutoff_Hz=160000, aaf_cutoff_Hz=600000,
        start_frequency_Hz=60000000000, end_frequency_Hz=62000000000, tx_power_level=20),
    "32 samples, 2 Rx, TDM": dict(
        SETTINGS, num_samples_per_chirp=32, sample_rate_Hz=1500000, rx_antennas=[1, 3],
        num_chirps_per_frame=2, mimo_mode="tdm", if_gain_dB=18, tx_power_level=0),
}


@pytest.mark.parametrize("name", sorted(OTHER_SETTINGS))
def test_tones_and_noise_read_back_at_their_ranges_and_levels(tmp_path, name):
    """Hann on a bin-centred tone of amplitude A reads 20 log10 A; white noise of σ reads
    σ per sample and σ² · 4 Σw² / (Σw)² per bin."""
    settings = OTHER_SETTINGS[name]
    n = settings["num_samples_per_chirp"]
    noise_lsb = 8.0
    tones = [(12, 0.02), (n // 2 - 10, 0.003)]
    codes = tone_codes(settings, frames=40, tones=tones, noise_lsb=noise_lsb, seed=1)
    rec = read_recording(write_recording(tmp_path, codes, settings))
    bin_m = bin_range_m(settings)
    levels = recording_levels(rec.adc(), rec.config, target_range_m=12 * bin_m,
                              beyond_aaf_m=(0.0, 64 * bin_m), in_band_m=(0.0, 64 * bin_m))
    assert_allclose(levels.range_m[1], bin_m, rtol=1e-12)
    w = np.hanning(n)
    sigma = noise_lsb / 2048
    for k, amp in tones:
        tone_db = 10 * np.log10(amp**2 + 4 * sigma**2 * np.sum(w**2) / np.sum(w) ** 2)
        assert abs(levels.profile_dbfs[k] - tone_db) < 0.3, (k, levels.profile_dbfs[k])
    assert abs(levels.target_dbfs - 20 * np.log10(0.02)) < 0.2
    # Per-sample noise (chirp-to-chirp differences, chirp means removed) on noise alone.
    quiet = tone_codes(settings, frames=40, tones=[], noise_lsb=noise_lsb, seed=2)
    rec_q = read_recording(write_recording(tmp_path / "q", quiet, settings))
    r_max = n // 2 * bin_m            # the two floors away from bin 0 and the Nyquist bin
    lv = recording_levels(rec_q.adc(), rec_q.config, beyond_aaf_m=(0.6 * r_max, 0.9 * r_max),
                          in_band_m=(0.2 * r_max, 0.5 * r_max))
    var = sigma**2 * (1 - 1 / n) + (1 / 2048) ** 2 / 12
    assert abs(lv.per_sample_noise_dbfs - 10 * np.log10(var)) < 0.15
    floor = 10 * np.log10(4 * var * np.sum(w**2) / np.sum(w) ** 2)
    assert abs(lv.floor_beyond_aaf_mean_dbfs - floor) < 0.5
    assert abs(lv.floor_in_band_dbfs - floor) < 0.7


def test_configuration_round_trips_into_the_project_and_dataset(tmp_path):
    settings = dict(SETTINGS, rx_antennas=[1, 3], num_chirps_per_frame=2, tx_power_level=15,
                    if_gain_dB=33, hp_cutoff_Hz=160000, aaf_cutoff_Hz=600000,
                    num_samples_per_chirp=128, sample_rate_Hz=1000000)
    codes = tone_codes(settings, frames=5, tones=[(30, 0.05)], noise_lsb=3.0)
    src = write_recording(tmp_path, codes, settings)
    out, proj = tmp_path / "real.h5", tmp_path / "real.json"
    assert main(["convert", str(src), "--to", str(out), "--project", str(proj)]) == 0
    converted = load_project(proj)
    # A radar recording gives a radar-only project: no ToF camera nobody asked for.
    assert converted.rig.tof is None and list(converted.sensor_configs()) == ["radar"]
    radar = converted.rig.radar
    assert radar.device_settings == settings
    assert radar.start_frequency_hz == 58e9 and radar.bandwidth_hz == 5.5e9
    assert radar.chirp_time_s == 128 / 1e6 and radar.sample_rate_hz == 1e6
    assert radar.samples_per_chirp == 128 and radar.chirps_per_frame == 2
    assert radar.chirp_repetition_time_s == settings["chirp_repetition_time_s"]
    assert [a.name for a in radar.rx] == ["rx1", "rx3"] and len(radar.tx) == 1
    assert radar.if_highpass_hz == 160e3 and radar.if_lowpass_hz == 600e3
    assert radar.if_gain_db == RF_CONVERSION_GAIN_DB + 35       # 30 dB HP + 5 dB VGA
    assert_allclose(radar.tx_power_dbm, TX_POWER_MAX_DBM + 20 * np.log10(16 / 32))
    ds = open_dataset(out)
    try:
        assert json.loads(ds.attrs["recording_config"]) == {
            "device_config": {"fmcw_single_shape": settings}}
        assert ds.attrs["source"] == "recording"
        assert_allclose(ds.time.values, np.arange(5) * settings["frame_repetition_time_s"])
        adc = ds.radar_adc.values
        assert adc.shape == (5, 2, 2, 128)
        assert_array_equal(adc, ((codes.astype(np.float64) - 2048) / 2048
                                 ).transpose(0, 2, 1, 3).astype(np.float32))
        profile = ds.radar_range_profile_integrated.isel(frame=0).values
        r_peak = float(ds.range.values[int(np.argmax(profile))])
        assert abs(r_peak - 30 * bin_range_m(settings)) <= 0.5 * bin_range_m(settings)
    finally:
        ds.close()


def test_baseband_gain_follows_the_sdk_rule():
    assert [baseband_gain_db(g) for g in (18, 23, 29, 30, 33, 47, 60)] == [
        18, 23, 28, 30, 35, 45, 60]


def test_tdm_mode_with_one_tx_reads_like_mimo_off(tmp_path):
    settings = dict(SETTINGS, mimo_mode="tdm")
    rec = read_recording(write_recording(
        tmp_path, tone_codes(settings, frames=2, tones=[], noise_lsb=1.0), settings))
    assert rec.config.n_channels == 3


def _mutate(tmp_path: Path, name: str) -> Path:
    codes = tone_codes(SETTINGS, frames=2, tones=[(10, 0.01)], noise_lsb=1.0)
    src = write_recording(tmp_path, codes)
    stream = src / "RadarIfxAvian_00"
    cfg_path = stream / "config.json"
    doc = json.loads(cfg_path.read_text())
    shape = doc["device_config"]["fmcw_single_shape"]
    if name == "missing config":
        cfg_path.unlink()
    elif name == "malformed config":
        cfg_path.write_text('{"device_config": {')
    elif name == "unknown key":
        shape["chirp_shape"] = "saw"
    elif name == "missing key":
        del shape["sample_rate_Hz"]
    elif name == "wrong type":
        shape["num_samples_per_chirp"] = "64"
    elif name == "shape":
        np.save(stream / "radar.npy", codes[:, :2])
    elif name == "dtype":
        np.save(stream / "radar.npy", codes.astype(np.float32))
    elif name == "truncated":
        data = (stream / "radar.npy").read_bytes()
        (stream / "radar.npy").write_bytes(data[: len(data) // 2])
    elif name == "out of range":
        bad = codes.copy()
        bad[0, 0, 0, 0] = 4096
        np.save(stream / "radar.npy", bad)
    elif name == "two tx without mimo":
        shape["tx_antennas"] = [1, 2]
    elif name == "down-chirp":
        shape["start_frequency_Hz"], shape["end_frequency_Hz"] = 63.5e9, 58e9
    elif name == "if gain":
        shape["if_gain_dB"] = 70
    elif name == "rx 4":
        shape["rx_antennas"] = [1, 4]
        np.save(stream / "radar.npy", codes[:, :2])
    elif name == "tdm two tx":
        shape["mimo_mode"], shape["tx_antennas"] = "tdm", [1, 2]
        np.save(stream / "radar.npy", np.concatenate([codes, codes], axis=1))
    elif name == "frame time":
        shape["frame_repetition_time_s"] = 0
    elif name == "sample rate":
        shape["sample_rate_Hz"] = 1e12
    elif name == "no stream":
        for f in stream.iterdir():
            f.unlink()
        stream.rmdir()
    if name not in ("missing config", "malformed config", "no stream"):
        cfg_path.write_text(json.dumps(doc))
    return src


BAD = {"missing config": "config.json: missing", "malformed config": "not valid JSON",
       "unknown key": "unknown fmcw_single_shape keys ['chirp_shape']",
       "missing key": "lacks ['sample_rate_Hz']", "wrong type": "num_samples_per_chirp",
       "shape": "shape (2, 2, 4, 64)", "dtype": "dtype float32",
       "truncated": "truncated", "out of range": "code 4096 outside the 12-bit",
       "two tx without mimo": "mimo_mode 'off'", "down-chirp": "down-chirps",
       "if gain": "if_gain_dB = 70", "no stream": "not a Radar Fusion GUI recording",
       "frame time": "frame_repetition_time_s = 0 must be positive",
       "sample rate": "sample_rate_hz", "rx 4": "has Tx 1 and Rx 1–3",
       "tdm two tx": "has Tx 1 and Rx 1–3"}


@pytest.mark.parametrize("name", sorted(BAD))
def test_bad_recording_gives_one_clear_error(name, tmp_path, capsys):
    src = _mutate(tmp_path, name)
    with pytest.raises(RecordingError, match=None):
        read_recording(src)
    rc = main(["convert", str(src), "--to", str(tmp_path / "x.h5")])
    err = capsys.readouterr().err.strip()
    assert rc != 0
    assert len(err.splitlines()) == 1 and err.startswith("tofradar: error:"), err
    assert BAD[name] in err, err
    assert not (tmp_path / "x.h5").exists()


# ------------------------------------------------------------- the front-end additions
def test_leakage_paths_are_tones_at_their_lengths_with_the_coupling_formula():
    """Direct path of length ℓ and an echo: tones of delay ℓ/c, amplitude √(2 R P_t 10^(L/10))
    · 10^(G/20) / V_fs, through the IF filters."""
    from simcore.scene.radar_config import LeakageEcho
    from simcore.scene.radar_presets import bgt60tr13c
    from simcore.sensors.radar.equation import if_filter_response
    from simcore.sensors.radar.receiver import leakage_if

    cfg = bgt60tr13c(leakage_dbc=-50.0, leakage_path_mm=40.0, if_gain_db=50.0,
                     leakage_echoes=[LeakageEcho(path_mm=300.0, level_dbc=-90.0)])
    t = cfg.sample_times_s()
    k, f_c = cfg.slope_hz_per_s, cfg.start_frequency_hz
    expected = np.zeros(len(t), dtype=complex)
    for ell_mm, dbc in ((40.0, -50.0), (300.0, -90.0)):
        p = 1e-3 * 10 ** ((cfg.tx_power_dbm + dbc) / 10)
        amp = np.sqrt(2 * 50.0 * p) * 10 ** (50.0 / 20) / cfg.adc_full_scale_v
        tau = ell_mm * 1e-3 / SPEED_OF_LIGHT
        expected += amp * if_filter_response(k * tau, cfg) * np.exp(
            1j * (2 * np.pi * f_c * tau + 2 * np.pi * k * tau * t - np.pi * k * tau**2))
    out = leakage_if(cfg)
    assert out.shape == (1, 3, len(t))
    for ch in range(3):                       # one length for every pair
        assert_allclose(out[0, ch], expected, rtol=1e-9, atol=1e-15)
    off = cfg.model_copy(update={"leakage_dbc": None})
    assert not np.any(leakage_if(off))        # no leakage switches the echoes off too


def test_noise_after_the_filters_is_white_beyond_the_anti_aliasing_filter():
    """Thermal noise through a 4th-order 300 kHz low-pass plus white σ_a: far above the
    cutoff the PSD is σ_a² alone; below it, thermal + σ_a²."""
    from simcore.scene.radar_presets import bgt60tr13c
    from simcore.sensors.radar.equation import noise_std_fs
    from simcore.sensors.radar.receiver import receiver_noise

    cfg = bgt60tr13c(if_highpass_hz=0.0, if_lowpass_hz=300e3, if_lowpass_order=4,
                     adc_noise_fs=2e-3, if_gain_db=60.0)
    x = receiver_noise(cfg, (400, 3, 512), np.random.default_rng(4))
    psd = np.mean(np.abs(np.fft.rfft(x, axis=-1)) ** 2, axis=(0, 1)) / 512   # σ² per bin
    f = np.fft.rfftfreq(512, 1 / cfg.sample_rate_hz)
    sigma_t = noise_std_fs(cfg)
    assert_allclose(psd[(f > 900e3) & (f < 990e3)].mean(), 2e-3**2, rtol=0.05)
    low = (f > 20e3) & (f < 100e3)
    assert_allclose(psd[low].mean(), sigma_t**2 + 2e-3**2, rtol=0.05)
    quiet = cfg.model_copy(update={"noise_variance_adc": 0.0})
    assert not np.any(receiver_noise(quiet, (2, 3, 512), np.random.default_rng(4)))


def test_convert_refuses_to_overwrite_and_misplaced_options(tmp_path, capsys):
    src = write_recording(tmp_path, tone_codes(SETTINGS, frames=2, tones=[], noise_lsb=1.0))
    out = tmp_path / "a.h5"
    assert main(["convert", str(src), "--to", str(out)]) == 0
    capsys.readouterr()
    for argv, message in (
            (["convert", str(src), "--to", str(out)], "already exists"),
            (["convert", str(src), "--to", str(tmp_path / "a.mcap")], "HDF5 dataset (.h5)"),
            (["convert", str(out), "--to", str(tmp_path / "b.mcap"), "--project",
              str(tmp_path / "p.json")], "--project is for a recording folder")):
        assert main(argv) != 0
        err = capsys.readouterr().err.strip()
        assert len(err.splitlines()) == 1 and err.startswith("tofradar: error:"), err
        assert message in err, err
    assert main(["convert", str(src), "--to", str(out), "--overwrite"]) == 0


def test_the_report_section_says_when_the_recording_is_absent(tmp_path, monkeypatch):
    from simcore.report.real import RECORDING_ENV, real_section, shared_recording

    monkeypatch.setenv(RECORDING_ENV, str(tmp_path / "nowhere"))
    assert shared_recording() is None
    file, _title, text, numbers = real_section(tmp_path, quick=True)
    assert file == "" and numbers == {"recording": None} and "is not present" in text
    monkeypatch.setenv(RECORDING_ENV, str(write_recording(
        tmp_path, tone_codes(SETTINGS, frames=4, tones=[(12, 0.01)], noise_lsb=2.0))))
    assert shared_recording() == tmp_path / "rec"


def test_ellipsoid_mesh_encloses_the_ellipsoid_volume():
    from simcore.report.real import ellipsoid_obj

    text = ellipsoid_obj((0.1, 0.2, 0.3), n_lat=96, n_lon=192)
    v = np.array([[float(t) for t in ln.split()[1:]] for ln in text.splitlines()
                  if ln.startswith("v ")])
    f = np.array([[int(t) - 1 for t in ln.split()[1:]] for ln in text.splitlines()
                  if ln.startswith("f ")])
    a, b, c = v[f[:, 0]], v[f[:, 1]], v[f[:, 2]]
    volume = np.einsum("ij,ij->i", a, np.cross(b, c)).sum() / 6     # divergence theorem
    assert_allclose(volume, 4 / 3 * np.pi * 0.1 * 0.2 * 0.3, rtol=2e-3)   # outward faces
    assert_allclose(np.sum((v / [0.1, 0.2, 0.3]) ** 2, axis=1), 1.0, atol=1e-4)  # on it


@pytest.mark.parametrize("name", ["shared", "128 samples, 1 Rx, 16 chirps"])
def test_a_breathing_tone_gives_its_rate_and_amplitude_through_convert_and_products(
        tmp_path, name, capsys):
    """A chest at bin 12 moving d(t) = A sin(2π f t) behind a static phasor of the same bin
    and a leakage tone: ``tofradar convert`` then ``tofradar products`` (the vital-sign
    estimator a simulated run gets) find that bin, f and A."""
    settings = OTHER_SETTINGS[name]
    n, frames = settings["num_samples_per_chirp"], 240
    rate_hz, amp_m = 0.3, 3e-3
    lam = SPEED_OF_LIGHT / (0.5 * (settings["start_frequency_Hz"] + settings["end_frequency_Hz"]))
    t = np.arange(frames) * settings["frame_repetition_time_s"]
    theta = 4 * np.pi * amp_m * np.sin(2 * np.pi * rate_hz * t) / lam          # (frames,)
    shape = (frames, len(settings["rx_antennas"]), settings["num_chirps_per_frame"], n)
    s = np.arange(n)
    x = (0.05 * np.cos(2 * np.pi * 12 * s / n + theta[:, None, None, None])   # the chest
         + 0.03 * np.cos(2 * np.pi * 12 * s / n + 1.0)                          # static, same bin
         + 0.2 * np.cos(2 * np.pi * s / n))                                     # leakage
    rng = np.random.default_rng(5)
    codes = np.clip(np.rint(2048 + 2048 * x + 2.0 * rng.standard_normal(shape)), 0, 4095
                    ).astype(np.uint16)
    src = write_recording(tmp_path, codes, settings)
    out = tmp_path / "breathing.h5"
    assert main(["convert", str(src), "--to", str(out)]) == 0
    assert main(["products", str(out)]) == 0
    said = capsys.readouterr().out
    ds = open_dataset(out)                     # opened like a simulated run's products
    try:
        d = ds.radar_vitals_displacement.values
    finally:
        ds.close()
    import h5py

    with h5py.File(out, "r") as f:
        g = dict(f["radar/vitals"].attrs)
    assert int(g["range_bin"]) == 12
    assert_allclose(g["range_m"], 12 * bin_range_m(settings), rtol=1e-9)
    assert abs(g["breathing_rate_hz"] - rate_hz) < 0.002
    assert_allclose(g["breathing_amplitude_m"], amp_m, rtol=0.02)
    # The displacement is d(t), mean removed (a phase that grows = moving away).
    expected = amp_m * np.sin(2 * np.pi * rate_hz * t)
    assert np.max(np.abs(d - (expected - expected.mean()))) < 0.02 * amp_m
    assert "breathing 0.30" in said
