"""Dataset generation: frames as independent jobs, written in frame order by one writer.

Frames run in-process, on local processes or on a Dask cluster.

The unit of work is :func:`compute_frame` on a :class:`RunSpec` and a frame index. A
frame's random numbers come from ``(seed, index)`` alone, so a frame is bit-identical
whichever process computes it and in whatever order.
"""

from __future__ import annotations

import asyncio
import contextlib
import functools
import hashlib
import json
import multiprocessing
import os
import signal
from collections.abc import Callable, Generator, Iterator, Mapping, Sequence
from concurrent.futures import Future, ProcessPoolExecutor
from concurrent.futures.process import BrokenProcessPool
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from simcore.pipeline import Frame, Simulator
from simcore.preflight import RunError
from simcore.scene.project_io import project_from_dict
from simcore.sensors.base import H5Items
from simcore.sensors.schema import must_be_finite, nan_allowed

if TYPE_CHECKING:
    from simcore.scene.model import Project


@dataclass(frozen=True)
class RunSpec:
    """Everything a worker needs to compute any frame of a run (picklable, small)."""

    project_json: str
    base_dir: str
    seed: int

    @property
    def key(self) -> str:
        """Identity of the run (workers cache one simulator per key)."""
        text = f"{self.seed}\n{self.base_dir}\n{self.project_json}"
        return hashlib.sha256(text.encode()).hexdigest()


@dataclass
class FrameResult:
    """One computed frame, ready for the writer."""

    index: int
    items: H5Items
    tables: dict[str, NDArray[Any]] = field(default_factory=dict)
    timings_ms: dict[str, float] = field(default_factory=dict)


@dataclass(frozen=True)
class ArraySlot:
    """One per-frame array of a run over scenes, as every frame of the dataset holds it.

    ``entity`` names the dimension of the first axis when it counts things (``object``,
    ``person``, ``segment``: :data:`simcore.io.reader.ENTITY_GROUPS`); ``shape[0]`` is
    then the largest scene's count, and a scene with fewer is padded.
    """

    path: str
    shape: tuple[int, ...]
    dtype: str
    unit: str
    entity: str | None = None


@dataclass(frozen=True)
class ScenesSpec:
    """A run over several scenes: ``frames_per_scene`` frames of each, one after another.

    Dataset frame ``k`` is frame ``k % frames_per_scene`` of scene
    ``k // frames_per_scene``; every scene keeps its own seed, so a frame equals the same
    frame of that scene run alone, bit for bit. ``static_sha256`` holds (path, digest) of
    the run-constant arrays every scene shares (sensor axes; not the names and ids of
    objects and people, which are per scene); ``layout`` the per-frame arrays of every
    frame, padded to the largest scene's object, person and segment counts
    (:func:`pad_items`).
    """

    scenes: tuple[RunSpec, ...]
    frames_per_scene: int
    static_sha256: tuple[tuple[str, str], ...] = ()
    layout: tuple[ArraySlot, ...] = ()

    @property
    def key(self) -> str:
        """Identity of the run."""
        text = "\n".join(s.key for s in self.scenes) + f"\n{self.frames_per_scene}"
        return hashlib.sha256(text.encode()).hexdigest()

    def locate(self, index: int) -> tuple[int, int]:
        """(scene, frame of that scene) of dataset frame ``index``."""
        return divmod(index, self.frames_per_scene)


AnySpec = RunSpec | ScenesSpec
_SIMULATORS: dict[str, Simulator] = {}


def _simulator(spec: RunSpec) -> Simulator:
    sim = _SIMULATORS.get(spec.key)
    if sim is None:
        close_simulators()
        base = Path(spec.base_dir)
        project = project_from_dict(json.loads(spec.project_json), base_dir=base)
        sim = Simulator(project, base_dir=base, seed=spec.seed)
        _SIMULATORS[spec.key] = sim
    return sim


def close_simulators() -> None:
    """Release this process's cached simulators (offscreen windows) now, not at exit.

    The speckle phases kept per (seed, object) go too: a run over scenes moves on to
    another seed, so its memory stays flat however many scenes it runs.
    """
    from simcore.sensors.radar.surfaces import release_phase_caches

    for sim in _SIMULATORS.values():
        sim.close()
    _SIMULATORS.clear()
    release_phase_caches()


class NonFiniteOutputError(RunError):
    """A frame produced NaN or infinite values where the dataset promises numbers."""


#: Common datasets whose every value must be finite (the sensors' raw data say so in their
#: schemas: :attr:`simcore.sensors.schema.Output.finite`).
STRICT_PREFIXES = ("/time", "/poses/")


def check_finite(index: int, items: H5Items, kinds: Mapping[str, str]) -> None:
    """Refuse a frame whose outputs are not numbers.

    Raw data and poses must be finite (NaN only where the sensor kind's schema allows it);
    a DSP product (dB maps) may hold −∞ dB and NaN where allowed, but not +∞ and not only
    non-finite values. ``kinds``: the kind of each sensor, by name.
    """
    for path, (array, unit) in items.items():
        arr = np.asarray(array)
        if arr.dtype.kind not in "fc" or arr.size == 0:
            continue
        values = np.asarray(arr.real if arr.dtype.kind == "c" else arr, dtype=np.float64)
        if arr.dtype.kind == "c":
            values = np.concatenate([values.ravel(), arr.imag.astype(np.float64).ravel()])
        finite = np.isfinite(values)
        if finite.all():
            continue
        nan_ok = nan_allowed(path, kinds)
        if path.startswith(STRICT_PREFIXES) or must_be_finite(path, kinds):
            bad = ~finite & ~np.isnan(values) if nan_ok else ~finite
        elif not finite.any() and not nan_ok:
            bad = ~finite
        else:
            bad = np.isposinf(values) | (np.isnan(values) if not nan_ok and unit != "dB"
                                         else np.zeros_like(finite))
        if bad.any():
            raise NonFiniteOutputError(
                f"frame {index}: {path} has {int(bad.sum())} of {values.size} values NaN or "
                "infinite; the configuration is outside the range the model computes "
                "reliably (see 'tofradar validate')")


