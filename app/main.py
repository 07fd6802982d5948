"""Entry point of the desktop GUI: ``tofradar gui [PROJECT]``."""

from __future__ import annotations

import sys
from pathlib import Path


def main(project_path: str | Path | None = None) -> int:
    """Open the main window (on ``project_path`` if given) and run the event loop.

    Returns
    -------
    int
        The application's exit status.
    """
    from PyQt6.QtWidgets import QApplication

    from app.dialogs.help import maybe_show_first_run_guide
    from app.main_window import MainWindow
    from app.theme import apply_dark_theme

    app = QApplication.instance() or QApplication(sys.argv[:1])
    app.setApplicationName("tofradar")
    app.setOrganizationName("tofradar")
    apply_dark_theme(app)  # type: ignore[arg-type]
    window = MainWindow(project_path)
    window.show()
    maybe_show_first_run_guide(window, window.settings)
    return int(app.exec())


if __name__ == "__main__":
    sys.exit(main(sys.argv[1] if len(sys.argv) > 1 else None))
