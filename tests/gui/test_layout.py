"""The main window from 1280×720 up: every dock's content visible, colour bars present."""

from __future__ import annotations

import pytest
from PyQt6.QtCore import QRect, Qt
from PyQt6.QtWidgets import QApplication, QDockWidget, QTabBar

from app.main_window import initial_window_size, stage_label

pytestmark = pytest.mark.gui


class _Screen:
    def __init__(self, w: int, h: int):
        self._rect = QRect(0, 0, w, h)

    def availableGeometry(self) -> QRect:  # noqa: N802 - Qt's name
        return self._rect


def test_window_opens_sized_to_the_screen():
    assert initial_window_size(_Screen(1366, 768)).width() == int(1366 * 0.95)
    assert initial_window_size(_Screen(1366, 768)).height() == int(768 * 0.95)
    assert (initial_window_size(_Screen(2560, 1440)).width(),
            initial_window_size(_Screen(2560, 1440)).height()) == (1720, 1020)
    assert initial_window_size(None).width() == 1720


def _visible_rect(widget) -> QRect:
    """The part of ``widget`` that its ancestors leave visible (window coordinates)."""
    rect = QRect(widget.mapTo(widget.window(), widget.rect().topLeft()), widget.size())
    parent = widget.parentWidget()
    while parent is not None:
        top_left = parent.mapTo(parent.window(), parent.rect().topLeft()) \
            if parent is not parent.window() else parent.rect().topLeft()
        rect = rect.intersected(QRect(top_left, parent.size()))
        parent = parent.parentWidget()
    return rect


@pytest.mark.parametrize("size", [(1280, 720), (1366, 768)])
def test_every_dock_is_usable_at_small_screen_sizes(make_window, wait_frame, size):
    window = make_window()
    wait_frame(window)
    window.resize(*size)
    QApplication.processEvents()
    assert (window.width(), window.height()) == size      # no minimum size beyond it
    for name, dock in window.docks.items():
        if not dock.isVisible():
            assert name == "rgb"                          # only shown with an RGB camera
            continue
        dock.raise_()
        QApplication.processEvents()
        content = dock.widget()
        assert content.width() >= 60 and content.height() >= 60, (name, content.size())
    for name, panel in window.panels.items():
        panel.draw_now()
        visible = _visible_rect(panel)
        assert visible.width() >= 200 and visible.height() >= 120, (name, visible)
        bars = [getattr(panel, a) for a in ("bar", "depth_bar", "amp_bar") if hasattr(panel, a)]
        for bar in bars:                                  # colour bars present and drawn
            box = bar.sceneBoundingRect()
            assert box.width() > 10 and box.height() > 40, (name, box)
            view = panel.findChild(type(bar.scene().views()[0]))
            assert view.viewport().rect().contains(view.mapFromScene(box.center()))
        assert panel.info.width() > 50
    # The range profile's units are not cut ("m/s" → "m") and the readout line is there.
    assert window.rd_panel.plot.getAxis("left").labelString().endswith("(m/s)</span>")


def test_reset_layout_brings_docks_back_and_no_stale_tab_bar(make_window):
    window = make_window()
    window.docks["profile"].setFloating(True)
    window.docks["rd"].hide()
    window.removeDockWidget(window.docks["ra"])
    window.reset_layout()
    QApplication.processEvents()
    for name in ("profile", "rd", "ra", "tof", "scene", "inspector", "antennas"):
        dock: QDockWidget = window.docks[name]
        assert dock.isVisible() and not dock.isFloating(), name
    assert window.dockWidgetArea(window.docks["ra"]) == Qt.DockWidgetArea.RightDockWidgetArea
    # No tab bar of the bottom group's earlier forms is drawn over the Inspector.
    inspector = window.docks["inspector"].geometry()
    for bar in window.findChildren(QTabBar):
        if bar.parent() is window and bar.isVisible():
            assert not bar.geometry().intersects(inspector), \
                [bar.tabText(i) for i in range(bar.count())]


def test_status_bar_stage_names_are_words():
    assert stage_label("render_background") == "background"
    assert stage_label("radar_background_prepare") == "background prepare"
    assert "_" not in stage_label("radar_background_label_scatterers")
