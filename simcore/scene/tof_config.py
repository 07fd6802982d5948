"""Configuration of the AMCW Time-of-Flight camera.

The physics parameters follow one radiometric chain (see ``docs/physics_tof.md``): the
camera's own illumination (``illumination_power_w``, spread evenly over the field of view)
lights a surface at range R; the surface returns ``f(θ)/π`` of the irradiance per
steradian (the ToF-band material response); each pixel collects it through a lens of
f-number N over its pitch p during ``exposure_time_s`` per correlation sample, with
quantum efficiency η. This gives the mean signal electrons of one correlation sample::

    S = P f p² T η λ / (4 N² Ω_ill R² h c)

With the defaults a white Lambertian wall (f = 1) at 1 m gives
``signal_electrons_at_1m`` ≈ 17 900 e⁻ per sample, well below the 40 000 e⁻ full well,
while near-IR retroreflective tape (f ≈ 60) at 3 m exceeds it and saturates.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from functools import reduce
from math import gcd
from typing import Annotated, Any, Literal

from pydantic import Field, model_validator

from simcore.scene import device_hooks
from simcore.scene.camera import PinholeIntrinsics
from simcore.scene.motion import Pose
from simcore.scene.sensor_timing import SensorTiming

SPEED_OF_LIGHT = 299_792_458.0
PLANCK = 6.626_070_15e-34
#: Largest f / gcd(f1, f2, …) accepted for multi-frequency unwrapping (number of wrap
#: candidates).
MAX_UNWRAP_RATIO = 256
#: Most modulation frequencies per depth frame (three: Kinect v2, Azure Kinect).
MAX_FREQUENCIES = 3
#: Modulation frequencies of AMCW cameras (Hz): 1 kHz to 1 GHz.
MIN_MODULATION_HZ = 1e3
MAX_MODULATION_HZ = 1e9
#: Largest render grid per axis (pixels, supersampling included).
MAX_RENDER_AXIS = 16384


class TofCameraConfig(SensorTiming):
    """AMCW ToF camera: resolution, field of view, mounting pose, modulation and physics.

    ``pose_on_rig`` uses the rig's body convention (x forward, y left, z up); the camera's
    optical frame (x right, y down, z forward) is derived from it. Defaults are the
    :func:`pmd_pico_flexx` preset.
    """

    preset: str = "pmd_pico_flexx"
    width: int = Field(224, ge=1, le=4096)
    height: int = Field(171, ge=1, le=4096)
    fov_h_deg: float = Field(62.0, ge=0.1, lt=170)
    fov_v_deg: float = Field(45.0, ge=0.1, lt=170)
    pose_on_rig: Pose = Pose()
    supersampling: int = Field(2, ge=1, le=8, description="sub-pixels per axis (2 → 2×2)")
    modulation_frequencies_hz: list[
        Annotated[float, Field(ge=MIN_MODULATION_HZ, le=MAX_MODULATION_HZ, allow_inf_nan=False)]
    ] = Field(default_factory=lambda: [20e6], min_length=1, max_length=MAX_FREQUENCIES)
    wavelength_nm: float = Field(850.0, ge=200, le=20_000, allow_inf_nan=False,
                                 description="illumination wavelength (nm): UV to thermal IR")

    # --- illumination and optics -------------------------------------------------------
    illumination_power_w: float = Field(
        1.0, gt=0, le=1e4, allow_inf_nan=False,
        description="mean optical power of the modulated illumination during exposure (W), "
                    "spread evenly over the camera's field of view")
    exposure_time_s: float = Field(
        250e-6, ge=1e-9, le=1.0, allow_inf_nan=False,
        description="integration time of each of the four correlation samples (s)")
    f_number: float = Field(1.2, ge=0.5, le=64, allow_inf_nan=False,
                            description="lens f-number N (0.5 is the physical limit in air)")
    pixel_pitch_um: float = Field(17.5, ge=0.1, le=1000, allow_inf_nan=False)
    quantum_efficiency: float = Field(0.25, gt=0, le=1, allow_inf_nan=False)
    demodulation_contrast: float = Field(
        0.8, gt=0, le=1, allow_inf_nan=False,
        description="modulated fraction m of the signal: C_i = S (1 + m cos(φ + iπ/2)) + B")
    ambient_irradiance_w_m2: float = Field(
        0.05, ge=0, le=1e5, allow_inf_nan=False,
        description="ambient light on the scene within the camera's optical band (W/m²)")

    # --- pixel and read-out ------------------------------------------------------------
    full_well_electrons: float = Field(
        40_000.0, ge=1, le=1e9, allow_inf_nan=False,
        description="saturation level of one correlation sample (e⁻)")
    conversion_gain_dn_per_electron: float = Field(
        0.1, ge=1e-6, le=1e4, allow_inf_nan=False, description="read-out gain (DN per e⁻)")
    adc_bits: int = Field(12, ge=1, le=24)
    read_noise_electrons: float = Field(20.0, ge=0, le=1e9, allow_inf_nan=False)
    crosstalk_sigma_px: float = Field(
        0.5, ge=0, le=20, allow_inf_nan=False,
        description="σ of the Gaussian cross-talk kernel on the correlation images (pixels)")
    min_amplitude_dn: float = Field(
        20.0, ge=0, le=2**24, allow_inf_nan=False,
        description="pixels with a smaller demodulated amplitude are invalid (DN)")
    motion_artifacts: bool = Field(
        False, description="take each of the four correlation samples from a render at its "
                           "own exposure time (slower: four ToF renders per frame)")
    motion_sampling: Literal["renders", "reprojection"] = Field(
        "renders", description="motion artefacts from four renders at the samples' times, "
                               "or from the frame's render reprojected with each pixel's "
                               "known velocity (no extra renders; exact for translating "
                               "planar surfaces, moving silhouettes stay at the frame time)")
    sample_interval_s: float = Field(
        1e-3, gt=0, le=1.0, allow_inf_nan=False,
        description="time between the starts of consecutive correlation samples (s)")
    auto_exposure: bool = Field(
        False, description="choose each frame's exposure time from the previous frame's "
                           "signal, like the camera's auto-exposure modes")
    auto_exposure_target: float = Field(
        0.6, gt=0, le=1, allow_inf_nan=False,
        description="auto-exposure puts the brightest 1 % of pixels at this fraction of "
                    "the full well")
    exposure_range_s: tuple[float, float] = Field(
        (1e-6, 2e-3), description="shortest and longest exposure auto-exposure may choose "
                                   "(s)")
    multipath: bool = Field(
        False, description="add multipath interference: light reaching a pixel through a "
                           "second (diffuse) surface the camera sees (one bounce)")
    multipath_patch_px: int = Field(
        8, ge=1, le=64,
        description="the secondary surfaces are sampled every this many sensor pixels "
                    "(smaller: finer and slower)")
    multipath_model: Literal["screen", "room"] = Field(
        "screen",
        description="multipath model: 'screen' one bounce from the surfaces the camera sees; "
                    "'room' every bounce from every surface of the scene, with occlusion "
                    "(surfel radiosity, simcore.sensors.tof.radiosity)")
    multipath_surfel_m: float = Field(
        0.25, ge=0.005, le=5.0, allow_inf_nan=False,
        description="'room' multipath: the scene's surfaces are cut into triangles of at "
                    "most this edge (m; smaller: finer and slower)")
    multipath_bounces: int = Field(
        0, ge=0, le=1000,
        description="'room' multipath: indirect bounces summed (1: one bounce); 0: all, "
                    "until the series converges")
    multipath_moving: Literal["first_order", "exact"] = Field(
        "first_order",
        description="'room' multipath where objects move: 'first_order' keeps the still "
                    "objects' exact solution and adds what the moving ones change to first "
                    "order in them (milliseconds; simcore.sensors.tof.room_movers); 'exact' "
                    "recomputes every pair with them each frame (seconds per frame)")
    ideal: bool = Field(
        False, description="ideal sensor for validation and ground truth: no shot or read "
                           "noise and no ADC quantisation")

    specular: bool = Field(
        False, description="specular near-IR inter-reflections: light reaching a pixel via "
                           "glossy or metal surfaces (mirror paths up to a triple bounce, "
                           "GGX lobe), e.g. a metal corner reflector's retroreflection")
    # --- optics and electronics switches (off here, so older projects keep their output;
    #     on in the pmd_pico_flexx preset, as in the real camera) -----------------------
    ambient_light: bool = Field(
        True, description="ambient light (ambient_irradiance_w_m2) adds its electrons, shot "
                          "noise and saturation to every sample")
    background_suppression: bool = Field(
        False, description="suppression of background illumination (SBI): the pixel removes "
                           "the ambient charge before saturation; its shot noise remains")
    wiggling: bool = Field(
        False, description="cyclic 'wiggling' depth error from the 3rd and 5th harmonics of "
                           "the modulation/correlation waveforms")
    wiggling_harmonics: tuple[Annotated[float, Field(ge=0, le=0.5)],
                              Annotated[float, Field(ge=0, le=0.5)]] = Field(
        (0.02, 0.005), description="relative amplitudes a3, a5 of the correlation "
                                   "function's 3rd and 5th harmonics")
    distortion: bool = Field(
        False, description="Brown–Conrady lens distortion of the rays the pixels see")
    distortion_coefficients: tuple[float, float, float, float, float] = Field(
        (-0.37, 0.14, 0.0, 0.0, 0.0),
        description="Brown–Conrady (k1, k2, p1, p2, k3) in OpenCV's convention")
    vignetting: bool = Field(
        False, description="natural vignetting: collected light falls off as cos⁴ of the "
                           "off-axis angle")
    stray_light: bool = Field(
        False, description="light scattered inside the lens: a long-tail point-spread "
                           "function on the complex correlation images")
    stray_light_fraction: float = Field(
        0.02, ge=0, le=1, allow_inf_nan=False,
        description="fraction of each pixel's light scattered into the PSF's tail")
    stray_light_radius_px: float = Field(
        8.0, gt=0, le=1e4, allow_inf_nan=False,
        description="core radius r0 of the tail (1 + r²/r0²)^-3/2 (sensor pixels)")
    # Interference mitigation between cameras (docs/interference.md); off by default.
    hop_step_hz: float = Field(
        0.0, ge=0, le=100e6, allow_inf_nan=False,
        description="modulation frequency hopping per frame: every modulation frequency "
                    "is raised by c × hop_step_hz with a channel c drawn from 0 … "
                    "hop_channels − 1 every frame (Hz); another camera on another "
                    "frequency only adds shot noise")
    hop_channels: int = Field(
        1, ge=1, le=1024, description="hopping channels (1 = no frequency hopping)")
    hop_seed: int = Field(
        0, ge=0, le=2**31 - 1,
        description="seed of this camera's hopping sequence; cameras with equal seeds "
                    "and settings hop in step")

    @model_validator(mode="before")
    @classmethod
    def _device_defaults(cls, data: Any) -> Any:
        """A device preset named in a project gives the fields the project leaves out."""
        if isinstance(data, dict) and isinstance(data.get("preset"), str):
            defaults = device_hooks.preset_defaults("tof", data["preset"])
            if defaults is not None:
                return {**defaults, **data}
        return data

    @model_validator(mode="after")
    def _device_limits(self) -> TofCameraConfig:
        """A device preset's limits (:mod:`simcore.scene.devices`) hold."""
        problems = device_hooks.limit_problems(self)
        if problems:
            raise ValueError(f"preset {self.preset!r}: " + "; ".join(problems))
        return self

    @model_validator(mode="after")
    def _check_exposure_range(self) -> TofCameraConfig:
        low, high = self.exposure_range_s
        if not (1e-9 <= low <= high <= 1.0):
            raise ValueError(f"exposure_range_s must be 1 ns ≤ shortest ≤ longest ≤ 1 s "
                             f"(got {low:g} s, {high:g} s)")
        return self

    @model_validator(mode="after")
    def _check_frequencies(self) -> TofCameraConfig:
        for axis, size in (("width", self.width), ("height", self.height)):
            if size * self.supersampling > MAX_RENDER_AXIS:
                raise ValueError(
                    f"{axis} × supersampling = {size} × {self.supersampling} = "
                    f"{size * self.supersampling} render pixels; at most {MAX_RENDER_AXIS} "
                    "per axis")
        freqs = self.modulation_frequencies_hz
        top = max(freqs) + (self.hop_channels - 1) * self.hop_step_hz
        if top > MAX_MODULATION_HZ:
            raise ValueError(f"the highest hopping channel modulates at {top:.4g} Hz; at most "
                             f"{MAX_MODULATION_HZ:g} Hz")
        if any(not (f > 0 and math.isfinite(f)) for f in freqs):
            raise ValueError("modulation_frequencies_hz must be positive and finite")
        if len(freqs) >= 2:
            whole = [round(f) for f in freqs]
            if len(set(whole)) != len(whole):
                raise ValueError(f"modulation_frequencies_hz {freqs}: the frequencies must "
                                 "differ")
            if min(whole) < 1:
                raise ValueError("modulation frequencies must be at least 1 Hz")
            common = reduce(gcd, whole)
            if max(freqs) / common > MAX_UNWRAP_RATIO:
                raise ValueError(
                    f"modulation_frequencies_hz {freqs}: their greatest common divisor "
                    f"({common} Hz) is too small for unwrapping (f/gcd must be at most "
                    f"{MAX_UNWRAP_RATIO}); choose frequencies with a larger common divisor")
        return self

    # --- geometry ----------------------------------------------------------------------
    def intrinsics(self) -> PinholeIntrinsics:
        """Pinhole intrinsics of the sensor pixel grid (``width`` × ``height``)."""
        return PinholeIntrinsics.from_fov(self.width, self.height, self.fov_h_deg,
                                          self.fov_v_deg)

    def render_intrinsics(self) -> PinholeIntrinsics:
        """Supersampled render grid: ``supersampling``² sub-pixels tile each sensor pixel."""
        return self.intrinsics().scaled(self.supersampling)

    @property
    def illumination_solid_angle_sr(self) -> float:
        """Solid angle of the rectangular field of view that the illumination fills (sr)."""
        a = math.radians(self.fov_h_deg) / 2
        b = math.radians(self.fov_v_deg) / 2
        return 4.0 * math.asin(math.sin(a) * math.sin(b))

    # --- radiometry --------------------------------------------------------------------
    @property
    def electrons_per_radiance(self) -> float:
        """Electrons per correlation sample per unit scene radiance (e⁻ per W m⁻² sr⁻¹).

        Pixel étendue ``π p² / (4 N²)`` (flat field: the illumination profile is assumed
        to compensate lens vignetting) times exposure, quantum efficiency and photons/J.
        """
        pitch = self.pixel_pitch_um * 1e-6
        etendue = math.pi * pitch**2 / (4.0 * self.f_number**2)
        photons_per_joule = self.wavelength_nm * 1e-9 / (PLANCK * SPEED_OF_LIGHT)
        return etendue * self.exposure_time_s * self.quantum_efficiency * photons_per_joule

    @property
    def signal_electrons_at_1m(self) -> float:
        """Mean signal electrons per sample from a response-1 surface at 1 m (e⁻).

        A surface of ToF-band response ``f`` at range ``R`` gives
        ``signal_electrons_at_1m * f / R²``.
        """
        radiant_intensity = self.illumination_power_w / self.illumination_solid_angle_sr
        return radiant_intensity / math.pi * self.electrons_per_radiance

    @property
    def ambient_electrons(self) -> float:
        """Ambient electrons per sample from a response-1 surface (e⁻), times ``f``."""
        return self.ambient_irradiance_w_m2 / math.pi * self.electrons_per_radiance

    @property
    def adc_max_dn(self) -> int:
        """Largest ADC code (DN)."""
        return int(2**self.adc_bits - 1)

    # --- modulation --------------------------------------------------------------------
    @property
    def unambiguous_range_m(self) -> float:
        """Unambiguous range c / (2 f) of the first modulation frequency (m)."""
        return SPEED_OF_LIGHT / (2.0 * self.modulation_frequencies_hz[0])

    @property
    def combined_unambiguous_range_m(self) -> float:
        """Unambiguous range after unwrapping: c / (2 gcd(f1, f2, …)) (m; frequencies in Hz).

        Equals :attr:`unambiguous_range_m` with one frequency.
        """
        freqs = self.modulation_frequencies_hz
        if len(freqs) == 1:
            return self.unambiguous_range_m
        return SPEED_OF_LIGHT / (2.0 * reduce(gcd, [round(f) for f in freqs]))


