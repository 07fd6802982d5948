"""The one helper every input file goes through (``simcore.scene.files``)."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from simcore.scene.files import (
    InputFileError,
    check_regular_file,
    read_json_file,
    read_regular_file,
    reference_problem,
)

pytestmark = pytest.mark.timeout(60)


def test_a_regular_file_is_read_whole(tmp_path):
    (tmp_path / "a.txt").write_bytes(b"x" * 100)
    assert read_regular_file(tmp_path / "a.txt", max_bytes=100) == b"x" * 100
    assert check_regular_file(tmp_path / "a.txt", max_bytes=100)[1] == 100


@pytest.mark.parametrize("kind", ["fifo", "dev_zero", "directory", "loop", "missing", "big"])
def test_special_files_are_refused_without_blocking(kind, tmp_path):
    path = tmp_path / "f.json"
    if kind == "fifo":
        os.mkfifo(path)                      # no writer: a plain open() would block forever
    elif kind == "dev_zero":
        path.symlink_to("/dev/zero")         # never ends
    elif kind == "directory":
        path.mkdir()
    elif kind == "loop":
        path.symlink_to(path)
    elif kind == "big":
        path.write_bytes(b"0" * 101)
    with pytest.raises(InputFileError) as info:
        read_json_file(path, max_bytes=100, label=str(path))
    text = str(info.value)
    assert text.startswith(f"{path}: ")
    expected = {"fifo": "not a regular file", "dev_zero": "not a regular file",
                "directory": "not a regular file", "loop": "symlink loop",
                "missing": "No such file", "big": "file has 101 bytes; at most 100"}[kind]
    assert expected in text
    assert info.value.missing == (kind == "missing")


@pytest.mark.parametrize(("text", "reason"), [("{", "not valid JSON"), ("NaN", "NaN"),
                                              ("[" * 100_000, "nested too deeply"),
                                              ("9" * 5000, "4300 digits")])
def test_bad_json_names_the_reason(text, reason, tmp_path):
    (tmp_path / "a.json").write_text(text)
    with pytest.raises(InputFileError, match=reason):
        read_json_file(tmp_path / "a.json", max_bytes=1 << 20)


def test_reference_policy(tmp_path):
    project = tmp_path / "project"
    project.mkdir()
    (project / "in.bvh").write_text("x")
    (tmp_path / "out.bvh").write_text("x")
    (project / "link.bvh").symlink_to(tmp_path / "out.bvh")
    (project / "zero.bvh").symlink_to("/dev/zero")

    def problem(ref: str, **kw: bool) -> str | None:
        return reference_problem(project, ref, what="BVH clip", max_bytes=10, **kw)

    assert problem("in.bvh") is None
    assert problem(str(project / "in.bvh")) is None                # absolute, inside
    for ref in ("../out.bvh", str(tmp_path / "out.bvh"), "link.bvh", "zero.bvh"):
        assert "outside the project folder" in (problem(ref) or ""), ref
    assert problem("../out.bvh", allow_outside_paths=True) is None
    assert "not a regular file" in (problem("zero.bvh", allow_outside_paths=True) or "")
    assert "BVH clip file not found" in (problem("none.bvh") or "")
    (project / "big.bvh").write_text("x" * 11)
    assert problem("big.bvh") == "'big.bvh' has 11 bytes; allowed at most 10"


def test_a_file_swapped_for_a_fifo_after_the_check_does_not_block(tmp_path, monkeypatch):
    # The race: checked as a regular file, replaced by a FIFO before it is opened. The
    # open does not block (O_NONBLOCK) and the descriptor is checked again.
    import simcore.scene.files as files

    path = tmp_path / "a.json"
    path.write_text("{}")
    real_check = files.check_regular_file

    def check_then_swap(p: Path, **kw: object) -> tuple[Path, int]:
        out = real_check(p, **kw)  # type: ignore[arg-type]
        path.unlink()
        os.mkfifo(path)
        return out

    monkeypatch.setattr(files, "check_regular_file", check_then_swap)
    with pytest.raises(InputFileError, match="not a regular file"):
        files.read_regular_file(path, max_bytes=100)
