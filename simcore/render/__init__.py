"""Headless per-band rendering of scene snapshots into float geometry buffers."""

from simcore.render.buffers import RenderBuffers, downsample_ground_truth
from simcore.render.camera import PinholeIntrinsics
from simcore.render.renderer import SceneRenderer

__all__ = ["PinholeIntrinsics", "RenderBuffers", "SceneRenderer", "downsample_ground_truth"]
