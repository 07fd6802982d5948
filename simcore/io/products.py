"""Post-processing of a finished dataset: micro-Doppler spectrogram and vital signs.

:func:`write_radar_products` reads one radar's raw ADC cubes (``/<radar>/adc``), their
true chirp times (``/<radar>/chirp_start_time``) and the project stored in the file, runs
:mod:`simcore.dsp.microdoppler` and :mod:`simcore.dsp.vitals` with the project's DSP
options and the radar's own configuration, and writes two groups into the same file
(replacing earlier ones); :func:`write_all_radar_products` does so for every radar with ADC
data. The built-in radar is ``radar``, so its groups are ``/radar/spectrogram`` and
``/radar/vitals`` as before; a radar named ``rear`` has ``/rear/spectrogram`` and
``/rear/vitals``. A radar slower than the timeline (``/<radar>/captured``) uses the frames it
captured in; its vitals keep one value per frame of the dataset, NaN where it did not
capture.

``/<radar>/spectrogram``
    ``power`` (columns, doppler) float32 dB, ``time`` (columns,) s, ``velocity_axis``
    (doppler,) m/s (positive = moving away); attributes ``mode``, ``window``,
    ``range_min_m``, ``range_max_m`` (the gate; per-frame gates around an object are
    listed in ``gate_center`` (N,) m).
``/<radar>/vitals``
    ``displacement`` (N,) m (the chest bin's phase displacement over the whole run),
    ``breathing_rate``, ``heart_rate`` (N,) Hz and ``breathing_amplitude``,
    ``heart_amplitude`` (N,) m: estimates over the last ``vitals_window_s`` seconds at
    each frame (NaN until that much data exists); attributes ``range_bin``, ``range_m``
    and the whole-run estimates ``breathing_rate_hz``, ``breathing_amplitude_m``,
    ``heart_rate_hz``, ``heart_amplitude_m``.

The cubes are read one frame at a time; what is kept grows with frames × (range bins +
gate bins × chirps × channels), not with the whole cube.
"""

from __future__ import annotations

import json
import os
from dataclasses import dataclass
from typing import Any

import h5py
import numpy as np
from numpy.typing import NDArray

from simcore.dsp.microdoppler import (
    OBJECT_GATE_HALF_WIDTH_M,
    Spectrogram,
    frame_spectrogram,
    gate_bins,
    gate_slow_time,
    stft_spectrogram,
)
from simcore.dsp.processing import radar_axes
from simcore.dsp.spectrum import range_fft
from simcore.dsp.vitals import VitalSigns, estimate_vital_signs, select_vital_bin
from simcore.scene.dsp_config import DspConfig
from simcore.scene.model import Project
from simcore.scene.project_io import project_from_dict
from simcore.scene.radar_config import RadarConfig


class ProductsError(ValueError):
    """The dataset cannot give these products (missing arrays, too few frames)."""


@dataclass(frozen=True)
class RadarProductsSummary:
    """What :func:`write_radar_products` computed.

    Attributes
    ----------
    spectrogram : Spectrogram
        The micro-Doppler spectrogram.
    vitals : VitalSigns or None
        Whole-run vital-sign estimate (None with fewer than 8 frames).
    range_m : float
        Range of the chest bin used for the vital signs (m).
    """

    spectrogram: Spectrogram
    vitals: VitalSigns | None
    range_m: float


def _require(f: h5py.File, path: str) -> h5py.Dataset:
    if path not in f or not isinstance(f[path], h5py.Dataset):
        raise ProductsError(f"{f.filename}: no {path} (run with the radar's ADC output)")
    return f[path]


def _object_range(f: h5py.File, name: str, radar: str) -> NDArray[np.float64]:
    """Object ``name``'s true range from ``radar``, every frame (m).

    The built-in radar's is ``/objects/radar_range``, another radar's
    ``/objects/<radar>/range``.
    """
    truth = "/objects/radar_range" if radar == "radar" else f"/objects/{radar}/range"
    if "/objects/names" not in f or truth not in f:
        raise ProductsError(f"{f.filename}: no object {name!r}: the dataset has no "
                            f"/objects/names and {truth}")
    names = [n.decode() if isinstance(n, bytes) else str(n) for n in f["/objects/names"][()]]
    if name not in names:
        raise ProductsError(f"{f.filename}: no object {name!r} (objects: {', '.join(names)})")
    return np.asarray(f[truth][:, names.index(name)], dtype=np.float64)


