"""ToF camera stage time (render buffers → depth) at the preset resolution on a project."""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np

from simcore.render import RenderRequest, SceneRenderer
from simcore.resources import example_path
from simcore.scene import load_project
from simcore.scene.snapshot import take_snapshot
from simcore.sensors.tof.camera import simulate_tof
from simcore.sensors.tof.sensor import diffuse_albedo, mirror_table, tof_bands


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("project", nargs="?", default=str(example_path("office")))
    parser.add_argument("--frames", type=int, default=30)
    parser.add_argument("--two-frequencies", action="store_true",
                        help="add a 16 MHz second modulation frequency (unwrapping)")
    args = parser.parse_args()
    project = load_project(args.project)
    cfg = project.rig.tof
    if args.two_frequencies:
        cfg = cfg.model_copy(update={"modulation_frequencies_hz":
                                     [cfg.modulation_frequencies_hz[0], 16e6]})
    renderer = SceneRenderer(project)
    grid = cfg.render_intrinsics()
    buffers = renderer.render(take_snapshot(project, 0.0), RenderRequest("tof", "tof", grid))
    renderer.close()
    albedo, mirrors = diffuse_albedo(tof_bands(project), buffers), mirror_table(tof_bands(project))
    print(f"{args.project}: ToF {cfg.width}x{cfg.height}, supersampling {cfg.supersampling} "
          f"(render {grid.width}x{grid.height}), f_mod {cfg.modulation_frequencies_hz} Hz")
    for noise in (True, False):
        simulate_tof(buffers, cfg, rng=np.random.default_rng(0), noise=noise, albedo=albedo,
                     mirrors=mirrors)  # warm-up
        times = []
        for i in range(args.frames):
            t0 = time.perf_counter()
            out = simulate_tof(buffers, cfg, rng=np.random.default_rng(i), noise=noise,
                               albedo=albedo, mirrors=mirrors)
            times.append((time.perf_counter() - t0) * 1e3)
        print(f"  tof stage (noise={noise!s:5s}): median {statistics.median(times):6.1f} ms, "
              f"min {min(times):6.1f} ms over {args.frames} frames; "
              f"valid {out.valid.mean():.1%}, saturated {out.saturated.sum()} px")


if __name__ == "__main__":
    main()
