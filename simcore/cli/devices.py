"""``tofradar devices``: the device library's radars and ToF cameras."""

from __future__ import annotations

import argparse

from simcore.cli.common import (
    _Parser,
)


def cmd_devices(args: argparse.Namespace) -> int:
    """List the device library's radars and cameras with their key figures."""
    from simcore.scene.devices import devices_table

    print("\n".join(devices_table()))
    return 0


def add_parser(sub: argparse._SubParsersAction[_Parser], common: list[_Parser]) -> None:
    """The ``devices`` subcommand."""
    p = sub.add_parser("devices", help="list the device library (radars and ToF cameras) "
                       "with their key figures", parents=common)
    p.set_defaults(func=cmd_devices)
