"""The ToF camera's outputs, declared once (:mod:`simcore.sensors.schema`)."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np
from numpy.typing import NDArray

from simcore.scene.layout import Output, Preview, PreviewFrame, SensorSchema
from simcore.sensors.timing_outputs import TIMING_OUTPUTS

IMAGE = "sensor_msgs/msg/Image"


def angle_axes(config: Any, statics: Mapping[str, NDArray[np.generic]]) -> PreviewFrame:
    """Horizontal and vertical view angles (deg) over the image, from the camera's FoV."""
    h, v = float(config.fov_h_deg), float(config.fov_v_deg)
    return ((-h / 2, h / 2, -v / 2, v / 2), "horizontal angle (deg, right +)",
            "vertical angle (deg, up +)", False)


SCHEMA = SensorSchema(
    kind="tof",
    outputs=(
        Output("depth", ("row", "col"), "m", "float32", finite=True,
               preview=Preview("measured depth (grey: invalid)", "depth (m)", mask="valid",
                               axes=angle_axes),
               topic="depth", message=IMAGE,
               description="measured depth, 0 where invalid (as a real camera reports)"),
        Output("amplitude", ("row", "col"), "DN", "float32", finite=True,
               preview=Preview("amplitude", "amplitude (DN)", cmap="gray", axes=angle_axes),
               topic="amplitude", message=IMAGE,
               description="modulation amplitude of the correlation samples"),
        Output("intensity", ("row", "col"), "DN", "float32", finite=True,
               description="mean of the correlation samples (grey-value image)"),
        Output("valid", ("row", "col"), "1", "bool", finite=True,
               description="depth is valid (not saturated, not too dark)"),
        Output("correlation", ("tap", "row", "col"), "DN", "float32", finite=True,
               description="the four correlation samples C0..C3"),
        Output("gt_range", ("row", "col"), "m", "float32", nan=True,
               preview=Preview("ground-truth range", "range (m)", axes=angle_axes),
               description="true range along each pixel's ray, NaN where no surface"),
        Output("gt_object_id", ("row", "col"), "1", "int32",
               description="id of the object seen in each pixel, −1 = none"),
        Output("exposure_time", (), "s", "float64", finite=True,
               description="exposure time of the frame (auto-exposure)"),
        Output("gt_body_part", ("row", "col"), "1", "int32", optional=True,
               description="body part seen in each pixel (projects with people), −1 = none"),
        *TIMING_OUTPUTS,
    ),
    derived_topics={"camera_info": "sensor_msgs/msg/CameraInfo",
                    "points": "sensor_msgs/msg/PointCloud2"},
)
