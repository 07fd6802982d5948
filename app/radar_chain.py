"""The radar front end and DSP run by the GUI's worker when the pipeline's frames lack them.

Once :meth:`simcore.pipeline.Simulator.frame` fills ``frame.radar`` and ``frame.dsp`` this
module is not used. Until then it runs the same simcore stages the pipeline will run
(:class:`simcore.sensors.radar.RadarFrontEnd` then :func:`simcore.dsp.process_frame`) on
the frame's radar render, keeping the front end between frames so that its scatterers are
re-used while the render is (antenna drags).
"""

from __future__ import annotations

import time
from typing import Any

from simcore.scene import Project


class RadarChain:
    """Front end + DSP for frames that carry only renders; ``None`` where unavailable."""

    def __init__(self) -> None:
        self._front_end: Any = None
        self.error: str | None = None

    def process(self, frame: Any, project: Project, timings_ms: dict[str, float]) -> Any:
        """Return :class:`simcore.dsp.RadarProducts` of ``frame`` (None if unavailable)."""
        try:
            from simcore.dsp import process_frame
            from simcore.dsp.config import DspConfig
            from simcore.pipeline import frame_rng
            from simcore.sensors.radar import RadarFrontEnd
        except ImportError as exc:
            self.error = f"radar chain not available: {exc}"
            return None
        if self._front_end is None:
            self._front_end = RadarFrontEnd(project)
        fe = self._front_end
        fe.project = project
        fe.speckle_seed = project.seed
        start = time.perf_counter()
        rng = frame_rng(project.seed, frame.index)
        # A separate stream from the ToF noise of the same frame.
        rng = type(rng)(rng.bit_generator.jumped())
        output = fe.simulate(frame.snapshot, frame.radar_buffers, rng=rng)
        mid = time.perf_counter()
        dsp_config = getattr(project, "dsp", None) or DspConfig()
        products = process_frame(output.adc, project.rig.radar, dsp_config,
                                 radar_to_world=frame.radar_buffers.sensor.transform)
        end = time.perf_counter()
        timings_ms["radar"] = (mid - start) * 1e3
        timings_ms["dsp"] = (end - mid) * 1e3
        self.error = None
        return products
