"""Real radar recordings: the Infineon Radar Fusion GUI / ifxdaq format, read and measured.

A recording is a folder holding ``RadarIfxAvian_<nn>/`` with ``radar.npy`` (unsigned ADC
codes, shape ``(frames, channels, chirps, samples)``), ``config.json`` (the device
configuration, ``device_config.fmcw_single_shape``) and ``meta.json`` (``adc_resolution``
and the device description); the folder itself may hold a ``meta.json`` of the capture.
:func:`read_recording` checks all of it and gives the ADC cube in the simulator's units
and layout; :func:`recording_levels` measures it the way ``../shared/real/README.md``
describes (the calibration of ``docs/physics_radar.md``); :func:`convert_recording` writes
it as a dataset (``docs/dataset.md``, "Converted recordings").

ADC codes become fractions of the full scale as the simulator writes them:
``(code − 2^(b−1)) / 2^(b−1)`` for a ``b``-bit ADC (code 2048 of a 12-bit ADC is 0, code 0
is −1, code 4095 is 2047/2048).
"""

from __future__ import annotations

import json
import math
import os
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from simcore.scene.radar_config import SPEED_OF_LIGHT, RadarConfig

#: Keys of ``device_config.fmcw_single_shape`` and their types (all required).
SINGLE_SHAPE_KEYS: dict[str, type | tuple[type, ...]] = {
    "aaf_cutoff_Hz": (int, float),
    "chirp_repetition_time_s": (int, float),
    "end_frequency_Hz": (int, float),
    "frame_repetition_time_s": (int, float),
    "hp_cutoff_Hz": (int, float),
    "if_gain_dB": (int, float),
    "mimo_mode": str,
    "num_chirps_per_frame": int,
    "num_samples_per_chirp": int,
    "rx_antennas": list,
    "sample_rate_Hz": (int, float),
    "start_frequency_Hz": (int, float),
    "tx_antennas": list,
    "tx_power_level": int,
}
_KIND_NAMES: dict[type | tuple[type, ...], str] = {
    (int, float): "a number", int: "an integer", str: "a string", list: "a list"}
#: MIMO modes of a single-shape configuration: one Tx, or Tx in turn (TDM).
MIMO_MODES = ("off", "tdm")
#: ADC resolution assumed when ``meta.json`` does not give one (the BGT60TR13C's).
DEFAULT_ADC_BITS = 12
#: Radar stream folders of a Radar Fusion GUI recording.
STREAM_GLOB = "RadarIfxAvian_*"


class RecordingError(ValueError):
    """A recording that cannot be read: the message names the file and what is wrong."""


@dataclass(frozen=True)
class RadarRecording:
    """A radar recording read from disk.

    Attributes
    ----------
    folder : Path
        The stream folder (``RadarIfxAvian_<nn>``).
    settings : dict
        ``device_config.fmcw_single_shape`` as recorded.
    device_meta, capture_meta : dict
        The stream's and the capture's ``meta.json`` (empty when absent).
    adc_bits : int
        ADC resolution (bits).
    codes : ndarray, shape (frames, channels, chirps, samples), uint16
        The raw codes (memory-mapped).
    config : RadarConfig
        A radar that reproduces the recording's configuration
        (:func:`simcore.scene.radar_presets.bgt60tr13c_from_device`).
    """

    folder: Path
    settings: dict[str, Any]
    device_meta: dict[str, Any]
    capture_meta: dict[str, Any]
    adc_bits: int
    codes: NDArray[np.uint16]
    config: RadarConfig

    @property
    def n_frames(self) -> int:
        """Number of frames."""
        return int(self.codes.shape[0])

    @property
    def frame_repetition_time_s(self) -> float:
        """Time between frame starts (s)."""
        return float(self.settings["frame_repetition_time_s"])

    def frame_times_s(self) -> NDArray[np.float64]:
        """Frame timestamps ``k · frame_repetition_time_s``, shape (frames,), s."""
        return np.arange(self.n_frames, dtype=np.float64) * self.frame_repetition_time_s

    def frame_adc(self, index: int) -> NDArray[np.float32]:
        """Frame ``index`` in FS, shape (chirps, channels, samples), float32."""
        return codes_to_fs(np.asarray(self.codes[index]), self.adc_bits).transpose(1, 0, 2)

    def adc(self) -> NDArray[np.float32]:
        """All frames in FS, shape (frames, chirps, channels, samples), float32."""
        return codes_to_fs(np.asarray(self.codes), self.adc_bits).transpose(0, 2, 1, 3)


