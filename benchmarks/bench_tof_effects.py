"""ToF stage with every effect on: CPU time of ``simulate_tof`` on recorded frames.

Runs the project (default: the bundled office) with every ToF and radar effect switch on
(:func:`simcore.bench.with_effects`, motion artefacts by reprojection) for ``--frames``
frames, records what the ToF stage was given, then calls ``simulate_tof`` on those inputs
again ``--rounds`` times in frame order (so the multipath reuse across frames works as in a
run) and prints the median CPU time of the calling thread per frame. CPU time, not wall
time: on a machine shared with other jobs it is the steadier measure of the stage's own
cost (the kernels are single-threaded). For an A/B, run it from two checkouts one after
the other, alternating.
"""

from __future__ import annotations

import argparse
import statistics
import time
from pathlib import Path
from typing import Any

import numpy as np

import simcore.sensors.tof.sensor as tof_sensor
from simcore.bench import with_effects
from simcore.pipeline import Simulator
from simcore.resources import example_path
from simcore.scene import load_project
from simcore.sensors.tof.camera import simulate_tof


def record(project_path: Path, frames: int) -> list[tuple[tuple[Any, ...], dict[str, Any]]]:
    """The arguments of every ``simulate_tof`` call of ``frames`` frames (rng left out)."""
    calls: list[tuple[tuple[Any, ...], dict[str, Any]]] = []
    original = tof_sensor.simulate_tof

    def spy(*args: Any, **kwargs: Any) -> Any:
        calls.append((args, {k: v for k, v in kwargs.items() if k != "rng"}))
        return original(*args, **kwargs)

    project = with_effects(load_project(project_path), on=True)
    tof_sensor.simulate_tof = spy
    try:
        with Simulator(project, base_dir=project_path.parent) as sim:
            for i in range(frames):
                sim.frame(i % max(sim.n_frames, 1))
    finally:
        tof_sensor.simulate_tof = original
    return calls


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("project", nargs="?", default=str(example_path("office")))
    parser.add_argument("--frames", type=int, default=6)
    parser.add_argument("--rounds", type=int, default=4)
    args = parser.parse_args()
    calls = record(Path(args.project), args.frames)
    times: list[float] = []
    for r in range(args.rounds + 1):            # round 0 warms up (compiled kernels, caches)
        for call_args, kwargs in calls:
            t0 = time.thread_time()
            simulate_tof(*call_args, rng=np.random.default_rng(0), **kwargs)
            if r:
                times.append(time.thread_time() - t0)
    print(f"{args.project}: every effect on, {len(calls)} frames x {args.rounds} rounds: "
          f"simulate_tof CPU median {statistics.median(times) * 1e3:.1f} ms, "
          f"min {min(times) * 1e3:.1f} ms per frame")


if __name__ == "__main__":
    main()
