"""HDF5 dataset writer: one frame at a time, chunked per frame, compressed, flat memory.

Layout (see ``docs/dataset.md``): every per-frame array gets a leading frame axis N and a
``unit`` attribute; run-constant arrays (axes, object names) are written once; ``/meta``
carries the format version, the full project JSON, creation time, tofradar version and
seed. The file is flushed after every frame, so an interrupted run leaves a readable file
holding the frames completed so far (``/meta`` attribute ``n_frames``).
"""

from __future__ import annotations

import datetime as _dt
import os
from pathlib import Path
from types import TracebackType
from typing import Any

import h5py
import numpy as np
from numpy.typing import NDArray

import simcore

DATASET_FORMAT_VERSION = 1
COMPRESSION: dict[str, Any] = {"compression": "gzip", "compression_opts": 1, "shuffle": True}


class DatasetExistsError(FileExistsError):
    """The output file exists and overwriting was not requested."""


class ResumeError(ValueError):
    """An existing file cannot be continued with ``--resume``."""


class DatasetWriter:
    """Append frames to an HDF5 dataset file.

    Parameters
    ----------
    path : path-like
        Output file.
    project_json : str
        The full project document, stored in ``/meta``.
    seed : int
        Random seed of the run, stored in ``/meta``.
    overwrite : bool
        Replace an existing file (otherwise :class:`DatasetExistsError`).
    """

    def __init__(self, path: str | os.PathLike[str], *, project_json: str, seed: int,
                 overwrite: bool = False, resume: bool = False,
                 extra_meta: dict[str, Any] | None = None):
        self.path = Path(path)
        if resume and self.path.exists():
            self._open_for_resume(project_json, seed)
            return
        if self.path.exists() and not overwrite:
            raise DatasetExistsError(
                f"{self.path} already exists; use --overwrite to replace it or --resume to "
                "continue it"
            )
        self.path.parent.mkdir(parents=True, exist_ok=True)
        self.file = h5py.File(self.path, "w")
        meta = self.file.create_group("meta")
        meta.attrs["format_version"] = DATASET_FORMAT_VERSION
        meta.attrs["project_json"] = project_json
        meta.attrs["created"] = _dt.datetime.now(_dt.timezone.utc).isoformat()
        meta.attrs["tofradar_version"] = simcore.__version__
        meta.attrs["seed"] = seed
        meta.attrs["n_frames"] = 0
        for key, value in (extra_meta or {}).items():
            meta.attrs[key] = value
        self.n_frames = 0

    def _open_for_resume(self, project_json: str, seed: int) -> None:
        try:
            self.file = h5py.File(self.path, "a")
        except OSError as exc:
            raise ResumeError(f"cannot resume {self.path}: not a readable HDF5 file ({exc})"
                              ) from None
        meta = self.file.get("meta")
        if meta is None or "n_frames" not in meta.attrs:
            self.file.close()
            raise ResumeError(f"cannot resume {self.path}: it is not a tofradar dataset")
        if meta.attrs["project_json"] != project_json or int(meta.attrs["seed"]) != seed:
            self.file.close()
            raise ResumeError(f"cannot resume {self.path}: it was written from a different "
                              "project or seed")
        self.n_frames = int(meta.attrs["n_frames"])
        self._truncate()

    def _frame_datasets(self) -> list[h5py.Dataset]:
        found: list[h5py.Dataset] = []

        def visit(name: str, obj: object) -> None:
            if isinstance(obj, h5py.Dataset) and obj.maxshape and obj.maxshape[0] is None \
                    and obj.attrs.get("per_frame", False):
                found.append(obj)

        self.file.visititems(visit)
        return found

    def _truncate(self) -> None:
        """Drop anything written past ``n_frames`` (a frame interrupted half-way)."""
        for ds in self._frame_datasets():
            if ds.attrs.get("table", False):
                keep = ds.fields("frame")[:] < self.n_frames if len(ds) else np.zeros(0, bool)
                if not keep.all():
                    ds.resize(int(np.count_nonzero(keep)), axis=0)
            elif ds.shape[0] != self.n_frames:
                ds.resize(self.n_frames, axis=0)

    def write_static(self, items: dict[str, tuple[NDArray[Any], str]]) -> None:
        """Write run-constant arrays (axes, names) once, with their units."""
        for path, (array, unit) in items.items():
            arr = np.asarray(array)
            if arr.dtype.kind == "U":
                ds = self.file.create_dataset(path, data=arr.astype(object),
                                              dtype=h5py.string_dtype())
            else:
                ds = self.file.create_dataset(path, data=arr)
            ds.attrs["unit"] = unit

    def append(self, items: dict[str, tuple[NDArray[Any], str]]) -> None:
        """Append one frame: every array gets index ``n_frames`` along a new first axis."""
        n = self.n_frames
        for path, (array, unit) in items.items():
            arr = np.asarray(array)
            if path not in self.file:
                ds = self.file.create_dataset(
                    path, shape=(0, *arr.shape), maxshape=(None, *arr.shape), dtype=arr.dtype,
                    chunks=(1, *arr.shape) if arr.ndim else (1024,),
                    **(COMPRESSION if arr.size > 64 else {}),
                )
                ds.attrs["unit"] = unit
                ds.attrs["per_frame"] = True
            ds = self.file[path]
            if ds.shape[1:] != arr.shape:
                raise ValueError(f"{path}: frame shape {arr.shape} != dataset {ds.shape[1:]}")
            ds.resize(n + 1, axis=0)
            ds[n] = arr
        self.n_frames = n + 1
        self.file["meta"].attrs["n_frames"] = self.n_frames
        self.file.flush()

    def append_rows(self, path: str, rows: NDArray[Any], *, unit: str = "") -> None:
        """Append records of the current frame to a growing table (e.g. detections).

        Call before :meth:`append` of the same frame; ``rows`` must have a ``frame`` field.
        """
        if path not in self.file:
            ds = self.file.create_dataset(path, shape=(0,), maxshape=(None,), dtype=rows.dtype,
                                          chunks=(1024,), **COMPRESSION)
            ds.attrs["unit"] = unit
            ds.attrs["per_frame"] = True
            ds.attrs["table"] = True
        ds = self.file[path]
        start = ds.shape[0]
        ds.resize(start + len(rows), axis=0)
        ds[start:] = rows

    def close(self) -> None:
        """Drop any half-written frame, flush and close the file."""
        if self.file.id.valid:
            self._truncate()
            self.file.close()

    def __enter__(self) -> DatasetWriter:
        return self

    def __exit__(self, exc_type: type[BaseException] | None, exc: BaseException | None,
                 tb: TracebackType | None) -> None:
        self.close()