def _captured_rows(f: h5py.File, radar: str, n_rows: int) -> tuple[NDArray[np.intp],
                                                                   NDArray[np.intp]]:
    """(rows of the radar's arrays, their frames) of the frames the radar captured in.

    A radar slower than the timeline has ``/<radar>/captured`` (one flag per frame); its
    arrays hold a row per frame (rows of the frames it captured in are used) or a row per
    capture (all are).
    """
    path = f"/{radar}/captured"
    rows = np.arange(n_rows)
    if path not in f:
        return rows, rows
    captured = np.asarray(f[path][()], dtype=bool).ravel()
    frames = np.flatnonzero(captured)
    if captured.size == n_rows:
        return frames, frames
    if frames.size == n_rows:
        return rows, frames
    raise ProductsError(f"{f.filename}: {path} flags {frames.size} captures of "
                        f"{captured.size} frames, but /{radar}/adc has {n_rows} rows")


def _gates(dc: DspConfig, r: NDArray[np.float64], centre: NDArray[np.float64] | None,
           n: int) -> tuple[list[NDArray[np.intp]], float, float]:
    if centre is not None:
        gates = [gate_bins(r, min_m=c - OBJECT_GATE_HALF_WIDTH_M,
                           max_m=c + OBJECT_GATE_HALF_WIDTH_M) for c in centre]
        return gates, float(np.min(centre) - OBJECT_GATE_HALF_WIDTH_M), float(
            np.max(centre) + OBJECT_GATE_HALF_WIDTH_M)
    lo, hi = dc.spectrogram_range_m or (dc.min_range_m, float(r[-1]))
    return [gate_bins(r, min_m=lo, max_m=hi)] * n, float(lo), float(hi)


def _spectrogram(dc: DspConfig, rc: RadarConfig, cubes: list[NDArray[np.complex64]],
                 chirp_t: NDArray[np.float64], gates: list[NDArray[np.intp]]) -> Spectrogram:
    t_rep = len(rc.tx) * rc.chirp_repetition_time_s
    kw: dict[str, Any] = {"chirp_interval_s": t_rep, "wavelength_m": rc.wavelength_m,
                          "window": dc.spectrogram_window,
                          "sidelobe_db": dc.spectrogram_window_sidelobe_db,
                          "fft_size": dc.spectrogram_fft_size,
                          "clutter_removal": dc.spectrogram_clutter_removal}
    if dc.spectrogram_mode == "frame":
        return frame_spectrogram(cubes, chirp_t.mean(axis=1), range_bins=gates, **kw)
    union = np.unique(np.concatenate(gates))
    slow = np.concatenate([gate_slow_time(c, range_bins=union) for c in cubes])
    return stft_spectrogram(slow, chirp_t.reshape(-1), overlap=dc.spectrogram_overlap,
                            segment_length=dc.spectrogram_segment_chirps
                            or rc.chirps_per_frame, **kw)


def _sliding_vitals(x: NDArray[np.complex64], rate_hz: float, rc: RadarConfig,
                    dc: DspConfig) -> NDArray[np.float64]:
    """Per-frame estimates over the last ``vitals_window_s`` (frames, 4); NaN before."""
    n = x.size
    win = max(8, int(round(dc.vitals_window_s * rate_hz)))
    out = np.full((n, 4), np.nan)
    for k in range(win - 1, n):
        out[k] = estimate_vital_signs(
            x[k - win + 1:k + 1], sample_rate_hz=rate_hz, wavelength_m=rc.wavelength_m,
            breathing_band_hz=dc.vitals_breathing_band_hz,
            heart_band_hz=dc.vitals_heart_band_hz, window=dc.vitals_window,
            static_offset=dc.vitals_static_offset).as_row()
    return out


def _replace_group(f: h5py.File, path: str) -> h5py.Group:
    if path in f:
        del f[path]
    return f.create_group(path)


def _put(group: h5py.Group, name: str, data: NDArray[Any], unit: str) -> None:
    ds = group.create_dataset(name, data=data)
    ds.attrs["unit"] = unit


def radars_with_adc(path: str | os.PathLike[str]) -> list[str]:
    """Names of the dataset's radars that have ADC data (``/<name>/adc``), project order.

    ``["radar"]`` (the built-in radar) when none of its radars has, so asking for its
    products names what is missing; ``[]`` when the project has no radar.
    """
    with h5py.File(path, "r") as f:
        if "meta" not in f or "project_json" not in f["meta"].attrs:
            return ["radar"]
        project = project_from_dict(json.loads(f["meta"].attrs["project_json"]),
                                    check_files=False)
        radars = project.sensors_of_kind("radar")
        found = [n for n in radars if f"/{n}/adc" in f]
    return found or (["radar"] if radars else [])


