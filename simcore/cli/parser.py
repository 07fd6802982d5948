"""The ``tofradar`` parser: a table of commands, each a module of :mod:`simcore.cli`.

A command module ``simcore/cli/NAME.py`` provides ``add_parser(sub, common)``, which adds its
subparser and sets ``func`` to its ``cmd_*`` function. A new command is a new module and one
row of :data:`COMMANDS`.
"""

from __future__ import annotations

import argparse
import importlib
import os
import sys
import warnings
from collections.abc import Callable, Sequence

from simcore import __version__
from simcore.cli.common import _common, _Parser, _report_error

#: The subcommands in the order ``tofradar --help`` lists them: (name, module path).
COMMANDS = (
    ("gui", "simcore.cli.gui"),
    ("run", "simcore.cli.run"),
    ("generate", "simcore.cli.generate"),
    ("sweep", "simcore.cli.sweep"),
    ("report", "simcore.cli.report"),
    ("convert", "simcore.cli.convert"),
    ("serve", "simcore.cli.serve"),
    ("products", "simcore.cli.products"),
    ("import", "simcore.cli.import_scene"),
    ("devices", "simcore.cli.devices"),
    ("validate", "simcore.cli.validate"),
    ("bench", "simcore.cli.bench"),
    ("materials", "simcore.cli.materials"),
    ("examples", "simcore.cli.examples"),
)


def build_parser() -> argparse.ArgumentParser:
    """The argument parser of the ``tofradar`` command."""
    parser = _Parser(
        prog="tofradar", parents=[_common(debug_only=True)],
        description="Synchronized AMCW ToF camera and FMCW radar simulation from one 3D scene.",
    )
    parser.add_argument("--version", action="version", version=f"%(prog)s {__version__}")
    sub = parser.add_subparsers(dest="command")
    common = [_common()]
    for _name, module in COMMANDS:
        importlib.import_module(module).add_parser(sub, common)
    return parser


def main(argv: Sequence[str] | None = None, *,
         gui_launcher: Callable[[str | None], int] | None = None) -> int:
    """Run the ``tofradar`` command line.

    ``gui_launcher(project_path_or_None)`` opens the GUI; the ``app`` package passes it
    (the core never imports the GUI). Every error ends as one line
    ``tofradar: error: …`` on stderr and a non-zero exit status; ``--debug`` raises it
    with its traceback instead.
    """
    parser = build_parser()
    args = parser.parse_args(argv)
    if args.command is None:
        args = parser.parse_args(["gui", *(argv or [])])
    args.gui_launcher = gui_launcher
    debug = args.debug or getattr(args, "debug_global", False)
    if not debug:
        # Numerical warnings are not messages for the user (the outputs are checked); worker
        # processes inherit the setting through the environment.
        warnings.simplefilter("ignore", RuntimeWarning)
        os.environ.setdefault("PYTHONWARNINGS", "ignore::RuntimeWarning")
    try:
        return int(args.func(args))
    except KeyboardInterrupt:
        print("tofradar: interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:
        # The reader of the output went away (``tofradar materials | head``): not an error.
        # Point stdout at /dev/null so the interpreter's final flush does not complain.
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 0
    except Exception as exc:  # noqa: BLE001 — the one top-level error path
        if debug:
            raise
        return _report_error(exc)
