"""The compiled shading kernels against the numpy implementation they replaced.

``reference_shade_pixels`` below is the renderer's former numpy shading, kept verbatim as
the reference: the kernels must give the same fields, bit for bit (the band intensity to
within one float32 ulp, see :func:`simcore.render.shading_kernels.band_response_one`), on
a scene with every case the shading distinguishes: facets, smooth surfaces (interpolated
vertex normals), analytic spheres, moving and spinning objects, a moving and turning rig,
metallic, specular and retro-reflecting materials, background pixels and grazing facets.
"""

# ruff: noqa: D103

from __future__ import annotations

import numpy as np
import pytest
from numpy.typing import NDArray

from simcore.render import PinholeIntrinsics, RenderRequest, SceneRenderer
from simcore.render.renderer import (
    _PIXEL_FIELDS,
    Raster,
    _Geometry,
    _ray_grid,
    _shade,
    _shade_pixels,
    changed_pixels,
)
from simcore.render.shading_kernels import band_response_one, shade_geometry
from simcore.scene import Box, Cylinder, Motion, Plane, Pose, Project, SceneObject, Sphere
from simcore.scene.materials import band_response
from simcore.scene.model import SensorRig
from simcore.scene.snapshot import take_snapshot

TOF = PinholeIntrinsics.from_fov(224, 171, 62, 45)
#: The fields a geometry-only pass computes (the others are read-only zeros).
_GEOMETRY_FIELDS = ("range_m", "object_index", "object_id")
RADAR = PinholeIntrinsics.from_fov(320, 240, 100)


# --- reference: the former numpy implementation ------------------------------------------

def _pixel_rays(intr: PinholeIntrinsics, pixel: NDArray[np.intp]) -> NDArray[np.float64]:
    """Rays ``(x/z, y/z, 1)`` of the given flat pixel indices, shape (n, 3), float64."""
    rows, cols = np.divmod(pixel, intr.width)
    d = np.ones((len(pixel), 3))
    d[:, 0] = (cols + 0.5 - intr.cx) / intr.fx
    d[:, 1] = (rows + 0.5 - intr.cy) / intr.fy
    return d



def _rotate(x: NDArray[np.float64], m: NDArray[np.float64]) -> NDArray[np.float64]:
    """``x @ m`` for x of shape (n, 3), element by element.

    No BLAS: each row gets the same rounding whatever n is.
    """
    return x[:, 0:1] * m[0] + x[:, 1:2] * m[1] + x[:, 2:3] * m[2]


