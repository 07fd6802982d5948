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

from simcore.render import RenderBuffers, RenderRequest, render_once
from simcore.scene import Box, Pose, Project, SceneObject
from simcore.scene.model import SensorRig
from simcore.scene.tof_config import SPEED_OF_LIGHT, TofCameraConfig
from simcore.sensors.tof.camera import simulate_tof
from simcore.sensors.tof.sensor import diffuse_albedo, tof_bands

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


def tof_render(project: Project, cfg: TofCameraConfig) -> RenderBuffers:
    """The ToF render of ``project`` at t = 0 with ``cfg``'s intrinsics."""
    return render_once(project, RenderRequest("tof", "tof", cfg.render_intrinsics()))


def simulate(project: Project, *, multipath: bool) -> tuple[np.ndarray, np.ndarray]:
    cfg = project.rig.tof.model_copy(update={"multipath": multipath})
    buf = tof_render(project, cfg)
    out = simulate_tof(buf, cfg, rng=np.random.default_rng(0), noise=False,
                       albedo=diffuse_albedo(tof_bands(project), buf))
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
    buf = tof_render(project, cfg)
    with pytest.raises(ValueError, match="albedo"):
        simulate_tof(buf, cfg, rng=np.random.default_rng(0))


def _corner_depths(step: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Ideal depth with the fast multipath (``step``), the exact sum (step 1) and none."""
    import simcore.sensors.tof.camera as cam

    project = corner_project()
    cfg = project.rig.tof.model_copy(update={"multipath": True})
    buf = tof_render(project, cfg)
    albedo = diffuse_albedo(tof_bands(project), buf)
    depths = []
    for s in (step, 1):
        planes = cam._multipath_planes(buf, cfg, albedo, receiver_step=s)
        depths.append(_depth_with(buf, cfg, planes))
    off = simulate_tof(buf, cfg.model_copy(update={"multipath": False}),
                       rng=np.random.default_rng(0), noise=False).depth_m
    return depths[0], depths[1], off


def _depth_with(buf, cfg, planes):  # type: ignore[no-untyped-def]
    """Depth of the ideal camera with the given indirect planes (phase of the phasor sum)."""
    import simcore.sensors.tof.camera as cam

    r, signal, _ = cam._sample_signal(buf, cfg)
    k = cfg.supersampling
    phase = r * np.float32(4 * np.pi * cfg.modulation_frequencies_hz[0] / SPEED_OF_LIGHT)
    m = signal * np.float32(cfg.demodulation_contrast)
    re = cam._block_mean(m * np.cos(phase), k) + planes[1]
    im = cam._block_mean(m * np.sin(phase), k) + planes[2]
    return (np.mod(np.arctan2(im, re), 2 * np.pi)
            * SPEED_OF_LIGHT / (4 * np.pi * cfg.modulation_frequencies_hz[0]))


def test_fast_multipath_matches_the_exact_sum_at_the_corner() -> None:
    """The coarse-grid sum with surface-aware interpolation keeps the corner bias (10 %)."""
    fast, exact, off = _corner_depths(4)
    bias_fast, bias_exact = fast - off, exact - off
    row = bias_exact.shape[0] // 2
    cols = np.arange(8, bias_exact.shape[1] - 8)
    cols = cols[np.abs(cols + 0.5 - bias_exact.shape[1] / 2) > 4]
    ref = bias_exact[row, cols]
    assert ref.max() > 0.02
    assert np.max(np.abs(bias_fast[row, cols] - ref)) < 0.1 * ref.max()
    inner = (slice(8, -8), slice(8, -8))
    assert abs(bias_fast[inner].mean() - bias_exact[inner].mean()) < 0.1 * bias_exact[inner].mean()


def test_compiled_pair_sums_equal_the_numpy_sum() -> None:
    """The compiled kernel is the numpy one-bounce sum with the receiver's leg taken out."""
    from simcore.sensors.tof.multipath import Senders, _reduced, one_bounce

    rng = np.random.default_rng(3)
    pts = rng.uniform(-1, 1, (50, 3)).astype(np.float32) + np.float32([0, 0, 3])
    nrm = rng.normal(size=(50, 3)).astype(np.float32)
    nrm /= np.linalg.norm(nrm, axis=1, keepdims=True)
    q = rng.uniform(-1, 1, (70, 3)).astype(np.float32) + np.float32([0, 0, 3])
    nq = rng.normal(size=(70, 3)).astype(np.float32)
    nq /= np.linalg.norm(nq, axis=1, keepdims=True)
    senders = Senders(points_m=q, normals=nq, weight=rng.uniform(0, 1e-3, 70).astype(np.float32),
                      range_m=np.linalg.norm(q, axis=1).astype(np.float32))
    freqs = [20e6, 16e6]
    mag, ph = one_bounce(pts, nrm, senders, freqs)
    k = [2 * np.pi * f / SPEED_OF_LIGHT for f in freqs]
    got = _reduced(pts, nrm, senders, k)
    np.testing.assert_allclose(got[:, 0], mag, rtol=1e-4)
    r_p = np.linalg.norm(pts, axis=1)
    for j, (re, im) in enumerate(ph):
        want = (re + 1j * im) * np.exp(-1j * k[j] * r_p)
        np.testing.assert_allclose(got[:, 1 + 2 * j] + 1j * got[:, 2 + 2 * j], want,
                                   rtol=1e-4, atol=1e-4 * np.abs(want).max())


def test_still_scene_reuses_the_one_bounce_sums_exactly() -> None:
    """A byte-identical render reuses the sums; the exposure still scales the planes."""
    import simcore.sensors.tof.camera as cam

    project = corner_project()
    cfg = project.rig.tof.model_copy(update={"multipath": True})
    buf = tof_render(project, cfg)
    albedo = diffuse_albedo(tof_bands(project), buf)
    cam._ONE_BOUNCE_CACHE.clear()
    first = cam._multipath_planes(buf, cfg, albedo)
    calls = []
    original = cam.one_bounce_image
    try:
        cam.one_bounce_image = lambda *a, **k: calls.append(1) or original(*a, **k)
        longer = cfg.model_copy(update={"exposure_time_s": 2 * cfg.exposure_time_s})
        again = cam._multipath_planes(buf, longer, albedo)
        assert calls == [], "the still scene's sums were reused"
        np.testing.assert_allclose(again, 2 * first, rtol=1e-6)
        moved = albedo * np.float32(0.5)                  # different inputs: recomputed
        half = cam._multipath_planes(buf, cfg, moved)
        assert calls == [1]
    finally:
        cam.one_bounce_image = original
    cam._ONE_BOUNCE_CACHE.clear()
    np.testing.assert_allclose(cam._multipath_planes(buf, cfg, moved), half, rtol=1e-6)


def test_a_moving_object_updates_the_sums_to_the_full_sum() -> None:
    """Frame-to-frame reuse: a box moving in front of the corner gives the full sum.

    The reference is the sum over all senders at every receiver with nothing reused
    (an empty cache); with the previous frame's sums reused, only the changed sender tiles
    and the new receivers are summed, and the result must be the same numbers.
    """
    import simcore.sensors.tof.camera as cam
    import simcore.sensors.tof.multipath as mp

    base = corner_project()
    cfg = base.rig.tof.model_copy(update={"multipath": True})
    frames = []
    for y in (0.3, 0.2):               # a small white box moves 0.1 m sideways
        box = SceneObject(id=9, name="box", geometry=Box(size_m=(0.2, 0.2, 0.2)),
                          pose=Pose(position_m=(1.2, y, 0.0)), material="white_paint")
        project = base.model_copy(update={"objects": [*base.objects, box]})
        buf = tof_render(project, cfg)
        frames.append((buf, diffuse_albedo(tof_bands(project), buf)))
    pairs: list[int] = []
    counted = mp._tile_sums

    def counting(p, n, s, k, tiles):  # type: ignore[no-untyped-def]
        bounds = s.tiles()
        pairs.append(len(p) * int(np.sum(bounds[tiles + 1] - bounds[tiles])))
        return counted(p, n, s, k, tiles)

    original = cam._ONE_BOUNCE_REUSE
    reuse = mp.OneBounceCache()
    try:
        cam._ONE_BOUNCE_REUSE = reuse
        mp._tile_sums = counting
        cam._ONE_BOUNCE_CACHE.clear()
        cam._multipath_planes(frames[0][0], cfg, frames[0][1])
        pairs.clear()
        updated = cam._multipath_planes(frames[1][0], cfg, frames[1][1])
        pairs_updated = sum(pairs)
        pairs.clear()
        reuse.clear()
        cam._ONE_BOUNCE_CACHE.clear()
        full = cam._multipath_planes(frames[1][0], cfg, frames[1][1])
        pairs_full = sum(pairs)
    finally:
        mp._tile_sums = counted
        cam._ONE_BOUNCE_REUSE = original
        cam._ONE_BOUNCE_CACHE.clear()
    assert np.abs(full).max() > 0
    # Bit-identical: a frame's output does not depend on the frames before it.
    np.testing.assert_array_equal(updated, full)
    assert pairs_updated < pairs_full / 3, "only the changed part was summed"


def test_office_corners_keep_the_reference_bias() -> None:
    """The office as shipped (multipath on): near its concave creases (wall–wall and
    wall–floor) the depth bias of the fast sum is that of the every-pixel reference sum
    (``receiver_step=1``) within 10 %, per surface and over the crease pixels."""
    import simcore.sensors.tof.camera as cam
    from simcore.render.buffers import downsample_ground_truth
    from simcore.resources import example_path
    from simcore.scene import load_project
    from simcore.sensors.tof.multipath import RECEIVER_STEP

    project = load_project(example_path("office"))
    cfg = project.rig.tof
    assert cfg.multipath, "office.json ships with ToF multipath on"
    buf = tof_render(project, cfg)
    albedo = diffuse_albedo(tof_bands(project), buf)
    cam._ONE_BOUNCE_CACHE.clear()
    cam._ONE_BOUNCE_REUSE.clear()
    off = _depth_with(buf, cfg, np.zeros((3, cfg.height, cfg.width), dtype=np.float32))
    bias = {s: _depth_with(buf, cfg, cam._multipath_planes(buf, cfg, albedo, receiver_step=s))
            - off for s in (RECEIVER_STEP, 1)}
    cam._ONE_BOUNCE_CACHE.clear()
    cam._ONE_BOUNCE_REUSE.clear()
    _, ids = downsample_ground_truth(buf, cfg.supersampling)
    surfaces = {o.name: o.id for o in project.objects
                if o.name in ("floor", "back_wall", "left_wall", "right_wall")}
    room = np.isin(ids, list(surfaces.values()))
    # Crease pixels: room surfaces with another room surface within 3 pixels.
    crease = np.zeros_like(room)
    for dy in range(-3, 4):
        for dx in range(-3, 4):
            shifted = np.roll(np.roll(ids, dy, axis=0), dx, axis=1)
            crease |= room & np.isin(shifted, list(surfaces.values())) & (shifted != ids)
    crease[:3] = crease[-3:] = False
    crease[:, :3] = crease[:, -3:] = False
    assert crease.sum() > 100
    fast, ref = bias[RECEIVER_STEP][crease], bias[1][crease]
    print(f"crease bias: fast {np.median(fast) * 1e3:.1f} mm, reference "
          f"{np.median(ref) * 1e3:.1f} mm over {crease.sum()} px")
    assert np.median(ref) > 0.005, "concave creases read long"
    assert abs(np.median(fast) - np.median(ref)) < 0.1 * np.median(ref)
    for name, oid in surfaces.items():
        seen = ids == oid
        if seen.sum() < 200:
            continue
        f_med, r_med = np.median(bias[RECEIVER_STEP][seen]), np.median(bias[1][seen])
        print(f"{name}: fast {f_med * 1e3:.1f} mm, reference {r_med * 1e3:.1f} mm")
        assert abs(f_med - r_med) < 0.1 * abs(r_med) + 1e-4, name


def test_a_longer_walk_reuses_the_receiver_rows_and_keeps_the_full_sum() -> None:
    """Over several frames every frame is bit-identical to the full sum with nothing reused,
    while the receivers' rows of tile sums live in a pool reused from frame to frame (kept
    receivers keep their row, new ones take rows the frames before freed)."""
    import simcore.sensors.tof.camera as cam
    import simcore.sensors.tof.multipath as mp

    base = corner_project()
    cfg = base.rig.tof.model_copy(update={"multipath": True})
    frames = []
    for y in (0.3, 0.2, 0.1, 0.2, 0.25):
        box = SceneObject(id=9, name="box", geometry=Box(size_m=(0.2, 0.2, 0.2)),
                          pose=Pose(position_m=(1.2, y, 0.0)), material="white_paint")
        project = base.model_copy(update={"objects": [*base.objects, box]})
        buf = tof_render(project, cfg)
        frames.append((buf, diffuse_albedo(tof_bands(project), buf)))
    original = cam._ONE_BOUNCE_REUSE
    reuse = mp.OneBounceCache()
    try:
        full = []
        for buf, albedo in frames:
            cam._ONE_BOUNCE_REUSE = mp.OneBounceCache()        # nothing to reuse
            cam._ONE_BOUNCE_CACHE.clear()
            full.append(cam._multipath_planes(buf, cfg, albedo))
        cam._ONE_BOUNCE_REUSE = reuse
        for (buf, albedo), want in zip(frames, full, strict=True):
            cam._ONE_BOUNCE_CACHE.clear()
            got = cam._multipath_planes(buf, cfg, albedo)
            assert np.abs(want).max() > 0
            np.testing.assert_array_equal(got, want)
    finally:
        cam._ONE_BOUNCE_REUSE = original
        cam._ONE_BOUNCE_CACHE.clear()
    record = next(iter(reuse._last.values()))           # the receivers' pool stays small
    assert len(record.tiles) <= 3 * int(np.sum(record.row >= 0)) + 64
