"""The validation report (``tofradar report``): one module per section, a new section a new file.

``build.py`` holds :func:`generate_report`, which runs the sections in order and writes the
figures, ``README.md`` and ``numbers.json``; ``_common.py`` what the sections share (the
figure record, plotting, the office's truths). Each other module is one section:
``office_tof``, ``office_radar``, ``range_azimuth``, ``doppler``, ``calibration``,
``side_by_side``, ``surfaces``, ``multipath``, ``interference``, ``products`` and ``real``
(the simulation beside a real BGT60TR13C recording).

The report sits above the pipeline: it may import :mod:`simcore.pipeline`, the sensors,
DSP, render, scene and io packages, never the command line (:mod:`simcore.cli`), the runs
(:mod:`simcore.runs`) or the GUI.
"""

from simcore.report.build import Figure, ReportResult, generate_report

__all__ = ["Figure", "ReportResult", "generate_report"]
