"""Radar-only, ToF-only and renamed-sensor projects in the GUI (issue 40).

Each project is built from the bundled office as a user would: by editing its JSON (the
built-in ``rig.tof`` / ``rig.radar`` set to null, or moved into ``rig.sensors`` under
other names). The known answers come from the office itself: a sensor computes the same
data whatever other sensors the project has (the radar-only office's radar maps are the
office's, the ToF-only office's depth is the office's), and a renamed camera or radar sees
the same noise-free things (object ids per pixel, each object's true range) as the
built-in one it was copied from.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from simcore.resources import EXAMPLES_DIR
from simcore.scene.tof_config import TofCameraConfig

pytestmark = pytest.mark.gui

OFFICE = EXAMPLES_DIR / "office.json"
RADAR_PANELS = {"Range profile", "Range-Doppler", "Range-azimuth"}
RADAR_DOCKS = ("profile", "rd", "ra", "spectrogram", "antennas")


def office_variant(tmp_path: Path, name: str, edit: Any) -> Path:
    """The office with ``edit`` applied to its JSON, saved as ``<name>.json``."""
    data = json.loads(OFFICE.read_text())
    edit(data)
    path = tmp_path / f"{name}.json"
    path.write_text(json.dumps(data, indent=1))
    return path


def radar_only(data: dict[str, Any]) -> None:
    data["rig"]["tof"] = None


def tof_only(data: dict[str, Any]) -> None:
    data["rig"]["radar"] = None


def renamed(data: dict[str, Any]) -> None:
    """No sensor called tof or radar: the office's two as cam_front and fmcw_front."""
    rig = data["rig"]
    tof, radar = rig.pop("tof", None) or {}, rig.pop("radar", None) or {}
    rig["tof"] = rig["radar"] = None
    rig.setdefault("sensors", {}).update({"cam_front": {"kind": "tof", **tof},
                                          "fmcw_front": {"kind": "radar", **radar}})


def _steps(window) -> list[str]:
    stack = window.document.undo_stack
    return [stack.text(i) for i in range(stack.index())]


def _shown_docks(window) -> set[str]:
    return {key for key, dock in window.docks.items() if not dock.isHidden()}


def _office_frame(make_window, wait_frame):
    """The office's own first frame (the reference of the variants)."""
    window = make_window(OFFICE)
    wait_frame(window)
    return window, window.last_view


def test_radar_only_office_shows_radar_panels_only(make_window, wait_frame, tmp_path):
    window, office = _office_frame(make_window, wait_frame)
    assert window.open_project(office_variant(tmp_path, "radar_only", radar_only), ask=False)
    project = window.document.project
    assert project.rig.tof is None and list(project.sensor_configs()) == ["radar"]
    assert set(window.panels) == RADAR_PANELS
    shown = _shown_docks(window)
    assert "tof" not in shown and "rgb" not in shown
    assert set(RADAR_DOCKS) <= shown
    assert not window.docks["tof"].toggleViewAction().isEnabled()
    wait_frame(window)
    view = window.last_view
    assert view.tof is None and view.tofs == {}
    # The radar computes what it computes beside a ToF camera: the same maps.
    np.testing.assert_array_equal(window.rd_panel.view.radar.range_doppler_db,
                                  office.radar.range_doppler_db)
    for panel in (window.profile_panel, window.rd_panel, window.ra_panel):
        assert panel.error is None and panel.draw_count > 0
    # The ToF camera's page says there is none; the radar pages edit the radar.
    editor = window.sensor_editor
    tof_page = editor.tabs.indexOf(editor.kind_pages["tof"][0])
    assert not editor.tabs.isTabEnabled(tof_page)
    assert "no ToF camera" in editor.tabs.tabToolTip(tof_page)
    assert editor.tabs.isTabEnabled(editor.tabs.indexOf(editor.kind_pages["radar"][0]))
    # The 3D view draws the radar's frustum and no camera's, and shows the radar's band.
    actors = window.viewport._rig_actors
    assert "radar_fov" in actors and "tof_fov" not in actors
    assert window.viewport.band == "radar"


