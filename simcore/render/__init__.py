"""Headless per-band rendering of scene snapshots into float geometry buffers."""

from simcore.render.buffers import RenderBuffers, downsample_ground_truth
from simcore.render.renderer import RenderRequest, SceneRenderer, render_once
from simcore.scene.camera import PinholeIntrinsics

__all__ = ["PinholeIntrinsics", "RenderBuffers", "RenderRequest", "SceneRenderer",
           "downsample_ground_truth", "render_once"]
