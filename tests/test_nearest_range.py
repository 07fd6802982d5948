"""Nearest range of an object from the radar (issue #34): analytic box and sphere answers."""

from __future__ import annotations

import numpy as np
import pytest

from simcore.render.meshes import build_mesh
from simcore.scene import Project
from simcore.scene.geometry import Box, Sphere
from simcore.scene.ground_truth import nearest_range, object_ground_truth
from simcore.scene.snapshot import take_snapshot


def _truth(objects: list[dict]) -> object:
    """Ground truth of a project whose radar sits at the origin looking along world +x."""
    project = Project.model_validate({**Project().model_dump(), "objects": objects})
    snap = take_snapshot(project, 0.0)
    radar = snap.sensors["radar"]
    assert np.allclose(radar.position, 0.0) and np.allclose(radar.rotation[:, 2], [1, 0, 0])
    meshes = [build_mesh(o.geometry) for o in project.objects]
    return object_ground_truth(project, snap, [m.points for m in meshes],
                               local_triangles=[m.triangles for m in meshes])


def _obj(name: str, geometry: dict, position: tuple[float, float, float]) -> dict:
    return {"id": 1, "name": name, "geometry": geometry, "pose": {"position_m": position}}


def test_a_box_centred_at_2_m_is_seen_from_its_front_face_at_1_75_m():
    truth = _truth([_obj("box", {"kind": "box", "size_m": (0.5, 0.5, 0.5)}, (2.0, 0.0, 0.0))])
    assert truth.radar_range_m[0] == pytest.approx(2.0)          # reference point: centre
    assert truth.radar_nearest_range_m[0] == pytest.approx(1.75, abs=1e-6)  # front face
    # Its nearest corner is farther: the face's middle, not a vertex, is what counts.
    assert np.sqrt(1.75**2 + 2 * 0.25**2) > 1.75 + 0.03


def test_an_off_axis_box_is_nearest_at_the_clamped_point():
    lo, hi = np.array([1.5, 0.4, -0.3]), np.array([2.1, 1.0, 0.3])
    centre, size = (lo + hi) / 2, hi - lo
    truth = _truth([_obj("box", {"kind": "box", "size_m": tuple(size)}, tuple(centre))])
    closest = np.clip(np.zeros(3), lo, hi)                      # analytic: (1.5, 0.4, 0)
    # The mesh's vertices are float32 (VTK): 1e-6 m.
    assert truth.radar_nearest_range_m[0] == pytest.approx(np.linalg.norm(closest), abs=1e-6)


def test_a_sphere_is_nearest_one_radius_before_its_centre():
    r, d = 0.3, 3.0
    truth = _truth([_obj("ball", {"kind": "sphere", "radius_m": r}, (d, 0.0, 0.0))])
    # The mesh lies inside the sphere (vertices on it): never nearer than d − r, and its
    # facets deviate from the sphere by less than 1 cm at this size.
    assert d - r - 1e-9 <= truth.radar_nearest_range_m[0] <= d - r + 0.01


def test_without_triangles_the_nearest_vertex_counts():
    pts = np.array([[1.0, -1, -1], [1, 1, -1], [1, 1, 1], [1, -1, 1]])
    assert nearest_range(np.zeros(3), pts) == pytest.approx(np.sqrt(3.0))
    assert nearest_range(np.zeros(3), pts, np.array([[0, 1, 2], [0, 2, 3]])) == 1.0
    assert np.isnan(nearest_range(np.zeros(3), np.zeros((0, 3))))


@pytest.mark.parametrize("seed", range(5))
def test_nearest_point_on_random_triangles_matches_dense_sampling(seed):
    rng = np.random.default_rng(seed)
    pts = rng.normal(size=(30, 3)) + np.array([2.0, 0.0, 0.0])
    tris = rng.integers(0, 30, size=(20, 3))
    tris = tris[(tris[:, 0] != tris[:, 1]) & (tris[:, 1] != tris[:, 2])
                & (tris[:, 0] != tris[:, 2])]
    origin = rng.normal(size=3) * 0.3
    got = nearest_range(origin, pts, tris)
    # Exact reference: the minimum of a fine barycentric sampling of every triangle,
    # which can only be at or above the true minimum, and within the sampling step of it.
    n = 200
    u, v = np.meshgrid(np.linspace(0, 1, n + 1), np.linspace(0, 1, n + 1))
    keep = u + v <= 1
    u, v = u[keep], v[keep]
    a, b, c = pts[tris[:, 0]], pts[tris[:, 1]], pts[tris[:, 2]]
    samples = (a[:, None] + u[None, :, None] * (b - a)[:, None]
               + v[None, :, None] * (c - a)[:, None])
    sampled = np.sqrt(np.min(np.sum((samples - origin) ** 2, axis=2)))
    step = np.max(np.linalg.norm(np.concatenate([b - a, c - a, c - b]), axis=1)) / n
    assert got <= sampled + 1e-12
    assert got >= sampled - step


