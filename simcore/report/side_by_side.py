"""Section: the ToF and radar views of one office frame side by side."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from simcore.pipeline import Frame
from simcore.report._common import (
    Figure,
    _plt,
    _save,
)
from simcore.scene.model import Project


def side_by_side(frame: Frame, project: Project, out: Path) -> tuple[Figure, dict[str, Any]]:
    """Figure 6: ToF and radar point clouds of the same frame in one 3D view."""
    plt = _plt()
    tof = frame.outputs["tof"]
    intr = project.tof().intrinsics()
    rays = intr.ray_directions()
    rays /= np.linalg.norm(rays, axis=-1, keepdims=True)
    pts = (tof.depth_m[..., None] * rays)[tof.valid]
    world = pts @ frame.snapshot.sensors["tof"].rotation.T + frame.snapshot.sensors["tof"].position
    world = world[:: max(1, len(world) // 12000)]
    det = frame.outputs["radar"].dsp.detections
    fig = plt.figure(figsize=(11, 7), constrained_layout=True)
    ax = fig.add_subplot(projection="3d")
    ax.scatter(world[:, 0], world[:, 1], world[:, 2], s=0.6, c=world[:, 2], cmap="viridis",
               alpha=0.5, label=f"ToF point cloud ({int(tof.valid.sum())} valid pixels)")
    if det.xyz_world_m is not None and len(det.range_m):
        ax.scatter(det.xyz_world_m[:, 0], det.xyz_world_m[:, 1], det.xyz_world_m[:, 2], s=40,
                   c="red", depthshade=False, label=f"radar detections ({len(det.range_m)})")
    rig = frame.snapshot.rig.origin
    ax.scatter(*rig, marker="^", s=80, c="k", label="sensor rig")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.set_zlabel("z (m)")
    ax.set_xlim(0, 6)
    ax.set_ylim(-3, 3)
    ax.set_zlim(0, 3)
    ax.view_init(elev=28, azim=-130)
    ax.set_title(f"ToF and radar of one frame, same timestamp t = {frame.time_s:.2f} s")
    ax.legend(loc="upper left", fontsize=8)
    name = "fig6_side_by_side.png"
    _save(fig, out / name)
    numbers = {"time_s": frame.time_s, "tof_points": int(tof.valid.sum()),
               "radar_detections": int(len(det.range_m)),
               "radar_time_s": float(frame.outputs["radar"].raw.time_s)}
    radar_start = frame.outputs["radar"].raw.time_s
    text = (
        f"Both sensors of one frame come from one scene snapshot at t = {frame.time_s:.2f} s "
        f"(the radar's first chirp starts at {radar_start:.2f} s): the dense ToF point "
        f"cloud ({numbers['tof_points']} valid pixels) and the sparse radar point cloud "
        f"({numbers['radar_detections']} detections) in the same world frame. The radar sees "
        f"the corner reflector that the paper box hides from the ToF camera."
    )
    return Figure(name, "ToF and radar side by side", text), numbers
