"""Detections coloured by their ground-truth object on request (View menu)."""

from __future__ import annotations

import numpy as np
import pytest

from app.panels.base import NOISE_BRUSH, label_brush
from simcore.resources import example_path

pytestmark = pytest.mark.gui


def test_detections_take_their_objects_colour(make_window, wait_frame, qtbot):
    window = make_window(example_path("point_targets"))
    wait_frame(window)
    det = window.last_view.radar.detections
    assert det.object_id is not None and len(det.object_id) == len(det)
    corners = {o.id for o in window.document.project.objects}
    assert set(det.object_id.tolist()) <= corners      # every detection is a reflector
    window.label_colours_action.trigger()
    assert window.rd_panel.colour_by_label
    qtbot.waitUntil(lambda: window.rd_panel.draw_count > 0, timeout=30_000)
    brushes = [p.brush().color().getRgb() for p in window.rd_panel.markers.points()]
    expected = [label_brush(int(i)).color().getRgb() for i in det.object_id]
    assert brushes == expected
    assert len(set(brushes)) == len(set(det.object_id.tolist()))
    assert NOISE_BRUSH.color().getRgb() not in brushes
    window.label_colours_action.trigger()
    plain = {p.brush().color().getRgb() for p in window.rd_panel.markers.points()}
    assert len(plain) == 1
    np.testing.assert_array_equal(det.range_m, window.last_view.radar.detections.range_m)
