"""Radar signal processing: range/Doppler/angle FFTs, windows, CFAR, point clouds.

Pure functions over numpy arrays (keyword-only options, shapes and units in every
docstring) plus :func:`process_frame`, which runs the whole chain on one ADC cube
``(chirps, channels, samples)`` and returns every product in a :class:`RadarProducts`.
Conventions (``docs/dsp.md``): velocity positive = moving away; azimuth positive towards
the radar's +x (right); elevation positive up (−y); points in the radar optical frame.
"""

from simcore.dsp.angle import (
    ArrayLayout,
    antenna_positions_m,
    array_layout,
    bartlett_spectrum,
    capon_spectrum,
    direction_vectors,
    estimate_angles,
    fft_azimuth_power,
    fft_beamform,
    interpolate_fft_power,
    monopulse_azimuth_rad,
    monopulse_direction_cosine,
    spatial_covariance,
    steering_vectors,
    virtual_array_positions_m,
)
from simcore.dsp.cfar import (
    CfarResult,
    ca_cfar_1d,
    ca_cfar_2d,
    cfar_1d,
    cfar_2d,
    cfar_threshold_factor,
    group_peaks,
    os_cfar_1d,
    os_cfar_2d,
)
from simcore.dsp.detections import (
    DETECTION_DTYPE,
    DETECTION_UNITS,
    Detections,
    spherical_to_radar_xyz,
    transform_points,
)
from simcore.dsp.maps import (
    bird_eye_axes,
    bird_eye_image,
    range_azimuth_power,
    range_doppler_power,
    range_profile_power,
)
from simcore.dsp.microdoppler import (
    Spectrogram,
    SpectrogramBuffer,
    doppler_column_from_map,
    frame_spectrogram,
    gate_bins,
    stft_spectrogram,
)
from simcore.dsp.peaks import parabolic_peak_offset
from simcore.dsp.processing import (
    RadarAxes,
    RadarProducts,
    process_frame,
    radar_axes,
    static_axes_items,
)
from simcore.dsp.spectrum import (
    compensate_tdm_doppler,
    doppler_fft,
    range_axis_m,
    range_fft,
    remove_static_clutter,
    velocity_axis_mps,
)
from simcore.dsp.vitals import (
    VitalSigns,
    VitalSignsBuffer,
    estimate_vital_signs,
    frame_slow_time,
    select_vital_bin,
)
from simcore.dsp.windows import make_window, power_to_db
from simcore.scene.dsp_config import DspConfig

__all__ = [
    "DETECTION_DTYPE",
    "DETECTION_UNITS",
    "ArrayLayout",
    "CfarResult",
    "Detections",
    "DspConfig",
    "RadarAxes",
    "RadarProducts",
    "Spectrogram",
    "SpectrogramBuffer",
    "VitalSigns",
    "VitalSignsBuffer",
    "antenna_positions_m",
    "array_layout",
    "bartlett_spectrum",
    "bird_eye_axes",
    "bird_eye_image",
    "ca_cfar_1d",
    "ca_cfar_2d",
    "capon_spectrum",
    "cfar_1d",
    "cfar_2d",
    "cfar_threshold_factor",
    "compensate_tdm_doppler",
    "direction_vectors",
    "doppler_column_from_map",
    "doppler_fft",
    "estimate_angles",
    "estimate_vital_signs",
    "fft_azimuth_power",
    "fft_beamform",
    "frame_slow_time",
    "frame_spectrogram",
    "gate_bins",
    "group_peaks",
    "interpolate_fft_power",
    "make_window",
    "monopulse_azimuth_rad",
    "monopulse_direction_cosine",
    "os_cfar_1d",
    "os_cfar_2d",
    "parabolic_peak_offset",
    "power_to_db",
    "process_frame",
    "radar_axes",
    "range_axis_m",
    "range_azimuth_power",
    "range_doppler_power",
    "range_fft",
    "range_profile_power",
    "remove_static_clutter",
    "select_vital_bin",
    "spatial_covariance",
    "spherical_to_radar_xyz",
    "static_axes_items",
    "steering_vectors",
    "stft_spectrogram",
    "transform_points",
    "velocity_axis_mps",
    "virtual_array_positions_m",
]
