"""The ``tofradar`` command line: gui, run, convert, serve, validate, bench."""

from __future__ import annotations

import argparse
import json
import os
import signal
import sys
import threading
from collections.abc import Callable, Iterator, Sequence
from contextlib import contextmanager
from pathlib import Path
from typing import TYPE_CHECKING, Any

from simcore.scene.project_io import ProjectError, load_project, project_to_json

if TYPE_CHECKING:
    from simcore.runner import FrameResult


class CliError(Exception):
    """An error reported to the user as one line, with exit status 2."""


def _int_at_least(minimum: int) -> Callable[[str], int]:
    """Argument type: an integer >= ``minimum``, with a one-line error otherwise."""
    what = "a positive integer" if minimum == 1 else f"an integer >= {minimum}"

    def parse(text: str) -> int:
        try:
            value = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"expected {what}, got {text!r}") from None
        if value < minimum:
            raise argparse.ArgumentTypeError(f"expected {what}, got {value}")
        return value

    return parse


_positive_int = _int_at_least(1)
_non_negative_int = _int_at_least(0)


def _positive_float(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a positive number, got {text!r}") from None
    if not (value > 0 and value < float("inf")):
        raise argparse.ArgumentTypeError(f"expected a positive number, got {text}")
    return value


@contextmanager
def stop_on_sigint() -> Iterator[threading.Event]:
    """Turn the first Ctrl+C into a request to stop after the frame being written.

    A KeyboardInterrupt raised at an arbitrary point can land in a garbage-collector
    callback, where Python only prints it and carries on; a flag checked between frames
    cannot be lost. A second Ctrl+C interrupts at once.
    """
    stop = threading.Event()

    def handler(signum: int, frame: object) -> None:
        if stop.is_set():
            raise KeyboardInterrupt
        stop.set()

    previous = signal.signal(signal.SIGINT, handler)
    try:
        yield stop
    finally:
        signal.signal(signal.SIGINT, previous)


def cmd_validate(args: argparse.Namespace) -> int:
    """Check a project file; print OK or the list of problems."""
    project = load_project(args.project)
    print(f"OK: {args.project} ({len(project.objects)} objects, format_version "
          f"{project.format_version})")
    return 0


def cmd_run(args: argparse.Namespace) -> int:
    """Render frames of a project headlessly into an HDF5 dataset."""
    from tqdm import tqdm

    from simcore.io.hdf5_writer import DatasetExistsError, ResumeError
    from simcore.runner import frame_count, run_dataset

    project_path = Path(args.project)
    project = load_project(project_path)
    seed = project.seed if args.seed is None else args.seed
    n_frames = frame_count(args.frames, args.duration, project.timeline.frame_rate_hz,
                           project.timeline.n_frames)
    out = Path(args.out)
    if out.is_dir():
        raise CliError(f"--out {out} is a directory; give a file name such as {out}/run.h5")
    if args.resume and args.overwrite:
        raise CliError("--resume and --overwrite exclude each other")
    bar = tqdm(total=n_frames, desc="frames", unit="frame", file=sys.stderr,
               disable=args.quiet)

    def progress(done: int, total: int, result: FrameResult) -> bool:
        bar.n = done
        bar.refresh()
        if args.preview:
            _write_previews(Path(args.preview), result)
        return not stop.is_set()

    try:
        with stop_on_sigint() as stop:
            report = run_dataset(project_to_json(project), project_path.parent, out,
                                 n_frames=n_frames, seed=seed, overwrite=args.overwrite,
                                 resume=args.resume, workers=args.workers,
                                 scheduler=args.scheduler, on_frame=progress)
    except (DatasetExistsError, ResumeError) as exc:
        raise CliError(str(exc)) from None
    finally:
        bar.close()
    if report.interrupted:
        print(f"interrupted: {report.frames_done} of {n_frames} frames are in {out}; "
              f"continue with --resume", file=sys.stderr)
        return 130
    if report.frames_done > report.first_frame:
        print(f"wrote frames {report.first_frame}..{report.frames_done - 1} to {out}")
    else:
        print(f"{out} already has {report.first_frame} frames; nothing to do")
    return 0


def _write_previews(preview_dir: Path, result: FrameResult) -> None:
    """PNG previews of one computed frame (invalid depth pixels grey)."""
    import numpy as np

    from simcore.io.previews import save_previews

    images: dict[str, tuple[Any, str]] = {
        name: (result.items[path][0], cmap) for name, path, cmap in PREVIEWS
        if path in result.items}
    if "tof_depth" in images and "/tof/valid" in result.items:
        depth = images["tof_depth"][0].astype(float)
        images["tof_depth"] = (np.where(result.items["/tof/valid"][0], depth, np.nan), "viridis")
    save_previews(preview_dir, result.index, images)


#: (file name part, dataset path, colour map) of the PNG previews.
PREVIEWS = [
    ("tof_gt_range", "/tof/gt_range", "viridis"),
    ("tof_depth", "/tof/depth", "viridis"),
    ("tof_amplitude", "/tof/amplitude", "gray"),
    ("radar_range_doppler", "/radar/range_doppler", "magma"),
    ("radar_range_azimuth", "/radar/range_azimuth", "magma"),
]


def cmd_sweep(args: argparse.Namespace) -> int:
    """One dataset per combination of the varied fields, with the parameters recorded."""
    from simcore.io.hdf5_writer import DatasetExistsError, ResumeError
    from simcore.runner import frame_count, run_dataset
    from simcore.sweep import SweepError, expand, parameters_json, parse_vary

    project_path = Path(args.project)
    project = load_project(project_path)
    try:
        variants = expand(project, [parse_vary(v) for v in args.vary])
    except SweepError as exc:
        raise CliError(str(exc)) from None
    out_dir = Path(args.out)
    if out_dir.exists() and not out_dir.is_dir():
        raise CliError(f"--out {out_dir} exists and is not a directory")
    out_dir.mkdir(parents=True, exist_ok=True)
    index = []
    for i, (params, variant) in enumerate(variants):
        path = out_dir / f"variant_{i:04d}.h5"
        seed = variant.seed if args.seed is None else args.seed
        n_frames = frame_count(args.frames, args.duration, variant.timeline.frame_rate_hz,
                               variant.timeline.n_frames)
        print(f"[{i + 1}/{len(variants)}] {path.name}: {parameters_json(params)}")
        try:
            with stop_on_sigint() as stop:
                report = run_dataset(
                    project_to_json(variant), project_path.parent, path, n_frames=n_frames,
                    seed=seed, overwrite=args.overwrite, resume=args.resume,
                    workers=args.workers, scheduler=args.scheduler,
                    extra_meta={"sweep_parameters": parameters_json(params)},
                    on_frame=lambda done, total, result: not stop.is_set())
        except (DatasetExistsError, ResumeError) as exc:
            raise CliError(str(exc)) from None
        if report.interrupted:
            print("interrupted; continue with --resume", file=sys.stderr)
            return 130
        index.append({"file": path.name, "parameters": params, "frames": n_frames,
                      "seed": seed})
    (out_dir / "sweep.json").write_text(json.dumps({"project": str(project_path),
                                                    "variants": index}, indent=2) + "\n")
    print(f"wrote {len(variants)} datasets and sweep.json to {out_dir}")
    return 0


def cmd_report(args: argparse.Namespace) -> int:
    """Regenerate the validation report (figures + README.md)."""
    from simcore.report import generate_report

    def say(message: str) -> None:
        if not args.quiet:
            print(f"  {message}", file=sys.stderr)

    result = generate_report(Path(args.out), quick=args.quick, progress=say)
    print(f"wrote {len(result.figures)} figures and README.md to {result.out_dir}")
    return 0


def cmd_bench(args: argparse.Namespace) -> int:
    """Time every pipeline stage over a number of frames; IF accuracy and GUI latency."""
    from simcore.bench import run_benchmark
    from simcore.resources import example_path

    project_path = Path(args.project) if args.project else example_path("office")
    load_project(project_path)  # report a bad file before anything starts
    result = run_benchmark(project_path, frames=args.frames)
    if args.json:
        print(json.dumps(result))
        return 0
    print(f"{project_path.name}: {args.frames} frames, median {result['frame_ms_median']:.1f} "
          f"ms/frame ({result['fps']:.2f} frames/s), CPU {result['cpu_ms_median']:.1f} ms/frame")
    for k, v in result["stages_ms"].items():
        print(f"  {k:<18} {v:8.2f} ms")
    print(f"  IF synthesis vs direct sum: {result['if_error_db']:.1f} dB on "
          f"{result['subset']} scatterers, speed-up {result['if_speedup']:.0f}x "
          f"(NUFFT of all {result['scatterers']} scatterers {result['nufft_full_ms']:.1f} ms)")
    print(f"  antenna edit -> radar maps: {result['antenna_edit_ms']:.1f} ms")
    print(f"  load average before/after: {result['machine']['load_before']} / "
          f"{result['machine']['load_after']}")
    return 0


def cmd_gui(args: argparse.Namespace) -> int:
    """Open the desktop GUI through the launcher the ``app`` package registered."""
    if args.gui_launcher is None:
        raise CliError("the GUI is not available from this entry point; run 'tofradar gui'")
    if not (os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY")):
        raise CliError("no display found (DISPLAY is not set); the GUI needs one. "
                       "Use 'tofradar run PROJECT --out FILE.h5' for headless work.")
    if args.project:
        load_project(args.project)  # report a bad file here, before Qt starts
    return int(args.gui_launcher(args.project))


def build_parser() -> argparse.ArgumentParser:
    """The argument parser of the ``tofradar`` command."""
    parser = argparse.ArgumentParser(
        prog="tofradar",
        description="Synchronized AMCW ToF camera and FMCW radar simulation from one 3D scene.",
    )
    sub = parser.add_subparsers(dest="command")
    p = sub.add_parser("gui", help="open the desktop GUI (default)")
    p.add_argument("project", nargs="?", help="project file to open")
    p.set_defaults(func=cmd_gui)

    p = sub.add_parser("run", help="render frames headlessly into an HDF5 dataset")
    p.add_argument("project", help="project JSON file")
    p.add_argument("--out", required=True,
                   help="output file: HDF5 (.h5, default) or an MCAP recording (.mcap)")
    p.add_argument("--frames", type=_positive_int, help="number of frames (default: timeline)")
    p.add_argument("--duration", type=_positive_float, metavar="S",
                   help="simulated seconds (frames = S × frame rate)")
    p.add_argument("--seed", type=_non_negative_int, help="random seed (default: project seed)")
    p.add_argument("--overwrite", action="store_true", help="replace an existing output file")
    p.add_argument("--resume", action="store_true",
                   help="continue an interrupted run of the same project and seed")
    p.add_argument("--workers", type=_positive_int, default=1,
                   help="local worker processes (default 1)")
    p.add_argument("--scheduler", metavar="ADDRESS",
                   help="run frames on Dask: 'local' for an embedded cluster of --workers "
                        "processes, or a scheduler address such as tcp://host:8786")
    p.add_argument("--preview", metavar="DIR", help="also write PNG previews into DIR")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    p.set_defaults(func=cmd_run)

    p = sub.add_parser("sweep", help="one dataset per combination of varied project fields")
    p.add_argument("project", help="project JSON file")
    p.add_argument("--vary", action="append", required=True, metavar="PATH=START:STOP:STEP",
                   help="field path and values, e.g. objects[0].pose.position_m[0]=1:3:0.5 "
                        "or rig.radar.chirps_per_frame=16,32 (repeatable)")
    p.add_argument("--out", required=True, metavar="DIR", help="output directory")
    p.add_argument("--frames", type=_positive_int, help="frames per variant")
    p.add_argument("--duration", type=_positive_float, metavar="S", help="seconds per variant")
    p.add_argument("--seed", type=_non_negative_int, help="random seed (default: project's)")
    p.add_argument("--overwrite", action="store_true", help="replace existing datasets")
    p.add_argument("--resume", action="store_true", help="continue interrupted datasets")
    p.add_argument("--workers", type=_positive_int, default=1, help="local worker processes")
    p.add_argument("--scheduler", metavar="ADDRESS", help="Dask scheduler ('local' or address)")
    p.set_defaults(func=cmd_sweep)

    p = sub.add_parser("report", help="regenerate the validation report with figures")
    p.add_argument("--out", default="docs/validation", help="output directory")
    p.add_argument("--quick", action="store_true", help="fewer frames (for tests)")
    p.add_argument("--quiet", action="store_true", help="no progress messages")
    p.set_defaults(func=cmd_report)

    _add_robotics_commands(sub)

    p = sub.add_parser("validate", help="check a project file")
    p.add_argument("project", help="project JSON file")
    p.set_defaults(func=cmd_validate)

    p = sub.add_parser("bench", help="frame-time benchmark per stage")
    p.add_argument("project", nargs="?", help="project (default: bundled office.json)")
    p.add_argument("--frames", type=_positive_int, default=30, help="frames to time")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.set_defaults(func=cmd_bench)
    return parser


def cmd_convert(args: argparse.Namespace) -> int:
    """Convert an HDF5 dataset into an MCAP recording with ROS 2 messages."""
    from simcore.io.hdf5_writer import DatasetExistsError
    from simcore.io.mcap_writer import convert_hdf5_to_mcap

    source, target = Path(args.source), Path(args.to)
    if not source.is_file():
        raise CliError(f"{source}: no such dataset")
    if target.suffix.lower() != ".mcap":
        raise CliError(f"--to {target}: only MCAP (.mcap) is supported")
    try:
        n = convert_hdf5_to_mcap(source, target, overwrite=args.overwrite)
    except DatasetExistsError as exc:
        raise CliError(str(exc)) from None
    print(f"wrote {n} frames to {target}")
    return 0


def cmd_serve(args: argparse.Namespace) -> int:
    """Publish frames live over the Foxglove WebSocket protocol."""
    from simcore.io.live import serve

    project_path = Path(args.project)
    project = load_project(project_path)

    def ready(port: int) -> None:
        print(f"serving on ws://{args.host}:{port} (Foxglove WebSocket protocol)", flush=True)

    with stop_on_sigint() as stop:
        report = serve(project, base_dir=project_path.parent, host=args.host, port=args.port,
                       n_frames=args.frames, loop=args.loop, realtime=not args.fast,
                       wait_for_client=not args.no_wait, seed=args.seed, on_ready=ready,
                       stop=stop)
    print(f"published {report.frames_published} frames")
    return 0


def _add_robotics_commands(sub: Any) -> None:
    """The ``convert`` and ``serve`` subcommands (docs/robotics.md)."""
    p = sub.add_parser("convert", help="convert an HDF5 dataset into an MCAP recording")
    p.add_argument("source", help="HDF5 dataset")
    p.add_argument("--to", required=True, help="output MCAP file (.mcap)")
    p.add_argument("--overwrite", action="store_true", help="replace an existing output file")
    p.set_defaults(func=cmd_convert)

    p = sub.add_parser("serve", help="publish frames live over the Foxglove WebSocket protocol")
    p.add_argument("project", help="project JSON file")
    p.add_argument("--host", default="127.0.0.1", help="interface (default 127.0.0.1)")
    p.add_argument("--port", type=_non_negative_int, default=8765,
                   help="TCP port (default 8765; 0 = any free port)")
    p.add_argument("--frames", type=_positive_int, help="frames to publish (default: timeline)")
    p.add_argument("--loop", action="store_true", help="repeat the timeline until Ctrl+C")
    p.add_argument("--fast", action="store_true",
                   help="publish as fast as frames are computed (default: timeline frame rate)")
    p.add_argument("--no-wait", action="store_true",
                   help="start at once (default: wait until a client subscribes)")
    p.add_argument("--seed", type=_non_negative_int, help="random seed (default: project's)")
    p.set_defaults(func=cmd_serve)


def main(argv: Sequence[str] | None = None, *,
         gui_launcher: Callable[[str | None], int] | None = None) -> int:
    """Run the ``tofradar`` command line.

    ``gui_launcher(project_path_or_None)`` opens the GUI; the ``app`` package passes it
    (the core never imports the GUI).
    """
    parser = build_parser()
    args = parser.parse_args(argv)
    if args.command is None:
        args = parser.parse_args(["gui", *(argv or [])])
    args.gui_launcher = gui_launcher
    try:
        return int(args.func(args))
    except ProjectError as exc:
        print(f"tofradar: error: {exc}", file=sys.stderr)
        return 2
    except CliError as exc:
        print(f"tofradar: error: {exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("tofradar: interrupted", file=sys.stderr)
        return 130
    except OSError as exc:
        print(f"tofradar: error: {exc}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
