"""The device library: real radars and ToF cameras as presets with sources and limits.

A :class:`Device` is a preset factory (a :class:`RadarConfig` or :class:`TofCameraConfig`
of the real device), a one-line description, the sources of its numbers, the values that
are assumptions, and its limits. Naming a device in a project (``"preset":
"ti_iwr6843isk"`` on a radar or ToF configuration) fills every field the project leaves
out from the preset (:func:`preset_defaults`), and a configuration outside the device's
limits is refused when it is loaded or validated (:func:`limit_problems`), with the
device's limit named. The two presets that predate the library (``bgt60tr13c``,
``pmd_pico_flexx``) are the defaults of every configuration and keep their old
behaviour: their fields are the class defaults (old project files load identically) and
their limits are reported by ``tofradar validate``, not enforced.

``tofradar devices`` lists the library with :func:`device_figures`; ``docs/devices.md``
has the tables and the sources.
"""

from __future__ import annotations

import contextvars
import copy
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from functools import cache
from typing import Any, Literal

from simcore.scene import device_cameras as cams
from simcore.scene import device_hooks
from simcore.scene import device_radars as rads
from simcore.scene.radar_config import SPEED_OF_LIGHT, RadarConfig
from simcore.scene.radar_presets import bgt60tr13c
from simcore.scene.ti_mmwave import TI_IF_PASSBAND, TI_SPEED_OF_LIGHT
from simcore.scene.tof_config import TofCameraConfig, pmd_pico_flexx

Kind = Literal["radar", "tof"]


@dataclass(frozen=True)
class Device:
    """A real sensor in the library.

    Attributes
    ----------
    name : str
        Preset name (``"preset"`` in a project).
    kind : {"radar", "tof"}
    title : str
        Vendor and model.
    description : str
        One line for lists and the GUI.
    factory : callable
        Returns a fresh configuration of the device.
    limits : RadarLimits or CameraLimits
    sources : dict
        Figure → citation.
    assumptions : tuple of str
        Values that are not public.
    enforced : bool
        Refuse configurations outside the limits (False: report them only).
    """

    name: str
    kind: Kind
    title: str
    description: str
    factory: Callable[[], Any]
    limits: Any
    sources: dict[str, str]
    assumptions: tuple[str, ...]
    enforced: bool = True


def _radar(name: str, title: str, description: str, factory: Callable[[], RadarConfig],
           limits: rads.RadarLimits, *, enforced: bool = True) -> Device:
    return Device(name, "radar", title, description, factory, limits,
                  rads.RADAR_SOURCES[name], rads.RADAR_ASSUMPTIONS.get(name, ()), enforced)


def _camera(name: str, title: str, description: str, factory: Callable[[], TofCameraConfig],
            limits: cams.CameraLimits, *, enforced: bool = True) -> Device:
    return Device(name, "tof", title, description, factory, limits,
                  cams.CAMERA_SOURCES[name], cams.CAMERA_ASSUMPTIONS.get(name, ()), enforced)


#: The library: preset name → device.
DEVICES: dict[str, Device] = {d.name: d for d in (
    _radar("ti_iwr6843isk", "TI IWR6843ISK",
           "60–64 GHz, 3 Tx × 4 Rx TDM-MIMO, 2-D virtual array (SDK profile_2d.cfg)",
           rads.ti_iwr6843isk, rads.IWR6843_LIMITS),
    _radar("ti_awr1843boost", "TI AWR1843BOOST",
           "76–81 GHz, 2 Tx × 4 Rx TDM-MIMO, 8-element ULA (SDK profile_2d.cfg)",
           rads.ti_awr1843boost, rads.AWR1843_LIMITS),
    _radar("bgt60tr13c", "Infineon BGT60TR13C",
           "60 GHz, 1 Tx × 3 Rx in an L, real IF (the reference paper's radar)",
           bgt60tr13c, rads.BGT60TR13C_LIMITS, enforced=False),
    _radar("infineon_bgt60utr11aip", "Infineon BGT60UTR11AIP",
           "58–63.5 GHz, 1 Tx × 1 Rx antennas in package, real IF",
           rads.infineon_bgt60utr11aip, rads.BGT60UTR11_LIMITS),
    _camera("pmd_pico_flexx", "pmd CamBoard pico flexx",
            "224×171, 62°×45°, 20 MHz, 850 nm (the reference paper's camera)",
            pmd_pico_flexx, cams.PICO_FLEXX_LIMITS, enforced=False),
    _camera("kinect_v2", "Microsoft Kinect v2",
            "512×424, 70.6°×60°, 80/16/120 MHz unwrapped to 18.7 m",
            cams.kinect_v2, cams.KINECT_V2_LIMITS),
    _camera("azure_kinect_wfov", "Microsoft Azure Kinect (WFOV, 1 MP)",
            "1024×1024, 120°×120°, three frequencies, 15 fps",
            cams.azure_kinect_wfov, cams.AZURE_KINECT_LIMITS),
    _camera("pmd_flexx2", "pmd CamBoard flexx2",
            "224×172, 56°×44°, 940 nm VCSEL, up to 60 fps",
            cams.pmd_flexx2, cams.FLEXX2_LIMITS),
)}