def write_all_radar_products(path: str | os.PathLike[str], *,
                             object_name: str | None = None
                             ) -> dict[str, RadarProductsSummary]:
    """:func:`write_radar_products` for every radar with ADC data, by radar name."""
    return {radar: write_radar_products(path, object_name=object_name, radar=radar)
            for radar in radars_with_adc(path)}


def write_radar_products(path: str | os.PathLike[str], *,
                         object_name: str | None = None,
                         radar: str = "radar") -> RadarProductsSummary:
    """Compute one radar's spectrogram and vital signs and store them in the dataset.

    Parameters
    ----------
    path : path-like
        A finished HDF5 dataset with ``/<radar>/adc`` (``docs/dataset.md``); opened for
        writing.
    object_name : str, keyword-only, optional
        Follow this object: the spectrogram's range gate moves with its true range from
        this radar (``/objects/radar_range``, another radar's ``/objects/<radar>/range``;
        ± :data:`OBJECT_GATE_HALF_WIDTH_M`) and the
        chest bin is searched within that interval. Otherwise the gates come from the
        project's ``dsp.spectrogram_range_m`` and ``dsp.vitals_range_m``.
    radar : str, keyword-only
        Name of the radar (default: the built-in ``radar``). Its products go to
        ``/<radar>/spectrogram`` and ``/<radar>/vitals``; a radar slower than the
        timeline uses the frames it captured in (``/<radar>/captured``).

    Returns
    -------
    RadarProductsSummary

    Raises
    ------
    ProductsError
        Missing arrays, a sensor that is not a radar, an unknown object, or fewer than 2
        frames.
    """
    with h5py.File(path, "r+") as f:
        adc = _require(f, f"/{radar}/adc")
        chirp_ds = _require(f, f"/{radar}/chirp_start_time")
        project = project_from_dict(json.loads(f["meta"].attrs["project_json"]),
                                    check_files=False)
        rc = _radar_config(f, project, radar)
        dc = project.dsp
        rows, frames = _captured_rows(f, radar, int(adc.shape[0]))
        chirp_t = np.asarray(chirp_ds[:, :, 0], dtype=np.float64)[rows]
        n = int(rows.size)
        if n < 2:
            raise ProductsError(f"{f.filename}: {n} frame(s) of {radar!r}; the products need "
                                "at least 2")
        r = radar_axes(rc, dc).range_m
        centre = (None if object_name is None
                  else _object_range(f, object_name, radar)[frames])
        gates, lo, hi = _gates(dc, r, centre, n)
        union = np.unique(np.concatenate(gates))
        ch = min(dc.vitals_channel, int(adc.shape[2]) - 1)
        gated, slow = _range_spectra(adc, rows, dc, n_bins=r.size, union=union, channel=ch)
        sg = _spectrogram(dc, rc, gated, chirp_t, [np.searchsorted(union, g) for g in gates])
        _write_spectrogram(f, radar, sg, dc, lo, hi, centre)
        k, rate, times, whole = _whole_run_vitals(slow, chirp_t, r, rc, dc, centre)
        _write_vitals(f, radar, slow[:, k], times, rate, whole, frames, rc, dc,
                      range_bin=k, range_m=float(r[k]))
        return RadarProductsSummary(sg, whole, float(r[k]))


def _radar_config(f: h5py.File, project: Project, radar: str) -> RadarConfig:
    """The configuration of the project's radar ``radar`` (ProductsError if none)."""
    try:
        rc = project.sensor_config(radar)
    except KeyError as exc:
        raise ProductsError(f"{f.filename}: {exc.args[0]}") from None
    if not isinstance(rc, RadarConfig):
        raise ProductsError(f"{f.filename}: sensor {radar!r} is not a radar (radars: "
                            f"{', '.join(project.sensors_of_kind('radar'))})")
    return rc


