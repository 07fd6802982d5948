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

from simcore.preflight import MAX_FRAMES
from simcore.scene.files import InputFileError, check_regular_file, is_inside, read_json_file
from simcore.scene.limits import (
    MAX_RECORDING_ARRAY_BYTES,
    MAX_RECORDING_FRAME_BYTES,
    MAX_RECORDING_FRAME_TIME_S,
    MAX_RECORDING_JSON_BYTES,
    MIN_RECORDING_FRAME_TIME_S,
)
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


def _read_json(path: Path, root: Path | None = None, *,
               allow_outside_paths: bool = False) -> dict[str, Any]:
    """A recording's JSON part: a regular file inside ``root``, at most 1 MiB, an object."""
    _check_part(path, root, allow_outside_paths=allow_outside_paths)
    try:
        data = read_json_file(path, max_bytes=MAX_RECORDING_JSON_BYTES, label=str(path))
    except InputFileError as exc:
        if exc.missing:
            raise RecordingError(f"{path}: missing") from None
        raise RecordingError(str(exc)) from None
    if not isinstance(data, dict):
        raise RecordingError(f"{path}: expected a JSON object, got {type(data).__name__}")
    return data


def _check_part(path: Path, root: Path | None, *, allow_outside_paths: bool) -> None:
    """Refuse a part that leads outside the recording's folder (symlinks resolved).

    Unless ``allow_outside_paths``: the path policy of every referenced file.
    """
    if root is None or allow_outside_paths:
        return
    try:
        real = path.resolve()
    except (OSError, RuntimeError):
        raise RecordingError(f"{path}: symlink loop") from None
    if real.exists() and not is_inside(real, root):
        raise RecordingError(f"{path}: resolves to {real}, outside the recording folder "
                             f"{root} (pass --allow-outside-paths to accept it)")


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
    t_f = settings["frame_repetition_time_s"]
    if not MIN_RECORDING_FRAME_TIME_S <= t_f <= MAX_RECORDING_FRAME_TIME_S:
        raise RecordingError(f"{source}: frame_repetition_time_s = {t_f:g} s; allowed "
                             f"{MIN_RECORDING_FRAME_TIME_S:g}–{MAX_RECORDING_FRAME_TIME_S:g} s")
    chirps_s = settings["num_chirps_per_frame"] * settings["chirp_repetition_time_s"]
    if chirps_s > t_f:
        raise RecordingError(f"{source}: frame_repetition_time_s = {t_f:g} s is shorter than "
                             f"its {settings['num_chirps_per_frame']} chirps of "
                             f"{settings['chirp_repetition_time_s']:g} s ({chirps_s:g} s)")
    return dict(settings)


def _npy_header(path: Path) -> tuple[tuple[int, ...], np.dtype[Any], bool, int]:
    """Shape, dtype, Fortran order and data offset of a ``.npy`` file (a regular file)."""
    try:
        real, _ = check_regular_file(path, max_bytes=MAX_RECORDING_ARRAY_BYTES, label=str(path))
    except InputFileError as exc:
        if exc.missing:
            raise RecordingError(f"{path}: missing") from None
        raise RecordingError(str(exc)) from None
    fd = os.open(real, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0))
    with os.fdopen(fd, "rb") as fh:
        try:
            version = np.lib.format.read_magic(fh)
            if version == (1, 0):
                shape, fortran, dtype = np.lib.format.read_array_header_1_0(fh)
            elif version in ((2, 0), (3, 0)):
                shape, fortran, dtype = np.lib.format.read_array_header_2_0(fh)
            else:
                raise ValueError(f"unsupported .npy version {version}")
        except (ValueError, OSError, EOFError, SyntaxError) as exc:
            raise RecordingError(f"{path}: not a .npy array ({' '.join(str(exc).split())[:160]})"
                                 "; truncated or damaged") from None
        return tuple(shape), np.dtype(dtype), bool(fortran), fh.tell()


