"""``tofradar convert``: datasets to MCAP or TI captures, recordings to datasets."""

from __future__ import annotations

import argparse
from pathlib import Path

from simcore.cli.common import (
    CliError,
    _Parser,
)


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
    existed = target.exists()
    try:
        report = convert_recording(source, target, project_out=args.project,
                                   overwrite=args.overwrite,
                                   allow_outside_paths=args.allow_outside_paths)
    except BaseException as exc:
        # No complete-looking dataset of a conversion that did not finish.
        if not existed:
            target.unlink(missing_ok=True)
        if isinstance(exc, (RecordingError, DatasetExistsError)):
            raise CliError(str(exc)) from None
        if isinstance(exc, OSError) and not isinstance(exc, DatasetExistsError):
            raise CliError(f"{exc.filename or target}: {exc.strerror or exc}") from None
        raise
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


def add_parser(sub: argparse._SubParsersAction[_Parser], common: list[_Parser]) -> None:
    """The ``convert`` subcommand."""
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
