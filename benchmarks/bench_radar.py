"""Radar front end on a bundled project at its preset: time and error vs the direct sum.

Reports the scatterer count, the time of each stage (scatterers, NUFFT synthesis, receiver
chain), the NUFFT's relative error against the exact direct sum (on a random subset of the
scatterers for all chirps and channels, and on the whole scene for one chirp and channel),
and the speed-up over the direct sum, whose full cost is extrapolated from the subset
(the direct sum is linear in the number of scatterers). ``--all-moving`` gives every
scatterer the relative velocity of a rig moving at 0.3 m/s (the moving-scatterer path: one
2-D type-3 transform per Tx–Rx pair over all chirps, see ``docs/physics_radar.md``).
"""

from __future__ import annotations

import argparse
import dataclasses
import time
from collections.abc import Callable

import numpy as np

from simcore.render import RenderRequest, SceneRenderer
from simcore.resources import example_path
from simcore.scene import load_project
from simcore.scene.snapshot import take_snapshot
from simcore.sensors.radar import radar_scatterers
from simcore.sensors.radar.scene import RadarScene
from simcore.sensors.radar.synthesis import receiver_chain, synthesize_if, synthesize_if_direct


def best_of(fn: Callable[[], object], repeat: int) -> tuple[float, object]:
    times, result = [], None
    for _ in range(repeat):
        t0 = time.perf_counter()
        result = fn()
        times.append(time.perf_counter() - t0)
    return min(times), result


def error_db(fast: np.ndarray, ref: np.ndarray) -> float:
    return float(20 * np.log10(np.linalg.norm(fast - ref) / np.linalg.norm(ref)))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("project", nargs="?", default=str(example_path("office")))
    parser.add_argument("--subset", type=int, default=2000,
                        help="scatterers in the direct-sum subset")
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--all-moving", action="store_true",
                        help="give every scatterer the velocity of a rig moving at 0.3 m/s")
    parser.add_argument("--full-chirp", action="store_true",
                        help="also compare the whole scene on one chirp and channel")
    args = parser.parse_args()

    project = load_project(args.project)
    cfg = project.rig.radar
    renderer = SceneRenderer(project)
    snap = take_snapshot(project, 0.0)
    buffers = renderer.render(snap, RenderRequest("radar", "radar", cfg.render_intrinsics()))
    scene = RadarScene.from_project(project, snap)
    t_scat, _ = best_of(lambda: radar_scatterers(scene, buffers, config=cfg), args.repeat)
    scatterers = radar_scatterers(scene, buffers, config=cfg)
    if args.all_moving:
        scatterers = dataclasses.replace(
            scatterers, velocities_mps=scatterers.velocities_mps + np.array([0.0, 0.0, -0.3]))
    n = len(scatterers)
    moving = int(np.any(scatterers.velocities_mps != 0, axis=1).sum())
    print(f"{args.project}: preset {cfg.preset}, {cfg.chirps_per_frame} chirps × "
          f"{cfg.n_channels} channels × {cfg.samples_per_chirp} samples, render "
          f"{buffers.shape[1]}×{buffers.shape[0]}")
    print(f"  scatterers        {n} ({moving} moving)   {t_scat * 1e3:8.1f} ms")

    t_fast, ideal = best_of(lambda: synthesize_if(scatterers, cfg), args.repeat)
    assert isinstance(ideal, np.ndarray)
    t_rx, _ = best_of(lambda: receiver_chain(ideal, cfg, np.random.default_rng(0)),
                      args.repeat)
    print(f"  NUFFT synthesis                        {t_fast * 1e3:8.1f} ms")
    print(f"  receiver chain                         {t_rx * 1e3:8.1f} ms")

    rng = np.random.default_rng(0)
    subset = scatterers.subset(np.sort(rng.choice(n, size=min(args.subset, n), replace=False)))
    part = (lambda z: z) if cfg.complex_iq else np.real
    t_sub_fast, sub_fast = best_of(lambda: synthesize_if(subset, cfg), args.repeat)
    t_sub_direct, sub_direct = best_of(lambda: synthesize_if_direct(subset, cfg), 1)
    assert isinstance(sub_fast, np.ndarray) and isinstance(sub_direct, np.ndarray)
    err_sub = error_db(part(sub_fast), part(sub_direct))
    t_direct_full = t_sub_direct * n / len(subset)
    print(f"  direct sum, {len(subset)} scatterers            {t_sub_direct * 1e3:8.1f} ms "
          f"(NUFFT {t_sub_fast * 1e3:.1f} ms); error of NUFFT {err_sub:.1f} dB")
    print(f"  direct sum, all {n} (extrapolated)  {t_direct_full:8.1f} s")
    print(f"  speed-up of NUFFT synthesis over the direct sum: {t_direct_full / t_fast:,.0f}×")
    if args.full_chirp:
        one = cfg.model_copy(update={"chirps_per_frame": 1})
        t0 = time.perf_counter()
        ref = synthesize_if_direct(scatterers, one, chunk=4096)
        t_one = time.perf_counter() - t0
        err_full = error_db(part(ideal[:1]), part(ref))
        print(f"  whole scene, chirp 0, all channels: direct {t_one:.1f} s, "
              f"error of NUFFT {err_full:.1f} dB")
    renderer.close()


if __name__ == "__main__":
    main()
