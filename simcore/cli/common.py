"""What the commands share.

One-line errors (:class:`CliError`, :func:`_report_error`), argument types, the run's
preflight, disk and time checks, store options and the options every subcommand takes.
"""

from __future__ import annotations

import argparse
import errno
import json
import os
import signal
import sys
import threading
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import TYPE_CHECKING, Any, NoReturn

from simcore.preflight import MAX_FRAMES, MAX_SEED, RunError
from simcore.scene.project_io import ProjectError

if TYPE_CHECKING:
    from simcore.preflight import CostEstimate
    from simcore.scene.model import Project


#: Defaults of the Dask timeouts (kept equal to simcore.runs.runner's, without importing it).
CONNECT_TIMEOUT_S = 10.0


TASK_TIMEOUT_S = 600.0


class CliError(Exception):
    """An error reported to the user as one line, with exit status 2."""


#: Longest error line printed (characters).
MAX_ERROR_LENGTH = 600


#: Most worker processes of one run.
MAX_WORKERS = 256


class _Parser(argparse.ArgumentParser):
    """Argument errors as one line ``tofradar: error: …`` (exit status 2), no usage dump."""

    def error(self, message: str) -> NoReturn:
        _print_error(f"{self.prog.removeprefix('tofradar').strip() or 'arguments'}: {message}")
        raise SystemExit(2)


def _print_error(message: str) -> None:
    line = " ".join(str(message).split())
    if len(line) > MAX_ERROR_LENGTH:
        line = line[: MAX_ERROR_LENGTH - 3] + "..."
    print(f"tofradar: error: {line}", file=sys.stderr)


def _int_at_least(minimum: int, maximum: int | None = None) -> Callable[[str], int]:
    """Argument type: an integer in [minimum, maximum], with a one-line error otherwise."""
    what = "a positive integer" if minimum == 1 else f"an integer >= {minimum}"
    if maximum is not None:
        what += f" up to {maximum}"

    def parse(text: str) -> int:
        if len(text) > 40:
            raise argparse.ArgumentTypeError(f"expected {what}, got {len(text)} characters")
        try:
            value = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"expected {what}, got {text!r}") from None
        if value < minimum or (maximum is not None and value > maximum):
            raise argparse.ArgumentTypeError(f"expected {what}, got {value}")
        return value

    return parse


_positive_int = _int_at_least(1)


_frames_int = _int_at_least(1, MAX_FRAMES)


_seed_int = _int_at_least(0, MAX_SEED)


_workers_int = _int_at_least(1, MAX_WORKERS)


