"""ToF camera presets of the device library: Kinect v2, Azure Kinect (1 MP), pmd flexx2.

Every number names its source in :data:`CAMERA_SOURCES` (``docs/devices.md`` has the same
table); values that are not public are listed in :data:`CAMERA_ASSUMPTIONS`.

Sources (cited by key below):

- ``[K2]`` Microsoft, Kinect for Windows v2 sensor specifications: depth 512 × 424,
  70.6° × 60°, 30 frames/s, 0.5–4.5 m.
- ``[JSSC15]`` C. S. Bamji et al., "A 0.13 µm CMOS System-on-Chip for a 512 × 424
  Time-of-Flight Image Sensor With Multi-Frequency Photo-Demodulation up to 130 MHz and
  2 GS/s ADC", IEEE J. Solid-State Circuits 50(1), 2015: 10 µm pixels, several modulation
  frequencies per depth frame.
- ``[LIBFREENECT2]`` OpenKinect libfreenect2, depth packet processors: the three
  modulation frequencies 80, 16 and 120 MHz, each with three phase steps, and the
  maximum depth 18.75 m (= c / (2 · 8 MHz)).
- ``[AK]`` Microsoft, Azure Kinect DK hardware specification, depth camera: modes NFOV
  unbinned 640 × 576 at 75° × 65° (30 fps, 12.8 ms exposure), NFOV binned 320 × 288,
  WFOV binned 512 × 512 at 120° × 120° (30 fps, 12.8 ms), WFOV unbinned 1024 × 1024 at
  120° × 120° (15 fps, 20.3 ms); 850 nm illumination.
- ``[ISSCC18]`` C. S. Bamji et al., "1Mpixel 65nm BSI 320MHz demodulated TOF image sensor
  with 3.5 µm global shutter pixels and analog binning", ISSCC 2018: 1024 × 1024,
  3.5 µm pixels, modulation up to 320 MHz.
- ``[FLEXX2]`` pmd technologies, CamBoard pmd flexx2 data sheet: 224 × 172 pixels,
  56° × 44°, 940 nm VCSEL, 0.1–4 m, up to 60 frames/s.
- ``[ROYALE]`` pmd Royale SDK use cases of the pico flexx (``MODE_9_5FPS_2000`` …
  ``MODE_5_45FPS_500``: raw frames, frame rate, longest exposure in µs) and its data sheet
  (224 × 171, 62° × 45°, 850 nm).
"""

from __future__ import annotations

from dataclasses import dataclass

from simcore.scene.tof_config import TofCameraConfig


@dataclass(frozen=True)
class CameraMode:
    """One operating mode of a camera (a vendor 'use case' or 'depth mode')."""

    name: str
    width: int
    height: int
    max_frame_rate_hz: float
    max_exposure_s: float
    n_frequencies: int


@dataclass(frozen=True)
class CameraLimits:
    """What a ToF camera can be configured to do.

    Attributes
    ----------
    modes : tuple of CameraMode
        The device's modes; a configuration's resolution must be one of theirs.
    exposure_range_s : (float, float)
        Shortest and longest exposure of one correlation sample (s).
    modulation_range_hz : (float, float)
        Lowest and highest modulation frequency (Hz).
    """

    modes: tuple[CameraMode, ...]
    exposure_range_s: tuple[float, float]
    modulation_range_hz: tuple[float, float]


# --------------------------------------------------------------------- Kinect v2
KINECT_V2_FREQUENCIES_HZ = [80e6, 16e6, 120e6]
KINECT_V2_LIMITS = CameraLimits(
    modes=(CameraMode("depth 512x424 @ 30 fps (3 frequencies)", 512, 424, 30.0, 2e-3, 3),),
    exposure_range_s=(1e-6, 2e-3), modulation_range_hz=(10e6, 130e6))


def kinect_v2() -> TofCameraConfig:
    """Microsoft Kinect v2 (Kinect for Xbox One / for Windows v2) depth camera.

    512 × 424 pixels over 70.6° × 60° [K2], 10 µm pixels [JSSC15], three modulation
    frequencies 80, 16 and 120 MHz [LIBFREENECT2] unwrapped over c / (2 · 8 MHz) =
    18.74 m (:func:`simcore.sensors.tof.camera.unwrap_frequencies`). The real camera
    takes three phase steps per frequency; the model takes four (the same phase and
    amplitude without noise). Illumination power, exposure, f-number and the 850 nm
    wavelength are assumptions.
    """
    return TofCameraConfig(
        preset="kinect_v2", width=512, height=424, fov_h_deg=70.6, fov_v_deg=60.0,
        supersampling=1, modulation_frequencies_hz=list(KINECT_V2_FREQUENCIES_HZ),
        wavelength_nm=850.0, pixel_pitch_um=10.0, illumination_power_w=2.0,
        exposure_time_s=500e-6, exposure_range_s=(1e-6, 2e-3), f_number=1.1)


# ------------------------------------------------------------------ Azure Kinect
AZURE_KINECT_FREQUENCIES_HZ = [200e6, 160e6, 20e6]
AZURE_KINECT_LIMITS = CameraLimits(
    modes=(CameraMode("NFOV unbinned 640x576 @ 30 fps", 640, 576, 30.0, 12.8e-3 / 12, 3),
           CameraMode("NFOV 2x2 binned 320x288 @ 30 fps", 320, 288, 30.0, 12.8e-3 / 12, 3),
           CameraMode("WFOV 2x2 binned 512x512 @ 30 fps", 512, 512, 30.0, 12.8e-3 / 12, 3),
           CameraMode("WFOV unbinned 1024x1024 @ 15 fps", 1024, 1024, 15.0, 20.3e-3 / 12, 3)),
    exposure_range_s=(1e-6, 20.3e-3 / 12), modulation_range_hz=(10e6, 320e6))