def reference_shade_pixels(raster: Raster, idx: NDArray[np.intp] | None
                  ) -> dict[str, NDArray[np.generic]]:
    """The numpy implementation the kernels replaced: fields of all pixels or of ``idx``."""
    snapshot, intr, geo = raster.snapshot, raster.intrinsics, raster.geometry
    tables = raster.tables
    sensor = snapshot.sensor(raster.sensor)
    transforms = snapshot.object_transforms()
    n_tri = len(geo.triangles)
    rot, origin = sensor.rotation, sensor.position
    u, v, ray_norm = _ray_grid(intr)                              # flat, (H * W,)
    label = raster.labels.ravel()                                  # 0 = background
    if idx is not None:
        u, v, ray_norm, label = u[idx], v[idx], ray_norm[idx], label[idx]

    # Per-triangle planes in the optical frame: n·X = delta, n facing the sensor; row 0
    # is the background (normal 0, delta NaN), row k + 1 triangle k.
    vertices, vnormals = geo.world_vertices(transforms)
    corners = geo.triangles
    a = vertices[corners[:, 0]]
    face = np.cross(vertices[corners[:, 1]] - a, vertices[corners[:, 2]] - a)
    face /= np.maximum(np.linalg.norm(face, axis=1, keepdims=True), 1e-300)
    n_opt = face @ rot                                           # world → optical
    delta = np.einsum("ij,ij->i", face, a - origin)
    flip = np.where(delta > 0, -1.0, 1.0)
    plane_n = np.zeros((n_tri + 1, 3), dtype=np.float32)
    plane_n[1:] = n_opt * flip[:, None]
    plane_d = np.full(n_tri + 1, np.nan, dtype=np.float32)
    plane_d[1:] = delta * flip
    normals = np.take(plane_n, label, axis=0)                    # (N, 3)
    nx, ny, nz = normals[:, 0], normals[:, 1], normals[:, 2]
    denom = nx * u
    denom += ny * v
    denom += nz
    with np.errstate(divide="ignore", invalid="ignore"):
        t = np.take(plane_d, label) / denom
    t[~(t > 0)] = np.nan                                         # grazing / behind
    valid = np.isfinite(t)
    obj = np.take(geo.label_object, label)
    obj[~valid] = -1
    pixel = np.arange(label.size) if idx is None else idx        # flat image index
    if raster.geometry_only:
        zero = np.zeros(1, dtype=np.float32)
        return {
            "range_m": t * ray_norm,
            "points_m": np.broadcast_to(zero, (label.size, 3)),
            "normals": np.broadcast_to(zero, (label.size, 3)),
            "cos_incidence": np.broadcast_to(zero, (label.size,)),
            "object_index": obj,
            "object_id": np.take(tables.ids, obj),
            "intensity": np.broadcast_to(zero, (label.size,)),
            "velocity_mps": np.broadcast_to(zero, (label.size, 3)),
            "radial_velocity_mps": np.broadcast_to(zero, (label.size,)),
        }

    # Smooth surfaces: interpolate vertex normals with barycentric weights.
    smooth = np.take(geo.label_smooth, label)
    smooth &= valid
    if smooth.any():
        _smooth_normals(geo, intr, np.flatnonzero(smooth), pixel, label, t, vertices,
                        vnormals, rot, origin, normals)
    if tables.sphere_radius.any():
        _refine_spheres(tables.sphere_radius, intr, pixel, obj, valid, origin, rot,
                        transforms, t, normals)

    points = np.empty(normals.shape, dtype=np.float32)
    np.multiply(t, u, out=points[:, 0])
    np.multiply(t, v, out=points[:, 1])
    points[:, 2] = t
    rng = t * ray_norm
    cos_inc = nx * u
    cos_inc += ny * v
    cos_inc += nz
    cos_inc /= -ray_norm
    np.clip(cos_inc, 0.0, 1.0, out=cos_inc)
    cos_inc[~valid] = 0.0

    # Exact rigid-body velocity of each surface point relative to the sensor origin:
    # v(X) = v_obj + w x (X - c) - v_sensor = (v_obj - v_sensor - w x c) + w x X.
    n_obj = len(snapshot.objects)
    lin = np.zeros((n_obj + 1, 3))
    ang = np.zeros((n_obj + 1, 3))
    if n_obj:
        v_w = np.array([s.velocity_mps for s in snapshot.objects])
        w_w = np.array([s.angular_velocity_rps for s in snapshot.objects])
        c_w = transforms[:, :3, 3] - origin
        lin[:n_obj] = (v_w - sensor.velocity_mps - np.cross(w_w, c_w)) @ rot
        ang[:n_obj] = w_w @ rot
    velocity = np.zeros(normals.shape, dtype=np.float32)
    radial = np.zeros(t.shape, dtype=np.float32)
    moving = np.any((lin != 0) | (ang != 0), axis=1)             # last row (none): False
    if moving.any():
        sel = np.flatnonzero(np.take(moving, obj))                # valid pixels only
        o = obj[sel]
        vel = lin[o]
        if np.any(ang[o]):
            vel += np.cross(ang[o], points[sel].astype(np.float64))
        velocity[sel] = vel
        rays = _pixel_rays(intr, pixel[sel])
        radial[sel] = np.einsum("ij,ij->i", vel, rays) / np.linalg.norm(rays, axis=1)

    params = {k: np.take(arr, obj) for k, arr in tables.params.items()}
    params["roughness"][~valid] = 1.0
    intensity = np.asarray(band_response(cos_inc, **params), dtype=np.float32)
    intensity[~valid] = 0.0
    return {
        "range_m": rng,
        "points_m": points,
        "normals": normals,
        "cos_incidence": cos_inc,
        "object_index": obj,
        "object_id": np.take(tables.ids, obj),
        "intensity": intensity,
        "velocity_mps": velocity,
        "radial_velocity_mps": radial,
    }


