"""TI mmWave raw captures (DCA1000EVM ``.bin`` + mmWave SDK ``.cfg``), read and written.

Layout (``docs/devices.md``, "TI DCA1000 captures", with sources):

- The ``.bin`` file is the LVDS stream the DCA1000EVM records (TI, *DCA1000EVM Data
  Capture Card* user guide SPRUIJ4; mmWave Studio user guide, "raw ADC data format"):
  little-endian signed 16-bit words, frame after frame, no header. A frame is
  ``numLoops`` loops of the ``frameCfg`` chirp slots (TDM-MIMO: one Tx per slot, slot
  order = chirp order), each chirp holds every enabled Rx.
- **2 LVDS lanes** (xWR16xx/18xx/68xx, the SDK's non-interleaved mode): per chirp, the Rx
  one after the other, each ``numAdcSamples`` samples; complex samples come in groups of
  four words ``I0 I1 Q0 Q1`` (two samples per group, OpenRadar's
  ``mmwave.dataloader.DCA1000.organize``; TI's ``readDCA1000.m`` for xWR16xx/18xx); real
  samples are stored in order.
- **4 LVDS lanes** (xWR12xx/14xx): each lane carries one Rx, interleaved per sample:
  complex groups of eight words ``I_rx0 … I_rx3 Q_rx0 … Q_rx3``, real groups of four
  (TI's ``readDCA1000.m`` for xWR14xx).
- ADC codes: a ``b``-bit ADC (``adcCfg numADCBits``: 0 → 12, 1 → 14, 2 → 16 bits) stores
  its signed codes in the 16-bit words; this module maps code ``k`` to ``k / 2^(b−1)``
  of full scale, the simulator's FS convention (``docs/physics_radar.md``), so a
  simulated cube quantised to ``b`` bits round-trips bit for bit.

The cube the reader returns is the simulator's ``(frames, chirps, tx*rx, samples)``: TI's
chirp ``loop · n_tx + t`` with Rx ``r`` is the model's chirp ``loop``, channel
``t · n_rx + r`` — the same memory order.
"""

from __future__ import annotations

import json
import math
import os
import re
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray
from pydantic import ValidationError

from simcore.scene.radar_config import RadarConfig
from simcore.scene.ti_mmwave import ADC_BITS, TiSettings, radar_from_ti, ti_from_radar

#: LVDS lane counts the reader and writer know (DCA1000EVM: 2 for xWR16/18/68xx, 4 for
#: xWR12/14xx).
LANES = (2, 4)
#: mmWave SDK demo CLI commands (SDK user guide, "Configuration (.cfg) file format"); the
#: ones not listed in :data:`_PARSED` carry processing settings and are kept as text.
KNOWN_COMMANDS = frozenset({
    "sensorStop", "sensorStart", "flushCfg", "dfeDataOutputMode", "channelCfg", "adcCfg",
    "adcbufCfg", "profileCfg", "chirpCfg", "frameCfg", "lowPower", "guiMonitor", "cfarCfg",
    "multiObjBeamForming", "clutterRemoval", "calibDcRangeSig", "extendedMaxVelocity",
    "lvdsStreamCfg", "compRangeBiasAndRxChanPhase", "measureRangeBiasAndRxChanPhase",
    "CQRxSatMonitor", "CQSigImgMonitor", "analogMonitor", "aoaFovCfg", "cfarFovCfg",
    "calibData", "bpmCfg", "advFrameCfg", "subFrameCfg", "staticBoundaryBox",
    "boundaryBox", "sensorPosition", "gatingParam", "stateParam", "allocationParam",
    "maxAcceleration", "trackingCfg", "presenceBoundaryBox", "idlePowerCycle",
    "clutterRemovalCfg", "antGeometry0", "antGeometry1", "antPhaseRot", "fovCfg",
    "compressionCfg", "mpdBoundaryBox", "cliOutputCfg"})
#: Commands and their argument counts that this module reads.
_PARSED = {"dfeDataOutputMode": 1, "channelCfg": 3, "adcCfg": 2, "adcbufCfg": 5,
           "profileCfg": 14, "chirpCfg": 8, "frameCfg": 7}


class CaptureError(ValueError):
    """A capture or configuration that cannot be read; the message names file and field."""


# ---------------------------------------------------------------------------- .cfg
def _numbers(cmd: str, args: list[str], where: str) -> list[float]:
    want = _PARSED[cmd]
    if len(args) < want:
        raise CaptureError(f"{where}: {cmd} takes {want} arguments, got {len(args)}")
    try:
        values = [float(a) for a in args[:want]]
    except ValueError:
        raise CaptureError(f"{where}: {cmd} {' '.join(args)}: arguments must be "
                           "numbers") from None
    if not all(math.isfinite(v) for v in values):
        raise CaptureError(f"{where}: {cmd}: arguments must be finite")
    return values


