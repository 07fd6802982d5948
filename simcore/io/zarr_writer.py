"""Zarr v3 datasets: the HDF5 layout in shards of frames, on a disk or in an object store.

``tofradar run PROJECT --out run.zarr`` (or ``s3://bucket/run``, ``gs://…``,
``memory://…``, ``file://…``) writes the arrays, attributes and units of the HDF5 layout
(``docs/dataset.md``) as a Zarr v3 hierarchy:

- every per-frame array has shape ``(N, …)``, one chunk per frame inside shards of
  ``shard_frames`` frames (Blosc/Zstd level 1 with byte shuffle), and the v3
  ``dimension_names`` of :data:`simcore.io.reader.DIMS`, so ``xarray.open_zarr(url,
  group="radar")`` names its dimensions;
- small arrays (at most :data:`SMALL_VALUES` values per frame: ``/time``, counts, poses,
  per-object truth, the detections' fields) are chunked one shard each, which saves zarr's
  per-chunk work (an office frame's writing: 30 → 21 ms of CPU);
- the detections (a compound table in HDF5) are one array per field,
  ``radar/detections_by_frame/<field>`` of shape ``(N, max_detections)``, valid up to
  ``radar/detections_count[k]`` in frame ``k``;
- ``meta/frame_sha256`` ``(N, 32)`` uint8 holds each frame's SHA-256 (the same digest as
  the HDF5 file's hex string) and is the frame's completion record: it is written after
  the frame's data, one chunk per shard, so a frame counts only when its whole shard is
  stored; root attribute ``n_frames`` (the complete frames from the start) is committed
  by the driver.

Shards are the unit of writing: one process writes a whole shard (its frames' data, then
its checksums) and no two processes ever write one shard, so workers write their own
frames concurrently (:func:`write_shard`) while the driver only creates the arrays and
commits metadata. ``resume`` recomputes the shards without a complete record.

A frame is prepared when it arrives (:class:`ShardBuffer`): its checksum is taken, its
large arrays' chunks are Blosc-compressed (:class:`ShardEncoder`, the bytes of zarr's
sharding codec) and its small arrays copied into the shard's blocks, so the work is
spread over the frames in the writer thread; a complete shard is then one store write
per array (:class:`BlockEncoder` for the small ones), the completion record last. These
are the bytes zarr's own codecs write; arrays of other codecs go through zarr.
"""

from __future__ import annotations

import datetime as _dt
import json
import os
import warnings
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any, Literal

import numpy as np
from numpy.typing import NDArray

import simcore
from simcore.io.hdf5_writer import (
    DATASET_FORMAT_VERSION,
    DatasetExistsError,
    ResumeError,
    frame_checksum,
)
from simcore.io.layout import sensor_kinds

#: Frames per shard by default (a shard of the office is about 32 MB before compression).
DEFAULT_SHARD_FRAMES = 16
#: Arrays of at most this many values per frame (16 KiB of float32) get one chunk per
#: shard (no inner chunks): reading one frame of them decodes at most 256 KiB.
SMALL_VALUES = 4096
CHECKSUM_PATH = "meta/frame_sha256"
#: Attributes of the root group set when the store is created (the rest are extra meta).
CORE_ATTRS = ("format_version", "project_json", "created", "tofradar_version", "seed",
              "n_frames", "shard_frames", "storage")


def _codecs(dtype: np.dtype[Any]) -> dict[str, Any]:
    from zarr.codecs import BloscCodec

    shuffle: Literal["shuffle", "noshuffle"] = "shuffle" if dtype.itemsize > 1 else "noshuffle"
    return {"compressors": BloscCodec(cname="zstd", clevel=1, shuffle=shuffle,
                                      typesize=dtype.itemsize)}


