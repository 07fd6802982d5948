"""Render time per pass (ToF and radar band) on a bundled project, at the radar's 1000×342."""

from __future__ import annotations

import argparse
import statistics
import time

from simcore.render import RenderRequest, SceneRenderer
from simcore.render.renderer import _IndexPass
from simcore.resources import example_path
from simcore.scene import load_project
from simcore.scene.snapshot import take_snapshot


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("project", nargs="?", default=str(example_path("office")))
    parser.add_argument("--frames", type=int, default=20)
    args = parser.parse_args()
    project = load_project(args.project)
    renderer = SceneRenderer(project)
    grids = {"tof": project.rig.tof.render_intrinsics(),
             "radar": project.rig.radar.render_intrinsics()}
    n_tri = len(renderer.geometry.triangles)
    print(f"{args.project}: {len(project.objects)} objects, {n_tri} triangles")
    for band, intr in grids.items():
        snap = take_snapshot(project, 0.0)
        request = RenderRequest(band, band, intr)
        renderer.render(snap, request)  # warm-up
        total, raster = [], []
        index_pass: _IndexPass = renderer._passes[band]
        for i in range(args.frames):
            snap = take_snapshot(project, i / project.timeline.frame_rate_hz)
            t0 = time.perf_counter()
            index_pass.render(intr, snap.sensor(band),
                              snap.object_transforms(), renderer.visible_in(band))
            t1 = time.perf_counter()
            renderer.render(snap, request)
            t2 = time.perf_counter()
            raster.append((t1 - t0) * 1e3)
            total.append((t2 - t1) * 1e3)
        print(f"  {band:5s} {intr.width}x{intr.height}: pass {statistics.median(total):7.1f} ms "
              f"(rasterise + read-back {statistics.median(raster):6.1f} ms, rest is float "
              f"shading in numpy)")
    renderer.close()


if __name__ == "__main__":
    main()
