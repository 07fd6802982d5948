"""ToF multipath interference against a brute-force one-bounce sum written out here.

Scene: two white walls meet in a vertical concave corner 2 m ahead of the camera, each
at 45° to the line of sight (looking into the corner of a room). The reference is the
one-bounce integral over a dense grid of patches on the walls' visible parts, built from
the geometry (not from the render): for the centre row's pixels it adds the indirect
phasors to the direct one and reads the depth from the phase.
"""

from __future__ import annotations

import numpy as np
import pytest

from simcore.render import RenderRequest, SceneRenderer
from simcore.scene import Box, Pose, Project, SceneObject
from simcore.scene.model import SensorRig
from simcore.scene.snapshot import take_snapshot
from simcore.scene.tof_config import SPEED_OF_LIGHT, TofCameraConfig
from simcore.sensors.tof.camera import simulate_tof
from simcore.sensors.tof.sensor import diffuse_albedo

CORNER_M = 2.0
LENGTH_M = 3.0
HEIGHT_M = 4.0
RHO = 0.85          # white_paint's ToF reflectance (matte: the specular part is 0.01)


def corner_project(*, corner: bool = True) -> Project:
    s = 1 / np.sqrt(2)
    walls = []
    # Left wall runs from the corner towards (−1, +1)/√2; its face looks to (−1, −1)/√2.
    for name, along, normal, yaw in (("left", (-s, s), (-s, -s), 45.0),
                                     ("right", (-s, -s), (-s, s), -45.0)):
        centre = (np.array([CORNER_M, 0.0]) + np.array(along) * LENGTH_M / 2
                  - np.array(normal) * 0.01)
        walls.append(SceneObject(
            id=len(walls) + 1, name=name, geometry=Box(size_m=(0.02, LENGTH_M, HEIGHT_M)),
            pose=Pose(position_m=(float(centre[0]), float(centre[1]), 0.0),
                      rotation_deg=(0.0, 0.0, yaw)), material="white_paint"))
    if not corner:   # one flat wall facing the camera, 2 m ahead
        walls = [SceneObject(id=1, name="flat", geometry=Box(size_m=(0.02, 6.0, HEIGHT_M)),
                             pose=Pose(position_m=(CORNER_M + 0.01, 0.0, 0.0)),
                             material="white_paint")]
    tof = TofCameraConfig(crosstalk_sigma_px=0.0)
    return Project(objects=walls, rig=SensorRig(tof=tof))


def simulate(project: Project, *, multipath: bool) -> tuple[np.ndarray, np.ndarray]:
    cfg = project.rig.tof.model_copy(update={"multipath": multipath})
    renderer = SceneRenderer(project)
    try:
        buf = renderer.render(take_snapshot(project, 0.0),
                              RenderRequest("tof", "tof", cfg.render_intrinsics()))
    finally:
        renderer.close()
    out = simulate_tof(buf, cfg, rng=np.random.default_rng(0), noise=False,
                       albedo=diffuse_albedo(project, buf))
    return out.depth_m, out.gt_range


