"""TI DCA1000 captures (.bin + mmWave SDK .cfg): round trips, an independent reader, errors.

The independent reader below is the published layout written out here (the ``openradar``
package on PyPI, 1.0.1, imports scikit-learn and old APIs at package import, so it is not
installed): OpenRadar's ``mmwave.dataloader.DCA1000.organize`` for 2 LVDS lanes (groups of
four words ``I0 I1 Q0 Q1``, reshaped to (chirps, rx, samples)) and TI's ``readDCA1000.m``
for 4 lanes (groups of eight words, four lanes' I then their Q).
"""

from __future__ import annotations

import json

import h5py
import numpy as np
import pytest
from numpy.testing import assert_array_equal

from simcore.cli import main
from simcore.io.ti_dca1000 import (
    CaptureError,
    parse_cfg,
    read_capture,
    write_capture,
    write_cfg,
)
from simcore.scene.device_radars import AWR1843_PROFILE_2D, IWR6843ISK_PROFILE_2D
from simcore.scene.project_io import save_project
from simcore.scene.radar_config import RadarConfig
from simcore.scene.tof_config import TofCameraConfig


def openradar_organize(words: np.ndarray, chirps: int, rx: int, samples: int) -> np.ndarray:
    """OpenRadar's 2-lane layout: ``ret[0::2] = w[0::4] + 1j w[2::4]``, ``ret[1::2] = …``."""
    ret = np.zeros(len(words) // 2, dtype=complex)
    ret[0::2] = words[0::4] + 1j * words[2::4]
    ret[1::2] = words[1::4] + 1j * words[3::4]
    return ret.reshape((chirps, rx, samples))


def read_dca1000_4lane(words: np.ndarray, chirps: int, samples: int) -> np.ndarray:
    """TI readDCA1000.m, 4 lanes complex: reshape to 8 rows, rows 1–4 + j rows 5–8."""
    cols = words.reshape(-1, 8).T                      # (8, chirps·samples)
    lanes = cols[0:4] + 1j * cols[4:8]                  # (rx, chirps·samples)
    return lanes.reshape(4, chirps, samples).transpose(1, 0, 2)


def random_cube(settings, frames: int, *, seed: int = 0) -> np.ndarray:
    """A complex cube in FS on the 16-bit grid, (frames, loops, tx*rx, samples)."""
    rng = np.random.default_rng(seed)
    shape = (frames, settings.loops, settings.n_tx * settings.n_rx, settings.num_adc_samples)
    codes = rng.integers(-2**15, 2**15, size=(*shape, 2))
    return ((codes[..., 0] + 1j * codes[..., 1]) / 2**15).astype(np.complex64)


# -------------------------------------------------------------------- layout


def test_two_lane_capture_reads_the_same_in_openradar_layout(tmp_path):
    s = IWR6843ISK_PROFILE_2D
    adc = random_cube(s, 2)
    write_capture(tmp_path / "a.bin", adc, s, lanes=2)
    words = np.fromfile(tmp_path / "a.bin", dtype="<i2").astype(np.int64)
    per_frame = words.size // 2
    chirps = s.loops * s.n_tx
    for k in range(2):
        frame = openradar_organize(words[k * per_frame:(k + 1) * per_frame], chirps, s.n_rx,
                                   s.num_adc_samples)
        # TI chirp loop·n_tx + t with Rx r = the simulator's chirp loop, channel t·n_rx + r.
        want = adc[k].reshape(s.loops, s.n_tx, s.n_rx, -1).reshape(chirps, s.n_rx, -1)
        assert_array_equal(frame, want.astype(np.complex128) * 2**15)
    back = read_capture(tmp_path / "a.bin")
    assert_array_equal(back.adc(), adc)
    assert parse_cfg((tmp_path / "a.cfg").read_text()) == s


def test_four_lane_capture_reads_the_same_in_ti_layout(tmp_path):
    s = AWR1843_PROFILE_2D
    adc = random_cube(s, 1, seed=4)
    write_capture(tmp_path / "b.bin", adc, s, lanes=4)
    words = np.fromfile(tmp_path / "b.bin", dtype="<i2").astype(np.int64)
    chirps = s.loops * s.n_tx
    frame = read_dca1000_4lane(words, chirps, s.num_adc_samples)
    want = adc[0].reshape(chirps, s.n_rx, -1)
    assert_array_equal(frame, want.astype(np.complex128) * 2**15)
    assert_array_equal(read_capture(tmp_path / "b.bin", lanes=4).adc(), adc)


def test_real_capture_round_trips(tmp_path):
    from dataclasses import replace

    s = replace(IWR6843ISK_PROFILE_2D, complex_iq=False, adc_bits=12, loops=4)
    rng = np.random.default_rng(2)
    codes = rng.integers(-2**11, 2**11, size=(3, s.loops, s.n_tx * s.n_rx, s.num_adc_samples))
    adc = (codes / 2**11).astype(np.float32)
    write_capture(tmp_path / "r.bin", adc, s)
    assert "adcCfg 0 0" in (tmp_path / "r.cfg").read_text()
    words = np.fromfile(tmp_path / "r.bin", dtype="<i2")
    assert_array_equal(words, codes.reshape(-1))       # real 2-lane: codes in order
    assert_array_equal(read_capture(tmp_path / "r.bin").adc(), adc)


# -------------------------------------------------------- simulated run ↔ capture


def ti_project(tmp_path):
    from scenes import wall_project

    project = wall_project(3.0, "aluminium")
    project.rig.radar = RadarConfig.model_validate(
        {"preset": "ti_iwr6843isk", "chirps_per_frame": 4, "render_width": 48,
         "render_height": 48})
    project.rig.tof = TofCameraConfig(width=16, height=12, supersampling=1)
    path = tmp_path / "ti.json"
    save_project(project, path)
    return path


def test_simulated_run_as_capture_and_back(tmp_path, capsys):
    project = ti_project(tmp_path)
    sim, capture = tmp_path / "sim.h5", tmp_path / "sim.bin"
    assert main(["run", str(project), "--out", str(sim), "--frames", "2", "--quiet"]) == 0
    assert main(["convert", str(sim), "--to", str(capture)]) == 0
    assert "wrote 2 frames" in capsys.readouterr().out
    with h5py.File(sim) as f:
        adc = f["radar/adc"][:]
    assert adc.dtype == np.complex64 and adc.shape == (2, 4, 12, 256)
    assert np.abs(adc).max() > 1e-3                 # the wall's echo, not zeros
    # The independent reader gives the simulated cube's codes, bit for bit.
    words = np.fromfile(capture, dtype="<i2").astype(np.int64)
    frame0 = openradar_organize(words[: words.size // 2], 12, 4, 256)
    assert_array_equal(frame0, adc[0].reshape(12, 4, 256).astype(np.complex128) * 2**15)
    cfg_text = capture.with_suffix(".cfg").read_text()
    assert "profileCfg 0 60 359 7 57.14 0 0 70 1 256 5209 0 0 158" in cfg_text
    assert "frameCfg 0 2 4 2 100 1 0" in cfg_text
    # Back with convert: the simulated dataset's ADC cube, and a project reproducing it.
    back, proj = tmp_path / "back.h5", tmp_path / "back.json"
    assert main(["convert", str(capture), "--to", str(back), "--project", str(proj)]) == 0
    with h5py.File(back) as f:
        assert_array_equal(f["radar/adc"][:], adc)
        assert f["meta"].attrs["source"] == "ti_dca1000"
        assert f["radar/range_doppler"].shape[0] == 2
    radar = json.loads(proj.read_text())["rig"]["radar"]
    with h5py.File(sim) as f:
        original = json.loads(f["meta"].attrs["project_json"])["rig"]["radar"]
    for key in ("start_frequency_hz", "bandwidth_hz", "chirp_time_s", "sample_rate_hz",
                "samples_per_chirp", "chirps_per_frame", "chirp_repetition_time_s",
                "complex_iq", "adc_bits"):
        assert radar[key] == pytest.approx(original[key], rel=1e-12), key
    assert radar["tx"] == original["tx"] and radar["rx"] == original["rx"]


def test_run_writes_a_capture_directly(tmp_path, capsys):
    project = ti_project(tmp_path)
    out = tmp_path / "direct.bin"
    assert main(["run", str(project), "--out", str(out), "--frames", "1", "--quiet"]) == 0
    s = read_capture(out).settings
    assert (s.loops, s.n_tx, s.n_rx, s.num_frames) == (4, 3, 4, 1)
    assert out.stat().st_size == 4 * 3 * 4 * 256 * 2 * 2
    assert main(["run", str(project), "--out", str(out), "--frames", "1", "--quiet"]) == 2
    assert "already exists" in capsys.readouterr().err


# -------------------------------------------------------------------- bad input


def _capture(tmp_path, *, cfg=None, frames=1, extra_bytes=0):
    s = IWR6843ISK_PROFILE_2D
    write_capture(tmp_path / "c.bin", random_cube(s, frames), s)
    if cfg is not None:
        (tmp_path / "c.cfg").write_text(cfg)
    if extra_bytes:
        with open(tmp_path / "c.bin", "ab") as f:
            f.write(b"\0" * extra_bytes)
    return tmp_path / "c.bin"


def _cfg(old: str, new: str) -> str:
    """The preset's .cfg with one piece of text replaced."""
    text = write_cfg(IWR6843ISK_PROFILE_2D)
    assert old in text
    return text.replace(old, new)


@pytest.mark.parametrize(("make", "args", "needle"), [
    (lambda p: _capture(p, extra_bytes=1000), [], "truncated: 1 whole frame(s)"),
    (lambda p: _capture(p, cfg=_cfg("frameCfg 0 2 16 0", "frameCfg 0 2 16 3")), [],
     "size mismatch: 1 frames of 196608 bytes, but frameCfg numFrames = 3"),
    (lambda p: _capture(p, cfg=_cfg("frameCfg 0 2 16 0", "frameCfg 0 2 32 0")), [],
     "size mismatch: 196608 bytes is less than one frame of the configuration (393216"),
    (lambda p: _capture(p, cfg=_cfg("lowPower 0 0", "lowPowr 0 0")), [],
     "unknown command 'lowPowr'"),
    (lambda p: _capture(p, cfg=_cfg("adcbufCfg -1 0", "adcbufCfg -1 1")), [],
     "contradicts adcCfg adcOutputFmt"),
    (lambda p: _capture(p, cfg=_cfg("channelCfg 15 7 0", "channelCfg 15 3 0")), [],
     "enables a Tx that channelCfg txChannelEn = 3 leaves off"),
    (lambda p: _capture(p, cfg=_cfg("chirpCfg 2 2 0 0 0 0 0 4", "")), [],
     "no chirpCfg for chirp(s) [2]"),
    (lambda p: _capture(p, cfg="channelCfg 15 7 0\n"), [], "no adcCfg command"),
    (lambda p: _capture(p, cfg=_cfg("profileCfg 0 60 ", "profileCfg 0 62 ")), [],
     "c: the configuration cannot be modelled: preset 'ti_iwr6843isk': chirp 62.49–66 GHz "
     "leaves the TI IWR6843ISK's band 60–64 GHz"),
    (lambda p: _capture(p), ["--lanes", "3"], "lanes = 3: the DCA1000EVM records"),
    (lambda p: _capture(p, cfg=_cfg("channelCfg 15 7 0", "channelCfg 3 7 0")),
     ["--lanes", "4"], "lanes = 4 interleaves 4 Rx (one per lane), but channelCfg enables 2"),
])
def test_bad_captures_are_one_line_errors(tmp_path, capsys, make, args, needle):
    capture = make(tmp_path)
    status = main(["convert", str(capture), "--to", str(tmp_path / "o.h5"), *args])
    err = capsys.readouterr().err
    assert status == 2
    assert needle in err
    assert err.count("\n") == 1 and err.startswith("tofradar: error:")
    assert not (tmp_path / "o.h5").exists()


def test_missing_cfg_and_bad_file_size(tmp_path, capsys):
    (tmp_path / "lone.bin").write_bytes(b"\0" * 10)
    assert main(["convert", str(tmp_path / "lone.bin"), "--to", str(tmp_path / "o.h5")]) == 2
    assert "no configuration beside it" in capsys.readouterr().err
    (tmp_path / "lone.cfg").write_text(write_cfg(IWR6843ISK_PROFILE_2D))
    (tmp_path / "lone.bin").write_bytes(b"\0" * 11)
    assert main(["convert", str(tmp_path / "lone.bin"), "--to", str(tmp_path / "o.h5")]) == 2
    assert "size mismatch: 11 bytes" in capsys.readouterr().err
    with pytest.raises(CaptureError, match="profileCfg samples 256 at 5209 ksps"):
        parse_cfg(_cfg(" 57.14 ", " 40 "))


# ------------------------------------------------------ the published layout, written


def test_a_capture_in_the_published_layout_reads_as_the_cube(tmp_path):
    # Words laid out by hand from the 2-lane description (I0 I1 Q0 Q1 per pair of samples,
    # Rx after Rx within a chirp, chirps in frameCfg slot order): our reader must agree.
    s = IWR6843ISK_PROFILE_2D
    rng = np.random.default_rng(9)
    chirps = s.loops * s.n_tx
    i = rng.integers(-2**15, 2**15, size=(chirps, s.n_rx, s.num_adc_samples))
    q = rng.integers(-2**15, 2**15, size=i.shape)
    words = np.empty(i.size * 2, dtype="<i2")
    words[0::4] = i.reshape(-1)[0::2]
    words[1::4] = i.reshape(-1)[1::2]
    words[2::4] = q.reshape(-1)[0::2]
    words[3::4] = q.reshape(-1)[1::2]
    words.tofile(tmp_path / "hand.bin")
    (tmp_path / "hand.cfg").write_text(XWR68XX_CFG)
    cube = read_capture(tmp_path / "hand.bin").adc()[0]       # (loops, tx*rx, samples)
    # Simulator channel t·n_rx + r of loop l = TI chirp l·n_tx + t, Rx r.
    for loop, t, r in ((0, 0, 0), (3, 1, 2), (15, 2, 3)):
        want = (i[loop * 3 + t, r] + 1j * q[loop * 3 + t, r]) / 2**15
        assert_array_equal(cube[loop, t * 4 + r], want.astype(np.complex64))


XWR68XX_CFG = write_cfg(IWR6843ISK_PROFILE_2D)

# An mmWave Studio JSON export of the same configuration (the fields of its rfConfig and
# rawDataCaptureConfig that the reader uses; mmWave Studio writes hex strings for masks).
STUDIO_JSON = {
    "mmWaveDevices": [{
        "mmWaveDeviceId": 0,
        "rfConfig": {
            "waveformType": "legacyFrame", "MIMOScheme": "TDM",
            "rlChanCfg_t": {"rxChannelEn": "0xF", "txChannelEn": "0x7", "cascading": 0},
            "rlAdcOutCfg_t": {"fmt": {"b2AdcBits": 2, "b2AdcOutFmt": 1}},
            "rlProfiles": [{"rlProfileCfg_t": {
                "profileId": 0, "startFreqConst_GHz": 60.0, "idleTimeConst_usec": 359.0,
                "adcStartTimeConst_usec": 7.0, "rampEndTime_usec": 57.14,
                "txOutPowerBackoffCode": "0x0", "txPhaseShifter": "0x0",
                "freqSlopeConst_MHz_usec": 70.0, "txStartTime_usec": 1.0,
                "numAdcSamples": 256, "digOutSampleRate": 5209, "hpfCornerFreq1": 0,
                "hpfCornerFreq2": 0, "rxGain_dB": "0x9E"}}],
            "rlChirps": [{"rlChirpCfg_t": {
                "chirpStartIdx": k, "chirpEndIdx": k, "profileId": 0, "startFreqVar_MHz": 0,
                "freqSlopeVar_KHz_usec": 0, "idleTimeVar_usec": 0, "adcStartTimeVar_usec": 0,
                "txEnable": hex(1 << k)}} for k in range(3)],
            "rlFrameCfg_t": {"chirpStartIdx": 0, "chirpEndIdx": 2, "numLoops": 16,
                             "numFrames": 0, "framePeriodicity_msec": 100.0,
                             "triggerSelect": 1},
        },
        "rawDataCaptureConfig": {"rlDevLaneEnable_t": {"laneEn": "0x3"}},
    }],
}


def test_mmwave_studio_json_configures_a_capture(tmp_path, capsys):
    s = IWR6843ISK_PROFILE_2D
    adc = random_cube(s, 1, seed=7)
    write_capture(tmp_path / "adc_data.bin", adc, s)
    (tmp_path / "adc_data.cfg").unlink()
    (tmp_path / "adc_data.mmwave.json").write_text(json.dumps(STUDIO_JSON))
    capture = read_capture(tmp_path / "adc_data.bin")        # found beside it, 2 lanes
    assert capture.settings == s
    assert_array_equal(capture.adc(), adc)
    assert main(["convert", str(tmp_path / "adc_data.bin"), "--to", str(tmp_path / "o.h5"),
                 "--lanes", "4"]) == 2
    assert "lanes = 4, but" in capsys.readouterr().err
    broken = json.loads(json.dumps(STUDIO_JSON))
    del broken["mmWaveDevices"][0]["rfConfig"]["rlFrameCfg_t"]["numLoops"]
    (tmp_path / "adc_data.mmwave.json").write_text(json.dumps(broken))
    assert main(["convert", str(tmp_path / "adc_data.bin"), "--to", str(tmp_path / "o.h5")]) == 2
    assert "no rlFrameCfg_t.numLoops in the mmWave Studio configuration" \
        in capsys.readouterr().err
    swapped = json.loads(json.dumps(STUDIO_JSON))
    swapped["mmWaveDevices"][0]["rawDataCaptureConfig"]["rlDevDataFmtCfg_t"] = {"iqSwapSel": 1}
    (tmp_path / "adc_data.mmwave.json").write_text(json.dumps(swapped))
    assert main(["convert", str(tmp_path / "adc_data.bin"), "--to", str(tmp_path / "o.h5")]) == 2
    assert "iqSwapSel = 1: only I-before-Q" in capsys.readouterr().err
