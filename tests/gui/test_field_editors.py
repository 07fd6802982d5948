"""Editors of the link budget, CFAR cells and DSP options: save/load, undo, validation."""

from __future__ import annotations

import pytest

from app.document.document import ProjectDocument
from app.editors.field_editors import (
    DETECTION,
    LINK_BUDGET,
    PROCESSING,
    TOF_MULTIPATH,
    FieldSpec,
)
from app.editors.sensor_editor import PfaSpin, SensorEditor
from app.widgets.inputs import field_error
from simcore.scene import fieldpath, load_project

pytestmark = pytest.mark.gui

#: One new value per field (SI; None for "off"), each different from the default.
NEW_VALUES = {
    "rig.radar.tx_power_dbm": 12.0, "rig.radar.tx_gain_dbi": 9.5,
    "rig.radar.rx_gain_dbi": 3.0, "rig.radar.noise_figure_db": 8.5,
    "rig.radar.if_gain_db": 40.0, "rig.radar.adc_bits": None,
    "rig.radar.adc_full_scale_v": 0.5, "rig.radar.leakage_dbc": None,
    "rig.radar.leakage_path_mm": 38.0, "rig.radar.adc_noise_fs": 4.5e-4,
    "rig.radar.if_highpass_hz": 150e3, "rig.radar.if_lowpass_hz": 900e3,
    "rig.radar.speckle": False, "rig.radar.multipath_order": 2,
    "rig.radar.polarization": "H", "rig.radar.ideal": True,
    "rig.radar.rig_front_width_m": 0.06, "rig.radar.rig_front_height_m": 0.04,
    "rig.radar.rig_front_material": "wood",
    "rig.radar.chirp_jitter_s": 2e-6, "rig.radar.hop_step_hz": 250e6,
    "rig.radar.hop_channels": 4, "rig.radar.transmit_seed": 9,
    "dsp.cfar_guard_range": 3, "dsp.cfar_train_range": 12, "dsp.cfar_guard_doppler": 2,
    "dsp.cfar_train_doppler": 6, "dsp.cfar_os_rank": 0.6, "dsp.peak_grouping": "cluster",
    "dsp.max_detections": 64, "dsp.interpolate_peaks": False,
    "dsp.remove_dc": False, "dsp.range_window_sidelobe_db": 70.0,
    "dsp.doppler_window_sidelobe_db": 50.0, "dsp.tdm_doppler_compensation": False,
    "dsp.azimuth_min_deg": -60.0, "dsp.azimuth_max_deg": 60.0, "dsp.azimuth_step_deg": 0.5,
    "dsp.angle_fft_size": 128, "dsp.angle_peaks_within_db": 3.0,
    "dsp.interference_mitigation": "interpolate", "dsp.interference_threshold": 8.0,
    "rig.tof.multipath_model": "room", "rig.tof.multipath_surfel_m": 0.5,
    "rig.tof.multipath_bounces": 2, "rig.tof.multipath_moving": "exact",
}


def _enter(form, spec: FieldSpec, value) -> None:
    """Type ``value`` into the field's widget as a user would (box units)."""
    w = form.widgets[spec.path]
    if spec.kind == "bool":
        w.setChecked(bool(value))
    elif spec.kind == "choice":
        w.setCurrentText(value)
        w.activated.emit(w.currentIndex())
    elif value is None:
        w.setValue(w.minimum())
    else:
        w.setValue(value if spec.kind == "int" else value * spec.scale)


@pytest.fixture
def editor(qtbot):
    doc = ProjectDocument()
    ed = SensorEditor(doc)
    doc.setParent(ed)
    qtbot.addWidget(ed)
    return ed


def test_every_field_round_trips_through_save_load_and_undo(editor, tmp_path):
    doc = editor.document
    specs = [(editor.link_form, s) for s in LINK_BUDGET] + [
        (editor.detection_form, s) for s in DETECTION] + [
        (editor.processing_form, s) for s in PROCESSING] + [
        (editor.tof_interference_form, s) for s in TOF_MULTIPATH]
    assert {s.path for _, s in specs} == set(NEW_VALUES)
    before = doc.project
    for form, spec in specs:
        _enter(form, spec, NEW_VALUES[spec.path])
        assert field_error(form.widgets[spec.path]) is None, spec.path
        got, want = fieldpath.get(doc.project, spec.path), NEW_VALUES[spec.path]
        assert (got is None) if want is None else got == pytest.approx(want), spec.path
    assert doc.undo_stack.count() == len(specs)             # one undo step per field
    assert doc.undo_stack.text(0) == "Set Tx power to 12 dBm"       # in the user's words
    out = tmp_path / "link.json"
    doc.save(out)
    loaded = load_project(out)
    for path, value in NEW_VALUES.items():
        got = fieldpath.get(loaded, path)
        assert (got is None) if value is None else got == pytest.approx(value), path
    # The editor shows what it loaded.
    doc.new()
    doc.open(out)
    assert editor.link_form.widgets["rig.radar.tx_power_dbm"].value() == 12.0
    assert editor.link_form.widgets["rig.radar.adc_bits"].text() == "off (no quantization)"
    assert editor.link_form.widgets["rig.radar.if_highpass_hz"].value() == 150.0  # kHz
    # Undo all the way back restores the original project and the widgets.
    doc.replace(before, None)
    for form, spec in specs:
        _enter(form, spec, NEW_VALUES[spec.path])
    while doc.undo_stack.canUndo():
        doc.undo_stack.undo()
    assert doc.project == before
    assert editor.detection_form.widgets["dsp.cfar_train_range"].value() == \
        before.dsp.cfar_train_range


def test_refused_values_say_why_at_the_field_and_tooltips_state_units_and_range(editor):
    doc = editor.document
    box = editor.link_form.widgets["rig.radar.tx_power_dbm"]
    assert "dBm" in box.suffix() and "accepted: −100 to 60 dBm" in box.toolTip()
    count = doc.undo_stack.count()
    box.setValue(75.0)                                    # above the model's 60 dBm
    assert "60" in (field_error(box) or "")
    assert doc.undo_stack.count() == count and doc.project.rig.radar.tx_power_dbm == 5.0
    rank = editor.detection_form.widgets["dsp.cfar_os_rank"]
    rank.setValue(0.0)                                     # the model wants > 0
    assert field_error(rank)
    amin = editor.processing_form.widgets["dsp.azimuth_min_deg"]
    amin.setValue(85.0)                                    # above azimuth_max_deg (80)
    assert "azimuth" in (field_error(amin) or "")
    for spec in LINK_BUDGET + DETECTION + PROCESSING:
        w = {**editor.link_form.widgets, **editor.detection_form.widgets,
             **editor.processing_form.widgets}[spec.path]
        assert w.toolTip(), spec.path


def test_pfa_reads_as_a_number(editor):
    doc = editor.document
    pfa: PfaSpin = editor.pfa
    assert pfa.text() == "Pfa = 1e-06"
    pfa.lineEdit().setText("Pfa = 3e-7")
    pfa.interpretText()
    assert doc.project.dsp.cfar_pfa == pytest.approx(3e-7)
    assert pfa.text() == "Pfa = 3e-07"
    pfa.stepBy(1)                                          # half a decade rarer
    assert doc.project.dsp.cfar_pfa == pytest.approx(3e-7 / 10 ** 0.5)