def reference_error_m(cfg: TofCameraConfig, cols: np.ndarray, row: int) -> np.ndarray:
    """Depth error of the centre row from the one-bounce integral over dense wall patches."""
    intr = cfg.intrinsics()
    s = 1 / np.sqrt(2)
    # Optical frame: x right (= −y world), y down (= −z world), z forward (= x world).
    corner = np.array([0.0, 0.0, CORNER_M])
    walls = [(np.array([-s, 0.0, -s]), np.array([s, 0.0, -s])),    # left: along, normal
             (np.array([s, 0.0, -s]), np.array([-s, 0.0, -s]))]   # right
    step = 0.02
    patches = []
    for along, normal in walls:
        u, v = np.meshgrid(np.arange(step / 2, LENGTH_M, step),
                           np.arange(-HEIGHT_M / 2 + step / 2, HEIGHT_M / 2, step))
        pts = corner + u.reshape(-1, 1) * along + v.reshape(-1, 1) * np.array([0, 1.0, 0])
        uv = intr.project(pts)                       # senders: what the camera sees
        seen = ((uv[:, 0] >= 0) & (uv[:, 0] < intr.width)
                & (uv[:, 1] >= 0) & (uv[:, 1] < intr.height))
        patches.append((pts[seen], np.broadcast_to(normal, pts[seen].shape)))
    q = np.concatenate([p for p, _ in patches])
    nq = np.concatenate([n for _, n in patches])
    r_q = np.linalg.norm(q, axis=1)
    lit = RHO / np.pi * (nq @ np.zeros(3) - np.einsum("ij,ij->i", nq, q)) / r_q**3 * step**2
    k = 2 * np.pi * cfg.modulation_frequencies_hz[0] / SPEED_OF_LIGHT
    errors = []
    for col in cols:
        ray = np.array([(col + 0.5 - intr.cx) / intr.fx, (row + 0.5 - intr.cy) / intr.fy, 1.0])
        wall = 0 if ray[0] < 0 else 1        # left half of the image sees the left wall
        along, normal = walls[wall]
        t = (normal @ corner) / (normal @ ray)
        p = t * ray
        r_p = np.linalg.norm(p)
        d = q - p
        dist = np.linalg.norm(d, axis=1)
        cos_p = np.maximum(d @ normal, 0) / dist
        cos_q = np.maximum(-np.einsum("ij,ij->i", nq, d), 0) / dist
        indirect = RHO * lit * cos_p * cos_q / dist**2          # same units as the direct
        direct = RHO * (-(normal @ p) / r_p) / r_p**2
        total = direct * np.exp(1j * k * 2 * r_p) + np.sum(
            indirect * np.exp(1j * k * (r_q + dist + r_p)))
        measured = np.angle(total) % (2 * np.pi) / (2 * k)
        errors.append(measured - r_p)
    return np.asarray(errors)


def test_concave_corner_overestimates_depth_like_the_one_bounce_integral() -> None:
    project = corner_project()
    depth_on, gt = simulate(project, multipath=True)
    depth_off, _ = simulate(project, multipath=False)
    cfg = project.rig.tof
    row = cfg.height // 2
    cols = np.arange(8, cfg.width - 8, 6)
    cols = cols[np.abs(cols + 0.5 - cfg.width / 2) > 4]        # not the corner edge itself
    off_err = depth_off[row, cols] - gt[row, cols]
    on_err = depth_on[row, cols] - gt[row, cols]
    print("MPI depth error (mm):", np.round(on_err * 1e3, 1))
    assert np.max(np.abs(off_err)) < 2e-3, "without MPI the corner is measured right"
    assert np.all(on_err > 0), "MPI over-estimates depth on both walls"
    left, right = on_err[cols < cfg.width / 2], on_err[cols > cfg.width / 2]
    assert 0.01 < left.max() < 0.3 and 0.01 < right.max() < 0.3   # tens of mm
    ref = reference_error_m(cfg, cols, row)
    print("reference (mm):     ", np.round(ref * 1e3, 1))
    assert np.max(np.abs(on_err - ref)) < 0.2 * np.max(ref)


def test_a_flat_wall_shows_no_multipath() -> None:
    project = corner_project(corner=False)
    depth_on, gt = simulate(project, multipath=True)
    depth_off, _ = simulate(project, multipath=False)
    inner = (slice(10, -10), slice(10, -10))
    assert np.max(np.abs(depth_on[inner] - depth_off[inner])) < 1e-4


def test_multipath_needs_the_albedo() -> None:
    project = corner_project()
    cfg = project.rig.tof.model_copy(update={"multipath": True})
    renderer = SceneRenderer(project)
    try:
        buf = renderer.render(take_snapshot(project, 0.0),
                              RenderRequest("tof", "tof", cfg.render_intrinsics()))
    finally:
        renderer.close()
    with pytest.raises(ValueError, match="albedo"):
        simulate_tof(buf, cfg, rng=np.random.default_rng(0))
