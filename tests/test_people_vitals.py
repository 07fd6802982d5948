"""Vital signs of a simulated person measured by the project's own estimator, from datasets.

Simulator → HDF5 dataset → ``tofradar products --object <person>`` (the phase of the
chest's range bin, :func:`simcore.dsp.vitals.estimate_vital_signs`). Known answers: the
configured breathing rate and amplitude (a peak displacement along the chest's normal,
which faces the radar at about 1 m) and heart rate. The issue's bounds: breathing rate
within 0.02 Hz and amplitude within 20 %; heart rate within 0.1 Hz with breathing off.
Behind a paper box (opaque in the near-IR, nearly transparent at 60 GHz: the material
library's dual-band paper) the radar still measures them and the ToF does not see the
person.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import h5py
import numpy as np
import pytest

from simcore.cli import main
from simcore.resources import example_path

BREATHING_HZ, BREATHING_MM = 0.27, 4.0
HEART_HZ, HEART_MM = 1.1, 0.3


def _project(*, breathing: bool, heart: bool, box: bool) -> dict[str, Any]:
    """The bundled ``vital_signs`` sitter (chest about 1 m from the rig), rates changed
    from the example's, at 10 frames/s for 25 s, small ToF and radar renders."""
    d = json.loads(example_path("vital_signs").read_text())
    motion = d["objects"][0]["geometry"]["motion"]
    motion["vital_signs"] = {"breathing_rate_hz": BREATHING_HZ,
                             "breathing_amplitude_mm": BREATHING_MM if breathing else 0.0,
                             "heart_rate_hz": HEART_HZ,
                             "heart_amplitude_mm": HEART_MM if heart else 0.0}
    d["timeline"] = {"frame_rate_hz": 10.0, "duration_s": 25.0}
    d["rig"]["tof"].update({"width": 56, "height": 43, "supersampling": 1})
    d["rig"]["radar"].update({"render_width": 256, "render_height": 256, "chirps_per_frame": 4})
    if box:  # a thin paper screen between the rig and the sitter
        d["objects"].append({"id": 3, "name": "paper_box", "material": "paper",
                             "geometry": {"kind": "box", "size_m": [0.02, 1.4, 2.0]},
                             "pose": {"position_m": [0.55, 0.0, 1.0]}})
    return d


def _measure(tmp_path: Path, name: str, project: dict[str, Any]) -> dict[str, Any]:
    src, out = tmp_path / f"{name}.json", tmp_path / f"{name}.h5"
    src.write_text(json.dumps(project))
    assert main(["run", str(src), "--out", str(out), "--quiet"]) == 0
    assert main(["products", str(out), "--object", "sitter"]) == 0
    with h5py.File(out) as f:
        result = dict(f["radar/vitals"].attrs)
        result["tof_ids"] = f["tof/gt_object_id"][()]
        result["chest_range"] = f["people/segments/radar_range"][0, 2]
    return result


@pytest.mark.slow
@pytest.mark.parametrize("box", [False, True], ids=["free", "behind_paper_box"])
def test_breathing_rate_and_amplitude_from_the_chest_phase(tmp_path: Path, box: bool) -> None:
    r = _measure(tmp_path, "breathing", _project(breathing=True, heart=True, box=box))
    assert 0.8 < r["chest_range"] < 1.2
    assert r["breathing_rate_hz"] == pytest.approx(BREATHING_HZ, abs=0.02)
    assert r["breathing_amplitude_m"] == pytest.approx(BREATHING_MM * 1e-3, rel=0.2)
    if box:  # the ToF sees the paper, not the person
        assert np.count_nonzero(r["tof_ids"] == 1) == 0
        assert np.count_nonzero(r["tof_ids"] == 3) > 500


@pytest.mark.slow
@pytest.mark.parametrize("box", [False, True], ids=["free", "behind_paper_box"])
def test_heart_rate_from_the_chest_phase_when_breathing_is_off(tmp_path: Path,
                                                                box: bool) -> None:
    r = _measure(tmp_path, "heart", _project(breathing=False, heart=True, box=box))
    assert r["heart_rate_hz"] == pytest.approx(HEART_HZ, abs=0.1)
    if box:
        assert np.count_nonzero(r["tof_ids"] == 1) == 0
