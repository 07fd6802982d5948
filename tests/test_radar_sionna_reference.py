"""The room's own multipath returns against an independent polarimetric ray tracer.

``resources/references/sionna_room_paths.npz`` holds Sionna RT 2.2's paths (specular
reflections up to three bounces, ITU-R P.2040 concrete and metal at 60 GHz, isotropic
V-polarised antennas) from a radar back to itself in a 6 × 4 × 3 m concrete room, with and
without a metal left wall, computed by ``tools/references/sionna/room_paths.py`` in its
own environment (not a dependency of the package). tofradar's room returns
(:func:`simcore.sensors.radar.room.room_returns`) for the same room must reproduce every
multiple-bounce path Sionna finds within 20 dB of the front wall's direct return within
±3 cm of range and 3 dB; and every return of tofradar's that strong must be one of
Sionna's, except the room's edges and corners (dihedral and trihedral images), which
Sionna does not trace in this exactly monostatic geometry (their reflection points lie on
the edges). Levels compare as Sionna's path coefficient |a|
(:func:`simcore.report.sionna.tofradar_room_paths`).
"""

from __future__ import annotations

import numpy as np
import pytest

from simcore.report.sionna import REFERENCE, compare, tofradar_room_paths


def _edge_lengths(ref: np.lib.npyio.NpzFile) -> np.ndarray:
    """Path lengths of the room's edges (double images) and corners (triple images)."""
    radar, room = ref["radar_m"], ref["room_m"]
    gaps = np.stack([radar, room - radar])                     # distances to the faces
    out = [2 * np.hypot(a, b) for i in range(3) for j in range(i + 1, 3)
           for a in gaps[:, i] for b in gaps[:, j]]
    out += [2 * np.sqrt(a * a + b * b + c * c) for a in gaps[:, 0] for b in gaps[:, 1]
            for c in gaps[:, 2]]
    return np.array(out)


@pytest.mark.parametrize("scene", ["concrete", "metal_left"])
def test_room_returns_match_sionna(scene: str) -> None:
    ref = np.load(REFERENCE)
    res = compare(ref, scene)
    assert len(res["paths"]) >= 6
    for row in res["paths"]:
        assert row["tofradar_db"] is not None, f"Sionna's path at {row['range_m']:.3f} m"
        assert abs(row["range_error_cm"]) <= 3.0
        assert abs(row["tofradar_db"] - row["sionna_db"]) < 3.0, row
    # No strong return of tofradar's where Sionna has none (edges and corners aside).
    s_len = ref[f"{scene}_length_m"]
    front = 10 ** (res["front_db"] / 20)
    edges = _edge_lengths(ref)
    t_len, t_a = tofradar_room_paths(ref, metal_left=scene == "metal_left")
    for length, level in zip(t_len, t_a, strict=True):
        if level >= 0.1 * front and np.min(np.abs(edges - length)) > 1e-3:
            assert np.any(np.abs(s_len - length) <= 0.06), f"tofradar's {length / 2:.3f} m"


def test_the_report_section_draws_the_comparison(tmp_path) -> None:
    from simcore.report.sionna import sionna_section

    figures, numbers = sionna_section(tmp_path)
    assert (tmp_path / figures[0][0]).stat().st_size > 10_000
    for scene in ("concrete", "metal_left"):
        assert numbers[scene]["missing"] == 0
        assert numbers[scene]["max_level_error_db"] < 3.0