def pmd_pico_flexx() -> TofCameraConfig:
    """PMD CamBoard pico flexx: 224×171 px, 62°×45°, 20 MHz (7.5 m unambiguous), 850 nm."""
    return TofCameraConfig(
        preset="pmd_pico_flexx",
        width=224,
        height=171,
        fov_h_deg=62.0,
        fov_v_deg=45.0,
        supersampling=2,
        modulation_frequencies_hz=[20e6],
        wavelength_nm=850.0,
        auto_exposure=True,
        multipath=True,
        specular=True,
        wiggling=True,
        distortion=True,
        vignetting=True,
        stray_light=True,
        motion_artifacts=True,
        motion_sampling="reprojection",
    )


#: Named ToF camera presets: name → factory returning a fresh config.
TOF_PRESETS: dict[str, Callable[[], TofCameraConfig]] = {"pmd_pico_flexx": pmd_pico_flexx}


def tof_preset(name: str) -> TofCameraConfig:
    """Return a fresh config of the preset called ``name`` (ValueError if unknown).

    The device library's cameras (:mod:`simcore.scene.device_cameras`) are presets too.
    """
    TOF_PRESETS.update(device_hooks.camera_presets())
    try:
        return TOF_PRESETS[name]()
    except KeyError:
        raise ValueError(
            f"unknown ToF preset {name!r}; expected one of {sorted(TOF_PRESETS)}") from None