def codes_to_fs(codes: NDArray[np.integer], bits: int) -> NDArray[np.float32]:
    """Offset-binary ADC codes → fractions of the full scale, ``(code − 2^(b−1)) / 2^(b−1)``.

    Examples
    --------
    >>> codes_to_fs(np.array([0, 2048, 4095], dtype=np.uint16), 12).tolist()
    [-1.0, 0.0, 0.99951171875]
    """
    half = float(2 ** (bits - 1))
    return ((np.asarray(codes, dtype=np.float32) - half) / half).astype(np.float32)


def fs_to_codes(adc_fs: NDArray[np.floating], bits: int) -> NDArray[np.uint16]:
    """Inverse of :func:`codes_to_fs` (rounded, clipped to the code range)."""
    half = 2 ** (bits - 1)
    codes = np.clip(np.rint(np.asarray(adc_fs, dtype=np.float64) * half) + half, 0, 2 * half - 1)
    return codes.astype(np.uint16)


def _read_json(path: Path) -> dict[str, Any]:
    try:
        text = path.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise RecordingError(f"{path}: missing") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise RecordingError(f"{path}: cannot be read ({exc})") from None
    try:
        data = json.loads(text)
    except json.JSONDecodeError as exc:
        raise RecordingError(f"{path}: not valid JSON ({exc.msg} at line {exc.lineno})"
                             ) from None
    if not isinstance(data, dict):
        raise RecordingError(f"{path}: expected a JSON object, got {type(data).__name__}")
    return data


def stream_folder(path: str | os.PathLike[str]) -> Path:
    """The radar stream folder of a recording (the recording folder or the stream itself)."""
    p = Path(path)
    if not p.is_dir():
        raise RecordingError(f"{p}: no such recording folder")
    if (p / "radar.npy").exists() or (p / "config.json").exists():
        return p
    streams = sorted(q for q in p.glob(STREAM_GLOB) if q.is_dir())
    if not streams:
        raise RecordingError(f"{p}: no {STREAM_GLOB} folder with radar.npy and config.json "
                             "(not a Radar Fusion GUI recording)")
    if len(streams) > 1:
        raise RecordingError(f"{p}: {len(streams)} radar streams "
                             f"({', '.join(q.name for q in streams)}); pass one of them")
    return streams[0]


def check_settings(settings: Any, source: Path) -> dict[str, Any]:
    """Validate ``fmcw_single_shape``: known keys only, all present, types and values sane."""
    if not isinstance(settings, dict):
        raise RecordingError(f"{source}: device_config.fmcw_single_shape must be an object")
    unknown = sorted(set(settings) - set(SINGLE_SHAPE_KEYS))
    if unknown:
        raise RecordingError(f"{source}: unknown fmcw_single_shape keys {unknown}; known: "
                             f"{sorted(SINGLE_SHAPE_KEYS)}")
    missing = sorted(set(SINGLE_SHAPE_KEYS) - set(settings))
    if missing:
        raise RecordingError(f"{source}: fmcw_single_shape lacks {missing}")
    for key, kind in SINGLE_SHAPE_KEYS.items():
        value = settings[key]
        if isinstance(value, bool) or not isinstance(value, kind):
            raise RecordingError(f"{source}: {key} = {value!r} is not {_KIND_NAMES[kind]}")
        if isinstance(value, float) and not math.isfinite(value):
            raise RecordingError(f"{source}: {key} = {value!r} is not finite")
    for key in ("rx_antennas", "tx_antennas"):
        ants = settings[key]
        if not ants or any(isinstance(a, bool) or not isinstance(a, int) or a < 1 for a in ants) \
                or len(set(ants)) != len(ants):
            raise RecordingError(f"{source}: {key} = {ants!r}; expected distinct antenna "
                                 "numbers from 1")
    if settings["mimo_mode"] not in MIMO_MODES:
        raise RecordingError(f"{source}: mimo_mode = {settings['mimo_mode']!r}; expected one "
                             f"of {list(MIMO_MODES)}")
    if settings["mimo_mode"] == "off" and len(settings["tx_antennas"]) != 1:
        raise RecordingError(f"{source}: mimo_mode 'off' transmits on one antenna, but "
                             f"tx_antennas = {settings['tx_antennas']}")
    for key in ("num_chirps_per_frame", "num_samples_per_chirp"):
        if settings[key] < 1:
            raise RecordingError(f"{source}: {key} = {settings[key]} must be at least 1")
    for key in ("frame_repetition_time_s", "chirp_repetition_time_s", "sample_rate_Hz"):
        if settings[key] <= 0:
            raise RecordingError(f"{source}: {key} = {settings[key]} must be positive")
    return dict(settings)


