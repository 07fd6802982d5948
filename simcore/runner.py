"""Dataset generation: frames as independent jobs, written in frame order by one writer.

Frames run in-process, on local processes or on a Dask cluster.

The unit of work is :func:`compute_frame` on a :class:`RunSpec` and a frame index. A
frame's random numbers come from ``(seed, index)`` alone, so a frame is bit-identical
whichever process computes it and in whatever order.
"""

from __future__ import annotations

import hashlib
import json
import multiprocessing
import signal
from collections.abc import Callable, Iterator
from concurrent.futures import Future, ProcessPoolExecutor
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from numpy.typing import NDArray

from simcore.pipeline import Simulator
from simcore.scene.project_io import project_from_dict
from simcore.sensors.base import H5Items


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
    """Release this process's cached simulators (offscreen windows) now, not at exit."""
    for sim in _SIMULATORS.values():
        sim.close()
    _SIMULATORS.clear()


def compute_frame(spec: RunSpec, index: int) -> FrameResult:
    """Compute frame ``index`` of a run (in whichever process calls it)."""
    frame = _simulator(spec).frame(index)
    return FrameResult(index, frame.hdf5_items(), frame.table_rows(), frame.timings_ms)


def static_items(spec: RunSpec) -> H5Items:
    """Run-constant datasets (object names and ids, axes)."""
    return _simulator(spec).static_items()


def _ignore_sigint() -> None:
    """Worker processes leave Ctrl+C to the writer, which stops the run between frames."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)


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


def iter_frames(spec: RunSpec, indices: list[int], *, workers: int = 1,
                scheduler: str | None = None) -> Iterator[FrameResult]:
    """Yield the frames ``indices`` in order, computed by ``workers`` processes or Dask.

    Parameters
    ----------
    spec : RunSpec
        The run.
    indices : list of int
        Frames to compute, in the order they are yielded.
    workers : int
        Local worker processes (1 = in this process).
    scheduler : str, optional
        ``"local"`` for an embedded Dask ``LocalCluster`` with ``workers`` processes, or the
        address of a running Dask scheduler (``tcp://host:8786``).
    """
    window = max(2, 2 * workers)   # bounded look-ahead keeps memory flat on long runs
    if scheduler is not None:
        yield from _iter_dask(spec, indices, workers=workers, scheduler=scheduler,
                              window=window)
    elif workers <= 1:
        for i in indices:
            yield compute_frame(spec, i)
    else:
        ctx = multiprocessing.get_context("spawn")
        with ProcessPoolExecutor(max_workers=workers, mp_context=ctx,
                                 initializer=_ignore_sigint) as pool:
            def submit() -> Iterator[tuple[int, Callable[[], FrameResult]]]:
                for i in indices:
                    fut: Future[FrameResult] = pool.submit(compute_frame, spec, i)
                    yield i, fut.result
            try:
                yield from _in_order(submit(), window)
            except BaseException:
                pool.shutdown(wait=False, cancel_futures=True)
                raise


def _iter_dask(spec: RunSpec, indices: list[int], *, workers: int, scheduler: str,
               window: int) -> Iterator[FrameResult]:
    from dask.distributed import Client, LocalCluster

    cluster = None
    if scheduler == "local":
        cluster = LocalCluster(n_workers=max(1, workers), threads_per_worker=1,
                               processes=True, dashboard_address=None)
        client = Client(cluster)
    else:
        client = Client(scheduler)
    try:
        spec_future = client.scatter(spec, broadcast=True)

        def submit() -> Iterator[tuple[int, Callable[[], FrameResult]]]:
            for i in indices:
                fut = client.submit(compute_frame, spec_future, i, pure=False)
                yield i, fut.result
        yield from _in_order(submit(), window)
    finally:
        client.close()
        if cluster is not None:
            cluster.close()


def frame_count(n_frames: int | None, duration_s: float | None, frame_rate_hz: float,
                default: int) -> int:
    """Frames to produce from ``--frames`` or ``--duration`` (else the project timeline)."""
    if n_frames is not None:
        return n_frames
    if duration_s is not None:
        return max(1, int(round(duration_s * frame_rate_hz)))
    return default


@dataclass
class RunReport:
    """What a dataset run did."""

    path: Path
    first_frame: int
    frames_done: int
    frames_total: int
    interrupted: bool = False


def run_dataset(project_json: str, base_dir: Path, out: Path, *, n_frames: int, seed: int,
                overwrite: bool = False, resume: bool = False, workers: int = 1,
                scheduler: str | None = None, extra_meta: dict[str, Any] | None = None,
                on_frame: Callable[[int, int, FrameResult], bool] | None = None) -> RunReport:
    """Write ``n_frames`` frames of a project into ``out`` (HDF5, or MCAP for ``*.mcap``).

    ``on_frame(done, total, result)`` is called after each frame is written; returning
    False stops the run cleanly (as does Ctrl+C), leaving a valid file that
    ``resume=True`` continues.
    """
    from simcore.io.hdf5_writer import DatasetWriter
    from simcore.io.mcap_writer import McapWriter

    spec = RunSpec(project_json, str(base_dir), seed)
    kind = McapWriter if Path(out).suffix.lower() == ".mcap" else DatasetWriter
    writer = kind(out, project_json=project_json, seed=seed, overwrite=overwrite,
                  resume=resume, extra_meta=extra_meta)
    report = RunReport(out, writer.n_frames, writer.n_frames, n_frames)
    with writer:
        if writer.n_frames == 0:
            writer.write_static(static_items(spec))
        try:
            for result in iter_frames(spec, list(range(writer.n_frames, n_frames)),
                                      workers=workers, scheduler=scheduler):
                for path, rows in result.tables.items():
                    writer.append_rows(path, rows)
                writer.append(result.items)
                report.frames_done = writer.n_frames
                if on_frame is not None and not on_frame(writer.n_frames, n_frames, result):
                    report.interrupted = writer.n_frames < n_frames
                    break
        except KeyboardInterrupt:
            report.interrupted = True
        finally:
            close_simulators()
    return report


__all__ = ["FrameResult", "RunReport", "RunSpec", "compute_frame", "frame_count", "iter_frames",
           "run_dataset", "static_items"]
