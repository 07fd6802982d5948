"""Bad values, failing panels and long frames never leave the window stale or stuck."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from PyQt6.QtCore import QTimer

from app.widgets.inputs import field_error

pytestmark = pytest.mark.gui


def _assert_playback_goes_on(window, qtbot, frames: int = 2) -> None:
    """Playing shows ``frames`` new frames (the timeline is not stuck)."""
    shown: list[int] = []
    window.sim.frameReady.connect(lambda v: shown.append(v.index))
    start = window.time.index
    window.time.set_playing(True)
    try:
        qtbot.waitUntil(lambda: len(set(shown) - {start}) >= frames, timeout=60_000)
    finally:
        window.time.set_playing(False)


def _assert_panels_current(window, wait_frame) -> None:
    wait_frame(window)
    for name, panel in window.panels.items():
        assert panel.error is None, f"{name}: {panel.error}"
        # A hidden panel (the RGB camera without an RGB camera on the rig) keeps the frame
        # to draw when shown.
        current = panel.view if panel.isVisible() else panel._pending or panel.view
        assert current is window.last_view, f"{name} shows an older frame"


@pytest.mark.parametrize(("field", "value", "words"), [
    ("bandwidth_hz", 150.0, "bandwidth"),
    ("start_frequency_hz", 1.0, "start frequency"),
    ("chirps", 0, "Chirps / frame must be at least 1 (got 0)"),
    ("chirps", 1_000_000_000, "Chirps / frame must be at most 1024"),
    ("chirp_time_s", 500.0, "chirp repetition time (300.0 µs) is shorter than chirp time"),
])
def test_invalid_radar_value_is_refused_at_the_field(make_window, wait_frame, qtbot, field,
                                                     value, words):
    window = make_window()
    wait_frame(window)
    editor = window.sensor_editor
    widget = editor.chirps if field == "chirps" else editor.radar_widgets[field]
    doc = window.document
    before, steps = doc.project, doc.undo_stack.count()
    widget.setValue(value)  # what Enter or focus-out commits
    message = field_error(widget)
    assert message is not None and words in message, message
    assert "{" not in message, "no JSON in the message"
    assert widget.value() == pytest.approx(value), "no silent clamp: the value stays shown"
    assert doc.project is before and doc.undo_stack.count() == steps, "no undo step"
    label = widget.property("errorLabel")
    assert label is not None and label.isVisible() and words in label.text()
    _assert_panels_current(window, wait_frame)
    _assert_playback_goes_on(window, qtbot)
    # A valid value clears the mark.
    editor.refresh()
    assert field_error(widget) is None and not label.isVisible()


def test_huge_tof_needs_confirmation_or_is_refused(make_window, wait_frame, qtbot):
    """The office's ToF camera (224 × 171, 2× supersampling) grown one field at a time, with
    the memory budget pinned (it was 80 % of whatever memory was free, so whether the big
    camera was refused or offered depended on the machine's load): 4096 rows (≈ 1.5 GiB a
    frame) is applied; 4096 columns (≈ 17.1 GiB, ≈ 4.1 s a frame) is under a 32 GiB budget
    but over the confirmation limits, so it is offered and, declined, not applied; 8×
    supersampling breaks the per-axis render limit; and under a 16 GiB budget 4000 columns
    (≈ 16.7 GiB) is refused outright, without asking. Undo then takes back the rows, and
    the panels and playback go on."""
    window = make_window()
    wait_frame(window)
    window.memory_budget_bytes = lambda: 32 * 2**30
    asked = []

    def decline(cost):
        asked.append(cost)
        return False

    window.confirm_costly = decline
    editor = window.sensor_editor
    doc = window.document

    def edit(widget, value: int) -> str | None:
        steps = doc.undo_stack.count()
        widget.setValue(value)
        message = field_error(widget)
        if message is None:  # accepted: a cheap enough configuration, one undo step
            assert doc.undo_stack.count() == steps + 1
        else:
            assert doc.undo_stack.count() == steps, "a refused value is no undo step"
            assert "{" not in message, message
        return message

    assert edit(editor.tof_height, 4096) is None
    declined = edit(editor.tof_width, 4096)
    assert declined is not None and "not applied (declined)" in declined, declined
    assert "17.1 GiB" in declined, declined
    assert len(asked) == 1 and 17 * 2**30 < asked[0].memory_bytes < 17.2 * 2**30, asked
    too_fine = edit(editor.tof_ss, 8)
    assert too_fine is not None and "at most 16384 per axis" in too_fine, too_fine
    window.memory_budget_bytes = lambda: 16 * 2**30
    over = edit(editor.tof_width, 4000)
    assert over is not None and "over the budget of 16.0 GiB" in over, over
    assert "rig.tof render" in over, over
    assert len(asked) == 1, "a frame over the budget is not offered for confirmation"
    tof = doc.project.rig.tof
    assert (tof.height, tof.width, tof.supersampling) == (4096, 224, 2), tof
    # Stop the 4096-row frame (10-40 s on a loaded 2-core machine; no need to compute it
    # here) and undo the one applied step (no refused edit left an undo step to take
    # instead): the window goes on with the office's camera.
    window.sim.cancel()
    window.undo_action.trigger()
    assert doc.project.rig.tof.height == 171
    _assert_panels_current(window, wait_frame)
    _assert_playback_goes_on(window, qtbot)


def test_confirmed_costly_edit_is_applied(make_window, wait_frame):
    window = make_window()
    wait_frame(window)
    window.confirm_costly = lambda cost: True
    steps = window.document.undo_stack.count()
    window.sensor_editor.tof_width.setValue(4096)
    window.sensor_editor.tof_height.setValue(2048)
    assert field_error(window.sensor_editor.tof_height) is None
    assert window.document.project.rig.tof.height == 2048
    assert window.document.undo_stack.count() == steps + 2
    window.sim.cancel()  # no need to compute it here


def test_one_failing_panel_leaves_the_others_current(make_window, wait_frame, qtbot):
    window = make_window()
    wait_frame(window)
    broken = window.rd_panel

    def fail(view):
        raise ValueError("forced failure")

    broken.draw = fail
    others = [p for p in window.panels.values() if p is not broken]
    counts = [p.draw_count for p in others]
    _assert_playback_goes_on(window, qtbot, frames=3)
    wait_frame(window)
    assert broken.error is not None and "forced failure" in broken.error
    assert broken.error_label.isVisible()
    for panel, count in zip(others, counts, strict=True):
        if not panel.isVisible():
            continue  # draws when shown
        assert panel.error is None
        assert panel.draw_count >= count + 3
        assert panel.view is window.last_view
    # The 3D view shows the newest frame's radar points.
    cloud = window.viewport._cloud
    detections = window.last_view.radar.detections
    assert cloud.n_points == len(detections)
    np.testing.assert_allclose(cloud.points, detections.xyz_world_m, atol=1e-6)
    # Drawing again clears the panel's error.
    del broken.draw
    window.time.step(1)
    wait_frame(window)
    qtbot.waitUntil(lambda: broken.error is None, timeout=5000)
    assert not broken.error_label.isVisible()


def test_a_radar_with_a_tiny_range_still_draws(make_window, wait_frame, qtbot):
    """No range bin beyond the peak search's minimum range (0.256 m maximum): all draw."""
    window = make_window()
    wait_frame(window)
    view = window.last_view
    radar = view.radar
    short = dataclasses.replace(radar, range_axis_m=radar.range_axis_m * (
        0.256 / radar.range_axis_m[-1]))
    assert np.isnan(short.profile_peak_range_m())
    tiny = dataclasses.replace(view, radar=short)
    window._on_frame(tiny)
    for name, panel in window.panels.items():
        panel.draw_now()
        assert panel.error is None, f"{name}: {panel.error}"
        assert panel.view is tiny
    assert "peak —" in window.profile_panel.info.text()
    _assert_playback_goes_on(window, qtbot)