def _smooth_normals(geo: _Geometry, intr: PinholeIntrinsics, sel: NDArray[np.intp],
                    pixel: NDArray[np.intp], label: NDArray[np.uint32], t: NDArray[np.float32],
                    vertices: NDArray[np.float64], vnormals: NDArray[np.float64],
                    rot: NDArray[np.float64], origin: NDArray[np.float64],
                    normals: NDArray[np.float32]) -> None:
    """Barycentric interpolation of vertex normals on smooth triangles (in place).

    ``sel`` indexes the shaded pixels (``pixel[sel]`` are their image indices).
    """
    rays = _pixel_rays(intr, pixel[sel])
    corners = geo.triangles[label[sel].astype(np.intp) - 1]
    a, b, c = (vertices[corners[:, k]] for k in range(3))
    x = origin + _rotate(t[sel].astype(np.float64)[:, None] * rays, rot.T)  # world hits
    e1, e2, wv = b - a, c - a, x - a
    d00 = np.einsum("ij,ij->i", e1, e1)
    d01 = np.einsum("ij,ij->i", e1, e2)
    d11 = np.einsum("ij,ij->i", e2, e2)
    d20 = np.einsum("ij,ij->i", wv, e1)
    d21 = np.einsum("ij,ij->i", wv, e2)
    den = d00 * d11 - d01 * d01
    bu = np.clip((d11 * d20 - d01 * d21) / den, 0.0, 1.0)
    bv = np.clip((d00 * d21 - d01 * d20) / den, 0.0, 1.0)
    excess = np.maximum(bu + bv - 1.0, 0.0) / 2
    bu, bv = bu - excess, bv - excess
    n = _rotate((1 - bu - bv)[:, None] * vnormals[corners[:, 0]] + bu[:, None]
                * vnormals[corners[:, 1]] + bv[:, None] * vnormals[corners[:, 2]], rot)
    n /= np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-300)
    n *= np.where(np.einsum("ij,ij->i", n, rays) > 0, -1.0, 1.0)[:, None]
    normals[sel] = n


def _refine_spheres(sphere_radius: NDArray[np.float64], intr: PinholeIntrinsics,
                    pixel: NDArray[np.intp], obj: NDArray[np.int32], valid: NDArray[np.bool_],
                    origin: NDArray[np.float64], rot: NDArray[np.float64],
                    transforms: NDArray[np.float64], t: NDArray[np.float32],
                    normals: NDArray[np.float32]) -> None:
    """Replace facet hits on spheres by the exact ray–sphere intersection (in place)."""
    radius = np.take(sphere_radius, obj)
    sel = np.flatnonzero(valid & (radius > 0))
    if not sel.size:
        return
    r = radius[sel]
    centres = (transforms[:, :3, 3] - origin) @ rot               # per object, optical
    centre = centres[obj[sel]]
    d = _pixel_rays(intr, pixel[sel])
    a = np.einsum("ij,ij->i", d, d)
    b = -np.einsum("ij,ij->i", d, centre)
    c = np.einsum("ij,ij->i", centre, centre) - r**2
    disc = b * b - a * c
    ok = disc >= 0          # rays through the facets but past the true limb keep the facet
    root = (-b - np.sqrt(np.where(ok, disc, 0.0))) / a
    t_old = t[sel].astype(np.float64)
    t_sel = np.where(ok, root, t_old)
    n_sel = np.where(ok[:, None], (t_sel[:, None] * d - centre) / r[:, None], normals[sel])
    t[sel] = t_sel
    normals[sel] = n_sel


# --- the scene ---------------------------------------------------------------------------