def azure_kinect_wfov() -> TofCameraConfig:
    """Microsoft Azure Kinect DK depth camera, WFOV unbinned: the 1-megapixel module.

    1024 × 1024 pixels over 120° × 120°, 15 frames/s, 20.3 ms exposure per depth frame,
    850 nm [AK]; 3.5 µm pixels [ISSCC18]. The modulation frequencies are not published:
    three frequencies 200, 160 and 20 MHz (combined range c / (2 · 20 MHz) = 7.49 m) are an
    assumption, as is the split of the exposure over the 3 × 4 correlation samples
    (20.3 ms / 12 each), the illumination power and the f-number.
    """
    return TofCameraConfig(
        preset="azure_kinect_wfov", width=1024, height=1024, fov_h_deg=120.0,
        fov_v_deg=120.0, supersampling=1,
        modulation_frequencies_hz=list(AZURE_KINECT_FREQUENCIES_HZ), wavelength_nm=850.0,
        pixel_pitch_um=3.5, illumination_power_w=2.0, exposure_time_s=20.3e-3 / 12,
        exposure_range_s=(1e-6, 20.3e-3 / 12), f_number=1.3)


# ------------------------------------------------------------------- pmd flexx2
FLEXX2_LIMITS = CameraLimits(
    modes=(CameraMode("224x172 @ 5 fps (2 frequencies)", 224, 172, 5.0, 2e-3, 2),
           CameraMode("224x172 @ 30 fps (1 frequency)", 224, 172, 30.0, 1e-3, 1),
           CameraMode("224x172 @ 60 fps (1 frequency)", 224, 172, 60.0, 500e-6, 1)),
    exposure_range_s=(1e-6, 2e-3), modulation_range_hz=(5e6, 100e6))


def pmd_flexx2() -> TofCameraConfig:
    """The pmd CamBoard flexx2: 224 × 172 pixels, 56° × 44°, 940 nm VCSEL, up to 60 fps.

    Figures from [FLEXX2].

    The modulation frequency (60 MHz: 2.5 m unambiguous), exposure modes, pixel pitch and
    illumination power are not published (assumptions).
    """
    return TofCameraConfig(
        preset="pmd_flexx2", width=224, height=172, fov_h_deg=56.0, fov_v_deg=44.0,
        supersampling=2, modulation_frequencies_hz=[60e6], wavelength_nm=940.0,
        exposure_time_s=500e-6, exposure_range_s=(1e-6, 1e-3))


# ------------------------------------------------------------- pmd pico flexx
PICO_FLEXX_LIMITS = CameraLimits(
    modes=tuple(CameraMode(f"MODE_{raw}_{fps}FPS_{us}", 224, 171, float(fps), us * 1e-6,
                           2 if raw == 9 else 1)
                for raw, fps, us in ((9, 5, 2000), (9, 10, 1000), (9, 15, 700),
                                     (9, 25, 450), (5, 35, 600), (5, 45, 500))),
    exposure_range_s=(1e-6, 2e-3), modulation_range_hz=(10e6, 100e6))

#: Camera presets of this module (the pico flexx is in :mod:`simcore.scene.tof_config`).
CAMERA_PRESETS = {"kinect_v2": kinect_v2, "azure_kinect_wfov": azure_kinect_wfov,
                  "pmd_flexx2": pmd_flexx2}

CAMERA_SOURCES: dict[str, dict[str, str]] = {
    "kinect_v2": {
        "512 × 424 pixels, 70.6° × 60°, 30 fps": "[K2]",
        "10 µm pixel pitch": "[JSSC15]",
        "modulation 80, 16, 120 MHz; 18.75 m combined range": "[LIBFREENECT2]",
    },
    "azure_kinect_wfov": {
        "1024 × 1024, 120° × 120°, 15 fps, 20.3 ms exposure; other modes": "[AK]",
        "850 nm": "[AK]",
        "3.5 µm pixel pitch, modulation up to 320 MHz": "[ISSCC18]",
    },
    "pmd_flexx2": {"224 × 172, 56° × 44°, 940 nm, up to 60 fps": "[FLEXX2]"},
    "pmd_pico_flexx": {"224 × 171, 62° × 45°, 850 nm; use cases (fps, exposure)": "[ROYALE]",
                       "20 MHz": "the reference paper's camera setting"},
}
CAMERA_ASSUMPTIONS: dict[str, tuple[str, ...]] = {
    "kinect_v2": ("850 nm", "2 W illumination", "500 µs per correlation sample", "f/1.1",
                  "exposure range 1 µs–2 ms"),
    "azure_kinect_wfov": ("modulation 200, 160, 20 MHz",
                          "exposure split evenly over 3 × 4 samples",
                          "2 W illumination", "f/1.3"),
    "pmd_flexx2": ("60 MHz modulation", "modes' exposures", "17.5 µm pixel pitch",
                   "1 W illumination"),
    "pmd_pico_flexx": ("the preset keeps the reference paper's defaults: its limits are "
                       "reported, not enforced",),
}
