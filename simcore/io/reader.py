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

import json
import os
from typing import Any

import h5py
import numpy as np

from simcore.dsp.detections import DETECTION_UNITS

#: Dimension names of each dataset of the layout, without the leading ``frame`` axis of
#: per-frame arrays.
DIMS: dict[str, tuple[str, ...]] = {
    "/poses/rig": ("pose_row", "pose_col"),
    "/poses/objects": ("object", "pose_row", "pose_col"),
    "/objects/names": ("object",),
    "/objects/ids": ("object",),
    "/objects/velocity": ("object", "xyz"),
    "/objects/angular_velocity": ("object", "xyz"),
    "/objects/aabb": ("object", "corner", "xyz"),
    "/objects/obb_center": ("object", "xyz"),
    "/objects/obb_rotation": ("object", "xyz", "axis"),
    "/objects/obb_size": ("object", "axis"),
    "/objects/reference_point": ("object", "xyz"),
    "/objects/radar_range": ("object",),
    "/objects/radar_radial_velocity": ("object",),
    "/objects/radar_azimuth": ("object",),
    "/objects/radar_elevation": ("object",),
    "/tof/depth": ("row", "col"),
    "/tof/amplitude": ("row", "col"),
    "/tof/intensity": ("row", "col"),
    "/tof/valid": ("row", "col"),
    "/tof/correlation": ("tap", "row", "col"),
    "/tof/gt_range": ("row", "col"),
    "/tof/gt_object_id": ("row", "col"),
    "/rgb/image": ("rgb_row", "rgb_col", "color"),
    "/rgb/gt_object_id": ("rgb_row", "rgb_col"),
    "/radar/adc": ("chirp", "channel", "sample"),
    "/radar/chirp_start_time": ("chirp", "tx"),
    "/radar/range_axis": ("range",),
    "/radar/velocity_axis": ("velocity",),
    "/radar/azimuth_axis": ("azimuth",),
    "/radar/range_profile": ("channel", "range"),
    "/radar/range_profile_integrated": ("range",),
    "/radar/range_doppler": ("velocity", "range"),
    "/radar/range_azimuth": ("azimuth", "range"),
    "/radar/bird_eye": ("bev_z", "bev_x"),
    "/radar/bird_eye_x_axis": ("bev_x",),
    "/radar/bird_eye_z_axis": ("bev_z",),
    "/radar/detections_count": (),
    "/meta/frame_sha256": (),
}

#: Dimension names of the datasets that only projects with several rigs write.
RIGS_DIMS: dict[str, tuple[str, ...]] = {
    "/poses/rigs": ("rig", "pose_row", "pose_col"),
    "/poses/rig_names": ("rig",),
}

#: Dimension names of the datasets that only runs over several scenes write
#: (``tofradar run DIR``; docs/scenarios.md).
SCENE_DIMS: dict[str, tuple[str, ...]] = {
    "/scene_index": (),
    "/scenes/names": ("scene",),
    "/scenes/seeds": ("scene",),
    "/scenes/projects": ("scene",),
}

#: Datasets added after a run by ``tofradar products`` (:mod:`simcore.io.products`).
PRODUCT_DIMS: dict[str, tuple[str, ...]] = {
    "/radar/spectrogram/power": ("spectrogram_time", "spectrogram_velocity"),
    "/radar/spectrogram/time": ("spectrogram_time",),
    "/radar/spectrogram/velocity_axis": ("spectrogram_velocity",),
    "/radar/spectrogram/gate_center": ("frame",),
    "/radar/vitals/time": ("frame",),
    "/radar/vitals/displacement": ("frame",),
    "/radar/vitals/breathing_rate": ("frame",),
    "/radar/vitals/breathing_amplitude": ("frame",),
    "/radar/vitals/heart_rate": ("frame",),
    "/radar/vitals/heart_amplitude": ("frame",),
}

#: Dimension names of the datasets that only projects with people write (docs/people.md).
PEOPLE_DIMS: dict[str, tuple[str, ...]] = {
    "/tof/gt_body_part": ("row", "col"),
    "/rgb/gt_body_part": ("rgb_row", "rgb_col"),
    "/people/names": ("person",),
    "/people/object_ids": ("person",),
    "/people/body_part_names": ("body_part",),
    "/people/segments/names": ("segment",),
    "/people/segments/person": ("segment",),
    "/people/segments/body_part": ("segment",),
    "/people/segments/pose": ("segment", "pose_row", "pose_col"),
    "/people/segments/velocity": ("segment", "xyz"),
    "/people/segments/angular_velocity": ("segment", "xyz"),
    "/people/segments/radar_range": ("segment",),
    "/people/segments/radar_radial_velocity": ("segment",),
    "/people/segments/radar_azimuth": ("segment",),
    "/people/segments/radar_elevation": ("segment",),
    "/people/breathing_displacement": ("person",),
    "/people/heartbeat_displacement": ("person",),
    "/people/breathing_rate": ("person",),
    "/people/heart_rate": ("person",),
    "/people/gait_phase": ("person",),
}