def _scene(*, rig_moves: bool) -> Project:
    """Every kind of surface and motion the shading tells apart, in front of the rig."""
    spin = Motion(angular_velocity_dps=(10.0, -25.0, 40.0), velocity_mps=(0.2, 0.1, -0.3))
    objects = [
        SceneObject(id=1, name="wall", geometry=Box(size_m=(0.2, 5.0, 3.0)),
                    pose=Pose(position_m=(6.1, 0.0, 0.0)), material="concrete"),
        SceneObject(id=2, name="floor", geometry=Box(size_m=(10.0, 12.0, 0.1)),
                    pose=Pose(position_m=(3.0, 0.0, -1.2)), material="wood"),
        SceneObject(id=3, name="ball", geometry=Sphere(radius_m=0.45),
                    pose=Pose(position_m=(3.0, 0.8, 0.1)), material="aluminium",
                    motion=Motion(velocity_mps=(-0.5, 0.2, 0.0))),
        SceneObject(id=4, name="can", geometry=Cylinder(radius_m=0.3, height_m=1.2),
                    pose=Pose(position_m=(3.5, -1.0, -0.4), rotation_deg=(20.0, 10.0, 0.0)),
                    material="white_paint", motion=spin),
        SceneObject(id=5, name="crate", geometry=Box(size_m=(0.5, 0.6, 0.4)),
                    pose=Pose(position_m=(2.2, -0.2, -0.6), rotation_deg=(5.0, 30.0, 45.0)),
                    material="black_plastic",
                    motion=Motion(angular_velocity_dps=(0.0, 0.0, 90.0))),
        SceneObject(id=6, name="tape", geometry=Plane(size_m=(0.4, 0.3)),
                    pose=Pose(position_m=(4.0, 0.3, 0.9), rotation_deg=(0.0, 80.0, 0.0)),
                    material="ir_retroreflector_tape"),
        # Seen almost edge-on: grazing facets.
        SceneObject(id=7, name="sheet", geometry=Plane(size_m=(2.0, 1.0)),
                    pose=Pose(position_m=(2.5, 1.6, -0.5), rotation_deg=(0.0, 0.0, 0.5)),
                    material="paper"),
    ]
    rig = (SensorRig(motion=Motion(velocity_mps=(0.3, -0.1, 0.05),
                                   angular_velocity_dps=(0.0, 3.0, 8.0)))
           if rig_moves else SensorRig())
    return Project(objects=objects, rig=rig)


def _raster(renderer: SceneRenderer, project: Project, intr: PinholeIntrinsics, *,
            geometry_only: bool, time_s: float = 0.3) -> Raster:
    band = "radar" if geometry_only else "tof"
    return renderer.rasterize(take_snapshot(project, time_s),
                              RenderRequest(band, band, intr, geometry_only=geometry_only))


def _assert_same_fields(got: dict, want: dict) -> None:
    assert list(got) == list(want)
    for name, expected in want.items():
        actual = got[name]
        assert actual.dtype == expected.dtype, name
        assert actual.shape == expected.shape, name
        assert actual.flags.writeable == expected.flags.writeable, name
        if name == "intensity":
            np.testing.assert_array_max_ulp(actual, expected, maxulp=1)
        else:
            np.testing.assert_array_equal(actual, expected, err_msg=name, strict=True)
            np.testing.assert_array_equal(np.signbit(actual), np.signbit(expected),
                                          err_msg=name)


# --- tests -------------------------------------------------------------------------------

@pytest.mark.parametrize("rig_moves", [False, True])
@pytest.mark.parametrize(("intr", "geometry_only"), [(TOF, False), (RADAR, True)])
def test_kernels_match_numpy_reference(make_renderer, rig_moves, intr, geometry_only):
    project = _scene(rig_moves=rig_moves)
    raster = _raster(make_renderer(project), project, intr, geometry_only=geometry_only)
    valid = raster.labels > 0
    assert 0.3 < valid.mean() < 1.0, "the scene shows surfaces and background"
    got, want = _shade_pixels(raster, None), reference_shade_pixels(raster, None)
    if not geometry_only:
        obj = want["object_index"]
        assert {2, 3, 4, 5, 6} <= set(np.unique(obj)), "every kind of surface is in view"
        assert np.any(raster.geometry.label_smooth[raster.labels.ravel()])
    _assert_same_fields(got, want)


