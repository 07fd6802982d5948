"""The ``tofradar`` command line (being split into one module per command)."""

from simcore.cli.parser import *  # noqa: F403
from simcore.cli.parser import main

__all__ = ["main"]
