"""The stage cache runs a step once when several threads ask for it at the same time."""

from __future__ import annotations

import threading
from concurrent.futures import ThreadPoolExecutor

import pytest

from simcore.engine.cache import StageCache


def test_concurrent_askers_share_one_run() -> None:
    cache = StageCache()
    started, release = threading.Event(), threading.Event()
    calls: list[int] = []
    token = object()

    def step() -> int:
        calls.append(1)
        started.set()
        release.wait(5)
        return 42

    with ThreadPoolExecutor(4) as pool:
        first = pool.submit(cache.run, "shade", step, reads="cfg", inputs=(token,))
        assert started.wait(5)
        others = [pool.submit(cache.run, "shade", step, reads="cfg", inputs=(token,))
                  for _ in range(3)]
        release.set()
        results = [first.result(5)] + [f.result(5) for f in others]
    assert results == [42] * 4 and len(calls) == 1
    assert cache.misses["shade"] == 1 and cache.hits["shade"] == 3


def test_a_failed_run_lets_the_waiters_run_it() -> None:
    cache = StageCache()
    token = object()
    with pytest.raises(RuntimeError):
        cache.run("s", lambda: (_ for _ in ()).throw(RuntimeError("boom")), reads=1,
                  inputs=(token,))
    assert cache.run("s", lambda: 7, reads=1, inputs=(token,)) == 7


def test_a_disabled_cache_runs_every_time() -> None:
    cache = StageCache(enabled=False)
    calls: list[int] = []
    for _ in range(3):
        cache.run("s", lambda: calls.append(1), reads=1)
    assert len(calls) == 3