def _load_codes(path: Path, settings: dict[str, Any], bits: int) -> NDArray[np.uint16]:
    """``radar.npy`` memory-mapped, its dtype, shape and code range checked."""
    try:
        codes = np.load(path, mmap_mode="r", allow_pickle=False)
    except FileNotFoundError:
        raise RecordingError(f"{path}: missing") from None
    except (ValueError, OSError, EOFError) as exc:
        raise RecordingError(f"{path}: not a complete .npy array ({exc}); truncated or "
                             "damaged") from None
    if codes.dtype != np.uint16:
        raise RecordingError(f"{path}: dtype {codes.dtype}; expected uint16 ADC codes")
    n_ch = len(settings["rx_antennas"]) * (len(settings["tx_antennas"])
                                            if settings["mimo_mode"] == "tdm" else 1)
    expect = (n_ch, settings["num_chirps_per_frame"], settings["num_samples_per_chirp"])
    if codes.ndim != 4 or tuple(codes.shape[1:]) != expect or codes.shape[0] < 1:
        raise RecordingError(
            f"{path}: shape {tuple(codes.shape)}; config.json describes (frames, channels, "
            f"chirps, samples) = (N, {expect[0]}, {expect[1]}, {expect[2]})")
    top = int(codes.max())
    if top >= 2**bits:
        raise RecordingError(f"{path}: code {top} outside the {bits}-bit ADC range "
                             f"0…{2**bits - 1}")
    return codes


def read_recording(path: str | os.PathLike[str]) -> RadarRecording:
    """Read and check a Radar Fusion GUI / ifxdaq recording.

    Parameters
    ----------
    path : path-like
        The recording folder (holding ``RadarIfxAvian_<nn>/``) or the stream folder.

    Returns
    -------
    RadarRecording

    Raises
    ------
    RecordingError
        One sentence naming the file and what is wrong: a missing or malformed
        ``config.json``, unknown or inconsistent keys, an array whose dtype or shape
        disagrees with the configuration, a truncated ``radar.npy``, codes outside the ADC
        range.
    """
    from pydantic import ValidationError

    from simcore.scene.project_io import format_validation_error
    from simcore.scene.radar_presets import bgt60tr13c_from_device

    folder = stream_folder(path)
    cfg_path = folder / "config.json"
    doc = _read_json(cfg_path)
    unknown = sorted(set(doc) - {"device_config"})
    if unknown or not isinstance(doc.get("device_config"), dict):
        raise RecordingError(f"{cfg_path}: expected {{'device_config': "
                             f"{{'fmcw_single_shape': …}}}}, got keys {sorted(doc)}")
    shapes = sorted(doc["device_config"])
    if shapes != ["fmcw_single_shape"]:
        raise RecordingError(f"{cfg_path}: device_config holds {shapes}; only "
                             "fmcw_single_shape is supported")
    settings = check_settings(doc["device_config"]["fmcw_single_shape"], cfg_path)
    device_meta = _read_json(folder / "meta.json") if (folder / "meta.json").exists() else {}
    bits = device_meta.get("adc_resolution", DEFAULT_ADC_BITS)
    if isinstance(bits, bool) or not isinstance(bits, int) or not 1 <= bits <= 16:
        raise RecordingError(f"{folder / 'meta.json'}: adc_resolution = {bits!r}; expected "
                             "1…16 bits")
    capture = folder.parent / "meta.json"
    capture_meta = _read_json(capture) if capture.exists() else {}
    try:
        config = bgt60tr13c_from_device(settings, adc_bits=bits)
    except ValidationError as exc:
        raise RecordingError(f"{cfg_path}: the radar it describes is not valid: "
                             f"{'; '.join(format_validation_error(exc))}") from None
    except ValueError as exc:
        raise RecordingError(f"{cfg_path}: {' '.join(str(exc).split())}") from None
    codes = _load_codes(folder / "radar.npy", settings, bits)
    return RadarRecording(folder, settings, device_meta, capture_meta, bits, codes, config)