def devices(kind: Kind | None = None) -> list[Device]:
    """The library's devices (of one kind), radars first, in a fixed order."""
    return [d for d in DEVICES.values() if kind is None or d.kind == kind]


# ------------------------------------------------------------- presets by name
_BUILDING: contextvars.ContextVar[bool] = contextvars.ContextVar("_BUILDING", default=False)


@contextmanager
def _building() -> Iterator[None]:
    token = _BUILDING.set(True)
    try:
        yield
    finally:
        _BUILDING.reset(token)


@cache
def _dump(name: str) -> dict[str, Any]:
    with _building():
        return dict(DEVICES[name].factory().model_dump())


def preset_defaults(kind: Kind, name: str) -> dict[str, Any] | None:
    """The fields of device preset ``name`` a project leaves out take, or None.

    None for a name outside the library, of another kind, or one of the presets that
    predate it (their defaults are the configuration classes' own), and while a preset is
    being built.
    """
    device = DEVICES.get(name)
    if device is None or device.kind != kind or not device.enforced or _BUILDING.get():
        return None
    return copy.deepcopy(_dump(name))


# ------------------------------------------------------------------- limits
def _radar_problems(cfg: RadarConfig, device: Device) -> list[str]:
    lim: rads.RadarLimits = device.limits
    who = f"the {device.title}"
    out = []
    lo, hi = lim.band_hz
    top = cfg.start_frequency_hz + cfg.bandwidth_hz
    if cfg.start_frequency_hz < lo * (1 - 1e-9) or top > hi * (1 + 1e-9):
        out.append(f"chirp {cfg.start_frequency_hz / 1e9:.4g}–{top / 1e9:.4g} GHz leaves "
                   f"{who}'s band {lo / 1e9:g}–{hi / 1e9:g} GHz")
    if cfg.complex_iq not in lim.complex_iq:
        out.append(f"complex_iq = {cfg.complex_iq}: {who} samples "
                   f"{'complex' if lim.complex_iq == (True,) else 'real'} IF only")
    if cfg.sample_rate_hz > lim.max_sample_rate_hz * (1 + 1e-9):
        out.append(f"sample_rate_hz = {cfg.sample_rate_hz:.6g} exceeds {who}'s maximum "
                   f"sample rate {lim.max_sample_rate_hz:.6g} Hz")
    if cfg.if_lowpass_hz > lim.max_if_bandwidth_hz:
        out.append(f"if_lowpass_hz = {cfg.if_lowpass_hz:.6g} exceeds {who}'s maximum IF "
                   f"bandwidth {lim.max_if_bandwidth_hz:.6g} Hz")
    for field, value, limit, what in (
            ("samples_per_chirp", cfg.samples_per_chirp, lim.max_samples_per_chirp,
             "samples per chirp"),
            ("chirps_per_frame", cfg.chirps_per_frame, lim.max_chirps_per_frame,
             "chirps (loops) per frame"),
            ("tx", len(cfg.tx), lim.max_tx, "transmitters"),
            ("rx", len(cfg.rx), lim.max_rx, "receivers")):
        if value > limit:
            out.append(f"{field}: {value} exceeds {who}'s {limit} {what}")
    if cfg.adc_bits not in lim.adc_bits:
        out.append(f"adc_bits = {cfg.adc_bits}: {who}'s ADC gives "
                   f"{'/'.join(map(str, lim.adc_bits))} bits")
    if cfg.frame_rate_hz is not None:
        out += frame_rate_problems(cfg, device, cfg.frame_rate_hz)
    return out


