"""The scrolling micro-Doppler panel, fed frame by frame with synthetic radar frames.

The frames are processed by the real chain (:func:`simcore.dsp.process_frame`) from ADC
cubes synthesised with numpy (:mod:`tests.fmcw_synth`) of a point whose radial velocity
is ``V cos(2π f t)``; the panel's newest column must peak at that velocity.
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pytest

from app.frame_view import FrameView, ObjectMarks, TofView, radar_view_from_products
from app.panels.spectrogram import SpectrogramPanel
from simcore.dsp import DspConfig, process_frame
from simcore.scene import Project
from simcore.scene.model import SensorRig, Timeline
from simcore.scene.radar_config import RadarConfig
from tests.fmcw_synth import synth_frames

pytestmark = pytest.mark.gui

V_MAX, F_SWING, RATE_HZ = 2.0, 0.5, 10.0


def limb(t: np.ndarray) -> np.ndarray:
    return 1.5 + V_MAX / (2 * np.pi * F_SWING) * np.sin(2 * np.pi * F_SWING * t)


def frame_view(project: Project, index: int, *, with_truth: bool = False) -> FrameView:
    rc = project.rig.radar
    t = index / RATE_HZ
    adc = synth_frames(rc, [(limb, 0.05)], np.array([t]), noise_std=0.01, seed=index)[0]
    radar = radar_view_from_products(process_frame(adc, rc, project.dsp), project, np.eye(4))
    tof = TofView(np.zeros((2, 2), np.float32), np.zeros((2, 2), np.float32),
                  np.ones((2, 2), bool), 5.0)
    marks = None
    if with_truth:
        v = V_MAX * np.cos(2 * np.pi * F_SWING * t)
        marks = ObjectMarks(np.array([7], np.int32), np.array([float(limb(np.array(t)))]),
                            np.array([v]), np.zeros(1), np.zeros(1))
    return FrameView(index=index, time_s=t, tof=tof, radar=radar, object_poses=np.zeros(
        (0, 4, 4)), rig_pose=np.eye(4), objects=marks)


def make_project() -> Project:
    return Project(timeline=Timeline(duration_s=10.0, frame_rate_hz=RATE_HZ),
                   rig=SensorRig(radar=RadarConfig()),
                   dsp=DspConfig(spectrogram_history_s=4.0, spectrogram_range_m=(0.8, 2.2)))


def test_panel_scrolls_and_its_newest_column_peaks_at_the_true_velocity(qtbot) -> None:
    panel = SpectrogramPanel()
    qtbot.addWidget(panel)
    project = make_project()
    panel.set_project(project)
    panel.resize(700, 400)
    panel.show()
    qtbot.waitExposed(panel)
    v_axis = None
    for k in range(25):
        panel.show_frame(frame_view(project, k))
        rd = panel.view.radar
        v_axis = rd.velocity_axis_mps
        truth = V_MAX * np.cos(2 * np.pi * F_SWING * k / RATE_HZ)
        image = panel.image.image                        # (velocity rows, time columns)
        peak_row = int(np.argmax(image[:, -1]))
        assert abs(v_axis[peak_row] - truth) <= v_axis[1] - v_axis[0], k
        assert abs(panel.peak_velocity_mps() - truth) <= v_axis[1] - v_axis[0]
    assert panel.buffer is not None and panel.buffer.capacity == 40
    assert panel.image.image.shape == (v_axis.size, 40)
    assert panel.buffer.count == 25
    # The time axis ends at the newest frame; the units are on the axes.
    assert panel.plot.getAxis("bottom").labelString().endswith("(s)</span>")
    assert panel.plot.getAxis("left").labelString().endswith("(m/s)</span>")
    assert abs(panel.image.mapRectToParent(panel.image.boundingRect()).right()
               - (2.4 + 0.05)) < 1e-6
    # A jump back in time starts a new history; a skipped frame leaves an empty column.
    panel.show_frame(frame_view(project, 3))
    assert panel.buffer.count == 1
    panel.show_frame(frame_view(project, 5))
    assert panel.buffer.count == 3
    assert np.isnan(panel.buffer.spectrogram().power_db[1]).all()


def test_gate_follows_the_selected_object_and_its_truth_is_drawn(qtbot) -> None:
    panel = SpectrogramPanel()
    qtbot.addWidget(panel)
    project = make_project().model_copy(update={"dsp": DspConfig(spectrogram_range_m=(
        3.0, 4.0))})
    panel.set_project(project)
    panel.set_selected(7)
    panel.show()
    for k in range(6):
        panel.show_frame(frame_view(project, k, with_truth=True))
    lo, hi = panel._gate
    assert lo < float(limb(np.array(0.5))) < hi            # not the project's 3–4 m gate
    x, y = panel.truth_curve.getData()
    np.testing.assert_allclose(y, V_MAX * np.cos(2 * np.pi * F_SWING * np.arange(6) / RATE_HZ))
    if os.environ.get("TOFRADAR_SCREENSHOTS"):
        out = Path(os.environ["TOFRADAR_SCREENSHOTS"])
        for k in range(6, 40):
            panel.show_frame(frame_view(project, k, with_truth=True))
        panel.grab().save(str(out / "spectrogram_panel.png"))


def test_main_window_has_the_micro_doppler_dock(make_window, wait_frame, qtbot) -> None:
    window = make_window()
    wait_frame(window)
    dock = window.docks["spectrogram"]
    assert dock.isVisibleTo(window)
    qtbot.waitUntil(lambda: window.spectrogram_panel.buffer is not None
                    and window.spectrogram_panel.buffer.count > 0, timeout=30_000)
    dock.raise_()
    qtbot.waitUntil(lambda: window.spectrogram_panel.draw_count > 0, timeout=30_000)


def test_products_options_in_the_sensor_editor_round_trip(qtbot, tmp_path) -> None:
    from app.document.document import ProjectDocument
    from app.editors.field_editors import PRODUCTS
    from app.editors.sensor_editor import SensorEditor
    from app.widgets.inputs import field_error
    from simcore.scene import fieldpath, load_project

    new = {"dsp.spectrogram_mode": "stft", "dsp.spectrogram_window": "blackman",
           "dsp.spectrogram_segment_chirps": 64, "dsp.spectrogram_overlap": 0.75,
           "dsp.spectrogram_clutter_removal": False, "dsp.spectrogram_history_s": 20.0,
           "dsp.vitals_static_offset": "mean", "dsp.vitals_window_s": 20.0,
           "dsp.vitals_channel": 1}
    doc = ProjectDocument()
    editor = SensorEditor(doc)
    doc.setParent(editor)
    qtbot.addWidget(editor)
    form = editor.products_form
    assert {s.path for s in PRODUCTS} == set(new)
    for spec in PRODUCTS:
        w = form.widgets[spec.path]
        assert w.toolTip(), spec.path
        value = new[spec.path]
        if spec.kind == "bool":
            w.setChecked(bool(value))
        elif spec.kind == "choice":
            w.setCurrentText(value)
            w.activated.emit(w.currentIndex())
        else:
            w.setValue(value)
        assert field_error(w) is None, spec.path
    out = tmp_path / "p.json"
    doc.save(out)
    loaded = load_project(out)
    for path, value in new.items():
        assert fieldpath.get(loaded, path) == pytest.approx(value) if not isinstance(
            value, str) else fieldpath.get(loaded, path) == value, path
    overlap = form.widgets["dsp.spectrogram_overlap"]
    overlap.setValue(1.0)                                   # the model wants < 1
    assert field_error(overlap)
    assert doc.project.dsp.spectrogram_overlap == 0.75
    # Segment "off" is None: one frame's chirps.
    seg = form.widgets["dsp.spectrogram_segment_chirps"]
    seg.setValue(seg.minimum())
    assert doc.project.dsp.spectrogram_segment_chirps is None


def test_view_starts_at_the_first_column_while_the_history_fills(qtbot) -> None:
    panel = SpectrogramPanel()
    qtbot.addWidget(panel)
    project = make_project()                                # 4 s history at 10 Hz
    panel.set_project(project)
    panel.show()
    for k in range(3):
        panel.show_frame(frame_view(project, k))
    (x0, x1), _ = panel.plot.vb.viewRange()
    assert abs(x0 + 0.05) < 1e-6 and abs(x1 - 3.95) < 1e-6
    for k in range(3, 45):
        panel.show_frame(frame_view(project, k))
    qtbot.wait(20)
    (x0, x1), _ = panel.plot.vb.viewRange()
    assert abs(x1 - 4.45) < 1e-6 and abs(x0 - 0.45) < 1e-6   # scrolled: last 40 frames