def compute_frame(spec: AnySpec, index: int) -> FrameResult:
    """Compute frame ``index`` of a run (in whichever process calls it)."""
    return next(results(spec, [index]))


def results(spec: AnySpec, indices: Sequence[int]) -> Iterator[FrameResult]:
    """Frames ``indices`` of a run, in order, consecutive frames of a scene overlapped.

    In a run over scenes (:class:`ScenesSpec`), each frame gets its dataset index, the
    per-frame ``/scene_index`` and detection rows numbered by dataset frame; a scene whose
    run-constant arrays differ from the first scene's stops the run (:class:`RunError`).
    """
    if isinstance(spec, RunSpec):
        for frame in _simulator(spec).frames(indices):
            yield _result(frame)
        return
    groups: list[tuple[int, list[int]]] = []
    for k in indices:
        scene, _ = spec.locate(k)
        if not groups or groups[-1][0] != scene:
            groups.append((scene, []))
        groups[-1][1].append(k)
    for scene, ks in groups:
        sub = spec.scenes[scene]
        first = sub.key not in _SIMULATORS
        sim = _simulator(sub)
        if first and spec.static_sha256:
            check_shared_statics(scene, sim.static_items(), spec.static_sha256)
        for k, frame in zip(ks, sim.frames([spec.locate(k)[1] for k in ks]), strict=True):
            result = _result(frame)
            result.index = k
            if spec.layout:
                result.items = pad_items(result.items, spec.layout, scene=scene)
            result.items["/scene_index"] = (np.asarray(scene, dtype=np.int32), "1")
            for rows in result.tables.values():
                if rows.dtype.names is not None and "frame" in rows.dtype.names:
                    rows["frame"] = k
            yield result


def static_digest(items: H5Items) -> str:
    """SHA-256 of run-constant arrays (names, shapes, dtypes, values, units)."""
    digest = hashlib.sha256()
    for path in sorted(items):
        array, unit = items[path]
        arr = np.ascontiguousarray(np.asarray(array))
        digest.update(f"{path}|{unit}|{arr.dtype.str}|{arr.shape}|".encode())
        digest.update(arr.tobytes())
    return digest.hexdigest()


def shared_statics(items: H5Items) -> H5Items:
    """The run-constant arrays a run over scenes shares (sensor axes).

    All but those along an entity axis: the names and ids of objects, people and segments
    are per scene.
    """
    from simcore.io.layout import entity_of

    return {path: value for path, value in items.items() if entity_of(path) is None}


def static_digests(items: H5Items) -> tuple[tuple[str, str], ...]:
    """(path, SHA-256) of each shared run-constant array (:func:`shared_statics`)."""
    return tuple((path, static_digest({path: value}))
                 for path, value in sorted(shared_statics(items).items()))


def check_shared_statics(scene: int, items: H5Items,
                         reference: tuple[tuple[str, str], ...]) -> None:
    """Refuse a scene whose shared run-constant arrays (sensor axes) differ from the run's.

    A scene may lack some (a scene without people has no ``/people/body_part_names``);
    every one it has must equal the reference scene's.
    """
    known = dict(reference)
    for path, digest in static_digests(items):
        if known.get(path) != digest:
            raise RunError(f"scene {scene} has other sensor axes than the other scenes "
                           f"({path} differs: its sensor configuration differs); one dataset "
                           "holds scenes of one layout: vary values and object counts, not "
                           "the sensors")


def _fill_value(dtype: np.dtype[Any]) -> Any:
    """What a padded slot holds: NaN (floats), −1 (signed integers), 0, False or ""."""
    if dtype.kind in "fc":
        return np.nan
    if dtype.kind == "i":
        return -1
    if dtype.kind in "US":
        return ""
    return 0


