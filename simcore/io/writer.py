"""The one interface every dataset writer has, and the thread that takes writing off the engine.

:class:`FrameWriter` is what :func:`simcore.runs.runner.run_dataset` drives: HDF5
(:class:`simcore.io.hdf5_writer.DatasetWriter`), MCAP
(:class:`simcore.io.mcap_writer.McapWriter`) and Zarr v3
(:class:`simcore.io.zarr_writer.ZarrWriter`). :func:`open_writer` picks one from the
output's name; :class:`ThreadedWriter` runs a writer's frames in a background thread, so
that encoding, checksums and I/O of frame k overlap the computation of frame k+1.
"""

from __future__ import annotations

import os
import queue
import threading
from collections.abc import Callable
from types import TracebackType
from typing import Any, Protocol

from numpy.typing import NDArray

#: ``path → (array, unit)`` of one frame (as :meth:`simcore.pipeline.Frame.hdf5_items`).
Items = dict[str, tuple[NDArray[Any], str]]
#: URL schemes that name a Zarr store (fsspec / obstore).
ZARR_SCHEMES = ("file", "s3", "gs", "gcs", "az", "abfs", "memory", "http", "https")


class FrameWriter(Protocol):
    """A dataset being written: run-constant arrays once, then frames, then metadata.

    ``n_frames`` counts the complete frames at the start of the dataset (frames
    ``0..n_frames-1``); a resumed writer starts with the frames it found complete.
    """

    n_frames: int

    def write_static(self, items: Items) -> None:
        """Write the run-constant arrays (axes, object names) with their units."""

    def write_frame(self, index: int, items: Items, tables: dict[str, NDArray[Any]]) -> None:
        """Write frame ``index``: its arrays ``items`` and its table rows ``tables``."""

    def missing(self, n_total: int) -> list[int]:
        """Frames of ``0..n_total-1`` that are not complete yet, in order."""

    def close(self, *, keep: bool = True) -> None:
        """Commit the metadata and close (``keep=False``: the run failed)."""


def is_zarr_target(out: str | os.PathLike[str]) -> bool:
    """Whether ``out`` names a Zarr store: ``*.zarr`` or a URL such as ``s3://b/run``."""
    text = os.fspath(out)
    scheme, sep, _ = text.partition("://")
    if sep and scheme.lower() in ZARR_SCHEMES:
        return True
    return text.rstrip("/").lower().endswith(".zarr")


def open_writer(out: str | os.PathLike[str], *, project_json: str, seed: int,
                overwrite: bool = False, resume: bool = False,
                extra_meta: dict[str, Any] | None = None,
                storage_options: dict[str, Any] | None = None,
                shard_frames: int | None = None) -> Any:
    """The writer for ``out``: Zarr for ``*.zarr`` and URLs, MCAP for ``*.mcap``, else HDF5.

    Parameters
    ----------
    out : str or path-like
        File, folder or URL (``file://``, ``s3://``, ``gs://``, ``memory://``).
    project_json : str
        The project document, stored in the metadata.
    seed : int
        Random seed of the run.
    overwrite, resume : bool
        Replace an existing dataset, or continue it.
    extra_meta : dict, optional
        More metadata attributes.
    storage_options : dict, optional
        fsspec options of a remote Zarr store (``endpoint_url``, ``key``, …).
    shard_frames : int, optional
        Zarr: frames per shard (the unit one worker writes).
    """
    kw: dict[str, Any] = {"project_json": project_json, "seed": seed,
                          "overwrite": overwrite, "resume": resume, "extra_meta": extra_meta}
    if is_zarr_target(out):
        from simcore.io.zarr_writer import ZarrWriter

        if shard_frames is not None:
            kw["shard_frames"] = shard_frames
        return ZarrWriter(os.fspath(out), storage_options=storage_options, **kw)
    if os.fspath(out).lower().endswith(".mcap"):
        from simcore.io.mcap_writer import McapWriter

        return McapWriter(out, **kw)
    from simcore.io.hdf5_writer import DatasetWriter

    return DatasetWriter(out, **kw)


class ThreadedWriter:
    """Write frames in a background thread, at most ``depth`` frames behind the caller.

    :meth:`submit` hands a computed frame over and returns at once (or waits while
    ``depth`` frames are queued: memory stays bounded). After each frame is written the
    thread calls ``on_written(frames complete, frame)``; when that returns False or raises
    (Ctrl+C), the thread writes nothing more and :attr:`stopped` turns true, so a stop
    leaves exactly the frames the callback has seen. An error of the writer (a full disk)
    or of the callback is raised by the next :meth:`submit` or by :meth:`finish`.

    Parameters
    ----------
    writer : FrameWriter
        The dataset being written.
    on_written : callable, optional
        ``(frames complete, frame) -> bool``, called in the writer thread.
    depth : int
        Most frames waiting to be written.
    """

    def __init__(self, writer: Any, *, on_written: Callable[[int, Any], bool] | None = None,
                 depth: int = 2):
        self.writer = writer
        self.on_written = on_written
        self.stopped = False
        self._todo: queue.Queue[Any] = queue.Queue(maxsize=max(1, depth))
        self._error: BaseException | None = None
        self._thread = threading.Thread(target=self._loop, name="dataset-writer", daemon=True)
        self._thread.start()

    def _loop(self) -> None:
        while True:
            frame = self._todo.get()
            if frame is None:
                return
            if self.stopped:
                continue            # after a stop or an error: drop the rest
            try:
                self.writer.write_frame(frame.index, frame.items, frame.tables)
                if self.on_written is not None and not self.on_written(
                        self.writer.n_frames, frame):
                    self.stopped = True
            except BaseException as exc:  # noqa: BLE001 — raised again in the caller
                self._error = exc
                self.stopped = True

    def _raise(self) -> None:
        if self._error is not None:
            error, self._error = self._error, None
            raise error

    def submit(self, frame: Any) -> bool:
        """Queue ``frame`` (``.index``, ``.items``, ``.tables``); False once stopped."""
        while not self.stopped:
            try:
                self._todo.put(frame, timeout=0.2)
                break
            except queue.Full:
                continue
        self._raise()
        return not self.stopped

    def finish(self, *, drop: bool = False) -> None:
        """Write what is queued (or drop it: ``drop``), stop the thread, raise its error."""
        if drop:
            self.stopped = True
            while True:
                try:
                    self._todo.get_nowait()
                except queue.Empty:
                    break
        if self._thread.is_alive():
            self._todo.put(None)
            self._thread.join()
        self._raise()

    def __enter__(self) -> ThreadedWriter:
        return self

    def __exit__(self, exc_type: type[BaseException] | None, exc: BaseException | None,
                 tb: TracebackType | None) -> None:
        if self._thread.is_alive():
            self.finish(drop=exc_type is not None)


__all__ = ["FrameWriter", "Items", "ThreadedWriter", "is_zarr_target", "open_writer"]
