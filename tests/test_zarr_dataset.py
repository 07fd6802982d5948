"""Zarr v3 datasets (issue #32): same bits as HDF5, workers writing their own shards,
concurrent writers, an S3-compatible server, SIGKILL of a worker and of the driver."""

from __future__ import annotations

import hashlib
import os
import socket
import subprocess
import sys
import threading
import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np
import pytest
import xarray as xr
from fresh_process import peak_rss_per_frame
from hostile import base_project_dict, write_project

from simcore.cli import main
from simcore.io import open_dataset
from simcore.io.zarr_writer import ZarrWriter, create_arrays, open_group, write_shard
from simcore.runs.runner import run_dataset
from simcore.scene import load_project
from simcore.scene.project_io import project_to_json

SEED = 4


def tiny_project(tmp_path: Path, frames: int = 8) -> Path:
    doc = base_project_dict()
    doc["timeline"] = {"frame_rate_hz": 20.0, "duration_s": frames / 20.0}
    return write_project(doc, tmp_path / "tiny.json")


def run(project: Path, out: str | Path, *extra: str) -> int:
    return main(["run", str(project), "--out", str(out), "--quiet", "--seed", str(SEED),
                 *extra])


def assert_same_dataset(a: Any, b: Any) -> None:
    """Every variable of ``a`` is in ``b`` with the same dims, units and bits.

    The per-frame detection slots are compared where both hold rows (HDF5 pads to the most
    rows seen, Zarr to ``max_detections``); the SHA-256 digests as bytes (HDF5 stores hex).
    """
    assert set(a.variables) == set(b.variables)
    for name in a.variables:
        x, y = a[name].values, b[name].values
        if name == "meta_frame_sha256":
            x = np.array([bytes.fromhex(v.decode()) for v in x])
            y = np.array([bytes(row) for row in y])
        else:
            assert a[name].dims == b[name].dims, name
            assert a[name].attrs.get("units") == b[name].attrs.get("units"), name
        if "_by_frame_" in name:
            y = y[:, : x.shape[1]]
        assert x.shape == y.shape and x.dtype == y.dtype, name
        if x.dtype.kind == "O":
            assert list(x) == list(y), name
        else:
            assert x.tobytes() == y.tobytes(), name


def test_same_seed_gives_the_same_bits_in_hdf5_and_zarr(tmp_path):
    project = tiny_project(tmp_path)
    assert run(project, tmp_path / "a.h5", "--frames", "5") == 0
    assert run(project, tmp_path / "a.zarr", "--frames", "5", "--shard-frames", "2") == 0
    h5, zr = open_dataset(tmp_path / "a.h5"), open_dataset(tmp_path / "a.zarr")
    assert_same_dataset(h5, zr)
    assert zr.attrs["n_frames"] == 5 and zr.attrs["seed"] == SEED
    assert zr.attrs["project_json"] == h5.attrs["project_json"]
    # Plain xarray names every dimension from the v3 dimension_names.
    tof = xr.open_zarr(tmp_path / "a.zarr", group="tof", consolidated=False)
    assert tof.depth.dims == ("frame", "row", "col") and tof.depth.attrs["units"] == "m"
    np.testing.assert_array_equal(tof.depth.values, h5.tof_depth.values)
    radar = xr.open_zarr(tmp_path / "a.zarr", group="radar", consolidated=False)
    assert radar.adc.dims == ("frame", "chirp", "channel", "sample")
    np.testing.assert_array_equal(radar.adc.values, h5.radar_adc.values)
    h5.close()