def _range_spectra(adc: h5py.Dataset, rows: NDArray[np.intp], dc: DspConfig, *, n_bins: int,
                   union: NDArray[np.intp], channel: int) -> tuple[
        list[NDArray[np.complex64]], NDArray[np.complex64]]:
    """Range spectra of the gate bins, per frame, and the channel's slow-time profiles.

    Returns the (chirps, channels, gate bins) cube of each frame and the (frames, range)
    chirp-mean range profile of ``channel``; one frame in memory at a time.
    """
    gated, profiles = [], []
    for k in rows:
        cube = range_fft(adc[k], window=dc.range_window,
                         sidelobe_db=dc.range_window_sidelobe_db, remove_dc=dc.remove_dc,
                         n_bins=n_bins)
        gated.append(cube[:, :, union])
        profiles.append(cube[:, channel, :].mean(axis=0))
    return gated, np.stack(profiles)


def _write_spectrogram(f: h5py.File, radar: str, sg: Spectrogram, dc: DspConfig, lo: float,
                       hi: float, centre: NDArray[np.float64] | None) -> None:
    """Replace ``/<radar>/spectrogram`` with ``sg`` and its gate."""
    g = _replace_group(f, f"/{radar}/spectrogram")
    _put(g, "power", sg.power_db, "dB")
    _put(g, "time", sg.time_s, "s")
    _put(g, "velocity_axis", sg.velocity_mps, "m/s")
    g.attrs.update({"mode": dc.spectrogram_mode, "window": dc.spectrogram_window,
                    "range_min_m": lo, "range_max_m": hi})
    if centre is not None:
        _put(g, "gate_center", centre, "m")


def _whole_run_vitals(slow: NDArray[np.complex64], chirp_t: NDArray[np.float64],
                      r: NDArray[np.float64], rc: RadarConfig, dc: DspConfig,
                      centre: NDArray[np.float64] | None) -> tuple[
        int, float, NDArray[np.float64], VitalSigns | None]:
    """Chest bin, frame rate (Hz), frame times (s) and the whole-run vital signs.

    The vital signs are None with fewer than 8 frames.
    """
    v_lo, v_hi = ((float(np.mean(centre)) - 0.3, float(np.mean(centre)) + 0.3)
                  if centre is not None else dc.vitals_range_m
                  or (dc.min_range_m, float(r[-1])))
    k = select_vital_bin(slow, range_axis_m=r, min_range_m=v_lo, max_range_m=v_hi)
    times = chirp_t.mean(axis=1)
    rate = float(1.0 / np.median(np.diff(times)))
    whole = estimate_vital_signs(
        slow[:, k], sample_rate_hz=rate, wavelength_m=rc.wavelength_m,
        breathing_band_hz=dc.vitals_breathing_band_hz,
        heart_band_hz=dc.vitals_heart_band_hz, window=dc.vitals_window,
        static_offset=dc.vitals_static_offset, range_bin=k) if slow.shape[0] >= 8 else None
    return k, rate, times, whole


def _write_vitals(f: h5py.File, radar: str, chest: NDArray[np.complex64],
                  times: NDArray[np.float64], rate: float, whole: VitalSigns | None,
                  frames: NDArray[np.intp], rc: RadarConfig, dc: DspConfig, *,
                  range_bin: int, range_m: float) -> None:
    """Replace ``/<radar>/vitals``: times, displacement, sliding estimates, chest bin."""
    g = _replace_group(f, f"/{radar}/vitals")
    n = chest.size
    n_frames = int(f[f"/{radar}/captured"].shape[0]) if f"/{radar}/captured" in f else n

    def per_frame(values: NDArray[np.float64]) -> NDArray[np.float64]:
        """One value per frame of the dataset: NaN where the radar did not capture."""
        if n_frames == n:
            return values
        out = np.full(n_frames, np.nan)
        out[frames] = values
        return out

    _put(g, "time", per_frame(times), "s")
    if whole is not None:
        _put(g, "displacement", per_frame(whole.displacement_m), "m")
        sliding = _sliding_vitals(chest, rate, rc, dc)
        for j, (name, unit) in enumerate((("breathing_rate", "Hz"),
                                          ("breathing_amplitude", "m"),
                                          ("heart_rate", "Hz"), ("heart_amplitude", "m"))):
            _put(g, name, per_frame(sliding[:, j]), unit)
        g.attrs.update({"breathing_rate_hz": whole.breathing_rate_hz,
                        "breathing_amplitude_m": whole.breathing_amplitude_m,
                        "heart_rate_hz": whole.heart_rate_hz,
                        "heart_amplitude_m": whole.heart_amplitude_m})
    g.attrs.update({"range_bin": range_bin, "range_m": range_m})


__all__ = [
    "ProductsError",
    "RadarProductsSummary",
    "radars_with_adc",
    "write_all_radar_products",
    "write_radar_products",
]
