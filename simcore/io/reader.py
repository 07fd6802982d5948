"""Read a dataset as an ``xarray.Dataset``: named dimensions, SI coordinates, lazy arrays.

:func:`open_dataset` maps every array of the HDF5 layout (``docs/dataset.md``) onto one
variable named after its path (``/radar/range_doppler`` → ``radar_range_doppler``), with
named dimensions (``frame``, ``chirp``, ``channel``, ``sample``, ``row``, ``col``,
``range``, ``velocity``, ``azimuth``, …) and coordinates (``time`` in s, ``range`` in m,
``velocity`` in m/s, ``azimuth`` in deg, object names and ids). Arrays stay in the file:
each variable is a dask array over the HDF5 dataset, one chunk per frame, so opening a file
of any size reads only its metadata, and ``ds.radar_range_doppler.isel(frame=3)`` reads one
chunk. The detections table becomes variables ``detection_<field>`` along ``detection``
(read when the file is opened: it is small); its per-frame form
``/radar/detections_by_frame`` becomes ``radar_detections_by_frame_<field>`` along
(``frame``, ``slot``), valid up to ``radar_detections_count`` in each frame.

Examples
--------
>>> ds = open_dataset("out/demo.h5")  # doctest: +SKIP
>>> ds.radar_range_doppler.isel(frame=3).plot()  # doctest: +SKIP
"""

from __future__ import annotations

import os
from typing import Any

import h5py
import numpy as np

from simcore.dsp.detections import DETECTION_UNITS
from simcore.io.layout import (
    COORDS,
    DIMS,
    ENTITY_GROUPS,
    PEOPLE_DIMS,
    PRODUCT_DIMS,
    RIGS_DIMS,
    SCENE_DIMS,
    coord_of,
    dims_of,
    entity_of,
    inner_dims,
    sensor_kinds,
    table_dims,
)

__all__ = ["COORDS", "DIMS", "ENTITY_GROUPS", "PEOPLE_DIMS", "PRODUCT_DIMS", "RIGS_DIMS",
           "SCENE_DIMS", "coord_of", "dims_of", "entity_of", "inner_dims", "open_dataset",
           "open_zarr_dataset", "sensor_kinds", "table_dims"]

_LABELS = {"xyz": ["x", "y", "z"], "corner": ["min", "max"], "color": ["r", "g", "b"]}


def _datasets(f: h5py.File) -> list[h5py.Dataset]:
    found: list[h5py.Dataset] = []
    f.visititems(lambda name, obj: found.append(obj) if isinstance(obj, h5py.Dataset)
                 else None)
    return found


def _lazy(ds: h5py.Dataset) -> Any:
    """A dask array over an HDF5 dataset, one chunk per frame (nothing read yet)."""
    import dask.array as da

    chunks = ds.chunks if ds.chunks is not None else ds.shape
    return da.from_array(ds, chunks=chunks, name=f"tofradar:{ds.file.filename}:{ds.name}",
                         lock=True, asarray=True)


