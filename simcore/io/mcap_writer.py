"""MCAP recordings with ROS 2 messages (``tofradar run PROJECT --out run.mcap``).

:class:`McapWriter` has the interface of :class:`~simcore.io.hdf5_writer.DatasetWriter`
(``write_static``, ``append_rows``, ``append``), so the runner drives either; every frame
becomes the messages of :func:`simcore.io.ros2_messages.frame_messages`, all logged and
stamped at the frame's simulation time. :func:`convert_hdf5_to_mcap` replays an HDF5
dataset through the same writer (``tofradar convert run.h5 --to run.mcap``).
"""

from __future__ import annotations

import json
import os
from pathlib import Path
from typing import IO, Any

import h5py
import numpy as np
from numpy.typing import NDArray

import simcore
from simcore.io.hdf5_writer import DatasetExistsError, ResumeError, temporary_path
from simcore.io.ros2_messages import (
    Items,
    RigDescription,
    encoder,
    frame_messages,
    message_definition,
)
from simcore.scene.project_io import project_from_dict


class McapWriter:
    """Append frames to an MCAP file as ROS 2 (CDR) messages.

    Parameters
    ----------
    path : path-like
        Output file (``.mcap``).
    project_json : str
        The full project document (the rig, sensors and object names come from it; it is
        also stored as MCAP metadata ``tofradar`` with the seed).
    seed : int
        Random seed of the run.
    overwrite : bool
        Replace an existing file (otherwise :class:`DatasetExistsError`).
    resume : bool
        Not supported for MCAP (:class:`ResumeError` when the file exists).
    """

    def __init__(self, path: str | os.PathLike[str], *, project_json: str, seed: int,
                 overwrite: bool = False, resume: bool = False,
                 extra_meta: dict[str, Any] | None = None):
        from mcap.writer import Writer

        self.path = Path(path)
        if self.path.exists() and resume:
            raise ResumeError(f"{self.path}: MCAP recordings cannot be resumed; write an HDF5 "
                              "dataset (.h5) to resume, or use --overwrite")
        if self.path.exists() and not overwrite:
            raise DatasetExistsError(f"{self.path} already exists; use --overwrite to replace it")
        self.path.parent.mkdir(parents=True, exist_ok=True)
        self.project = project_from_dict(json.loads(project_json), check_files=False)
        # Written beside the target and renamed into place when finished (as HDF5 runs).
        self.tmp = temporary_path(self.path)
        self._stream: IO[bytes] = open(self.tmp, "wb")  # noqa: SIM115 (closed in close())
        self._writer = Writer(self._stream)
        self._writer.start(profile="ros2", library=f"tofradar {simcore.__version__}")
        meta = {"project_json": project_json, "seed": str(seed),
                **{k: str(v) for k, v in (extra_meta or {}).items()}}
        self._writer.add_metadata("tofradar", meta)
        # One ROS 2 schema per message type, one CDR channel per topic of every sensor.
        self._topics = RigDescription.of(self.project, {}).topics()
        schemas = {datatype: self._writer.register_schema(
            datatype, "ros2msg", message_definition(datatype).encode())
            for datatype in sorted(set(self._topics.values()))}
        self._channels = {topic: self._writer.register_channel(topic, "cdr", schemas[datatype])
                          for topic, datatype in self._topics.items()}
        self._rig: RigDescription | None = None
        self._rows: dict[str, NDArray[Any]] = {}
        self.n_frames = 0

    def write_static(self, items: Items) -> None:
        """Take the run-constant items (radar axes) the frames' messages need."""
        self._rig = RigDescription.of(self.project, items)

    def append_rows(self, path: str, rows: NDArray[Any], *, unit: str = "") -> None:
        """Keep a frame's table rows (detections) for the next :meth:`append`."""
        self._rows[path] = rows

    def append(self, items: Items) -> None:
        """Write one frame's messages (with the rows given since the last frame).

        Each message is logged at its stamp: ``/tf`` at the frame's time, a sensor's
        topics at its capture time; a sensor that does not capture in this frame has none.
        """
        if self._rig is None:
            self._rig = RigDescription.of(self.project, {})
        for message in frame_messages(self._rig, items, self._rows):
            self._writer.add_message(self._channels[message.topic], log_time=message.stamp_ns,
                                     data=encoder(message.datatype)(message.msg),
                                     publish_time=message.stamp_ns, sequence=self.n_frames)
        self._rows.clear()
        self.n_frames += 1

    def write_frame(self, index: int, items: Items, tables: dict[str, NDArray[Any]]) -> None:
        """Write frame ``index`` (the next one: a recording is written in time order)."""
        if index != self.n_frames:
            raise ValueError(f"{self.path}: frame {index} written after {self.n_frames} "
                             "frames; an MCAP recording is written in frame order")
        for path, rows in tables.items():
            self.append_rows(path, rows)
        self.append(items)

    def missing(self, n_total: int) -> list[int]:
        """Frames still to write."""
        return list(range(self.n_frames, n_total))

    def close(self, *, keep: bool = True) -> None:
        """Finish the MCAP file (summary and index), close it and put it in place.

        ``keep=False`` (a run that failed) with no frame written deletes it, so a failed
        start leaves nothing and a failed overwrite leaves the old file untouched.
        """
        if self._stream.closed:
            return
        discard = not keep and self.n_frames == 0
        try:
            if not discard:
                self._writer.finish()
        finally:
            self._stream.close()
        if discard:
            self.tmp.unlink(missing_ok=True)
        else:
            os.replace(self.tmp, self.path)

    def __enter__(self) -> McapWriter:
        return self

    def __exit__(self, exc_type: type[BaseException] | None, *exc: object) -> None:
        self.close(keep=exc_type is None or issubclass(exc_type, KeyboardInterrupt))