def pad_items(items: H5Items, layout: Sequence[ArraySlot], *, scene: int) -> H5Items:
    """A frame's arrays in the run's layout: entity axes padded, absent arrays filled.

    Arrays along an entity axis (objects, people, segments) are padded to the layout's
    count with :func:`_fill_value`; an array the scene does not have (the ``/people``
    truth of a scene without people) is all fill. Each entity group gets its per-frame
    ``<group>/count`` (int32) and ``<group>/valid`` (bool, True for the first ``count``
    slots). An array outside the layout, or of another shape, stops the run.
    """
    from simcore.io.layout import ENTITY_GROUPS, entity_of

    known = {slot.path for slot in layout}
    for path in items:
        if path not in known:
            raise RunError(f"scene {scene} writes {path}, which the scene the run's layout "
                           "was taken from does not; one dataset holds scenes of one layout")
    counts: dict[str, int] = {}
    for path, (array, _) in items.items():
        entity = entity_of(path)
        if entity is not None:
            n = int(np.shape(array)[0])
            if counts.setdefault(entity, n) != n:
                raise RunError(f"scene {scene}: {path} has {n} {entity}s, other arrays "
                               f"{counts[entity]}")
    out: H5Items = {}
    sizes = {slot.entity: slot.shape[0] for slot in layout if slot.entity is not None}
    for slot in layout:
        dtype = np.dtype(slot.dtype)
        found = items.get(slot.path)
        if found is None:
            out[slot.path] = (np.full(slot.shape, _fill_value(dtype), dtype=dtype), slot.unit)
            continue
        arr = np.asarray(found[0])
        if slot.entity is not None:
            n = arr.shape[0] if arr.ndim else 0
            if n < slot.shape[0] and arr.shape[1:] == slot.shape[1:]:
                padded = np.full(slot.shape, _fill_value(arr.dtype), dtype=arr.dtype)
                padded[:n] = arr
                arr = padded
        if arr.shape != slot.shape or arr.dtype != dtype:
            raise RunError(f"scene {scene}: {slot.path} has shape {arr.shape} "
                           f"({arr.dtype}), the run's layout {slot.shape} ({dtype}); one "
                           "dataset holds scenes of one layout (vary values and counts, "
                           "not the sensors)")
        out[slot.path] = (arr, found[1])
    for entity, size in sizes.items():
        group = ENTITY_GROUPS[entity]
        n = counts.get(entity, 0)
        out[f"{group}/count"] = (np.asarray(n, dtype=np.int32), "1")
        out[f"{group}/valid"] = (np.arange(size) < n, "1")
    return out


def _result(frame: Frame) -> FrameResult:
    items = frame.hdf5_items()
    check_finite(frame.index, items, frame.kinds or {n: n for n in frame.outputs})
    return FrameResult(frame.index, items, frame.table_rows(), frame.timings_ms)


def static_items(spec: AnySpec) -> H5Items:
    """Run-constant datasets (object names and ids, axes).

    Of a run over scenes: the first scene's, with each scene's name and seed.
    """
    if isinstance(spec, RunSpec):
        return _simulator(spec).static_items()
    reference = _reference_scene([_entity_statics(s) for s in spec.scenes])
    items = shared_statics(_simulator(spec.scenes[reference]).static_items())
    items.update(scene_entity_statics(spec.scenes))
    names = [json.loads(s.project_json).get("name", "") for s in spec.scenes]
    items["/scenes/names"] = (np.array(names, dtype=str), "")
    items["/scenes/seeds"] = (np.array([s.seed for s in spec.scenes], dtype=np.int64), "1")
    return items


def _entity_statics(spec: RunSpec) -> H5Items:
    """A scene's run-constant arrays along an entity axis, without building its simulator.

    The names and ids of its objects, people and segments, as its simulator's
    ``static_items`` has them.
    """
    from simcore.io.layout import entity_of
    from simcore.scene.people.expand import expand_people, people_of
    from simcore.scene.people.truth import people_static_items

    base = Path(spec.base_dir)
    project = project_from_dict(json.loads(spec.project_json), base_dir=base)
    items: H5Items = {
        "/objects/names": (np.array([o.name for o in project.objects], dtype=str), ""),
        "/objects/ids": (np.array([o.id for o in project.objects], dtype=np.int32), "1"),
    }
    people = people_of(expand_people(project, base_dir=base))
    if people is not None:
        items.update(people_static_items(people))
    return {path: value for path, value in items.items() if entity_of(path) is not None}


def _entity_counts(statics: H5Items) -> dict[str, int]:
    """Objects, people and segments of a scene (from its :func:`_entity_statics`)."""
    from simcore.io.layout import ENTITY_GROUPS

    return {entity: len(statics[f"{group}/names"][0]) if f"{group}/names" in statics else 0
            for entity, group in ENTITY_GROUPS.items()}


def _reference_scene(statics: Sequence[H5Items]) -> int:
    """The first scene with the most kinds of entity (objects, people, segments).

    The run's layout and shared run-constant arrays are taken from it.
    """
    kinds = [sum(n > 0 for n in _entity_counts(s).values()) for s in statics]
    return kinds.index(max(kinds))


def scene_entity_statics(scenes: Sequence[RunSpec]) -> H5Items:
    """Names and ids of every scene's objects, people and segments, padded per scene.

    ``/scenes/objects/names`` (S, largest object count) and so on for every run-constant
    array along an entity axis, padded with "" or −1, and ``/scenes/<group>/count`` (S,).
    """
    from simcore.io.layout import ENTITY_GROUPS, entity_of

    statics = [_entity_statics(s) for s in scenes]
    counts = [_entity_counts(s) for s in statics]
    out: H5Items = {}
    paths = list(dict.fromkeys(path for s in statics for path in s))
    for path in paths:
        entity = entity_of(path)
        assert entity is not None
        size = max(c[entity] for c in counts)
        first = next(s[path] for s in statics if path in s)
        arr0, unit = np.asarray(first[0]), first[1]
        dtype: Any = object if arr0.dtype.kind == "U" else arr0.dtype
        table = np.full((len(scenes), size, *arr0.shape[1:]), _fill_value(arr0.dtype),
                        dtype=dtype)
        for i, s in enumerate(statics):
            if path in s:
                values = np.asarray(s[path][0])
                table[i, : len(values)] = values
        out[f"/scenes{path}"] = (table.astype(str) if dtype is object else table, unit)
    for entity, group in ENTITY_GROUPS.items():
        if any(c[entity] for c in counts) or entity == "object":
            out[f"/scenes{group}/count"] = (
                np.array([c[entity] for c in counts], dtype=np.int32), "1")
    return out


