"""Headless renderer against analytic geometry."""

from __future__ import annotations

import numpy as np
import pytest
from scenes import wall_project

from simcore.render import PinholeIntrinsics, RenderRequest
from simcore.scene import Box, Motion, Plane, Pose, Project, SceneObject, Sphere
from simcore.scene.materials import BandMaterial, DualBandMaterial
from simcore.scene.model import SensorRig
from simcore.scene.snapshot import take_snapshot

TOF = PinholeIntrinsics.from_fov(448, 342, 62, 45)
RADAR = PinholeIntrinsics.from_fov(1000, 342, 100)


def unit_rays(intr: PinholeIntrinsics) -> np.ndarray:
    rays = intr.ray_directions()
    return rays / np.linalg.norm(rays, axis=-1, keepdims=True)


@pytest.mark.parametrize(("band", "intr"), [("tof", TOF), ("radar", RADAR)])
def test_wall_range_matches_analytic_per_pixel(make_renderer, band, intr):
    project = wall_project(2.0)
    buf = make_renderer(project).render(take_snapshot(project, 0.0),
                                        RenderRequest(band, band, intr))
    assert buf.valid.all(), "the wall fills the whole field of view"
    # A plane at z = 2 in the optical frame: range = 2 / cos(off-axis angle).
    expected = 2.0 / unit_rays(intr)[..., 2]
    np.testing.assert_allclose(buf.range_m, expected, atol=1e-3, rtol=0)
    np.testing.assert_allclose(buf.points_m[..., 2], 2.0, atol=1e-3)
    np.testing.assert_allclose(buf.normals, np.broadcast_to([0, 0, -1.0], buf.normals.shape),
                               atol=1e-6)
    np.testing.assert_allclose(buf.cos_incidence, unit_rays(intr)[..., 2], atol=1e-5)


def test_sphere_silhouette_and_range(make_renderer):
    radius, dist = 0.5, 3.0
    project = Project(objects=[SceneObject(id=3, name="ball", geometry=Sphere(radius_m=radius),
                                           pose=Pose(position_m=(dist, 0.2, -0.1)))])
    buf = make_renderer(project).render(take_snapshot(project, 0.0),
                                        RenderRequest("tof", "tof", TOF))
    centre = np.array([-0.2, 0.1, dist])  # optical frame: x right (= -y world), y down
    d = unit_rays(TOF)
    along = d @ centre
    miss2 = np.sum(centre**2) - along**2
    hit = miss2 < radius**2
    # Silhouette: any disagreement lies within one pixel of the analytic limb.
    pixel_angle = 1.0 / TOF.fx
    limb_distance = np.abs(np.sqrt(np.maximum(miss2, 0)) - radius) / along.clip(1e-9)
    disagree = hit != buf.valid
    assert disagree.sum() < 0.01 * hit.sum()
    assert np.all(limb_distance[disagree] < 1.5 * pixel_angle)
    both = hit & buf.valid
    expected = along - np.sqrt(np.maximum(radius**2 - miss2, 0))
    assert np.max(np.abs(buf.range_m[both] - expected[both])) < 1e-3
    assert set(np.unique(buf.object_id[buf.valid])) == {3}


