"""Per-frame writing cost of each writer, 1 to 16 concurrent writers into one Zarr store.

Each writer is a process that owns whole shards (as ``tofradar run --workers W`` assigns
them): it "computes" a frame by sleeping ``--engine-ms`` (a throttled engine, so that on a
small machine the writers, not the CPU, are what is measured), then writes the shard's
synthetic frames with :func:`simcore.io.zarr_writer.write_shard`, timing only the writing.
If writers got in each other's way (locks, a shared file, one process taking every frame),
the per-frame cost would grow with their number; the aggregate rate would stop growing.
Every frame's completion record is counted at the end.

    python benchmarks/bench_writers.py [--writers 1,2,4,8,16] [--s3]

``--s3`` writes to an S3-compatible server (moto, on 127.0.0.1) instead of a local folder.
"""

from __future__ import annotations

import argparse
import multiprocessing
import os
import socket
import statistics
import tempfile
import time
from typing import Any

import numpy as np

SHARD = 4                 # frames per shard
SHARDS_PER_WRITER = 3


def synthetic_frame(k: int) -> dict[str, tuple[np.ndarray, str]]:
    """A frame of ~0.4 MB: a ToF-sized image stack and radar ADC, values from ``k``."""
    rng = np.random.default_rng(k)
    return {"/time": (np.array([0.05 * k]), "s"),
            "/tof/depth": (rng.normal(2.0, 0.01, (171, 224)).astype(np.float32), "m"),
            "/tof/amplitude": (rng.normal(50, 3, (171, 224)).astype(np.float32), "DN"),
            "/radar/adc": (rng.normal(0, 0.01, (16, 3, 512)).astype(np.float32), "FS")}


def _writer(target: Any, shards: list[list[int]], engine_s: float, out: Any) -> None:
    from simcore.io.zarr_writer import write_shard

    costs = []
    # Writers start out of step, as workers of a real run do (frames take varying times).
    time.sleep(engine_s * SHARD * (hash(tuple(shards[0])) % 97) / 97)
    for frames in shards:
        batch = []
        for k in frames:
            time.sleep(engine_s)                 # the throttled engine
            batch.append((k, synthetic_frame(k), {}))
        t0 = time.perf_counter()
        write_shard(target, batch)
        costs.append((time.perf_counter() - t0) / len(frames))
    out.put(costs)


def measure(url: str, writers: int, engine_s: float,
            storage_options: dict[str, Any] | None) -> tuple[float, float, int]:
    """(median per-frame write cost in s, frames/s of all writers, frames complete)."""
    from simcore.io.zarr_writer import ZarrWriter, create_arrays, open_group

    n_total = writers * SHARDS_PER_WRITER * SHARD
    writer = ZarrWriter(url, project_json="{}", seed=0, overwrite=True, shard_frames=SHARD,
                        storage_options=storage_options)
    writer.missing(n_total)
    create_arrays(writer.group, synthetic_frame(0), {}, n_total=n_total, shard_frames=SHARD,
                  max_detections=1)
    target = writer.target()
    shards = writer.shards_of(range(n_total))
    ctx = multiprocessing.get_context("fork")
    results = ctx.Queue()
    procs = [ctx.Process(target=_writer, args=(target, shards[i::writers], engine_s, results))
             for i in range(writers)]
    t0 = time.perf_counter()
    for p in procs:
        p.start()
    costs = [c for _ in procs for c in results.get()]
    for p in procs:
        p.join()
    elapsed = time.perf_counter() - t0
    records = np.asarray(open_group(url, mode="r", storage_options=storage_options)
                         ["meta/frame_sha256"][:])
    return statistics.median(costs), n_total / elapsed, int(records.any(axis=1).sum())


def _moto() -> tuple[Any, dict[str, Any], str]:
    from moto.server import ThreadedMotoServer

    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    server = ThreadedMotoServer(ip_address="127.0.0.1", port=port, verbose=False)
    server.start()
    for key in ("AWS_ACCESS_KEY_ID", "AWS_SECRET_ACCESS_KEY"):
        os.environ.setdefault(key, "testing")
    os.environ.setdefault("AWS_DEFAULT_REGION", "us-east-1")
    options = {"endpoint_url": f"http://127.0.0.1:{port}"}
    import s3fs

    s3fs.S3FileSystem(**options).mkdir("bench")
    return server, options, "s3://bench"


def main() -> None:
    """Print the per-frame write cost per writer and the aggregate rate for each count."""
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--writers", default="1,2,4,8,16")
    ap.add_argument("--engine-ms", type=float, default=400.0,
                    help="simulated compute time per frame (ms)")
    ap.add_argument("--s3", action="store_true", help="write to a local moto S3 server")
    args = ap.parse_args()
    server, options = None, None
    with tempfile.TemporaryDirectory() as tmp:
        base = tmp
        if args.s3:
            server, options, base = _moto()
        print(f"store: {'S3 (moto)' if args.s3 else 'local folder'}; shards of {SHARD} frames; "
              f"engine throttled to {args.engine_ms:g} ms/frame")
        print("writers | write ms/frame/writer (median) | frames/s all writers | complete")
        for w in (int(x) for x in args.writers.split(",")):
            cost, rate, done = measure(f"{base}/w{w}.zarr", w, args.engine_ms / 1e3, options)
            print(f"{w:7d} | {cost * 1e3:30.1f} | {rate:20.1f} | "
                  f"{done}/{w * SHARDS_PER_WRITER * SHARD}", flush=True)
    if server is not None:
        server.stop()


if __name__ == "__main__":
    main()
