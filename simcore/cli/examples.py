"""``tofradar examples``: list or copy the bundled example projects."""

from __future__ import annotations

import argparse
from pathlib import Path

from simcore.cli.common import (
    CliError,
    _common,
    _Parser,
)


def cmd_examples(args: argparse.Namespace) -> int:
    """List the bundled example projects, or copy them (with meshes) into a folder."""
    from simcore.examples import ExamplesError, copy_examples, list_examples

    if args.copy is None:
        for example in list_examples():
            print(f"{example.name + '.json':<28} {example.summary}")
        print("copy them into a folder with: tofradar examples --copy DIR")
        return 0
    try:
        written = copy_examples(Path(args.copy))
    except ExamplesError as exc:
        raise CliError(str(exc)) from None
    print(f"copied {len(written)} files to {args.copy}")
    return 0


def add_parser(sub: argparse._SubParsersAction[_Parser], common: list[_Parser]) -> None:
    """The ``examples`` subcommand."""
    p = sub.add_parser("examples", help="list the bundled example projects or copy them",
                       parents=[_common()])
    p.add_argument("--copy", metavar="DIR", help="copy them (with their meshes) into DIR")
    p.set_defaults(func=cmd_examples)