def scenes_layout(scenes: Sequence[RunSpec], statics: Sequence[H5Items], reference: int
                  ) -> tuple[ArraySlot, ...]:
    """The per-frame arrays of a run over scenes, from frame 0 of the reference scene.

    Arrays along an entity axis get the largest scene's count.
    """
    from simcore.io.layout import entity_of

    counts = [_entity_counts(s) for s in statics]
    frame = _result(next(_simulator(scenes[reference]).frames([0])))
    layout = []
    for path, (array, unit) in frame.items.items():
        arr = np.asarray(array)
        entity = entity_of(path)
        shape = arr.shape
        if entity is not None and arr.ndim:
            shape = (max(c[entity] for c in counts), *arr.shape[1:])
        layout.append(ArraySlot(path, tuple(int(n) for n in shape), arr.dtype.str, unit,
                                entity if arr.ndim else None))
    return tuple(layout)


def _ignore_sigint(driver: int | None = None) -> None:
    """Worker processes leave Ctrl+C to the writer, which stops the run between frames.

    On Linux they also get SIGKILL when the driver (process ``driver``) dies, and exit at
    once if it died before they started: a killed driver leaves no worker that goes on
    writing a shard beside the run that resumes it.
    """
    from simcore.io.hdf5_writer import _die_with_parent

    signal.signal(signal.SIGINT, signal.SIG_IGN)
    if driver is not None:
        _die_with_parent(driver)


def _in_order(futures: Iterator[tuple[int, Callable[[], FrameResult]]], window: int
              ) -> Iterator[FrameResult]:
    """Resolve (index, result getter) pairs with at most ``window`` outstanding, in order."""
    pending: list[Callable[[], FrameResult]] = []
    for _, get in futures:
        pending.append(get)
        if len(pending) >= window:
            yield pending.pop(0)()
    while pending:
        yield pending.pop(0)()


#: Seconds a Dask scheduler has to answer the connection handshake, and one frame to finish.
CONNECT_TIMEOUT_S = 10.0
TASK_TIMEOUT_S = 600.0
#: Address schemes of Dask's communication layer.
DASK_SCHEMES = ("tcp", "tls", "inproc", "ucx", "ws", "wss")


class SchedulerError(RunError):
    """A Dask scheduler cannot be used: bad address, no answer, a different service."""


def check_scheduler_address(address: str) -> None:
    """Refuse a scheduler address that is neither ``local`` nor ``scheme://host:port``."""
    if address == "local":
        return
    scheme, sep, rest = address.partition("://")
    if not sep:
        scheme, rest = "tcp", address
    if scheme not in DASK_SCHEMES:
        raise SchedulerError(f"--scheduler {address!r}: unknown scheme {scheme!r}; use "
                             f"'local' or one of {', '.join(s + '://' for s in DASK_SCHEMES)}")
    host, colon, port = rest.rpartition(":")
    if scheme in ("tcp", "tls", "ws", "wss") and (not colon or not host or not port.isdigit()
                                                  or not 0 < int(port) < 65536):
        raise SchedulerError(f"--scheduler {address!r}: expected {scheme}://HOST:PORT with a "
                             "port in 1..65535")


def probe_scheduler(address: str, *, timeout_s: float = CONNECT_TIMEOUT_S) -> None:
    """Check that a Dask scheduler answers at a ``tcp://`` address, within ``timeout_s``.

    A Dask server sends its handshake (a small frame count, then msgpack) as soon as a
    client connects; anything else (an HTTP server, a silent listener) is refused with a
    message instead of Dask's own "Unable to allocate 3.07 EiB" or a long hang.
    """
    import socket
    import struct

    scheme, sep, rest = address.partition("://")
    if sep and scheme != "tcp":
        return          # TLS and others: Dask's own connect timeout applies
    host, _, port = (rest if sep else address).rpartition(":")
    host = host.strip("[]")
    try:
        sock = socket.create_connection((host, int(port)), timeout=timeout_s)
    except (OSError, ValueError) as exc:
        raise SchedulerError(f"cannot connect to the Dask scheduler at {address}: "
                             f"{getattr(exc, 'strerror', None) or exc}") from None
    with sock:
        sock.settimeout(timeout_s)
        try:
            head = sock.recv(8, socket.MSG_WAITALL)
        except TimeoutError:
            raise SchedulerError(f"{address} accepted the connection but sent no Dask "
                                 f"handshake within {timeout_s:g} s; is a Dask scheduler "
                                 "listening on that port?") from None
        except OSError as exc:
            raise SchedulerError(f"{address}: {exc.strerror or exc}") from None
    if len(head) < 8 or struct.unpack("<Q", head)[0] > 64:
        shown = head[:8].decode("ascii", errors="replace")
        raise SchedulerError(f"{address} does not speak the Dask protocol (it sent "
                             f"{shown!r}); a different service listens on that port")


