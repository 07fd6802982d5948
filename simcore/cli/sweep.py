"""``tofradar sweep``: one dataset per combination of varied project fields."""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

from simcore.cli.common import (
    CliError,
    _check_disk,
    _check_scheduler,
    _check_time,
    _frames_int,
    _Parser,
    _positive_float,
    _run_options,
    _seed_int,
    _timeline_default,
    _workers_int,
    stop_on_sigint,
)
from simcore.scene.project_io import ProjectError, load_project, project_to_json


def cmd_sweep(args: argparse.Namespace) -> int:
    """One dataset per combination of the varied fields, with the parameters recorded."""
    from simcore.io.hdf5_writer import DatasetExistsError, DiskFullError, ResumeError
    from simcore.preflight import check as check_project
    from simcore.preflight import estimate_cost
    from simcore.runs.runner import frame_count, run_dataset
    from simcore.runs.sweep import SweepError, expand, parameters_json, parse_vary

    project_path = Path(args.project)
    project = load_project(project_path)
    for spec in args.vary:
        _check_vary_count(spec)
    try:
        variants = expand(project, [parse_vary(v) for v in args.vary])
    except (SweepError, ValueError, OverflowError) as exc:
        raise CliError(str(exc)) from None
    if args.scheduler is not None:
        _check_scheduler(args.scheduler)
    out_dir = Path(args.out)
    if out_dir.exists() and not out_dir.is_dir():
        raise CliError(f"--out {out_dir} exists and is not a directory")
    out_dir.mkdir(parents=True, exist_ok=True)
    index = []
    for i, (params, variant) in enumerate(variants):
        path = out_dir / f"variant_{i:04d}.h5"
        seed = variant.seed if args.seed is None else args.seed
        try:
            n_frames = frame_count(args.frames, args.duration, variant.timeline.frame_rate_hz,
                                   _timeline_default(variant, args))
        except ValueError as exc:
            raise CliError(str(exc)) from None
        problems = check_project(variant, base_dir=project_path.parent, n_frames=n_frames,
                                 seed=seed, allow_outside_paths=args.allow_outside_paths,
                                 memory_budget_bytes=2**63 if args.force else None)
        if problems:
            raise ProjectError(f"{project_path} variant {i} {parameters_json(params)}", problems)
        variant_cost = estimate_cost(variant, base_dir=project_path.parent)
        _check_disk(path, variant_cost, n_frames, force=args.force)
        _check_time(variant_cost, n_frames, args)
        print(f"[{i + 1}/{len(variants)}] {path.name}: {parameters_json(params)}")
        try:
            with stop_on_sigint() as stop:
                report = run_dataset(
                    project_to_json(variant), project_path.parent, path, n_frames=n_frames,
                    seed=seed, overwrite=args.overwrite, resume=args.resume,
                    workers=args.workers, scheduler=args.scheduler,
                    extra_meta={"sweep_parameters": parameters_json(params)},
                    on_frame=lambda done, total, result: not stop.is_set(),
                    task_timeout_s=args.task_timeout, connect_timeout_s=args.connect_timeout)
        except (DatasetExistsError, ResumeError) as exc:
            raise CliError(str(exc)) from None
        except DiskFullError as exc:
            raise CliError(f"{exc.strerror}; free space and continue with --resume") from None
        if report.interrupted:
            print("interrupted; continue with --resume", file=sys.stderr)
            return 130
        index.append({"file": path.name, "parameters": params, "frames": n_frames,
                      "seed": seed})
    (out_dir / "sweep.json").write_text(json.dumps({"project": str(project_path),
                                                    "variants": index}, indent=2) + "\n")
    print(f"wrote {len(variants)} datasets and sweep.json to {out_dir}")
    return 0


#: Most values one ``--vary`` may give.
MAX_VARY_VALUES = 10_000


def _check_vary_count(spec: str) -> None:
    """Refuse a ``--vary`` range with more values than :data:`MAX_VARY_VALUES` early."""
    _, _, values = spec.partition("=")
    parts = values.split(":")
    if len(parts) != 3:
        return
    try:
        start, stop, step = (float(p) for p in parts)
    except ValueError:
        return
    count = (stop - start) / step if step else float("inf")
    if not (abs(count) < MAX_VARY_VALUES):
        raise CliError(f"--vary {spec[:80]!r}: step {step:g} gives {abs(count):.3g} values; "
                       f"allowed at most {MAX_VARY_VALUES}")


def add_parser(sub: argparse._SubParsersAction[_Parser], common: list[_Parser]) -> None:
    """The ``sweep`` subcommand."""
    p = sub.add_parser("sweep", help="one dataset per combination of varied project fields",
                       parents=common)
    p.add_argument("project", help="project JSON file")
    p.add_argument("--vary", action="append", required=True, metavar="PATH=START:STOP:STEP",
                   help="field path and values, e.g. objects[0].pose.position_m[0]=1:3:0.5 "
                        "or rig.radar.chirps_per_frame=16,32 (repeatable)")
    p.add_argument("--out", required=True, metavar="DIR", help="output directory")
    p.add_argument("--frames", type=_frames_int, help="frames per variant")
    p.add_argument("--duration", type=_positive_float, metavar="S", help="seconds per variant")
    p.add_argument("--seed", type=_seed_int, help="random seed (default: project's)")
    p.add_argument("--overwrite", action="store_true", help="replace existing datasets")
    p.add_argument("--resume", action="store_true", help="continue interrupted datasets")
    p.add_argument("--workers", type=_workers_int, default=1, help="local worker processes")
    p.add_argument("--scheduler", metavar="ADDRESS", help="Dask scheduler ('local' or address)")
    _run_options(p)
    p.set_defaults(func=cmd_sweep)