def test_people_arrays_have_the_same_dimension_names_and_bits_in_zarr(tmp_path):
    """The people layout (docs/dataset.md#people) names its dimensions in Zarr too."""
    from people_scenes import walker_project

    doc = walker_project(speed=1.0, heading_deg=180.0, distance_m=3.0, frames=2)
    doc["rig"]["radar"]["chirps_per_frame"] = 16
    project = write_project(doc, tmp_path / "walker.json")
    assert run(project, tmp_path / "p.h5", "--frames", "2") == 0
    assert run(project, tmp_path / "p.zarr", "--frames", "2") == 0
    zr = open_dataset(tmp_path / "p.zarr")
    assert zr.people_segments_pose.dims == ("frame", "segment", "pose_row", "pose_col")
    assert_same_dataset(open_dataset(tmp_path / "p.h5"), zr)


def test_shards_encoded_here_are_the_bytes_zarr_writes(tmp_path):
    """Known answer: zarr's own codecs. Shards of 4 frames over 10 frames (the last one
    partial): large float32 and bool arrays (sharded), small ones and a detection table
    (one chunk per shard), written once by the direct encoders and once by zarr (encoders
    switched off): every stored object has the same bytes."""
    from simcore.io.zarr_writer import ArrayCache, ShardEncoder, write_shard_arrays

    rng = np.random.default_rng(0)
    rows = np.dtype([("frame", "<i8"), ("range", "<f4"), ("object_id", "<i4")])

    def table(k: int) -> np.ndarray:
        out = np.zeros(k % 3, dtype=rows)
        out["frame"], out["range"], out["object_id"] = k, rng.random(k % 3), 7
        return out

    frames = [(k, {"/tof/depth": (rng.normal(2, .01, (80, 64)).astype(np.float32), "m"),
                   "/tof/valid": (rng.random((80, 64)) > .3, "1"),
                   "/radar/adc": (rng.normal(0, .01, (16, 3, 128)).astype(np.float32), "FS"),
                   "/poses/rig": (rng.normal(size=(4, 4)), "m"),
                   "/time": (np.asarray(0.05 * k), "s")},
               {"/radar/detections": table(k)}) for k in range(10)]
    stores = {}
    for name, direct in (("direct", True), ("zarr", False)):
        group = open_group(str(tmp_path / f"{name}.zarr"), mode="w")
        create_arrays(group, frames[0][1], frames[0][2], n_total=10, shard_frames=4,
                      max_detections=3)
        cache = ArrayCache(group)
        if direct:
            assert all(cache.encoder(p) is not None for p in ("/tof/depth", "/tof/valid",
                                                              "/radar/adc"))
            assert all(cache.block_encoder(p) is not None for p in (
                "/time", "/poses/rig", "/radar/detections_by_frame/range", "meta/frame_sha256"))
        else:                                    # the reference: zarr writes every array
            cache.encoder = lambda path: None              # type: ignore[method-assign]
            cache.block_encoder = lambda path: None        # type: ignore[method-assign]
        for start in (0, 4, 8):
            write_shard_arrays(cache, frames[start:start + 4], max_detections=3)
        stores[name] = {f.relative_to(tmp_path / f"{name}.zarr"): f.read_bytes()
                        for f in (tmp_path / f"{name}.zarr").rglob("*") if f.is_file()}
    assert stores["direct"].keys() == stores["zarr"].keys()
    assert Path("tof/depth/c/2/0/0") in stores["direct"]
    assert Path("radar/detections_by_frame/range/c/2/0") in stores["direct"]
    for key, data in stores["direct"].items():
        assert data == stores["zarr"][key], key
    stored = open_group(str(tmp_path / "direct.zarr"), mode="r")
    assert ShardEncoder.of(stored["time"]) is None
    np.testing.assert_array_equal(stored["radar/detections_count"][:], [k % 3 for k in range(10)])
    np.testing.assert_array_equal(stored["poses/rig"][9], frames[9][1]["/poses/rig"][0])


def test_workers_write_their_own_shards_bit_identically(tmp_path):
    project = tiny_project(tmp_path)
    assert run(project, tmp_path / "a.h5", "--frames", "7") == 0
    assert run(project, tmp_path / "w.zarr", "--frames", "7", "--shard-frames", "2",
               "--workers", "2") == 0
    assert_same_dataset(open_dataset(tmp_path / "a.h5"), open_dataset(tmp_path / "w.zarr"))