def test_cancelling_a_long_frame_returns_control_at_once(make_window, wait_frame, qtbot,
                                                         frozen_simulation):
    """A costly frame (1024 chirps) whose simulation process is frozen cannot end at all:
    cancelling it gives control back (the event loop runs the next timer) without it, and
    the simulation process is a new one. Was: control back within 1 s of wall time, and a
    wait for the frame to have run 0.5 s (both depend on the machine's load)."""
    window = make_window()
    wait_frame(window)
    doc = window.document
    doc.set_value("rig.radar.chirps_per_frame", 1024)  # seconds per frame
    qtbot.waitUntil(lambda: window.sim.busy, timeout=10_000)
    with frozen_simulation(window) as pid:
        assert window.cancel_frame()
        ticked: list[bool] = []
        QTimer.singleShot(0, lambda: ticked.append(True))
        qtbot.waitUntil(lambda: bool(ticked), timeout=10_000)
        assert not window.sim.busy and window.sim.process_id != pid
    assert all(p.error and "stopped" in p.error for p in window.panels.values()
               if p.isVisible())
    assert not window.time.playing
    # Undo the costly edit: the fresh process computes the frame.
    window.undo_action.trigger()
    wait_frame(window)
    assert window.last_view.radar.range_doppler_db.shape[0] < 1024
    _assert_panels_current(window, wait_frame)


def test_window_handles_input_while_playing(make_window, wait_frame, qtbot, frozen_simulation):
    """While playing, the GUI thread never waits for a frame: with the simulation process
    frozen mid-playback (its frame cannot end), posted events are still answered and the
    time can still be moved; once the process goes on,
    playback goes on. Input delays while frames are drawn are timings, measured by
    ``benchmarks/bench_gui.py`` (was: median < 0.5 s and worst < 3 s here)."""
    window = make_window()
    wait_frame(window)
    answered: list[bool] = []

    def probe():
        QTimer.singleShot(0, lambda: answered.append(True))

    timer = QTimer()
    timer.timeout.connect(probe)
    timer.start(50)
    try:
        _assert_playback_goes_on(window, qtbot, frames=2)
        window.time.set_playing(True)
        qtbot.waitUntil(lambda: window.sim.busy, timeout=10_000)
        with frozen_simulation(window):
            answered.clear()
            qtbot.waitUntil(lambda: len(answered) > 10, timeout=30_000)
            assert window.sim.busy, "the frozen frame cannot have ended"
            window.time.set_playing(False)
            target = 0 if window.time.index else 1
            window.time.set_index(target)
            assert window.time.index == target
        _assert_playback_goes_on(window, qtbot, frames=3)
    finally:
        timer.stop()


def test_a_crashed_simulation_process_is_restarted(make_window, wait_frame, qtbot):
    import os
    import signal

    window = make_window()
    wait_frame(window)
    pid = window.sim.process_id
    os.kill(pid, signal.SIGKILL)  # e.g. the kernel's out-of-memory killer
    qtbot.waitUntil(lambda: window.sim.process_id not in (None, pid), timeout=5000)
    window.time.step(1)
    wait_frame(window)
    assert window.last_view.index == 1
    _assert_panels_current(window, wait_frame)
