"""Validation report, section "Multipath": tofradar's room returns against Sionna RT.

The reference is Sionna RT 2.2 (polarimetric ray tracing, ITU-R P.2040 materials at
60 GHz), run in its own environment by ``tools/references/sionna/room_paths.py``; its
paths are cached in ``resources/references/sionna_room_paths.npz``, so this section (and
``tests/test_radar_sionna_reference.py``) regenerate without it. The scene: a 6 × 4 × 3 m
concrete room, the radar 1 m above the floor and 2.5 m from the front wall, facing it,
with and without a metal left wall; isotropic V-polarised antennas.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from simcore.resources import RESOURCES_DIR
from simcore.scene.materials import BandMaterial
from simcore.scene.radar_config import SPEED_OF_LIGHT, CosinePattern, RadarConfig
from simcore.sensors.radar.multipath import Reflector
from simcore.sensors.radar.room import room_returns

REFERENCE = RESOURCES_DIR / "references" / "sionna_room_paths.npz"
#: ITU-R P.2040 concrete at 60 GHz (ε′ = 5.24, σ = 0.0462 f^0.7822 S/m: tan δ = 0.065).
CONCRETE = BandMaterial(permittivity=5.24, loss_tangent=0.065)
METAL = BandMaterial(metallic=1.0)
SCENES = ("concrete", "metal_left")


def room_reflectors(ref: Any, *, metal_left: bool) -> list[Reflector]:
    """The reference room's six inner faces in the radar's optical frame (radar facing +x)."""
    radar = np.asarray(ref["radar_m"], dtype=float)
    lx, ly, lz = (float(v) for v in ref["room_m"])
    freq = float(ref["frequency_hz"])

    def frame(v: NDArray[np.float64]) -> NDArray[np.float64]:
        return np.array([-v[1], -v[2], v[0]])           # x right, y down, z forward

    def face(obj: int, center: tuple[float, float, float], u: int, v: int,
             half: tuple[float, float], normal: tuple[float, float, float],
             band: BandMaterial) -> Reflector:
        eye = np.eye(3)
        return Reflector(obj, frame(np.array(center) - radar),
                         np.array([frame(eye[u]), frame(eye[v])]), np.array(half),
                         frame(np.array(normal, dtype=float)), False,
                         complex(band.coefficients(freq)[0]), 0.0, 0.0, band=band,
                         frequency_hz=freq)

    return [
        face(0, (lx / 2, ly / 2, 0), 0, 1, (lx / 2, ly / 2), (0, 0, 1), CONCRETE),
        face(1, (lx / 2, ly / 2, lz), 0, 1, (lx / 2, ly / 2), (0, 0, -1), CONCRETE),
        face(2, (lx, ly / 2, lz / 2), 1, 2, (ly / 2, lz / 2), (-1, 0, 0), CONCRETE),
        face(3, (0, ly / 2, lz / 2), 1, 2, (ly / 2, lz / 2), (1, 0, 0), CONCRETE),
        face(4, (lx / 2, ly, lz / 2), 0, 2, (lx / 2, lz / 2), (0, -1, 0),
             METAL if metal_left else CONCRETE),
        face(5, (lx / 2, 0, lz / 2), 0, 2, (lx / 2, lz / 2), (0, 1, 0), CONCRETE),
    ]


def tofradar_room_paths(ref: Any, *, metal_left: bool
                        ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Path lengths (m) and Sionna-equivalent levels |a| of tofradar's room returns.

    A return of cross-section σ at range D (path 2D) has ``|a| = λ √σ / ((4π)^{3/2} D²)``:
    the radar equation with isotropic antennas, as Sionna's path coefficient (an infinite
    plane's σ = π D² |Γ|² gives ``λ |Γ| / (4π · 2D)``).
    """
    lam = SPEED_OF_LIGHT / float(ref["frequency_hz"])
    # Sionna's antennas are isotropic: so is the element here (room_returns weighs each
    # path's legs by the pattern).
    cfg = RadarConfig(polarization="V", multipath_order=2,
                      element_pattern=CosinePattern(exponent_az=0.0, exponent_el=0.0))
    sets = room_returns(None, cfg, room_reflectors(ref, metal_left=metal_left),
                        buffers=None, order=2, time_s=0.0)
    d = np.array([np.linalg.norm(g.scatterers.positions_m[0]) for g in sets])
    sigma = np.array([g.scatterers.rcs_m2[0] for g in sets])
    return 2.0 * d, lam * np.sqrt(sigma) / ((4.0 * np.pi) ** 1.5 * d**2)


