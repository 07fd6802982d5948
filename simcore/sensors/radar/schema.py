"""The radar's outputs, declared once (:mod:`simcore.sensors.schema`)."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np
from numpy.typing import NDArray

from simcore.scene.layout import Output, Preview, PreviewFrame, SensorSchema
from simcore.sensors.timing_outputs import TIMING_OUTPUTS


def _edges(centres: NDArray[np.generic]) -> tuple[float, float]:
    """Outer edges of a regular axis given its bin centres."""
    c = np.asarray(centres, dtype=np.float64)
    if len(c) < 2:
        mid = float(c[0]) if len(c) else 0.0
        return mid - 0.5, mid + 0.5
    step = float(c[1] - c[0])
    return float(c[0]) - step / 2, float(c[-1]) + step / 2


def range_velocity_axes(config: Any, statics: Mapping[str, NDArray[np.generic]]
                        ) -> PreviewFrame | None:
    """Range (m) across, radial velocity (m/s) up, from the radar's axes."""
    if "range_axis" not in statics or "velocity_axis" not in statics:
        return None
    return ((*_edges(statics["range_axis"]), *_edges(statics["velocity_axis"])),
            "range (m)", "radial velocity (m/s, away +)", True)


def range_azimuth_axes(config: Any, statics: Mapping[str, NDArray[np.generic]]
                       ) -> PreviewFrame | None:
    """Range (m) across, azimuth (deg) up, from the radar's axes."""
    if "range_axis" not in statics or "azimuth_axis" not in statics:
        return None
    return ((*_edges(statics["range_axis"]), *_edges(statics["azimuth_axis"])),
            "range (m)", "azimuth (deg, right +)", True)


#: Object truth a radar adds: ``/objects/radar_<field>`` for the built-in radar,
#: ``/objects/<name>/<field>`` for another (and under ``/people/segments``).
TRUTH = (
    Output("range", ("object",), "m", "float64", description="range of the reference point"),
    Output("radial_velocity", ("object",), "m/s", "float64",
           description="radial velocity of the reference point (away +)"),
    Output("azimuth", ("object",), "deg", "float64", description="azimuth (right +)"),
    Output("elevation", ("object",), "deg", "float64", description="elevation (up +)"),
)

SCHEMA = SensorSchema(
    kind="radar",
    outputs=(
        Output("adc", ("chirp", "channel", "sample"), "FS", "float32|complex64", finite=True,
               topic="adc", message="tofradar_msgs/msg/RadarCube",
               description="raw ADC cube (real IF or complex IQ), full scale = 1"),
        Output("chirp_start_time", ("chirp", "tx"), "s", "float64", finite=True,
               description="start time of each chirp of each Tx after the frame's time"),
        Output("inr_db", (), "dB", "float64", optional=True,
               description="interference-to-noise ratio of the frame (other radars)"),
        Output("range_axis", ("range",), "m", "float64", per_frame=False, coord="range",
               description="range bin centres"),
        Output("velocity_axis", ("velocity",), "m/s", "float64", per_frame=False,
               coord="velocity", description="Doppler bin centres (away +)"),
        Output("azimuth_axis", ("azimuth",), "deg", "float64", per_frame=False,
               coord="azimuth", description="azimuth grid of the range–azimuth map"),
        Output("bird_eye_x_axis", ("bev_x",), "m", "float64", per_frame=False, coord="bev_x",
               description="lateral axis of the bird's-eye map"),
        Output("bird_eye_z_axis", ("bev_z",), "m", "float64", per_frame=False, coord="bev_z",
               description="forward axis of the bird's-eye map"),
        Output("range_profile", ("channel", "range"), "dB", "float32",
               description="range FFT power per channel, chirps averaged"),
        Output("range_profile_integrated", ("range",), "dB", "float32",
               description="range profile integrated over channels"),
        Output("range_doppler", ("velocity", "range"), "dB", "float32",
               preview=Preview("range–Doppler", "power (dB)", cmap="magma",
                               axes=range_velocity_axes),
               topic="range_doppler", message="tofradar_msgs/msg/RangeDopplerMap",
               description="range–Doppler map"),
        Output("range_azimuth", ("azimuth", "range"), "dB", "float32",
               preview=Preview("range–azimuth", "power (dB)", cmap="magma",
                               axes=range_azimuth_axes),
               description="range–azimuth map"),
        Output("bird_eye", ("bev_z", "bev_x"), "dB", "float32", nan=True,
               description="bird's-eye (x, z) map, NaN outside the field of view"),
        Output("detections", ("detection",), "", "record", per_frame=False,
               topic="detections", message="sensor_msgs/msg/PointCloud2",
               description="CFAR detections of every frame (one table)"),
        Output("detections_by_frame", ("slot",), "", "record",
               description="the detections per frame, padded (valid up to the count)"),
        Output("detections_count", (), "1", "int64", description="detections in the frame"),
        Output("spectrogram/power", ("spectrogram_time", "spectrogram_velocity"), "dB",
               "float32", per_frame=False, product=True,
               description="micro-Doppler spectrogram (tofradar products)"),
        Output("spectrogram/time", ("spectrogram_time",), "s", "float64", per_frame=False,
               product=True, coord="spectrogram_time", description="spectrogram time axis"),
        Output("spectrogram/velocity_axis", ("spectrogram_velocity",), "m/s", "float64",
               per_frame=False, product=True, coord="spectrogram_velocity",
               description="spectrogram velocity axis"),
        Output("spectrogram/gate_center", ("frame",), "m", "float64", per_frame=False,
               product=True, description="range gate of the spectrogram in each frame"),
        *(Output(f"vitals/{name}", ("frame",), unit, "float64", per_frame=False,
                 product=True, nan=True, description=f"vital signs: {name}")
          for name, unit in (("time", "s"), ("displacement", "m"), ("breathing_rate", "Hz"),
                             ("breathing_amplitude", "m"), ("heart_rate", "Hz"),
                             ("heart_amplitude", "m"))),
        *TIMING_OUTPUTS,
    ),
    tables=("detections",),
    truth=TRUTH,
)