def _commands(text: str, source: str) -> dict[str, list[tuple[list[float], str]]]:
    """Parsed commands by name: (numbers, 'file:line'), unknown commands refused."""
    out: dict[str, list[tuple[list[float], str]]] = {}
    for k, raw in enumerate(text.splitlines(), start=1):
        line = raw.split("%", 1)[0].strip()
        if not line:
            continue
        cmd, *args = line.split()
        where = f"{source}:{k}"
        if cmd not in KNOWN_COMMANDS:
            raise CaptureError(f"{where}: unknown command {cmd!r} (not an mmWave SDK CLI "
                               "command)")
        if cmd in ("advFrameCfg", "subFrameCfg"):
            raise CaptureError(f"{where}: {cmd}: advanced frames (sub-frames) are not "
                               "supported; use frameCfg")
        if cmd in _PARSED:
            out.setdefault(cmd, []).append((_numbers(cmd, args, where), where))
    for cmd in ("channelCfg", "adcCfg", "profileCfg", "chirpCfg", "frameCfg"):
        if cmd not in out:
            raise CaptureError(f"{source}: no {cmd} command; a capture's configuration "
                               f"needs channelCfg, adcCfg, profileCfg, chirpCfg and frameCfg")
    return out


def _format(cmds: dict[str, list[tuple[list[float], str]]], source: str
            ) -> tuple[bool, int]:
    """(complex, ADC bits) from adcCfg, checked against adcbufCfg."""
    (bits_code, fmt), where = cmds["adcCfg"][-1]
    if bits_code not in ADC_BITS or fmt not in (0, 1, 2):
        raise CaptureError(f"{where}: adcCfg {bits_code:g} {fmt:g}: numADCBits must be 0, 1 "
                           "or 2 (12, 14, 16 bits) and adcOutputFmt 0, 1 or 2 (real, "
                           "complex 1x, complex 2x)")
    complex_iq = fmt != 0
    for (_, buf_fmt, *_rest), buf_where in cmds.get("adcbufCfg", []):
        if buf_fmt not in (0, 1) or (buf_fmt == 0) != complex_iq:
            buf_kind = "complex" if buf_fmt == 0 else "real"
            raise CaptureError(
                f"{buf_where}: adcbufCfg adcOutputFmt = {buf_fmt:g} ({buf_kind}) "
                f"contradicts adcCfg adcOutputFmt = {fmt:g} "
                f"({'complex' if complex_iq else 'real'}) at {where}")
    return complex_iq, ADC_BITS[int(bits_code)]


def _chirp_slots(cmds: dict[str, list[tuple[list[float], str]]], profile_id: float,
                 tx_enabled: int) -> tuple[tuple[int, ...], list[float], str]:
    """``txEnable`` per slot of frameCfg's chirp range; the frame's numbers and location."""
    frame, f_where = cmds["frameCfg"][-1]
    first, last = int(frame[0]), int(frame[1])
    masks: dict[int, int] = {}
    for c, where in cmds["chirpCfg"]:
        start, end, pid, *variations, mask = c
        if pid != profile_id:
            raise CaptureError(f"{where}: chirpCfg profileId {pid:g} names no profileCfg "
                               f"(profile {profile_id:g} is defined)")
        if any(variations):
            raise CaptureError(f"{where}: chirpCfg frequency/slope/time variations are not "
                               "modelled; set them to 0")
        if int(mask) & ~tx_enabled or int(mask) == 0:
            raise CaptureError(f"{where}: chirpCfg txEnable = {mask:g} enables a Tx that "
                               f"channelCfg txChannelEn = {tx_enabled} leaves off")
        for i in range(int(start), int(end) + 1):
            masks[i] = int(mask)
    missing = [i for i in range(first, last + 1) if i not in masks]
    if last < first or missing:
        raise CaptureError(f"{f_where}: frameCfg chirps {first}…{last}: no chirpCfg for "
                           f"chirp(s) {missing or [last]}")
    return tuple(masks[i] for i in range(first, last + 1)), frame, f_where


