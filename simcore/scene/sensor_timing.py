"""When a sensor captures: its own frame rate and trigger offset on the timeline's clock.

The timeline's frame rate is the project's base clock: frame ``i`` is at ``i / rate``. A
sensor captures in every ``n``-th frame (``n`` = the timeline's rate / the sensor's rate, a
whole number), at the frame's time plus its trigger offset; its outputs carry that capture
time. Sensors with the same rate and offset share a timestamp.
"""

from __future__ import annotations

from pydantic import Field

from simcore.scene.base import Model


class SensorTiming(Model):
    """A sensor's frame rate (``None``: the timeline's) and trigger offset."""

    frame_rate_hz: float | None = Field(
        None, gt=0, le=1e6, allow_inf_nan=False,
        description="frames per second of this sensor (Hz); None: the timeline's. Must be "
                    "the timeline's rate divided by a whole number")
    trigger_offset_s: float = Field(
        0.0, ge=0, le=1e3, allow_inf_nan=False,
        description="delay of this sensor's capture after the frame's time (s); less than "
                    "its frame period")

    def frame_divider(self, timeline_rate_hz: float) -> int:
        """Every how many timeline frames the sensor captures (ValueError if not whole)."""
        if self.frame_rate_hz is None:
            return 1
        ratio = timeline_rate_hz / self.frame_rate_hz
        n = int(round(ratio))
        if n < 1 or abs(ratio - n) > 1e-9 * max(1.0, ratio):
            raise ValueError(
                f"frame_rate_hz: {self.frame_rate_hz:g} Hz is not the timeline's "
                f"{timeline_rate_hz:g} Hz divided by a whole number (the timeline ticks at "
                "the fastest sensor's rate)")
        return n

    def captures(self, index: int, timeline_rate_hz: float) -> bool:
        """Whether the sensor captures in timeline frame ``index``."""
        return index % self.frame_divider(timeline_rate_hz) == 0
