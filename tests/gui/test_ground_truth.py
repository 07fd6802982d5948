"""Ground-truth overlays, linked selection, A/B comparison and the processed range profile.

Known answers: the marks sit where the frame's ground truth puts each object, a clicked
detection selects the object its label names, a +10 dB Tx power edit shows as +10 dB at
the targets in the difference view.
"""

from __future__ import annotations

import numpy as np
import pytest
from numpy.testing import assert_allclose, assert_array_equal
from PyQt6.QtCore import QPointF, Qt

from app.panels.base import OUTLINE_RGBA, OUTLINE_SELECTED_RGBA, SELECTED_PEN, object_outlines
from simcore.resources import example_path

pytestmark = pytest.mark.gui


def test_outlines_trace_object_borders_and_the_selected_one_in_yellow():
    ids = np.full((6, 8), -1, dtype=np.int32)
    ids[1:5, 1:4] = 7
    ids[1:5, 4:7] = 9
    out = object_outlines(ids, selected_id=9)
    edge = out[..., 3] > 0
    # Interior pixels and the background carry no outline; every border pixel does.
    assert not edge[0].any() and not edge[:, 0].any()
    assert not edge[2:4, 2].any() and not edge[2:4, 5].any()
    assert edge[1, 1:7].all() and edge[4, 1:7].all() and edge[1:5, 3].all() and edge[1:5, 4].all()
    assert tuple(out[2, 1]) == OUTLINE_RGBA            # object 7's left border
    assert tuple(out[2, 4]) == OUTLINE_SELECTED_RGBA   # object 9 (selected) at the seam
    assert tuple(out[2, 6]) == OUTLINE_SELECTED_RGBA


def test_truth_marks_sit_at_each_objects_true_range_velocity_and_azimuth(make_window,
                                                                        wait_frame):
    window = make_window(example_path("point_targets"))
    wait_frame(window)
    view = window.last_view
    marks = view.objects
    assert marks is not None
    assert_array_equal(marks.object_id, [o.id for o in window.document.project.objects])
    for panel in window.panels.values():
        panel.draw_now()
    rd = window.rd_panel
    x, y = rd.truth.getData()
    assert_allclose(np.sort(x), np.sort(marks.range_m))
    assert_allclose(y[np.argsort(x)], marks.radial_velocity_mps[np.argsort(marks.range_m)])
    ra = window.ra_panel
    x, y = ra.truth.getData()
    az = np.rad2deg(np.arctan2(x, y))
    assert_allclose(np.sort(az), np.sort(marks.azimuth_deg), atol=1e-9)
    prof = window.profile_panel
    lines = sorted(line.value() for line in prof.truth_lines if line.isVisible())
    assert_allclose(lines, np.sort(marks.range_m))
    assert {t.toPlainText() for t in rd.truth_labels if t.isVisible()} == {
        "corner_1", "corner_2", "corner_3"}
    # Each reflector's strongest detection lies within a range bin of its true range.
    det = view.radar.detections
    bin_m = view.radar.range_axis_m[1] - view.radar.range_axis_m[0]
    for oid, rng in zip(marks.object_id, marks.range_m, strict=True):
        mine = det.range_m[det.object_id == oid]
        assert mine.size and np.min(np.abs(mine - rng)) < 1.5 * bin_m
    # The ToF outlines come from the frame's ground-truth id image.
    tof = window.tof_panel
    assert view.tof.gt_object_id is not None
    assert_array_equal(tof.outlines, object_outlines(view.tof.gt_object_id, None))
    window.truth_action.trigger()                       # View → Show ground truth off
    assert len(rd.truth.getData()[0]) == 0
    assert not any(line.isVisible() for line in prof.truth_lines)
    assert not tof.depth_outline.isVisible()


def test_clicking_a_detection_selects_its_object_and_says_what_it_measured(make_window,
                                                                          wait_frame, qtbot):
    window = make_window(example_path("point_targets"))
    wait_frame(window)
    det = window.last_view.radar.detections
    k = int(np.argmax(det.snr_db))
    target = int(det.object_id[k])
    assert target >= 0
    rd = window.rd_panel
    rd.draw_now()
    qtbot.waitUntil(lambda: rd.plot.sceneBoundingRect().height() > 50, timeout=5000)
    scene = rd.plot.vb.mapViewToScene(QPointF(float(det.range_m[k]), float(det.velocity_mps[k])))
    pos = rd.graphics.mapFromScene(scene)
    qtbot.mouseClick(rd.graphics.viewport(), Qt.MouseButton.LeftButton, pos=pos)
    qtbot.waitUntil(lambda: window.document.selection == target, timeout=5000)
    info = window.detection_info
    assert f"SNR {det.snr_db[k]:.1f} dB" in info and f"range {det.range_m[k]:.3f} m" in info
    assert "azimuth" in info and "elevation" in info
    name = next(o.name for o in window.document.project.objects if o.id == target)
    assert info.endswith(name) and rd.readout.text() == info
    # Selecting the object highlights its returns (yellow pens) and only those.
    pens = [p.pen().color().name() for p in rd.markers.points()]
    expected = [SELECTED_PEN.color().name() if i == target else "#ffffff"
                for i in det.object_id]
    assert pens == expected
    window.document.select(None)
    assert {p.pen().color().name() for p in rd.markers.points()} == {"#ffffff"}


def test_freeze_then_edit_shows_the_difference(make_window, wait_frame):
    window = make_window(example_path("point_targets"))
    wait_frame(window)
    prof = window.profile_panel
    prof.draw_now()
    before = prof.profile_db.copy()
    window.freeze_reference()
    assert window.difference_action.isEnabled()
    power = window.document.project.rig.radar.tx_power_dbm
    window.document.set_value("rig.radar.tx_power_dbm", power + 10.0)
    wait_frame(window)
    window.difference_action.trigger()
    for panel in window.comparable_panels():
        panel.draw_now()
        assert panel.show_difference
    r, delta = prof.difference_curve.getData()
    strong = before > np.max(before) - 10.0            # the reflectors' peaks
    assert strong.any()
    assert_allclose(delta[strong], 10.0, atol=0.5)
    rd = window.rd_panel
    rd_ref = rd.reference.radar.range_doppler_db
    assert_allclose(rd.image.image, window.last_view.radar.range_doppler_db - rd_ref,
                    atol=1e-4)
    assert rd.bar.getAxis("left").labelText == "A − B (dB)"
    window.difference_action.trigger()
    assert not rd.show_difference
    assert_allclose(rd.image.image, window.last_view.radar.range_doppler_db)


def test_range_profile_and_its_threshold_are_on_one_scale(make_window, wait_frame):
    """With static clutter removal the profile no longer floats 30–40 dB above the threshold."""
    window = make_window()
    wait_frame(window)
    window.document.set_value("dsp.static_clutter_removal", True)
    wait_frame(window)
    prof = window.profile_panel
    prof.draw_now()
    radar = window.last_view.radar
    expected = 10 * np.log10(np.mean(10 ** (radar.range_doppler_db / 10), axis=0))
    assert_allclose(prof.profile_db, expected, atol=1e-3)
    above = prof.profile_db > prof.threshold_db
    assert above.mean() < 0.05                          # noise stays under its threshold
    assert "processed" in prof.plot.titleLabel.text
    assert not prof.curves                              # raw spectra only on request
    prof.raw_box.setChecked(True)
    assert [c.name() for c in prof.curves] == [f"{n} raw" for n in radar.channel_names]
