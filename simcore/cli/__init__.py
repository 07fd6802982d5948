"""The ``tofradar`` command line: one module per command, registered in one table.

``parser.py`` holds the table of commands (:data:`~simcore.cli.parser.COMMANDS`),
:func:`build_parser` and :func:`main`; ``common.py`` what the commands share (one-line
errors, argument types, preflight, disk and time checks); every other module is one
command (``run.py`` is ``tofradar run``), with its ``add_parser(sub, common)`` and its
``cmd_*`` function.

The command line is the top layer of :mod:`simcore`: it may import any other part of
it (runs, report, bench, io, pipeline, scene …), and nothing in :mod:`simcore` imports it.
It never imports the GUI: ``app`` passes its launcher to :func:`main`.
"""

from simcore.cli.common import CliError
from simcore.cli.parser import build_parser, main

__all__ = ["CliError", "build_parser", "main"]
