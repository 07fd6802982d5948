"""Validation report, "Multipath" section: the radar's image-method ghosts in the corridor.

:func:`multipath_section` simulates one frame of ``multipath_corridor`` with the radar's
multipath off and at its stored order, and draws both range–azimuth maps (as fans in the
radar's horizontal plane) with the corner reflector and its ghosts marked where the image
geometry predicts them: order 1 at ``(R + R_m)/2`` towards the target (path Tx → wall →
target → Rx) and towards the image (the reverse path), order 2 at ``R_m`` towards the
image. The numbers are the predicted positions and the map's power there with multipath
off and on.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from simcore.pipeline import Simulator
from simcore.resources import example_path
from simcore.scene.geometry import CornerReflector
from simcore.scene.model import Project
from simcore.scene.project_io import load_project
from simcore.scene.snapshot import take_snapshot
from simcore.sensors.radar.multipath import find_reflectors

EXAMPLE = "multipath_corridor"


def predicted_ghosts(project: Project, time_s: float = 0.0) -> list[dict[str, Any]]:
    """The corner reflectors and their ghosts by the image geometry (radar frame).

    Returns
    -------
    list of dict
        ``label``, ``range_m``, ``azimuth_deg`` (+ = radar right), ``order`` (0 = direct),
        for every corner reflector and every reflector face it lies in front of (the
        aperture test of :mod:`simcore.sensors.radar.multipath` is not repeated here).
    """
    snap = take_snapshot(project, time_s)
    radar = snap.sensors["radar"]
    cfg = project.rig.radar
    out: list[dict[str, Any]] = []
    reflectors = find_reflectors(project, snap, cfg.wavelength_m)
    for i, o in enumerate(project.objects):
        if not isinstance(o.geometry, CornerReflector):
            continue
        p = (snap.objects[i].origin - radar.position) @ radar.rotation
        r = float(np.linalg.norm(p))
        az = float(np.degrees(np.arctan2(p[0], p[2])))
        out.append({"label": o.name, "range_m": r, "azimuth_deg": az, "order": 0})
        for refl in reflectors:
            s0 = float(-refl.center_m @ refl.normal)
            s = float((p - refl.center_m) @ refl.normal)
            if s0 * s <= 0 or (s0 < 0 and not refl.two_sided):
                continue
            img = refl.mirror(p)
            r_m = float(np.linalg.norm(img))
            az_m = float(np.degrees(np.arctan2(img[0], img[2])))
            name = project.objects[refl.object_index].name
            out.append({"label": f"{o.name} via {name} (a)", "range_m": 0.5 * (r + r_m),
                        "azimuth_deg": az, "order": 1})
            out.append({"label": f"{o.name} via {name} (b)", "range_m": 0.5 * (r + r_m),
                        "azimuth_deg": az_m, "order": 1})
            if cfg.multipath_order >= 2:
                out.append({"label": f"{o.name} via {name} twice", "range_m": r_m,
                            "azimuth_deg": az_m, "order": 2})
    return out


def _power_at(dsp: Any, range_m: float, azimuth_deg: float) -> float:
    """Range–azimuth map value (dB) at the cell nearest a position."""
    i = int(np.argmin(np.abs(np.asarray(dsp.axes.azimuth_deg) - azimuth_deg)))
    j = int(np.argmin(np.abs(np.asarray(dsp.axes.range_m) - range_m)))
    return float(dsp.range_azimuth_db[i, j])


def multipath_section(out_dir: str | Path, *, quick: bool = False
                      ) -> tuple[list[tuple[str, str, str]], dict[str, Any]]:
    """Figures and numbers of the report's "Multipath" section (radar half).

    Parameters
    ----------
    out_dir : str or Path
        Folder the PNG is written to (created if needed).
    quick : bool
        Accepted for the report's interface; the section is one frame either way.

    Returns
    -------
    (list of (file, title, text), dict)
        The figure (file name in ``out_dir``, title, reading paragraph) and the numbers:
        the predicted positions and the map's power there with multipath off and on.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    project = load_project(example_path(EXAMPLE))
    order = max(project.rig.radar.multipath_order, 1)
    maps = {}
    for k in (0, order):
        p = project.model_copy(deep=True)
        p.rig.radar.multipath_order = k
        with Simulator(p) as sim:
            maps[k] = sim.frame(0).outputs["radar"].dsp
    on = project.model_copy(deep=True)
    on.rig.radar.multipath_order = order
    marks = predicted_ghosts(on)
    numbers: dict[str, Any] = {"multipath_order": order, "marks": []}
    for m in marks:
        numbers["marks"].append({**m, "power_off_db": _power_at(maps[0], m["range_m"],
                                                                 m["azimuth_deg"]),
                                 "power_on_db": _power_at(maps[order], m["range_m"],
                                                          m["azimuth_deg"])})
    fig, axes = plt.subplots(1, 2, figsize=(13, 5.6), constrained_layout=True)
    top = max(float(np.max(maps[k].range_azimuth_db)) for k in maps)
    styles = {0: ("o", "cyan", "target"), 1: ("s", "lime", "order-1 ghost (predicted)"),
              2: ("D", "magenta", "order-2 ghost (predicted)")}
    for ax, k in zip(axes, (0, order), strict=True):
        dsp = maps[k]
        az = np.deg2rad(np.asarray(dsp.axes.azimuth_deg))
        rr, aa = np.meshgrid(np.asarray(dsp.axes.range_m), az)
        im = ax.pcolormesh(rr * np.sin(aa), rr * np.cos(aa), dsp.range_azimuth_db,
                           vmin=top - 50, vmax=top, cmap="magma", shading="gouraud")
        fig.colorbar(im, ax=ax, label="power (dB)")
        seen = set()
        for m in marks:
            if m["order"] > max(k, 0) and k == 0:
                continue
            marker, colour, label = styles[m["order"]]
            a = np.deg2rad(m["azimuth_deg"])
            ax.scatter(m["range_m"] * np.sin(a), m["range_m"] * np.cos(a), s=90,
                       marker=marker, facecolors="none", edgecolors=colour, lw=1.6,
                       label=None if label in seen else label)
            seen.add(label)
        ax.set_xlabel("cross-range x (m, radar frame, + = right)")
        ax.set_ylabel("down-range z (m)")
        ax.set_aspect("equal")
        ax.set_xlim(-3, 3)
        ax.set_ylim(0, 6)
        ax.set_title(f"multipath_order = {k}")
        ax.legend(loc="upper right", fontsize=8)
    name = "fig10_multipath_range_azimuth.png"
    fig.savefig(out / name, dpi=110)
    plt.close(fig)
    text = ("Range–azimuth map (Bartlett) of the multipath_corridor example without and with "
            "radar multipath. Circles: the corner reflector; squares: its order-1 ghosts at "
            "(R + R_m)/2, towards the target (path via the wall on the way out) and towards "
            "its mirror image in the aluminium wall (via the wall on the way back); diamonds: "
            "order 2 at R_m. The ghost appears only with multipath on, where the image "
            "geometry puts it; the L-shaped 3-Rx array resolves azimuth only coarsely.")
    return [(name, "Radar multipath: ghost of the corner reflector", text)], numbers


__all__ = ["multipath_section", "predicted_ghosts"]
