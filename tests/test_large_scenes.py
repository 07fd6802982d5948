"""Scenes scaled to kilometres (issue #19's hostile campaign): bounded runs or refusals.

A box scaled to ~3 km made ``tofradar run`` allocate ~20 GB in the radar's surface
facets while the preflight, which counts facets by area, let it start. The facets of a
triangle must grow with its area (the preflight's model), and a scene whose facets do
not fit the memory budget must be refused with the numbers before anything is written.
"""

from __future__ import annotations

import numpy as np
import pytest
from hostile import base_project_dict, write_project

from simcore.cli import main
from simcore.sensors.radar.surfaces import FACET_EDGE_M, split_triangles


def _areas(tri: np.ndarray) -> np.ndarray:
    return 0.5 * np.linalg.norm(np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]),
                                axis=1)


@pytest.mark.parametrize("legs_m", [(4.0, 300.0), (0.5, 40.0), (1.0, 1.0), (3.0, 4.0)])
def test_facets_cover_a_triangle_in_proportion_to_its_area(legs_m):
    """Right triangle with legs a, b: pieces cover exactly a·b/2, each with an edge of at
    most 10 cm and none over 10 cm·√2, and their number is at most ~2× the area over a
    half 10 cm square (the regular n² split of the 4 × 300 m one gave 9·10⁶, 37×)."""
    a, b = legs_m
    tri = np.array([[[0.0, 0.0, 0.0], [a, 0.0, 0.0], [0.0, b, 0.0]]])
    pieces, src = split_triangles(tri, FACET_EDGE_M)
    area = a * b / 2
    assert np.all(src == 0)
    assert _areas(pieces).sum() == pytest.approx(area, rel=1e-9)
    edges = np.linalg.norm(pieces - np.roll(pieces, 1, axis=1), axis=2)
    assert edges.min(axis=1).max() <= FACET_EDGE_M * (1 + 1e-6)
    assert edges.max() <= FACET_EDGE_M * np.sqrt(2) * (1 + 1e-6)
    assert len(pieces) <= 2.5 * area / (0.5 * FACET_EDGE_M**2) + 4 * (a + b) / FACET_EDGE_M


def test_a_regular_triangle_keeps_its_n_squared_split():
    """Equilateral 1 m triangle: n = 10 per edge, exactly n² = 100 similar pieces."""
    tri = np.array([[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.5, np.sqrt(3) / 2, 0.0]]])
    pieces, _ = split_triangles(tri, FACET_EDGE_M)
    assert len(pieces) == 100
    assert _areas(pieces) == pytest.approx(np.full(100, np.sqrt(3) / 400))


def test_a_three_kilometre_box_is_refused_with_the_numbers(tmp_path, capsys):
    """A 3 km cube has 5.4·10⁷ m² of surface, ~10¹⁰ facets of 10 cm: refused by name
    with the memory it needs, before the run writes anything."""
    doc = base_project_dict()
    doc["objects"][-1]["geometry"]["size_m"] = [3000.0, 3000.0, 3000.0]
    doc["objects"][-1]["pose"]["position_m"] = [1600.0, 0.0, 1.0]
    path = write_project(doc, tmp_path / "km_box.json")
    out = tmp_path / "km_box.h5"
    code = main(["run", str(path), "--out", str(out), "--frames", "1", "--quiet"])
    err = capsys.readouterr().err
    lines = err.strip().splitlines()
    assert code == 2 and not out.exists(), err
    assert len(lines) == 1 and lines[0].startswith("tofradar: error: "), err
    assert "memory:" in err and "rig.radar scatterers" in err and "GiB" in err, err


def test_a_mesh_scaled_to_kilometres_is_refused_with_its_area(tmp_path, capsys):
    """One triangle of 1 m legs scaled by 3000: 4.5·10⁶ m² of facets (its one triangle
    said nothing of that), refused by `validate` naming the area and geometry.scale."""
    (tmp_path / "t.obj").write_text("v 0 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\n")
    doc = base_project_dict()
    doc["objects"].append({"id": 50, "name": "mesh", "pose": {"position_m": [5.0, 0, 0]},
                           "geometry": {"kind": "mesh", "path": "t.obj", "scale": 3000.0}})
    path = write_project(doc, tmp_path / "km_mesh.json")
    code = main(["validate", str(path)])
    err = capsys.readouterr().err
    assert code == 2 and len(err.strip().splitlines()) == 1, err
    assert "memory:" in err and f"{0.5 * 3000.0**2:.3g} m²" in err, err
    assert "geometry.scale" in err, err