def _positive_float(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a positive number, got {text!r}") from None
    if not (value > 0 and value < float("inf")):
        raise argparse.ArgumentTypeError(f"expected a positive number, got {text[:40]}")
    return value


@contextmanager
def stop_on_sigint() -> Iterator[threading.Event]:
    """Turn the first Ctrl+C (or SIGTERM) into a request to stop after the frame being written.

    A KeyboardInterrupt raised at an arbitrary point can land in a garbage-collector
    callback, where Python only prints it and carries on; a flag checked between frames
    cannot be lost. A second signal interrupts at once. SIGTERM (what ``kill``, systemd
    and batch schedulers send) is handled exactly like SIGINT.
    """
    stop = threading.Event()

    def handler(signum: int, frame: object) -> None:
        if stop.is_set():
            raise KeyboardInterrupt
        stop.set()

    previous = {sig: signal.signal(sig, handler) for sig in (signal.SIGINT, signal.SIGTERM)}
    try:
        yield stop
    finally:
        for sig, old in previous.items():
            signal.signal(sig, old)


def _preflight(project: Project, project_path: Path, args: argparse.Namespace, *,
               n_frames: int | None = None, seed: int | None = None) -> CostEstimate:
    """Run :func:`simcore.preflight.check`; raise ProjectError listing every problem."""
    from simcore.preflight import check, estimate_cost

    force = getattr(args, "force", False)
    problems = check(project, base_dir=project_path.parent,
                     memory_budget_bytes=2**63 if force else None, n_frames=n_frames,
                     seed=seed, allow_outside_paths=args.allow_outside_paths)
    if problems:
        raise ProjectError(str(project_path), problems)
    return estimate_cost(project, base_dir=project_path.parent)


def _check_disk(out: Path, cost: CostEstimate, frames: int, *, force: bool) -> None:
    """Refuse a run whose dataset would not fit on the output's file system."""
    import shutil

    folder = out.parent if out.parent.exists() else Path.cwd()
    try:
        free = shutil.disk_usage(folder).free
    except OSError:
        return
    need = cost.disk_bytes_per_frame * frames
    if need > free and not force:
        raise CliError(f"--out {out}: {frames} frames need up to {need / 2**30:.2f} GiB "
                       f"(uncompressed, {cost.disk_bytes_per_frame / 2**20:.2f} MiB per frame) "
                       f"but {free / 2**30:.2f} GiB are free; free space, write fewer frames, "
                       "or pass --force (compression usually saves 2-5x)")


#: Default wall-time budget of one ``run`` (s): longer runs need ``--max-hours`` or --force.
TIME_BUDGET_S = 24 * 3600.0


def _check_time(cost: CostEstimate, frames: int, args: argparse.Namespace) -> None:
    """Refuse a run whose estimated duration exceeds ``--max-hours`` (unless --force)."""
    budget = getattr(args, "max_hours", None)
    budget_s = TIME_BUDGET_S if budget is None else budget * 3600.0
    need = cost.seconds_per_frame * frames
    if need > budget_s and not args.force:
        raise CliError(f"{frames} frames would take about {need / 3600:.1f} h "
                       f"(≈ {cost.seconds_per_frame:.2f} s per frame on this machine), over "
                       f"the {budget_s / 3600:g} h budget; write fewer frames, raise "
                       "--max-hours, or pass --force")


@contextmanager
def _run_errors(args: argparse.Namespace, bar: Any) -> Iterator[None]:
    """Dataset-writing failures of ``run`` as one-line CLI errors; the progress bar closed."""
    from simcore.io.hdf5_writer import DatasetExistsError, DiskFullError, ResumeError

    try:
        yield
    except (DatasetExistsError, ResumeError) as exc:
        raise CliError(str(exc)) from None
    except DiskFullError as exc:
        raise CliError(f"{exc.strerror}; free space and continue with --resume") from None
    except _store_errors() as exc:
        raise CliError(f"--out {args.out}: {type(exc).__name__}: {str(exc)[:300]}") from None
    finally:
        bar.close()


def _is_zarr_out(out: str) -> bool:
    from simcore.io.writer import is_zarr_target

    return is_zarr_target(out)


def _is_remote(out: str) -> bool:
    """``--out`` is a URL of a store other than a local file (``s3://``, ``memory://``)."""
    scheme, sep, _ = out.partition("://")
    return bool(sep) and scheme.lower() != "file" and _is_zarr_out(out)


def _storage_options(args: argparse.Namespace) -> dict[str, object] | None:
    """Storage options from ``--storage-option KEY=VALUE`` (values parsed as JSON if they can)."""
    options: dict[str, object] = {}
    for text in getattr(args, "storage_option", None) or []:
        key, sep, value = text.partition("=")
        if not sep or not key:
            raise CliError(f"--storage-option {text!r}: expected KEY=VALUE")
        try:
            options[key] = json.loads(value)
        except ValueError:
            options[key] = value
    endpoint = os.environ.get("TOFRADAR_S3_ENDPOINT")
    if endpoint and args.out.startswith("s3://") and "endpoint_url" not in options:
        options["endpoint_url"] = endpoint
    return options or None


def _store_errors() -> tuple[type[BaseException], ...]:
    """Errors of a store that cannot be reached or written (bad bucket, no credentials)."""
    errors: list[type[BaseException]] = [OSError, PermissionError]
    try:
        from botocore.exceptions import BotoCoreError, ClientError

        errors += [BotoCoreError, ClientError]
    except ImportError:
        pass
    return tuple(errors)


def _timeline_default(project: Project, args: argparse.Namespace) -> int:
    """Frames of the project's timeline when neither --frames nor --duration is given."""
    from simcore.preflight import timeline_frames

    if args.frames is not None or args.duration is not None:
        return 0
    frames = timeline_frames(project)
    if frames > MAX_FRAMES:
        raise CliError(f"{args.project}: timeline.duration_s × frame_rate_hz = {frames:.3g} "
                       f"frames; allowed at most {MAX_FRAMES} (or pass --frames)")
    return int(frames)


def _check_scheduler(address: str) -> None:
    from simcore.runs.runner import SchedulerError, check_scheduler_address

    try:
        check_scheduler_address(address)
    except SchedulerError as exc:
        raise CliError(str(exc)) from None


def _common(*, debug_only: bool = False) -> _Parser:
    """Options every subcommand takes."""
    common = _Parser(add_help=False)
    common.add_argument("--debug", action="store_true",
                        dest="debug_global" if debug_only else "debug",
                        help="print the traceback of an error instead of one line")
    if not debug_only:
        common.add_argument("--allow-outside-paths", action="store_true",
                            help="accept referenced files (meshes, BVH clips, an asset's "
                                 "buffers, a recording's parts) outside the folder that "
                                 "refers to them")
    return common


def _run_options(p: argparse.ArgumentParser) -> None:
    """Options shared by ``run`` and ``sweep``: limits, Dask timeouts."""
    p.add_argument("--force", action="store_true",
                   help="run even when the memory, disk or time estimate exceeds its budget")
    p.add_argument("--max-hours", type=_positive_float, default=None, metavar="H",
                   help=f"time budget of one run (default {TIME_BUDGET_S / 3600:g} h): "
                        "longer runs are refused unless --force")
    p.add_argument("--task-timeout", type=_positive_float, default=TASK_TIMEOUT_S, metavar="S",
                   help=f"longest wait for one frame on Dask (default {TASK_TIMEOUT_S:g} s)")
    p.add_argument("--connect-timeout", type=_positive_float, default=CONNECT_TIMEOUT_S,
                   metavar="S", help="longest wait for a Dask scheduler's handshake "
                                     f"(default {CONNECT_TIMEOUT_S:g} s)")


def _report_error(exc: BaseException) -> int:
    """Print ``exc`` as ``tofradar: error: …`` line(s); return the exit status."""
    from simcore.scene.mesh_files import MeshError

    if isinstance(exc, ProjectError):
        for problem in exc.problems:
            _print_error(f"{exc.source}: {problem}")
        return 2
    if isinstance(exc, (CliError, MeshError, RunError)):
        _print_error(str(exc))
        return 2
    if isinstance(exc, MemoryError):
        _print_error("out of memory; lower the render resolution, chirps or samples, or run "
                     "fewer workers ('tofradar validate' shows the estimate)")
        return 1
    if isinstance(exc, OSError):
        if exc.errno in (errno.ENOSPC, errno.EDQUOT):
            _print_error(f"disk full: {exc}; free space and continue with --resume")
        else:
            _print_error(str(exc))
        return 2
    name = type(exc).__name__
    text = " ".join(str(exc).split())
    text = text if len(text) <= 300 else text[:297] + "..."
    _print_error(f"{name}: {text} (run with --debug for the traceback)")
    return 1