def parse_cfg(text: str, *, source: str = "cfg") -> TiSettings:
    """The TI settings of an mmWave SDK ``.cfg`` text (one profile, ``frameCfg`` frames).

    Raises
    ------
    CaptureError
        An unknown command, a missing or malformed one, or commands that contradict each
        other (chirps naming an undefined profile or a disabled Tx, ADC samples that do not
        fit the ramp, adcbufCfg against adcCfg); the message names the file and line.
    """
    cmds = _commands(text, source)
    profiles = cmds["profileCfg"]
    if len(profiles) > 1:
        raise CaptureError(f"{profiles[1][1]}: several profileCfg; one profile is supported")
    p, p_where = profiles[0]
    rx_mask, tx_mask = int(cmds["channelCfg"][-1][0][0]), int(cmds["channelCfg"][-1][0][1])
    complex_iq, bits = _format(cmds, source)
    masks, frame, f_where = _chirp_slots(cmds, p[0], tx_mask)
    (_, start_ghz, idle, adc_start, ramp_end, tx_power, _phase, slope, tx_start, n,
     fs_ksps, hpf1, hpf2, rx_gain) = p
    if n < 2 or n != int(n) or fs_ksps <= 0 or slope <= 0:
        raise CaptureError(f"{p_where}: profileCfg numAdcSamples = {n:g}, digOutSampleRate "
                           f"= {fs_ksps:g}, freqSlopeConst = {slope:g}: must be positive "
                           "(up-chirps)")
    sampling_us = n / fs_ksps * 1e3
    if adc_start + sampling_us > ramp_end * (1 + 1e-6):
        raise CaptureError(
            f"{p_where}: profileCfg samples {n:g} at {fs_ksps:g} ksps take {sampling_us:.2f} "
            f"µs from adcStartTime {adc_start:g} µs, past rampEndTime {ramp_end:g} µs")
    if rx_mask <= 0 or rx_mask > 15:
        raise CaptureError(f"{source}: channelCfg rxChannelEn = {rx_mask}: 1…15 (4 Rx)")
    if frame[2] < 1 or frame[4] <= 0:
        raise CaptureError(f"{f_where}: frameCfg numLoops = {frame[2]:g}, "
                           f"framePeriodicity = {frame[4]:g} ms must be positive")
    return TiSettings(
        start_freq_ghz=start_ghz, idle_time_us=idle, adc_start_time_us=adc_start,
        ramp_end_time_us=ramp_end, freq_slope_mhz_us=slope, num_adc_samples=int(n),
        sample_rate_ksps=fs_ksps, tx_masks=masks, rx_mask=rx_mask, loops=int(frame[2]),
        frame_period_ms=frame[4], num_frames=int(frame[3]), complex_iq=complex_iq,
        adc_bits=bits, hpf1=int(hpf1), hpf2=int(hpf2), rx_gain_db=int(rx_gain),
        tx_out_power=int(tx_power), tx_start_time_us=tx_start)


def _studio_value(node: Any, path: str, source: str) -> float:
    """A number of an mmWave Studio JSON field: int, float or a hex string ("0x7")."""
    d = node
    for key in path.split("."):
        if not isinstance(d, dict) or key not in d:
            raise CaptureError(f"{source}: no {path} in the mmWave Studio configuration")
        d = d[key]
    try:
        value = float(int(d, 0)) if isinstance(d, str) else float(d)
    except (TypeError, ValueError):
        raise CaptureError(f"{source}: {path} = {d!r} is not a number") from None
    if not math.isfinite(value):
        raise CaptureError(f"{source}: {path} = {d!r} is not finite")
    return value


