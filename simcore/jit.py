"""Compiled inner loops: the one place that says how the core's kernels are compiled.

Hot per-pixel and per-facet loops (shading, facet visibility and amplitudes) are single
passes written as plain Python loops and compiled by numba: one pass over the data instead
of dozens of numpy temporaries, and without the GIL, so the radar chain's worker and the
calling thread's chain run on two cores at once. Compiled code is cached on disk next to
the source (``__pycache__``), so only the first run on a machine pays the compilation.

Set ``NUMBA_DISABLE_JIT=1`` to run the kernels as Python (slow; for debugging).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, TypeVar, cast

import numba

F = TypeVar("F", bound=Callable[..., Any])


def kernel(fn: F) -> F:
    """Compile ``fn`` with numba: no Python objects, GIL released, cached on disk.

    ``fastmath`` stays off: the kernels must give the same numbers as IEEE arithmetic in
    the order written (results are compared with numpy references in the tests).
    """
    return cast(F, numba.njit(cache=True, nogil=True, fastmath=False)(fn))


__all__ = ["kernel"]
