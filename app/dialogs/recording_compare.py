"""A real recording beside the simulation: the recording as reference A of the A/B panels.

The radar panels' A/B comparison ("Freeze A", "A − B") compares the frame shown with a
reference frame. :func:`set_recording_reference` makes a frame of a real recording that
reference: a converted dataset (``tofradar convert RECORDING_DIR --to OUT.h5``) or the
recording folder itself. Its ADC cube goes through the *project's* DSP
(:func:`simcore.dsp.process_frame` with ``project.dsp``), so both sides are processed
alike; the range-profile panel draws the recording's profile as the grey reference curve
and "A − B" shows the simulated frame minus the recording (dB). Issue #35.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import h5py
import numpy as np
from PyQt6.QtGui import QAction
from PyQt6.QtWidgets import QFileDialog, QMenu, QMessageBox, QWidget

import simcore.sensors  # noqa: F401  (registers the kinds' schemas)
from app.frame_view import FrameView, radar_view_from_products
from simcore.dsp import process_frame
from simcore.scene import Project
from simcore.scene.project_io import project_from_dict
from simcore.scene.radar_config import RadarConfig
from simcore.sensors.schema import schema_of


def recording_adc(path: str | Path, *, frame: int = 0
                  ) -> tuple[np.ndarray, RadarConfig, float]:
    """ADC cube (chirps, channels, samples) in FS, its radar and its time (s).

    ``path``: a converted recording (``.h5``, any tofradar dataset with ``/radar/adc``) or a
    Radar Fusion GUI recording folder.
    """
    p = Path(path)
    if p.is_dir():
        from simcore.io.recordings import read_recording

        rec = read_recording(p)
        k = min(max(frame, 0), rec.n_frames - 1)
        return rec.frame_adc(k), rec.config, float(rec.frame_times_s()[k])
    with h5py.File(p, "r") as f:
        project_json = f["meta"].attrs.get("project_json", "{}") if "meta" in f else "{}"
        project = project_from_dict(json.loads(project_json), check_files=False)
        found = [(name, cfg) for name, cfg in project.sensors_of_kind("radar").items()
                 if schema_of("radar").dataset_path(name, "adc") in f]
        if not found:
            raise ValueError(f"{p}: no radar ADC data in this file")
        name, radar = found[0]
        adc_ds = f[schema_of("radar").dataset_path(name, "adc")]
        k = min(max(frame, 0), adc_ds.shape[0] - 1)
        adc = np.asarray(adc_ds[k])
        t = float(f["time"][k]) if "time" in f else 0.0
    assert isinstance(radar, RadarConfig)
    return adc, radar, t


def recording_frame_view(path: str | Path, project: Project, *, frame: int = 0) -> FrameView:
    """A frame of a recording as the panels draw it, through ``project.dsp``."""
    adc, config, t = recording_adc(path, frame=frame)
    products = process_frame(adc, config, project.dsp)
    name = next(iter(project.sensors_of_kind("radar")), None)
    if name is None:
        raise ValueError("the project has no radar to compare the recording with")
    radar = radar_view_from_products(products, project, np.eye(4), name=name)
    return FrameView(index=frame, time_s=t, tof=None, radar=radar,
                     object_poses=np.zeros((0, 4, 4)), rig_pose=np.eye(4),
                     notes=[f"recording {Path(path).name}"])


def set_recording_reference(window: Any, path: str | Path, *, frame: int = 0) -> FrameView:
    """Make a recording's frame the A reference of every comparable panel of ``window``."""
    view = recording_frame_view(path, window.document.project, frame=frame)
    for panel in window.panels.values():
        if getattr(panel, "comparable", False):
            panel.reference = view
            panel.diff_button.setEnabled(True)
            panel.freeze_button.setText("A = recording")
            panel.freeze_button.setToolTip(f"Reference A: {Path(path).name}, frame {frame}; "
                                           "press to freeze the current frame instead")
            panel.redraw()
    return view


def add_compare_recording_action(window: QWidget, menu: QMenu) -> QAction:
    """File menu entry "Compare with recording…" (a dataset or a recording folder)."""
    action = QAction("Compare with &recording…", window)
    action.setToolTip("Show a real radar recording as reference A of the radar panels "
                      "(processed with this project's DSP); 'A − B' = simulation − recording")

    def choose() -> None:
        path, _ = QFileDialog.getOpenFileName(window, "Recording to compare with", "",
                                              "Datasets and recordings (*.h5 config.json)")
        if not path:
            return
        target = Path(path).parent.parent if Path(path).name == "config.json" else Path(path)
        try:
            set_recording_reference(window, target)
        except (OSError, ValueError, KeyError) as exc:
            QMessageBox.warning(window, "Compare with recording", str(exc))

    action.triggered.connect(choose)
    menu.addAction(action)
    return action
