"""``tofradar bench``: frame time per pipeline stage."""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path
from typing import Any

from simcore.cli.common import (
    _Parser,
    _positive_int,
    _preflight,
)
from simcore.scene.project_io import load_project


def cmd_bench(args: argparse.Namespace) -> int:
    """Time every pipeline stage over a number of frames; IF accuracy and GUI latency."""
    from simcore.bench import run_benchmark
    from simcore.resources import example_path

    project_path = Path(args.project) if args.project else example_path("office")
    # Report a bad file before anything starts.
    _preflight(load_project(project_path), project_path, args)
    result = run_benchmark(project_path, frames=args.frames)
    people = _people_speed(project_path, args.frames)
    if people is not None:
        result["people"] = people
    variants = None
    if args.effects:
        from simcore.bench import effect_variants

        variants = effect_variants(project_path, frames=args.frames)
    rigs = None
    if args.rigs:
        from simcore.bench import rig_variants

        rigs = rig_variants(project_path, frames=args.frames)
    kinds = None
    if args.sensors:
        from simcore.bench import sensor_variants

        kinds = sensor_variants(project_path, frames=args.frames)
        if kinds is None:
            print("bench --sensors: the project lacks ToF cameras or radars; nothing to "
                  "leave out", file=sys.stderr)
    if args.json:
        if variants is not None:
            result["effects"] = variants
        if rigs is not None:
            result["rigs"] = rigs
        if kinds is not None:
            result["sensor_variants"] = kinds
        print(json.dumps(result))
        return 0
    print(f"{project_path.name}: {args.frames} frames, median {result['frame_ms_median']:.1f} "
          f"ms/frame ({result['fps']:.2f} frames/s), CPU {result['cpu_ms_median']:.1f} ms/frame, "
          f"latency {result['latency_ms_median']:.1f} ms (frames overlap)")
    for k, v in result["stages_ms"].items():
        print(f"  {k:<18} {v:8.2f} ms")
    if "if_error_db" in result:
        print(f"  IF synthesis vs direct sum: {result['if_error_db']:.1f} dB on "
              f"{result['subset']} scatterers, speed-up {result['if_speedup']:.0f}x "
              f"(NUFFT of all {result['scatterers']} scatterers "
              f"{result['nufft_full_ms']:.1f} ms)")
        print(f"  antenna edit -> radar maps: {result['antenna_edit_ms']:.1f} ms")
    if result["thread_cpu_ms"]:
        threads = ", ".join(f"{k} {v:.1f}" for k, v in result["thread_cpu_ms"].items())
        floor = result["two_core_floor_ms"]
        print(f"  CPU per thread (ms/frame): {threads}; two free cores: at best "
              f"{floor:.1f} ms/frame ({1e3 / floor:.2f} frames/s)")
    print(f"  load average before/after: {result['machine']['load_before']} / "
          f"{result['machine']['load_after']}")
    if people is not None:
        print(f"  with its people {people['fps_with_people']:.2f} frames/s, without them "
              f"{people['fps_without_people']:.2f} frames/s (ratio {people['ratio']:.2f}, "
              f"same run)")
        print(f"  with rigid stand-ins (a cylinder of each person's size on its path) "
              f"{people['fps_stand_ins']:.2f} frames/s: people / stand-ins "
              f"{people['ratio_to_stand_ins']:.2f}")
        if people["floor_ratio"] == people["floor_ratio"]:     # not NaN
            print(f"  two free cores at best: with its people "
                  f"{people['floor_ms_with_people']:.1f} ms/frame, without them "
                  f"{people['floor_ms_without_people']:.1f} ms/frame "
                  f"(ratio {people['floor_ratio']:.2f})")
    if variants is not None:
        _print_effect_variants(variants)
    if rigs is not None:
        _print_rig_variants(rigs)
    if kinds is not None:
        _print_sensor_variants(kinds)
    return 0


def _print_sensor_variants(kinds: dict[str, Any]) -> None:
    """``bench --sensors``: all sensors, radars only, ToF cameras only (same run)."""
    for name in ("all_sensors", "radar_only", "tof_only"):
        v = kinds[name]
        stages = ", ".join(f"{k} {t:.1f}" for k, t in v["stages_ms"].items())
        print(f"{name:<12} {v['frame_ms_median']:7.1f} ms/frame ({v['fps']:.2f} frames/s), "
              f"CPU {v['cpu_ms_per_frame']:.1f} ms/frame; stages (ms): {stages}")
    print(f"  radar only is {kinds['radar_only_speedup']:.2f}x, ToF only "
          f"{kinds['tof_only_speedup']:.2f}x as fast as all sensors (CPU per frame: "
          f"{kinds['radar_only_cpu_ratio']:.2f}x, {kinds['tof_only_cpu_ratio']:.2f}x; same "
          f"run); load average before/after: {kinds['load']['before']} / "
          f"{kinds['load']['after']}")


def _print_rig_variants(rigs: dict[str, Any]) -> None:
    """``bench --rigs``: the project as it is and with a second rig, same run."""
    for name in ("one_rig", "two_rigs", "plain_one_rig", "plain_two_rigs"):
        v = rigs[name]
        stages = ", ".join(f"{k} {t:.1f}" for k, t in v["stages_ms"].items())
        print(f"{name:<14} {v['sensors']} sensors {v['frame_ms_median']:7.1f} ms/frame "
              f"({v['fps']:.2f} frames/s); stages (ms): {stages}")
    print(f"  two rigs / one rig frame time: {rigs['time_ratio']:.2f}, plain "
          f"{rigs['plain_time_ratio']:.2f} (same run); load average before/after: "
          f"{rigs['load']['before']} / {rigs['load']['after']}")


def _print_effect_variants(variants: dict[str, Any]) -> None:
    """``bench --effects``: every effect on, twice, and plain (all off, no person).

    Every effect on with ToF multipath by the project's model, then from the whole room.
    """
    for name in ("all_effects", "all_effects_room", "plain"):
        v = variants[name]
        stages = ", ".join(f"{k} {t:.1f}" for k, t in v["stages_ms"].items())
        print(f"{name:<16} {v['frame_ms_median']:7.1f} ms/frame ({v['fps']:.2f} frames/s); "
              f"stages (ms): {stages}")
    print(f"  load average before/after: {variants['load']['before']} / "
          f"{variants['load']['after']}")


def _people_speed(project_path: Path, frames: int) -> dict[str, Any] | None:
    """The project's frame rate with and without its people (None without people)."""
    from simcore.bench import people_speed

    return people_speed(project_path, frames=frames)


def add_parser(sub: argparse._SubParsersAction[_Parser], common: list[_Parser]) -> None:
    """The ``bench`` subcommand."""
    p = sub.add_parser("bench", help="frame-time benchmark per stage", parents=common)
    p.add_argument("project", nargs="?", help="project (default: bundled office.json)")
    p.add_argument("--frames", type=_positive_int, default=30, help="frames to time")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.add_argument("--effects", action="store_true",
                   help="also time the project with every ToF/radar effect on, and plain "
                        "(all off, no person), in the same run")
    p.add_argument("--rigs", action="store_true",
                   help="also time the project with a second rig (a copy of its ToF camera "
                        "and radar placed beside it), in the same run")
    p.add_argument("--sensors", action="store_true",
                   help="also time the project with its radars only and with its ToF cameras "
                        "only (what a frame saves without the other sensor), in the same run")
    p.set_defaults(func=cmd_bench)
