"""The ``tofradar`` command line: gui, run, convert, serve, validate, bench."""

from __future__ import annotations

import argparse
import errno
import json
import os
import signal
import sys
import threading
import warnings
from collections.abc import Callable, Iterator, Sequence
from contextlib import contextmanager
from pathlib import Path
from typing import TYPE_CHECKING, Any, NoReturn

from simcore import __version__
from simcore.preflight import MAX_FRAMES, MAX_SEED, RunError
from simcore.scene.model import sensor_kind
from simcore.scene.project_io import ProjectError, load_project, project_to_json

if TYPE_CHECKING:
    from simcore.io.previews import PreviewSensor
    from simcore.preflight import CostEstimate
    from simcore.runs.runner import FrameResult
    from simcore.scene.model import Project

#: Defaults of the Dask timeouts (kept equal to simcore.runs.runner's, without importing it).
CONNECT_TIMEOUT_S = 10.0
TASK_TIMEOUT_S = 600.0


class CliError(Exception):
    """An error reported to the user as one line, with exit status 2."""


#: Longest error line printed (characters).
MAX_ERROR_LENGTH = 600
#: Most worker processes of one run.
MAX_WORKERS = 256


class _Parser(argparse.ArgumentParser):
    """Argument errors as one line ``tofradar: error: …`` (exit status 2), no usage dump."""

    def error(self, message: str) -> NoReturn:
        _print_error(f"{self.prog.removeprefix('tofradar').strip() or 'arguments'}: {message}")
        raise SystemExit(2)


def _print_error(message: str) -> None:
    line = " ".join(str(message).split())
    if len(line) > MAX_ERROR_LENGTH:
        line = line[: MAX_ERROR_LENGTH - 3] + "..."
    print(f"tofradar: error: {line}", file=sys.stderr)


def _int_at_least(minimum: int, maximum: int | None = None) -> Callable[[str], int]:
    """Argument type: an integer in [minimum, maximum], with a one-line error otherwise."""
    what = "a positive integer" if minimum == 1 else f"an integer >= {minimum}"
    if maximum is not None:
        what += f" up to {maximum}"

    def parse(text: str) -> int:
        if len(text) > 40:
            raise argparse.ArgumentTypeError(f"expected {what}, got {len(text)} characters")
        try:
            value = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"expected {what}, got {text!r}") from None
        if value < minimum or (maximum is not None and value > maximum):
            raise argparse.ArgumentTypeError(f"expected {what}, got {value}")
        return value

    return parse


_positive_int = _int_at_least(1)
_frames_int = _int_at_least(1, MAX_FRAMES)
_seed_int = _int_at_least(0, MAX_SEED)
_workers_int = _int_at_least(1, MAX_WORKERS)


