"""The engine's one stage cache: results by (stage, configuration slice, input identities).

Every cached step of a frame — a render pass, a sensor's scatterers, an IF synthesis, a
DSP run — goes through :meth:`StageCache.run` with the configuration slice it reads (any
hashable value, usually the JSON of the config models it uses) and the objects it takes as
inputs. A later call with an equal slice and the *same* input objects returns the stored
result; anything else runs the step. Inputs are compared by identity, so a stage is
re-used exactly when the stages before it were, and a changed input never needs hashing.
"""

from __future__ import annotations

import threading
import time
from collections import OrderedDict
from collections.abc import Callable, Hashable, Sequence
from dataclasses import dataclass, field
from typing import Any, TypeVar

T = TypeVar("T")


@dataclass
class _Entry:
    reads: Hashable
    inputs: tuple[object, ...]
    value: Any


@dataclass
class StageCache:
    """Recent results of every stage, a few per stage name (least recently used dropped).

    Parameters
    ----------
    keep : int
        Results kept per stage name (a frame, its background and an edit's re-run need
        about two; the still-background accelerator adds one).
    enabled : bool
        False runs every step (the plain path that accelerated runs are checked against).

    Attributes
    ----------
    hits, misses : dict of str to int
        Per stage name, for tests and benchmarks.
    """

    keep: int = 3
    enabled: bool = True
    hits: dict[str, int] = field(default_factory=dict)
    misses: dict[str, int] = field(default_factory=dict)
    _entries: dict[str, OrderedDict[int, _Entry]] = field(default_factory=dict)
    _lock: threading.Lock = field(default_factory=threading.Lock)
    _next: int = 0
    _running: dict[Hashable, threading.Event] = field(default_factory=dict)

    def lookup(self, name: str, reads: Hashable, inputs: Sequence[object]
               ) -> tuple[bool, Any]:
        """``(True, value)`` for a stored result of ``name`` with these reads and inputs."""
        if not self.enabled:
            return False, None
        with self._lock:
            entries = self._entries.get(name)
            if entries:
                for key, entry in entries.items():
                    if (len(entry.inputs) == len(inputs)
                            and all(a is b for a, b in zip(entry.inputs, inputs, strict=True))
                            and entry.reads == reads):
                        entries.move_to_end(key)
                        self.hits[name] = self.hits.get(name, 0) + 1
                        return True, entry.value
        return False, None

    def store(self, name: str, reads: Hashable, inputs: Sequence[object], value: Any) -> None:
        """Keep ``value`` as the result of ``name`` for these reads and inputs."""
        if not self.enabled:
            return
        with self._lock:
            entries = self._entries.setdefault(name, OrderedDict())
            self._next += 1
            entries[self._next] = _Entry(reads, tuple(inputs), value)
            while len(entries) > self.keep:
                entries.popitem(last=False)

    def run(self, name: str, fn: Callable[[], T], *, reads: Hashable,
            inputs: Sequence[object] = (), timings: dict[str, float] | None = None,
            label: str | None = None) -> T:
        """The stored result of ``name`` for ``reads`` and ``inputs``, or ``fn()`` (stored).

        ``timings`` accumulates the wall time (ms) of steps that ran, under ``label``
        (default ``name``).
        """
        # One run per key at a time: a thread asking for a step another thread is running
        # (alike sensors on their own worker threads share a render's shading) waits for
        # that result instead of computing it again.
        key = (name, reads, tuple(id(i) for i in inputs))
        while True:
            found, value = self.lookup(name, reads, inputs)
            if found:
                return value
            with self._lock:
                running = self._running.get(key) if self.enabled else None
                if running is None:
                    self.misses[name] = self.misses.get(name, 0) + 1
                    mine = threading.Event()
                    if self.enabled:
                        self._running[key] = mine
            if running is None:
                break
            running.wait()       # then look again (or run it, if that run failed)
        try:
            t0 = time.perf_counter()
            value = fn()
            if timings is not None:
                with self._lock:
                    label_ = name if label is None else label
                    timings[label_] = (timings.get(label_, 0.0)
                                       + (time.perf_counter() - t0) * 1e3)
            self.store(name, reads, inputs, value)
        finally:
            with self._lock:
                if self._running.get(key) is mine:
                    del self._running[key]
            mine.set()
        return value

    def clear(self) -> None:
        """Forget every result."""
        with self._lock:
            self._entries.clear()