def open_dataset(path: str | os.PathLike[str], *,
                 storage_options: dict[str, Any] | None = None) -> Any:
    """Open a tofradar dataset (HDF5 file or Zarr store) as a lazy ``xarray.Dataset``.

    Parameters
    ----------
    path : path-like or str
        The HDF5 file, or a Zarr store: ``PATH.zarr`` or a URL (``s3://``, ``memory://``, …)
        (``docs/dataset.md``).
    storage_options : dict, optional
        fsspec options of a remote Zarr store.

    Returns
    -------
    xarray.Dataset
        One variable per array (``/a/b`` → ``a_b``), dimensions named as in :data:`DIMS`
        behind a leading ``frame`` for per-frame arrays, coordinates ``time`` (s) on
        ``frame``, ``range`` (m), ``velocity`` (m/s), ``azimuth`` (deg), ``bev_x``/``bev_z``
        (m), ``object_name``/``object_id``; every variable and coordinate carries its unit
        in the attributes ``units`` and ``unit``. The file stays open until ``ds.close()``.
        Attributes of ``/meta`` become the dataset's attributes.
    """
    from simcore.io.writer import is_zarr_target

    if is_zarr_target(path):
        return open_zarr_dataset(os.fspath(path), storage_options=storage_options)
    f = h5py.File(path, "r")
    try:
        n_frames = int(f["meta"].attrs["n_frames"])
        project_json = f["meta"].attrs.get("project_json", "")
        kinds = sensor_kinds(project_json.decode() if isinstance(project_json, bytes)
                             else str(project_json))
        variables: dict[str, Any] = {}
        coords: dict[str, Any] = {}
        for ds in _datasets(f):
            if ds.attrs.get("table_rows", False):  # per-frame rows, padded: lazy, by field
                variables.update(_table_rows_variables(ds, kinds))
            elif ds.attrs.get("table", False):  # the detections: rows of all frames, read now
                variables.update(_table_variables(ds, kinds))
            else:
                key, is_coord, var = _array_variable(ds, path, n_frames, kinds)
                (coords if is_coord else variables)[key] = var
        dataset = _hdf5_xarray(f, variables, coords, n_frames)
    except Exception:
        f.close()
        raise
    dataset.set_close(f.close)
    return dataset


def _table_rows_variables(ds: h5py.Dataset, kinds: dict[str, str]) -> dict[str, Any]:
    """A per-frame table (padded rows) as lazy ``<path>_<field>`` variables (frame, slot)."""
    import xarray as xr

    name = ds.name
    rows = _lazy(ds)
    base = name.strip("/").replace("/", "_")
    slot = table_dims(name, kinds)[1]
    return {f"{base}_{field}": xr.Variable(
        ("frame", slot), rows[field],
        attrs={"units": DETECTION_UNITS.get(field, ""), "hdf5_path": name})
        for field in ds.dtype.names or ()}


def _table_variables(ds: h5py.Dataset, kinds: dict[str, str]) -> dict[str, Any]:
    """The detections table (rows of all frames), read now, one variable per field."""
    import xarray as xr

    table = ds[()]
    detection = table_dims(ds.name, kinds)[0]
    return {f"{detection}_{field}": xr.Variable(
        (detection,), table[field],
        attrs={"units": DETECTION_UNITS.get(field, ""), "hdf5_path": ds.name})
        for field in ds.dtype.names or ()}


def _array_variable(ds: h5py.Dataset, path: str | os.PathLike[str], n_frames: int,
                    kinds: dict[str, str]) -> tuple[str, bool, Any]:
    """(name, whether a coordinate, variable) of one array, with its named dimensions.

    Coordinates and names are read now; every other array stays lazy in the file.
    """
    import xarray as xr

    name = ds.name
    unit = str(ds.attrs.get("unit", ""))
    attrs = {"units": unit, "unit": unit, "hdf5_path": name}
    per_frame = bool(ds.attrs.get("per_frame", False)) or (
        name == "/time" and ds.shape == (n_frames,))
    inner = dims_of(name, kinds) or tuple(
        f"{name.strip('/').replace('/', '_')}_dim{i}"
        for i in range(ds.ndim - per_frame))
    dims = (("frame",) if per_frame else ()) + inner
    if len(dims) != ds.ndim:
        raise ValueError(f"{path}: {name} has shape {ds.shape}, expected dims {dims}")
    coord = coord_of(name, kinds)
    if name == "/time" or coord is not None:  # small: read now, as coordinates
        values = ds.asstr()[()] if ds.dtype.kind == "O" else ds[()]
        return coord or "time", True, xr.Variable(dims, values, attrs=attrs)
    if getattr(h5py.check_string_dtype(ds.dtype), "length", 0) is None:
        # Names (variable-length strings): str, as from a Zarr store.
        return name.strip("/").replace("/", "_"), False, xr.Variable(
            dims, ds.asstr()[()].astype(str), attrs=attrs)
    return name.strip("/").replace("/", "_"), False, xr.Variable(dims, _lazy(ds), attrs=attrs)


