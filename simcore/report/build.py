"""Validation report: the reference simulator's experiments, regenerated as figures.

:func:`generate_report` runs the bundled example scenes through the whole pipeline, measures
each phenomenon against an independent answer (scene geometry, the radar equation written
out here from its constants, the exact direct-sum IF synthesis), draws one PNG per
experiment and writes ``README.md`` with a paragraph and the numbers for each. The numbers
are returned too, so that tests can hold them to the bars of the earlier issues.
"""

from __future__ import annotations

import json
from collections.abc import Callable
from pathlib import Path
from typing import Any

from simcore.pipeline import Simulator
from simcore.report._common import (
    Figure,
    ReportResult,
)
from simcore.report.calibration import calibration
from simcore.report.doppler import doppler_experiment
from simcore.report.multipath import multipath_section, tof_multipath_figure
from simcore.report.office_radar import office_radar_profile
from simcore.report.office_tof import office_tof
from simcore.report.products import products_section
from simcore.report.range_azimuth import office_range_azimuth
from simcore.report.side_by_side import side_by_side
from simcore.report.surfaces import (
    surfaces_moving_rig,
    surfaces_office_floor,
    surfaces_plate_sphere,
)
from simcore.resources import example_path
from simcore.scene.project_io import load_project


def generate_report(out_dir: str | Path, *, quick: bool = False,
                    progress: Callable[[str], None] | None = None) -> ReportResult:
    """Run every experiment, write the figures and ``README.md`` into ``out_dir``.

    ``quick`` uses fewer frames and calibration points (for tests); the figures and numbers
    are the same kind.
    """
    say = progress or (lambda message: None)
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    result = ReportResult(out)
    office = load_project(example_path("office"))
    with Simulator(office) as sim:
        frame = sim.frame(0)
    say("office frame done")
    for name, fn in (("office_tof", office_tof), ("office_radar", office_radar_profile),
                     ("office_range_azimuth", office_range_azimuth),
                     ("side_by_side", side_by_side)):
        fig, nums = fn(frame, office, out)
        result.figures.append(fig)
        result.numbers[name] = nums
        say(f"{name} done")
    doppler = load_project(example_path("doppler_back_and_forth"))
    n = 24 if quick else doppler.timeline.n_frames
    fig, nums = doppler_experiment(doppler, out, frames=n, progress=say)
    result.figures.insert(3, fig)
    result.numbers["doppler"] = nums
    fig, nums = calibration(out, quick=quick, progress=say)
    result.figures.insert(4, fig)
    result.numbers["calibration"] = nums
    surfaces: dict[str, Any] = {}
    fig, nums = surfaces_plate_sphere(out, progress=say)
    result.figures.append(fig)
    surfaces.update(nums)
    fig, nums = surfaces_office_floor(frame, office, out)
    result.figures.append(fig)
    surfaces["office_floor"] = nums
    say("surfaces: office floor done")
    fig, nums = surfaces_moving_rig(out, progress=say)
    result.figures.append(fig)
    surfaces["moving_rig"] = nums
    result.numbers["surfaces"] = surfaces
    figures, nums = multipath_section(out, quick=quick)
    for file, title, text in figures:
        result.figures.append(Figure(file, title, text, section="Multipath"))
    fig_tof, nums_tof = tof_multipath_figure(out)
    result.figures.append(Figure(*fig_tof, section="Multipath"))
    from simcore.report.sionna import sionna_section

    figures, nums_sionna = sionna_section(out)
    for file, title, text in figures:
        result.figures.append(Figure(file, title, text, section="Multipath"))
    result.numbers["multipath"] = {"radar": nums, "tof": nums_tof, "sionna": nums_sionna}
    from simcore.report.tof_reference import tof_reference_section

    figures, nums = tof_reference_section(out)
    for file, title, text in figures:
        result.figures.append(Figure(file, title, text, section="Multipath"))
    result.numbers["multipath"]["tof_mitransient"] = nums
    say("multipath done")
    from simcore.report.interference import interference_section

    figures, nums = interference_section(out, quick=quick)
    for file, title, text in figures:
        result.figures.append(Figure(file, title, text, section="Interference"))
    result.numbers["interference"] = nums
    say("interference done")
    figures, nums = products_section(out, quick=quick)
    for file, title, text in figures:
        result.figures.append(Figure(file, title, text, section="Radar products"))
    result.numbers["products"] = nums
    say("radar products done")
    real_bgt60tr13c(result, out, quick=quick)
    say("real BGT60TR13C done")
    _write_readme(result, quick=quick)
    (out / "numbers.json").write_text(json.dumps(result.numbers, indent=2, default=float) + "\n")
    return result


def real_bgt60tr13c(result: ReportResult, out: Path, *, quick: bool) -> None:
    """Section "simulation and a real BGT60TR13C" (:mod:`simcore.report.real`).

    Uses the shared real recording when present; otherwise the section says it is absent.
    """
    from simcore.report.real import real_section

    file, title, text, numbers = real_section(out, quick=quick)
    result.figures.append(Figure(file, title, text))
    result.numbers["real_bgt60tr13c"] = numbers


def _write_readme(result: ReportResult, *, quick: bool) -> None:
    lines = [
        "# Validation report",
        "",
        "Regenerated by `tofradar report` (or `make report`) from the bundled example "
        "scenes; every number below is measured by that run against an independent answer "
        "(scene geometry and exact rigid motion, the radar equation, the direct-sum IF "
        "synthesis). The raw numbers are in [numbers.json](numbers.json)."
        + (" *Quick mode: fewer frames and calibration points.*" if quick else ""),
        "",
    ]
    number, sub, section = 0, 0, None
    for fig in result.figures:
        if fig.section is None:
            number += 1
            lines += [f"## {number}. {fig.title}", ""]
        else:
            if fig.section != section:
                number += 1
                sub = 0
                lines += [f"## {number}. {fig.section}", ""]
            sub += 1
            title = fig.title.removeprefix(fig.section + ": ")
            lines += [f"### {number}.{sub} {title[:1].upper()}{title[1:]}", ""]
        section = fig.section
        lines += ([f"![{fig.title}]({fig.file})", ""] if fig.file else []) + [fig.text, ""]
    (result.out_dir / "README.md").write_text("\n".join(lines))