# ----------------------------------------------------------------------- measurement
def range_profile_dbfs(adc_fs: NDArray[np.floating]) -> NDArray[np.float64]:
    """Mean power range profile in dBFS, measured as ``../shared/real/README.md`` says.

    Per chirp: mean removed, a symmetric Hann window (``numpy.hanning``) normalised so
    that a full-scale sine reads 0 dBFS (``2 / Σw``), real FFT; power averaged over every
    other axis (frames, chirps, channels).

    Parameters
    ----------
    adc_fs : ndarray, shape (..., samples)
        Real ADC samples in FS.

    Returns
    -------
    ndarray, shape (samples // 2 + 1,)
        Power per range bin (dBFS); bin ``k`` is at beat frequency ``k f_s / samples``.
    """
    x = np.asarray(adc_fs, dtype=np.float64)
    x = x - x.mean(axis=-1, keepdims=True)
    w = np.hanning(x.shape[-1])
    spec = np.fft.rfft(x * w, axis=-1) * (2.0 / w.sum())
    power = np.mean(np.abs(spec.reshape(-1, spec.shape[-1])) ** 2, axis=0)
    return np.asarray(10.0 * np.log10(np.maximum(power, 1e-30)), dtype=np.float64)


def per_sample_noise_dbfs(adc_fs: NDArray[np.floating], *, chirp_axis: int = 1) -> float:
    """RMS of the chirp-to-chirp difference / √2 (dBFS): the noise, static returns removed.

    Each chirp's mean is removed first (as for the range profile), so a DC offset that
    drifts from chirp to chirp does not count.

    Parameters
    ----------
    adc_fs : ndarray, shape (frames, chirps, channels, samples)
        ADC samples in FS (at least two chirps).
    chirp_axis : int
        The chirp axis.
    """
    x = np.asarray(adc_fs, dtype=np.float64)
    d = np.diff(x - x.mean(axis=-1, keepdims=True), axis=chirp_axis) / math.sqrt(2.0)
    return float(10.0 * np.log10(max(float(np.mean(d**2)), 1e-30)))


@dataclass(frozen=True)
class RecordingLevels:
    """The levels of ``../shared/real/README.md`` (dBFS), and the profile they come from.

    Attributes
    ----------
    range_m : ndarray, shape (bins,)
        Range of each bin (m).
    profile_dbfs : ndarray, shape (bins,)
        :func:`range_profile_dbfs`.
    leakage_dbfs : tuple of float
        Bins 0, 1, 2 (the Tx→Rx leakage).
    target_dbfs : float
        The bin nearest ``target_range_m``.
    floor_beyond_aaf_dbfs : tuple of float
        Lowest and highest bin in ``beyond_aaf_m`` (beyond the anti-aliasing filter).
    floor_beyond_aaf_mean_dbfs, floor_in_band_dbfs : float
        Mean power (dB of the mean) over ``beyond_aaf_m`` and over ``in_band_m``.
    per_sample_noise_dbfs : float
        :func:`per_sample_noise_dbfs`.
    """

    range_m: NDArray[np.float64]
    profile_dbfs: NDArray[np.float64]
    leakage_dbfs: tuple[float, float, float]
    target_dbfs: float
    floor_beyond_aaf_dbfs: tuple[float, float]
    floor_beyond_aaf_mean_dbfs: float
    floor_in_band_dbfs: float
    per_sample_noise_dbfs: float

    def table(self) -> dict[str, float]:
        """The figures by name (dBFS)."""
        return {"leakage bin 0": self.leakage_dbfs[0], "leakage bin 1": self.leakage_dbfs[1],
                "leakage bin 2": self.leakage_dbfs[2], "target": self.target_dbfs,
                "floor beyond AAF (mean)": self.floor_beyond_aaf_mean_dbfs,
                "floor in band (mean)": self.floor_in_band_dbfs,
                "per-sample noise": self.per_sample_noise_dbfs}


