"""ToF multipath from the whole room (surfel radiosity) against radiative-transfer formulas."""

from __future__ import annotations

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose

from simcore.scene.tof_config import SPEED_OF_LIGHT
from simcore.sensors.tof.radiosity import (
    Room,
    _exchange,
    _form_factor,
    _segment_clear,
    facing_any,
    gather,
    occluder_boxes,
    radiosity,
    room_from_meshes,
    surfels_from_room,
    transfer,
)


def _quad(corner, u, v):
    """Two triangles of the rectangle corner + [0, 1]·u + [0, 1]·v, shape (2, 3, 3)."""
    c, u, v = (np.asarray(x, float) for x in (corner, u, v))
    return np.array([[c, c + u, c + u + v], [c, c + u + v, c + v]])


def _mesh(tris, outward):
    """A (points, faces, vertex normals) mesh of separate triangles facing ``outward``."""
    pts = tris.reshape(-1, 3)
    faces = np.arange(len(pts)).reshape(-1, 3)
    return pts, faces, np.repeat(np.asarray(outward, float)[None, :], len(pts), axis=0)


def _parallel_corner(x, y):
    """Form factor from a point to a parallel rectangle x × y (unit distance) above a corner.

    Howell's catalogue, configuration B-3.
    """
    a, b = math.sqrt(1 + x * x), math.sqrt(1 + y * y)
    return (x / a * math.atan(y / a) + y / b * math.atan(x / b)) / (2 * math.pi)


def _parallel_plates(x, y):
    """Form factor between two equal, coaxial, parallel rectangles (Howell C-11), X=a/c, Y=b/c."""
    a, b = 1 + x * x, 1 + y * y
    return 2 / (math.pi * x * y) * (
        0.5 * math.log(a * b / (1 + x * x + y * y)) + x * math.sqrt(b) * math.atan(x / math.sqrt(b))
        + y * math.sqrt(a) * math.atan(y / math.sqrt(a)) - x * math.atan(x) - y * math.atan(y))


@pytest.mark.parametrize(("x", "y"), [(0.5, 0.5), (1.0, 2.0), (3.0, 0.2)])
def test_point_to_rectangle_form_factor_is_howells(x, y):
    p, n = np.zeros(3), np.array([0.0, 0.0, 1.0])
    ff = sum(_form_factor(p, n, t) for t in _quad((0, 0, 1), (x, 0, 0), (0, y, 0)))
    assert_allclose(ff, _parallel_corner(x, y), rtol=1e-9)


@pytest.mark.parametrize("height", [0.1, 0.5, 0.9])
def test_form_factors_inside_a_closed_box_add_up_to_one(height):
    """A point inside a cube sees its whole hemisphere: the faces cut by its horizon too."""
    p, n = np.array([0.3, 0.6, height]), np.array([0.0, 0.0, 1.0])
    faces = [_quad((0, 0, 0), (1, 0, 0), (0, 1, 0)), _quad((0, 0, 1), (1, 0, 0), (0, 1, 0)),
             _quad((0, 0, 0), (1, 0, 0), (0, 0, 1)), _quad((0, 1, 0), (1, 0, 0), (0, 0, 1)),
             _quad((0, 0, 0), (0, 1, 0), (0, 0, 1)), _quad((1, 0, 0), (0, 1, 0), (0, 0, 1))]
    total = sum(_form_factor(p, n, t) for quad in faces for t in quad)
    assert_allclose(total, 1.0, rtol=1e-9)


def test_far_surfel_uses_the_point_form_factor_within_one_percent():
    tri = _quad((0, 0, 0), (0.1, 0, 0), (0, 0.1, 0))[:1]
    centre = tri.mean(axis=1)
    normal = np.array([[0.0, 0.0, 1.0]])
    size = np.array([0.1 * math.sqrt(2)])
    area = np.array([0.005])
    p, n = centre[0] + np.array([0.3, 0.2, 0.6]), np.array([0.0, -0.6, -0.8])
    exact = _form_factor(p, n, tri[0])
    approx = _exchange(p, n, 0, centre, normal, tri, area, size)
    assert exact > 0
    assert_allclose(approx, exact, rtol=0.01)
    assert _exchange(p, -n, 0, centre, normal, tri, area, size) == 0.0   # faces away


def test_segment_blocked_by_a_triangle_between_and_not_by_one_beside():
    wall = _quad((1, -1, -1), (0, 2, 0), (0, 0, 2)).astype(float)
    room = room_from_meshes([_mesh(wall, (-1, 0, 0))], [0.5], two_sided=[False])
    lo, hi = occluder_boxes(room)
    args = (room.triangles, room.occluder_start, lo, hi)
    assert not _segment_clear(np.zeros(3), np.array([2.0, 0.1, 0.2]), *args)
    assert _segment_clear(np.zeros(3), np.array([2.0, 3.0, 0.2]), *args)
    assert _segment_clear(np.zeros(3), np.array([0.9, 0.1, 0.2]), *args)   # stops short


def _plates(gap, side=1.0, patch=0.125, blocker=False):
    """Two coaxial parallel squares ``gap`` apart facing each other (+ a blocking plate)."""
    lower = _quad((0, 0, 0), (side, 0, 0), (0, side, 0))
    upper = _quad((0, 0, gap), (0, side, 0), (side, 0, 0))
    meshes = [_mesh(lower, (0, 0, 1)), _mesh(upper, (0, 0, -1))]
    if blocker:
        meshes.append(_mesh(_quad((-1, -1, gap / 2), (3, 0, 0), (0, 3, 0)), (0, 0, 1)))
    room = room_from_meshes(meshes, [0.8, 0.6, 0.5][:len(meshes)],
                            two_sided=[False, False, True][:len(meshes)])
    return room, surfels_from_room(room, patch_m=patch)


