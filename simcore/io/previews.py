"""PNG previews of frame products.

Labelled figures (axes in m, m/s and degrees, colour bars with units, frame and time in the
title) and plain colour-mapped images.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from simcore.scene.model import Project, sensor_kind
from simcore.sensors.schema import Output, schema_of

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
class PreviewSensor:
    """What the previews of one sensor need: its kind, configuration and static datasets.

    Attributes
    ----------
    kind : str
        The sensor's kind (its schema says which outputs have a figure).
    config : object
        Its configuration (a figure's axes may come from it: the ToF camera's FoV).
    statics : dict of str to ndarray
        Its run-constant datasets by output name (the radar's axes).
    """

    kind: str
    config: Any
    statics: Mapping[str, NDArray[np.generic]]


def preview_sensors(project: Project,
                    statics: Mapping[str, tuple[NDArray[np.generic], str]] | None = None
                    ) -> dict[str, PreviewSensor]:
    """Every sensor of ``project`` with what its figures need, by name.

    ``statics``: the run's static datasets (path → (array, unit)); by default each
    sensor's own (:meth:`Sensor.static_items`).
    """
    if statics is None:
        from simcore.sensors import active_sensors

        statics = {}
        for sensor in active_sensors(project):
            statics.update(sensor.static_items(project))
    out: dict[str, PreviewSensor] = {}
    for name, cfg in project.sensor_configs().items():
        prefix = f"/{name}/"
        own = {p[len(prefix):]: np.asarray(v[0]) for p, v in statics.items()
               if p.startswith(prefix)}
        out[name] = PreviewSensor(sensor_kind(cfg), cfg, own)
    return out


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
                        items: Mapping[str, tuple[NDArray[np.generic], str]],
                        sensors: Mapping[str, PreviewSensor] | None) -> list[Path]:
    """Labelled PNG figures ``frame_NNNNN_<sensor>_<output>.png`` of one frame.

    Every output that its kind's schema gives a preview (``Output.preview``), of every
    sensor in ``sensors``: ToF images with horizontal and vertical angle axes (degrees),
    the range–Doppler map range (m) × velocity (m/s), the range–azimuth map range (m) ×
    azimuth (degrees). Axes a figure cannot get are in pixels or bins.
    """
    t = float(np.asarray(items["/time"][0])) if "/time" in items else float("nan")
    paths = []
    for name, sensor in (sensors or {}).items():
        schema = schema_of(sensor.kind)
        for output in schema.previews():
            path = _sensor_figure(out_dir, index, t, items, name, sensor, output)
            if path is not None:
                paths.append(path)
    return paths


def _sensor_figure(out_dir: Path, index: int, t: float,
                   items: Mapping[str, tuple[NDArray[np.generic], str]], name: str,
                   sensor: PreviewSensor, output: Output) -> Path | None:
    """The figure of one output of one sensor (None when the frame does not hold it)."""
    schema = schema_of(sensor.kind)
    preview = output.preview
    ds_path = schema.dataset_path(name, output.name)
    if preview is None or ds_path not in items:
        return None
    image = np.asarray(items[ds_path][0], dtype=np.float64)
    mask_path = None if preview.mask is None else schema.dataset_path(name, preview.mask)
    if mask_path is not None and mask_path in items:
        image = np.where(np.asarray(items[mask_path][0], dtype=bool), image, np.nan)
    frame = None if preview.axes is None else preview.axes(sensor.config, sensor.statics)
    extent: tuple[float, float, float, float] | None = None
    xlabel, ylabel = ("column (px)", "row (px)") if output.dims[-1] == "col" else ("bin", "bin")
    if frame is not None:
        extent, xlabel, ylabel, flip = frame
        if flip:
            image = image[::-1]     # origin upper: the first bin at the bottom
    path = out_dir / f"frame_{index:05d}_{name}_{output.name.replace('/', '_')}.png"
    save_figure(path, image, title=f"{name}: {preview.title} — frame {index}, t = {t:.3f} s",
                cbar_label=preview.label, cmap=preview.cmap, extent=extent, xlabel=xlabel,
                ylabel=ylabel)
    return path
