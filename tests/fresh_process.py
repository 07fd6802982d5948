"""Peak memory of a run of its own: the run in a fresh interpreter.

``ru_maxrss`` is the peak of the whole process. In the test process that is whatever peak an
earlier test reached (under pytest-xdist, whichever tests the worker happened to run
before), so a run's growth could hide under it and a memory test would pass whatever the
run did. In a fresh interpreter the peak is the run's own.
"""

from __future__ import annotations

import importlib
import multiprocessing
import resource
from concurrent.futures import ProcessPoolExecutor
from typing import Any


def _peak_rss_mib() -> float:
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024


def _run(runner: str, args: tuple[Any, ...], kwargs: dict[str, Any]) -> tuple[Any, list[float]]:
    module, _, name = runner.rpartition(".")
    fn = getattr(importlib.import_module(module), name)
    rss: list[float] = []

    def sample(done: int, total: int, result: object) -> bool:
        rss.append(_peak_rss_mib())
        return True

    return fn(*args, on_frame=sample, **kwargs), rss


def peak_rss_per_frame(runner: str, *args: Any, **kwargs: Any) -> tuple[Any, list[float]]:
    """Call ``runner(*args, on_frame=..., **kwargs)`` in a fresh interpreter (spawn).

    Parameters
    ----------
    runner : str
        Dotted name of a run function taking ``on_frame``, e.g.
        ``"simcore.runs.runner.run_dataset"``.

    Returns
    -------
    tuple
        The run's return value, and the process's peak RSS (MiB) after each frame.
    """
    with ProcessPoolExecutor(1, mp_context=multiprocessing.get_context("spawn")) as pool:
        return pool.submit(_run, runner, args, kwargs).result()