def _positive_float(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a positive number, got {text!r}") from None
    if not (value > 0 and value < float("inf")):
        raise argparse.ArgumentTypeError(f"expected a positive number, got {text[:40]}")
    return value


@contextmanager
def stop_on_sigint() -> Iterator[threading.Event]:
    """Turn the first Ctrl+C (or SIGTERM) into a request to stop after the frame being written.

    A KeyboardInterrupt raised at an arbitrary point can land in a garbage-collector
    callback, where Python only prints it and carries on; a flag checked between frames
    cannot be lost. A second signal interrupts at once. SIGTERM (what ``kill``, systemd
    and batch schedulers send) is handled exactly like SIGINT.
    """
    stop = threading.Event()

    def handler(signum: int, frame: object) -> None:
        if stop.is_set():
            raise KeyboardInterrupt
        stop.set()

    previous = {sig: signal.signal(sig, handler) for sig in (signal.SIGINT, signal.SIGTERM)}
    try:
        yield stop
    finally:
        for sig, old in previous.items():
            signal.signal(sig, old)


def _preflight(project: Project, project_path: Path, args: argparse.Namespace, *,
               n_frames: int | None = None, seed: int | None = None) -> CostEstimate:
    """Run :func:`simcore.preflight.check`; raise ProjectError listing every problem."""
    from simcore.preflight import check, estimate_cost

    force = getattr(args, "force", False)
    problems = check(project, base_dir=project_path.parent,
                     memory_budget_bytes=2**63 if force else None, n_frames=n_frames,
                     seed=seed, allow_outside_paths=args.allow_outside_paths)
    if problems:
        raise ProjectError(str(project_path), problems)
    return estimate_cost(project, base_dir=project_path.parent)


def _check_disk(out: Path, cost: CostEstimate, frames: int, *, force: bool) -> None:
    """Refuse a run whose dataset would not fit on the output's file system."""
    import shutil

    folder = out.parent if out.parent.exists() else Path.cwd()
    try:
        free = shutil.disk_usage(folder).free
    except OSError:
        return
    need = cost.disk_bytes_per_frame * frames
    if need > free and not force:
        raise CliError(f"--out {out}: {frames} frames need up to {need / 2**30:.2f} GiB "
                       f"(uncompressed, {cost.disk_bytes_per_frame / 2**20:.2f} MiB per frame) "
                       f"but {free / 2**30:.2f} GiB are free; free space, write fewer frames, "
                       "or pass --force (compression usually saves 2-5x)")


#: Default wall-time budget of one ``run`` (s): longer runs need ``--max-hours`` or --force.
TIME_BUDGET_S = 24 * 3600.0


def _check_time(cost: CostEstimate, frames: int, args: argparse.Namespace) -> None:
    """Refuse a run whose estimated duration exceeds ``--max-hours`` (unless --force)."""
    budget = getattr(args, "max_hours", None)
    budget_s = TIME_BUDGET_S if budget is None else budget * 3600.0
    need = cost.seconds_per_frame * frames
    if need > budget_s and not args.force:
        raise CliError(f"{frames} frames would take about {need / 3600:.1f} h "
                       f"(≈ {cost.seconds_per_frame:.2f} s per frame on this machine), over "
                       f"the {budget_s / 3600:g} h budget; write fewer frames, raise "
                       "--max-hours, or pass --force")


def cmd_validate(args: argparse.Namespace) -> int:
    """Check a project file as ``run`` would; print OK and the cost, or every problem."""
    from simcore.scene.devices import project_limit_problems

    project = load_project(args.project)
    cost = _preflight(project, Path(args.project), args)
    device_problems, device_notes = project_limit_problems(project)
    if device_problems:
        raise ProjectError(args.project, device_problems)
    print(f"OK: {args.project} ({len(project.objects)} objects, format_version "
          f"{project.format_version}); {cost.describe()}")
    for note in device_notes:
        print(f"  note: {note}")
    rigs = project.all_rigs()
    if len(rigs) > 1 or project.rig.sensors:
        # Several sensors: each with its kind, rig and timing.
        rate = project.timeline.frame_rate_hz
        for name, cfg in project.sensor_configs().items():
            every = cfg.frame_divider(rate)  # type: ignore[attr-defined]
            offset = cfg.trigger_offset_s  # type: ignore[attr-defined]
            print(f"  {name}: {sensor_kind(cfg)} on rig {project.sensor_rig(name).name!r}, "
                  f"{rate / every:g} frames/s (every {every} frame{'s' if every > 1 else ''})"
                  f"{f', {offset * 1e3:g} ms after the frame' if offset else ''}")
    return 0


def cmd_run(args: argparse.Namespace) -> int:
    """Render frames of a project headlessly into an HDF5 dataset."""
    from tqdm import tqdm

    from simcore.runs.runner import frame_count, run_dataset

    project_path = Path(args.project)
    if project_path.is_dir():
        return _run_scenes(args)
    if args.out.lower().endswith(".bin"):
        return _run_ti_capture(args)
    project = load_project(project_path)
    seed = project.seed if args.seed is None else args.seed
    try:
        n_frames = frame_count(args.frames, args.duration, project.timeline.frame_rate_hz,
                               _timeline_default(project, args))
    except ValueError as exc:
        raise CliError(str(exc)) from None
    out: Path | str = Path(args.out)
    remote = _is_remote(args.out)
    if "://" in args.out:
        out = args.out                  # a URL stays a string (s3://bucket/run, file://…)
    elif Path(out).is_dir() and not _is_zarr_out(args.out):
        raise CliError(f"--out {out} is a directory; give a file name such as {out}/run.h5")
    if args.resume and args.overwrite:
        raise CliError("--resume and --overwrite exclude each other")
    if args.scheduler is not None:
        _check_scheduler(args.scheduler)
    cost = _preflight(project, project_path, args, n_frames=n_frames, seed=seed)
    if not remote:
        _check_disk(Path(args.out.removeprefix("file://")), cost, n_frames, force=args.force)
    _check_time(cost, n_frames, args)
    preview_axes = _preview_sensors(project) if args.preview else None
    bar = tqdm(total=n_frames, desc="frames", unit="frame", file=sys.stderr,
               disable=args.quiet)

    def progress(done: int, total: int, result: FrameResult) -> bool:
        bar.n = done
        bar.refresh()
        if args.preview and result.items:   # frames written by workers come without data
            _write_previews(Path(args.preview), result, preview_axes)
        return not stop.is_set()

    with _run_errors(args, bar), stop_on_sigint() as stop:
        report = run_dataset(project_to_json(project), project_path.parent, out,
                             n_frames=n_frames, seed=seed, overwrite=args.overwrite,
                             resume=args.resume, workers=args.workers,
                             scheduler=args.scheduler, on_frame=progress,
                             task_timeout_s=args.task_timeout,
                             connect_timeout_s=args.connect_timeout,
                             storage_options=_storage_options(args),
                             shard_frames=args.shard_frames)
    if report.interrupted:
        print(f"interrupted: {report.frames_done} of {n_frames} frames are in {out}; "
              f"continue with --resume", file=sys.stderr)
        return 130
    if report.frames_done > report.first_frame:
        print(f"wrote frames {report.first_frame}..{report.frames_done - 1} to {out}")
    else:
        print(f"{out} already has {report.first_frame} frames; nothing to do")
    return 0


#: Most projects of one run over a folder of scenes.
MAX_SCENES = 100_000


@contextmanager
def _run_errors(args: argparse.Namespace, bar: Any) -> Iterator[None]:
    """Dataset-writing failures of ``run`` as one-line CLI errors; the progress bar closed."""
    from simcore.io.hdf5_writer import DatasetExistsError, DiskFullError, ResumeError

    try:
        yield
    except (DatasetExistsError, ResumeError) as exc:
        raise CliError(str(exc)) from None
    except DiskFullError as exc:
        raise CliError(f"{exc.strerror}; free space and continue with --resume") from None
    except _store_errors() as exc:
        raise CliError(f"--out {args.out}: {type(exc).__name__}: {str(exc)[:300]}") from None
    finally:
        bar.close()


def _run_scenes(args: argparse.Namespace) -> int:
    """``tofradar run DIR``: every project of a folder into one dataset, a scene index per frame."""
    from tqdm import tqdm

    from simcore.runs.runner import frame_count, run_scenes

    folder = Path(args.project)
    files = sorted(p for p in folder.glob("*.json") if p.is_file())
    if not files:
        raise CliError(f"{folder}: a folder of projects holds *.json project files; found none")
    if len(files) > MAX_SCENES:
        raise CliError(f"{folder}: {len(files)} projects; allowed at most {MAX_SCENES}")
    if args.seed is not None:
        raise CliError("--seed: each scene of a folder runs with its own project seed")
    if args.preview:
        raise CliError("--preview is for one project, not a folder of scenes")
    if args.resume and args.overwrite:
        raise CliError("--resume and --overwrite exclude each other")
    if args.scheduler is not None:
        _check_scheduler(args.scheduler)
    first = load_project(files[0])
    try:
        per_scene = frame_count(args.frames, args.duration, first.timeline.frame_rate_hz,
                                _timeline_default(first, args))
    except ValueError as exc:
        raise CliError(str(exc)) from None
    total = per_scene * len(files)
    if total > MAX_FRAMES:
        raise CliError(f"{len(files)} scenes × {per_scene} frames = {total} frames; allowed at "
                       f"most {MAX_FRAMES}")
    scenes = []
    for path in files:
        project = load_project(path)
        _preflight(project, path, args, n_frames=per_scene, seed=project.seed)
        scenes.append((project_to_json(project), path.parent))
    cost = _preflight(first, files[0], args, n_frames=per_scene, seed=first.seed)
    out: Path | str = args.out if "://" in args.out else Path(args.out)
    if not _is_remote(args.out):
        _check_disk(Path(args.out.removeprefix("file://")), cost, total, force=args.force)
    _check_time(cost, total, args)
    bar = tqdm(total=total, desc="frames", unit="frame", file=sys.stderr, disable=args.quiet)

    def progress(done: int, n: int, result: FrameResult) -> bool:
        bar.n = done
        bar.set_postfix_str(f"scene {result.index // per_scene + 1}/{len(files)}",
                            refresh=False)
        bar.refresh()
        return not stop.is_set()

    with _run_errors(args, bar), stop_on_sigint() as stop:
        report = run_scenes(scenes, out, frames_per_scene=per_scene,
                            overwrite=args.overwrite, resume=args.resume,
                            workers=args.workers, scheduler=args.scheduler,
                            on_frame=progress, task_timeout_s=args.task_timeout,
                            connect_timeout_s=args.connect_timeout,
                            storage_options=_storage_options(args),
                            shard_frames=args.shard_frames)
    if report.interrupted:
        print(f"interrupted: {report.frames_done} of {total} frames are in {out}; "
              f"continue with --resume", file=sys.stderr)
        return 130
    print(f"wrote {len(files)} scenes × {per_scene} frames (frames {report.first_frame}.."
          f"{report.frames_done - 1}) to {out}")
    return 0


def _is_zarr_out(out: str) -> bool:
    from simcore.io.writer import is_zarr_target

    return is_zarr_target(out)


def _is_remote(out: str) -> bool:
    """``--out`` is a URL of a store other than a local file (``s3://``, ``memory://``)."""
    scheme, sep, _ = out.partition("://")
    return bool(sep) and scheme.lower() != "file" and _is_zarr_out(out)


def _storage_options(args: argparse.Namespace) -> dict[str, object] | None:
    """Storage options from ``--storage-option KEY=VALUE`` (values parsed as JSON if they can)."""
    options: dict[str, object] = {}
    for text in getattr(args, "storage_option", None) or []:
        key, sep, value = text.partition("=")
        if not sep or not key:
            raise CliError(f"--storage-option {text!r}: expected KEY=VALUE")
        try:
            options[key] = json.loads(value)
        except ValueError:
            options[key] = value
    endpoint = os.environ.get("TOFRADAR_S3_ENDPOINT")
    if endpoint and args.out.startswith("s3://") and "endpoint_url" not in options:
        options["endpoint_url"] = endpoint
    return options or None


def _store_errors() -> tuple[type[BaseException], ...]:
    """Errors of a store that cannot be reached or written (bad bucket, no credentials)."""
    errors: list[type[BaseException]] = [OSError, PermissionError]
    try:
        from botocore.exceptions import BotoCoreError, ClientError

        errors += [BotoCoreError, ClientError]
    except ImportError:
        pass
    return tuple(errors)


def _timeline_default(project: Project, args: argparse.Namespace) -> int:
    """Frames of the project's timeline when neither --frames nor --duration is given."""
    from simcore.preflight import timeline_frames

    if args.frames is not None or args.duration is not None:
        return 0
    frames = timeline_frames(project)
    if frames > MAX_FRAMES:
        raise CliError(f"{args.project}: timeline.duration_s × frame_rate_hz = {frames:.3g} "
                       f"frames; allowed at most {MAX_FRAMES} (or pass --frames)")
    return int(frames)


def _preview_sensors(project: Project) -> dict[str, PreviewSensor]:
    """What the preview figures of each sensor need (its axes)."""
    from simcore.io.previews import preview_sensors

    return preview_sensors(project)


def _write_previews(preview_dir: Path, result: FrameResult,
                    sensors: dict[str, PreviewSensor] | None) -> None:
    """Labelled PNG figures of one computed frame (invalid depth pixels grey)."""
    from simcore.io.previews import save_frame_previews

    save_frame_previews(preview_dir, result.index, result.items, sensors)


def _check_scheduler(address: str) -> None:
    from simcore.runs.runner import SchedulerError, check_scheduler_address

    try:
        check_scheduler_address(address)
    except SchedulerError as exc:
        raise CliError(str(exc)) from None


def cmd_generate(args: argparse.Namespace) -> int:
    """Write N randomized projects from a scenario spec (``simcore.scenarios``)."""
    from tqdm import tqdm

    from simcore.scenarios import generate

    bars: list[tqdm[None]] = []       # made at the first project: a bad spec prints one line only

    def progress(done: int, total: int) -> None:
        if not bars:
            bars.append(tqdm(total=total, desc="projects", unit="project", file=sys.stderr,
                             disable=args.quiet))
        bars[0].update(1)

    try:
        written = generate(args.spec, args.out, count=args.count, seed=args.seed,
                           overwrite=args.overwrite, on_project=progress)
    finally:
        for bar in bars:
            bar.close()
    print(f"wrote {len(written)} projects to {args.out} "
          f"({written[0].name} .. {written[-1].name})")
    if args.run is None:
        return 0
    run_args = build_parser().parse_args(["run", str(args.out), "--out", args.run])
    for key in ("frames", "workers", "scheduler", "quiet", "shard_frames", "storage_option",
                "overwrite_run", "resume", "force", "allow_outside_paths"):
        if hasattr(args, key):
            setattr(run_args, "overwrite" if key == "overwrite_run" else key,
                    getattr(args, key))
    return _run_scenes(run_args)


def cmd_sweep(args: argparse.Namespace) -> int:
    """One dataset per combination of the varied fields, with the parameters recorded."""
    from simcore.io.hdf5_writer import DatasetExistsError, DiskFullError, ResumeError
    from simcore.preflight import check as check_project
    from simcore.preflight import estimate_cost
    from simcore.runs.runner import frame_count, run_dataset
    from simcore.runs.sweep import SweepError, expand, parameters_json, parse_vary

    project_path = Path(args.project)
    project = load_project(project_path)
    for spec in args.vary:
        _check_vary_count(spec)
    try:
        variants = expand(project, [parse_vary(v) for v in args.vary])
    except (SweepError, ValueError, OverflowError) as exc:
        raise CliError(str(exc)) from None
    if args.scheduler is not None:
        _check_scheduler(args.scheduler)
    out_dir = Path(args.out)
    if out_dir.exists() and not out_dir.is_dir():
        raise CliError(f"--out {out_dir} exists and is not a directory")
    out_dir.mkdir(parents=True, exist_ok=True)
    index = []
    for i, (params, variant) in enumerate(variants):
        path = out_dir / f"variant_{i:04d}.h5"
        seed = variant.seed if args.seed is None else args.seed
        try:
            n_frames = frame_count(args.frames, args.duration, variant.timeline.frame_rate_hz,
                                   _timeline_default(variant, args))
        except ValueError as exc:
            raise CliError(str(exc)) from None
        problems = check_project(variant, base_dir=project_path.parent, n_frames=n_frames,
                                 seed=seed, allow_outside_paths=args.allow_outside_paths,
                                 memory_budget_bytes=2**63 if args.force else None)
        if problems:
            raise ProjectError(f"{project_path} variant {i} {parameters_json(params)}", problems)
        variant_cost = estimate_cost(variant, base_dir=project_path.parent)
        _check_disk(path, variant_cost, n_frames, force=args.force)
        _check_time(variant_cost, n_frames, args)
        print(f"[{i + 1}/{len(variants)}] {path.name}: {parameters_json(params)}")
        try:
            with stop_on_sigint() as stop:
                report = run_dataset(
                    project_to_json(variant), project_path.parent, path, n_frames=n_frames,
                    seed=seed, overwrite=args.overwrite, resume=args.resume,
                    workers=args.workers, scheduler=args.scheduler,
                    extra_meta={"sweep_parameters": parameters_json(params)},
                    on_frame=lambda done, total, result: not stop.is_set(),
                    task_timeout_s=args.task_timeout, connect_timeout_s=args.connect_timeout)
        except (DatasetExistsError, ResumeError) as exc:
            raise CliError(str(exc)) from None
        except DiskFullError as exc:
            raise CliError(f"{exc.strerror}; free space and continue with --resume") from None
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
    """``bench --effects``: the project with every effect on, and plain (all off, no person)."""
    for name in ("all_effects", "plain"):
        v = variants[name]
        stages = ", ".join(f"{k} {t:.1f}" for k, t in v["stages_ms"].items())
        print(f"{name:<12} {v['frame_ms_median']:7.1f} ms/frame ({v['fps']:.2f} frames/s); "
              f"stages (ms): {stages}")
    print(f"  load average before/after: {variants['load']['before']} / "
          f"{variants['load']['after']}")


def _people_speed(project_path: Path, frames: int) -> dict[str, Any] | None:
    """The project's frame rate with and without its people (None without people)."""
    from simcore.bench import people_speed

    return people_speed(project_path, frames=frames)


def cmd_examples(args: argparse.Namespace) -> int:
    """List the bundled example projects, or copy them (with meshes) into a folder."""
    from simcore.examples import ExamplesError, copy_examples, list_examples

    if args.copy is None:
        for example in list_examples():
            print(f"{example.name + '.json':<28} {example.summary}")
        print("copy them into a folder with: tofradar examples --copy DIR")
        return 0
    try:
        written = copy_examples(Path(args.copy))
    except ExamplesError as exc:
        raise CliError(str(exc)) from None
    print(f"copied {len(written)} files to {args.copy}")
    return 0


def cmd_materials(args: argparse.Namespace) -> int:
    """List the materials (library, or a project's table) with what each does per band."""
    from simcore.scene.materials import load_material_library, summarize_material
    from simcore.scene.project_io import material_table
    from simcore.scene.radar_config import SPEED_OF_LIGHT

    if args.project:
        project = load_project(args.project)
        table = material_table(project)
        f_radar = SPEED_OF_LIGHT / project.radar().wavelength_m
        own = {m.name for m in project.materials}
        users: dict[str, list[str]] = {}
        for o in project.objects:
            users.setdefault(o.material, []).append(o.name)
    else:
        # The library alone: at the default radar's chirp centre frequency.
        from simcore.scene.radar_config import RadarConfig

        f_radar = SPEED_OF_LIGHT / RadarConfig().wavelength_m
        table, own, users = load_material_library(), set(), {}
    for name in sorted(table):
        mat = table[name]
        tag = " (project)" if name in own else ""
        print(f"{name}{tag}: {summarize_material(mat, f_radar)}")
        if mat.description:
            print(f"    {mat.description}")
        if name in users:
            print(f"    used by {', '.join(users[name])}")
    if args.project:
        _print_materials_map(project)
    return 0


def _print_materials_map(project: Project) -> None:
    """The imported asset materials and the library materials they map to."""
    if not project.materials_map:
        return
    print("asset materials (materials_map):")
    for asset, name in sorted(project.materials_map.items()):
        n = sum(1 for o in project.objects if o.material in (f"asset:{asset}",))
        print(f"  {asset} -> {name} ({n} objects)")


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


def _common(*, debug_only: bool = False) -> _Parser:
    """Options every subcommand takes."""
    common = _Parser(add_help=False)
    common.add_argument("--debug", action="store_true",
                        dest="debug_global" if debug_only else "debug",
                        help="print the traceback of an error instead of one line")
    if not debug_only:
        common.add_argument("--allow-outside-paths", action="store_true",
                            help="accept mesh files outside the project's folder")
    return common


def _run_options(p: argparse.ArgumentParser) -> None:
    """Options shared by ``run`` and ``sweep``: limits, Dask timeouts."""
    p.add_argument("--force", action="store_true",
                   help="run even when the memory, disk or time estimate exceeds its budget")
    p.add_argument("--max-hours", type=_positive_float, default=None, metavar="H",
                   help=f"time budget of one run (default {TIME_BUDGET_S / 3600:g} h): "
                        "longer runs are refused unless --force")
    p.add_argument("--task-timeout", type=_positive_float, default=TASK_TIMEOUT_S, metavar="S",
                   help=f"longest wait for one frame on Dask (default {TASK_TIMEOUT_S:g} s)")
    p.add_argument("--connect-timeout", type=_positive_float, default=CONNECT_TIMEOUT_S,
                   metavar="S", help="longest wait for a Dask scheduler's handshake "
                                     f"(default {CONNECT_TIMEOUT_S:g} s)")


def build_parser() -> argparse.ArgumentParser:
    """The argument parser of the ``tofradar`` command."""
    parser = _Parser(
        prog="tofradar", parents=[_common(debug_only=True)],
        description="Synchronized AMCW ToF camera and FMCW radar simulation from one 3D scene.",
    )
    parser.add_argument("--version", action="version", version=f"%(prog)s {__version__}")
    sub = parser.add_subparsers(dest="command")
    common = [_common()]
    p = sub.add_parser("gui", help="open the desktop GUI (default)", parents=common)
    p.add_argument("project", nargs="?", help="project file to open")
    p.set_defaults(func=cmd_gui)

    p = sub.add_parser("run", help="render frames headlessly into an HDF5 dataset",
                       parents=common)
    p.add_argument("project", help="project JSON file, or a folder of projects (one dataset "
                                   "of every scene, a scene index per frame)")
    p.add_argument("--out", required=True,
                   help="output file: HDF5 (.h5, default), an MCAP recording (.mcap), a "
                        "Zarr store (.zarr, or a URL such as s3://bucket/run), or a TI "
                        "DCA1000 capture (.bin, with its mmWave SDK .cfg beside it)")
    p.add_argument("--frames", type=_frames_int, help="number of frames (default: timeline)")
    p.add_argument("--duration", type=_positive_float, metavar="S",
                   help="simulated seconds (frames = S × frame rate)")
    p.add_argument("--seed", type=_seed_int, help="random seed (default: project seed)")
    p.add_argument("--overwrite", action="store_true",
                   help="replace an existing output file (when the new one is complete)")
    p.add_argument("--resume", action="store_true",
                   help="continue an interrupted run of the same project and seed")
    p.add_argument("--workers", type=_workers_int, default=1,
                   help="local worker processes (default 1)")
    p.add_argument("--scheduler", metavar="ADDRESS",
                   help="run frames on Dask: 'local' for an embedded cluster of --workers "
                        "processes, or a scheduler address such as tcp://host:8786")
    p.add_argument("--preview", metavar="DIR", help="also write PNG previews into DIR")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    p.add_argument("--shard-frames", type=_int_at_least(1, 4096), default=16, metavar="K",
                   help="Zarr: frames per shard, the unit a worker writes (default 16)")
    p.add_argument("--storage-option", action="append", metavar="KEY=VALUE",
                   help="Zarr on a URL: an fsspec storage option such as "
                        "endpoint_url=http://127.0.0.1:9000 (repeatable)")
    _run_options(p)
    p.set_defaults(func=cmd_run)

    p = sub.add_parser("generate", help="randomized projects from a scenario spec",
                       parents=common)
    p.add_argument("spec", help="scenario spec (JSON or YAML, docs/scenarios.md)")
    p.add_argument("--count", type=_int_at_least(1, 100_000), required=True, metavar="N",
                   help="number of projects")
    p.add_argument("--out", required=True, metavar="DIR", help="folder for scene_NNNNN.json")
    p.add_argument("--seed", type=_seed_int, default=0, help="random seed (default 0)")
    p.add_argument("--overwrite", action="store_true", help="replace existing scene files")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    p.add_argument("--run", metavar="OUT",
                   help="then run every project into one dataset OUT (as 'tofradar run DIR')")
    p.add_argument("--frames", type=_frames_int,
                   help="with --run: frames per scene (default: the timeline)")
    p.add_argument("--workers", type=_workers_int, default=1,
                   help="with --run: local worker processes")
    p.add_argument("--scheduler", metavar="ADDRESS", help="with --run: Dask scheduler")
    p.add_argument("--shard-frames", type=_int_at_least(1, 4096), default=16, metavar="K",
                   help="with --run: Zarr frames per shard")
    p.add_argument("--storage-option", action="append", metavar="KEY=VALUE",
                   help="with --run: fsspec storage option of a Zarr URL (repeatable)")
    p.add_argument("--overwrite-run", action="store_true",
                   help="with --run: replace an existing dataset OUT")
    p.add_argument("--resume", action="store_true",
                   help="with --run: continue an interrupted dataset OUT")
    p.add_argument("--force", action="store_true",
                   help="with --run: run even over the memory, disk or time budget")
    p.set_defaults(func=cmd_generate)

    p = sub.add_parser("sweep", help="one dataset per combination of varied project fields",
                       parents=common)
    p.add_argument("project", help="project JSON file")
    p.add_argument("--vary", action="append", required=True, metavar="PATH=START:STOP:STEP",
                   help="field path and values, e.g. objects[0].pose.position_m[0]=1:3:0.5 "
                        "or rig.radar.chirps_per_frame=16,32 (repeatable)")
    p.add_argument("--out", required=True, metavar="DIR", help="output directory")
    p.add_argument("--frames", type=_frames_int, help="frames per variant")
    p.add_argument("--duration", type=_positive_float, metavar="S", help="seconds per variant")
    p.add_argument("--seed", type=_seed_int, help="random seed (default: project's)")
    p.add_argument("--overwrite", action="store_true", help="replace existing datasets")
    p.add_argument("--resume", action="store_true", help="continue interrupted datasets")
    p.add_argument("--workers", type=_workers_int, default=1, help="local worker processes")
    p.add_argument("--scheduler", metavar="ADDRESS", help="Dask scheduler ('local' or address)")
    _run_options(p)
    p.set_defaults(func=cmd_sweep)

    p = sub.add_parser("report", help="regenerate the validation report with figures",
                       parents=[_common()])
    p.add_argument("--out", default="docs/validation", help="output directory")
    p.add_argument("--quick", action="store_true", help="fewer frames (for tests)")
    p.add_argument("--quiet", action="store_true", help="no progress messages")
    p.set_defaults(func=cmd_report)

    _add_robotics_commands(sub, common)
    _add_products_command(sub, common)
    _add_asset_commands(sub, common)

    p = sub.add_parser("devices", help="list the device library (radars and ToF cameras) "
                       "with their key figures", parents=common)
    p.set_defaults(func=cmd_devices)

    p = sub.add_parser("validate", help="check a project file as 'run' would", parents=common)
    p.add_argument("project", help="project JSON file")
    p.set_defaults(func=cmd_validate)

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

    p = sub.add_parser("materials", help="list the materials and what each does per band",
                       parents=common)
    p.add_argument("project", nargs="?",
                   help="project (its material table and users; default: the library)")
    p.set_defaults(func=cmd_materials)

    p = sub.add_parser("examples", help="list the bundled example projects or copy them",
                       parents=[_common()])
    p.add_argument("--copy", metavar="DIR", help="copy them (with their meshes) into DIR")
    p.set_defaults(func=cmd_examples)
    return parser


#: Most values one ``--vary`` may give.
MAX_VARY_VALUES = 10_000


def _check_vary_count(spec: str) -> None:
    """Refuse a ``--vary`` range with more values than :data:`MAX_VARY_VALUES` early."""
    _, _, values = spec.partition("=")
    parts = values.split(":")
    if len(parts) != 3:
        return
    try:
        start, stop, step = (float(p) for p in parts)
    except ValueError:
        return
    count = (stop - start) / step if step else float("inf")
    if not (abs(count) < MAX_VARY_VALUES):
        raise CliError(f"--vary {spec[:80]!r}: step {step:g} gives {abs(count):.3g} values; "
                       f"allowed at most {MAX_VARY_VALUES}")


def _report_error(exc: BaseException) -> int:
    """Print ``exc`` as ``tofradar: error: …`` line(s); return the exit status."""
    from simcore.scene.mesh_files import MeshError

    if isinstance(exc, ProjectError):
        for problem in exc.problems:
            _print_error(f"{exc.source}: {problem}")
        return 2
    if isinstance(exc, (CliError, MeshError, RunError)):
        _print_error(str(exc))
        return 2
    if isinstance(exc, MemoryError):
        _print_error("out of memory; lower the render resolution, chirps or samples, or run "
                     "fewer workers ('tofradar validate' shows the estimate)")
        return 1
    if isinstance(exc, OSError):
        if exc.errno in (errno.ENOSPC, errno.EDQUOT):
            _print_error(f"disk full: {exc}; free space and continue with --resume")
        else:
            _print_error(str(exc))
        return 2
    name = type(exc).__name__
    text = " ".join(str(exc).split())
    text = text if len(text) <= 300 else text[:297] + "..."
    _print_error(f"{name}: {text} (run with --debug for the traceback)")
    return 1


def cmd_convert(args: argparse.Namespace) -> int:
    """Convert an HDF5 dataset into an MCAP recording with ROS 2 messages."""
    from simcore.io.hdf5_writer import DatasetExistsError
    from simcore.io.mcap_writer import convert_hdf5_to_mcap

    source, target = Path(args.source), Path(args.to)
    if source.is_dir():
        return _convert_recording(source, target, args)
    if source.suffix.lower() == ".bin" or target.suffix.lower() == ".bin":
        return _convert_ti(source, target, args)
    if args.cfg is not None or args.lanes is not None:
        raise CliError("--cfg and --lanes are for TI captures (CAPTURE.bin --to OUT.h5, or "
                       "DATASET.h5 --to OUT.bin)")
    if args.project is not None:
        raise CliError("--project is for a recording folder (RECORDING_DIR --to OUT.h5)")
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


def _convert_recording(source: Path, target: Path, args: argparse.Namespace) -> int:
    """A Radar Fusion GUI / ifxdaq recording → a dataset (+ a project reproducing it)."""
    from simcore.io.hdf5_writer import DatasetExistsError
    from simcore.io.recordings import RecordingError, convert_recording

    if target.suffix.lower() not in (".h5", ".hdf5"):
        raise CliError(f"--to {target}: a recording converts to an HDF5 dataset (.h5)")
    if args.project is not None and Path(args.project).suffix.lower() != ".json":
        raise CliError(f"--project {args.project}: a project file ends in .json")
    try:
        report = convert_recording(source, target, project_out=args.project,
                                   overwrite=args.overwrite)
    except (RecordingError, DatasetExistsError) as exc:
        raise CliError(str(exc)) from None
    print(f"wrote {report.n_frames} frames to {target}"
          + (f" and the project {report.project}" if report.project else ""))
    return 0


def _convert_ti(source: Path, target: Path, args: argparse.Namespace) -> int:
    """A TI DCA1000 capture ↔ a dataset (docs/devices.md, "TI DCA1000 captures")."""
    from simcore.io.hdf5_writer import DatasetExistsError
    from simcore.io.ti_dca1000 import CaptureError, convert_capture, export_capture

    try:
        if source.suffix.lower() == ".bin":
            if target.suffix.lower() not in (".h5", ".hdf5"):
                raise CliError(f"--to {target}: a TI capture converts to an HDF5 dataset (.h5)")
            if args.project is not None and Path(args.project).suffix.lower() != ".json":
                raise CliError(f"--project {args.project}: a project file ends in .json")
            n = convert_capture(source, target, cfg=args.cfg, lanes=args.lanes,
                                project_out=args.project, overwrite=args.overwrite)
            print(f"wrote {n} frames to {target}"
                  + (f" and the project {args.project}" if args.project else ""))
            return 0
        if args.project is not None or args.cfg is not None:
            raise CliError("--project and --cfg are for reading a capture (CAPTURE.bin --to "
                           "OUT.h5); writing one puts its .cfg beside it")
        if not source.is_file():
            raise CliError(f"{source}: no such dataset")
        n, cfg = export_capture(source, target, lanes=2 if args.lanes is None else args.lanes,
                                overwrite=args.overwrite)
    except (CaptureError, DatasetExistsError) as exc:
        raise CliError(str(exc)) from None
    print(f"wrote {n} frames to {target} and its configuration {cfg}")
    return 0


def _run_ti_capture(args: argparse.Namespace) -> int:
    """``run P.json --out X.bin``: run into a temporary dataset, then write the capture."""
    import contextlib
    import io
    import tempfile

    from simcore.io.ti_dca1000 import CaptureError, export_capture

    out = Path(args.out)
    if (out.exists() or out.with_suffix(".cfg").exists()) and not args.overwrite:
        raise CliError(f"{out} or its .cfg already exists; use --overwrite to replace it")
    if args.resume:
        raise CliError("--resume is for datasets; a TI capture is written in one go")
    with tempfile.TemporaryDirectory(dir=out.parent if out.parent.is_dir() else None) as tmp:
        args.out = str(Path(tmp) / f"{out.stem}.h5")
        with contextlib.redirect_stdout(io.StringIO()):      # its "wrote …" names the temp file
            status = cmd_run(args)
        if status != 0:
            return status
        try:
            n, cfg = export_capture(args.out, out, overwrite=True)
        except CaptureError as exc:
            raise CliError(str(exc)) from None
    print(f"wrote {n} frames to {out} and its configuration {cfg}")
    return 0


def cmd_devices(args: argparse.Namespace) -> int:
    """List the device library's radars and cameras with their key figures."""
    from simcore.scene.devices import devices_table

    print("\n".join(devices_table()))
    return 0


def cmd_serve(args: argparse.Namespace) -> int:
    """Publish frames live over the Foxglove WebSocket protocol."""
    from simcore.io.live import serve

    project_path = Path(args.project)
    project = load_project(project_path)
    _preflight(project, project_path, args, n_frames=args.frames, seed=args.seed)

    def ready(port: int) -> None:
        print(f"serving on ws://{args.host}:{port} (Foxglove WebSocket protocol)", flush=True)

    with stop_on_sigint() as stop:
        report = serve(project, base_dir=project_path.parent, host=args.host, port=args.port,
                       n_frames=args.frames, loop=args.loop, realtime=not args.fast,
                       wait_for_client=not args.no_wait, seed=args.seed, on_ready=ready,
                       stop=stop)
    print(f"published {report.frames_published} frames")
    return 0


def _add_robotics_commands(sub: argparse._SubParsersAction[_Parser],
                           common: list[_Parser]) -> None:
    """The ``convert`` and ``serve`` subcommands (docs/robotics.md)."""
    p = sub.add_parser("convert", help="convert an HDF5 dataset into an MCAP recording or a "
                       "TI DCA1000 capture (.bin), or a real radar recording (Radar Fusion GUI "
                       "folder, TI capture .bin + .cfg) into a dataset",
                       parents=common)
    p.add_argument("source", help="HDF5 dataset, a recording folder (RadarIfxAvian_*), or a "
                                  "TI DCA1000 capture (.bin)")
    p.add_argument("--to", required=True,
                   help="output MCAP file (.mcap) or TI capture (.bin, .cfg beside it) for a "
                        "dataset, HDF5 file (.h5) for a recording or capture")
    p.add_argument("--project", help="recording or TI capture only: also write a project "
                                     "(.json) whose radar reproduces its configuration")
    p.add_argument("--cfg", help="TI capture (.bin) only: the mmWave SDK .cfg or mmWave Studio "
                                 ".json that configured the radar (default: beside the "
                                 "capture)")
    p.add_argument("--lanes", type=int, help="TI capture only: LVDS lanes of the DCA1000 "
                                             "capture, 2 (xWR16/18/68xx) or 4 (default: the "
                                             "Studio JSON's, else 2)")
    p.add_argument("--overwrite", action="store_true", help="replace an existing output file")
    p.set_defaults(func=cmd_convert)

    p = sub.add_parser("serve", help="publish frames live over the Foxglove WebSocket protocol",
                       parents=common)
    p.add_argument("project", help="project JSON file")
    p.add_argument("--host", default="127.0.0.1", help="interface (default 127.0.0.1)")
    p.add_argument("--port", type=_int_at_least(0, 65535), default=8765,
                   help="TCP port (default 8765; 0 = any free port)")
    p.add_argument("--frames", type=_frames_int, help="frames to publish (default: timeline)")
    p.add_argument("--loop", action="store_true", help="repeat the timeline until Ctrl+C")
    p.add_argument("--fast", action="store_true",
                   help="publish as fast as frames are computed (default: timeline frame rate)")
    p.add_argument("--no-wait", action="store_true",
                   help="start at once (default: wait until a client subscribes)")
    p.add_argument("--seed", type=_seed_int, help="random seed (default: project's)")
    p.set_defaults(func=cmd_serve)


def cmd_products(args: argparse.Namespace) -> int:
    """Write the micro-Doppler spectrogram and vital signs of a finished dataset into it."""
    from simcore.io.products import ProductsError, radars_with_adc, write_radar_products

    source = Path(args.dataset)
    if not source.is_file():
        raise CliError(f"{source}: no such dataset")
    try:
        radars = [args.radar] if args.radar else radars_with_adc(source)
        if not radars:
            raise CliError(f"{source}: the dataset has no radar; the products (spectrogram, "
                           "vital signs) are a radar's")
        summaries = {radar: write_radar_products(source, object_name=args.object, radar=radar)
                     for radar in radars}
    except ProductsError as exc:
        raise CliError(str(exc)) from None
    except (OSError, KeyError) as exc:  # not HDF5, or no /meta: not one of our datasets
        raise CliError(f"{source}: not a tofradar HDF5 dataset ({exc})") from None
    for radar, summary in summaries.items():
        sg, vs = summary.spectrogram, summary.vitals
        print(f"{source}: /{radar}/spectrogram ({sg.power_db.shape[0]} columns × "
              f"{sg.power_db.shape[1]} Doppler bins) and /{radar}/vitals written")
        if vs is not None:
            print(f"chest bin at {summary.range_m:.3f} m: breathing {vs.breathing_rate_hz:.3f} "
                  f"Hz ({vs.breathing_amplitude_m * 1e3:.2f} mm), heart "
                  f"{vs.heart_rate_hz:.3f} Hz ({vs.heart_amplitude_m * 1e3:.3f} mm)")
    return 0


def _add_products_command(sub: argparse._SubParsersAction[_Parser],
                          common: list[_Parser]) -> None:
    """The ``products`` subcommand (docs/dsp.md, "Micro-Doppler and vital signs")."""
    p = sub.add_parser("products", help="add the micro-Doppler spectrogram and vital signs "
                                        "to a finished dataset", parents=common)
    p.add_argument("dataset", help="HDF5 dataset written by 'tofradar run'")
    p.add_argument("--object", default=None, metavar="NAME",
                   help="follow this object's true range (range gate and chest search)")
    p.add_argument("--radar", default=None, metavar="NAME",
                   help="only this radar (default: every radar with ADC data in the dataset)")
    p.set_defaults(func=cmd_products)
def cmd_import(args: argparse.Namespace) -> int:
    """Import a glTF/GLB/OBJ scene into a new project (or into a copy of BASE)."""
    from simcore.scene.asset_import import build_project, parse_map_options
    from simcore.scene.assets import AssetError, read_asset
    from simcore.scene.project_io import save_project

    out = Path(args.out)
    if out.suffix.lower() != ".json":
        raise CliError(f"--out {out}: the project file must end in .json")
    base = load_project(args.into) if args.into else None
    if base is not None and Path(args.into).resolve().parent != out.resolve().parent and any(
            o.geometry.kind == "mesh" for o in base.objects):
        raise CliError(f"--into {args.into}: its mesh paths are relative to its folder; "
                       "write --out into the same folder")
    try:
        overrides = parse_map_options(args.map)
        scene = read_asset(Path(args.scene), up=args.up)
        result = build_project(scene, out, base=base, overrides=overrides)
    except AssetError as exc:
        raise CliError(str(exc)) from None
    save_project(result.project, out)
    print(f"wrote {out}: {len(result.object_names)} objects, {result.n_triangles} triangles "
          f"from {Path(args.scene).name} (meshes in {out.stem}.meshes/)")
    print("material mapping:")
    for line in result.report_lines():
        print(line)
    for note in result.skipped:
        print(f"  skipped: {note}")
    return 0


def _add_asset_commands(sub: argparse._SubParsersAction[_Parser],
                        common: list[_Parser]) -> None:
    """The ``import`` subcommand (docs/assets.md)."""
    p = sub.add_parser("import", help="import a glTF/GLB/OBJ scene as a project's objects",
                       parents=common)
    p.add_argument("scene", help="asset file (.gltf with its buffers, .glb or .obj)")
    p.add_argument("--out", required=True, help="project file to write (.json)")
    p.add_argument("--into", metavar="BASE", help="add the objects to this project's "
                                                  "objects and rig (default: a new project)")
    p.add_argument("--map", action="append", metavar="ASSET_MATERIAL=LIBRARY_MATERIAL",
                   help="map an asset material to a library material (repeatable)")
    p.add_argument("--up", choices=("y", "z"), default="y",
                   help="up axis of an OBJ file (default y, as Blender exports; glTF is "
                        "always y up)")
    p.set_defaults(func=cmd_import)


def main(argv: Sequence[str] | None = None, *,
         gui_launcher: Callable[[str | None], int] | None = None) -> int:
    """Run the ``tofradar`` command line.

    ``gui_launcher(project_path_or_None)`` opens the GUI; the ``app`` package passes it
    (the core never imports the GUI). Every error ends as one line
    ``tofradar: error: …`` on stderr and a non-zero exit status; ``--debug`` raises it
    with its traceback instead.
    """
    parser = build_parser()
    args = parser.parse_args(argv)
    if args.command is None:
        args = parser.parse_args(["gui", *(argv or [])])
    args.gui_launcher = gui_launcher
    debug = args.debug or getattr(args, "debug_global", False)
    if not debug:
        # Numerical warnings are not messages for the user (the outputs are checked); worker
        # processes inherit the setting through the environment.
        warnings.simplefilter("ignore", RuntimeWarning)
        os.environ.setdefault("PYTHONWARNINGS", "ignore::RuntimeWarning")
    try:
        return int(args.func(args))
    except KeyboardInterrupt:
        print("tofradar: interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:
        # The reader of the output went away (``tofradar materials | head``): not an error.
        # Point stdout at /dev/null so the interpreter's final flush does not complain.
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 0
    except Exception as exc:  # noqa: BLE001 — the one top-level error path
        if debug:
            raise
        return _report_error(exc)


if __name__ == "__main__":
    sys.exit(main())