def test_radar_transparent_object_absent_from_radar_pass(make_renderer):
    invisible = DualBandMaterial(name="radar_invisible_card",
                                 bands={"tof": BandMaterial(reflectance=0.8),
                                        "radar": BandMaterial(opacity=0.0)})
    ir_clear = DualBandMaterial(name="ir_invisible_sheet", bands={"tof": BandMaterial(opacity=0.0)})
    project = Project(materials=[invisible, ir_clear], objects=[
        SceneObject(id=1, name="wall", geometry=Box(size_m=(0.2, 40, 30)),
                    pose=Pose(position_m=(4.1, 0, 0)), material="concrete"),
        SceneObject(id=2, name="box", geometry=Box(size_m=(0.3, 0.6, 0.6)),
                    pose=Pose(position_m=(2.0, 0, 0)), material="radar_invisible_card"),
        SceneObject(id=3, name="pane", geometry=Box(size_m=(0.01, 0.6, 0.6)),
                    pose=Pose(position_m=(1.0, 1.0, 0)), material="ir_invisible_sheet"),
    ])
    renderer = make_renderer(project)
    snap = take_snapshot(project, 0.0)
    tof = renderer.render(snap, RenderRequest("tof", "tof", TOF))
    radar = renderer.render(snap, RenderRequest("radar", "radar", RADAR))
    assert 2 in tof.object_id and 2 not in radar.object_id
    assert 3 in radar.object_id and 3 not in tof.object_id
    # Behind the invisible box the radar sees the wall at 4 m on boresight.
    r, c = RADAR.height // 2, RADAR.width // 2
    assert radar.object_id[r, c] == 1
    assert abs(radar.range_m[r, c] - 4.0) < 2e-3
    assert abs(tof.range_m[TOF.height // 2, TOF.width // 2] - 1.85) < 2e-3


def test_moving_plate_radial_velocity(make_renderer):
    v = np.array([1.5, -0.4, 0.3])
    project = Project(objects=[SceneObject(
        id=1, name="plate", geometry=Plane(size_m=(3.0, 3.0)),
        pose=Pose(position_m=(2.0, 0, 0), rotation_deg=(0, 90, 0)),
        motion=Motion(velocity_mps=tuple(v)))])
    buf = make_renderer(project).render(take_snapshot(project, 0.0),
                                        RenderRequest("tof", "tof", TOF))
    world_from_optical = take_snapshot(project, 0.0).sensors["tof"].rotation
    dirs = unit_rays(TOF) @ world_from_optical.T
    expected = dirs @ v
    assert buf.valid.sum() > 1000
    np.testing.assert_allclose(buf.radial_velocity_mps[buf.valid], expected[buf.valid],
                               atol=1e-5)


def test_rotating_plate_and_moving_rig_velocity(make_renderer):
    w = np.array([0.0, 0.0, 0.8])          # rad/s about world z through the plate centre
    v_rig = np.array([0.5, 0.2, 0.0])
    centre = np.array([2.5, 0.0, 0.0])
    project = Project(
        objects=[SceneObject(id=1, name="plate", geometry=Plane(size_m=(2.0, 2.0)),
                             pose=Pose(position_m=tuple(centre), rotation_deg=(0, 90, 0)),
                             motion=Motion(angular_velocity_dps=tuple(np.rad2deg(w))))],
        rig=SensorRig(motion=Motion(velocity_mps=tuple(v_rig))),
    )
    buf = make_renderer(project).render(take_snapshot(project, 0.0),
                                        RenderRequest("tof", "tof", TOF))
    rot = take_snapshot(project, 0.0).sensors["tof"].rotation
    dirs = unit_rays(TOF) @ rot.T
    points = buf.range_m[..., None] * dirs
    expected = np.einsum("hwk,hwk->hw", np.cross(w, points - centre) - v_rig, dirs)
    np.testing.assert_allclose(buf.radial_velocity_mps[buf.valid], expected[buf.valid],
                               atol=1e-5)


def test_render_window_is_reused(make_renderer):
    project = wall_project(2.0)
    renderer = make_renderer(project)
    renderer.render(take_snapshot(project, 0.0), RenderRequest("tof", "tof", TOF))
    window = renderer._passes["tof"].window
    renderer.render(take_snapshot(project, 0.1), RenderRequest("tof", "tof", TOF))
    assert renderer._passes["tof"].window is window
    assert renderer.render_count == 2


def test_see_through_pass_renders_only_where_a_hidden_object_shows(make_renderer):
    """The see-through pass: the wall behind a hidden pane, everywhere, from a moving rig.

    Rendered only in the pane's bounding box and shaded only where the labels differ from
    the full pass (same instant); the result is the analytic wall at 4 m in every pixel.
    """
    project = Project(
        objects=[
            SceneObject(id=1, name="wall", geometry=Box(size_m=(0.2, 40, 30)),
                        pose=Pose(position_m=(4.1, 0, 0)), material="concrete"),
            SceneObject(id=2, name="pane", geometry=Box(size_m=(0.02, 0.6, 0.4)),
                        pose=Pose(position_m=(2.0, 0.5, 0.1)), material="glass"),
        ],
        rig=SensorRig(motion=Motion(velocity_mps=(0.3, 0.1, 0.0))))
    renderer = make_renderer(project)
    snap = take_snapshot(project, 0.0)
    request = RenderRequest("radar", "radar", RADAR, geometry_only=True)
    full = renderer.rasterize(snap, request)
    full_buffers = renderer.shade(full)
    assert 2 in full_buffers.object_id, "the pane is in view"
    count = renderer.render_count
    through = renderer.rasterize_see_through(full, request, (False, True))
    assert renderer.render_count == count + 1
    buffers = renderer.shade(through, background=(full, full_buffers))
    assert set(np.unique(buffers.object_id)) == {1}
    np.testing.assert_allclose(buffers.range_m, 4.0 / unit_rays(RADAR)[..., 2], atol=1e-3)
    # With the pane behind the rig nothing hidden shows: no render, the same labels.
    project.objects[1].pose = Pose(position_m=(-2.0, 0.0, 0.0))
    away = take_snapshot(project, 0.0)
    full = renderer.rasterize(away, request)
    count = renderer.render_count
    through = renderer.rasterize_see_through(full, request, (False, True))
    assert renderer.render_count == count and through.labels is full.labels


def test_still_objects_cached_pass_equals_one_full_pass(make_renderer):
    """Still objects drawn once, then only the moving ones over them: the same labels.

    A box slides along the wall with its front face in the wall's plane (depth ties), in
    front of a still sphere and between still objects in the object order. Each snapshot's
    labels equal those of a fresh renderer that draws everything in one pass (the exact
    reference), with and without the moving box hidden.
    """
    project = Project(
        objects=[
            SceneObject(id=1, name="wall", geometry=Box(size_m=(0.2, 40, 30)),
                        pose=Pose(position_m=(4.1, 0, 0)), material="concrete"),
            SceneObject(id=2, name="slider", geometry=Box(size_m=(0.2, 0.8, 0.8)),
                        pose=Pose(position_m=(4.1, -0.6, 0.0)), material="aluminium",
                        motion=Motion(velocity_mps=(0.0, 2.0, 0.0))),
            SceneObject(id=3, name="ball", geometry=Sphere(radius_m=0.3),
                        pose=Pose(position_m=(3.0, 0.0, 0.1)), material="aluminium"),
        ])
    request = RenderRequest("radar", "radar", RADAR, geometry_only=True)
    renderer = make_renderer(project)
    for step in range(6):
        snap = take_snapshot(project, 0.1 * step)
        for hide in (None, (False, True, False)):
            labels = renderer.rasterize(snap, request, hide=hide).labels
            reference = make_renderer(project).rasterize(snap, request, hide=hide).labels
            np.testing.assert_array_equal(labels, reference, err_msg=f"{step} {hide}")
    pass_ = renderer._passes["radar"]
    assert [c.moving for c in pass_.chunks] == [False, True, False]
    assert pass_._still is not None, "the cached still pass was used"


@pytest.mark.parametrize("case", ["leaves the view", "passes through the camera"])
def test_moving_objects_box_read_back_equals_one_full_pass(make_renderer, monkeypatch, case):
    """Over the cached still pass only the moving objects' pixel box is read back and merged.

    A sphere either slides sideways across the view and out of it (a box at the image edge,
    then an empty one: no draw at all), or flies through the camera (vertices behind the
    near plane: the whole image). Every snapshot's labels equal those of a fresh renderer
    that draws everything in one pass, and each kind of box occurred.
    """
    motion = (Motion(velocity_mps=(0.0, 4.0, 0.0)) if case == "leaves the view"
              else Motion(velocity_mps=(-2.0, 0.0, 0.0)))
    start = (3.0, -0.6, 0.2) if case == "leaves the view" else (1.5, 0.1, 0.05)
    project = Project(
        objects=[
            SceneObject(id=1, name="wall", geometry=Box(size_m=(0.2, 40, 30)),
                        pose=Pose(position_m=(4.1, 0, 0)), material="concrete"),
            SceneObject(id=2, name="ball", geometry=Sphere(radius_m=0.4),
                        pose=Pose(position_m=start), material="aluminium", motion=motion),
            SceneObject(id=3, name="post", geometry=Box(size_m=(0.3, 0.3, 2.0)),
                        pose=Pose(position_m=(2.5, 0.4, 0.0)), material="aluminium"),
        ])
    request = RenderRequest("radar", "radar", RADAR, geometry_only=True)
    renderer = make_renderer(project)
    renderer.rasterize(take_snapshot(project, 0.0), request)
    renderer.rasterize(take_snapshot(project, 0.05), request)      # the still view, twice
    pass_ = renderer._passes["radar"]
    boxes: list[tuple[int, int, int, int] | None] = []
    real_box = pass_._moving_box

    def recorded(*args):
        boxes.append(real_box(*args))
        return boxes[-1]

    monkeypatch.setattr(pass_, "_moving_box", recorded)
    times = np.arange(0.1, 2.6, 0.1) if case == "leaves the view" else np.arange(0.1, 1.3, 0.1)
    for t in times:
        snap = take_snapshot(project, float(t))
        labels = renderer.rasterize(snap, request).labels
        reference = make_renderer(project).rasterize(snap, request).labels
        np.testing.assert_array_equal(labels, reference, err_msg=f"t={t:.1f}")
    full = (0, RADAR.height, 0, RADAR.width)
    if case == "leaves the view":
        assert any(b is not None and b[0] < b[1] and b[2] < b[3] and b != full for b in boxes)
        assert any(b is not None and (b[0] == b[1] or b[2] == b[3]) for b in boxes)
        assert all(b is not None for b in boxes)
    else:
        assert None in boxes


def _ellipsoid_distance(p: np.ndarray, radii) -> np.ndarray:
    """Distance of points ``p`` (N, 3) to an ellipsoid's surface: the nearest point is
    ``x_i = r_i² p_i / (t + r_i²)`` with Σ (r_i p_i / (t + r_i²))² = 1, decreasing in
    t > −min r_i², solved by bisection; where that root is not in the bracket (a point inside,
    on the plane of its shortest axis) the surface point on the ray from the centre, an
    upper bound."""
    r2 = np.asarray(radii, dtype=np.float64) ** 2
    lo = np.full(len(p), -r2.min())
    hi = np.full(len(p), np.linalg.norm(p, axis=1) * np.sqrt(r2.max()) + 1e-9)
    with np.errstate(divide="ignore", invalid="ignore"):
        for _ in range(200):
            t = 0.5 * (lo + hi)
            f = np.sum((np.sqrt(r2) * p / (t[:, None] + r2)) ** 2, axis=1) - 1.0
            lo, hi = np.where(f > 0, t, lo), np.where(f > 0, hi, t)
        nearest = r2 * p / ((0.5 * (lo + hi))[:, None] + r2)
    exact = np.linalg.norm(p - nearest, axis=1)
    rho = np.linalg.norm(p / np.sqrt(r2), axis=1)
    radial = np.linalg.norm(p, axis=1) * np.abs(1.0 - 1.0 / rho)
    return np.where(np.isfinite(exact), np.minimum(exact, radial), radial)


def _triangle_samples(mesh) -> np.ndarray:
    """A barycentric grid of points on every triangle of ``mesh``, shape (N, 3)."""
    steps = np.linspace(0.0, 1.0, 9)
    bary = np.array([(a, b, 1 - a - b) for a in steps for b in steps if a + b <= 1 + 1e-12])
    return np.einsum("kc,tcd->tkd", bary, mesh.points[mesh.triangles]).reshape(-1, 3)


def test_ellipsoid_distance_helper_against_spheres_and_axes():
    p = np.array([[0.0, 0.0, 2.0], [0.5, 0.0, 0.0], [0.3, 0.4, 0.0]])
    np.testing.assert_allclose(_ellipsoid_distance(p, (1.0, 1.0, 1.0)), [1.0, 0.5, 0.5])
    p = np.array([[3.0, 0.0, 0.0], [0.0, 0.0, 2.5], [0.0, 1.5, 0.0]])
    np.testing.assert_allclose(_ellipsoid_distance(p, (1.0, 2.0, 3.0)), [2.0, 0.5, 0.5])


@pytest.mark.parametrize("radii", [(0.018, 0.047, 0.097), (0.072, 0.072, 0.22),
                                   (0.112, 0.171, 0.142), (0.3, 0.05, 0.05),
                                   (0.03, 0.02, 0.35), (1.0, 0.8, 0.5)])
def test_ellipsoid_triangles_lie_within_the_tolerance_of_the_ellipsoid(radii):
    """Every point of every triangle (a barycentric grid of each) lies within the
    tessellation tolerance of the exact ellipsoid, and within the gap bound at other
    resolutions too; vertices on the surface with its exact normals."""
    from vtkmodules.util.numpy_support import vtk_to_numpy
    from vtkmodules.vtkFiltersSources import vtkSphereSource

    from simcore.render.meshes import (
        ELLIPSOID_TOLERANCE_M,
        build_mesh,
        ellipsoid_gap_bound,
        ellipsoid_resolution,
    )
    from simcore.scene.geometry import Ellipsoid

    r = np.asarray(radii)
    mesh = build_mesh(Ellipsoid(radii_m=radii))
    gap = _ellipsoid_distance(_triangle_samples(mesh), r)
    assert gap.max() <= ELLIPSOID_TOLERANCE_M
    n_theta, n_phi = ellipsoid_resolution(radii)
    assert len(mesh.triangles) == 2 * n_theta * (n_phi - 2)           # a UV sphere's
    np.testing.assert_allclose(np.linalg.norm(mesh.points / r, axis=1), 1.0, atol=1e-9)
    grad = mesh.points / r**2               # the gradient of (x/a)² + (y/b)² + (z/c)²
    np.testing.assert_allclose(mesh.normals, grad / np.linalg.norm(grad, axis=1)[:, None],
                               atol=1e-9)
    for n_theta, n_phi in ((8, 4), (12, 9), (28, 14)):
        src = vtkSphereSource()
        src.SetThetaResolution(n_theta)
        src.SetPhiResolution(n_phi)
        src.Update()
        unit = vtk_to_numpy(src.GetOutput().GetPoints().GetData()).astype(np.float64)
        tris = vtk_to_numpy(src.GetOutput().GetPolys().GetConnectivityArray()).reshape(-1, 3)
        coarse = type(mesh)(unit / 0.5 * r, unit, tris.astype(np.int64))   # radius 0.5
        measured = _ellipsoid_distance(_triangle_samples(coarse), r).max()
        assert measured <= ellipsoid_gap_bound(radii, n_theta, n_phi)


def test_small_ellipsoids_get_fewer_triangles_than_large_ones():
    """The tessellation follows the size: a hand's ellipsoid is cut coarser than a thigh's,
    and a 1 m ellipsoid finer than both (the same tolerance on each)."""
    from simcore.render.meshes import ellipsoid_resolution

    def triangles(radii):
        n_theta, n_phi = ellipsoid_resolution(radii)
        return n_theta * (n_phi - 2)

    assert triangles((0.018, 0.047, 0.097)) < triangles((0.072, 0.072, 0.22)) \
        < triangles((1.0, 0.8, 0.5))
