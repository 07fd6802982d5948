"""Validation report, "Multipath" section: radar ghosts in the corridor, ToF MPI in the office.

:func:`multipath_section` simulates one frame of ``multipath_corridor`` with the radar's
multipath off and at its stored order, and draws both range–azimuth maps (as fans in the
radar's horizontal plane) with the corner reflector and its ghosts marked where the image
geometry predicts them: order 1 at ``(R + R_m)/2`` towards the target (path Tx → wall →
target → Rx) and towards the image (the reverse path), order 2 at ``R_m`` towards the
image. The numbers are the predicted positions and the map's power there with multipath
off and on.

:func:`tof_multipath_figure` renders frame 0 of ``office`` once and simulates the ideal
(noise-free) ToF camera on it with multipath interference off and on: the depth error
maps against the rendered range and the MPI's depth shift per object.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any, Literal

import numpy as np
from numpy.typing import NDArray

from simcore.pipeline import Simulator
from simcore.resources import example_path
from simcore.scene.geometry import CornerReflector
from simcore.scene.model import Project
from simcore.scene.project_io import load_project
from simcore.scene.snapshot import take_snapshot
from simcore.sensors.radar.multipath import find_reflectors
from simcore.sensors.radar.scene import RadarScene

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
    cfg = project.radar()
    out: list[dict[str, Any]] = []
    reflectors = find_reflectors(RadarScene.from_project(project, snap), cfg.wavelength_m)
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
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    project = load_project(example_path(EXAMPLE))
    # Order 2: the trihedral's ghost is its image's own return (order 2); a trihedral
    # sends nothing towards the other ends of the order-1 paths (retro-reflection).
    order: Literal[0, 1, 2] = 2
    maps: dict[int, Any] = {}
    for k in (0, order):
        p = project.model_copy(deep=True)
        p.radar().multipath_order = k
        with Simulator(p) as sim:
            maps[k] = sim.frame(0).outputs["radar"].dsp
    on = project.model_copy(deep=True)
    on.radar().multipath_order = order
    marks = predicted_ghosts(on)
    numbers: dict[str, Any] = {"multipath_order": order, "marks": []}
    for m in marks:
        numbers["marks"].append({**m, "power_off_db": _power_at(maps[0], m["range_m"],
                                                                 m["azimuth_deg"]),
                                 "power_on_db": _power_at(maps[order], m["range_m"],
                                                          m["azimuth_deg"])})
    name = "fig10_multipath_range_azimuth.png"
    _draw_maps(out / name, maps, marks, order)
    text = ("Range–azimuth map (Bartlett) of the multipath_corridor example without and with "
            "radar multipath (order 2). Circles: the corner reflector; squares: where the "
            "order-1 paths would put ghosts, at (R + R_m)/2 (via the wall on the way out or "
            "back); a trihedral returns a wave only towards where it came from, so these "
            "are 30–40 dB under a point target's; diamonds: order 2 at R_m, the corner seen "
            "by the radar's image in the aluminium wall. The ghost appears only with "
            "multipath on, where the image geometry puts it; the L-shaped 3-Rx array "
            "resolves azimuth only coarsely.")
    return [(name, "Radar multipath: ghost of the corner reflector", text)], numbers


def _draw_maps(path: Path, maps: dict[int, Any], marks: list[dict[str, Any]], order: int
               ) -> None:
    """:func:`multipath_section`'s figure, written to ``path``.

    The range–azimuth fans without and with multipath (order ``order``), with the
    predicted target and ghost positions marked.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

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
    fig.savefig(path, dpi=110)
    plt.close(fig)


def tof_multipath_figure(out_dir: str | Path, example: str = "office"
                         ) -> tuple[tuple[str, str, str], dict[str, Any]]:
    """ToF depth error with multipath interference off and on (frame 0, ideal camera).

    Returns
    -------
    ((file, title, text), dict)
        The figure and its numbers: per object with at least 50 valid pixels, the median and
        95th percentile of the MPI depth shift (on − off, mm), and the same over all valid
        pixels; the time of the one-bounce sum.
    """
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    project = load_project(example_path(example))
    cfg = project.tof()
    frames, seconds = _mpi_frames(project)
    numbers, err = _mpi_numbers(project, frames, seconds, example=example)
    name = _mpi_figure(err, numbers["per_object"], out)
    model = ("the whole-room model: light bounced any number of times by every surface, "
             f"{cfg.multipath_surfel_m} m surfels" if cfg.multipath_model == "room" else
             f"one diffuse bounce, {cfg.multipath_patch_px}-px senders")
    text = (f"Ideal ToF camera (no noise) on frame 0 of the {example} example with multipath "
            f"interference off and on ({model}). Off, the error is zero except the mixed "
            "pixels at depth edges (grey: no valid depth); on, every surface lit by its "
            "neighbours reads long, most "
            "where the direct light is weak and the neighbours bright: the floor seen at a "
            "grazing angle, the concave wall–floor and wall–wall corners. Median shift "
            f"{numbers['median_shift_mm']:.0f} mm, 95th percentile "
            f"{numbers['p95_shift_mm']:.0f} mm. The models are checked against a brute-force "
            "one-bounce integral (tests/test_tof_multipath.py) and against the path tracer "
            "mitransient on a corner, a furnished room and this office "
            "(tests/test_tof_mitransient.py).")
    return (name, "ToF multipath interference: depth error in the office", text), numbers


