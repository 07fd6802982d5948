"""The RGB camera as a registered sensor (optional: on when a project sets ``rig.rgb``)."""

from __future__ import annotations

import dataclasses

import numpy as np

from simcore.render.renderer import RenderRequest
from simcore.scene.model import Project
from simcore.scene.people.expand import body_part_table
from simcore.scene.project_io import material_table
from simcore.scene.rgb_config import RgbCameraConfig
from simcore.sensors.base import H5Items, SensorBase, SensorContext, config_key
from simcore.sensors.rgb.camera import BAND, RgbOutput, object_colors, simulate_rgb
from simcore.sensors.rgb.schema import SCHEMA


class RgbSensor(SensorBase):
    """Colour camera (``rig.rgb`` or a named one): the visible band seen from the camera."""

    kind = "rgb"
    schema = SCHEMA
    band = BAND
    on_worker = False

    def _config(self, project: Project) -> RgbCameraConfig:
        cfg = project.sensor_configs().get(self.name)
        if cfg is None:
            raise ValueError(f"the project has no RGB camera {self.name!r}"
                             + (" (rig.rgb is not set)" if self.name == "rgb" else ""))
        assert isinstance(cfg, RgbCameraConfig)
        return cfg

    def render_request(self, project: Project) -> RenderRequest:
        """The visible-band pass from the camera, one render pixel per image pixel."""
        return RenderRequest(self.name, self.band, self._config(project).render_intrinsics())

    def see_through(self, project: Project) -> tuple[bool, ...] | None:
        """No second pass: the band's objects are opaque or invisible (opacity 0)."""
        return None

    def sample_offsets_s(self, project: Project) -> tuple[float, ...]:
        """No extra renders."""
        return ()

    def simulate(self, ctx: SensorContext) -> RgbOutput:
        """The colour image of the frame's render."""
        cfg = self._config(ctx.project)
        out: RgbOutput = ctx.stage(
            "rgb", lambda: simulate_rgb(ctx.buffers, cfg,
                                        object_colors(ctx.project.objects,
                                                      material_table(ctx.project, copy=False))),
            reads=(config_key(cfg), config_key(*ctx.project.materials),
                   config_key(*ctx.project.objects)),
            inputs=(ctx.buffers,))
        parts = body_part_table(ctx.project)
        if np.any(parts >= 0):  # people: per-pixel body part beside the object id
            table = np.append(parts, np.int32(-1))
            out = dataclasses.replace(
                out, gt_body_part=np.ascontiguousarray(table[ctx.buffers.object_index]))
        return out

    def static_items(self, project: Project) -> H5Items:
        """No run-constant datasets."""
        return {}
