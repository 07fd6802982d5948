"""``tofradar products``: a finished dataset's micro-Doppler and vital signs."""

from __future__ import annotations

import argparse
from pathlib import Path

from simcore.cli.common import (
    CliError,
    _Parser,
)


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


def add_parser(sub: argparse._SubParsersAction[_Parser], common: list[_Parser]) -> None:
    """The ``products`` subcommand."""
    p = sub.add_parser("products", help="add the micro-Doppler spectrogram and vital signs "
                                        "to a finished dataset", parents=common)
    p.add_argument("dataset", help="HDF5 dataset written by 'tofradar run'")
    p.add_argument("--object", default=None, metavar="NAME",
                   help="follow this object's true range (range gate and chest search)")
    p.add_argument("--radar", default=None, metavar="NAME",
                   help="only this radar (default: every radar with ADC data in the dataset)")
    p.set_defaults(func=cmd_products)