def _load_codes(path: Path, settings: dict[str, Any], bits: int) -> NDArray[np.uint16]:
    """``radar.npy`` memory-mapped, its header, size and code range checked first."""
    shape, dtype, fortran, offset = _npy_header(path)
    if dtype.hasobject:
        raise RecordingError(f"{path}: holds Python objects (pickled); expected uint16 ADC "
                             "codes")
    if dtype != np.uint16:
        raise RecordingError(f"{path}: dtype {dtype}; expected uint16 ADC codes")
    n_ch = len(settings["rx_antennas"]) * (len(settings["tx_antennas"])
                                            if settings["mimo_mode"] == "tdm" else 1)
    expect = (n_ch, settings["num_chirps_per_frame"], settings["num_samples_per_chirp"])
    if len(shape) != 4 or tuple(shape[1:]) != expect or shape[0] < 1 or fortran:
        raise RecordingError(
            f"{path}: shape {tuple(shape)}{' (Fortran order)' if fortran else ''}; "
            f"config.json describes (frames, channels, chirps, samples) = "
            f"(N, {expect[0]}, {expect[1]}, {expect[2]}) in C order")
    if shape[0] > MAX_FRAMES:
        raise RecordingError(f"{path}: {shape[0]} frames; allowed at most {MAX_FRAMES}")
    need = offset + math.prod(shape) * dtype.itemsize
    size = path.stat().st_size
    if size < need:
        raise RecordingError(f"{path}: {size} bytes, but its header describes {need} "
                             f"({shape[0]} frames); truncated or damaged")
    codes = np.memmap(path, dtype=dtype, mode="r", offset=offset, shape=shape)
    top = max(int(codes[k].max()) for k in range(shape[0]))
    if top >= 2**bits:
        raise RecordingError(f"{path}: code {top} outside the {bits}-bit ADC range "
                             f"0…{2**bits - 1}")
    return codes


def _check_cost(config: RadarConfig, cfg_path: Path) -> None:
    """Refuse a recording whose one frame would not fit the conversion's memory budget."""
    from simcore.preflight import estimate_cost
    from simcore.scene.model import Project, SensorRig

    cost = estimate_cost(Project(rig=SensorRig(radar=config)))
    if cost.memory_bytes > MAX_RECORDING_FRAME_BYTES:
        field, part = cost.memory_parts[0]
        raise RecordingError(
            f"{cfg_path}: converting one frame of {config.chirps_per_frame} chirps × "
            f"{config.samples_per_chirp} samples would need ≈ {cost.memory_bytes / 2**30:.2f} "
            f"GiB ({part / 2**30:.2f} GiB for {field}); the budget is "
            f"{MAX_RECORDING_FRAME_BYTES / 2**30:g} GiB")


