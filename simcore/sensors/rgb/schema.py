"""The RGB camera's outputs, declared once (:mod:`simcore.sensors.schema`)."""

from __future__ import annotations

from simcore.scene.layout import Output, SensorSchema
from simcore.sensors.timing_outputs import TIMING_OUTPUTS

SCHEMA = SensorSchema(
    kind="rgb",
    outputs=(
        Output("image", ("rgb_row", "rgb_col", "color"), "sRGB", "uint8", finite=True,
               topic="image", message="sensor_msgs/msg/Image",
               description="sRGB colour image"),
        Output("gt_object_id", ("rgb_row", "rgb_col"), "1", "int32",
               description="id of the object seen in each pixel, −1 = none"),
        Output("gt_body_part", ("rgb_row", "rgb_col"), "1", "int32", optional=True,
               description="body part seen in each pixel (projects with people), −1 = none"),
        *TIMING_OUTPUTS,
    ),
    derived_topics={"camera_info": "sensor_msgs/msg/CameraInfo"},
)