#: Dimensions whose length is a scene's count of things (objects, people, body segments),
#: and the group of each: in a run over scenes whose counts differ, arrays along them are
#: padded to the largest scene's count, with ``<group>/count`` and ``<group>/valid`` per
#: frame and the names per scene under ``/scenes<group>/`` (docs/dataset.md).
ENTITY_GROUPS: dict[str, str] = {"object": "/objects", "person": "/people",
                                 "segment": "/people/segments"}


def inner_dims(path: str) -> tuple[str, ...] | None:
    """Dimension names of a dataset of the layout, without a per-frame leading ``frame``."""
    for table in (DIMS, RIGS_DIMS, PEOPLE_DIMS, SCENE_DIMS, PRODUCT_DIMS):
        if path in table:
            return table[path]
    return None


def entity_of(path: str) -> str | None:
    """The entity dimension (``object``, ``person``, ``segment``) of ``path``'s first axis."""
    dims = inner_dims(path)
    return dims[0] if dims and dims[0] in ENTITY_GROUPS else None


def _entity_scene_dims() -> dict[str, tuple[str, ...]]:
    """``/objects/count``, ``/objects/valid``, ``/scenes/objects/names`` … of each entity."""
    out: dict[str, tuple[str, ...]] = {}
    for entity, group in ENTITY_GROUPS.items():
        out[f"{group}/count"] = ()
        out[f"{group}/valid"] = (entity,)
        out[f"/scenes{group}/count"] = ("scene",)
    for table in (DIMS, PEOPLE_DIMS):
        for path, dims in table.items():
            if dims and dims[0] in ENTITY_GROUPS:
                out[f"/scenes{path}"] = ("scene", *dims)
    return out


SCENE_DIMS.update(_entity_scene_dims())

#: Axis datasets that become coordinates: path → coordinate name.
COORDS = {
    "/radar/range_axis": "range",
    "/radar/velocity_axis": "velocity",
    "/radar/azimuth_axis": "azimuth",
    "/radar/bird_eye_x_axis": "bev_x",
    "/radar/bird_eye_z_axis": "bev_z",
    "/radar/spectrogram/time": "spectrogram_time",
    "/radar/spectrogram/velocity_axis": "spectrogram_velocity",
    "/objects/names": "object_name",
    "/poses/rig_names": "rig_name",
    "/objects/ids": "object_id",
    "/people/names": "person_name",
    "/people/segments/names": "segment_name",
    "/people/body_part_names": "body_part_name",
}

_LABELS = {"xyz": ["x", "y", "z"], "corner": ["min", "max"], "color": ["r", "g", "b"]}


#: Dimensions that keep their name under a named sensor's group (they have label coordinates
#: or mean the same for every sensor); the others get the sensor's name as a prefix.
_COMMON_DIMS = frozenset({"xyz", "corner", "color", "axis", "pose_row", "pose_col", "object",
                          "segment", "person"})


def sensor_kinds(project_json: str) -> dict[str, str]:
    """Kind of every sensor of a stored project document, by name (``{}`` if unreadable).

    Read from the document as stored (any format version: a version-2 project has the
    built-in ``tof`` and ``radar``, and ``rgb`` when set).
    """
    try:
        doc = json.loads(project_json)
        rig = doc.get("rig") or {}
        kinds = {k: k for k in ("tof", "radar") if k in rig or "rig" in doc}
        if rig.get("rgb") is not None:
            kinds["rgb"] = "rgb"
        for r in [rig, *(doc.get("rigs") or [])]:
            for name, cfg in (r.get("sensors") or {}).items():
                kinds[str(name)] = str(cfg.get("kind", ""))
        return kinds
    except (ValueError, AttributeError, TypeError):
        return {}


def _builtin_path(path: str, kinds: dict[str, str]) -> tuple[str, str] | None:
    """``(path under its kind's group, sensor name)`` for a named sensor's dataset path."""
    head, sep, rest = path.strip("/").partition("/")
    kind = kinds.get(head)
    if not sep or kind is None or kind == head:
        return None
    return f"/{kind}/{rest}", head