def _mpi_frames(project: Project) -> tuple[dict[bool, Any], dict[bool, float]]:
    """The ideal ToF frame 0 with multipath off and on, and the ToF stage's time (s).

    Through the engine (:class:`~simcore.pipeline.Simulator`), so that the project's own
    multipath model runs as in a dataset: the whole-room model needs the scene's surfaces,
    not only the camera's render.
    """
    cfg = project.tof()
    frames, seconds = {}, {}
    for on in (False, True):
        # Multipath alone: the other optics (wiggling, distortion, …) off, for a clean figure.
        c = cfg.model_copy(update={"multipath": on, "ideal": True, "specular": False,
                                   "wiggling": False, "distortion": False,
                                   "vignetting": False, "stray_light": False,
                                   "motion_artifacts": False, "auto_exposure": False})
        rig = project.rig.model_copy(update={"tof": c, "radar": None})
        alone = project.model_copy(update={"rig": rig, "rigs": []})
        with Simulator(alone, base_dir=None) as sim:
            frame = sim.frame(0)
        frames[on] = next(o for o in frame.outputs.values() if hasattr(o, "depth_m"))
        seconds[on] = frame.timings_ms.get("tof", 0.0) / 1e3
    return frames, seconds


def _mpi_numbers(project: Project, frames: dict[bool, Any], seconds: dict[bool, float], *,
                 example: str) -> tuple[dict[str, Any], dict[bool, NDArray[np.float64]]]:
    """The MPI depth shift per object and overall; the depth error images (mm)."""
    cfg = project.tof()
    gt = frames[False].gt_range
    valid = frames[False].valid & frames[True].valid & (gt > 0)
    err = {on: np.where(valid, frames[on].depth_m - gt, np.nan) * 1e3 for on in frames}
    shift = err[True] - err[False]
    ids = frames[False].gt_object_id
    per_object = {}
    for o in project.objects:
        sel = valid & (ids == o.id)
        if np.count_nonzero(sel) >= 50:
            per_object[o.name] = {"pixels": int(np.count_nonzero(sel)),
                                  "median_mm": float(np.median(shift[sel])),
                                  "p95_mm": float(np.percentile(shift[sel], 95))}
    numbers = {"example": example, "multipath_patch_px": cfg.multipath_patch_px,
               "median_shift_mm": float(np.nanmedian(shift)),
               "p95_shift_mm": float(np.nanpercentile(shift, 95)),
               "median_abs_error_off_mm": float(np.nanmedian(np.abs(err[False]))),
               "median_abs_error_on_mm": float(np.nanmedian(np.abs(err[True]))),
               "tof_ms_off": 1e3 * seconds[False], "tof_ms_on": 1e3 * seconds[True],
               "per_object": per_object}
    return numbers, err


def _mpi_figure(err: dict[bool, NDArray[np.float64]], per_object: dict[str, Any],
                out: Path) -> str:
    """Depth error images off and on, and the shift per object; the file name."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 3, figsize=(15, 4.3), constrained_layout=True)
    # The colour range: 150 mm, or wider to hold the 95th percentile of the error (the
    # whole-room model's walls read half a metre long), in steps of 50 mm.
    spread = float(np.nanpercentile(np.abs(err[True]), 95)) if np.isfinite(err[True]).any() \
        else 0.0
    lim = max(150.0, 50.0 * math.ceil(spread / 50.0))
    for ax, img, title in ((axes[0], err[False], "depth error, multipath off"),
                           (axes[1], err[True], "depth error, multipath on")):
        ax.set_facecolor("0.55")          # grey: no valid depth (no return, edge, dark)
        im = ax.imshow(img, cmap="RdBu_r", vmin=-lim, vmax=lim)
        fig.colorbar(im, ax=ax, label="measured − true range (mm)")
        ax.set_title(title)
        ax.set_xlabel("column (px)")
        ax.set_ylabel("row (px)")
    ax = axes[2]
    names = sorted(per_object, key=lambda n: per_object[n]["median_mm"])
    y = np.arange(len(names))
    ax.barh(y, [per_object[n]["median_mm"] for n in names], color="tab:red", label="median")
    ax.scatter([per_object[n]["p95_mm"] for n in names], y, color="k", marker="|", s=120,
               label="95th percentile")
    ax.set_yticks(y, names, fontsize=8)
    ax.set_xlabel("MPI depth shift, on − off (mm)")
    ax.set_title("per object")
    ax.legend(loc="lower right", fontsize=8)
    name = "fig11_tof_multipath_depth_error.png"
    fig.savefig(out / name, dpi=100)
    plt.close(fig)
    return name


__all__ = ["multipath_section", "predicted_ghosts", "tof_multipath_figure"]