def _band_mean_db(profile: NDArray[np.float64], mask: NDArray[np.bool_]) -> float:
    return float(10.0 * np.log10(np.mean(10.0 ** (profile[mask] / 10.0))))


def recording_levels(adc_fs: NDArray[np.floating], config: RadarConfig, *,
                     target_range_m: float = 0.33,
                     beyond_aaf_m: tuple[float, float] = (0.70, 0.87),
                     in_band_m: tuple[float, float] = (0.16, 0.25)) -> RecordingLevels:
    """Measure leakage, target, noise floors and per-sample noise of real-IF ADC frames.

    Parameters
    ----------
    adc_fs : ndarray, shape (frames, chirps, channels, samples)
        Real ADC samples in FS (a recording's :meth:`RadarRecording.adc`, or simulated
        frames stacked).
    config : RadarConfig
        The radar (sample rate and chirp slope give each bin's range).
    target_range_m : float
        Range of the target bin (m).
    beyond_aaf_m, in_band_m : tuple of float
        Range intervals (m) of the two noise floors (bins whose centre lies inside).

    Returns
    -------
    RecordingLevels
    """
    x = np.asarray(adc_fs)
    if x.ndim != 4 or x.shape[1] < 2 or np.iscomplexobj(x):
        raise ValueError(f"expected real frames (frames, chirps ≥ 2, channels, samples), got "
                         f"shape {x.shape}")
    profile = range_profile_dbfs(x)
    n = x.shape[-1]
    bin_m = config.sample_rate_hz / n * SPEED_OF_LIGHT / (2.0 * config.slope_hz_per_s)
    r = np.arange(profile.size) * bin_m
    beyond = (r >= beyond_aaf_m[0]) & (r <= beyond_aaf_m[1])
    band = (r >= in_band_m[0]) & (r <= in_band_m[1])
    if not beyond.any() or not band.any():
        raise ValueError(f"the range bins ({bin_m * 100:.2f} cm up to {r[-1]:.2f} m) miss "
                         f"{beyond_aaf_m} m or {in_band_m} m")
    k = int(np.argmin(np.abs(r - target_range_m)))
    return RecordingLevels(
        range_m=r, profile_dbfs=profile,
        leakage_dbfs=(float(profile[0]), float(profile[1]), float(profile[2])),
        target_dbfs=float(profile[k]),
        floor_beyond_aaf_dbfs=(float(profile[beyond].min()), float(profile[beyond].max())),
        floor_beyond_aaf_mean_dbfs=_band_mean_db(profile, beyond),
        floor_in_band_dbfs=_band_mean_db(profile, band),
        per_sample_noise_dbfs=per_sample_noise_dbfs(x))


# ----------------------------------------------------------------------- conversion
@dataclass(frozen=True)
class ConvertReport:
    """What :func:`convert_recording` wrote: frames, the dataset and the project (or None)."""

    n_frames: int
    dataset: Path
    project: Path | None


