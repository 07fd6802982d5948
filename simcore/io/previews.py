"""PNG previews of frame products.

Labelled figures (axes in m, m/s and degrees, colour bars with units, frame and time in the
title) and plain colour-mapped images.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

INVALID_RGB = (0.35, 0.35, 0.35)


def save_image(path: Path, image: NDArray[np.floating], *, cmap: str = "viridis",
               vmin: float | None = None, vmax: float | None = None) -> None:
    """Save a 2-D array as a colour-mapped PNG; NaN pixels are drawn grey.

    Without explicit limits the colour scale spans the 1st to 99th percentile.
    """
    from matplotlib import colormaps

    data = np.asarray(image, dtype=np.float64)
    finite = np.isfinite(data)
    lo_p, hi_p = (np.percentile(data[finite], [1, 99]) if finite.any() else (0.0, 1.0))
    lo = vmin if vmin is not None else float(lo_p)
    hi = vmax if vmax is not None else float(hi_p)
    norm = np.clip((np.where(finite, data, lo) - lo) / max(hi - lo, 1e-12), 0, 1)
    rgba = colormaps[cmap](norm)
    rgba[~finite, :3] = INVALID_RGB
    import matplotlib.image

    path.parent.mkdir(parents=True, exist_ok=True)
    matplotlib.image.imsave(path, (rgba * 255).astype(np.uint8))


def save_previews(out_dir: Path, index: int, images: dict[str, tuple[NDArray[np.floating], str]]
                  ) -> list[Path]:
    """Write ``frame_NNNNN_<name>.png`` for each (image, colormap) in ``images``."""
    paths = []
    for name, (image, cmap) in images.items():
        path = out_dir / f"frame_{index:05d}_{name}.png"
        save_image(path, image, cmap=cmap)
        paths.append(path)
    return paths


@dataclass(frozen=True)
class PreviewAxes:
    """Physical axes of the preview figures.

    Attributes
    ----------
    tof_fov_deg : tuple of float
        Horizontal and vertical field of view of the ToF camera (degrees).
    range_m : ndarray, shape (range,)
        Range bin centres (m).
    velocity_mps : ndarray, shape (doppler,)
        Doppler bin centres (m/s, positive = moving away).
    azimuth_deg : ndarray, shape (azimuth,)
        Azimuth grid (degrees, positive = right).
    """

    tof_fov_deg: tuple[float, float]
    range_m: NDArray[np.float64]
    velocity_mps: NDArray[np.float64]
    azimuth_deg: NDArray[np.float64]


#: name → (dataset path, title, colour-bar label, colour map) of the labelled previews.
FIGURES = {
    "tof_gt_range": ("/tof/gt_range", "ToF ground-truth range", "range (m)", "viridis"),
    "tof_depth": ("/tof/depth", "ToF measured depth (grey: invalid)", "depth (m)", "viridis"),
    "tof_amplitude": ("/tof/amplitude", "ToF amplitude", "amplitude (DN)", "gray"),
    "radar_range_doppler": ("/radar/range_doppler", "radar range–Doppler", "power (dB)",
                            "magma"),
    "radar_range_azimuth": ("/radar/range_azimuth", "radar range–azimuth", "power (dB)",
                            "magma"),
}


def _edges(centres: NDArray[np.float64]) -> tuple[float, float]:
    """Outer edges of a regular axis given its bin centres."""
    if len(centres) < 2:
        c = float(centres[0]) if len(centres) else 0.0
        return c - 0.5, c + 0.5
    step = float(centres[1] - centres[0])
    return float(centres[0]) - step / 2, float(centres[-1]) + step / 2


def save_figure(path: Path, image: NDArray[np.floating], *, title: str, cbar_label: str,
                cmap: str, extent: tuple[float, float, float, float] | None,
                xlabel: str, ylabel: str) -> None:
    """One labelled figure: image with physical axes, a colour bar with units, a title.

    ``extent`` is (left, right, bottom, top) in axis units; NaN pixels are grey and the
    colour scale spans the 1st to 99th percentile of the finite pixels.
    """
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    data = np.asarray(image, dtype=np.float64)
    finite = np.isfinite(data)
    lo, hi = (np.percentile(data[finite], [1, 99]) if finite.any() else (0.0, 1.0))
    if hi <= lo:
        hi = lo + 1.0
    fig = Figure(figsize=(6.4, 4.6), dpi=100)
    FigureCanvasAgg(fig)
    ax = fig.add_subplot()
    ax.set_facecolor(INVALID_RGB)
    im = ax.imshow(np.ma.masked_invalid(data), cmap=cmap, vmin=lo, vmax=hi, origin="upper",
                   aspect="auto", extent=extent, interpolation="nearest")
    cbar = fig.colorbar(im, ax=ax)
    cbar.set_label(cbar_label)
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.set_title(title, fontsize=10)
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path)


def save_frame_previews(out_dir: Path, index: int,
                        items: dict[str, tuple[NDArray[np.generic], str]],
                        axes: PreviewAxes | None) -> list[Path]:
    """Labelled PNG figures ``frame_NNNNN_<name>.png`` of one frame's products.

    ToF images have horizontal and vertical angle axes (degrees); the range–Doppler map
    range (m) × velocity (m/s); the range–azimuth map range (m) × azimuth (degrees).
    Without ``axes`` the axes are in bins and pixels.
    """
    t = float(np.asarray(items["/time"][0])) if "/time" in items else float("nan")
    paths = []
    for name, (ds_path, what, label, cmap) in FIGURES.items():
        if ds_path not in items:
            continue
        image = np.asarray(items[ds_path][0], dtype=np.float64)
        if name == "tof_depth" and "/tof/valid" in items:
            image = np.where(np.asarray(items["/tof/valid"][0], dtype=bool), image, np.nan)
        extent: tuple[float, float, float, float] | None = None
        xlabel, ylabel = "column (px)", "row (px)"
        if axes is not None and name.startswith("tof"):
            h, v = axes.tof_fov_deg
            extent = (-h / 2, h / 2, -v / 2, v / 2)
            xlabel, ylabel = "horizontal angle (deg, right +)", "vertical angle (deg, up +)"
        elif axes is not None and name == "radar_range_doppler":
            extent = (*_edges(axes.range_m), *_edges(axes.velocity_mps))
            image = image[::-1]     # origin upper: first velocity bin at the bottom
            xlabel, ylabel = "range (m)", "radial velocity (m/s, away +)"
        elif axes is not None and name == "radar_range_azimuth":
            extent = (*_edges(axes.range_m), *_edges(axes.azimuth_deg))
            image = image[::-1]
            xlabel, ylabel = "range (m)", "azimuth (deg, right +)"
        elif name.startswith("radar"):
            xlabel, ylabel = "range bin", "bin"
        path = out_dir / f"frame_{index:05d}_{name}.png"
        save_figure(path, image, title=f"{what} — frame {index}, t = {t:.3f} s",
                    cbar_label=label, cmap=cmap, extent=extent, xlabel=xlabel, ylabel=ylabel)
        paths.append(path)
    return paths
