"""A real recording beside the simulation in the A/B panels (issue #35)."""

from __future__ import annotations

import h5py
import numpy as np
import pytest

from app.dialogs.recording_compare import recording_frame_view, set_recording_reference
from simcore.dsp import process_frame
from simcore.io.recordings import read_recording
from simcore.report.real import shared_recording

pytestmark = pytest.mark.gui


def _recording(tmp_path):
    import sys
    from pathlib import Path

    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
    from test_recordings import SETTINGS, tone_codes, write_recording

    codes = tone_codes(SETTINGS, frames=2, tones=[(12, 0.05)], noise_lsb=2.0)
    return write_recording(tmp_path, codes)


def test_a_recording_becomes_reference_a_with_the_projects_dsp(make_window, wait_frame,
                                                               tmp_path, qtbot):
    from simcore.cli import main

    src = shared_recording() or _recording(tmp_path)
    project = tmp_path / "from_recording.json"     # the recording's radar, empty scene
    assert main(["convert", str(src), "--to", str(tmp_path / "rec.h5"), "--project",
                 str(project)]) == 0
    window = make_window(project)
    wait_frame(window)
    view = set_recording_reference(window, src, frame=1)
    rec = read_recording(src)
    expected = process_frame(rec.frame_adc(1), rec.config, window.document.project.dsp)
    np.testing.assert_allclose(view.radar.profile_db, expected.range_profile_db)
    profile = window.panels["Range profile"]
    assert profile.reference is view and profile.diff_button.isEnabled()
    profile.set_show_difference(True)
    wait_frame(window)
    qtbot.wait(300)
    assert profile.show_difference
    path = tmp_path / "ab.png"
    window.grab().save(str(path))
    assert path.stat().st_size > 10_000
    assert recording_frame_view(src, window.document.project).radar is not None


def test_converted_and_simulated_datasets_are_references_alike(make_window, wait_frame,
                                                               tmp_path):
    """The converted dataset (.h5) gives the same reference as the recording folder, and a
    simulated run of the project made from it (a point target added: ``tofradar run``
    wants an object) is opened the same way."""
    import json

    from simcore.cli import main

    src = _recording(tmp_path)
    project, converted, simulated = (tmp_path / "p.json", tmp_path / "rec.h5",
                                     tmp_path / "sim.h5")
    assert main(["convert", str(src), "--to", str(converted), "--project", str(project)]) == 0
    doc = json.loads(project.read_text())
    doc["objects"] = [{"id": 1, "name": "target", "geometry": {"kind": "point_target",
                                                                "rcs_m2": 0.01},
                       "pose": {"position_m": [0.4, 0.0, 0.0]}}]
    project.write_text(json.dumps(doc))
    assert main(["run", str(project), "--out", str(simulated), "--frames", "2"]) == 0
    window = make_window(project)
    wait_frame(window)
    from_folder = recording_frame_view(src, window.document.project, frame=1)
    view = set_recording_reference(window, converted, frame=1)
    np.testing.assert_array_equal(view.radar.profile_db, from_folder.radar.profile_db)
    assert view.time_s == from_folder.time_s > 0
    assert window.panels["Range profile"].reference is view
    sim_view = set_recording_reference(window, simulated, frame=1)
    with h5py.File(simulated, "r") as f:
        adc = np.asarray(f["radar/adc"][1])
    expected = process_frame(adc, window.document.project.rig.radar, window.document.project.dsp)
    np.testing.assert_allclose(sim_view.radar.profile_db, expected.range_profile_db)
    assert window.panels["Range profile"].reference is sim_view