def iter_frames(spec: AnySpec, indices: Sequence[int], *, workers: int = 1,
                scheduler: str | None = None, task_timeout_s: float = TASK_TIMEOUT_S,
                connect_timeout_s: float = CONNECT_TIMEOUT_S) -> Iterator[FrameResult]:
    """Yield the frames ``indices`` in order, computed by ``workers`` processes or Dask.

    Parameters
    ----------
    spec : RunSpec
        The run.
    indices : sequence of int
        Frames to compute, in the order they are yielded.
    workers : int
        Local worker processes (1 = in this process).
    scheduler : str, optional
        ``"local"`` for an embedded Dask ``LocalCluster`` with ``workers`` processes, or the
        address of a running Dask scheduler (``tcp://host:8786``).
    task_timeout_s : float
        Longest wait for one frame from Dask (:class:`SchedulerError` beyond).
    connect_timeout_s : float
        Longest wait for a Dask scheduler's handshake.
    """
    window = max(2, 2 * workers)   # bounded look-ahead keeps memory flat on long runs
    if scheduler is not None:
        yield from _iter_dask(spec, indices, workers=workers, scheduler=scheduler,
                              window=window, task_timeout_s=task_timeout_s,
                              connect_timeout_s=connect_timeout_s)
    elif workers <= 1:
        # In this process, consecutive frames overlapped (Simulator.frames).
        yield from results(spec, indices)
    else:
        ctx = multiprocessing.get_context("spawn")
        with ProcessPoolExecutor(max_workers=workers, mp_context=ctx,
                                 initializer=_ignore_sigint,
                                 initargs=(os.getpid(),)) as pool:
            def submit() -> Iterator[tuple[int, Callable[[], FrameResult]]]:
                for i in indices:
                    fut: Future[FrameResult] = pool.submit(compute_frame, spec, i)
                    yield i, functools.partial(_pool_result, pool, fut)
            try:
                yield from _in_order(submit(), window)
            except BrokenProcessPool:
                pool.shutdown(wait=False, cancel_futures=True)
                raise RunError("a worker process died (killed, out of memory or a crash in "
                               "native code); the file keeps every complete frame, continue "
                               "with --resume") from None
            except BaseException:
                pool.shutdown(wait=False, cancel_futures=True)
                raise


def _pool_result(pool: ProcessPoolExecutor, fut: Future[FrameResult]) -> FrameResult:
    """``fut.result()``, raising :class:`BrokenProcessPool` when a worker process died.

    The pool notices a dead worker by itself, except when the worker died while sending a
    result: the pool's reader thread then waits for the rest of that message for ever
    (CPython 3.11). Every second without a result, the workers are checked; if one died,
    the others are killed and the parent's end of the result pipe is closed, so that the
    stuck read ends (EOF) and the pool breaks as usual.
    """
    while True:
        try:
            return fut.result(timeout=1.0)
        except TimeoutError:
            processes = list(getattr(pool, "_processes", {}).values())
            if not any(p.exitcode not in (None, 0) for p in processes):
                continue
        for p in processes:
            p.kill()
        writer = getattr(getattr(pool, "_result_queue", None), "_writer", None)
        if writer is not None:
            writer.close()
        try:
            return fut.result(timeout=30.0)
        except TimeoutError:
            raise BrokenProcessPool("a worker process died") from None


def _iter_dask(spec: AnySpec, indices: Sequence[int], *, workers: int, scheduler: str,
               window: int, task_timeout_s: float, connect_timeout_s: float
               ) -> Iterator[FrameResult]:
    with _dask_client(scheduler, workers=workers, connect_timeout_s=connect_timeout_s
                      ) as client:
        spec_future = client.scatter(spec, broadcast=True)

        def submit() -> Iterator[tuple[int, Callable[[], FrameResult]]]:
            for i in indices:
                fut = client.submit(compute_frame, spec_future, i, pure=False)

                def get(fut: Any = fut, i: int = i) -> FrameResult:
                    try:
                        result: FrameResult = fut.result(timeout=task_timeout_s)
                    except (TimeoutError, asyncio.TimeoutError):
                        raise SchedulerError(f"frame {i} did not finish within "
                                             f"{task_timeout_s:g} s on {scheduler}") from None
                    return result
                yield i, get
        yield from _in_order(submit(), window)


@contextlib.contextmanager
def _dask_client(scheduler: str, *, workers: int, connect_timeout_s: float
                 ) -> Iterator[Any]:
    """A Dask client of ``scheduler``, closed with its cluster on exit.

    ``"local"``: an embedded cluster of ``workers`` processes. One clear error when it
    cannot connect.
    """
    check_scheduler_address(scheduler)
    if scheduler != "local":
        probe_scheduler(scheduler, timeout_s=connect_timeout_s)
    from dask.distributed import Client, LocalCluster

    cluster = None
    try:
        if scheduler == "local":
            cluster = LocalCluster(n_workers=max(1, workers), threads_per_worker=1,
                                   processes=True, dashboard_address=None)
            client = Client(cluster, timeout=connect_timeout_s)
        else:
            client = Client(scheduler, timeout=connect_timeout_s)
    except (OSError, TimeoutError) as exc:
        if cluster is not None:
            cluster.close()
        raise SchedulerError(f"cannot connect to the Dask scheduler at {scheduler} within "
                             f"{connect_timeout_s:g} s: {exc}") from None
    try:
        yield client
    finally:
        client.close()
        if cluster is not None:
            cluster.close()


#: Most frames of one run.
MAX_FRAMES = 10_000_000