def test_tof_only_office_shows_tof_panels_only(make_window, wait_frame, tmp_path):
    window, office = _office_frame(make_window, wait_frame)
    assert window.open_project(office_variant(tmp_path, "tof_only", tof_only), ask=False)
    assert window.document.project.rig.radar is None
    assert set(window.panels) == {"ToF camera"}
    shown = _shown_docks(window)
    assert "tof" in shown and not shown & set(RADAR_DOCKS)
    wait_frame(window)
    view = window.last_view
    assert view.radar is None and view.radars == {}
    # The camera's depth is the office's (its noise too: the radar takes no draws of it).
    np.testing.assert_array_equal(window.tof_panel.view.tof.depth_m, office.tof.depth_m)
    assert window.tof_panel.error is None
    editor = window.sensor_editor
    for page in editor.kind_pages["radar"]:
        assert not editor.tabs.isTabEnabled(editor.tabs.indexOf(page))
    assert not window.antenna_editor.isEnabled()
    assert editor.tabs.isTabEnabled(editor.tabs.currentIndex()), "a disabled page is not shown"
    actors = window.viewport._rig_actors
    assert "tof_fov" in actors and "radar_fov" not in actors


def test_remove_last_radar_undo_and_add_a_tof_camera_back(make_window, wait_frame, qtbot):
    window = make_window(OFFICE)
    doc, rigs = window.document, window.sensor_editor.rigs
    original, n0 = doc.project, doc.undo_stack.index()
    wait_frame(window)
    # The office's only radar goes: one undo step; its panels and frustum go with it.
    rigs.select("sensor", "radar")
    assert rigs.remove_button.isEnabled()
    rigs.remove_selected()
    assert doc.project.rig.radar is None
    assert _steps(window)[n0:] == ["Remove radar radar"]
    assert set(window.panels) == {"ToF camera"}
    assert not _shown_docks(window) & set(RADAR_DOCKS)
    wait_frame(window)
    assert window.last_view.radar is None
    qtbot.waitUntil(lambda: "radar_fov" not in window.viewport._rig_actors)
    assert window.viewport._cloud_key == (), "no stale detections in the 3D view"
    # One undo brings it back, as it was.
    doc.undo_stack.undo()
    assert doc.project == original and doc.undo_stack.index() == n0
    assert set(window.panels) == {"ToF camera", *RADAR_PANELS}
    assert set(RADAR_DOCKS) <= _shown_docks(window)
    wait_frame(window)
    assert window.profile_panel.view.radar is not None
    assert "radar_fov" in window.viewport._rig_actors
    # Now the ToF camera goes; the radar is then the last sensor and stays.
    rigs.select("sensor", "tof")
    rigs.remove_selected()
    assert list(doc.project.sensor_configs()) == ["radar"]
    assert set(window.panels) == RADAR_PANELS and "tof" not in _shown_docks(window)
    rigs.select("sensor", "radar")
    assert not rigs.remove_button.isEnabled()
    assert "needs at least one sensor" in rigs.remove_button.toolTip()
    steps = _steps(window)
    with qtbot.waitSignal(rigs.editFailed) as refused:
        rigs.remove_selected()
    assert "only sensor" in refused.args[0] and "at least one sensor" in refused.args[0]
    assert _steps(window) == steps and "radar" in doc.project.sensor_configs()
    # A ToF camera added to the first rig fills its empty field: defaults, one step.
    rigs.select("rig", "rig")
    rigs.add_sensor("tof")
    assert doc.project.rig.tof == TofCameraConfig()
    assert _steps(window)[-1] == "Add ToF camera tof to rig"
    assert rigs.selected == ("sensor", "tof")
    assert set(window.panels) == {"ToF camera", *RADAR_PANELS}
    assert "tof" in _shown_docks(window)
    wait_frame(window)
    cfg = doc.project.rig.tof
    assert window.tof_panel.view.tof.depth_m.shape == (cfg.height, cfg.width)
    doc.undo_stack.undo()
    assert doc.project.rig.tof is None, "adding it back was one undo step"


