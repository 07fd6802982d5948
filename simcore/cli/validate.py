"""``tofradar validate``: check a project file as ``run`` would."""

from __future__ import annotations

import argparse
from pathlib import Path

from simcore.cli.common import (
    _Parser,
    _preflight,
)
from simcore.scene.model import sensor_kind
from simcore.scene.project_io import ProjectError, load_project


def cmd_validate(args: argparse.Namespace) -> int:
    """Check a project file as ``run`` would; print OK and the cost, or every problem."""
    from simcore.scene.devices import project_limit_problems

    project = load_project(args.project)
    cost = _preflight(project, Path(args.project), args)
    device_problems, device_notes = project_limit_problems(project)
    if device_problems:
        raise ProjectError(args.project, device_problems)
    print(f"OK: {args.project} ({len(project.objects)} objects, format_version "
          f"{project.format_version}); {cost.describe()}")
    for note in device_notes:
        print(f"  note: {note}")
    rigs = project.all_rigs()
    if len(rigs) > 1 or project.rig.sensors:
        # Several sensors: each with its kind, rig and timing.
        rate = project.timeline.frame_rate_hz
        for name, cfg in project.sensor_configs().items():
            every = cfg.frame_divider(rate)  # type: ignore[attr-defined]
            offset = cfg.trigger_offset_s  # type: ignore[attr-defined]
            print(f"  {name}: {sensor_kind(cfg)} on rig {project.sensor_rig(name).name!r}, "
                  f"{rate / every:g} frames/s (every {every} frame{'s' if every > 1 else ''})"
                  f"{f', {offset * 1e3:g} ms after the frame' if offset else ''}")
    return 0


def add_parser(sub: argparse._SubParsersAction[_Parser], common: list[_Parser]) -> None:
    """The ``validate`` subcommand."""
    p = sub.add_parser("validate", help="check a project file as 'run' would", parents=common)
    p.add_argument("project", help="project JSON file")
    p.set_defaults(func=cmd_validate)
