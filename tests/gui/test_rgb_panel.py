"""The RGB camera's panel: shown with the camera, drawing the frame's colour image."""

from __future__ import annotations

import numpy as np
import pytest

from simcore.resources import example_path

pytestmark = pytest.mark.gui


def test_rgb_panel_follows_the_rig(make_window, wait_frame, qtbot):
    window = make_window(example_path("office_rgb"))
    wait_frame(window)
    dock = window.docks["rgb"]
    assert dock.isVisibleTo(window)
    dock.raise_()
    qtbot.waitUntil(lambda: window.rgb_panel.draw_count > 0, timeout=30_000)
    shown = window.rgb_panel.image.image
    assert shown.shape == (480, 640, 3)
    np.testing.assert_array_equal(shown, window.last_view.rgb)
    # Removing the camera from the rig hides the panel; the frames go on without it.
    window.document.set_value("rig.rgb", None)
    wait_frame(window)
    assert not dock.isVisibleTo(window)
    assert window.last_view.rgb is None


def test_no_rgb_panel_without_the_camera(make_window, wait_frame):
    window = make_window(example_path("office"))
    wait_frame(window)
    assert not window.docks["rgb"].isVisibleTo(window)