def test_renamed_office_panels_show_the_renamed_sensors(make_window, wait_frame, tmp_path):
    window, office = _office_frame(make_window, wait_frame)
    assert window.open_project(office_variant(tmp_path, "renamed", renamed), ask=False)
    doc = window.document
    assert set(doc.project.sensor_configs()) == {"cam_front", "fmcw_front"}
    assert set(window.panels) == {"ToF camera", *RADAR_PANELS}
    wait_frame(window)
    view = window.last_view
    assert list(view.tofs) == ["cam_front"] and list(view.radars) == ["fmcw_front"]
    assert window.tof_panel.sensor == "cam_front"
    for panel in (window.profile_panel, window.rd_panel, window.ra_panel):
        assert panel.sensor == "fmcw_front" and panel.error is None and panel.draw_count > 0
    # Each dock names the sensor its panel shows.
    assert window.docks["tof"].windowTitle() == "ToF camera · cam_front"
    assert window.docks["rd"].windowTitle().endswith("· fmcw_front")
    # The renamed sensors see what the built-in ones saw (noise-free outputs).
    np.testing.assert_array_equal(window.tof_panel.view.tof.gt_object_id,
                                  office.tof.gt_object_id)
    truth = window.profile_panel.view.objects
    assert truth is not None
    np.testing.assert_allclose(truth.range_m, office.objects.range_m, rtol=0, atol=1e-12)
    # The editors edit them: the ToF page sets cam_front's width, the Radar page names it.
    editor = window.sensor_editor
    assert "cam_front on rig" in editor.tof_box.title()
    assert "fmcw_front on rig" in editor.radar_box.title()
    editor.tof_width.setValue(80)
    assert doc.project.rig.sensors["cam_front"].width == 80
    wait_frame(window)
    assert window.tof_panel.view.tof.depth_m.shape[1] == 80
    assert {"label:cam_front", "label:fmcw_front"} <= set(window.viewport._rig_actors)


def test_every_example_opens_with_the_panels_of_its_sensors(make_window, wait_frame):
    """Each bundled example, opened in turn in one window, shows its sensors' panels."""
    window = make_window(None)
    kinds = {"tof": {"ToF camera"}, "rgb": {"RGB camera"}, "radar": RADAR_PANELS}
    examples = sorted(EXAMPLES_DIR.glob("*.json"))
    assert len(examples) >= 13
    for example in examples:
        assert window.open_project(example, ask=False), example.name
        project = window.document.project
        expected = set().union(*(titles for kind, titles in kinds.items()
                                 if project.sensors_of_kind(kind)))
        assert set(window.panels) == expected, example.name
        wait_frame(window)
        for title, panel in window.panels.items():
            assert panel.error is None, f"{example.name}: {title}: {panel.error}"
        assert window.last_error_dialog is None, example.name


def test_saved_layout_keeps_a_closed_radar_dock_closed(make_window, tmp_path):
    """A dock the user closed stays closed at the next start; another kind's follows."""
    first = make_window(OFFICE)
    first.docks["ra"].close()
    first.close()  # saves the layout
    window = make_window(office_variant(tmp_path, "radar_only", radar_only))
    shown = _shown_docks(window)
    assert "ra" not in shown and {"profile", "rd"} <= shown and "tof" not in shown
    assert window.docks["ra"].toggleViewAction().isEnabled(), "the user may open it again"
    # A project with an RGB camera shows its panel though the last layout had none.
    assert window.open_project(EXAMPLES_DIR / "office_rgb.json", ask=False)
    assert {"tof", "rgb"} <= _shown_docks(window)
