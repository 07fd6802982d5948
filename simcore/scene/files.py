"""Every input file the tool opens goes through here: type, size and path checked first.

A FIFO opened for reading blocks until a writer appears, ``/dev/zero`` never ends, a
directory cannot be read and a symlink may lead out of the project's folder. So before a
file is opened it is resolved (symlinks followed, loops refused), required to be a regular
file of at most a given size, and — for a file a project or a recording *refers to* —
required to lie inside the referring folder unless the user passed
``--allow-outside-paths``. The file is then opened without blocking and read with a
bounded read, so a file swapped for a FIFO or grown in between cannot hang or flood the
process. Every problem is one :class:`InputFileError` naming the file.
"""

from __future__ import annotations

import errno
import json
import os
import stat
from collections.abc import Sequence
from pathlib import Path
from typing import Any


class InputFileError(ValueError):
    """A file that cannot be used as input: ``str()`` is ``"LABEL: problem"``.

    Attributes
    ----------
    path : Path
        The file as given.
    problem : str
        What is wrong, without the file's name.
    missing : bool
        The file does not exist.
    """

    def __init__(self, path: Path, problem: str, *, label: str | None = None,
                 missing: bool = False) -> None:
        self.path = Path(path)
        self.problem = problem
        self.missing = missing
        super().__init__(f"{label if label is not None else self.path.name}: {problem}")


def _resolve(path: Path, label: str | None) -> Path:
    try:
        return path.resolve(strict=True)
    except RuntimeError as exc:
        raise InputFileError(path, f"symlink loop: {exc}", label=label) from None
    except OSError as exc:
        if exc.errno == errno.ELOOP:
            raise InputFileError(path, f"symlink loop: {exc.strerror}", label=label) from None
        raise InputFileError(path, f"cannot open: {exc.strerror}", label=label,
                             missing=exc.errno == errno.ENOENT) from None


def check_regular_file(path: str | os.PathLike[str], *, max_bytes: int,
                       label: str | None = None) -> tuple[Path, int]:
    """Resolve ``path``; refuse anything but a regular file of at most ``max_bytes``.

    Returns
    -------
    real : Path
        The resolved path (symlinks followed).
    size : int
        Its size (bytes).
    """
    path = Path(path)
    real = _resolve(path, label)
    try:
        st = os.stat(real)
    except OSError as exc:
        raise InputFileError(path, f"cannot open: {exc.strerror}", label=label) from None
    if not stat.S_ISREG(st.st_mode):
        raise InputFileError(path, "not a regular file (device, FIFO, socket or directory)",
                             label=label)
    if st.st_size > max_bytes:
        raise InputFileError(path, f"file has {st.st_size} bytes; at most {max_bytes}",
                             label=label)
    return real, int(st.st_size)


def read_regular_file(path: str | os.PathLike[str], *, max_bytes: int,
                      label: str | None = None) -> bytes:
    """The bytes of a regular file of at most ``max_bytes`` (:func:`check_regular_file`).

    The file is opened with ``O_NONBLOCK`` and checked again on the open descriptor, and
    at most ``max_bytes + 1`` bytes are read: a file replaced by a FIFO or a device after
    the check neither blocks nor floods memory.
    """
    path = Path(path)
    real, _ = check_regular_file(path, max_bytes=max_bytes, label=label)
    try:
        fd = os.open(real, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0))
    except OSError as exc:
        raise InputFileError(path, f"cannot open: {exc.strerror}", label=label) from None
    with os.fdopen(fd, "rb") as fh:
        if not stat.S_ISREG(os.fstat(fh.fileno()).st_mode):
            raise InputFileError(path, "not a regular file", label=label)
        try:
            data = fh.read(max_bytes + 1)
        except OSError as exc:
            raise InputFileError(path, f"cannot read: {exc.strerror}", label=label) from None
    if len(data) > max_bytes:
        raise InputFileError(path, f"file is larger than {max_bytes} bytes", label=label)
    return data


