"""A/B: frames/s of ``tofradar run`` (the engine plus a dataset writer) vs ``Simulator.frames``.

Each measurement runs in a fresh process (imports not timed), alternating engine and
writers round by round, so that a loaded machine slows them alike; the ratios
``run / engine`` of each round are what to compare.

    python benchmarks/bench_run.py [--frames 40] [--rounds 3] [--targets h5,zarr]
"""

from __future__ import annotations

import argparse
import json
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

PROJECT = Path(__file__).resolve().parents[1] / "resources" / "examples" / "office.json"


def _engine(n: int) -> float:
    """Seconds for ``n`` frames of Simulator.frames (with each frame's dataset items)."""
    from simcore.pipeline import Simulator
    from simcore.scene.project_io import load_project

    project = load_project(PROJECT)
    t0 = time.perf_counter()
    with Simulator(project, base_dir=PROJECT.parent) as sim:
        for frame in sim.frames(range(n)):
            frame.hdf5_items()
            frame.table_rows()
    return time.perf_counter() - t0


def _run(n: int, out: str, workers: int) -> float:
    """Seconds for ``run_dataset`` of ``n`` frames into ``out`` (as ``tofradar run``)."""
    from simcore.runner import run_dataset
    from simcore.scene.project_io import load_project, project_to_json

    project = load_project(PROJECT)
    t0 = time.perf_counter()
    run_dataset(project_to_json(project), PROJECT.parent, out, n_frames=n,
                seed=project.seed, workers=workers)
    return time.perf_counter() - t0


def _child(argv: list[str]) -> None:
    kind, n = argv[0], int(argv[1])
    seconds = _engine(n) if kind == "engine" else _run(n, argv[2], int(argv[3]))
    print(json.dumps({"seconds": seconds}))


def _measure(args: list[str]) -> float:
    proc = subprocess.run([sys.executable, __file__, "--child", *args], check=True,
                          capture_output=True, text=True)
    return float(json.loads(proc.stdout.strip().splitlines()[-1])["seconds"])


def main() -> None:
    """Alternate engine and writer runs; print frames/s and the ratio per round."""
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--frames", type=int, default=40)
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--targets", default="h5,zarr", help="comma list: h5, zarr, mcap")
    ap.add_argument("--workers", type=int, default=1)
    args = ap.parse_args()
    n = args.frames
    ratios: dict[str, list[float]] = {}
    with tempfile.TemporaryDirectory() as tmp:
        for r in range(args.rounds):
            engine_fps = n / _measure(["engine", str(n)])
            line = [f"round {r}: engine {engine_fps:6.2f} frames/s"]
            for target in args.targets.split(","):
                out = str(Path(tmp) / f"run{r}.{target}")
                fps = n / _measure(["run", str(n), out, str(args.workers)])
                ratios.setdefault(target, []).append(fps / engine_fps)
                line.append(f"{target} {fps:6.2f} ({fps / engine_fps:.2f}x)")
            print(" | ".join(line), flush=True)
    for target, values in ratios.items():
        print(f"{target}: median ratio run/engine {statistics.median(values):.2f} "
              f"over {len(values)} rounds")


if __name__ == "__main__":
    if len(sys.argv) > 1 and sys.argv[1] == "--child":
        _child(sys.argv[2:])
    else:
        main()