def parse_studio_json(text: str, *, source: str = "json") -> tuple[TiSettings, int | None]:
    """The TI settings of an mmWave Studio JSON export, and its LVDS lane count.

    Reads ``mmWaveDevices[0].rfConfig`` (``rlChanCfg_t``, ``rlAdcOutCfg_t``, one
    ``rlProfiles`` entry, ``rlChirps``, ``rlFrameCfg_t``) and
    ``rawDataCaptureConfig.rlDevLaneEnable_t.laneEn`` (None when absent); then the same
    checks as :func:`parse_cfg`, which it converts to. ``rlDevDataFmtCfg_t.iqSwapSel``
    must be 0 (I before Q).
    """
    try:
        doc = json.loads(text)
        rf = doc["mmWaveDevices"][0]["rfConfig"]
    except (ValueError, KeyError, IndexError, TypeError):
        raise CaptureError(f"{source}: not an mmWave Studio JSON configuration (no "
                           "mmWaveDevices[0].rfConfig)") from None
    if rf.get("waveformType", "legacyFrame") != "legacyFrame":
        raise CaptureError(f"{source}: waveformType {rf.get('waveformType')!r}: advanced "
                           "frames are not supported; use legacyFrame")
    profiles = rf.get("rlProfiles") or []
    chirps = rf.get("rlChirps") or []
    if len(profiles) != 1 or not chirps:
        raise CaptureError(f"{source}: {len(profiles)} rlProfiles and {len(chirps)} rlChirps; "
                           "one profile and its chirps are supported")
    p = profiles[0]
    prof = ("rlProfileCfg_t.profileId", "rlProfileCfg_t.startFreqConst_GHz",
            "rlProfileCfg_t.idleTimeConst_usec", "rlProfileCfg_t.adcStartTimeConst_usec",
            "rlProfileCfg_t.rampEndTime_usec", "rlProfileCfg_t.txOutPowerBackoffCode",
            "rlProfileCfg_t.txPhaseShifter", "rlProfileCfg_t.freqSlopeConst_MHz_usec",
            "rlProfileCfg_t.txStartTime_usec", "rlProfileCfg_t.numAdcSamples",
            "rlProfileCfg_t.digOutSampleRate", "rlProfileCfg_t.hpfCornerFreq1",
            "rlProfileCfg_t.hpfCornerFreq2", "rlProfileCfg_t.rxGain_dB")
    chirp = ("chirpStartIdx", "chirpEndIdx", "profileId", "startFreqVar_MHz",
             "freqSlopeVar_KHz_usec", "idleTimeVar_usec", "adcStartTimeVar_usec", "txEnable")
    frame = ("chirpStartIdx", "chirpEndIdx", "numLoops", "numFrames", "framePeriodicity_msec")
    lines = [
        "channelCfg " + " ".join(_g(_studio_value(rf, f"rlChanCfg_t.{k}", source))
                                 for k in ("rxChannelEn", "txChannelEn")) + " 0",
        "adcCfg " + " ".join(_g(_studio_value(rf, f"rlAdcOutCfg_t.fmt.{k}", source))
                             for k in ("b2AdcBits", "b2AdcOutFmt")),
        "profileCfg " + " ".join(_g(_studio_value(p, k, source)) for k in prof),
        *("chirpCfg " + " ".join(_g(_studio_value(c, f"rlChirpCfg_t.{k}", source))
                                 for k in chirp) for c in chirps),
        "frameCfg " + " ".join(_g(_studio_value(rf, f"rlFrameCfg_t.{k}", source))
                               for k in frame) + " 1 0",
    ]
    settings = parse_cfg("\n".join(lines), source=source)
    capture_cfg = doc["mmWaveDevices"][0].get("rawDataCaptureConfig", {})
    swap = capture_cfg.get("rlDevDataFmtCfg_t", {}).get("iqSwapSel", 0)
    if swap not in (0, "0x0", "0"):
        raise CaptureError(f"{source}: rawDataCaptureConfig.rlDevDataFmtCfg_t.iqSwapSel = "
                           f"{swap!r}: only I-before-Q captures (0) are supported")
    lane_mask = capture_cfg.get("rlDevLaneEnable_t", {}).get("laneEn")
    if lane_mask is None:
        return settings, None
    mask = int(_studio_value({"laneEn": lane_mask}, "laneEn", source))
    return settings, bin(mask).count("1")


def _g(x: float) -> str:
    """A number as the SDK's .cfg files write it (no trailing zeros)."""
    return f"{x:.10g}"


def write_cfg(s: TiSettings) -> str:
    """An mmWave SDK ``.cfg`` text for ``s`` (the xwr68xx/18xx demo's command set).

    ``lvdsStreamCfg -1 0 1 0`` streams the raw ADC data over LVDS to the DCA1000.
    """
    tx_all = 0
    for m in s.tx_masks:
        tx_all |= m
    bits_code = {v: k for k, v in ADC_BITS.items()}[s.adc_bits]
    lines = [
        "% written by tofradar (docs/devices.md): a simulated capture's configuration",
        "sensorStop", "flushCfg", "dfeDataOutputMode 1",
        f"channelCfg {s.rx_mask} {tx_all} 0",
        f"adcCfg {bits_code} {1 if s.complex_iq else 0}",
        f"adcbufCfg -1 {0 if s.complex_iq else 1} 1 1 1",
        "profileCfg 0 " + " ".join(_g(v) for v in (
            s.start_freq_ghz, s.idle_time_us, s.adc_start_time_us, s.ramp_end_time_us,
            s.tx_out_power, 0, s.freq_slope_mhz_us, s.tx_start_time_us, s.num_adc_samples,
            s.sample_rate_ksps, s.hpf1, s.hpf2, s.rx_gain_db)),
    ]
    lines += [f"chirpCfg {k} {k} 0 0 0 0 0 {m}" for k, m in enumerate(s.tx_masks)]
    lines += [f"frameCfg 0 {s.n_tx - 1} {s.loops} {s.num_frames} {_g(s.frame_period_ms)} 1 0",
              "lowPower 0 0", "lvdsStreamCfg -1 0 1 0", "sensorStart"]
    return "\n".join(lines) + "\n"


