"""Shared fixtures: small scenes built in code, a renderer that is always closed, and the
free memory the tests take the machine to have (so no outcome depends on its load)."""

from __future__ import annotations

from collections.abc import Iterator

import pytest

from simcore import preflight
from simcore.render import SceneRenderer
from simcore.scene import Project

#: Free memory (MemAvailable) the tests take the machine to have. The memory budget of a run
#: and of a GUI edit is 80 % of the free memory, so without a pin a test's refusal or
#: confirmation would depend on what else the machine is doing (issue 41). Runs in a
#: subprocess still see the real figure; none of those comes near a budget.
PINNED_FREE_MEMORY_BYTES = 16 * 2**30


@pytest.fixture(autouse=True)
def pinned_free_memory(monkeypatch: pytest.MonkeyPatch) -> None:
    """Every test sees :data:`PINNED_FREE_MEMORY_BYTES` of free memory."""
    monkeypatch.setattr(preflight, "available_memory_bytes", lambda: PINNED_FREE_MEMORY_BYTES)


@pytest.fixture
def make_renderer() -> Iterator:
    """Factory for renderers that are closed at the end of the test."""
    made: list[SceneRenderer] = []

    def factory(project: Project, **kw: object) -> SceneRenderer:
        r = SceneRenderer(project, **kw)  # type: ignore[arg-type]
        made.append(r)
        return r

    yield factory
    for r in made:
        r.close()
