"""The room's exchange kept for still objects equals a full recomputation (issue 42 speed)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose, assert_array_equal

from simcore.sensors.tof import room_cache
from simcore.sensors.tof.radiosity import (
    _form_factor,
    gather,
    room_from_meshes,
    surfels_from_room,
    transfer,
)


def _quad(corner, u, v):
    c, u, v = (np.asarray(x, float) for x in (corner, u, v))
    return np.array([[c, c + u, c + u + v], [c, c + u + v, c + v]])


def _mesh(quads_and_normals):
    """(points, faces, vertex normals) of separate triangles, each quad with its normal."""
    tris = np.concatenate([q for q, _ in quads_and_normals])
    normals = np.concatenate([np.repeat(np.asarray(n, float)[None], 3 * len(q), axis=0)
                              for q, n in quads_and_normals])
    pts = tris.reshape(-1, 3)
    return pts, np.arange(len(pts)).reshape(-1, 3), normals


def _box(lo, size):
    """A closed box (outward normals) with corner ``lo`` and edges ``size``."""
    x, y, z = (np.asarray(a, float) for a in ((size[0], 0, 0), (0, size[1], 0), (0, 0, size[2])))
    lo = np.asarray(lo, float)
    return _mesh([(_quad(lo, y, x), (0, 0, -1)), (_quad(lo + z, x, y), (0, 0, 1)),
                  (_quad(lo, x, z), (0, -1, 0)), (_quad(lo + y, z, x), (0, 1, 0)),
                  (_quad(lo, z, y), (-1, 0, 0)), (_quad(lo + x, y, z), (1, 0, 0))])


def _room(mover_at):
    """A 3 × 2 × 2 m room (five walls, inward), a still table and a moving box."""
    walls = _mesh([(_quad((0, 0, 0), (3, 0, 0), (0, 2, 0)), (0, 0, 1)),
                   (_quad((0, 0, 2), (0, 2, 0), (3, 0, 0)), (0, 0, -1)),
                   (_quad((3, 0, 0), (0, 2, 0), (0, 0, 2)), (-1, 0, 0)),
                   (_quad((0, 0, 0), (0, 0, 2), (3, 0, 0)), (0, 1, 0)),
                   (_quad((0, 2, 0), (3, 0, 0), (0, 0, 2)), (0, -1, 0))])
    table = _box((2.0, 0.5, 0.0), (0.6, 1.0, 0.7))
    mover = _box(mover_at, (0.3, 0.3, 1.2))
    return room_from_meshes([walls, table, mover], [0.8, 0.5, 0.6],
                            two_sided=[False, False, False])


def _full(room, patch):
    surfels = surfels_from_room(room, patch_m=patch)
    factor, distance = transfer(surfels, room)
    return surfels, factor, distance


def _same(a, b):
    """``a`` (surfels, factor, distance) equals ``b`` up to the order of the surfels."""
    sa, fa, da = a
    sb, fb, db = b
    where = {v.tobytes(): i for i, v in enumerate(sb.vertices)}
    order = np.array([where[v.tobytes()] for v in sa.vertices])
    assert len(order) == len(sb.vertices)
    assert_array_equal(fa, fb[np.ix_(order, order)])
    assert_array_equal(da, db[np.ix_(order, order)])
    assert_array_equal(sa.albedo, sb.albedo[order])


def test_a_moving_object_gives_the_exchange_of_a_full_recomputation(monkeypatch):
    monkeypatch.setattr(room_cache, "_BLOCK", {})
    patch = 0.4
    shadows = []
    for at in [(1.0, 0.8, 0.0), (1.3, 0.6, 0.0), (0.6, 1.2, 0.0), (1.3, 0.6, 0.0)]:
        room = _room(at)
        got = room_cache.room_transfer(room, patch)
        full = _full(room, patch)
        _same(got, full)
        shadows.append(int((full[1] > 0).sum()))
    assert len(set(shadows)) > 1              # the mover's shadow changes the still pairs
    assert len(room_cache._BLOCK[patch].digests) == 2          # walls and table kept


def test_an_object_that_starts_to_move_frees_the_pairs_it_shadowed(monkeypatch):
    monkeypatch.setattr(room_cache, "_BLOCK", {})
    patch = 0.4
    room_cache.room_transfer(_room((1.0, 0.8, 0.0)), patch)        # every object still
    room = _room((0.2, 0.2, 0.0))
    _same(room_cache.room_transfer(room, patch), _full(room, patch))


@pytest.mark.parametrize("pieces", [8, 20])
def test_a_fine_mesh_merges_into_clusters_with_its_form_factor(pieces):
    """A 0.2 m square cut into many small triangles: clusters keep its area and, seen from
    2 m, its form factor (the exact sum over the small triangles) within 1 %."""
    step = 0.2 / pieces
    quads = [_quad((i * step, j * step, 0), (step, 0, 0), (0, step, 0))
             for i in range(pieces) for j in range(pieces)]
    room = room_from_meshes([_mesh([(q, (0, 0, 1)) for q in quads]),
                             _mesh([(_quad((-5, -5, 2), (0, 10, 0), (10, 0, 0)), (0, 0, -1))])],
                            [0.5, 0.5], two_sided=[False, False])
    s = surfels_from_room(room, patch_m=0.25)
    square = s.centre[:, 2] < 1.0
    assert square.sum() == 1                                    # one cluster
    assert_allclose(s.area[square].sum(), 0.04, rtol=1e-12)
    p, n = np.array([0.7, -0.4, 2.0]), np.array([0.0, 0.0, -1.0])
    exact = sum(_form_factor(p, n, t) for q in quads for t in q)
    merged = _form_factor(p, n, s.vertices[square][0])
    assert_allclose(merged, exact, rtol=0.01)
    assert math.isclose(float(s.albedo[square][0]), 0.5)


def test_the_kept_gather_equals_the_full_gather(monkeypatch):
    """Receivers on the walls, the mover walking: kept + blocked + fresh = full gather."""
    monkeypatch.setattr(room_cache, "_BLOCK", {})
    monkeypatch.setattr(room_cache, "_RECEIVERS", {})
    patch = 0.4
    rng = np.random.default_rng(3)
    points = np.column_stack([rng.uniform(0.1, 2.9, 40), rng.uniform(0.1, 1.9, 40),
                              np.full(40, 1e-3)])
    normals = np.repeat([[0.0, 0.0, 1.0]], 40, axis=0)
    ks = [0.0, 2 * math.pi * 20e6 / 299_792_458.0]
    taken_off = []
    blocked = room_cache._blocked

    def spy(*args):
        out = blocked(*args)
        taken_off.append(float(np.abs(out).max()))
        return out

    monkeypatch.setattr(room_cache, "_blocked", spy)
    for at in [(1.0, 0.8, 0.0), (1.3, 0.6, 0.0), (0.6, 1.2, 0.0)]:
        room = _room(at)
        surfels, _, _ = room_cache.room_transfer(room, patch)
        exitance = np.stack([np.exp(1j * k * surfels.centre[:, 0]) * surfels.albedo
                             for k in ks])
        got = room_cache.room_gather(points, normals, surfels, room, exitance, ks,
                                     patch_m=patch)
        full = gather(points, normals, surfels, room, exitance, ks)
        assert_allclose(got, full, rtol=1e-5, atol=1e-7 * np.abs(full).max())
    assert max(taken_off) > 0                   # the mover's shadow on kept receivers
