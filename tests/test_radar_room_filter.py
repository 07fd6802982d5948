"""The compiled filter of the room's face sequences drops only what the exact trace drops.

:func:`simcore.sensors.radar.room_kernel.room_candidates` tests every sequence of two or
three faces with a margin towards keeping it; the room's paths it leads to must be those of
the exhaustive search that traces every sequence in Python (``room._search``, the search
before the filter), path for path, in the same order, bit for bit. Rooms: a concrete box
room with furniture boxes (legs between faces blocked by them) and a two-sided metal panel,
the radar at random positions and orientations inside.
"""

from __future__ import annotations

import numpy as np
import pytest

from simcore.scene.materials import BandMaterial
from simcore.sensors.radar import room
from simcore.sensors.radar.reflectors import Reflector, polarization_vector

LAM = 299_792_458.0 / 61e9
FREQ = 61e9
CONCRETE = BandMaterial(reflectance=0.3, permittivity=5.3, loss_tangent=0.05)
METAL = BandMaterial(reflectance=0.0, specular=0.0, metallic=1.0)


def face(center: np.ndarray, u: np.ndarray, v: np.ndarray, normal: np.ndarray, obj: int,
         band: BandMaterial, *, two_sided: bool = False) -> Reflector:
    """A rectangle centred at ``center`` with half edges ``u``, ``v`` (world = radar frame)."""
    a, b = float(np.linalg.norm(u)), float(np.linalg.norm(v))
    return Reflector(object_index=obj, center_m=np.asarray(center, float),
                     axes=np.array([u / a, v / b]), half_size_m=np.array([a, b]),
                     normal=np.asarray(normal, float) / np.linalg.norm(normal),
                     two_sided=two_sided, gamma=complex(band.coefficients(FREQ)[0]),
                     height_rms_m=0.0, normal_speed_mps=0.0, band=band, frequency_hz=FREQ)


def box_faces(center: np.ndarray, half: np.ndarray, obj: int, band: BandMaterial, *,
              inward: bool = False) -> list[Reflector]:
    """The six faces of an axis-aligned box (outward normals, or inward for a room)."""
    eye = np.eye(3)
    out = []
    for k in range(3):
        i, j = (k + 1) % 3, (k + 2) % 3
        for sign in (1.0, -1.0):
            n = sign * eye[k] * (-1.0 if inward else 1.0)
            out.append(face(center + sign * half[k] * eye[k], half[i] * eye[i],
                            half[j] * eye[j], n, obj, band))
    return out


def furnished_room(rng: np.random.Generator) -> list[Reflector]:
    """6 × 4 × 3 m room, two desks, a cabinet and a two-sided metal panel, seen from a
    random radar pose (the faces moved into the radar's frame)."""
    faces = box_faces(np.array([0.0, 0.0, 1.5]), np.array([3.0, 2.0, 1.5]), 0, CONCRETE,
                      inward=True)
    faces += box_faces(np.array([1.5, 1.0, 0.75]), np.array([0.6, 0.4, 0.02]), 1, CONCRETE)
    faces += box_faces(np.array([-1.2, -1.3, 0.7]), np.array([0.5, 0.3, 0.7]), 2, METAL)
    faces += box_faces(np.array([0.5, -0.8, 0.4]), np.array([0.3, 0.5, 0.4]), 3, CONCRETE)
    faces.append(face(np.array([2.2, -1.0, 1.2]), np.array([0.0, 0.5, 0.0]),
                      np.array([0.0, 0.0, 0.6]), np.array([1.0, 0.0, 0.0]), 4, METAL,
                      two_sided=True))
    position = np.array([rng.uniform(-2.5, 2.5), rng.uniform(-1.6, 1.6), rng.uniform(0.3, 2.5)])
    yaw, pitch = rng.uniform(-np.pi, np.pi), rng.uniform(-0.4, 0.4)
    cy, sy, cp, sp = np.cos(yaw), np.sin(yaw), np.cos(pitch), np.sin(pitch)
    rot = np.array([[cy, -sy, 0.0], [sy, cy, 0.0], [0.0, 0.0, 1.0]]) @ np.array(
        [[cp, 0.0, sp], [0.0, 1.0, 0.0], [-sp, 0.0, cp]])          # radar axes in the world
    return [Reflector(f.object_index, (f.center_m - position) @ rot, f.axes @ rot,
                      f.half_size_m, f.normal @ rot, f.two_sided, f.gamma, 0.0, 0.0, f.band,
                      FREQ) for f in faces]