@pytest.mark.parametrize(("intr", "geometry_only"), [(TOF, False), (RADAR, True)])
def test_kernels_on_a_pixel_subset_match_numpy_reference(make_renderer, intr, geometry_only):
    project = _scene(rig_moves=True)
    raster = _raster(make_renderer(project), project, intr, geometry_only=geometry_only)
    idx = np.sort(np.random.default_rng(3).choice(raster.labels.size, 5000, replace=False))
    got = _shade_pixels(raster, idx)
    _assert_same_fields(got, reference_shade_pixels(raster, idx))
    full = _shade_pixels(raster, None)
    for name in _PIXEL_FIELDS:
        np.testing.assert_array_equal(got[name], np.asarray(full[name])[idx], err_msg=name)


def test_geometry_only_range_is_analytic_plane_distance(make_renderer):
    """A wall 3 m ahead: range 3 / cos(off-axis angle), object id everywhere."""
    project = Project(objects=[SceneObject(id=9, name="wall",
                                           geometry=Box(size_m=(0.2, 60.0, 60.0)),
                                           pose=Pose(position_m=(3.1, 0.0, 0.0)))])
    raster = _raster(make_renderer(project), project, RADAR, geometry_only=True, time_s=0.0)
    buf = _shade(raster)
    rays = RADAR.ray_directions()
    expected = 3.0 * np.linalg.norm(rays, axis=-1)
    np.testing.assert_allclose(buf.range_m, expected, rtol=2e-6)
    assert np.all(buf.object_id == 9) and np.all(buf.object_index == 0)
    assert not buf.normals.flags.writeable and not np.any(buf.intensity)


def test_sphere_range_and_normal_are_analytic(make_renderer):
    """Ray–sphere intersection: range and outward normal of the exact sphere."""
    centre_world, radius = np.array([2.5, -0.3, 0.2]), 0.6
    project = Project(objects=[SceneObject(id=1, name="ball", geometry=Sphere(radius_m=radius),
                                           pose=Pose(position_m=tuple(centre_world)))])
    raster = _raster(make_renderer(project), project, TOF, geometry_only=False, time_s=0.0)
    buf = _shade(raster)
    sensor = raster.snapshot.sensor("tof")
    centre = (centre_world - sensor.position) @ sensor.rotation        # optical frame
    d = TOF.ray_directions() / np.linalg.norm(TOF.ray_directions(), axis=-1, keepdims=True)
    along = d @ centre
    disc = along**2 - (centre @ centre - radius**2)
    hit = buf.valid & (disc > 1e-3)
    assert hit.sum() > 1000
    expected = along - np.sqrt(np.where(hit, disc, 0.0))
    np.testing.assert_allclose(buf.range_m[hit], expected[hit], atol=2e-6, rtol=1e-6)
    normal = (expected[..., None] * d - centre) / radius
    np.testing.assert_allclose(buf.normals[hit], normal[hit], atol=2e-6)
    np.testing.assert_allclose(buf.cos_incidence[hit], -np.sum(normal * d, -1)[hit],
                               atol=2e-6)


def test_background_shading_matches_shading_all_pixels(make_renderer):
    """A still rig: only the moving objects' pixels are shaded, the rest copied."""
    project = _scene(rig_moves=False)
    renderer = make_renderer(project)
    hide = tuple(np.any(o.motion.velocity_mps) or np.any(o.motion.angular_velocity_dps)
                 for o in project.objects)
    for intr, geometry_only in ((TOF, False), (RADAR, True)):
        band = "radar" if geometry_only else "tof"
        request = RenderRequest(band, band, intr, geometry_only=geometry_only)
        still = project.model_copy(update={"objects": [
            o.model_copy(update={"motion": Motion()}) for o in project.objects]})
        bg_raster = renderer.rasterize(take_snapshot(still, 0.3), request, hide=hide)
        background = (bg_raster, _shade(bg_raster))
        raster = renderer.rasterize(take_snapshot(still, 0.3), request)
        idx = changed_pixels(raster, background)
        assert idx is not None and 0 < idx.size
        partial, full = _shade(raster, background), _shade(raster)
        for name in _PIXEL_FIELDS:
            np.testing.assert_array_equal(getattr(partial, name), getattr(full, name),
                                          err_msg=name, strict=True)
            # Geometry-only passes leave read-only zeros, whichever way they are shaded.
            writeable = getattr(partial, name).flags.writeable
            assert writeable == getattr(full, name).flags.writeable, name
            assert writeable == (not geometry_only or name in _GEOMETRY_FIELDS), name