def read_text_file(path: str | os.PathLike[str], *, max_bytes: int,
                   label: str | None = None) -> str:
    """A regular file's UTF-8 text (:func:`read_regular_file`)."""
    data = read_regular_file(path, max_bytes=max_bytes, label=label)
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise InputFileError(Path(path), f"not UTF-8 text ({exc.reason} at byte {exc.start})",
                             label=label) from None


def _no_constant(name: str) -> float:
    raise ValueError(f"{name} is not a valid JSON number")


def read_json_file(path: str | os.PathLike[str], *, max_bytes: int,
                   label: str | None = None) -> Any:
    """A regular file's JSON document; ``NaN``/``Infinity`` and deep nesting refused."""
    text = read_text_file(path, max_bytes=max_bytes, label=label)
    try:
        return json.loads(text, parse_constant=_no_constant)
    except json.JSONDecodeError as exc:
        raise InputFileError(Path(path), f"not valid JSON ({exc.msg} at line {exc.lineno}, "
                                         f"column {exc.colno})", label=label) from None
    except RecursionError:
        raise InputFileError(Path(path), "not valid JSON (nested too deeply)",
                             label=label) from None
    except ValueError as exc:   # NaN/Infinity, or an integer of more than 4300 digits
        raise InputFileError(Path(path), f"not valid JSON ({' '.join(str(exc).split())[:120]})",
                             label=label) from None


def is_inside(real: Path, folder: Path) -> bool:
    """Whether the resolved path ``real`` lies inside ``folder`` (resolved here)."""
    try:
        real.relative_to(folder.resolve())
    except (ValueError, OSError, RuntimeError):
        return False
    return True


def reference_path(base_dir: Path | None, reference: str) -> Path:
    """A referenced file's path: absolute as given, else relative to ``base_dir``."""
    path = Path(reference)
    return path if path.is_absolute() else (base_dir or Path.cwd()) / path


def reference_problem(base_dir: Path | None, reference: str, *, what: str,
                      suffixes: Sequence[str] | None = None, max_bytes: int,
                      allow_outside_paths: bool = False) -> str | None:
    """Why a file a project refers to breaks the path policy (None if it does not).

    The policy of every referenced file (meshes, BVH clips, recording parts): a known
    suffix, inside the referring folder after ``..`` and symlinks are resolved (unless
    ``allow_outside_paths``), a regular file (not a device, FIFO, socket, directory or
    symlink loop) of at most ``max_bytes``.

    Parameters
    ----------
    base_dir : Path, optional
        The referring folder (the project's); default: the working folder.
    reference : str
        The path as written in the project.
    what : str
        The kind of file, for messages ("mesh", "BVH clip").
    suffixes : sequence of str, optional
        Accepted suffixes (lower case, with the dot).
    max_bytes : int
        Largest size.
    allow_outside_paths : bool
        Accept files outside the folder (``--allow-outside-paths``).
    """
    base = base_dir or Path.cwd()
    path = reference_path(base, reference)
    if suffixes is not None and path.suffix.lower() not in suffixes:
        return f"unsupported {what} format {path.suffix!r} (use {', '.join(suffixes)})"
    try:
        real = path.resolve(strict=True)
    except RuntimeError:
        return f"symlink loop at {reference!r}"
    except OSError as exc:
        if exc.errno == errno.ELOOP:
            return f"symlink loop at {reference!r}"
        return f"{what} file not found: {path}"
    if not allow_outside_paths and not is_inside(real, base):
        return (f"{reference!r} is outside the project folder (move it there or pass "
                f"--allow-outside-paths); it resolves to {real}")
    try:
        check_regular_file(real, max_bytes=max_bytes)
    except InputFileError as exc:
        if "not a regular file" in exc.problem:
            return f"{reference!r} is not a regular file (device, FIFO, socket or directory)"
        if exc.problem.startswith("file has"):
            return f"{reference!r} has {exc.problem.removeprefix('file has ')}".replace(
                "; at most", "; allowed at most")
        return f"cannot open {reference!r}: {exc.problem}"
    return None


__all__ = ["InputFileError", "check_regular_file", "is_inside", "read_json_file",
           "read_regular_file", "read_text_file", "reference_path", "reference_problem"]