def follows(faces: list[Reflector]) -> np.ndarray:
    """``follows`` of ``room._room_paths`` (which face can come after which)."""
    corners = np.array([[f.center_m + sa * f.half_size_m[0] * f.axes[0]
                         + sb * f.half_size_m[1] * f.axes[1]
                         for sa, sb in ((-1, -1), (1, -1), (1, 1), (-1, 1))] for f in faces])
    normals = np.array([f.normal for f in faces])
    signed = np.einsum("jcd,id->ijc", corners, normals) - np.einsum(
        "id,id->i", np.array([f.center_m for f in faces]), normals)[:, None, None]
    tol = room.EDGE_TOLERANCE_M
    reach = np.any(signed > tol, axis=2) | (
        np.array([f.two_sided for f in faces])[:, None] & np.any(signed < -tol, axis=2))
    return reach & reach.T


@pytest.mark.parametrize("seed", range(6))
@pytest.mark.parametrize("max_faces", [2, 3])
def test_filtered_search_finds_the_paths_of_the_full_search(seed: int, max_faces: int) -> None:
    faces = furnished_room(np.random.default_rng(seed))
    room._room_paths.cache_clear()
    found = room._room_paths(room._key(faces), LAM, "V", max_faces)
    reference = room._search([room._face_of(k) for k in room._key(faces)],
                             follows([room._face_of(k) for k in room._key(faces)]),
                             max_faces, LAM, polarization_vector("V"))
    assert len(found) > 0
    assert [p[0] for p in found] == [p[0] for p in reference]
    for a, b in zip(found, reference, strict=True):
        for u, v in zip(a[1:4], b[1:4], strict=True):
            np.testing.assert_array_equal(u, v)
        assert a[4] == b[4]


def test_a_bare_room_has_more_paths_than_the_filter_first_holds() -> None:
    """Six faces, 108 paths at three faces (more than the 4 × faces rows the compiled pass
    starts with): the same paths as the full search."""
    faces = box_faces(np.array([0.3, -0.2, 1.2]), np.array([3.0, 2.0, 1.5]), 0, CONCRETE,
                      inward=True)
    room._room_paths.cache_clear()
    found = room._room_paths(room._key(faces), LAM, "H", 3)
    own = [room._face_of(k) for k in room._key(faces)]
    reference = room._search(own, follows(own), 3, LAM, polarization_vector("H"))
    assert len(found) > 4 * len(faces)
    assert [p[0] for p in found] == [p[0] for p in reference]
    assert [p[4] for p in found] == [p[4] for p in reference]


def test_two_faces_of_one_box_make_no_path() -> None:
    """A box on the floor, seen from aside: its side face and the floor make a concave
    edge (a dihedral: the radar's double image, found); its front and side faces meet at a
    convex edge, where no wave goes from one to the other. The reflection points of such
    sequences fall on the common edge, within the edge tolerance, and the box's bottom
    corner (side, floor, front) came out as a trihedral before (the office's paper box on
    its desk: a peak as strong as the back wall's)."""
    floor = face(np.array([0.0, 1.0, 3.0]), np.array([3.0, 0.0, 0.0]),
                 np.array([0.0, 0.0, 3.0]), np.array([0.0, -1.0, 0.0]), 0, CONCRETE)
    wall = face(np.array([0.0, 0.0, 6.0]), np.array([3.0, 0.0, 0.0]),
                np.array([0.0, 1.0, 0.0]), np.array([0.0, 0.0, -1.0]), 2, CONCRETE)
    box = box_faces(np.array([0.6, 0.8, 3.0]), np.array([0.2, 0.2, 0.2]), 1, METAL)
    faces = [floor, wall, *box]
    room._room_paths.cache_clear()
    seqs = [p[0] for p in room._room_paths(room._key(faces), LAM, "V", 3)]
    assert (0, 1) in seqs and (1, 0) in seqs                  # the floor–wall edge
    assert [s for s in seqs if sum(faces[i].object_index == 1 for i in s) > 1] == []
