"""The sensor editor's device lists: the library's radars and cameras, with descriptions."""

from __future__ import annotations

import pytest
from PyQt6.QtCore import Qt

pytestmark = pytest.mark.gui


def test_sensor_editor_offers_the_device_library(make_window):
    window = make_window()
    ed = window.sensor_editor
    radars = [ed.radar_preset.itemText(i) for i in range(ed.radar_preset.count())]
    cameras = [ed.tof_preset.itemText(i) for i in range(ed.tof_preset.count())]
    assert {"ti_iwr6843isk", "ti_awr1843boost", "infineon_bgt60utr11aip"} <= set(radars)
    assert {"kinect_v2", "azure_kinect_wfov", "pmd_flexx2"} <= set(cameras)
    k = radars.index("ti_awr1843boost")
    assert "76–81 GHz" in ed.radar_preset.itemData(k, Qt.ItemDataRole.ToolTipRole)
    ed.apply_radar_preset("ti_iwr6843isk")
    radar = window.document.project.rig.radar
    assert radar.preset == "ti_iwr6843isk" and len(radar.tx) == 3 and radar.complex_iq
    assert ed.radar_device.text().startswith("TI IWR6843ISK: 60–64 GHz")
    ed.apply_tof_preset("kinect_v2")
    tof = window.document.project.rig.tof
    assert tof.modulation_frequencies_hz == [80e6, 16e6, 120e6]
    assert ed.tof_device.text().startswith("Microsoft Kinect v2")
    # Editing the first frequency keeps the third (it has no box of its own).
    ed.tof_f1.setValue(40.0)
    assert window.document.project.rig.tof.modulation_frequencies_hz == [40e6, 16e6, 120e6]
