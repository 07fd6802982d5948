"""``tofradar report``: regenerate the validation report."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from simcore.cli.common import (
    _common,
    _Parser,
)


def cmd_report(args: argparse.Namespace) -> int:
    """Regenerate the validation report (figures + README.md)."""
    from simcore.report import generate_report

    def say(message: str) -> None:
        if not args.quiet:
            print(f"  {message}", file=sys.stderr)

    result = generate_report(Path(args.out), quick=args.quick, progress=say)
    print(f"wrote {len(result.figures)} figures and README.md to {result.out_dir}")
    return 0


def add_parser(sub: argparse._SubParsersAction[_Parser], common: list[_Parser]) -> None:
    """The ``report`` subcommand."""
    p = sub.add_parser("report", help="regenerate the validation report with figures",
                       parents=[_common()])
    p.add_argument("--out", default="docs/validation", help="output directory")
    p.add_argument("--quick", action="store_true", help="fewer frames (for tests)")
    p.add_argument("--quiet", action="store_true", help="no progress messages")
    p.set_defaults(func=cmd_report)