def read_recording(path: str | os.PathLike[str], *,
                   allow_outside_paths: bool = False) -> RadarRecording:
    """Read and check a Radar Fusion GUI / ifxdaq recording.

    Parameters
    ----------
    path : path-like
        The recording folder (holding ``RadarIfxAvian_<nn>/``) or the stream folder.
    allow_outside_paths : bool
        Accept parts (``radar.npy``, ``config.json``, ``meta.json``) that are symlinks to
        files outside the recording folder.

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
    root = Path(path).resolve()
    policy = {"allow_outside_paths": allow_outside_paths}
    cfg_path = folder / "config.json"
    doc = _read_json(cfg_path, root, **policy)
    unknown = sorted(set(doc) - {"device_config"})
    if unknown or not isinstance(doc.get("device_config"), dict):
        raise RecordingError(f"{cfg_path}: expected {{'device_config': "
                             f"{{'fmcw_single_shape': …}}}}, got keys {sorted(doc)}")
    shapes = sorted(doc["device_config"])
    if shapes != ["fmcw_single_shape"]:
        raise RecordingError(f"{cfg_path}: device_config holds {shapes}; only "
                             "fmcw_single_shape is supported")
    settings = check_settings(doc["device_config"]["fmcw_single_shape"], cfg_path)
    device_meta = (_read_json(folder / "meta.json", root, **policy)
                   if _present(folder / "meta.json") else {})
    bits = device_meta.get("adc_resolution", DEFAULT_ADC_BITS)
    if isinstance(bits, bool) or not isinstance(bits, int) or not 1 <= bits <= 16:
        raise RecordingError(f"{folder / 'meta.json'}: adc_resolution = {bits!r}; expected "
                             "1…16 bits")
    capture = folder.parent / "meta.json"
    capture_meta = (_read_json(capture, root if capture.parent == root else capture.parent,
                               **policy) if _present(capture) else {})
    try:
        config = bgt60tr13c_from_device(settings, adc_bits=bits)
    except ValidationError as exc:
        raise RecordingError(f"{cfg_path}: the radar it describes is not valid: "
                             f"{'; '.join(format_validation_error(exc))}") from None
    except ValueError as exc:
        raise RecordingError(f"{cfg_path}: {' '.join(str(exc).split())}") from None
    _check_cost(config, cfg_path)
    _check_part(folder / "radar.npy", root, **policy)
    codes = _load_codes(folder / "radar.npy", settings, bits)
    return RadarRecording(folder, settings, device_meta, capture_meta, bits, codes, config)


def _present(path: Path) -> bool:
    """Whether ``path`` exists as anything (a dangling symlink counts: it is reported)."""
    return path.is_symlink() or path.exists()


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
                      overwrite: bool = False,
                      allow_outside_paths: bool = False) -> ConvertReport:
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
    allow_outside_paths : bool
        Accept recording parts that lead outside the recording folder.

    The recording, the project it gives (its timeline passes the pre-run checks) and the
    folders the outputs go to are checked before the dataset is started (``tofradar
    convert`` also removes a dataset it began when a later step fails).
    """
    from simcore.dsp import process_frame, static_axes_items
    from simcore.io.hdf5_writer import DatasetExistsError, DatasetWriter
    from simcore.scene.project_io import project_to_json, save_project
    from simcore.sensors.schema import schema_of

    rec = read_recording(source, allow_outside_paths=allow_outside_paths)
    project = _checked_project(rec)
    if project_out is not None and Path(project_out).exists() and not overwrite:
        raise DatasetExistsError(f"{project_out} already exists; use --overwrite to replace it")
    for target, what in ((Path(out), "--to"), (Path(project_out or out), "--project")):
        _check_writable(target, what)
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


def _checked_project(rec: RadarRecording) -> Any:
    """The recording's project, refused unless its timeline passes the pre-run checks."""
    from pydantic import ValidationError

    from simcore.preflight import check
    from simcore.scene.project_io import format_validation_error

    where = rec.folder / "config.json"
    try:
        project = recording_project(rec)
    except ValidationError as exc:
        raise RecordingError(f"{where}: the project it gives is not valid: "
                             f"{'; '.join(format_validation_error(exc))}") from None
    # The converted scene is empty by design; every other pre-run check applies.
    problems = [p for p in check(project, n_frames=rec.n_frames, parse_meshes=False,
                                 memory_budget_bytes=2**63)
                if not p.startswith("objects:")]
    if problems:
        raise RecordingError(f"{where}: the project it gives would not run: {problems[0]}")
    return project


def _check_writable(target: Path, what: str) -> None:
    """Refuse an output whose folder is missing or not writable, before anything is written."""
    folder = target.parent if str(target.parent) else Path(".")
    if target.is_dir():
        raise RecordingError(f"{what} {target}: is a folder; give a file name")
    if not folder.is_dir():
        raise RecordingError(f"{what} {target}: the folder {folder} does not exist")
    import tempfile

    try:    # a file made and removed: permissions, ACLs and read-only mounts alike
        fd, probe = tempfile.mkstemp(dir=folder, prefix=".tofradar-probe-")
        os.close(fd)
        os.unlink(probe)
    except OSError as exc:
        raise RecordingError(f"{what} {target}: cannot write into {folder} "
                             f"({exc.strerror})") from None


__all__ = ["ConvertReport", "RadarRecording", "RecordingError", "RecordingLevels",
           "codes_to_fs", "convert_recording", "fs_to_codes", "per_sample_noise_dbfs",
           "range_profile_dbfs", "read_recording", "recording_levels", "recording_project"]
