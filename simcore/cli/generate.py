"""``tofradar generate``: randomized projects from a scenario spec."""

from __future__ import annotations

import argparse
import sys

from simcore.cli import run
from simcore.cli.common import (
    _common,
    _frames_int,
    _int_at_least,
    _Parser,
    _seed_int,
    _workers_int,
)


def cmd_generate(args: argparse.Namespace) -> int:
    """Write N randomized projects from a scenario spec (``simcore.scenarios``)."""
    from tqdm import tqdm

    from simcore.scenarios import generate

    bars: list[tqdm[None]] = []       # made at the first project: a bad spec prints one line only

    def progress(done: int, total: int) -> None:
        if not bars:
            bars.append(tqdm(total=total, desc="projects", unit="project", file=sys.stderr,
                             disable=args.quiet))
        bars[0].update(1)

    try:
        written = generate(args.spec, args.out, count=args.count, seed=args.seed,
                           overwrite=args.overwrite, on_project=progress,
                           n_frames=args.frames if args.run is not None else None,
                           allow_outside_paths=args.allow_outside_paths,
                           memory_budget_bytes=2**63 if args.force else None)
    finally:
        for bar in bars:
            bar.close()
    print(f"wrote {len(written)} projects to {args.out} "
          f"({written[0].name} .. {written[-1].name})")
    if args.run is None:
        return 0
    parser = _Parser(prog="tofradar")     # the ``run`` command's parser and defaults
    run.add_parser(parser.add_subparsers(dest="command"), [_common()])
    run_args = parser.parse_args(["run", str(args.out), "--out", args.run])
    for key in ("frames", "workers", "scheduler", "quiet", "shard_frames", "storage_option",
                "overwrite_run", "resume", "force", "allow_outside_paths"):
        if hasattr(args, key):
            setattr(run_args, "overwrite" if key == "overwrite_run" else key,
                    getattr(args, key))
    return run._run_scenes(run_args)


def add_parser(sub: argparse._SubParsersAction[_Parser], common: list[_Parser]) -> None:
    """The ``generate`` subcommand."""
    p = sub.add_parser("generate", help="randomized projects from a scenario spec",
                       parents=common)
    p.add_argument("spec", help="scenario spec (JSON or YAML, docs/scenarios.md)")
    p.add_argument("--count", type=_int_at_least(1, 100_000), required=True, metavar="N",
                   help="number of projects")
    p.add_argument("--out", required=True, metavar="DIR", help="folder for scene_NNNNN.json")
    p.add_argument("--seed", type=_seed_int, default=0, help="random seed (default 0)")
    p.add_argument("--overwrite", action="store_true", help="replace existing scene files")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    p.add_argument("--run", metavar="OUT",
                   help="then run every project into one dataset OUT (as 'tofradar run DIR')")
    p.add_argument("--frames", type=_frames_int,
                   help="with --run: frames per scene (default: the timeline)")
    p.add_argument("--workers", type=_workers_int, default=1,
                   help="with --run: local worker processes")
    p.add_argument("--scheduler", metavar="ADDRESS", help="with --run: Dask scheduler")
    p.add_argument("--shard-frames", type=_int_at_least(1, 4096), default=16, metavar="K",
                   help="with --run: Zarr frames per shard")
    p.add_argument("--storage-option", action="append", metavar="KEY=VALUE",
                   help="with --run: fsspec storage option of a Zarr URL (repeatable)")
    p.add_argument("--overwrite-run", action="store_true",
                   help="with --run: replace an existing dataset OUT")
    p.add_argument("--resume", action="store_true",
                   help="with --run: continue an interrupted dataset OUT")
    p.add_argument("--force", action="store_true",
                   help="with --run: run even over the memory, disk or time budget")
    p.set_defaults(func=cmd_generate)