def compare(ref: Any, scene: str) -> dict[str, Any]:
    """Sionna's multiple-bounce paths within 20 dB of the front wall, and tofradar's match.

    Returns ``front_db`` (the front wall's |a|, dB) and ``paths``: per Sionna path its
    range (m), bounces, Sionna's and tofradar's level relative to the front wall (dB) and
    the range difference (cm); tofradar's nearest-level path within ±3 cm (None: none).
    """
    length, a, bounces = ref[f"{scene}_length_m"], np.abs(ref[f"{scene}_a"]), \
        ref[f"{scene}_bounces"]
    gap = 2.0 * (float(ref["room_m"][0]) - float(ref["radar_m"][0]))
    front = float(np.max(a[(bounces == 1) & (np.abs(length - gap) < 0.01)]))
    t_len, t_a = tofradar_room_paths(ref, metal_left=scene == "metal_left")
    rows = []
    for i in np.argsort(length):
        if bounces[i] < 2 or a[i] < 0.1 * front:
            continue
        near = np.flatnonzero(np.abs(t_len - length[i]) <= 0.06)
        row: dict[str, Any] = {"range_m": float(length[i] / 2), "bounces": int(bounces[i]),
                               "sionna_db": float(20 * np.log10(a[i] / front)),
                               "tofradar_db": None, "range_error_cm": None}
        if len(near):
            j = near[np.argmin(np.abs(np.log(t_a[near] / a[i])))]
            row["tofradar_db"] = float(20 * np.log10(t_a[j] / front))
            row["range_error_cm"] = float(100 * (t_len[j] - length[i]) / 2)
        rows.append(row)
    return {"front_db": float(20 * np.log10(front)), "paths": rows}


def sionna_section(out_dir: str | Path) -> tuple[list[tuple[str, str, str]], dict[str, Any]]:
    """Figure and numbers of the comparison (section "Multipath").

    Returns
    -------
    (list of (file, title, text), dict)
        One figure (levels against range, Sionna and tofradar, both rooms) and, per room,
        :func:`compare`'s rows with the largest level and range differences.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    ref = np.load(REFERENCE)
    numbers: dict[str, Any] = {}
    fig, axes = plt.subplots(1, 2, figsize=(11, 4), sharey=True)
    for ax, scene in zip(axes, SCENES, strict=True):
        res = compare(ref, scene)
        rows = res["paths"]
        matched = [r for r in rows if r["tofradar_db"] is not None]
        res["max_level_error_db"] = max((abs(r["tofradar_db"] - r["sionna_db"])
                                         for r in matched), default=float("nan"))
        res["max_range_error_cm"] = max((abs(r["range_error_cm"]) for r in matched),
                                        default=float("nan"))
        res["missing"] = len(rows) - len(matched)
        numbers[scene] = res
        ax.plot([r["range_m"] for r in rows], [r["sionna_db"] for r in rows], "o", mfc="none",
                ms=9, label="Sionna RT 2.2")
        ax.plot([r["range_m"] for r in matched], [r["tofradar_db"] for r in matched], "x",
                label="tofradar room returns")
        ax.set_title(f"{scene.replace('_', ' ')} room: {len(rows)} paths, "
                     f"max {res['max_level_error_db']:.2f} dB")
        ax.set_xlabel("range (m)")
        ax.grid(alpha=0.3)
    axes[0].set_ylabel("level re the front wall (dB)")
    axes[0].legend()
    fig.tight_layout()
    name = "fig10_multipath_sionna.png"
    fig.savefig(out / name, dpi=110)
    plt.close(fig)
    c, m = numbers["concrete"], numbers["metal_left"]
    text = (
        "Every path radar → room → radar with two or three specular bounces that Sionna RT "
        "2.2 (polarimetric, ITU-R P.2040 concrete and metal at 60 GHz, isotropic V antennas; "
        "tools/references/sionna) finds within 20 dB of the front wall's return, and "
        "tofradar's room returns for the same 6 × 4 × 3 m room (radar 1 m above the floor, "
        "2.5 m from the front wall): "
        f"concrete {len(c['paths'])} paths, largest level difference "
        f"{c['max_level_error_db']:.2f} dB, range {c['max_range_error_cm']:.2f} cm, "
        f"{c['missing']} missing; with a metal left wall {len(m['paths'])} paths, "
        f"{m['max_level_error_db']:.2f} dB, {m['max_range_error_cm']:.2f} cm, "
        f"{m['missing']} missing. tofradar also returns the room's edges and corners "
        "(dihedral and trihedral images), which Sionna does not trace in this exactly "
        "monostatic geometry (their reflection points lie on the edges). Single-bounce "
        "returns (the walls' own) are the surface facets, held against the exact PO "
        "integral and the image method in tests/test_radar_po_plate.py.")
    from simcore.report.sionna_targets import targets_figure

    targets, numbers["targets"] = targets_figure(out)
    from simcore.report.sionna_office import office_figure

    office, numbers["office"] = office_figure(out)
    return [(name, "Radar multipath against Sionna RT", text), targets, office], numbers


__all__ = ["REFERENCE", "compare", "room_reflectors", "sionna_section", "tofradar_room_paths"]
