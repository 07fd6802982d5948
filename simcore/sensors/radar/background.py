"""The radar IF over a still background: transform only the facets a frame changes.

With the rig and some objects still, the engine renders the still objects alone once and
tells the sensor which pixels of each frame's render differ from that background
(:class:`simcore.sensors.base.Background`). A frame's IF is then

    y = y(background) − y(background facets the frame changes) + y(the frame's facets there)

where ``y(background)`` is computed once per radar configuration. The facets a pixel
belongs to (the facet grid of :func:`simcore.sensors.radar.scatterers.scatterers_from_render`)
are this module's business: the engine knows only pixels.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from simcore.scene.camera import PinholeIntrinsics
from simcore.sensors.radar.scatterers import KIND_FACET, Scatterers

#: Above this fraction of changed facet cells the plain path is cheaper.
MAX_CHANGED_FRACTION = 0.5


@dataclass(frozen=True)
class BackgroundFacets:
    """The facet scatterers of a background render, indexable by facet cell.

    Attributes
    ----------
    scatterers : Scatterers
        Facet scatterers of the background (no analytic targets), with their facet keys.
    n_objects : int
        Number of project objects (the facet key is ``cell * n_objects + object``).
    """

    scatterers: Scatterers
    n_objects: int

    @classmethod
    def of(cls, scatterers: Scatterers, n_objects: int) -> BackgroundFacets:
        """Keep the facets of a background's scatterers."""
        facets = scatterers.subset(scatterers.kind == KIND_FACET)
        if facets.facet_key is None:
            raise ValueError("background scatterers must come from a render (facet keys)")
        return cls(facets, max(n_objects, 1))

    def in_cells(self, cells: NDArray[np.bool_]) -> Scatterers:
        """The background facets whose cell is flagged in ``cells`` (flat facet grid)."""
        return self.scatterers.subset(np.flatnonzero(self.cell_mask(cells)))

    def cell_mask(self, cells: NDArray[np.bool_]) -> NDArray[np.bool_]:
        """Which background facets have their cell flagged in ``cells``, shape (M,)."""
        key = self.scatterers.facet_key
        assert key is not None
        return np.take(cells, key // self.n_objects)


def changed_cells(changed: NDArray[np.intp], render: PinholeIntrinsics,
                  facets: PinholeIntrinsics) -> NDArray[np.bool_] | None:
    """Facet cells that hold a changed render pixel, shape (facet H × facet W,), flat.

    None when the render is not the facet grid scaled by an integer, or when more than
    :data:`MAX_CHANGED_FRACTION` of the cells changed (the plain path is cheaper then).
    """
    h, w = render.height, render.width
    step = h // facets.height if facets.height and h % facets.height == 0 else 0
    if step < 1 or w != facets.width * step:
        return None
    rows, cols = np.divmod(changed, w)
    cells = np.zeros(facets.height * facets.width, dtype=bool)
    cells[(rows // step) * facets.width + cols // step] = True
    if np.count_nonzero(cells) > MAX_CHANGED_FRACTION * cells.size:
        return None
    return cells


def cell_pixels(cells: NDArray[np.bool_], render: PinholeIntrinsics,
                facets: PinholeIntrinsics) -> NDArray[np.bool_]:
    """Render pixels of the flagged facet cells, shape (H, W)."""
    grid = cells.reshape(facets.height, facets.width)
    step = render.height // facets.height
    return np.repeat(np.repeat(grid, step, axis=0), step, axis=1) if step > 1 else grid
