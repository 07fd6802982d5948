"""The Help menu: getting started, keyboard shortcuts, documentation, About.

``install_help_menu(window, menu)`` fills a main window's Help menu; the pages are plain
HTML in non-modal dialogs, so they can stay open beside the window.
"""

from __future__ import annotations

import html
from pathlib import Path

from PyQt6.QtCore import QSettings, Qt, QUrl
from PyQt6.QtGui import QAction, QDesktopServices
from PyQt6.QtWidgets import (
    QDialog,
    QDialogButtonBox,
    QMainWindow,
    QMenu,
    QMessageBox,
    QTextBrowser,
    QVBoxLayout,
    QWidget,
)

import simcore

#: The documentation pages: file in ``docs/`` → title.
DOC_PAGES = {
    "gui.md": "The desktop GUI",
    "architecture.md": "Architecture",
    "physics.md": "Physics overview",
    "physics_tof.md": "ToF camera model",
    "physics_radar.md": "Radar model",
    "dsp.md": "Radar processing (DSP)",
    "dataset.md": "Datasets (HDF5)",
    "performance.md": "Performance",
}

#: Shortcuts that are not actions of the window (widgets handle them).
EXTRA_SHORTCUTS = [
    ("Del", "Delete the selected object (in the scene list or the 3D view)"),
    ("R", "Reset the 3D camera"),
    ("Left-drag / right-drag / wheel / middle-drag", "3D view: orbit / zoom / zoom / pan"),
    ("Click", "Antenna board: bring the element below a stack to the top"),
]

FIRST_RUN_GUIDE = """
<h2>Getting started with tofradar</h2>
<p>tofradar simulates an AMCW time-of-flight camera and an FMCW radar looking at one 3D
scene. Everything you see in the panels is what the batch pipeline computes for the same
project file.</p>
<ol>
<li><b>Open an example</b>: <i>File → Open example → office</i>. Examples are templates:
<i>Save</i> asks where to put your copy.</li>
<li><b>Look around</b> in the 3D view (left-drag orbits, wheel zooms, <b>R</b> resets).
The green frustum is the ToF camera's field of view, the orange one the radar's.</li>
<li><b>Move things</b>: click an object, drag the gizmo's arrows and rings, or type exact
values in the <i>Inspector</i>. <i>Edit → Add</i> puts new objects in front of the
sensors, facing them.</li>
<li><b>Watch the sensors</b>: the ToF depth and amplitude images, the range profile,
range–Doppler and range–azimuth maps on the right update after every edit.</li>
<li><b>Explore the antenna array</b> in the <i>Antenna array</i> tab: drag Tx and Rx
elements, apply layouts, and read the beam pattern and grating lobes beside the board.</li>
<li><b>Set the time span</b> and the random seed in <i>Timeline and seed</i>; press
<b>Space</b> to play.</li>
<li><b>Export</b> a dataset (<i>File → Export dataset</i>) with the same frames.</li>
</ol>
<p>Every edit can be undone (<b>Ctrl+Z</b>). <i>Help → Keyboard shortcuts</i> lists the
keys.</p>
"""


def docs_folder() -> Path | None:
    """The documentation folder of a source checkout (``None`` in an installed wheel)."""
    folder = Path(__file__).resolve().parents[2] / "docs"  # app/dialogs/help.py → checkout
    return folder if (folder / "gui.md").is_file() else None


def shortcut_rows(window: QMainWindow) -> list[tuple[str, str]]:
    """(keys, what) of every window action with a shortcut, then the widget shortcuts."""
    rows = []
    seen = set()
    for action in window.actions():
        keys = [s.toString(s.SequenceFormat.NativeText) for s in action.shortcuts()]
        keys = [k for k in keys if k]
        text = action.text().replace("&", "").rstrip("…").strip()
        if keys and text and (text, tuple(keys)) not in seen:
            seen.add((text, tuple(keys)))
            rows.append((" or ".join(keys), text))
    rows.sort(key=lambda r: r[1].lower())
    return rows + EXTRA_SHORTCUTS


