"""PNG previews of frame products (colour-mapped images, invalid pixels grey)."""

from __future__ import annotations

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