def _dims(path: str, ndim: int, *, per_frame: bool,
          kinds: dict[str, str] | None = None) -> tuple[str, ...]:
    from simcore.io.layout import dims_of

    inner = dims_of(path, kinds) or tuple(
        f"{path.strip('/').replace('/', '_')}_dim{i}" for i in range(ndim))
    if len(inner) != ndim:
        inner = tuple(f"{path.strip('/').replace('/', '_')}_dim{i}" for i in range(ndim))
    return ("frame", *inner) if per_frame else inner


def open_group(url: str, *, mode: str, storage_options: dict[str, Any] | None = None) -> Any:
    """Open the Zarr v3 group at ``url`` (path or fsspec URL)."""
    import zarr

    kw: dict[str, Any] = {"mode": mode, "zarr_format": 3}
    if mode != "w":
        # Our own reads and appends see the store as it is, not its consolidated
        # metadata (which is rewritten as frames are committed: :func:`consolidate`).
        kw["use_consolidated"] = False
    if "://" in url and storage_options:
        kw["storage_options"] = storage_options
    return zarr.open_group(_store_url(url), **kw)


def consolidate(group: Any) -> None:
    """Write the consolidated metadata of ``group``'s store (``xarray.open_zarr`` reads it).

    Rewritten whenever the count of complete frames changes, so a reader that trusts it
    sees every array and the committed ``n_frames``.
    """
    import zarr

    with warnings.catch_warnings():
        # zarr 3 warns that consolidated metadata is not yet part of the v3 spec.
        warnings.simplefilter("ignore", UserWarning)
        zarr.consolidate_metadata(group.store, zarr_format=3)


def _store_url(url: str) -> str:
    return url.removeprefix("file://") if url.startswith("file://") else url


@dataclass(frozen=True)
class ShardTarget:
    """Where a worker writes its shards (picklable, small)."""

    url: str
    storage_options: dict[str, Any] | None
    shard_frames: int
    n_total: int
    max_detections: int


