"""Crash safety of datasets (issue #19): SIGKILL at random moments, SIGTERM, failing
overwrites and a full disk; ``--resume`` must give the uninterrupted run bit for bit."""

from __future__ import annotations

import multiprocessing
import os
import random
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path
from typing import Any

import h5py
import numpy as np
import pytest
from h5data import assert_same_data, datasets
from hostile import base_project_dict, write_project

from simcore.cli import main
from simcore.io.hdf5_writer import CHECKSUM_PATH, frame_checksum, temporary_path
from simcore.runs.runner import run_dataset
from simcore.scene import load_project
from simcore.scene.project_io import project_to_json

FRAMES = 40
SEED = 3
#: SIGKILLs of the crash test (the issue asks for at least 20).
KILLS = int(os.environ.get("TOFRADAR_CRASH_KILLS", "20"))


def small_project(tmp_path: Path) -> Path:
    doc = base_project_dict()
    doc["timeline"] = {"frame_rate_hz": 20.0, "duration_s": FRAMES / 20.0}
    return write_project(doc, tmp_path / "crash.json")




def assert_frames_intact(path: Path, reference: dict[str, np.ndarray]) -> int:
    """Every frame the file counts equals the reference; returns that count."""
    with h5py.File(path, "r") as f:
        n = int(f["meta"].attrs["n_frames"])
        assert n >= 1, "a file in place holds at least one frame"
        for name, ref in reference.items():
            if name == "radar/detections":
                continue     # rebuilt from the per-frame rows when a run ends cleanly
            ds = f[name]
            if ds.attrs.get("per_frame", False) and not ds.attrs.get("table_rows", False):
                assert ds.shape[0] >= n, name
                np.testing.assert_array_equal(ds[:n], ref[:n], err_msg=name)
        for k in range(n):
            rows = int(f["radar/detections_count"][k])
            np.testing.assert_array_equal(f["radar/detections_by_frame"][k, :rows],
                                          reference["radar/detections_by_frame"][k, :rows])
            assert f[CHECKSUM_PATH][k] == reference[CHECKSUM_PATH.lstrip("/")][k]
    return n


def cli(*args: str) -> list[str]:
    return [sys.executable, "-m", "simcore.cli", *args]


#: Children of a fork server: no interpreter start-up per kill, and each starts from a clean
#: process that has imported the CLI but never rendered or computed. A plain fork of the test
#: process would inherit its OpenGL, OpenMP and thread-pool state (threads do not survive a
#: fork; a child that waits on one hangs).
FORK = multiprocessing.get_context("forkserver")
FORK.set_forkserver_preload(["simcore.cli"])


def run_quietly(argv: list[str]) -> None:
    """Child process: run the CLI with its output discarded; exit with its status."""
    devnull = os.open(os.devnull, os.O_WRONLY)
    os.dup2(devnull, 1)
    os.dup2(devnull, 2)
    os._exit(main(argv))


def wait_for_phase(proc: Any, out: Path, phase: str, rng: random.Random) -> None:
    """Return at a random moment of ``phase`` of a run (or when the run has ended)."""
    start_size = out.stat().st_size if out.exists() else 0
    grow = rng.uniform(0, 800_000)          # ≈ 0 to 8 frames of this project
    deadline = time.monotonic() + 120

    def reached() -> bool:
        if phase == "start":
            return True
        if phase == "partial":
            return temporary_path(out).exists() or out.exists()
        return out.exists() and out.stat().st_size >= start_size + grow

    while not reached() and proc.is_alive() and time.monotonic() < deadline:
        time.sleep(0.005)
    time.sleep(rng.uniform(0.0, 0.3) if phase == "start" else rng.uniform(0, 0.2))


def test_sigkill_at_random_moments_then_resume_is_bit_identical(tmp_path):
    project = small_project(tmp_path)
    reference_path = tmp_path / "reference.h5"
    assert main(["run", str(project), "--out", str(reference_path), "--seed", str(SEED),
                 "--quiet"]) == 0
    reference = datasets(reference_path)
    out = tmp_path / "crash.h5"
    rng = random.Random(1919)
    kills, completed, seen = 0, 0, []
    while kills < KILLS or completed == 0:
        resume = ["--resume"] if out.exists() else []
        # A child of the fork server runs the CLI (the resume check runs in it as in real use).
        proc = FORK.Process(target=run_quietly, args=(["run", str(project), "--out", str(out),
                                                       "--seed", str(SEED), "--quiet",
                                                       *resume],))
        proc.start()
        if kills < KILLS:
            # Kill in a random phase: start-up, file creation, frames (or the resume check).
            phase = rng.choice(["start", "partial", "frames", "frames", "frames"])
            wait_for_phase(proc, out, phase, rng)
        if kills < KILLS and proc.is_alive():
            proc.kill()
            proc.join()
            kills += 1
            seen.append(assert_frames_intact(out, reference) if out.exists() else 0)
            if rng.random() < 0.25:
                out.unlink(missing_ok=True)     # a fresh start: kills before the first frame
            continue
        proc.join(timeout=300)
        if proc.is_alive():
            proc.kill()
            pytest.fail("a run of 40 frames did not end in 300 s")
        assert proc.exitcode == 0, proc.exitcode
        completed += 1
        assert_same_data(out, reference_path)
        if kills < KILLS:
            out.unlink()          # again from the start: more kills in early phases
    # The kills landed in several phases: before the first frame and between/inside frames.
    assert 0 in seen and len(set(seen)) >= 3, seen
    print(f"{kills} SIGKILLs, frames on disk at each kill: {seen}; {completed} completed runs")


