"""Why an edit was refused, in words, for the field that was edited.

The project model (pydantic, :mod:`simcore.scene`) and :func:`simcore.preflight.check` say
what is wrong with a project in terms of its fields (``rig.radar.chirps_per_frame: Input
should be greater than or equal to 1``; cross-field rules name the model and quote its whole
input). The GUI shows the reason next to the field the user edited, so this module turns
those errors into short sentences with the GUI's own names for the fields — "chirps / frame
must be ≥ 1 (got 0)", "chirp repetition time (300.0 µs) is shorter than chirp time
(500.0 µs)" — and never quotes a whole configuration.
"""

from __future__ import annotations

import re
from typing import Any

from pydantic import ValidationError

#: The GUI's names of model fields, used in messages (field name → words).
FIELD_WORDS: dict[str, str] = {
    "start_frequency_hz": "start frequency",
    "bandwidth_hz": "bandwidth",
    "chirp_time_s": "chirp time",
    "sample_rate_hz": "ADC sample rate",
    "chirp_repetition_time_s": "chirp repetition time",
    "samples_per_chirp": "samples / chirp",
    "chirps_per_frame": "chirps / frame",
    "render_width": "render width",
    "render_height": "render height",
    "render_fov_h_deg": "render FOV",
    "render_supersampling": "radar render supersampling",
    "if_highpass_hz": "IF high-pass frequency",
    "supersampling": "supersampling",
    "modulation_frequencies_hz": "modulation frequencies",
    "fov_h_deg": "horizontal FOV",
    "fov_v_deg": "vertical FOV",
    "width": "width",
    "height": "height",
    "position_mm": "position",
    "position_m": "position",
    "rotation_deg": "rotation",
    "cfar_pfa": "false-alarm rate",
    "min_range_m": "min detection range",
    "max_range_m": "max range",
    "range_fft_size": "range FFT size",
    "doppler_fft_size": "Doppler FFT size",
    "frame_rate_hz": "frame rate",
    "duration_s": "duration",
}

_BOUNDS = {"greater_than_equal": ("≥", "ge"), "less_than_equal": ("≤", "le"),
           "greater_than": (">", "gt"), "less_than": ("<", "lt")}
_IDENT = re.compile(r"\b(?:rig\.(?:radar|tof)\.|dsp\.)?([a-z][a-z0-9]*(?:_[a-z0-9]+)+)\b")


def in_words(text: str) -> str:
    """Replace model field names (``chirp_time_s``) in ``text`` by the GUI's words."""
    return _IDENT.sub(lambda m: FIELD_WORDS.get(m.group(1), m.group(0)), text)


def _field_name(loc: tuple[Any, ...]) -> str | None:
    names = [p for p in loc if isinstance(p, str)]
    return names[-1] if names else None


def _value(value: Any) -> str:
    if isinstance(value, float):
        return f"{value:.6g}"
    if isinstance(value, (int, str)):
        return str(value)
    return ""


def describe_error(err: dict[str, Any]) -> str:
    """One pydantic error as a sentence (no quoted dicts or lists)."""
    name = _field_name(tuple(err.get("loc", ())))
    words = FIELD_WORDS.get(name or "", name or "")
    kind = err.get("type", "")
    value = _value(err.get("input"))
    got = f" (got {value})" if value else ""
    if kind in _BOUNDS:
        sign, key = _BOUNDS[kind]
        limit = (err.get("ctx") or {}).get(key)
        return f"{words} must be {sign} {_value(limit) or limit}{got}".strip()
    message = str(err.get("msg", "")).removeprefix("Value error, ")
    if isinstance(err.get("input"), (dict, list)):
        # A rule across fields (a model validator): its message names the fields.
        return in_words(message)
    return f"{words}: {in_words(message)}{got}" if words else in_words(message) + got


def describe_validation_error(exc: ValidationError) -> list[str]:
    """Every problem of a pydantic error, one sentence each."""
    return [describe_error(dict(err)) for err in exc.errors()]


def describe_problem(line: str) -> str:
    """A :func:`simcore.preflight.check` line (``field: message``) in the GUI's words."""
    return in_words(line)


__all__ = ["FIELD_WORDS", "describe_error", "describe_problem", "describe_validation_error",
           "in_words"]