# ---------------------------------------------------------------------------- .bin
def frame_words(s: TiSettings) -> int:
    """16-bit words per frame: loops × slots × Rx × samples × (2 if complex)."""
    return s.loops * s.n_tx * s.n_rx * s.num_adc_samples * (2 if s.complex_iq else 1)


def _check_lanes(s: TiSettings, lanes: int) -> None:
    if lanes not in LANES:
        raise CaptureError(f"lanes = {lanes}: the DCA1000EVM records 2 LVDS lanes (xWR16xx/"
                           "18xx/68xx) or 4 (xWR12xx/14xx)")
    if lanes == 4 and s.n_rx != 4:
        raise CaptureError(f"lanes = 4 interleaves 4 Rx (one per lane), but channelCfg "
                           f"enables {s.n_rx}; a 2-lane capture stores the Rx in turn")
    if lanes == 2 and s.complex_iq and s.num_adc_samples % 2:
        raise CaptureError(f"lanes = 2 packs complex samples in pairs (I0 I1 Q0 Q1), but "
                           f"numAdcSamples = {s.num_adc_samples} is odd")


def decode_frames(words: NDArray[np.int16], s: TiSettings, *, lanes: int = 2
                  ) -> NDArray[np.int32] | NDArray[np.complex64]:
    """Raw words of whole frames → codes, shape (frames, loops·tx, rx, samples).

    Real captures give int32 codes, complex ones complex64 codes (``I + jQ``).
    """
    _check_lanes(s, lanes)
    n_frames = words.size // frame_words(s)
    chirps, rx, n = s.loops * s.n_tx, s.n_rx, s.num_adc_samples
    w = words.astype(np.int32)
    if lanes == 2:
        if s.complex_iq:
            g = w.reshape(-1, 4)
            z = np.empty((g.shape[0], 2), dtype=np.complex64)
            z[:, 0] = g[:, 0] + 1j * g[:, 2]
            z[:, 1] = g[:, 1] + 1j * g[:, 3]
            return z.reshape(n_frames, chirps, rx, n)
        return w.reshape(n_frames, chirps, rx, n)
    if s.complex_iq:
        g = w.reshape(n_frames, chirps, n, 2, rx)
        return (g[:, :, :, 0] + 1j * g[:, :, :, 1]).astype(np.complex64).transpose(0, 1, 3, 2)
    return w.reshape(n_frames, chirps, n, rx).transpose(0, 1, 3, 2)


def encode_frames(codes: NDArray[Any], s: TiSettings, *, lanes: int = 2) -> NDArray[np.int16]:
    """Inverse of :func:`decode_frames`: codes (frames, loops·tx, rx, samples) → words."""
    _check_lanes(s, lanes)
    c = np.asarray(codes)
    if lanes == 2:
        if s.complex_iq:
            pairs = c.reshape(-1, 2)
            g = np.stack([pairs[:, 0].real, pairs[:, 1].real, pairs[:, 0].imag,
                          pairs[:, 1].imag], axis=1)
            return np.rint(g).astype(np.int16).reshape(-1)
        return np.rint(c.real).astype(np.int16).reshape(-1)
    t = c.transpose(0, 1, 3, 2)                       # (frames, chirps, samples, rx)
    if s.complex_iq:
        g = np.stack([t.real, t.imag], axis=3)        # (frames, chirps, samples, 2, rx)
        return np.rint(g).astype(np.int16).reshape(-1)
    return np.rint(t.real).astype(np.int16).reshape(-1)


