"""A/B: frames/s of ``tofradar run`` (the engine plus a dataset writer) vs ``Simulator.frames``.

Each measurement runs in a fresh process (imports not timed), alternating engine and
writers round by round, so that a loaded machine slows them alike; the ratios
``run / engine`` of each round are what to compare. Also printed: CPU time per frame (all
threads); on a machine whose cores are all busy, throughput follows the CPU a frame costs,
so ``engine CPU / run CPU`` is the ratio that load does not scramble.

    python benchmarks/bench_run.py [--frames 40] [--rounds 3] [--targets h5,zarr]
"""

from __future__ import annotations

import argparse
import json
import resource
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
    from simcore.runs.runner import run_dataset
    from simcore.scene.project_io import load_project, project_to_json

    project = load_project(PROJECT)
    t0 = time.perf_counter()
    run_dataset(project_to_json(project), PROJECT.parent, out, n_frames=n,
                seed=project.seed, workers=workers)
    return time.perf_counter() - t0


def _cpu_s() -> float:
    """CPU seconds of this process so far, all threads (user + system)."""
    usage = resource.getrusage(resource.RUSAGE_SELF)
    return usage.ru_utime + usage.ru_stime


def _child(argv: list[str]) -> None:
    kind, n = argv[0], int(argv[1])
    cpu0 = _cpu_s()
    seconds = _engine(n) if kind == "engine" else _run(n, argv[2], int(argv[3]))
    print(json.dumps({"seconds": seconds, "cpu_s": _cpu_s() - cpu0}))


def _measure(args: list[str]) -> tuple[float, float]:
    """(wall seconds, CPU seconds) of one measurement in a fresh process."""
    proc = subprocess.run([sys.executable, __file__, "--child", *args], check=True,
                          capture_output=True, text=True)
    result = json.loads(proc.stdout.strip().splitlines()[-1])
    return float(result["seconds"]), float(result["cpu_s"])


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
    cpu_ratios: dict[str, list[float]] = {}
    with tempfile.TemporaryDirectory() as tmp:
        for r in range(args.rounds):
            wall, cpu = _measure(["engine", str(n)])
            engine_fps, engine_cpu = n / wall, cpu / n
            line = [f"round {r}: engine {engine_fps:6.2f} frames/s "
                    f"{engine_cpu * 1e3:5.0f} ms CPU/frame"]
            for target in args.targets.split(","):
                out = str(Path(tmp) / f"run{r}.{target}")
                wall, cpu = _measure(["run", str(n), out, str(args.workers)])
                fps = n / wall
                ratios.setdefault(target, []).append(fps / engine_fps)
                cpu_ratios.setdefault(target, []).append(engine_cpu / (cpu / n))
                line.append(f"{target} {fps:6.2f} ({fps / engine_fps:.2f}x) "
                            f"{cpu / n * 1e3:5.0f} ms CPU ({engine_cpu * n / cpu:.2f}x)")
            print(" | ".join(line), flush=True)
    for target, values in ratios.items():
        print(f"{target}: median ratio run/engine {statistics.median(values):.2f} frames/s, "
              f"{statistics.median(cpu_ratios[target]):.2f} by CPU time, "
              f"over {len(values)} rounds")


if __name__ == "__main__":
    if len(sys.argv) > 1 and sys.argv[1] == "--child":
        _child(sys.argv[2:])
    else:
        main()
