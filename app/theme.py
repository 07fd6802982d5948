"""A dark Fusion theme for the application (engineering-tool look)."""

from __future__ import annotations

from PyQt6.QtGui import QColor, QPalette
from PyQt6.QtWidgets import QApplication

STYLE_SHEET = """
QMainWindow::separator { background: #2a2f36; width: 4px; height: 4px; }
QDockWidget { font-weight: bold; }
QDockWidget::title { background: #2a2f36; padding: 3px 6px; text-align: left; }
QGroupBox { border: 1px solid #3a414b; border-radius: 4px; margin-top: 14px; padding-top: 4px; }
QGroupBox::title { subcontrol-origin: margin; left: 8px; padding: 0 4px; color: #8fb4d9; }
QToolBar { spacing: 4px; border: none; }
QStatusBar QLabel { padding: 0 6px; }
QTabBar::tab { padding: 4px 10px; }
QSlider::groove:horizontal { height: 6px; background: #3a414b; border-radius: 3px; }
QSlider::sub-page:horizontal { background: #2f6fb0; border-radius: 3px; }
QSlider::handle:horizontal { background: #8fb4d9; width: 12px; margin: -4px 0;
                             border-radius: 6px; }
"""


def apply_dark_theme(app: QApplication) -> None:
    """Fusion style with a dark palette and a few style-sheet touches."""
    app.setStyle("Fusion")
    pal = QPalette()
    base, window, text = QColor("#1b1f24"), QColor("#23272e"), QColor("#d6dae0")
    pal.setColor(QPalette.ColorRole.Window, window)
    pal.setColor(QPalette.ColorRole.WindowText, text)
    pal.setColor(QPalette.ColorRole.Base, base)
    pal.setColor(QPalette.ColorRole.AlternateBase, QColor("#262b32"))
    pal.setColor(QPalette.ColorRole.ToolTipBase, QColor("#2f353d"))
    pal.setColor(QPalette.ColorRole.ToolTipText, text)
    pal.setColor(QPalette.ColorRole.Text, text)
    pal.setColor(QPalette.ColorRole.Button, QColor("#2c323a"))
    pal.setColor(QPalette.ColorRole.ButtonText, text)
    pal.setColor(QPalette.ColorRole.BrightText, QColor("#ff6b6b"))
    pal.setColor(QPalette.ColorRole.Highlight, QColor("#2f6fb0"))
    pal.setColor(QPalette.ColorRole.HighlightedText, QColor("#ffffff"))
    pal.setColor(QPalette.ColorRole.Link, QColor("#6cb6ff"))
    pal.setColor(QPalette.ColorGroup.Disabled, QPalette.ColorRole.Text, QColor("#6b737d"))
    pal.setColor(QPalette.ColorGroup.Disabled, QPalette.ColorRole.ButtonText, QColor("#6b737d"))
    pal.setColor(QPalette.ColorGroup.Disabled, QPalette.ColorRole.WindowText, QColor("#6b737d"))
    app.setPalette(pal)
    app.setStyleSheet(STYLE_SHEET)
