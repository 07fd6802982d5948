"""Headless `tofradar run`: dataset layout, overwrite protection, previews."""

from __future__ import annotations

import subprocess
import sys

import h5py
import numpy as np

from simcore.cli import main
from simcore.resources import example_path
from simcore.scene import load_project


def test_run_writes_ground_truth_layout(tmp_path):
    out = tmp_path / "wall.h5"
    assert main(["run", str(example_path("wall")), "--out", str(out), "--frames", "2",
                 "--seed", "7", "--quiet", "--preview", str(tmp_path / "prev")]) == 0
    project = load_project(example_path("wall"))
    h, w = project.rig.tof.height, project.rig.tof.width
    with h5py.File(out) as f:
        assert f["meta"].attrs["seed"] == 7
        assert f["meta"].attrs["n_frames"] == 2
        assert "wall" in f["meta"].attrs["project_json"]
        np.testing.assert_allclose(f["time"][:], [0.0, 0.1])
        assert f["time"].attrs["unit"] == "s"
        assert f["tof/gt_range"].shape == (2, h, w)
        assert f["tof/gt_object_id"].dtype == np.int32
        assert f["poses/rig"].shape == (2, 4, 4)
        assert f["poses/objects"].shape == (2, 1, 4, 4)
        assert [n.decode() if isinstance(n, bytes) else n for n in f["objects/names"][:]] \
            == ["wall"]
        gt = f["tof/gt_range"][0]
    # Wall face 2.0 m ahead of the camera: centre pixels see ~2.0 m.
    assert abs(float(gt[h // 2, w // 2]) - 2.0) < 0.01
    assert sorted(p.name for p in (tmp_path / "prev").iterdir())[0].startswith("frame_00000_")


def test_run_refuses_to_overwrite(tmp_path, capsys):
    out = tmp_path / "x.h5"
    out.write_bytes(b"precious")
    assert main(["run", str(example_path("wall")), "--out", str(out), "--frames", "1",
                 "--quiet"]) == 2
    assert "already exists; use --overwrite" in capsys.readouterr().err
    assert out.read_bytes() == b"precious"


def test_bad_arguments_are_one_line_errors():
    proc = subprocess.run([sys.executable, "-m", "simcore.cli", "run", "nope.json", "--out",
                           "x.h5", "--frames", "-3"], capture_output=True, text=True, timeout=60)
    assert proc.returncode == 2
    assert "expected a positive integer" in proc.stderr
    assert "Traceback" not in proc.stderr
    proc = subprocess.run([sys.executable, "-m", "simcore.cli", "run", "nope.json", "--out",
                           "x.h5"], capture_output=True, text=True, timeout=60)
    assert proc.returncode == 2 and "file not found" in proc.stderr
    assert "Traceback" not in proc.stderr
