"""Dataset writers (HDF5, Zarr, MCAP), the xarray reader, the live stream, PNG previews.

:func:`open_dataset` is imported lazily (it needs xarray) so that ``import simcore.io``
stays cheap.
"""

from __future__ import annotations

from typing import Any

# The sensor kinds declare their output schemas when registered: every reader and writer
# here works from them.
import simcore.sensors  # noqa: F401


def open_dataset(path: Any, *, storage_options: dict[str, Any] | None = None) -> Any:
    """Open a tofradar dataset (HDF5 file or Zarr store) as a lazy ``xarray.Dataset``.

    See :func:`simcore.io.reader.open_dataset`; ``storage_options`` are the fsspec options
    of a remote Zarr store (``{"endpoint_url": ...}``).
    """
    from simcore.io.reader import open_dataset as _open

    return _open(path, storage_options=storage_options)


__all__ = ["open_dataset"]