def test_dask_workers_write_their_own_shards(tmp_path):
    project = tiny_project(tmp_path)
    assert run(project, tmp_path / "a.h5", "--frames", "5") == 0
    assert run(project, tmp_path / "d.zarr", "--frames", "5", "--shard-frames", "2",
               "--workers", "2", "--scheduler", "local") == 0
    assert_same_dataset(open_dataset(tmp_path / "a.h5"), open_dataset(tmp_path / "d.zarr"))


def synthetic_frame(k: int) -> tuple[dict[str, tuple[np.ndarray, str]], dict[str, Any]]:
    """Frame ``k`` of a synthetic run: every value encodes the frame index."""
    image = (np.arange(24 * 32, dtype=np.float32).reshape(24, 32) + 1000.0 * k)
    items = {"/time": (np.array([0.05 * k]), "s"), "/tof/depth": (image, "m"),
             "/radar/adc": (np.full((4, 2, 16), k, dtype=np.float32), "FS")}
    return items, {}


def test_sixteen_concurrent_writers_lose_no_frame(tmp_path):
    """16 threads write disjoint shards into one store at once; every frame is there."""
    shard, n_total = 3, 16 * 3 * 2 - 1            # two shards per writer, the last one short
    writer = ZarrWriter(str(tmp_path / "c.zarr"), project_json="{}", seed=0, shard_frames=shard)
    assert writer.missing(n_total) == list(range(n_total))
    items0, tables0 = synthetic_frame(0)
    create_arrays(writer.group, items0, tables0, n_total=n_total, shard_frames=shard,
                  max_detections=4)
    target = writer.target()
    shards = writer.shards_of(range(n_total))
    barrier = threading.Barrier(16)
    errors: list[BaseException] = []

    def worker(mine: list[list[int]]) -> None:
        try:
            barrier.wait()
            for frames in mine:
                write_shard(target, [(k, *synthetic_frame(k)) for k in frames])
        except BaseException as exc:  # noqa: BLE001 — reported by the test
            errors.append(exc)

    threads = [threading.Thread(target=worker, args=(shards[i::16],)) for i in range(16)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert not errors
    writer.mark_complete(range(n_total))
    group = open_group(str(tmp_path / "c.zarr"), mode="r")
    assert group.attrs["n_frames"] == n_total
    depth, adc = group["tof/depth"][:], group["radar/adc"][:]
    records = group["meta/frame_sha256"][:]
    for k in range(n_total):
        items, _ = synthetic_frame(k)
        np.testing.assert_array_equal(depth[k], items["/tof/depth"][0], err_msg=str(k))
        assert (adc[k] == k).all()
        assert records[k].any(), f"frame {k} has no completion record"
    assert len({bytes(r) for r in records}) == n_total      # each frame its own checksum


def test_resume_after_a_stop_recomputes_only_incomplete_shards(tmp_path):
    project_path = tiny_project(tmp_path)
    text = project_to_json(load_project(project_path))
    assert run(project_path, tmp_path / "full.h5", "--frames", "7") == 0

    def stop_after_first_shard(done: int, total: int, result: object) -> bool:
        return done < 2

    out = tmp_path / "part.zarr"
    report = run_dataset(text, project_path.parent, out, n_frames=7, seed=SEED,
                         on_frame=stop_after_first_shard, shard_frames=2)
    assert report.interrupted and report.frames_done == 2
    assert open_group(str(out), mode="r").attrs["n_frames"] == 2
    assert run(project_path, out, "--frames", "7", "--resume") == 0
    assert_same_dataset(open_dataset(tmp_path / "full.h5"), open_dataset(out))


def test_existing_store_needs_overwrite_or_resume(tmp_path, capsys):
    project = tiny_project(tmp_path)
    assert run(project, tmp_path / "a.zarr", "--frames", "2") == 0
    assert run(project, tmp_path / "a.zarr", "--frames", "2") == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "already exists" in err[0]
    assert run(project, tmp_path / "a.zarr", "--frames", "3", "--seed", "9", "--resume") == 2
    assert "different project or seed" in capsys.readouterr().err
    assert run(project, tmp_path / "a.zarr", "--frames", "3", "--overwrite") == 0


# ---------------------------------------------------------------------- S3 (moto server)
def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


@pytest.fixture
def s3(monkeypatch) -> Iterator[tuple[str, str]]:
    """An S3-compatible server (moto) on 127.0.0.1 with an empty bucket: (endpoint, bucket)."""
    pytest.importorskip("s3fs")
    server_mod = pytest.importorskip("moto.server")
    port = _free_port()
    server = server_mod.ThreadedMotoServer(ip_address="127.0.0.1", port=port, verbose=False)
    server.start()
    for key, value in {"AWS_ACCESS_KEY_ID": "testing", "AWS_SECRET_ACCESS_KEY": "testing",
                       "AWS_DEFAULT_REGION": "us-east-1"}.items():
        monkeypatch.setenv(key, value)
    endpoint = f"http://127.0.0.1:{port}"
    import s3fs

    bucket = f"runs-{port}"         # moto keeps buckets across servers of one process
    s3fs.S3FileSystem(endpoint_url=endpoint).mkdir(bucket)
    try:
        yield endpoint, bucket
    finally:
        server.stop()


def cli(*args: str) -> list[str]:
    return [sys.executable, "-m", "simcore.cli", *args]


def s3_n_frames(url: str, endpoint: str) -> int:
    try:
        return int(open_group(url, mode="r", storage_options={"endpoint_url": endpoint})
                   .attrs.get("n_frames", 0))
    except Exception:  # noqa: BLE001 — not created yet
        return 0


def test_s3_write_and_resume_through_the_users_code_path(tmp_path, s3):
    s3, bucket = s3
    project = tiny_project(tmp_path)
    assert run(project, tmp_path / "ref.h5", "--frames", "5") == 0
    url = f"s3://{bucket}/stop.zarr"
    text = project_to_json(load_project(project))
    report = run_dataset(text, project.parent, url, n_frames=5, seed=SEED,
                         on_frame=lambda done, total, r: done < 2, shard_frames=2,
                         storage_options={"endpoint_url": s3})
    assert report.frames_done == 2
    # The endpoint from the environment, as a user of an S3-compatible store sets it.
    env = {**os.environ, "TOFRADAR_S3_ENDPOINT": s3}
    proc = subprocess.run(cli("run", str(project), "--out", url, "--frames", "5", "--seed",
                              str(SEED), "--quiet", "--resume"), env=env, capture_output=True,
                          text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr
    ds = open_dataset(url, storage_options={"endpoint_url": s3})
    assert_same_dataset(open_dataset(tmp_path / "ref.h5"), ds)


@pytest.mark.slow
def test_sigkill_of_driver_and_worker_on_s3_then_resume_is_bit_identical(tmp_path, s3):
    """Kill the driver of an in-process run, a worker of a two-worker run, and the driver
    of a two-worker run, each followed by --resume; the store ends complete and equal."""
    psutil = pytest.importorskip("psutil")
    s3, bucket = s3
    frames = 12
    project = tiny_project(tmp_path, frames)
    assert run(project, tmp_path / "ref.h5", "--frames", str(frames)) == 0
    url = f"s3://{bucket}/crash.zarr"
    base = cli("run", str(project), "--out", url, "--frames", str(frames), "--seed",
               str(SEED), "--quiet", "--shard-frames", "2", "--storage-option",
               f"endpoint_url={s3}")
    # 1. The driver (writing in-process) is killed once a shard is committed.
    proc = subprocess.Popen(base, stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 300
    while proc.poll() is None and s3_n_frames(url, s3) < 2 and time.monotonic() < deadline:
        time.sleep(0.05)
    assert proc.poll() is None, "the run ended before the driver could be killed"
    proc.kill()
    proc.wait()
    killed_at = s3_n_frames(url, s3)
    assert 2 <= killed_at < frames
    # 2. Resumed with two workers; one worker is killed while shards are written.
    proc = subprocess.Popen([*base, "--resume", "--workers", "2"], stderr=subprocess.PIPE,
                            text=True)
    workers: list[Any] = []
    while proc.poll() is None and time.monotonic() < deadline and not workers:
        workers = [c for c in psutil.Process(proc.pid).children()
                   if "spawn_main" in " ".join(c.cmdline())]
        time.sleep(0.05)
    assert workers, "no worker process to kill"
    time.sleep(1.0)
    workers[0].kill()
    _, err = proc.communicate(timeout=300)
    if proc.returncode != 0:          # the usual case: the pool broke, one clear message
        lines = err.strip().splitlines()
        assert proc.returncode == 2 and len(lines) == 1, err
        assert "worker process died" in lines[0] and "--resume" in lines[0]
    # 2b. Resumed with two workers again; this time the driver is killed while its workers
    #     write shards: the workers die with it (none goes on writing beside step 3).
    if s3_n_frames(url, s3) < frames:
        proc = subprocess.Popen([*base, "--resume", "--workers", "2"],
                                stderr=subprocess.PIPE, text=True)
        workers = []
        while proc.poll() is None and time.monotonic() < deadline and not workers:
            workers = [c for c in psutil.Process(proc.pid).children()
                       if "spawn_main" in " ".join(c.cmdline())]
            time.sleep(0.05)
        if workers:
            time.sleep(1.0)
            proc.kill()
            proc.wait()
            gone, alive = psutil.wait_procs(workers, timeout=20)
            assert not alive, f"workers outlived the killed driver: {alive}"
        else:
            proc.wait()
    # 3. Resumed again: complete and bit-identical to the uninterrupted run.
    proc3 = subprocess.run([*base, "--resume"], capture_output=True, text=True, timeout=300)
    assert proc3.returncode == 0, proc3.stderr
    ds = open_dataset(url, storage_options={"endpoint_url": s3})
    assert ds.attrs["n_frames"] == frames
    assert_same_dataset(open_dataset(tmp_path / "ref.h5"), ds)
    digest = hashlib.sha256(ds.tof_depth.values.tobytes()).hexdigest()
    assert digest == hashlib.sha256(open_dataset(tmp_path / "ref.h5").tof_depth.values
                                    .tobytes()).hexdigest()


@pytest.mark.slow
def test_memory_stays_flat_over_200_frames_into_zarr(tmp_path):
    project_path = tiny_project(tmp_path)
    text = project_to_json(load_project(project_path))
    report, rss = peak_rss_per_frame("simcore.runs.runner.run_dataset", text, project_path.parent,
                                     tmp_path / "long.zarr", n_frames=200, seed=1,
                                     shard_frames=16)
    assert report.frames_done == 200
    growth = rss[-1] - rss[31]       # after two shards (warm-up) to the end
    assert growth < 50, f"peak RSS grew {growth:.1f} MiB over 168 frames"


def test_overwrite_never_deletes_a_folder_that_is_not_a_tofradar_store(tmp_path, capsys):
    project = tiny_project(tmp_path)
    folder = tmp_path / "photos.zarr"
    folder.mkdir()
    (folder / "holiday.jpg").write_bytes(b"precious")
    assert run(project, f"file://{folder}", "--frames", "1", "--overwrite") == 2
    assert "not a tofradar Zarr store" in capsys.readouterr().err
    assert (folder / "holiday.jpg").read_bytes() == b"precious"
