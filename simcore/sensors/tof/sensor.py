"""The ToF camera as a registered sensor: its render pass and its frame."""

from __future__ import annotations

from simcore.render.renderer import RenderRequest
from simcore.scene.model import Project
from simcore.sensors.base import H5Items, SensorContext, config_key
from simcore.sensors.tof.camera import TofOutput, simulate_tof


class TofSensor:
    """AMCW ToF camera (``rig.tof``): the near-infrared band seen from the camera."""

    name = "tof"
    band = "tof"
    rng_stream = 0
    on_worker = False

    def render_request(self, project: Project) -> RenderRequest:
        """The supersampled near-infrared pass from the camera."""
        return RenderRequest(self.name, self.band, project.rig.tof.render_intrinsics())

    def sample_offsets_s(self, project: Project) -> tuple[float, ...]:
        """With motion artefacts: renders at the 2nd to 4th correlation samples' times."""
        cfg = project.rig.tof
        if not cfg.motion_artifacts:
            return ()
        return tuple(i * cfg.sample_interval_s for i in (1, 2, 3))

    def simulate(self, ctx: SensorContext) -> TofOutput:
        """The camera model over the render (and the sample renders, if any)."""
        cfg = ctx.project.rig.tof
        samples = (ctx.buffers, *ctx.sample_buffers) if ctx.sample_buffers else None
        return ctx.stage(
            "tof", lambda: simulate_tof(ctx.buffers, cfg, rng=ctx.rng, sample_buffers=samples),
            reads=(config_key(cfg), ctx.seed, ctx.index),
            inputs=(ctx.buffers, *ctx.sample_buffers))

    def static_items(self, project: Project) -> H5Items:
        """No run-constant datasets."""
        return {}
