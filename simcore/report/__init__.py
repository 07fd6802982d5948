"""The validation report (being split into one module per section)."""

from simcore.report.build import Figure, ReportResult, generate_report

__all__ = ["Figure", "ReportResult", "generate_report"]
