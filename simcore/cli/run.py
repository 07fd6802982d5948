"""``tofradar run``: render a project's frames headlessly into a dataset."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import TYPE_CHECKING

from simcore.cli.common import (
    CliError,
    _check_disk,
    _check_scheduler,
    _check_time,
    _frames_int,
    _int_at_least,
    _is_remote,
    _is_zarr_out,
    _Parser,
    _positive_float,
    _preflight,
    _run_errors,
    _run_options,
    _seed_int,
    _storage_options,
    _timeline_default,
    _workers_int,
    stop_on_sigint,
)
from simcore.preflight import MAX_FRAMES
from simcore.scene.project_io import load_project, project_to_json

if TYPE_CHECKING:
    from simcore.io.previews import PreviewSensor
    from simcore.runs.runner import FrameResult
    from simcore.scene.model import Project


def cmd_run(args: argparse.Namespace) -> int:
    """Render frames of a project headlessly into an HDF5 dataset."""
    from tqdm import tqdm

    from simcore.runs.runner import frame_count, run_dataset

    project_path = Path(args.project)
    if project_path.is_dir():
        return _run_scenes(args)
    if args.out.lower().endswith(".bin"):
        return _run_ti_capture(args)
    project = load_project(project_path)
    seed = project.seed if args.seed is None else args.seed
    try:
        n_frames = frame_count(args.frames, args.duration, project.timeline.frame_rate_hz,
                               _timeline_default(project, args))
    except ValueError as exc:
        raise CliError(str(exc)) from None
    out: Path | str = Path(args.out)
    remote = _is_remote(args.out)
    if "://" in args.out:
        out = args.out                  # a URL stays a string (s3://bucket/run, file://…)
    elif Path(out).is_dir() and not _is_zarr_out(args.out):
        raise CliError(f"--out {out} is a directory; give a file name such as {out}/run.h5")
    if args.resume and args.overwrite:
        raise CliError("--resume and --overwrite exclude each other")
    if args.scheduler is not None:
        _check_scheduler(args.scheduler)
    cost = _preflight(project, project_path, args, n_frames=n_frames, seed=seed)
    if not remote:
        _check_disk(Path(args.out.removeprefix("file://")), cost, n_frames, force=args.force)
    _check_time(cost, n_frames, args)
    preview_axes = _preview_sensors(project) if args.preview else None
    bar = tqdm(total=n_frames, desc="frames", unit="frame", file=sys.stderr,
               disable=args.quiet)

    def progress(done: int, total: int, result: FrameResult) -> bool:
        bar.n = done
        bar.refresh()
        if args.preview and result.items:   # frames written by workers come without data
            _write_previews(Path(args.preview), result, preview_axes)
        return not stop.is_set()

    with _run_errors(args, bar), stop_on_sigint() as stop:
        report = run_dataset(project_to_json(project), project_path.parent, out,
                             n_frames=n_frames, seed=seed, overwrite=args.overwrite,
                             resume=args.resume, workers=args.workers,
                             scheduler=args.scheduler, on_frame=progress,
                             task_timeout_s=args.task_timeout,
                             connect_timeout_s=args.connect_timeout,
                             storage_options=_storage_options(args),
                             shard_frames=args.shard_frames)
    if report.interrupted:
        print(f"interrupted: {report.frames_done} of {n_frames} frames are in {out}; "
              f"continue with --resume", file=sys.stderr)
        return 130
    if report.frames_done > report.first_frame:
        print(f"wrote frames {report.first_frame}..{report.frames_done - 1} to {out}")
    else:
        print(f"{out} already has {report.first_frame} frames; nothing to do")
    return 0


#: Most projects of one run over a folder of scenes.
MAX_SCENES = 100_000


def _run_scenes(args: argparse.Namespace) -> int:
    """``tofradar run DIR``: every project of a folder into one dataset, a scene index per frame."""
    from tqdm import tqdm

    from simcore.runs.runner import frame_count, run_scenes

    folder = Path(args.project)
    files = sorted(p for p in folder.glob("*.json") if p.is_file())
    if not files:
        raise CliError(f"{folder}: a folder of projects holds *.json project files; found none")
    if len(files) > MAX_SCENES:
        raise CliError(f"{folder}: {len(files)} projects; allowed at most {MAX_SCENES}")
    if args.seed is not None:
        raise CliError("--seed: each scene of a folder runs with its own project seed")
    if args.preview:
        raise CliError("--preview is for one project, not a folder of scenes")
    if args.resume and args.overwrite:
        raise CliError("--resume and --overwrite exclude each other")
    if args.scheduler is not None:
        _check_scheduler(args.scheduler)
    first = load_project(files[0])
    try:
        per_scene = frame_count(args.frames, args.duration, first.timeline.frame_rate_hz,
                                _timeline_default(first, args))
    except ValueError as exc:
        raise CliError(str(exc)) from None
    total = per_scene * len(files)
    if total > MAX_FRAMES:
        raise CliError(f"{len(files)} scenes × {per_scene} frames = {total} frames; allowed at "
                       f"most {MAX_FRAMES}")
    scenes = []
    for path in files:
        project = load_project(path)
        _preflight(project, path, args, n_frames=per_scene, seed=project.seed)
        scenes.append((project_to_json(project), path.parent))
    cost = _preflight(first, files[0], args, n_frames=per_scene, seed=first.seed)
    out: Path | str = args.out if "://" in args.out else Path(args.out)
    if not _is_remote(args.out):
        _check_disk(Path(args.out.removeprefix("file://")), cost, total, force=args.force)
    _check_time(cost, total, args)
    bar = tqdm(total=total, desc="frames", unit="frame", file=sys.stderr, disable=args.quiet)

    def progress(done: int, n: int, result: FrameResult) -> bool:
        bar.n = done
        bar.set_postfix_str(f"scene {result.index // per_scene + 1}/{len(files)}",
                            refresh=False)
        bar.refresh()
        return not stop.is_set()

    with _run_errors(args, bar), stop_on_sigint() as stop:
        report = run_scenes(scenes, out, frames_per_scene=per_scene,
                            overwrite=args.overwrite, resume=args.resume,
                            workers=args.workers, scheduler=args.scheduler,
                            on_frame=progress, task_timeout_s=args.task_timeout,
                            connect_timeout_s=args.connect_timeout,
                            storage_options=_storage_options(args),
                            shard_frames=args.shard_frames)
    if report.interrupted:
        print(f"interrupted: {report.frames_done} of {total} frames are in {out}; "
              f"continue with --resume", file=sys.stderr)
        return 130
    print(f"wrote {len(files)} scenes × {per_scene} frames (frames {report.first_frame}.."
          f"{report.frames_done - 1}) to {out}")
    return 0


def _preview_sensors(project: Project) -> dict[str, PreviewSensor]:
    """What the preview figures of each sensor need (its axes)."""
    from simcore.io.previews import preview_sensors

    return preview_sensors(project)


def _write_previews(preview_dir: Path, result: FrameResult,
                    sensors: dict[str, PreviewSensor] | None) -> None:
    """Labelled PNG figures of one computed frame (invalid depth pixels grey)."""
    from simcore.io.previews import save_frame_previews

    save_frame_previews(preview_dir, result.index, result.items, sensors)


def _run_ti_capture(args: argparse.Namespace) -> int:
    """``run P.json --out X.bin``: run into a temporary dataset, then write the capture."""
    import contextlib
    import io
    import tempfile

    from simcore.io.ti_dca1000 import CaptureError, export_capture

    out = Path(args.out)
    if (out.exists() or out.with_suffix(".cfg").exists()) and not args.overwrite:
        raise CliError(f"{out} or its .cfg already exists; use --overwrite to replace it")
    if args.resume:
        raise CliError("--resume is for datasets; a TI capture is written in one go")
    with tempfile.TemporaryDirectory(dir=out.parent if out.parent.is_dir() else None) as tmp:
        args.out = str(Path(tmp) / f"{out.stem}.h5")
        with contextlib.redirect_stdout(io.StringIO()):      # its "wrote …" names the temp file
            status = cmd_run(args)
        if status != 0:
            return status
        try:
            n, cfg = export_capture(args.out, out, overwrite=True)
        except CaptureError as exc:
            raise CliError(str(exc)) from None
    print(f"wrote {n} frames to {out} and its configuration {cfg}")
    return 0


def add_parser(sub: argparse._SubParsersAction[_Parser], common: list[_Parser]) -> None:
    """The ``run`` subcommand."""
    p = sub.add_parser("run", help="render frames headlessly into an HDF5 dataset",
                       parents=common)
    p.add_argument("project", help="project JSON file, or a folder of projects (one dataset "
                                   "of every scene, a scene index per frame)")
    p.add_argument("--out", required=True,
                   help="output file: HDF5 (.h5, default), an MCAP recording (.mcap), a "
                        "Zarr store (.zarr, or a URL such as s3://bucket/run), or a TI "
                        "DCA1000 capture (.bin, with its mmWave SDK .cfg beside it)")
    p.add_argument("--frames", type=_frames_int, help="number of frames (default: timeline)")
    p.add_argument("--duration", type=_positive_float, metavar="S",
                   help="simulated seconds (frames = S × frame rate)")
    p.add_argument("--seed", type=_seed_int, help="random seed (default: project seed)")
    p.add_argument("--overwrite", action="store_true",
                   help="replace an existing output file (when the new one is complete)")
    p.add_argument("--resume", action="store_true",
                   help="continue an interrupted run of the same project and seed")
    p.add_argument("--workers", type=_workers_int, default=1,
                   help="local worker processes (default 1)")
    p.add_argument("--scheduler", metavar="ADDRESS",
                   help="run frames on Dask: 'local' for an embedded cluster of --workers "
                        "processes, or a scheduler address such as tcp://host:8786")
    p.add_argument("--preview", metavar="DIR", help="also write PNG previews into DIR")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    p.add_argument("--shard-frames", type=_int_at_least(1, 4096), default=16, metavar="K",
                   help="Zarr: frames per shard, the unit a worker writes (default 16)")
    p.add_argument("--storage-option", action="append", metavar="KEY=VALUE",
                   help="Zarr on a URL: an fsspec storage option such as "
                        "endpoint_url=http://127.0.0.1:9000 (repeatable)")
    _run_options(p)
    p.set_defaults(func=cmd_run)
