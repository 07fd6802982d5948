"""The room's own multipath returns against an independent polarimetric ray tracer.

``tests/data/sionna_room_paths.npz`` holds Sionna RT 2.2's paths (specular reflections
up to three bounces, ITU-R P.2040 concrete and metal at 60 GHz, isotropic V-polarised
antennas) from a radar back to itself in a 6 × 4 × 3 m concrete room, with and without a
metal left wall, computed by ``tools/references/sionna/room_paths.py`` in its own
environment (not a dependency of the package). Here tofradar's room returns
(:func:`simcore.sensors.radar.room.room_returns`) for the same room must reproduce every
multiple-bounce path Sionna finds within 20 dB of the front wall's direct return, within
±3 cm of range and 3 dB; and every return of tofradar's that strong must be one of
Sionna's, except the room's edges and corners, which tofradar has and Sionna in this
exactly monostatic geometry does not trace (their reflection points lie on the edges).

Levels compare as Sionna's path coefficient ``|a|``: a return of cross-section σ at range
D (path 2D) gives ``|a| = λ √σ / ((4π)^{3/2} D²)`` (the radar equation with isotropic
antennas; an infinite plane's σ = π D² |Γ|² gives Sionna's ``λ |Γ| / (4π · 2D)``).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from simcore.scene.materials import BandMaterial
from simcore.scene.radar_config import RadarConfig
from simcore.sensors.radar.multipath import Reflector
from simcore.sensors.radar.room import room_returns

DATA = Path(__file__).parent / "data" / "sionna_room_paths.npz"
CONCRETE = BandMaterial(permittivity=5.24, loss_tangent=0.065)   # ITU-R P.2040 at 60 GHz
METAL = BandMaterial(metallic=1.0)


def reflectors(ref: np.lib.npyio.NpzFile, *, metal_left: bool) -> list[Reflector]:
    """The room's six inner faces in the radar's optical frame (radar facing +x world)."""
    radar = ref["radar_m"]
    lx, ly, lz = ref["room_m"]
    freq = float(ref["frequency_hz"])

    def point(p: tuple[float, float, float]) -> np.ndarray:
        x, y, z = np.asarray(p, dtype=float) - radar
        return np.array([-y, -z, x])                 # x right, y down, z forward

    def vector(v: tuple[float, float, float]) -> np.ndarray:
        x, y, z = v
        return np.array([-y, -z, x], dtype=float)

    def face(obj: int, center: tuple[float, float, float], u: tuple[float, float, float],
             v: tuple[float, float, float], half: tuple[float, float],
             normal: tuple[float, float, float], band: BandMaterial) -> Reflector:
        return Reflector(obj, point(center), np.array([vector(u), vector(v)]),
                         np.array(half, dtype=float), vector(normal), False,
                         complex(band.coefficients(freq)[0]), 0.0, 0.0, band=band,
                         frequency_hz=freq)

    ex, ey, ez = (1, 0, 0), (0, 1, 0), (0, 0, 1)
    return [
        face(0, (lx / 2, ly / 2, 0), ex, ey, (lx / 2, ly / 2), (0, 0, 1), CONCRETE),
        face(1, (lx / 2, ly / 2, lz), ex, ey, (lx / 2, ly / 2), (0, 0, -1), CONCRETE),
        face(2, (lx, ly / 2, lz / 2), ey, ez, (ly / 2, lz / 2), (-1, 0, 0), CONCRETE),
        face(3, (0, ly / 2, lz / 2), ey, ez, (ly / 2, lz / 2), (1, 0, 0), CONCRETE),
        face(4, (lx / 2, ly, lz / 2), ex, ez, (lx / 2, lz / 2), (0, -1, 0),
             METAL if metal_left else CONCRETE),
        face(5, (lx / 2, 0, lz / 2), ex, ez, (lx / 2, lz / 2), (0, 1, 0), CONCRETE),
    ]


def tofradar_paths(ref: np.lib.npyio.NpzFile, *, metal_left: bool
                   ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(path lengths (m), |a|, degenerate: reflection points on an edge) of the room."""
    lam = 299_792_458.0 / float(ref["frequency_hz"])
    cfg = RadarConfig(polarization="V", multipath_order=2)
    sets = room_returns(None, cfg, reflectors(ref, metal_left=metal_left),  # type: ignore[arg-type]
                        buffers=None, order=2, time_s=0.0)
    d = np.array([np.linalg.norm(g.scatterers.positions_m[0]) for g in sets])
    sigma = np.array([g.scatterers.rcs_m2[0] for g in sets])
    level = lam * np.sqrt(sigma) / ((4 * np.pi) ** 1.5 * d**2)
    return 2 * d, level, np.array([_on_edge(ref, 2 * x) for x in d])


def _on_edge(ref: np.lib.npyio.NpzFile, length: float) -> bool:
    """Whether a path of this length is an edge's or corner's double/triple image."""
    radar = ref["radar_m"]
    room = ref["room_m"]
    gaps = np.stack([radar, room - radar])                     # distances to the faces
    candidates = [2 * np.hypot(a, b) for i in range(3) for j in range(i + 1, 3)
                  for a in gaps[:, i] for b in gaps[:, j]]
    candidates += [2 * np.sqrt(a * a + b * b + c * c) for a in gaps[:, 0]
                   for b in gaps[:, 1] for c in gaps[:, 2]]
    return bool(np.min(np.abs(np.array(candidates) - length)) < 1e-3)


@pytest.mark.parametrize("scene", ["concrete", "metal_left"])
def test_room_returns_match_sionna(scene: str) -> None:
    ref = np.load(DATA)
    s_len, s_a, s_n = ref[f"{scene}_length_m"], np.abs(ref[f"{scene}_a"]), ref[f"{scene}_bounces"]
    front = float(np.max(s_a[(s_n == 1) & (np.abs(s_len - 2 * (ref["room_m"][0]
                                                               - ref["radar_m"][0])) < 0.01)]))
    t_len, t_a, edge = tofradar_paths(ref, metal_left=scene == "metal_left")
    strong = (s_n >= 2) & (s_a >= front * 0.1)
    assert np.count_nonzero(strong) >= 6
    for length, level in zip(s_len[strong], s_a[strong], strict=True):
        near = np.abs(t_len - length) <= 0.06                  # ±3 cm of range
        assert np.any(near), f"Sionna's path of {length:.3f} m is missing"
        err = 20 * np.log10(t_a[near] / level)
        assert np.min(np.abs(err)) < 3.0, f"{length:.3f} m: {err} dB"
    # No strong return of tofradar's where Sionna has none (edges and corners aside).
    for length, level, on_edge in zip(t_len, t_a, edge, strict=True):
        if level >= front * 0.1 and not on_edge:
            assert np.any(np.abs(s_len - length) <= 0.06), f"tofradar's {length:.3f} m"
