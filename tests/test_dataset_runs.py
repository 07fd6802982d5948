"""Dataset generation at scale: reproducibility, workers, Dask, resume, memory, sweeps."""

from __future__ import annotations

import json
from pathlib import Path

import h5py
import numpy as np
import pytest
from fresh_process import peak_rss_per_frame
from h5data import assert_same_data, datasets

from simcore.cli import main
from simcore.resources import example_path
from simcore.runs.runner import run_dataset
from simcore.scene import load_project, save_project
from simcore.scene.project_io import project_to_json


def small_project(tmp_path: Path, name: str = "point_targets") -> Path:
    """The example with small sensor grids, so that many frames run quickly."""
    project = load_project(example_path(name))
    project.rig.tof.width, project.rig.tof.height = 64, 48
    project.rig.radar.render_width, project.rig.radar.render_height = 240, 82
    path = tmp_path / f"{name}_small.json"
    save_project(project, path)
    return path




def run(project: Path, out: Path, *extra: str) -> int:
    return main(["run", str(project), "--out", str(out), "--quiet", *extra])


def test_same_seed_is_bit_identical_also_with_two_workers(tmp_path):
    project = small_project(tmp_path)
    assert run(project, tmp_path / "a.h5", "--frames", "4", "--seed", "3") == 0
    assert run(project, tmp_path / "b.h5", "--frames", "4", "--seed", "3") == 0
    assert run(project, tmp_path / "c.h5", "--frames", "4", "--seed", "3",
               "--workers", "2") == 0
    assert_same_data(tmp_path / "a.h5", tmp_path / "b.h5")
    assert_same_data(tmp_path / "a.h5", tmp_path / "c.h5")
    assert run(project, tmp_path / "d.h5", "--frames", "4", "--seed", "4") == 0
    a, d = datasets(tmp_path / "a.h5"), datasets(tmp_path / "d.h5")
    np.testing.assert_array_equal(a["tof/gt_range"], d["tof/gt_range"])   # not random
    assert not np.array_equal(a["tof/correlation"], d["tof/correlation"])  # noise differs


def test_dask_local_cluster_matches_in_process(tmp_path):
    project = small_project(tmp_path)
    assert run(project, tmp_path / "a.h5", "--frames", "3") == 0
    assert run(project, tmp_path / "b.h5", "--frames", "3", "--workers", "2",
               "--scheduler", "local") == 0
    assert_same_data(tmp_path / "a.h5", tmp_path / "b.h5")


def test_interrupted_run_is_readable_and_resume_completes_it_identically(tmp_path):
    project_path = small_project(tmp_path)
    project = load_project(project_path)
    text = project_to_json(project)

    def interrupt_after_three(done: int, total: int, result: object) -> bool:
        if done == 3:
            raise KeyboardInterrupt
        return True

    out = tmp_path / "part.h5"
    report = run_dataset(text, tmp_path, out, n_frames=7, seed=5,
                         on_frame=interrupt_after_three)
    assert report.interrupted and report.frames_done == 3
    with h5py.File(out) as f:                       # a valid file with three frames
        assert f["meta"].attrs["n_frames"] == 3
        assert f["time"].shape == (3,)
        assert f["tof/depth"].shape[0] == 3
    assert run(project_path, out, "--frames", "7", "--seed", "5", "--resume") == 0
    assert run(project_path, tmp_path / "full.h5", "--frames", "7", "--seed", "5") == 0
    assert_same_data(out, tmp_path / "full.h5")


def test_resume_refuses_a_different_project(tmp_path, capsys):
    project = small_project(tmp_path)
    assert run(project, tmp_path / "a.h5", "--frames", "2") == 0
    assert run(project, tmp_path / "a.h5", "--frames", "3", "--seed", "9", "--resume") == 2
    assert "different project or seed" in capsys.readouterr().err


@pytest.mark.slow
def test_memory_stays_flat_over_200_frames(tmp_path):
    project_path = small_project(tmp_path)
    text = project_to_json(load_project(project_path))
    _, rss = peak_rss_per_frame("simcore.runs.runner.run_dataset", text, tmp_path,
                                tmp_path / "long.h5", n_frames=200, seed=1)
    growth = rss[-1] - rss[9]        # after warm-up (windows, caches) to the end
    assert growth < 50, f"peak RSS grew {growth:.1f} MiB over 190 frames"


def test_sweep_writes_one_dataset_per_variant_with_parameters(tmp_path):
    project = small_project(tmp_path)
    out = tmp_path / "sweep"
    assert main(["sweep", str(project), "--vary", "objects[1].pose.position_m[0]=2.0:2.5:0.5",
                 "--out", str(out), "--frames", "1"]) == 0
    index = json.loads((out / "sweep.json").read_text())
    assert [v["parameters"] for v in index["variants"]] == [
        {"objects[1].pose.position_m[0]": 2.0}, {"objects[1].pose.position_m[0]": 2.5}]
    for variant, x in zip(index["variants"], (2.0, 2.5), strict=True):
        with h5py.File(out / variant["file"]) as f:
            assert json.loads(f["meta"].attrs["sweep_parameters"]) == variant["parameters"]
            stored = json.loads(f["meta"].attrs["project_json"])
            assert stored["objects"][1]["pose"]["position_m"][0] == x
            assert f["poses/objects"][0, 1, 0, 3] == pytest.approx(x)


def test_duration_sets_frame_count(tmp_path):
    project = small_project(tmp_path)
    assert run(project, tmp_path / "d.h5", "--duration", "0.3") == 0
    with h5py.File(tmp_path / "d.h5") as f:
        np.testing.assert_allclose(f["time"][:], [0.0, 0.1, 0.2])


@pytest.mark.parametrize("workers", ["1", "2"])
def test_ctrl_c_stops_cleanly_with_a_valid_file(tmp_path, workers):
    import signal
    import subprocess
    import sys
    import time

    out = tmp_path / "sig.h5"
    proc = subprocess.Popen(
        [sys.executable, "-m", "simcore.cli", "run", str(example_path("office")), "--out",
         str(out), "--frames", "2000", "--quiet", "--workers", workers],
        stderr=subprocess.PIPE, text=True)
    # Interrupt once a few frames are on disk (the file grows ~0.7 MB per office frame),
    # however slow the machine is today.
    deadline = time.monotonic() + 300
    while time.monotonic() < deadline and proc.poll() is None:
        if out.exists() and out.stat().st_size > 3_000_000:
            break
        time.sleep(0.2)
    assert proc.poll() is None, "the run ended before it could be interrupted"
    proc.send_signal(signal.SIGINT)
    try:
        _, err = proc.communicate(timeout=120)
    except subprocess.TimeoutExpired:
        proc.kill()
        pytest.fail(f"no exit 120 s after SIGINT: {proc.communicate()[1][-2000:]}")
    assert proc.returncode == 130, err
    assert "continue with --resume" in err and "Traceback" not in err
    with h5py.File(out) as f:
        n = int(f["meta"].attrs["n_frames"])
        assert 0 < n < 2000
        assert f["time"].shape == (n,) and f["tof/depth"].shape[0] == n
