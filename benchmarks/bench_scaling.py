"""How frame time grows with render resolution, chirps and antennas (office.json variants).

For each variant of the bundled office scene this prints the median frame time (frames
1..N after an untimed frame 0, the same loop as ``tofradar bench``), the CPU time per
frame, the IF synthesis and DSP stage medians, and the time of a full NUFFT synthesis of all
the frame's scatterers (no static-background re-use: the cost of an antenna edit or of a
moving rig). Variants:

* ``--what resolution``: radar facet grid 500×171, 1000×342 (default), 2000×684 and ToF
  supersampling 1, 2, 3 (render pixels and scatterers ∝ area);
* ``--what chirps``: 8, 16, 32, 64 chirps per frame;
* ``--what antennas``: 1 Tx with 2, 3, 4, 8 Rx (ULA), and 2 Tx × 4 Rx;
* ``--what moving``: the whole scene moving relative to the radar (rig on a slow dolly),
  the worst case for the synthesis (every scatterer transformed per chirp and pair);
* ``--what tolerance``: ``nufft_tolerance`` 1e-9 (the preset), 1e-6 and 1e-4 (single
  precision transforms), rig still and moving.

Run ``python benchmarks/bench_scaling.py --what chirps``; ``--json`` prints one JSON list.
"""

from __future__ import annotations

import argparse
import json
import time
from collections.abc import Iterator
from typing import Any

import numpy as np

from simcore.pipeline import Simulator
from simcore.resources import example_path
from simcore.scene import load_project
from simcore.scene.model import Project
from simcore.scene.radar_arrays import ula
from simcore.scene.radar_config import SPEED_OF_LIGHT
from simcore.sensors.radar import radar_scatterers
from simcore.sensors.radar.scene import RadarScene
from simcore.sensors.radar.synthesis import synthesize_if


def _with_radar(project: Project, **update: Any) -> Project:
    radar = project.rig.radar.model_copy(update=update)
    return project.model_copy(update={"rig": project.rig.model_copy(update={"radar": radar})})


def _with_tof(project: Project, **update: Any) -> Project:
    tof = project.rig.tof.model_copy(update=update)
    return project.model_copy(update={"rig": project.rig.model_copy(update={"tof": tof})})


def variants(project: Project, what: str) -> Iterator[tuple[str, Project]]:
    """(label, project) pairs of one scaling series."""
    half_lambda_mm = 0.5 * SPEED_OF_LIGHT / project.rig.radar.start_frequency_hz * 1e3
    if what == "resolution":
        for w, h in ((500, 171), (1000, 342), (2000, 684)):
            yield f"radar {w}x{h}", _with_radar(project, render_width=w, render_height=h)
        for s in (1, 2, 3):
            yield f"ToF supersampling {s}", _with_tof(project, supersampling=s)
    elif what == "chirps":
        for n in (8, 16, 32, 64):
            yield f"{n} chirps", _with_radar(project, chirps_per_frame=n)
    elif what == "antennas":
        for n in (2, 3, 4, 8):
            yield f"1 Tx x {n} Rx", _with_radar(project, rx=ula(n, half_lambda_mm))
        yield "2 Tx x 4 Rx", _with_radar(
            project, tx=ula(2, 4 * half_lambda_mm, prefix="tx", origin_mm=(-6.0, 0.0)),
            rx=ula(4, half_lambda_mm))
    elif what == "moving":
        yield "rig still", project
        motion = project.rig.motion.model_copy(update={"velocity_mps": (0.05, 0.0, 0.0)})
        yield "rig moving", project.model_copy(
            update={"rig": project.rig.model_copy(update={"motion": motion})})
    elif what == "tolerance":
        motion = project.rig.motion.model_copy(update={"velocity_mps": (0.05, 0.0, 0.0)})
        moving = project.model_copy(
            update={"rig": project.rig.model_copy(update={"motion": motion})})
        for tol in (1e-9, 1e-6, 1e-4):
            yield f"rig still, tol {tol:g}", _with_radar(project, nufft_tolerance=tol)
            yield f"rig moving, tol {tol:g}", _with_radar(moving, nufft_tolerance=tol)
    else:
        raise ValueError(f"unknown series {what!r}")


def measure(project: Project, frames: int) -> dict[str, Any]:
    """Median frame time, CPU per frame, stage medians and a full synthesis time."""
    path = example_path("office")
    with Simulator(project, base_dir=path.parent) as sim:
        sim.frame(0)
        walls, cpus, stages = [], [], {}
        frame = None
        for i in range(frames):
            c0, t0 = time.process_time(), time.perf_counter()
            frame = sim.frame((i + 1) % sim.n_frames)
            walls.append((time.perf_counter() - t0) * 1e3)
            cpus.append((time.process_time() - c0) * 1e3)
            for k, v in frame.timings_ms.items():
                stages.setdefault(k, []).append(v)
        assert frame is not None
        scatterers = radar_scatterers(RadarScene.from_project(project, frame.snapshot),
                                      frame.buffers["radar"], config=project.rig.radar,
                                      seed=sim.seed,
                                      see_through=frame.see_through.get("radar"))
        cfg = project.rig.radar
        full = []
        for _ in range(3):
            t0 = time.perf_counter()
            synthesize_if(scatterers, cfg)
            full.append((time.perf_counter() - t0) * 1e3)
        moving = int(np.count_nonzero(np.any(scatterers.velocities_mps != 0, axis=1)))
    return {
        "frame_ms": float(np.median(walls)),
        "cpu_ms": float(np.median(cpus)),
        "synthesis_ms": float(np.median(stages.get("radar_synthesis", [np.nan]))),
        "dsp_ms": float(np.median(stages.get("dsp", [np.nan]))),
        "render_radar_ms": float(np.median(stages.get("render_radar", [np.nan]))),
        "render_tof_ms": float(np.median(stages.get("render_tof", [np.nan]))),
        "full_synthesis_ms": min(full),
        "scatterers": len(scatterers),
        "moving": moving,
        "chirps": cfg.chirps_per_frame,
        "pairs": cfg.n_channels,
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--what", default="chirps",
                        choices=["resolution", "chirps", "antennas", "moving", "tolerance"])
    parser.add_argument("--frames", type=int, default=10)
    parser.add_argument("--json", action="store_true")
    args = parser.parse_args()
    project = load_project(example_path("office"))
    rows = []
    for label, variant in variants(project, args.what):
        row = {"variant": label, **measure(variant, args.frames)}
        rows.append(row)
        if not args.json:
            print(f"{label:<22} frame {row['frame_ms']:7.1f} ms  CPU {row['cpu_ms']:7.1f} ms  "
                  f"synthesis {row['synthesis_ms']:6.1f}  DSP {row['dsp_ms']:5.1f}  "
                  f"render radar/ToF {row['render_radar_ms']:5.1f}/{row['render_tof_ms']:5.1f}"
                  f"  full NUFFT {row['full_synthesis_ms']:7.1f} ms  "
                  f"({row['scatterers']} scatterers, {row['moving']} moving, "
                  f"{row['chirps']} chirps x {row['pairs']} pairs)", flush=True)
    if args.json:
        print(json.dumps(rows))


if __name__ == "__main__":
    main()