def frame_count(n_frames: int | None, duration_s: float | None, frame_rate_hz: float,
                default: int) -> int:
    """Frames to produce from ``--frames`` or ``--duration`` (else the project timeline).

    Raises ValueError (naming the option and the limit) beyond :data:`MAX_FRAMES`.
    """
    if n_frames is not None:
        count, what = n_frames, f"--frames {n_frames}"
    elif duration_s is not None:
        frames = duration_s * frame_rate_hz
        if not frames < MAX_FRAMES + 0.5:
            raise ValueError(f"--duration {duration_s:g} s at {frame_rate_hz:g} Hz gives "
                             f"{frames:.3g} frames; allowed at most {MAX_FRAMES}")
        count, what = max(1, int(round(frames))), f"--duration {duration_s:g}"
    else:
        count, what = default, "timeline.duration_s × frame_rate_hz"
    if count > MAX_FRAMES:
        raise ValueError(f"{what}: {count:.3g} frames; allowed at most {MAX_FRAMES}")
    return count


@dataclass
class RunReport:
    """What a dataset run did."""

    path: Path | str
    first_frame: int
    frames_done: int
    frames_total: int
    interrupted: bool = False


def run_dataset(project_json: str, base_dir: Path, out: Path | str, *, n_frames: int, seed: int,
                overwrite: bool = False, resume: bool = False, workers: int = 1,
                scheduler: str | None = None, extra_meta: dict[str, Any] | None = None,
                on_frame: Callable[[int, int, FrameResult], bool] | None = None,
                task_timeout_s: float = TASK_TIMEOUT_S,
                connect_timeout_s: float = CONNECT_TIMEOUT_S,
                storage_options: dict[str, Any] | None = None,
                shard_frames: int | None = None) -> RunReport:
    """Write ``n_frames`` frames of a project into ``out`` (HDF5, Zarr or MCAP).

    ``out`` is an HDF5 file, a Zarr store (``*.zarr`` or a URL such as ``s3://bucket/run``,
    with fsspec ``storage_options``) or an MCAP recording (``*.mcap``); see
    :func:`simcore.io.writer.open_writer`. Frames are written in a background thread while
    the next ones are computed.


    ``on_frame(done, total, result)`` is called after each frame is written; returning
    False stops the run cleanly (as does Ctrl+C), leaving a valid file that
    ``resume=True`` continues. A run that fails before its first frame leaves no file; a
    failing ``overwrite`` leaves the old file untouched (see :class:`DatasetWriter`).
    """
    from simcore.preflight import check
    from simcore.scene.project_io import ProjectError

    # The safety subset of the preflight (callers such as the CLI and the GUI run the whole
    # of it, with the memory budget and the mesh path policy, before they get here).
    problems = check(project_from_dict(json.loads(project_json), base_dir=Path(base_dir)),
                     base_dir=Path(base_dir), memory_budget_bytes=2**63, n_frames=n_frames,
                     seed=seed, allow_outside_paths=True, parse_meshes=False)
    if problems:
        raise ProjectError(f"project for {out}", problems)
    spec = RunSpec(project_json, str(base_dir), seed)
    return _run(spec, out, project_json=project_json, seed=seed, n_frames=n_frames,
                overwrite=overwrite, resume=resume, workers=workers, scheduler=scheduler,
                extra_meta=extra_meta, on_frame=on_frame, task_timeout_s=task_timeout_s,
                connect_timeout_s=connect_timeout_s, storage_options=storage_options,
                shard_frames=shard_frames)


def run_scenes(scenes: Sequence[tuple[str, Path]], out: Path | str, *, frames_per_scene: int,
               overwrite: bool = False, resume: bool = False, workers: int = 1,
               scheduler: str | None = None, extra_meta: dict[str, Any] | None = None,
               on_frame: Callable[[int, int, FrameResult], bool] | None = None,
               task_timeout_s: float = TASK_TIMEOUT_S,
               connect_timeout_s: float = CONNECT_TIMEOUT_S,
               storage_options: dict[str, Any] | None = None,
               shard_frames: int | None = None) -> RunReport:
    """Write ``frames_per_scene`` frames of each scene, one after another, into one dataset.

    ``scenes`` are ``(project JSON, base folder)`` pairs (a folder of generated projects,
    ``tofradar run DIR``); each scene runs with its own project seed. Dataset frame ``k``
    is frame ``k % frames_per_scene`` of scene ``k // frames_per_scene`` and records it in
    the per-frame ``/scene_index``; ``/scenes/names``, ``/scenes/seeds`` and
    ``/scenes/projects`` describe the scenes, and the root ``project_json`` is scene 0's.
    Frames are spread over the workers like a one-scene run's (whole shards per worker
    in a Zarr store), and ``resume`` continues the same folder of scenes.

    Scenes may hold different objects and people: arrays along the object, person and
    segment axes are padded to the largest scene's count (NaN, −1 or False), with
    per-frame ``/objects/count`` and ``/objects/valid`` (and ``/people/…``,
    ``/people/segments/…``), and each scene's names and ids in ``/scenes/objects/names``
    and so on (:func:`pad_items`, :func:`scene_entity_statics`); the layout comes from
    frame 0 of the first scene with the most kinds of entity, computed here. Every scene
    must share the sensors' axes and ``dsp.max_detections``; else :class:`RunError`
    before the first frame, or when a worker first meets the scene.
    """
    from simcore.preflight import check
    from simcore.scene.project_io import ProjectError

    if not scenes:
        raise RunError("no scenes to run")
    if is_mcap(out):
        raise RunError(f"--out {out}: a run over scenes writes HDF5 or Zarr, not MCAP")
    specs = []
    sensors: list[str] = []
    limit = None
    for i, (project_json, base_dir) in enumerate(scenes):
        project = project_from_dict(json.loads(project_json), base_dir=Path(base_dir))
        problems = check(project, base_dir=Path(base_dir), memory_budget_bytes=2**63,
                         n_frames=frames_per_scene, seed=project.seed,
                         allow_outside_paths=True, parse_meshes=False)
        if problems:
            raise ProjectError(f"scene {i} for {out}", problems)
        if limit is None:
            limit = project.dsp.max_detections
        elif project.dsp.max_detections != limit:
            raise RunError(f"scene {i}: dsp.max_detections {project.dsp.max_detections} "
                           f"differs from scene 0's {limit}; one dataset holds scenes of "
                           "one layout")
        specs.append(RunSpec(project_json, str(base_dir), project.seed))
        sensors.append(_sensor_key(project))
    statics = [_entity_statics(s) for s in specs]
    reference = _reference_scene(statics)
    try:
        digests = static_digests(_simulator(specs[reference]).static_items())
        # Every scene of another sensor configuration than the reference's is checked
        # here, before the first frame (one simulator per distinct configuration).
        seen = {sensors[reference]}
        for i, key in enumerate(sensors):
            if key not in seen:
                check_shared_statics(i, _simulator(specs[i]).static_items(), digests)
                seen.add(key)
        layout = scenes_layout(specs, statics, reference)
    finally:
        close_simulators()
    spec = ScenesSpec(tuple(specs), frames_per_scene, digests, layout)
    meta = dict(extra_meta or {})
    meta["scenes"] = len(specs)
    meta["frames_per_scene"] = frames_per_scene
    meta["scenes_sha256"] = spec.key
    return _run(spec, out, project_json=specs[0].project_json, seed=specs[0].seed,
                n_frames=frames_per_scene * len(specs), overwrite=overwrite, resume=resume,
                workers=workers, scheduler=scheduler, extra_meta=meta, on_frame=on_frame,
                task_timeout_s=task_timeout_s, connect_timeout_s=connect_timeout_s,
                storage_options=storage_options, shard_frames=shard_frames)


