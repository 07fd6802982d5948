"""Saved project files get the user's umask (0644 under 022) and keep an existing mode."""

from __future__ import annotations

import os
import stat

import pytest

from app.document.document import ProjectDocument
from simcore.resources import EXAMPLES_DIR

pytestmark = pytest.mark.gui


@pytest.fixture
def umask_022():
    old = os.umask(0o022)
    yield
    os.umask(old)


def test_a_saved_file_has_mode_0644_under_umask_022_and_keeps_its_mode(tmp_path, umask_022):
    doc = ProjectDocument()
    doc.open(EXAMPLES_DIR / "wall.json")          # a template: no file of its own
    doc.set_value("seed", 99)
    new = tmp_path / "wall.json"
    doc.save(new)
    assert stat.S_IMODE(new.stat().st_mode) == 0o644
    # An existing file keeps its own mode through the atomic replace.
    os.chmod(new, 0o600)
    doc.set_value("seed", 100)
    doc.save()
    assert stat.S_IMODE(new.stat().st_mode) == 0o600
    os.chmod(new, 0o664)
    doc.set_value("seed", 101)
    doc.save()
    assert stat.S_IMODE(new.stat().st_mode) == 0o664
    # No temporary file is left beside it.
    assert sorted(p.name for p in tmp_path.iterdir()) == ["wall.json"]
