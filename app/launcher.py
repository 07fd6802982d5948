"""The ``tofradar`` console script: the core command line plus the GUI launcher.

Qt is imported only when the ``gui`` command runs, so headless commands stay light.
"""

from __future__ import annotations

import sys
from collections.abc import Sequence


def launch_gui(project: str | None) -> int:
    """Open the main window (imports Qt)."""
    from app.main import main as gui_main

    return int(gui_main(project))


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``tofradar`` console script."""
    from simcore.cli import main as cli_main

    return cli_main(argv, gui_launcher=launch_gui)


if __name__ == "__main__":
    sys.exit(main())
