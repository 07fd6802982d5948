"""``tofradar gui``: open the desktop GUI (the default command)."""

from __future__ import annotations

import argparse
import os

from simcore.cli.common import (
    CliError,
    _Parser,
)
from simcore.scene.project_io import load_project


def cmd_gui(args: argparse.Namespace) -> int:
    """Open the desktop GUI through the launcher the ``app`` package registered."""
    if args.gui_launcher is None:
        raise CliError("the GUI is not available from this entry point; run 'tofradar gui'")
    if not (os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY")):
        raise CliError("no display found (DISPLAY is not set); the GUI needs one. "
                       "Use 'tofradar run PROJECT --out FILE.h5' for headless work.")
    if args.project:
        load_project(args.project)  # report a bad file here, before Qt starts
    return int(args.gui_launcher(args.project))


def add_parser(sub: argparse._SubParsersAction[_Parser], common: list[_Parser]) -> None:
    """The ``gui`` subcommand."""
    p = sub.add_parser("gui", help="open the desktop GUI (default)", parents=common)
    p.add_argument("project", nargs="?", help="project file to open")
    p.set_defaults(func=cmd_gui)