def test_sigterm_stops_as_cleanly_as_sigint(tmp_path):
    project = small_project(tmp_path)
    out = tmp_path / "term.h5"
    proc = subprocess.Popen(cli("run", str(project), "--out", str(out), "--frames", "100000",
                                "--quiet"), stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 300
    while time.monotonic() < deadline and proc.poll() is None and not out.exists():
        time.sleep(0.05)
    assert proc.poll() is None, "the run ended before it could be stopped"
    proc.send_signal(signal.SIGTERM)
    try:
        _, err = proc.communicate(timeout=120)
    except subprocess.TimeoutExpired:
        proc.kill()
        pytest.fail("no exit 120 s after SIGTERM")
    assert proc.returncode == 130, err
    assert "continue with --resume" in err and "Traceback" not in err
    with h5py.File(out, "r") as f:
        n = int(f["meta"].attrs["n_frames"])
        assert 0 < n < 100000
        assert f["time"].shape == (n,) and f["tof/depth"].shape[0] == n
        assert f["radar/detections_count"].shape == (n,)
        det = f["radar/detections"][()]
        assert len(det) == int(f["radar/detections_count"][()].sum())
    assert not temporary_path(out).exists()


def test_failing_overwrite_leaves_the_old_file_byte_identical(tmp_path):
    project_path = small_project(tmp_path)
    out = tmp_path / "old.h5"
    assert main(["run", str(project_path), "--out", str(out), "--frames", "2",
                 "--quiet"]) == 0
    before = out.read_bytes()

    def fail_at_three(done: int, total: int, result: object) -> bool:
        if done == 3:
            raise RuntimeError("injected failure")
        return True

    text = project_to_json(load_project(project_path))
    with pytest.raises(RuntimeError, match="injected"):
        run_dataset(text, tmp_path, out, n_frames=6, seed=1, overwrite=True,
                    on_frame=fail_at_three)
    assert out.read_bytes() == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["crash.json", "old.h5"]
    # A successful overwrite replaces it.
    assert main(["run", str(project_path), "--out", str(out), "--frames", "3", "--quiet",
                 "--overwrite"]) == 0
    with h5py.File(out, "r") as f:
        assert f["meta"].attrs["n_frames"] == 3


def test_checksums_cover_every_frame_and_resume_drops_a_damaged_one(tmp_path):
    project_path = small_project(tmp_path)
    out = tmp_path / "sum.h5"
    assert main(["run", str(project_path), "--out", str(out), "--frames", "4", "--quiet"]) == 0
    with h5py.File(out, "a") as f:
        per_frame = {"/" + n: o for n, o in _walk(f) if o.attrs.get("per_frame", False)}
        for k in range(4):
            arrays = [(p, ds[k]) for p, ds in per_frame.items()
                      if p != CHECKSUM_PATH and not ds.attrs.get("table_rows", False)]
            rows = int(f["radar/detections_count"][k])
            arrays.append(("/radar/detections_by_frame",
                           f["radar/detections_by_frame"][k, :rows]))
            assert frame_checksum(arrays).encode() == f[CHECKSUM_PATH][k]
        f["tof/depth"][2, 0, 0] += 1.0          # damage frame 2
    assert main(["run", str(project_path), "--out", str(out), "--frames", "5", "--quiet",
                 "--resume"]) == 0
    assert_same_data_frames(out, project_path, tmp_path, frames=5)


def _walk(f: h5py.File) -> list[tuple[str, h5py.Dataset]]:
    found: list[tuple[str, h5py.Dataset]] = []
    f.visititems(lambda n, o: found.append((n, o)) if isinstance(o, h5py.Dataset) else None)
    return found


def assert_same_data_frames(out: Path, project_path: Path, tmp_path: Path, frames: int) -> None:
    ref = tmp_path / "ref_frames.h5"
    assert main(["run", str(project_path), "--out", str(ref), "--frames", str(frames),
                 "--quiet"]) == 0
    assert_same_data(out, ref)


def test_unopenable_file_is_a_clear_resume_error(tmp_path, capsys):
    project_path = small_project(tmp_path)
    out = tmp_path / "junk.h5"
    out.write_bytes(b"\x89HDF\r\n\x1a\n" + os.urandom(4000))
    assert main(["run", str(project_path), "--out", str(out), "--frames", "2", "--quiet",
                 "--resume"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("tofradar: error: cannot resume") and err.count("\n") == 1, err


@pytest.fixture
def tiny_disk(tmp_path):
    """A 1.2 MB tmpfs (root only); skipped where mounting is not allowed."""
    if os.geteuid() != 0 or shutil.which("mount") is None:
        pytest.skip("mounting a small tmpfs needs root")
    mnt = tmp_path / "disk"
    mnt.mkdir()
    proc = subprocess.run(["mount", "-t", "tmpfs", "-o", "size=1200k", "tmpfs", str(mnt)],
                          capture_output=True, text=True)
    if proc.returncode != 0:
        pytest.skip(f"cannot mount a tmpfs here: {proc.stderr.strip()}")
    yield mnt
    subprocess.run(["umount", "-l", str(mnt)], capture_output=True)


def test_full_disk_is_one_message_and_a_resumable_file(tmp_path, tiny_disk):
    project = small_project(tmp_path)
    out = tiny_disk / "full.h5"
    proc = subprocess.run(cli("run", str(project), "--out", str(out), "--quiet", "--force",
                              "--seed", str(SEED)),
                          capture_output=True, text=True, timeout=300)
    assert proc.returncode == 2, proc.stderr
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("tofradar: error: disk full"), proc.stderr
    assert "--resume" in lines[0]
    reference_path = tmp_path / "reference.h5"
    assert main(["run", str(project), "--out", str(reference_path), "--seed", str(SEED),
                 "--quiet"]) == 0
    n = assert_frames_intact(out, datasets(reference_path))
    assert 0 < n < FRAMES
    subprocess.run(["mount", "-o", "remount,size=20m", str(tiny_disk)], check=True)
    assert main(["run", str(project), "--out", str(out), "--seed", str(SEED), "--quiet",
                 "--resume"]) == 0
    assert_same_data(out, reference_path)


def test_a_killed_worker_process_is_one_message_and_a_valid_file(tmp_path):
    psutil = pytest.importorskip("psutil")
    project = small_project(tmp_path)
    out = tmp_path / "workers.h5"
    proc = subprocess.Popen(cli("run", str(project), "--out", str(out), "--frames", "100000",
                                "--quiet", "--workers", "2"), stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 300
    while time.monotonic() < deadline and proc.poll() is None and not out.exists():
        time.sleep(0.05)
    assert proc.poll() is None, "the run ended before a worker could be killed"
    workers = [c for c in psutil.Process(proc.pid).children()
               if "spawn_main" in " ".join(c.cmdline())]
    assert workers
    workers[0].kill()
    try:
        _, err = proc.communicate(timeout=120)
    except subprocess.TimeoutExpired:
        proc.kill()
        pytest.fail("no exit 120 s after a worker was killed")
    lines = err.strip().splitlines()
    assert proc.returncode == 2 and len(lines) == 1, err
    assert lines[0].startswith("tofradar: error: a worker process died") and "--resume" in err
    with h5py.File(out, "r") as f:
        n = int(f["meta"].attrs["n_frames"])
        assert n >= 1 and f["time"].shape == (n,)


def test_a_worker_dying_mid_result_breaks_the_pool_instead_of_hanging():
    """A worker killed while it sends a result leaves half a message in the result pipe.

    CPython 3.11's pool then waits for the rest of it for ever (what a CI run of
    ``test_a_killed_worker_process_is_one_message_and_a_valid_file`` once hit: no exit
    120 s after the kill). The runner's wait notices the dead worker and breaks the pool.
    """
    import struct
    from concurrent.futures import ProcessPoolExecutor
    from concurrent.futures.process import BrokenProcessPool

    from simcore.runs.runner import _pool_result

    pool = ProcessPoolExecutor(max_workers=2, mp_context=multiprocessing.get_context("spawn"))
    try:
        assert list(pool.map(abs, [-1, -2])) == [1, 2]          # both workers up
        fut = pool.submit(time.sleep, 5)
        time.sleep(0.3)
        # Half a message (a 1000-byte header, 10 bytes of it), then its sender dies.
        writer = pool._result_queue._writer
        os.write(writer.fileno(), struct.pack("!i", 1000) + b"0123456789")
        time.sleep(0.3)
        os.kill(next(iter(pool._processes)), signal.SIGKILL)
        with pytest.raises(BrokenProcessPool) as broken:
            _pool_result(pool, fut)
        # The pool broke by itself once the pipe was closed (its own message), not by the
        # runner's 30 s fallback ("a worker process died"); a hang meets the test timeout.
        assert str(broken.value) != "a worker process died", broken.value
    finally:
        for p in list(pool._processes.values()):
            p.kill()
        pool.shutdown(wait=True)