def read_words(path: Path, s: TiSettings) -> NDArray[np.int16]:
    """The whole frames of a capture, checked against the configuration's frame size.

    Raises
    ------
    CaptureError
        An empty file, a file that ends inside a frame (truncated), or a frame count that
        contradicts ``frameCfg numFrames`` (size mismatch).
    """
    size = path.stat().st_size
    frame_bytes = 2 * frame_words(s)
    if size == 0 or size % 2:
        raise CaptureError(f"{path}: size mismatch: {size} bytes is not a whole number of "
                           f"16-bit words of a frame ({frame_bytes} bytes)")
    n, rest = divmod(size, frame_bytes)
    if rest and (n >= 1 or s.num_frames):
        raise CaptureError(
            f"{path}: truncated: {n} whole frame(s) of {frame_bytes} bytes and {rest} bytes "
            f"of the next (the configuration's frame: {s.loops} loops × {s.n_tx} Tx × "
            f"{s.n_rx} Rx × {s.num_adc_samples} {'complex ' if s.complex_iq else ''}samples)")
    if n == 0:
        raise CaptureError(f"{path}: size mismatch: {size} bytes is less than one frame of the "
                           f"configuration ({frame_bytes} bytes)")
    if s.num_frames and n != s.num_frames:
        raise CaptureError(f"{path}: size mismatch: {n} frames of {frame_bytes} bytes, but "
                           f"frameCfg numFrames = {s.num_frames}")
    return np.fromfile(path, dtype="<i2")


@dataclass(frozen=True)
class TiCapture:
    """A DCA1000 capture read with its configuration.

    Attributes
    ----------
    settings : TiSettings
    codes : ndarray, shape (frames, loops·tx, rx, samples)
        ADC codes (int32 real or complex64 ``I + jQ``) in TI's chirp order.
    cfg_text : str
        The ``.cfg`` the capture was taken with.
    """

    settings: TiSettings
    codes: NDArray[Any]
    cfg_text: str

    @property
    def n_frames(self) -> int:
        """Frames in the capture."""
        return int(self.codes.shape[0])

    def adc(self) -> NDArray[Any]:
        """All frames in FS, the simulator's (frames, chirps, tx*rx, samples).

        float32 (real) or complex64 (IQ), code ``k`` → ``k / 2^(b−1)``.
        """
        s = self.settings
        scale = np.float32(2.0 ** (s.adc_bits - 1))
        shape = (self.n_frames, s.loops, s.n_tx * s.n_rx, s.num_adc_samples)
        x = self.codes.reshape(shape) / scale
        return x.astype(np.complex64 if s.complex_iq else np.float32)


def _cfg_beside(capture: Path) -> Path:
    """The configuration next to a capture.

    Same stem ``.cfg`` (mmWave SDK) or ``.json`` / ``.mmwave.json`` (mmWave Studio), else
    the only ``.cfg`` in its folder.
    """
    same = capture.with_suffix(".cfg")
    stem = re.sub(r"_Raw_\d+$", "", capture.stem)        # mmWave Studio's adc_data_Raw_0
    for name in (same.name, f"{stem}.cfg", f"{capture.stem}.mmwave.json",
                 f"{stem}.mmwave.json", f"{capture.stem}.json", f"{stem}.json"):
        if (capture.parent / name).is_file():
            return capture.parent / name
    others = sorted(capture.parent.glob("*.cfg"))
    if len(others) == 1:
        return others[0]
    raise CaptureError(f"{capture}: no configuration beside it ({same.name}); give the "
                       "mmWave SDK .cfg with --cfg")


def read_capture(path: str | os.PathLike[str], *, cfg: str | os.PathLike[str] | None = None,
                 lanes: int | None = None) -> TiCapture:
    """Read a DCA1000 capture (``.bin``) with the configuration of the radar.

    Parameters
    ----------
    path : path-like
        The raw capture.
    cfg : path-like, optional
        The mmWave SDK ``.cfg`` or mmWave Studio ``.json``; default: beside the capture
        (:func:`_cfg_beside`).
    lanes : int, optional
        LVDS lanes of the capture (2 or 4); default: the JSON's ``laneEn``, else 2.

    Raises
    ------
    CaptureError
        Missing files, a bad configuration (:func:`parse_cfg`), a size that does not
        match it (:func:`read_words`), a lane count the configuration cannot use.
    """
    capture = Path(path)
    if not capture.is_file():
        raise CaptureError(f"{capture}: no such capture file")
    cfg_path = Path(cfg) if cfg is not None else _cfg_beside(capture)
    try:
        text = cfg_path.read_text(encoding="utf-8", errors="strict")
    except (OSError, UnicodeDecodeError) as exc:
        raise CaptureError(f"{cfg_path}: cannot read the configuration ({exc})") from None
    if cfg_path.suffix.lower() == ".json":
        settings, json_lanes = parse_studio_json(text, source=str(cfg_path))
        if json_lanes is not None and lanes is not None and json_lanes != lanes:
            raise CaptureError(f"lanes = {lanes}, but {cfg_path} enables {json_lanes} LVDS "
                               "lanes (rlDevLaneEnable_t.laneEn)")
        lanes = lanes if lanes is not None else json_lanes
    else:
        settings = parse_cfg(text, source=str(cfg_path))
    lanes = 2 if lanes is None else lanes
    _check_lanes(settings, lanes)
    words = read_words(capture, settings)
    return TiCapture(settings, decode_frames(words, settings, lanes=lanes), text)


