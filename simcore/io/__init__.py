"""Dataset writers (HDF5, MCAP), the xarray reader, the live stream and exports (PNG previews).

:func:`open_dataset` is imported lazily (it needs xarray) so that ``import simcore.io``
stays cheap.
"""

from __future__ import annotations

from typing import Any


def open_dataset(path: Any) -> Any:
    """Open a tofradar HDF5 dataset as a lazy ``xarray.Dataset`` (:mod:`simcore.io.reader`)."""
    from simcore.io.reader import open_dataset as _open

    return _open(path)


__all__ = ["open_dataset"]