def _sensor_key(project: Project) -> str:
    """The sensors' configurations and the DSP of a scene: equal keys give equal axes."""
    return json.dumps({"sensors": {name: cfg.model_dump(mode="json")
                                   for name, cfg in project.sensor_configs().items()},
                       "dsp": project.dsp.model_dump(mode="json")}, sort_keys=True)


def is_mcap(out: Path | str) -> bool:
    """Whether ``out`` names an MCAP recording."""
    return str(out).lower().endswith(".mcap")


def _run(spec: AnySpec, out: Path | str, *, project_json: str, seed: int, n_frames: int,
         overwrite: bool, resume: bool, workers: int, scheduler: str | None,
         extra_meta: dict[str, Any] | None,
         on_frame: Callable[[int, int, FrameResult], bool] | None, task_timeout_s: float,
         connect_timeout_s: float, storage_options: dict[str, Any] | None,
         shard_frames: int | None) -> RunReport:
    from simcore.io.hdf5_writer import ResumeError
    from simcore.io.writer import open_writer

    writer = open_writer(out, project_json=project_json, seed=seed, overwrite=overwrite,
                         resume=resume, extra_meta=extra_meta, storage_options=storage_options,
                         shard_frames=shard_frames)
    if isinstance(spec, ScenesSpec) and resume:
        stored = _stored_attr(writer, "scenes_sha256")
        if stored is not None and stored != spec.key:
            writer.close(keep=True)
            raise ResumeError(f"cannot resume {out}: it was written from other scenes")
    todo = writer.missing(n_frames)
    report = RunReport(out, writer.n_frames, writer.n_frames, n_frames)
    with writer:
        try:
            if writer.n_frames == 0 and len(todo) == n_frames:
                static = static_items(spec)
                if isinstance(spec, ScenesSpec):
                    static["/scenes/projects"] = (
                        np.array([s.project_json for s in spec.scenes], dtype=str), "")
                writer.write_static(static)
            how: dict[str, Any] = {"workers": workers, "scheduler": scheduler,
                                   "task_timeout_s": task_timeout_s,
                                   "connect_timeout_s": connect_timeout_s}
            if hasattr(writer, "shards_of") and (workers > 1 or scheduler is not None):
                _write_shards(writer, spec, todo, report, on_frame, **how)
            else:
                _write_frames(writer, spec, todo, report, on_frame, **how)
        except KeyboardInterrupt:
            report.interrupted = True
        finally:
            close_simulators()
    report.frames_done = writer.n_frames
    return report


def _stored_attr(writer: Any, key: str) -> Any:
    """A metadata attribute of an opened writer's dataset (HDF5 ``/meta`` or Zarr root)."""
    group = getattr(writer, "group", None)
    if group is not None:
        return group.attrs.get(key)
    file = getattr(writer, "file", None)
    if file is not None and "meta" in file:
        value = file["meta"].attrs.get(key)
        return value.decode() if isinstance(value, bytes) else value
    return None