def recording_project(recording: RadarRecording, *, name: str | None = None) -> Any:
    """A project whose radar reproduces the recording: empty scene, its frame timing.

    Returns
    -------
    simcore.scene.model.Project
        A radar-only rig: ``rig.radar`` = :attr:`RadarRecording.config`, no ToF camera;
        timeline at ``1 / frame_repetition_time_s`` over the recording's frames; no
        objects.
    """
    from simcore.scene.model import Project, SensorRig, Timeline

    t_f = recording.frame_repetition_time_s
    return Project(
        name=name or recording.folder.parent.name,
        description=f"reproduces the radar configuration of the recording "
                    f"{recording.folder.parent.name}/{recording.folder.name} "
                    "(tofradar convert --project); the scene is empty",
        timeline=Timeline(frame_rate_hz=1.0 / t_f, duration_s=recording.n_frames * t_f),
        rig=SensorRig(tof=None, radar=recording.config))


def convert_recording(source: str | os.PathLike[str], out: str | os.PathLike[str], *,
                      project_out: str | os.PathLike[str] | None = None,
                      overwrite: bool = False) -> ConvertReport:
    """Write a recording as a dataset of the simulator's layout (``docs/dataset.md``).

    Per frame: ``/time`` (``k · frame_repetition_time_s``), ``/radar/adc`` (FS, float32,
    (chirps, channels, samples)), ``/radar/chirp_start_time`` and the products of
    :func:`simcore.dsp.process_frame` with the project's default DSP; ``/meta`` holds the
    project (:func:`recording_project`), ``source = "recording"``, the recording's
    ``config.json`` and ``meta.json`` files and the code conversion.

    Parameters
    ----------
    source : path-like
        Recording folder (:func:`read_recording`).
    out : path-like
        Output HDF5 file.
    project_out : path-like, optional
        Also save the project there (JSON).
    overwrite : bool
        Replace existing output files.
    """
    from simcore.dsp import process_frame, static_axes_items
    from simcore.io.hdf5_writer import DatasetExistsError, DatasetWriter
    from simcore.scene.project_io import project_to_json, save_project
    from simcore.sensors.schema import schema_of

    rec = read_recording(source)
    project = recording_project(rec)
    if project_out is not None and Path(project_out).exists() and not overwrite:
        raise DatasetExistsError(f"{project_out} already exists; use --overwrite to replace it")
    (radar, cfg), = project.sensors_of_kind("radar").items()
    dsp = project.dsp
    schema = schema_of("radar")
    meta = {"source": "recording", "recording_path": str(Path(source).resolve()),
            "recording_config": json.dumps({"device_config": {"fmcw_single_shape":
                                                              rec.settings}}),
            "recording_meta": json.dumps({"device": rec.device_meta,
                                          "capture": rec.capture_meta}),
            "adc_conversion": f"(code - {2 ** (rec.adc_bits - 1)}) / "
                              f"{2 ** (rec.adc_bits - 1)} ({rec.adc_bits}-bit offset binary)"}
    times = rec.frame_times_s()
    starts = cfg.chirp_start_times_s()
    with DatasetWriter(out, project_json=project_to_json(project), seed=project.seed,
                       overwrite=overwrite, extra_meta=meta) as writer:
        writer.write_static(static_axes_items(cfg, dsp, group=radar))
        for k in range(rec.n_frames):
            adc = rec.frame_adc(k)
            products = process_frame(adc, cfg, dsp)
            writer.append_rows(schema.dataset_path(radar, "detections"),
                               products.detection_records(k))
            writer.append({"/time": (np.asarray(times[k]), "s"),
                           schema.dataset_path(radar, "adc"): (adc, "FS"),
                           schema.dataset_path(radar, "chirp_start_time"): (times[k] + starts,
                                                                            "s"),
                           **products.hdf5_items(group=radar)})
    if project_out is not None:
        save_project(project, project_out)
    return ConvertReport(rec.n_frames, Path(out), None if project_out is None
                         else Path(project_out))


__all__ = ["ConvertReport", "RadarRecording", "RecordingError", "RecordingLevels",
           "codes_to_fs", "convert_recording", "fs_to_codes", "per_sample_noise_dbfs",
           "range_profile_dbfs", "read_recording", "recording_levels", "recording_project"]