def write_capture(path: str | os.PathLike[str], adc_fs: NDArray[Any], settings: TiSettings,
                  *, lanes: int = 2) -> Path:
    """Write a simulated ADC cube as a DCA1000 capture, with its ``.cfg`` beside it.

    Parameters
    ----------
    path : path-like
        The ``.bin`` to write; the configuration goes to the same stem ``.cfg``.
    adc_fs : ndarray, shape (frames, chirps, tx*rx, samples)
        The cube in FS (float real or complex IQ), on the ``settings.adc_bits`` grid.
    settings : TiSettings
    lanes : int
        LVDS lanes (2 or 4).

    Returns
    -------
    Path
        The ``.cfg`` written.

    Raises
    ------
    CaptureError
        A cube whose shape or values do not fit the configuration.
    """
    s = settings
    x = np.asarray(adc_fs)
    want = (s.loops, s.n_tx * s.n_rx, s.num_adc_samples)
    if x.ndim != 4 or x.shape[1:] != want:
        raise CaptureError(f"ADC cube of shape {x.shape}; the configuration needs "
                           f"(frames, {want[0]}, {want[1]}, {want[2]})")
    half = 2.0 ** (s.adc_bits - 1)
    codes = x.astype(np.complex128 if s.complex_iq else np.float64) * half
    if np.iscomplexobj(x) != s.complex_iq:
        raise CaptureError("the cube is " + ("complex" if np.iscomplexobj(x) else "real")
                           + " but the configuration is not")
    parts = [codes.real, codes.imag] if s.complex_iq else [codes.real]
    if any(np.any(np.abs(p - np.rint(p)) > 1e-3) for p in parts):
        raise CaptureError(f"the ADC cube is not on the {s.adc_bits}-bit grid (is the radar's "
                           "adc_bits set?); the capture format holds integer codes")
    shaped = codes.reshape(x.shape[0], s.loops * s.n_tx, s.n_rx, s.num_adc_samples)
    words = encode_frames(shaped, s, lanes=lanes)
    out = Path(path)
    words.astype("<i2").tofile(out)
    cfg_path = out.with_suffix(".cfg")
    cfg_path.write_text(write_cfg(s), encoding="utf-8")
    return cfg_path


# ------------------------------------------------------------------- datasets
def capture_radar(settings: TiSettings) -> RadarConfig:
    """The model radar of a capture: the TI board whose band holds the chirp.

    60–64 GHz → IWR6843ISK antennas and levels; otherwise (76–81 GHz) AWR1843BOOST's.
    """
    from simcore.scene import device_radars as rads

    if settings.start_freq_ghz < 70:
        tx, rx = rads.ti_board_layout(rads.ISK_HALF_WAVELENGTH_MM)
        return radar_from_ti(settings, tx_layout=tx, rx_layout=rx, preset="ti_iwr6843isk",
                             **rads.IWR6843_LEVELS)
    tx, rx = rads.ti_board_layout(rads.BOOST_HALF_WAVELENGTH_MM)
    return radar_from_ti(settings, tx_layout=tx, rx_layout=rx, preset="ti_awr1843boost",
                         **rads.AWR1843_LEVELS)


def capture_project(capture: TiCapture, *, name: str) -> Any:
    """A project whose radar reproduces the capture's configuration (empty scene)."""
    from simcore.scene.model import Project, SensorRig, Timeline

    period = capture.settings.frame_period_ms * 1e-3
    try:
        radar = capture_radar(capture.settings)
    except ValidationError as exc:
        reasons = "; ".join(str(e["msg"]).removeprefix("Value error, ") for e in exc.errors())
        raise CaptureError(f"{name}: the configuration cannot be modelled: {reasons}") from None
    except ValueError as exc:
        raise CaptureError(f"{name}: the configuration cannot be modelled: {exc}") from None
    return Project(
        name=name, description=f"reproduces the TI radar configuration of the capture {name} "
                               "(tofradar convert --project); the scene is empty",
        timeline=Timeline(frame_rate_hz=1.0 / period, duration_s=capture.n_frames * period),
        rig=SensorRig(tof=None, radar=radar))