def test_band_response_twin_matches_numpy():
    rng = np.random.default_rng(7)
    n = 20000
    cos32 = rng.uniform(-0.1, 1.1, n).astype(np.float32)
    cos32[:50] = rng.uniform(0.0, 2e-6, 50)                  # below the 1e-6 clip
    cos32[50:60] = [0.0, 1.0, -0.0, 1e-6, 1.0, 0.5, 0.25, 0.0, 1.0, 0.999]
    params = {
        "reflectance": rng.uniform(0.0, 1.0, n),
        "specular": np.where(rng.random(n) < 0.2, 0.0, rng.uniform(0.0, 2.0, n)),
        "roughness": rng.uniform(0.01, 2.0, n),
        "metallic": np.where(rng.random(n) < 0.3, 1.0, rng.uniform(0.0, 1.0, n)),
        "retro_gain": np.where(rng.random(n) < 0.8, 0.0, rng.uniform(0.0, 100.0, n)),
    }
    want = band_response(cos32, **params)
    got = np.array([band_response_one(float(c), *(float(params[k][i]) for k in params))
                    for i, c in enumerate(cos32)], dtype=np.float32)
    np.testing.assert_array_max_ulp(got, want, maxulp=1)
    # Cosines of any float64 value (not only float32 ones) agree within float32 rounding.
    cos64 = rng.uniform(0.0, 1.0, n)
    want64 = band_response(cos64, **params)
    got64 = np.array([band_response_one(c, *(float(params[k][i]) for k in params))
                      for i, c in enumerate(cos64)], dtype=np.float32)
    np.testing.assert_array_max_ulp(got64, want64, maxulp=1)


def test_band_response_twin_known_values():
    # White Lambertian wall at normal incidence: 1; a pure mirror lobe at normal
    # incidence: specular / roughness²; a retro-reflector adds its gain at any angle.
    assert band_response_one(1.0, 1.0, 0.0, 0.3, 0.0, 0.0) == 1.0
    assert band_response_one(1.0, 0.0, 0.5, 0.2, 1.0, 0.0) == pytest.approx(0.5 / 0.04)
    assert band_response_one(0.0, 0.5, 0.0, 0.3, 0.0, 60.0) == pytest.approx(60.0, abs=1e-6)


def test_plane_hit_edge_cases_follow_ieee_division():
    """Background, grazing rays (n · ray = 0) and planes behind: as numpy divides."""
    labels = np.arange(6, dtype=np.uint32)
    plane_n = np.array([[0, 0, 0], [0, 0, -1], [1, 0, 0], [1, 0, 0], [1, 0, 0], [0, 0, 1]],
                       dtype=np.float32)
    plane_d = np.array([np.nan, -2.0, -1.0, 1.0, 0.0, -3.0], dtype=np.float32)
    u = np.zeros(6, dtype=np.float32)
    ray_norm = np.full(6, 1.5, dtype=np.float32)
    label_object = np.array([-1, 0, 0, 0, 0, 0], dtype=np.int32)
    ids = np.array([7, -1], dtype=np.int32)
    rng, obj, obj_id = shade_geometry(labels, np.zeros(0, np.int64), False, u, u, ray_norm,
                                      plane_n, plane_d, label_object, ids)
    # Hit at t = 2; -1/0 = -inf and 0/0 are no hit (NaN); 1/0 = +inf stays, not a hit.
    np.testing.assert_array_equal(rng, np.array([np.nan, 3.0, np.nan, np.inf, np.nan, np.nan],
                                                dtype=np.float32))
    np.testing.assert_array_equal(obj, [-1, 0, -1, -1, -1, -1])
    np.testing.assert_array_equal(obj_id, [-1, 7, -1, -1, -1, -1])