def dims_of(path: str, kinds: dict[str, str] | None = None) -> tuple[str, ...] | None:
    """Dimension names of dataset ``path`` (without the frame axis), None when unknown.

    A named sensor's datasets (``/front_radar/range_doppler``) have the dimensions of its
    kind's (``/radar/range_doppler``), prefixed with its name (``front_radar_velocity``,
    ``front_radar_range``) so that sensors with other axes do not clash; a named radar's
    object truth (``/objects/<name>/range``) is along ``object``, its people truth
    (``/people/segments/<name>/range``) along ``segment``.
    """
    found = (DIMS.get(path) or RIGS_DIMS.get(path) or PRODUCT_DIMS.get(path)
             or PEOPLE_DIMS.get(path) or SCENE_DIMS.get(path))
    if found is not None or not kinds:
        return found
    builtin = _builtin_path(path, kinds)
    if builtin is not None:
        base = dims_of(builtin[0])
        if base is None:
            return None
        return tuple(d if d in _COMMON_DIMS else f"{builtin[1]}_{d}" for d in base)
    parts = path.strip("/").split("/")
    if len(parts) == 3 and parts[0] == "objects" and parts[1] in kinds:
        return ("object",)
    if len(parts) == 4 and parts[:2] == ["people", "segments"] and parts[2] in kinds:
        return ("segment",)
    return None


def coord_of(path: str, kinds: dict[str, str] | None = None) -> str | None:
    """The coordinate that dataset ``path`` becomes, None for a plain variable.

    ``/radar/range_axis`` → ``range``; a named radar's ``/<name>/range_axis`` →
    ``<name>_range``.
    """
    if path in COORDS or not kinds:
        return COORDS.get(path)
    builtin = _builtin_path(path, kinds)
    if builtin is None or builtin[0] not in COORDS:
        return None
    return f"{builtin[1]}_{COORDS[builtin[0]]}"


def _table_names(path: str, kinds: dict[str, str]) -> tuple[str, str]:
    """Row dimension of a detections table and slot dimension of its per-frame form.

    ``detection`` and ``slot`` for the built-in radar's; ``<name>_detection`` and
    ``<name>_slot`` for a named radar's (its variables ``<name>_detection_<field>``).
    """
    builtin = _builtin_path(path.removesuffix("_by_frame"), kinds)
    if builtin is None:
        return "detection", "slot"
    return f"{builtin[1]}_detection", f"{builtin[1]}_slot"


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
    import xarray as xr

    f = h5py.File(path, "r")
    try:
        n_frames = int(f["meta"].attrs["n_frames"])
        project_json = f["meta"].attrs.get("project_json", "")
        kinds = sensor_kinds(project_json.decode() if isinstance(project_json, bytes)
                             else str(project_json))
        variables: dict[str, Any] = {}
        coords: dict[str, Any] = {}
        for ds in _datasets(f):
            name = ds.name
            unit = str(ds.attrs.get("unit", ""))
            attrs = {"units": unit, "unit": unit, "hdf5_path": name}
            if ds.attrs.get("table_rows", False):  # per-frame rows, padded: lazy, by field
                rows = _lazy(ds)
                base = name.strip("/").replace("/", "_")
                slot = _table_names(name, kinds)[1]
                for field in ds.dtype.names or ():
                    variables[f"{base}_{field}"] = xr.Variable(
                        ("frame", slot), rows[field],
                        attrs={"units": DETECTION_UNITS.get(field, ""), "hdf5_path": name})
                continue
            if ds.attrs.get("table", False):  # the detections: rows of all frames, read now
                table = ds[()]
                detection = _table_names(name, kinds)[0]
                for field in ds.dtype.names or ():
                    variables[f"{detection}_{field}"] = xr.Variable(
                        (detection,), table[field],
                        attrs={"units": DETECTION_UNITS.get(field, ""), "hdf5_path": name})
                continue
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
                coords[coord or "time"] = xr.Variable(dims, values, attrs=attrs)
            elif getattr(h5py.check_string_dtype(ds.dtype), "length", 0) is None:
                # Names (variable-length strings): str, as from a Zarr store.
                variables[name.strip("/").replace("/", "_")] = xr.Variable(
                    dims, ds.asstr()[()].astype(str), attrs=attrs)
            else:
                var = xr.Variable(dims, _lazy(ds), attrs=attrs)
                variables[name.strip("/").replace("/", "_")] = var
        coords["frame"] = xr.Variable(("frame",), np.arange(n_frames))
        for dim, labels in _LABELS.items():
            coords.setdefault(dim, xr.Variable((dim,), np.array(labels)))
        meta = {k: (v.decode() if isinstance(v, bytes) else v)
                for k, v in f["meta"].attrs.items()}
        dataset = xr.Dataset(variables, coords=coords, attrs=meta)
        # Only dims that some variable uses keep their label coordinates.
        unused = [d for d in _LABELS if d not in dataset.dims]
        dataset = dataset.drop_vars(unused)
    except Exception:
        f.close()
        raise
    dataset.set_close(f.close)
    return dataset


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
        detection, slot = _table_names(table, kinds)
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
