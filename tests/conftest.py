"""Shared fixtures: small scenes built in code, a renderer that is always closed."""

from __future__ import annotations

from collections.abc import Iterator

import pytest

from simcore.render import SceneRenderer
from simcore.scene import Project


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
