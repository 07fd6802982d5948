"""Headless per-band rendering of scene snapshots into float geometry buffers."""

from simcore.render.buffers import RenderBuffers, downsample_ground_truth
from simcore.render.renderer import SceneRenderer
from simcore.scene.camera import PinholeIntrinsics

__all__ = ["PinholeIntrinsics", "RenderBuffers", "SceneRenderer", "downsample_ground_truth"]
