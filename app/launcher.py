"""The ``tofradar`` console script: the core command line plus the GUI launcher.

Qt is imported only when the ``gui`` command runs, so headless commands stay light and
work on an install without the ``[gui]`` extra.
"""

from __future__ import annotations

import sys
from collections.abc import Sequence
from importlib.util import find_spec

#: Packages the GUI needs beyond the core (the ``tofradar[gui]`` extra).
GUI_PACKAGES = ("PyQt6", "pyvista", "pyvistaqt", "pyqtgraph")


def missing_gui_packages() -> list[str]:
    """The GUI packages that are not installed (found without importing them)."""
    return [name for name in GUI_PACKAGES if find_spec(name) is None]


def launch_gui(project: str | None) -> int:
    """Open the main window (imports Qt)."""
    from app.main import main as gui_main

    return int(gui_main(project))


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``tofradar`` console script."""
    from simcore.cli import main as cli_main

    args = list(sys.argv[1:] if argv is None else argv)
    if (not args or args[0] == "gui") and missing_gui_packages():
        print(f"tofradar: error: the GUI is not installed (missing "
              f"{', '.join(missing_gui_packages())}); install it with: "
              "pip install 'tofradar[gui]'", file=sys.stderr)
        return 2
    return cli_main(args, gui_launcher=launch_gui)


if __name__ == "__main__":
    sys.exit(main())