class ZarrWriter:
    """Write a run into a Zarr v3 store, a shard of frames at a time.

    Parameters
    ----------
    url : str
        ``PATH.zarr`` or an fsspec URL (``file://``, ``s3://``, ``gs://``, ``memory://``).
    project_json : str
        The project document, stored as root attribute ``project_json``.
    seed : int
        Random seed of the run.
    overwrite : bool
        Replace an existing store (it is deleted when the run starts).
    resume : bool
        Continue an existing store of the same project and seed.
    extra_meta : dict, optional
        More root attributes.
    storage_options : dict, optional
        fsspec options of a remote store (``endpoint_url``, ``key``, ``secret``, …).
    shard_frames : int
        Frames per shard.
    """

    def __init__(self, url: str, *, project_json: str, seed: int, overwrite: bool = False,
                 resume: bool = False, extra_meta: dict[str, Any] | None = None,
                 storage_options: dict[str, Any] | None = None,
                 shard_frames: int = DEFAULT_SHARD_FRAMES):
        self.url = url
        self.path = url
        self.storage_options = storage_options
        self.max_detections = _max_detections(project_json)
        self.kinds = sensor_kinds(project_json)
        self._pending: dict[int, ShardBuffer] = {}
        self._complete: set[int] = set()
        self._arrays: ArrayCache | None = None
        self.n_total = 0
        existing = _exists(url, storage_options)
        if existing and resume:
            self.group = open_group(url, mode="r+", storage_options=storage_options)
            self._check_resume(project_json, seed)
            self.shard_frames = int(self.group.attrs["shard_frames"])
        elif existing and not overwrite:
            raise DatasetExistsError(f"{url} already exists; use --overwrite to replace it or "
                                     "--resume to continue it")
        else:
            if existing:
                _check_replaceable(url, storage_options)
            self.shard_frames = max(1, int(shard_frames))
            self.group = open_group(url, mode="w", storage_options=storage_options)
            attrs = {"format_version": DATASET_FORMAT_VERSION, "project_json": project_json,
                     "created": _dt.datetime.now(_dt.timezone.utc).isoformat(),
                     "tofradar_version": simcore.__version__, "seed": int(seed),
                     "n_frames": 0, "shard_frames": self.shard_frames, "storage": "zarr"}
            attrs.update({k: _plain(v) for k, v in (extra_meta or {}).items()})
            self.group.attrs.update(attrs)
        self.n_frames = int(self.group.attrs.get("n_frames", 0))

    # ------------------------------------------------------------------ opening
    def _check_resume(self, project_json: str, seed: int) -> None:
        attrs = self.group.attrs
        if "n_frames" not in attrs or attrs.get("storage") != "zarr":
            raise ResumeError(f"cannot resume {self.url}: it is not a tofradar dataset")
        if attrs.get("project_json") != project_json or int(attrs.get("seed", -1)) != seed:
            raise ResumeError(f"cannot resume {self.url}: it was written from a different "
                              "project or seed")
        if int(attrs.get("format_version", 0)) != DATASET_FORMAT_VERSION:
            raise ResumeError(f"cannot resume {self.url}: dataset format "
                              f"{attrs.get('format_version')}")

    def target(self) -> ShardTarget:
        """What a worker needs to write shards of this store."""
        return ShardTarget(self.url, self.storage_options, self.shard_frames, self.n_total,
                           self.max_detections)

    @property
    def has_arrays(self) -> bool:
        """Whether the per-frame arrays exist (created with the first shard)."""
        return CHECKSUM_PATH in self.group

    def shards_of(self, frames: Sequence[int]) -> list[list[int]]:
        """``frames`` grouped by shard, in order."""
        out: dict[int, list[int]] = {}
        for k in frames:
            out.setdefault(k // self.shard_frames, []).append(k)
        return list(out.values())

    def missing(self, n_total: int) -> list[int]:
        """Frames of ``0..n_total-1`` in shards without a complete record (resizes arrays)."""
        self.n_total = n_total
        if not self.has_arrays:
            return list(range(n_total))
        for array in self._per_frame_arrays():
            if array.shape[0] != n_total:
                array.resize((n_total, *array.shape[1:]))
        done = np.any(np.asarray(self.group[CHECKSUM_PATH][:]) != 0, axis=1)
        todo: list[int] = []
        for start in range(0, n_total, self.shard_frames):
            stop = min(n_total, start + self.shard_frames)
            if done[start:stop].all():
                self._complete.update(range(start, stop))
            else:
                todo.extend(range(start, stop))
        self._commit()
        return todo

    def _per_frame_arrays(self) -> list[Any]:
        return [array for _, array in self.group.members(max_depth=None)
                if hasattr(array, "shape") and array.attrs.get("per_frame", False)]

    # ------------------------------------------------------------------ writing
    def write_static(self, items: dict[str, tuple[NDArray[Any], str]]) -> None:
        """Write run-constant arrays (axes, names) once, with their units."""
        for path, (array, unit) in items.items():
            arr = np.asarray(array)
            dtype: Any = str if arr.dtype.kind == "U" else arr.dtype
            out = self.group.create_array(
                path.strip("/"), shape=arr.shape, dtype=dtype, overwrite=True,
                dimension_names=_dims(path, arr.ndim, per_frame=False, kinds=self.kinds),
                attributes={"unit": unit, "units": unit},
                **({} if dtype is str else _codecs(arr.dtype)))
            out[...] = arr

    def write_frame(self, index: int, items: dict[str, tuple[NDArray[Any], str]],
                    tables: dict[str, NDArray[Any]]) -> None:
        """Add frame ``index`` to its shard's buffer; write the shard once it is complete."""
        shard = index // self.shard_frames
        start = shard * self.shard_frames
        if self._arrays is None and self.n_total:
            if not self.has_arrays:      # the run's first frame: create the arrays
                create_arrays(self.group, items, tables, n_total=self.n_total,
                              shard_frames=self.shard_frames,
                              max_detections=self.max_detections, kinds=self.kinds)
            self._arrays = ArrayCache(self.group)
        buffer = self._pending.get(shard)
        if buffer is None:
            end = min(self.n_total, start + self.shard_frames) if self.n_total else \
                start + self.shard_frames
            buffer = self._pending[shard] = ShardBuffer(start, end - start, self._arrays)
        buffer.add(index, items, tables)
        frames = range(start, min(self.n_total or index + 1, start + self.shard_frames))
        if all(k in buffer.added for k in frames):
            del self._pending[shard]
            if not self.has_arrays:
                assert buffer.first is not None
                create_arrays(self.group, *buffer.first, n_total=self.n_total,
                              shard_frames=self.shard_frames,
                              max_detections=self.max_detections, kinds=self.kinds)
            if self._arrays is None:
                self._arrays = ArrayCache(self.group)
            buffer.write(self._arrays, len(frames), max_detections=self.max_detections)
            self.mark_complete(frames)

    def mark_complete(self, frames: Sequence[int]) -> None:
        """Count ``frames`` as stored (their shard's record is written) and commit."""
        self._complete.update(frames)
        self._commit()

    def _commit(self) -> None:
        n = self.n_frames
        while n in self._complete:
            n += 1
        if n != int(self.group.attrs.get("n_frames", -1)):
            self.group.attrs["n_frames"] = n
            consolidate(self.group)
        self.n_frames = n

    def close(self, *, keep: bool = True) -> None:
        """Commit ``n_frames``; frames of an unfinished shard are dropped (recomputed later)."""
        self._pending.clear()

    def __enter__(self) -> ZarrWriter:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


def _check_replaceable(url: str, storage_options: dict[str, Any] | None) -> None:
    """Refuse to delete anything but a tofradar Zarr store (``--overwrite`` of a folder)."""
    try:
        attrs = open_group(url, mode="r", storage_options=storage_options).attrs
        ours = attrs.get("storage") == "zarr" and "project_json" in attrs
    except Exception:  # noqa: BLE001 — not a Zarr group at all
        ours = False
    if not ours:
        raise DatasetExistsError(f"{url} exists and is not a tofradar Zarr store; refusing to "
                                 "replace it (choose another --out)")


def _plain(value: Any) -> Any:
    """A JSON-able attribute value."""
    if isinstance(value, np.generic):
        return value.item()
    return value


def _max_detections(project_json: str) -> int:
    try:
        return int(json.loads(project_json).get("dsp", {}).get("max_detections", 256))
    except (ValueError, AttributeError):
        return 256


def _exists(url: str, storage_options: dict[str, Any] | None) -> bool:
    if "://" not in url or url.startswith("file://"):
        path = _store_url(url)
        if os.path.exists(path) and not os.path.isdir(path):
            raise DatasetExistsError(f"{url} exists and is not a folder; choose another --out")
        return os.path.isdir(path) and bool(os.listdir(path))
    try:
        open_group(url, mode="r", storage_options=storage_options)
    except (FileNotFoundError, KeyError, ValueError, OSError):
        return False
    except Exception as exc:  # noqa: BLE001 — zarr's own "no group here" errors
        if type(exc).__name__ in ("GroupNotFoundError", "NodeNotFoundError"):
            return False
        raise
    return True


def create_arrays(group: Any, items: dict[str, tuple[NDArray[Any], str]],
                  tables: dict[str, NDArray[Any]], *, n_total: int, shard_frames: int,
                  max_detections: int, kinds: dict[str, str] | None = None) -> None:
    """Create the per-frame arrays of a run from its first frame (the driver does this)."""
    def make(path: str, shape: tuple[int, ...], dtype: np.dtype[Any], unit: str,
             dims: tuple[str, ...]) -> None:
        size = int(np.prod(shape)) if shape else 1
        layout: dict[str, Any]
        if size <= SMALL_VALUES:
            layout = {"chunks": (shard_frames, *shape)}
        else:
            layout = {"chunks": (1, *shape), "shards": (shard_frames, *shape)}
        group.create_array(path.strip("/"), shape=(n_total, *shape), dtype=dtype,
                           fill_value=0, overwrite=True, dimension_names=dims,
                           attributes={"unit": unit, "units": unit, "per_frame": True},
                           **layout, **_codecs(dtype))

    for path, (array, unit) in items.items():
        arr = np.asarray(array)
        make(path, arr.shape, arr.dtype, unit,
             _dims(path, arr.ndim, per_frame=True, kinds=kinds))
    from simcore.dsp.detections import DETECTION_UNITS

    for path, rows in tables.items():
        fields: dict[str, Any] = dict(rows.dtype.fields or {})
        for name, (dtype, *_) in fields.items():
            make(f"{path}_by_frame/{name}", (max_detections,), dtype,
                 DETECTION_UNITS.get(name, ""), ("frame", "slot"))
        group[f"{path.strip('/')}_by_frame"].attrs.update(
            {"table_rows": True, "fields": list(fields)})
        make(f"{path}_count", (), np.dtype(np.int64), "1", ("frame",))
    make(CHECKSUM_PATH, (32,), np.dtype(np.uint8), "", ("frame", "sha256_byte"))


class ArrayCache:
    """Array handles of one open group, looked up once (each lookup reads ``zarr.json``)."""

    def __init__(self, group: Any):
        self.group = group
        self._arrays: dict[str, Any] = {}
        self._encoders: dict[str, ShardEncoder | None] = {}

    def __getitem__(self, path: str) -> Any:
        key = path.strip("/")
        array = self._arrays.get(key)
        if array is None:
            array = self._arrays[key] = self.group[key]
        return array

    def encoder(self, path: str) -> ShardEncoder | None:
        """The direct shard encoder of ``path`` (None: zarr writes it)."""
        key = path.strip("/")
        if key not in self._encoders:
            self._encoders[key] = ShardEncoder.of(self[key])
        return self._encoders[key]

    def block_encoder(self, path: str) -> BlockEncoder | None:
        """The direct encoder of a small array of one chunk per shard (None: zarr)."""
        key = "block:" + path.strip("/")
        if key not in self._encoders:
            self._encoders[key] = BlockEncoder.of(self[path])  # type: ignore[assignment]
        return self._encoders[key]  # type: ignore[return-value]


def _blosc_of(codecs: Any, dtype: np.dtype[Any]) -> Any:
    """The Blosc (numcodecs) of codecs [bytes (little endian; none for bytes), Blosc], or None."""
    from numcodecs import Blosc
    from zarr.codecs import BloscCodec, BytesCodec

    if len(codecs) != 2 or not isinstance(codecs[0], BytesCodec) or \
            not isinstance(codecs[1], BloscCodec):
        return None
    endian = codecs[0].endian
    if not (endian.value == "little" if endian is not None else dtype.itemsize == 1):
        return None
    b = codecs[1]
    shuffle = {"noshuffle": 0, "shuffle": 1, "bitshuffle": 2}[b.shuffle.value]
    return Blosc.from_config({"cname": b.cname.value, "clevel": b.clevel, "shuffle": shuffle,
                              "blocksize": b.blocksize, "typesize": b.typesize})


class BlockEncoder:
    """Encodes a small array's chunk of one shard of frames as zarr would, without zarr.

    For ``create_arrays``' small arrays (one chunk of ``shard_frames`` frames, codecs
    [bytes, Blosc]): the chunk is the shard's frames, padded with the fill value past the
    array's end, Blosc-compressed, stored under the chunk's key.
    """

    def __init__(self, array: Any, blosc: Any, rows: int) -> None:
        self.array, self.blosc, self.rows = array, blosc, rows
        self.dtype = np.dtype(array.dtype).newbyteorder("<")

    @classmethod
    def of(cls, array: Any) -> BlockEncoder | None:
        """The encoder of ``array``, or None when its codecs or chunks differ."""
        try:
            codecs = array.metadata.codecs
            chunk = tuple(array.metadata.chunk_grid.chunk_shape)
        except AttributeError:
            return None
        blosc = _blosc_of(codecs, np.dtype(array.dtype))
        if blosc is None or chunk[1:] != tuple(array.shape[1:]):
            return None
        return cls(array, blosc, chunk[0])

    def write(self, start: int, block: NDArray[Any]) -> Any:
        """The store write of rows ``start…`` (a coroutine), or None if not a whole chunk."""
        from zarr.core.buffer import default_buffer_prototype

        n = len(block)
        if start % self.rows or n != min(self.rows, self.array.shape[0] - start):
            return None
        full = np.full((self.rows, *block.shape[1:]), self.array.fill_value, self.dtype)
        full[:n] = block
        data = bytes(self.blosc.encode(full.reshape(-1).view(np.uint8)))
        coords = (start // self.rows, *([0] * (self.array.ndim - 1)))
        key = self.array.store_path / self.array.metadata.encode_chunk_key(coords)
        return key.set(default_buffer_prototype().buffer.from_bytes(data))


def _put(arrays: ArrayCache, path: str, start: int, block: NDArray[Any],
         writes: list[Any]) -> None:
    """Rows ``start…`` of ``path``: a direct store write queued in ``writes``, or zarr's."""
    encoder = arrays.block_encoder(path)
    write = None if encoder is None else encoder.write(start, block)
    if write is not None:
        writes.append(write)
        return
    array = arrays[path]
    array[start:start + len(block)] = (block if block.dtype == array.dtype
                                       else block.astype(array.dtype))


class ShardEncoder:
    """Encodes an array's frames and shards as zarr's sharding codec would, without zarr.

    For the arrays of one chunk per frame in shards of frames (``create_arrays``' large
    arrays: codecs ``sharding_indexed`` of [bytes (little endian), Blosc], index [bytes
    (little endian), CRC-32C] at the end). A frame's chunk is Blosc-compressed when the
    frame arrives (:meth:`chunk`; Blosc drops the GIL), and a shard is the frames' chunks
    one after another, then the index of (offset, length) pairs and its CRC-32C
    (:meth:`shard`): the bytes zarr itself writes (``tests/test_zarr_dataset.py``
    compares them), without zarr's per-chunk work, in one store write per array and shard.
    """

    def __init__(self, array: Any, blosc: Any, shard_frames: int) -> None:
        self.array = array
        self.blosc = blosc
        self.dtype = np.dtype(array.dtype).newbyteorder("<")
        self.shard_frames = shard_frames

    @classmethod
    def of(cls, array: Any) -> ShardEncoder | None:
        """The encoder of ``array``, or None when its codecs are not the ones above."""
        try:
            from zarr.codecs import BytesCodec, Crc32cCodec, ShardingCodec

            codecs = array.metadata.codecs
            outer = tuple(array.metadata.chunk_grid.chunk_shape)
        except (AttributeError, ImportError):
            return None
        if len(codecs) != 1 or not isinstance(codecs[0], ShardingCodec):
            return None
        sharding = codecs[0]
        blosc = _blosc_of(sharding.codecs, np.dtype(array.dtype))
        index = sharding.index_codecs
        if (tuple(sharding.chunk_shape) != (1, *outer[1:]) or blosc is None or len(index) != 2
                or not isinstance(index[0], BytesCodec) or index[0].endian is None
                or index[0].endian.value != "little"
                or not isinstance(index[1], Crc32cCodec)
                or sharding.index_location.value != "end"):
            return None
        return cls(array, blosc, outer[0])

    def frame(self, arr: NDArray[Any]) -> NDArray[Any]:
        """A frame as the array stores it (its dtype, little endian, C order)."""
        return np.ascontiguousarray(arr, dtype=self.dtype)

    def chunk(self, frame: NDArray[Any]) -> bytes:
        """One frame's chunk, compressed (``frame`` from :meth:`frame`)."""
        return bytes(self.blosc.encode(frame.reshape(-1).view(np.uint8)))

    def shard(self, chunks: Sequence[bytes]) -> bytes:
        """A shard of the frames' ``chunks`` (the first frames of the shard), with its index."""
        import google_crc32c

        index = np.full((self.shard_frames, *([1] * (self.array.ndim - 1)), 2), 2**64 - 1,
                        dtype="<u8")
        flat = index.reshape(self.shard_frames, 2)
        offset = 0
        for j, chunk in enumerate(chunks):
            flat[j] = (offset, len(chunk))
            offset += len(chunk)
        index_bytes = index.tobytes()
        crc = np.array([google_crc32c.value(index_bytes)], dtype="<u4").tobytes()
        return b"".join(chunks) + index_bytes + crc

    def key(self, start: int) -> Any:
        """The store path of the shard that begins at frame ``start``."""
        coords = (start // self.shard_frames, *([0] * (self.array.ndim - 1)))
        return self.array.store_path / self.array.metadata.encode_chunk_key(coords)


class ShardBuffer:
    """The frames of one shard, gathered as they come, then written in one go.

    :meth:`add` copies a frame's arrays into the shard's blocks (frames × frame shape)
    and takes its checksum at once, so this work is spread over the frames as they
    arrive (in the writer thread, beside the engine) instead of falling on the frame that
    completes the shard; :meth:`write` then leaves zarr only the encoding and storing of
    each array's block.

    Parameters
    ----------
    start : int
        The shard's first frame.
    capacity : int
        Frames the shard can hold (fewer in the last shard of a run).
    """

    def __init__(self, start: int, capacity: int, arrays: ArrayCache | None = None) -> None:
        self.start = start
        self.capacity = capacity
        self.arrays = arrays
        self.added: set[int] = set()
        self.first: tuple[Any, Any] | None = None     # a frame's items and tables
        self.blocks: dict[str, NDArray[Any]] = {}
        self.chunks: dict[str, list[bytes]] = {}       # arrays encoded here, frame by frame
        self.rows: dict[str, list[NDArray[Any]]] = {}
        self.digests = np.zeros((capacity, 32), dtype=np.uint8)

    def add(self, index: int, items: dict[str, tuple[NDArray[Any], str]],
            tables: dict[str, NDArray[Any]]) -> None:
        """Copy frame ``index`` into the blocks and record its checksum."""
        j = index - self.start
        if not 0 <= j < self.capacity:
            raise ValueError(f"frame {index} is not in the shard of frames {self.start}.."
                             f"{self.start + self.capacity - 1}")
        if self.first is None:
            self.first = (items, tables)
        stored: list[tuple[str, NDArray[Any]]] = []
        for path, rows in tables.items():
            self.rows.setdefault(path, [np.zeros(0, rows.dtype)] * self.capacity)[j] = rows
            stored.append((f"{path}_by_frame", rows))
            stored.append((f"{path}_count", np.asarray(len(rows), dtype=np.int64)))
        for path, (array, _) in items.items():
            arr = np.asarray(array)
            encoder = None if self.arrays is None else self.arrays.encoder(path)
            if encoder is not None:
                frame = encoder.frame(arr)
                chunks = self.chunks.setdefault(path, [b""] * self.capacity)
                if frame.shape != tuple(encoder.array.shape[1:]):
                    raise ValueError(f"{path}: frame shape {frame.shape} != "
                                     f"{tuple(encoder.array.shape[1:])}")
                chunks[j] = encoder.chunk(frame)
                stored.append((path, frame))
                continue
            block = self.blocks.get(path)
            if block is None:
                block = self.blocks[path] = np.zeros((self.capacity, *arr.shape), arr.dtype)
            if block.shape[1:] != arr.shape:
                raise ValueError(f"{path}: frame shape {arr.shape} != {block.shape[1:]}")
            block[j] = arr
            stored.append((path, block[j]))
        self.digests[j] = np.frombuffer(bytes.fromhex(frame_checksum(stored)), dtype=np.uint8)
        self.added.add(index)

    def write(self, arrays: ArrayCache, frames: int, *, max_detections: int) -> None:
        """Write the first ``frames`` frames, then their checksums (the shard's record)."""
        import zarr
        from zarr.core.buffer import default_buffer_prototype
        from zarr.core.sync import sync

        start = self.start
        writes = []
        for path, chunks in self.chunks.items():
            encoder = arrays.encoder(path)
            assert encoder is not None
            shard = default_buffer_prototype().buffer.from_bytes(encoder.shard(chunks[:frames]))
            writes.append(encoder.key(start).set(shard))
        # Every chunk is written, also one equal to the fill value: no read-back, no deletes.
        with zarr.config.set({"array.write_empty_chunks": True}):
            for path, block in self.blocks.items():
                _put(arrays, path, start, block[:frames], writes)
            for path, rows in self.rows.items():
                _write_table(arrays, path, rows[:frames], start, writes,
                             max_detections=max_detections)
            if writes:
                sync(_gather(writes))
            # The record last, once the data are stored.
            last: list[Any] = []
            _put(arrays, CHECKSUM_PATH, start, self.digests[:frames], last)
            if last:
                sync(_gather(last))


def write_shard_arrays(group: Any, batch: list[tuple[int, Any, Any]], *,
                       max_detections: int) -> None:
    """Write the frames of one shard (consecutive indices), then their checksums.

    ``group`` is the store's root group (or an :class:`ArrayCache` of it). The checksums
    are the shard's completion record: written last, so a shard cut short (a killed
    process) has none and is recomputed by ``--resume``.
    """
    arrays = group if isinstance(group, ArrayCache) else ArrayCache(group)
    buffer = ShardBuffer(batch[0][0], len(batch), arrays)
    for index, items, tables in batch:
        buffer.add(index, items, tables)
    buffer.write(arrays, len(batch), max_detections=max_detections)


async def _gather(writes: list[Any]) -> None:
    import asyncio

    await asyncio.gather(*writes)


def _write_table(arrays: ArrayCache, path: str, frames: list[NDArray[Any]], start: int,
                 writes: list[Any], *, max_detections: int) -> None:
    counts = np.array([len(rows) for rows in frames], dtype=np.int64)
    if counts.max(initial=0) > max_detections:
        raise ValueError(f"{path}: {int(counts.max())} rows in one frame, more than "
                         f"max_detections = {max_detections}")
    names = frames[0].dtype.names or ()
    for name in names:
        out = arrays[f"{path}_by_frame/{name}"]
        block = np.zeros((len(frames), max_detections), dtype=out.dtype)
        for j, rows in enumerate(frames):
            block[j, : len(rows)] = rows[name]
        _put(arrays, f"{path}_by_frame/{name}", start, block, writes)
    _put(arrays, f"{path}_count", start, counts, writes)


_GROUPS: dict[ShardTarget, Any] = {}


def write_shard(target: ShardTarget, batch: list[tuple[int, Any, Any]]) -> None:
    """Write one shard's frames into the store of ``target`` (in a worker process).

    The arrays exist (the driver created them); only this shard's objects are written.
    """
    key = ShardTarget(target.url, None, target.shard_frames, 0, 0)
    group = _GROUPS.get(key)
    if group is None:
        group = ArrayCache(open_group(target.url, mode="r+",
                                      storage_options=target.storage_options))
        _GROUPS.clear()
        _GROUPS[key] = group
    write_shard_arrays(group, batch, max_detections=target.max_detections)


__all__ = ["DEFAULT_SHARD_FRAMES", "BlockEncoder", "ShardBuffer", "ShardEncoder", "ShardTarget",
           "ZarrWriter", "create_arrays", "open_group", "write_shard", "write_shard_arrays",
           "ArrayCache"]