def _write_frames(writer: Any, spec: AnySpec, todo: Sequence[int], report: RunReport,
                  on_frame: Callable[[int, int, FrameResult], bool] | None, **how: Any
                  ) -> None:
    """Compute the frames ``todo`` and write them in a thread beside the engine.

    ``on_frame`` runs in the writer thread after each frame; a stop (False, Ctrl+C) drops
    the frames computed but not written, so the dataset ends where the callback stopped.
    """
    from simcore.io.writer import ThreadedWriter

    n_frames = report.frames_total

    def written(done: int, result: FrameResult) -> bool:
        report.frames_done = done
        return on_frame is None or on_frame(done, n_frames, result)

    with ThreadedWriter(writer, on_written=written) as threaded:
        completed = False
        try:
            for result in iter_frames(spec, todo, **how):
                if not threaded.submit(result):
                    break
            completed = True
        finally:
            threaded.finish(drop=not completed or threaded.stopped)
    report.interrupted = threaded.stopped and writer.n_frames < n_frames


def compute_shard(spec: AnySpec, target: Any, frames: Sequence[int]) -> int:
    """Compute the frames of one shard and write them into the store (in a worker).

    Returns the number of frames written. Only this process writes this shard: the driver
    never sends one shard to two workers at once, and a shard retried after a worker died
    is rewritten whole.
    """
    from simcore.io.zarr_writer import write_shard

    batch = [(r.index, r.items, r.tables) for r in results(spec, frames)]
    write_shard(target, batch)
    return len(batch)


def _write_shards(writer: Any, spec: AnySpec, todo: Sequence[int], report: RunReport,
                  on_frame: Callable[[int, int, FrameResult], bool] | None, *, workers: int,
                  scheduler: str | None, task_timeout_s: float, connect_timeout_s: float
                  ) -> None:
    """Workers compute and write whole shards; this process only schedules and commits.

    The shard that creates the arrays (the first one of a new store) is written here.
    """
    shards = writer.shards_of(todo)
    if shards and not writer.has_arrays:
        _write_frames(writer, spec, shards.pop(0), report, on_frame, workers=1,
                      scheduler=None, task_timeout_s=task_timeout_s,
                      connect_timeout_s=connect_timeout_s)
        if report.interrupted:
            return
    target = writer.target()
    done = report.frames_total - sum(len(frames) for frames in shards)
    window = max(2, 2 * workers)
    run = (_shards_on_dask(spec, target, shards, workers=workers, scheduler=scheduler,
                           window=window, task_timeout_s=task_timeout_s,
                           connect_timeout_s=connect_timeout_s) if scheduler is not None
           else _shards_on_pool(spec, target, shards, workers=workers, window=window))
    with contextlib.closing(run):
        for frames in run:
            writer.mark_complete(frames)
            report.frames_done = writer.n_frames
            for k in frames:
                done += 1
                if on_frame is not None and not on_frame(done, report.frames_total,
                                                         FrameResult(k, {})):
                    report.interrupted = True
            if report.interrupted:
                break


def _shards_on_pool(spec: AnySpec, target: Any, shards: list[list[int]], *, workers: int,
                    window: int) -> Generator[list[int], None, None]:
    """Shards written by local worker processes, yielded as they complete."""
    from concurrent.futures import FIRST_COMPLETED, wait

    ctx = multiprocessing.get_context("spawn")
    pool = ProcessPoolExecutor(max_workers=workers, mp_context=ctx, initializer=_ignore_sigint,
                               initargs=(os.getpid(),))
    pending: dict[Future[int], list[int]] = {}
    todo = list(shards)
    try:
        while todo or pending:
            while todo and len(pending) < window:
                frames = todo.pop(0)
                pending[pool.submit(compute_shard, spec, target, frames)] = frames
            finished, _ = wait(list(pending), return_when=FIRST_COMPLETED)
            for fut in finished:
                frames = pending.pop(fut)
                fut.result()
                yield frames
    except BrokenProcessPool:
        raise RunError("a worker process died (killed, out of memory or a crash in native "
                       "code); the store keeps every complete shard, continue with "
                       "--resume") from None
    finally:
        # Shards being written finish (complete shards only); queued ones are dropped.
        pool.shutdown(wait=True, cancel_futures=True)


def _shards_on_dask(spec: AnySpec, target: Any, shards: list[list[int]], *, workers: int,
                    scheduler: str, window: int, task_timeout_s: float,
                    connect_timeout_s: float) -> Generator[list[int], None, None]:
    """Shards written by Dask workers, yielded as they complete."""
    with _dask_client(scheduler, workers=workers, connect_timeout_s=connect_timeout_s
                      ) as client:
        from dask.distributed import as_completed

        spec_future = client.scatter(spec, broadcast=True)
        todo = list(shards)
        running = as_completed()
        frames_of: dict[Any, list[int]] = {}

        def submit() -> None:
            frames = todo.pop(0)
            fut = client.submit(compute_shard, spec_future, target, frames, pure=False)
            frames_of[fut.key] = frames
            running.add(fut)

        for _ in range(min(window, len(todo))):
            submit()
        for fut in running:
            try:
                fut.result(timeout=task_timeout_s * target.shard_frames)
            except (TimeoutError, asyncio.TimeoutError):
                raise SchedulerError(f"shard of frames {frames_of[fut.key][0]}.. did not "
                                     f"finish in time on {scheduler}") from None
            yield frames_of.pop(fut.key)
            if todo:
                submit()


__all__ = ["ArraySlot", "FrameResult", "NonFiniteOutputError", "RunReport", "RunSpec",
           "SchedulerError", "ScenesSpec", "check_scheduler_address", "compute_frame",
           "compute_shard", "frame_count", "iter_frames", "pad_items", "probe_scheduler", "results",
           "run_dataset", "run_scenes", "scene_entity_statics", "static_digest",
           "static_digests", "static_items"]
