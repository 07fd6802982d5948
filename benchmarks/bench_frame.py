"""Whole-frame benchmark over the bundled examples (``tofradar bench`` for each of them).

Prints, per project, the median frame time and rate, the CPU time per frame, the stage
medians, the IF synthesis error and speed-up against the direct sum and the antenna-edit
latency (:func:`simcore.bench.run_benchmark`). ``--json`` prints one JSON object keyed by
project name. The machine's load average is printed with each result: other jobs on a
shared machine change the timings, so compare runs only at similar load, or A/B.
"""

from __future__ import annotations

import argparse
import json

from simcore.bench import run_benchmark
from simcore.resources import EXAMPLES_DIR


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("projects", nargs="*",
                        help="project files (default: every bundled example)")
    parser.add_argument("--frames", type=int, default=30)
    parser.add_argument("--json", action="store_true")
    args = parser.parse_args()
    paths = args.projects or sorted(str(p) for p in EXAMPLES_DIR.glob("*.json"))
    results = {}
    for path in paths:
        r = run_benchmark(path, frames=args.frames)
        results[path] = r
        if args.json:
            continue
        stages = ", ".join(f"{k} {v:.1f}" for k, v in r["stages_ms"].items())
        print(f"{path}: {r['frame_ms_median']:.1f} ms/frame ({r['fps']:.1f} frames/s), CPU "
              f"{r['cpu_ms_median']:.1f} ms/frame; {stages} ms; IF error {r['if_error_db']:.1f}"
              f" dB, speed-up {r['if_speedup']:.0f}x; antenna edit {r['antenna_edit_ms']:.1f} "
              f"ms; {r['scatterers']} scatterers ({r['scatterers_moving']} moving, "
              f"{r['scatterers_transformed']:.0f} transformed per frame); load "
              f"{r['machine']['load_before']}", flush=True)
    if args.json:
        print(json.dumps(results))


if __name__ == "__main__":
    main()
