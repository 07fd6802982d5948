"""Issue 42's radar acceptance on the office: tofradar's range profile against Sionna RT.

``resources/references/sionna_office_paths.npz`` holds the paths Sionna RT 2.2 traces
(``tools/references/sionna/scene_paths.py``, its own environment, not a dependency) through
the office exported by ``tools/references/export_scene.py --without-people`` at t = 0: the
room's and the furniture's specular returns (up to three interactions, reflections and
slab crossings, V and H) and the corner reflector behind the paper box by geometric
optics. tofradar runs the same office (no person, its radar ideal and monostatic, the
radar-band materials made smooth: the reference has no diffuse part) at the office's
multipath order 1 and at order 2; both become the same Hann-windowed, zero-padded range
profile (:mod:`simcore.report.sionna_office`, :mod:`simcore.report.sionna_targets`).

Acceptance (issue 42): every return of the reference within 20 dB of the corner
reflector's direct return or the back wall's (the wall ahead) is in tofradar's profile
within ±3 cm and 3 dB; tofradar has no coherent return within 20 dB of the stronger of
the two where the reference has none, except where Sionna finds an edge diffraction there
(a metal plate's far edge, which tofradar's physical-optics facets give and specular ray
tracing does not). At order 1 tofradar follows pairs of faces only, so the reference's
three-bounce returns are missing: that is checked to be all that is missing.
"""

from __future__ import annotations

import numpy as np
import pytest

from simcore.report.sionna_office import REFERENCE, compare_office
from simcore.report.sionna_targets import LEVEL_TOLERANCE_DB, RANGE_TOLERANCE_M


@pytest.fixture(scope="module")
def ref() -> np.lib.npyio.NpzFile:
    return np.load(REFERENCE)


def _off(rows: list[dict]) -> list[dict]:
    return [r for r in rows if r["tofradar_db"] is None
            or abs(r["range_error_cm"]) > 100 * RANGE_TOLERANCE_M
            or abs(r["tofradar_db"] - r["sionna_db"]) > LEVEL_TOLERANCE_DB]


@pytest.mark.parametrize("polarization", ["V", "H"])
def test_the_office_at_order_2_has_every_strong_return(ref, polarization: str) -> None:
    res = compare_office(ref, polarization, 2)
    assert len(res["matched"]) >= 5              # corner, back wall, its edges and corners
    assert not _off(res["matched"]), _off(res["matched"])
    assert not res["spurious"], res["spurious"]
    # What the specular reference lacks is a diffraction Sionna finds: within 3 dB of it.
    for e in res["diffraction"]:
        assert abs(e["tofradar_db"] - e["sionna_diffraction_db"]) <= LEVEL_TOLERANCE_DB, e


@pytest.mark.parametrize("polarization", ["V", "H"])
def test_the_office_at_its_own_order_misses_only_three_bounce_returns(
        ref, polarization: str) -> None:
    res = compare_office(ref, polarization, 1)
    assert not res["spurious"], res["spurious"]
    off = _off(res["matched"])
    assert all(r["tofradar_db"] is None for r in off), off       # found ones are right
    p = polarization
    half = np.asarray(ref[f"{p}_room_length_m"]) / 2
    bounces = np.asarray(ref[f"{p}_room_bounces"])
    for r in off:
        near = np.abs(half - r["range_m"]) <= RANGE_TOLERANCE_M
        assert np.any(near) and np.all(bounces[near] >= 3), r


def test_the_corner_behind_the_paper_box_is_seen_through_two_walls(ref) -> None:
    """The reference's corner return crosses the box four times (in and out of two
    walls), and its V and H levels differ by the walls' oblique TE/TM transmission
    (V enters the box's side near grazing): tofradar's within 1 dB of each."""
    assert np.all(ref["V_corner0_crossings"][ref["V_corner0_bounces"] == 0] == 4)
    levels = {}
    for p in ("V", "H"):
        res = compare_office(ref, p, 2)
        row = min(res["matched"], key=lambda r: abs(r["range_m"] - res["direct_m"]))
        assert abs(row["range_m"] - res["direct_m"]) < RANGE_TOLERANCE_M
        assert abs(row["tofradar_db"] - row["sionna_db"]) < 1.0, row
        levels[p] = row
    assert levels["H"]["sionna_db"] - levels["V"]["sionna_db"] > 5.0