def shortcut_sheet_html(window: QMainWindow) -> str:
    """The keyboard shortcuts as an HTML table."""
    body = "".join(f"<tr><td><b>{html.escape(k)}</b></td><td>{html.escape(w)}</td></tr>"
                   for k, w in shortcut_rows(window))
    return (f"<h2>Keyboard shortcuts</h2><table cellspacing='0' cellpadding='4'>{body}"
            "</table>")


def about_text() -> str:
    """The About box's text, with the version."""
    return (f"<h3>tofradar {html.escape(simcore.__version__)}</h3>"
            "<p>Synchronised AMCW time-of-flight camera and FMCW radar simulation from one 3D "
            "scene: renders, sensor physics, radar DSP and HDF5 datasets.</p>"
            "<p>Command line: <code>tofradar run</code>, <code>tofradar gui</code>.</p>")


class HelpPage(QDialog):
    """A non-modal page of rich text with a Close button."""

    def __init__(self, title: str, body_html: str, parent: QWidget | None = None):
        super().__init__(parent)
        self.setWindowTitle(title)
        self.setAttribute(Qt.WidgetAttribute.WA_DeleteOnClose)
        layout = QVBoxLayout(self)
        self.browser = QTextBrowser()
        self.browser.setOpenExternalLinks(True)
        self.browser.setHtml(body_html)
        layout.addWidget(self.browser)
        buttons = QDialogButtonBox(QDialogButtonBox.StandardButton.Close)
        buttons.rejected.connect(self.close)
        layout.addWidget(buttons)
        self.resize(620, 560)


def open_doc(name: str) -> bool:
    """Open ``docs/<name>`` with the desktop's viewer; False when there are no docs."""
    folder = docs_folder()
    if folder is None or not (folder / name).is_file():
        return False
    return QDesktopServices.openUrl(QUrl.fromLocalFile(str(folder / name)))


def install_help_menu(window: QMainWindow, menu: QMenu) -> dict[str, QAction]:
    """Fill ``menu`` with Getting started, Keyboard shortcuts, Documentation and About.

    Returns the actions by key ("guide", "shortcuts", "about", and "doc:<file>") so that
    tests can trigger them. The last page opened is kept as ``window.help_page``.
    """
    actions: dict[str, QAction] = {}

    def show(title: str, body: str) -> None:
        page = HelpPage(title, body, window)
        window.help_page = page  # type: ignore[attr-defined]
        page.show()

    actions["guide"] = menu.addAction("&Getting started")
    actions["guide"].triggered.connect(lambda: show("Getting started", FIRST_RUN_GUIDE))
    actions["shortcuts"] = menu.addAction("&Keyboard shortcuts")
    actions["shortcuts"].setShortcut("F1")
    actions["shortcuts"].triggered.connect(
        lambda: show("Keyboard shortcuts", shortcut_sheet_html(window)))
    docs = menu.addMenu("&Documentation")
    folder = docs_folder()
    for name, title in DOC_PAGES.items():
        act = docs.addAction(title)
        act.setToolTip(f"docs/{name}")
        act.setEnabled(folder is not None and (folder / name).is_file())
        act.triggered.connect(lambda _=False, n=name: open_doc(n))
        actions[f"doc:{name}"] = act
    if folder is None:
        docs.addAction("(the documentation is in the source repository's docs/ folder)"
                       ).setEnabled(False)
    menu.addSeparator()
    actions["about"] = menu.addAction("&About tofradar")
    actions["about"].triggered.connect(
        lambda: QMessageBox.about(window, "About tofradar", about_text()))
    window.addAction(actions["shortcuts"])
    return actions


def maybe_show_first_run_guide(window: QMainWindow, settings: QSettings) -> bool:
    """Show the Getting started page on the first start only; True when shown."""
    if settings.value("help/first_run_done", False, type=bool):
        return False
    settings.setValue("help/first_run_done", True)
    page = HelpPage("Getting started", FIRST_RUN_GUIDE, window)
    window.help_page = page  # type: ignore[attr-defined]
    page.show()
    return True
