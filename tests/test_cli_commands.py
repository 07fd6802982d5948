"""The command line is a table of commands, one module each (simcore/cli/parser.py)."""

from __future__ import annotations

import argparse

from simcore.cli import build_parser
from simcore.cli.parser import COMMANDS


def test_each_row_of_the_table_is_one_subcommand_run_by_its_own_module():
    parser = build_parser()
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    assert list(sub.choices) == [name for name, _ in COMMANDS]
    for name, module in COMMANDS:
        func = sub.choices[name].get_default("func")
        assert func.__module__ == module and func.__name__.startswith("cmd_"), (name, func)