def _camera_problems(cfg: TofCameraConfig, device: Device, rate_hz: float | None = None
                     ) -> list[str]:
    """Limits of a camera: a mode with this resolution, exposure (and frame rate)."""
    lim: cams.CameraLimits = device.limits
    who = f"the {device.title}"
    n_freq = len(cfg.modulation_frequencies_hz)
    modes = [m for m in lim.modes if (m.width, m.height) == (cfg.width, cfg.height)
             and m.n_frequencies >= n_freq]
    if not modes:
        listed = "; ".join(m.name for m in lim.modes)
        return [f"width × height = {cfg.width} × {cfg.height} with {n_freq} "
                f"frequencies is none of {who}'s modes ({listed})"]
    out = []
    longest = max(cfg.exposure_time_s, cfg.exposure_range_s[1])
    shortest = min(cfg.exposure_time_s, cfg.exposure_range_s[0])
    top = max(m.max_exposure_s for m in modes)
    if longest > top * (1 + 1e-9) or shortest < lim.exposure_range_s[0] * (1 - 1e-9):
        out.append(f"exposure_time_s/exposure_range_s: {shortest:.4g}–{longest:.4g} s is "
                   f"outside {who}'s exposure range {lim.exposure_range_s[0]:.4g}–{top:.4g} s")
    elif rate_hz is not None:
        fits = [m for m in modes if longest <= m.max_exposure_s * (1 + 1e-9)]
        fastest = max(m.max_frame_rate_hz for m in fits)
        if rate_hz > fastest * (1 + 1e-9):
            out.append(f"frame rate {rate_hz:g} Hz exceeds {who}'s {fastest:g} frames/s "
                       f"at {longest * 1e6:.4g} µs exposure (modes: "
                       + "; ".join(m.name for m in fits) + ")")
    f_lo, f_hi = lim.modulation_range_hz
    for f in cfg.modulation_frequencies_hz:
        if not f_lo <= f <= f_hi:
            out.append(f"modulation_frequencies_hz: {f / 1e6:g} MHz is outside {who}'s "
                       f"{f_lo / 1e6:g}–{f_hi / 1e6:g} MHz")
    return out


def frame_rate_problems(cfg: RadarConfig | TofCameraConfig, device: Device,
                        rate_hz: float) -> list[str]:
    """Problems with running ``cfg`` of ``device`` at ``rate_hz`` frames per second."""
    who = f"the {device.title}"
    if isinstance(cfg, RadarConfig):
        lo, hi = device.limits.frame_rate_hz
        out = []
        if not lo * (1 - 1e-9) <= rate_hz <= hi * (1 + 1e-9):
            out.append(f"frame rate {rate_hz:g} Hz is outside {who}'s {lo:.4g}–{hi:g} Hz")
        if cfg.frame_duration_s > 1.0 / rate_hz:
            out.append(f"the chirps take {cfg.frame_duration_s * 1e3:.4g} ms, longer than "
                       f"a frame at {rate_hz:g} Hz")
        return out
    return [p for p in _camera_problems(cfg, device, rate_hz) if p.startswith("frame rate")]


def limit_problems(cfg: RadarConfig | TofCameraConfig, *, enforced_only: bool = True
                   ) -> list[str]:
    """Where ``cfg`` leaves the limits of the device its ``preset`` names (empty: none).

    ``enforced_only``: only for devices whose limits are enforced (the configuration
    classes refuse these); False also reports the older presets' limits.
    """
    device = DEVICES.get(cfg.preset)
    kind = "radar" if isinstance(cfg, RadarConfig) else "tof"
    if device is None or device.kind != kind or _BUILDING.get():
        return []
    if enforced_only and not device.enforced:
        return []
    if isinstance(cfg, RadarConfig):
        return _radar_problems(cfg, device)
    return _camera_problems(cfg, device, cfg.frame_rate_hz)


# ------------------------------------------------------------------- figures
def radar_figures(cfg: RadarConfig, *, device: Device | None = None) -> dict[str, float]:
    """Range resolution, maximum range and velocity resolution of a radar (m, m/s).

    For a TI device the figures are computed as TI's tools do
    (:func:`simcore.scene.ti_mmwave.ti_figures`: λ at the chirp's start frequency,
    usable IF 90 % of the complex sample rate, c = 3·10⁸ m/s); otherwise from the model:
    ``c / (2 B_sampled)``, the beat frequency at ``f_s`` (complex) or ``f_s / 2`` (real),
    and ``λ / (2 N_c N_tx T_r)`` at the centre wavelength. The maximum range is further
    capped by the device's IF bandwidth.
    """
    ti = device is not None and device.name.startswith("ti_")
    c = TI_SPEED_OF_LIGHT if ti else SPEED_OF_LIGHT
    sampled_bw = cfg.slope_hz_per_s * cfg.samples_per_chirp / cfg.sample_rate_hz
    if_max = cfg.sample_rate_hz * (1.0 if cfg.complex_iq else 0.5)
    if ti:
        if_max *= TI_IF_PASSBAND
        # TI's startFreq: the ramp's start, the ADC start time before the model's chirp.
        adc_start = (cfg.device_settings or {}).get("ti_adc_start_time_us", 0.0)
        lead_s = float(adc_start) * 1e-6 if isinstance(adc_start, (int, float)) else 0.0
        f_ref = cfg.start_frequency_hz - cfg.slope_hz_per_s * lead_s
    else:
        f_ref = cfg.start_frequency_hz + 0.5 * cfg.bandwidth_hz
    if device is not None:
        if_max = min(if_max, device.limits.max_if_bandwidth_hz)
    t_loop = cfg.chirp_repetition_time_s * len(cfg.tx)
    lam = c / f_ref
    return {"range_resolution_m": c / (2 * sampled_bw),
            "max_range_m": if_max * c / (2 * cfg.slope_hz_per_s),
            "velocity_resolution_mps": lam / (2 * cfg.chirps_per_frame * t_loop),
            "max_velocity_mps": lam / (4 * t_loop)}