def test_a_box_geometry_mesh_has_the_box_faces():
    mesh = build_mesh(Box(size_m=(0.5, 0.5, 0.5)))
    assert mesh is not None and np.allclose(np.abs(mesh.points), 0.25)
    assert build_mesh(Sphere(radius_m=0.3)) is not None


def test_truth_cache_gives_the_uncached_truth_as_objects_and_the_radar_move():
    """Frames of a still box, a moving box and a point target, the rig still then moving:
    the truth computed with the cache of still objects equals the truth computed afresh
    (bit for bit), and the still box's nearest range follows the moving radar."""
    from simcore.scene.ground_truth import TruthCache

    objects = [_obj("still", {"kind": "box", "size_m": (0.5, 0.5, 0.5)}, (2.0, 0.0, 0.0)),
               {**_obj("mover", {"kind": "box", "size_m": (0.2, 0.2, 0.2)}, (3.0, 1.0, 0.0)),
                "id": 2, "motion": {"velocity_mps": (0.0, -0.5, 0.0)}},
               {**_obj("point", {"kind": "point_target", "rcs_m2": 1.0}, (4.0, -1.0, 0.5)),
                "id": 3}]
    data = {**Project().model_dump(), "objects": objects}
    data["rig"]["motion"] = {"keyframes": [
        {"time_s": 0.0}, {"time_s": 1.0}, {"time_s": 2.0, "position_m": (0.3, 0.4, 0.1)}]}
    project = Project.model_validate(data)
    meshes = [None if o.geometry.kind == "point_target" else build_mesh(o.geometry)
              for o in project.objects]
    points = [None if m is None else m.points for m in meshes]
    triangles = [None if m is None else m.triangles for m in meshes]
    cache = TruthCache()
    kept = []
    for t in (0.0, 0.5, 1.0, 1.5, 2.0, 2.0, 0.5):
        snap = take_snapshot(project, t)
        cached = object_ground_truth(project, snap, points, local_triangles=triangles,
                                     cache=cache)
        kept.append(cache._objects.get(0))
        fresh = object_ground_truth(project, snap, points, local_triangles=triangles)
        for name in fresh.__dataclass_fields__:
            assert np.array_equal(getattr(cached, name), getattr(fresh, name),
                                  equal_nan=True), (t, name)
        radar = snap.sensors["radar"].position
        closest = np.clip(radar, [1.75, -0.25, -0.25], [2.25, 0.25, 0.25])
        assert cached.radar_nearest_range_m[0] == pytest.approx(
            np.linalg.norm(closest - radar), abs=1e-6)
    # The still box was kept while it stayed (not re-made every frame).
    assert kept[0] is kept[1] is kept[2] is kept[6]


def test_the_compiled_search_equals_the_vectorised_closest_points_on_random_triangles():
    """The compiled triangle loop against the vectorised Ericson reference (every triangle,
    no culling): random triangles, points near and far, degenerate (zero-area) ones too."""
    from simcore.scene.ground_truth import _closest_on_triangles, nearest_ranges

    rng = np.random.default_rng(3)
    for n in (1, 5, 200):
        pts = rng.normal(size=(3 * n, 3))
        tris = np.arange(3 * n).reshape(n, 3)
        if n > 1:
            pts[3:6] = pts[3]                                  # a point-like triangle
            pts[7] = pts[6] + 0.5 * (pts[8] - pts[6])          # a segment-like one
        for o in (np.zeros(3), rng.normal(size=3) * 3, pts[0] + 1e-3):
            a, b, c = pts[tris[:, 0]], pts[tris[:, 1]], pts[tris[:, 2]]
            reference = np.min(np.linalg.norm(_closest_on_triangles(o, a, b, c) - o, axis=1))
            got = nearest_ranges(o, [(pts, tris)])[0]
            assert got == pytest.approx(reference, rel=1e-12, abs=1e-12)