def convert_capture(source: str | os.PathLike[str], out: str | os.PathLike[str], *,
                    cfg: str | os.PathLike[str] | None = None, lanes: int | None = None,
                    project_out: str | os.PathLike[str] | None = None,
                    overwrite: bool = False) -> int:
    """Write a DCA1000 capture as a dataset of the simulator's layout; return its frames.

    Per frame ``/time`` (``k · framePeriodicity``), ``/radar/adc`` (FS, the simulator's
    (chirps, tx*rx, samples)), ``/radar/chirp_start_time`` and the products of
    :func:`simcore.dsp.process_frame`; ``/meta`` holds the project
    (:func:`capture_project`), ``source = "ti_dca1000"`` and the ``.cfg`` text.
    """
    from simcore.dsp import process_frame, static_axes_items
    from simcore.io.hdf5_writer import DatasetExistsError, DatasetWriter
    from simcore.scene.project_io import project_to_json, save_project
    from simcore.sensors.schema import schema_of

    capture = read_capture(source, cfg=cfg, lanes=lanes)
    project = capture_project(capture, name=Path(source).stem)
    if project_out is not None and Path(project_out).exists() and not overwrite:
        raise DatasetExistsError(f"{project_out} already exists; use --overwrite to replace it")
    (name, radar), = project.sensors_of_kind("radar").items()
    assert isinstance(radar, RadarConfig)
    dsp = project.dsp
    schema = schema_of("radar")
    meta = {"source": "ti_dca1000", "capture_path": str(Path(source).resolve()),
            "capture_cfg": capture.cfg_text,
            "adc_conversion": f"code / {2 ** (capture.settings.adc_bits - 1)} "
                              f"({capture.settings.adc_bits}-bit signed codes)"}
    adc = capture.adc()
    period = capture.settings.frame_period_ms * 1e-3
    starts = radar.chirp_start_times_s()
    with DatasetWriter(out, project_json=project_to_json(project), seed=project.seed,
                       overwrite=overwrite, extra_meta=meta) as writer:
        writer.write_static(static_axes_items(radar, dsp, group=name))
        for k in range(capture.n_frames):
            products = process_frame(adc[k], radar, dsp)
            writer.append_rows(schema.dataset_path(name, "detections"),
                               products.detection_records(k))
            writer.append({"/time": (np.asarray(k * period), "s"),
                           schema.dataset_path(name, "adc"): (adc[k], "FS"),
                           schema.dataset_path(name, "chirp_start_time"): (k * period + starts,
                                                                           "s"),
                           **products.hdf5_items(group=name)})
    if project_out is not None:
        save_project(project, project_out)
    return capture.n_frames


def export_capture(source: str | os.PathLike[str], out: str | os.PathLike[str], *,
                   lanes: int = 2, overwrite: bool = False) -> tuple[int, Path]:
    """Write a dataset's radar ADC cube as a DCA1000 capture + ``.cfg``.

    The first radar of the dataset's project; frame period from the timeline (and the
    radar's own frame rate). Returns (frames, the ``.cfg`` path).

    Raises
    ------
    CaptureError
        No radar, a radar TI's format cannot hold (more than 4 Rx, no ADC quantisation,
        an ADC resolution other than 12/14/16 bits).
    """
    import h5py

    from simcore.scene.project_io import project_from_dict

    out_path = Path(out)
    if not overwrite:
        for p in (out_path, out_path.with_suffix(".cfg")):
            if p.exists():
                raise CaptureError(f"{p} already exists; use --overwrite to replace it")
    with h5py.File(source, "r") as f:
        raw = f["meta"].attrs.get("project_json", "")
        project = project_from_dict(json.loads(raw.decode() if isinstance(raw, bytes) else raw),
                                    source=str(source), check_files=False)
        radars = [(n, c) for n, c in project.sensor_configs().items()
                  if isinstance(c, RadarConfig)]
        if not radars:
            raise CaptureError(f"{source}: the dataset's project has no radar")
        name, radar = radars[0]
        if f"{name}/adc" not in f:
            raise CaptureError(f"{source}: no /{name}/adc in the dataset")
        adc = np.asarray(f[f"{name}/adc"])
    if radar.adc_bits not in (12, 14, 16):
        raise CaptureError(f"{name}.adc_bits = {radar.adc_bits}: the TI capture format holds "
                           "12-, 14- or 16-bit codes")
    rate = project.timeline.frame_rate_hz
    period = radar.frame_divider(rate) / rate
    try:
        settings = ti_from_radar(radar, frame_period_s=period, num_frames=adc.shape[0])
    except ValueError as exc:
        raise CaptureError(f"{name}: {exc}") from None
    cfg_path = write_capture(out_path, adc, settings, lanes=lanes)
    return int(adc.shape[0]), cfg_path
