"""Outputs every sensor kind shares: its capture flags and times (a slower sensor)."""

from __future__ import annotations

from simcore.scene.layout import Output

#: Written when a project's sensors capture at different rates or offsets
#: (``/<sensor>/captured``, ``/<sensor>/time``).
TIMING_OUTPUTS = (
    Output("captured", (), "1", "bool", optional=True,
           description="whether the sensor captured in this frame"),
    Output("time", (), "s", "float64", optional=True,
           description="the sensor's capture time in this frame"),
)