def camera_figures(cfg: TofCameraConfig) -> dict[str, Any]:
    """Resolution, field of view, frequencies and unambiguous range of a camera."""
    return {"resolution": f"{cfg.width}×{cfg.height}",
            "fov_deg": f"{cfg.fov_h_deg:g}×{cfg.fov_v_deg:g}",
            "frequencies_mhz": "/".join(f"{f / 1e6:g}" for f in cfg.modulation_frequencies_hz),
            "unambiguous_range_m": cfg.combined_unambiguous_range_m}


def device_figures(device: Device) -> dict[str, Any]:
    """The key figures of a device's preset (:func:`radar_figures`, :func:`camera_figures`)."""
    with _building():
        cfg = device.factory()
    if isinstance(cfg, RadarConfig):
        return radar_figures(cfg, device=device)
    return camera_figures(cfg)


def devices_table() -> list[str]:
    """Lines of ``tofradar devices``: one per device with its key figures."""
    lines = [f"radars:\n  {'name':<30} {'range res':>9} {'max range':>9} {'vel. res':>10}  "
             "device"]
    for d in devices("radar"):
        f = device_figures(d)
        lines.append(f"  {d.name:<30} {f['range_resolution_m'] * 100:6.2f} cm "
                     f"{f['max_range_m']:7.2f} m {f['velocity_resolution_mps']:6.3f} m/s  "
                     f"{d.title}: {d.description}")
    lines.append(f"cameras:\n  {'name':<30} {'pixels':>9}  {'FoV (deg)':>9}  "
                 f"{'f_mod (MHz)':>11}  {'unambig.':>8}  device")
    for d in devices("tof"):
        f = device_figures(d)
        rng = f["unambiguous_range_m"]
        lines.append(f"  {d.name:<30} {f['resolution']:>9}  {f['fov_deg']:>9}  "
                     f"{f['frequencies_mhz']:>11}  {rng:6.2f} m  {d.title}: {d.description}")
    return lines


def project_limit_problems(project: Any) -> tuple[list[str], list[str]]:
    """Device limits a project's sensors break at the project's frame rates.

    Returns
    -------
    (problems, notes) : list of str, list of str
        ``problems``: frame rates outside an enforced device's limits (the configuration
        classes check everything else when the project loads); ``notes``: any limit of a
        device whose limits are reported only (``bgt60tr13c``, ``pmd_pico_flexx``).
    """
    problems: list[str] = []
    notes: list[str] = []
    rate = project.timeline.frame_rate_hz
    for name, cfg in project.sensor_configs().items():
        device = DEVICES.get(getattr(cfg, "preset", ""))
        if device is None or not isinstance(cfg, (RadarConfig, TofCameraConfig)):
            continue
        if device.kind != ("radar" if isinstance(cfg, RadarConfig) else "tof"):
            continue
        try:
            sensor_rate = rate / cfg.frame_divider(rate)
        except ValueError:
            continue                       # preflight names a rate that does not divide
        found = frame_rate_problems(cfg, device, sensor_rate)
        if device.enforced:
            problems += [f"{name}: preset {device.name!r}: {p}" for p in found]
        else:
            notes += [f"{name}: outside the {device.title}'s limits (reported, not enforced): "
                      f"{p}" for p in found + limit_problems(cfg, enforced_only=False)]
    return problems, notes


device_hooks.install(defaults=preset_defaults,  # type: ignore[arg-type]
                     limits=limit_problems,
                     cameras=cams.CAMERA_PRESETS)