@pytest.mark.parametrize("gap", [0.5, 1.0, 2.0])
def test_facing_plates_exchange_howells_form_factor(gap):
    """Power from a uniformly lit plate onto a facing one: A₁ F₁₂ M₁ (reciprocity, C-11)."""
    room, s = _plates(gap)
    factor, distance = transfer(s, room)
    lower = s.normal[:, 2] > 0
    emitted = np.where(lower, 1.0, 0.0)[None, :].astype(complex)
    total = radiosity(factor, distance, s.albedo, emitted, [0.0], bounces=2)
    received = (total[0].real / s.albedo)[~lower] @ s.area[~lower]     # Σ E_i A_i on plate 2
    assert_allclose(received, _parallel_plates(1 / gap, 1 / gap), rtol=0.02)


def test_second_bounce_carries_its_path_length_as_phase():
    """Two small facing patches: the light back on patch 1 after two bounces is
    ``ρ₁ ρ₂ F₁₂ F₂₁ M e^{i k 2d}`` (both legs in the phase)."""
    d = 1.5
    room, s = _plates(d, side=0.05, patch=0.05)
    factor, distance = transfer(s, room)
    k = 2 * math.pi * 20e6 / SPEED_OF_LIGHT
    lower = s.normal[:, 2] > 0
    emitted = np.where(lower, 1.0, 0.0)[None, :].astype(complex)
    third = radiosity(factor, distance, s.albedo, emitted, [k], bounces=3)
    second = radiosity(factor, distance, s.albedo, emitted, [k], bounces=2)
    back = (third - second)[0, lower]                  # the third order, on patch 1
    f = _parallel_plates(0.05 / d, 0.05 / d)           # F₁₂ = F₂₁ (equal areas)
    expected = 0.8 * 0.6 * f * f * np.exp(2j * k * d)
    assert_allclose(back.sum() / lower.sum(), expected, rtol=0.03)
    assert_allclose(np.angle(back.mean() / expected), 0.0, atol=2e-3)


def test_series_to_convergence_solves_the_radiosity_equation():
    room, s = _plates(0.5, patch=0.25)
    factor, distance = transfer(s, room)
    k = 2 * math.pi * 20e6 / SPEED_OF_LIGHT
    rng = np.random.default_rng(1)
    emitted = (rng.random(len(s.area)) * np.exp(1j * rng.random(len(s.area))))[None, :]
    total = radiosity(factor, distance, s.albedo, emitted, [k], tolerance=1e-12)
    kernel = factor * np.exp(1j * k * distance) * s.albedo[:, None]
    exact = np.linalg.solve(np.eye(len(s.area)) - kernel, emitted[0])
    assert_allclose(total[0], exact, rtol=1e-5, atol=1e-9)


def test_occluder_between_plates_stops_the_exchange():
    room, s = _plates(1.0, blocker=True)
    factor, _ = transfer(s, room)
    plates = np.abs(s.centre[:, 2] - 0.5) > 0.1
    assert factor[np.ix_(plates, plates)].max() == 0.0
    assert factor[np.ix_(~plates, plates)].max() > 0.0          # the blocker sees both


def test_gather_at_a_point_is_the_form_factor_times_exitance():
    """Uniform exitance of a plate above a point: E = M F (Howell B-3, four corners);
    surfels beyond FAR_SIZES use the point form factor (within 1 %)."""
    room, s = _plates(1.0)
    exitance = np.where(s.normal[:, 2] < 0, 2.0, 0.0)[None, :].astype(complex)
    p = np.array([[0.5, 0.5, 0.0]])
    got = gather(p, np.array([[0.0, 0.0, 1.0]]), s, room, exitance, [0.0])
    assert_allclose(got[0, 0].real, 2.0 * 4 * _parallel_corner(0.5, 0.5), rtol=0.01)


def test_room_outer_faces_face_nothing():
    """A closed box seen from inside: its outward faces face no other triangle."""
    inner = [(_quad((0, 0, 0), (0, 1, 0), (1, 0, 0)), (0, 0, 1)),
             (_quad((0, 0, 1), (1, 0, 0), (0, 1, 0)), (0, 0, -1))]
    tris = np.concatenate([t for t, _ in inner])
    normals = np.concatenate([np.repeat(np.asarray(n, float)[None], 2, axis=0)
                              for _, n in inner])
    assert facing_any(tris, normals).all()
    assert not facing_any(tris, -normals).any()


def test_surfels_tile_the_triangles():
    room = Room(_quad((0, 0, 0), (2.0, 0, 0), (0, 0.3, 0)), np.array([[0, 0, 1.0]] * 2),
                np.array([0.5, 0.5]), np.array([0, 2]))
    room2 = room_from_meshes([_mesh(room.triangles, (0, 0, 1)),
                              _mesh(_quad((0, 0, 1), (0, 1, 0), (1, 0, 0)), (0, 0, -1))],
                             [0.5, 0.5], two_sided=[False, False])
    s = surfels_from_room(room2, patch_m=0.1)
    assert_allclose(s.area.sum(), 2.0 * 0.3 + 1.0)
    assert s.size.max() <= 0.1 * math.sqrt(2) + 1e-12


def test_too_many_surfels_is_one_clear_error(monkeypatch):
    from simcore.sensors.tof import radiosity as module
    from simcore.sensors.tof import room_cache

    room, _ = _plates(1.0)
    monkeypatch.setattr(module, "MAX_TRANSFER_BYTES", 1000)
    with pytest.raises(ValueError, match=r"multipath_surfel_m = 0.05 m .* use larger surfels"):
        room_cache._room_transfer(room, 0.05)