def _hdf5_xarray(f: h5py.File, variables: dict[str, Any], coords: dict[str, Any],
                 n_frames: int) -> Any:
    """The ``xarray.Dataset``: frame and label coordinates, ``/meta`` as attributes."""
    import xarray as xr

    coords["frame"] = xr.Variable(("frame",), np.arange(n_frames))
    for dim, labels in _LABELS.items():
        coords.setdefault(dim, xr.Variable((dim,), np.array(labels)))
    meta = {k: (v.decode() if isinstance(v, bytes) else v)
            for k, v in f["meta"].attrs.items()}
    dataset = xr.Dataset(variables, coords=coords, attrs=meta)
    # Only dims that some variable uses keep their label coordinates.
    unused = [d for d in _LABELS if d not in dataset.dims]
    return dataset.drop_vars(unused)


def _zarr_arrays(group: Any) -> list[tuple[str, Any]]:
    return sorted(("/" + name, node) for name, node in group.members(max_depth=None)
                  if hasattr(node, "shape"))


def open_zarr_dataset(url: str, *, storage_options: dict[str, Any] | None = None) -> Any:
    """Open a tofradar Zarr store like :func:`open_dataset` opens an HDF5 file.

    The same variables, dimensions, coordinates and units; per-frame arrays are cut to the
    ``n_frames`` complete frames. The detections' fields (one array each,
    ``radar/detections_by_frame/<field>``) become ``radar_detections_by_frame_<field>``
    along (``frame``, ``slot``) and, cut to each frame's count, ``detection_<field>``
    along ``detection``.
    """
    import dask.array as da
    import xarray as xr

    from simcore.io.zarr_writer import open_group

    group = open_group(url, mode="r", storage_options=storage_options)
    n_frames = int(group.attrs["n_frames"])
    kinds = sensor_kinds(str(group.attrs.get("project_json", "")))
    variables: dict[str, Any] = {}
    coords: dict[str, Any] = {}
    tables: dict[str, dict[str, Any]] = {}
    for name, array in _zarr_arrays(group):
        unit = str(array.attrs.get("unit", ""))
        dims = tuple(array.metadata.dimension_names or ())
        per_frame = bool(array.attrs.get("per_frame", False))
        attrs = {"units": unit, "unit": unit, "zarr_path": name}
        table, sep, field = name.rpartition("_by_frame/")
        if sep and per_frame:
            tables.setdefault(table, {})[field] = array
            continue
        coord = coord_of(name, kinds)
        if name == "/time" or coord is not None:  # small: read now, as coordinates
            values = np.asarray(array[:n_frames] if per_frame else array[...])
            if values.dtype.kind == "T":        # NumPy 2 strings → objects, as from HDF5
                values = values.astype(object)
            coords[coord or "time"] = xr.Variable(dims, values, attrs=attrs)
            continue
        data = da.from_zarr(array)
        variables[name.strip("/").replace("/", "_")] = xr.Variable(
            dims, data[:n_frames] if per_frame else data, attrs=attrs)
    for table, fields in tables.items():
        counts = np.asarray(group[f"{table.strip('/')}_count"][:n_frames])
        keep = np.arange(next(iter(fields.values())).shape[1])[None, :] < counts[:, None]
        base = table.strip("/").replace("/", "_")
        detection, slot = table_dims(table, kinds)
        for field, array in fields.items():
            unit = DETECTION_UNITS.get(field, "")
            attrs = {"units": unit, "zarr_path": f"{table}_by_frame/{field}"}
            data = da.from_zarr(array)[:n_frames]
            variables[f"{base}_by_frame_{field}"] = xr.Variable(("frame", slot), data,
                                                                attrs=attrs)
            flat = np.asarray(array[:n_frames])[keep]
            variables[f"{detection}_{field}"] = xr.Variable((detection,), flat, attrs=attrs)
    coords["frame"] = xr.Variable(("frame",), np.arange(n_frames))
    for dim, labels in _LABELS.items():
        coords.setdefault(dim, xr.Variable((dim,), np.array(labels)))
    meta = {k: v for k, v in group.attrs.items()}
    dataset = xr.Dataset(variables, coords=coords, attrs=meta)
    unused = [d for d in _LABELS if d not in dataset.dims]
    return dataset.drop_vars(unused)