def convert_hdf5_to_mcap(source: str | os.PathLike[str], target: str | os.PathLike[str], *,
                         overwrite: bool = False) -> int:
    """Write the frames of an HDF5 dataset into an MCAP recording.

    Parameters
    ----------
    source : path-like
        HDF5 dataset (``docs/dataset.md`` layout).
    target : path-like
        MCAP file to write.
    overwrite : bool
        Replace ``target`` if it exists.

    Returns
    -------
    int
        Number of frames written.
    """
    with h5py.File(source, "r") as f:
        meta = f["meta"].attrs
        n = int(meta["n_frames"])
        project = project_from_dict(json.loads(str(meta["project_json"])), check_files=False)
        radars = list(project.sensors_of_kind("radar"))
        static_prefixes = ("/objects/", "/people/", *(f"/{r}/" for r in radars))
        per_frame, static = [], {}
        for name, obj in _datasets(f):
            unit = str(obj.attrs.get("unit", ""))
            if obj.attrs.get("table", False) or obj.attrs.get("table_rows", False) or (
                    name.endswith("_count")):
                continue
            if obj.attrs.get("per_frame", False):
                per_frame.append((name, obj, unit))
            elif name.startswith(static_prefixes):
                static[name] = (obj[()], unit)
        with McapWriter(target, project_json=str(meta["project_json"]),
                        seed=int(meta["seed"]), overwrite=overwrite) as writer:
            writer.write_static(static)
            for k in range(n):
                for radar in radars:
                    rows = _detections_of_frame(f, k, radar, n)
                    if rows is not None:
                        writer.append_rows(f"/{radar}/detections", rows)
                items = {}
                for name, obj, unit in per_frame:
                    row = _row_of_frame(f, name, len(obj), k, n)
                    if row is not None:
                        items[name] = (obj[row], unit)
                writer.append(items)
    return n


def _row_of_frame(f: h5py.File, path: str, rows: int, k: int, n: int) -> int | None:
    """Row of frame ``k`` in a per-frame dataset of ``rows`` rows (None: not captured).

    A dataset with a row per frame: row ``k``. A sensor's dataset with a row per capture
    (fewer rows than frames): its ``/<sensor>/captured`` flags say which row, if any.
    """
    if rows == n:
        return k
    captured_path = f"/{path.strip('/').split('/')[0]}/captured"
    if captured_path == f"/{path.strip('/')}" or captured_path not in f:
        return k if k < rows else None
    captured = np.asarray(f[captured_path][()], dtype=bool)
    if k >= captured.size or not captured[k]:
        return None
    row = int(np.count_nonzero(captured[:k]))
    return row if row < rows else None


def _detections_of_frame(f: h5py.File, k: int, radar: str = "radar",
                         n: int | None = None) -> NDArray[Any] | None:
    """Frame ``k``'s detection rows of ``radar``: from the per-frame table, or the flat one."""
    if f"{radar}/detections_by_frame" in f:
        table = f[f"{radar}/detections_by_frame"]
        row = _row_of_frame(f, f"/{radar}/detections_by_frame", len(table), k,
                            len(table) if n is None else n)
        if row is None:
            return None
        return np.asarray(table[row][: int(f[f"{radar}/detections_count"][row])])
    if f"{radar}/detections" in f:
        det = f[f"{radar}/detections"]
        return np.asarray(det[det["frame"] == k]) if len(det) else np.asarray(det[:0])
    return None


def _datasets(f: h5py.File) -> list[tuple[str, h5py.Dataset]]:
    found: list[tuple[str, h5py.Dataset]] = []

    def visit(name: str, obj: object) -> None:
        if isinstance(obj, h5py.Dataset):
            found.append(("/" + name, obj))

    f.visititems(visit)
    return found
