"""Why an edit was refused, in words, for the field that was edited.

The project model (pydantic, :mod:`simcore.scene`) and :func:`simcore.preflight.check` say
what is wrong with a project in terms of its fields (``rig.radar.chirps_per_frame: Input
should be greater than or equal to 1``; cross-field rules name the model and quote its whole
input). The GUI shows the reason next to the field the user edited, so this module turns
those errors into short sentences with the GUI's own names for the fields and quantities
in units with SI prefixes — "chirps / frame must be at least 1 (got 0)", "bandwidth = 150
GHz is more than 0.5 × start frequency (60 GHz)" — never ``3e+11`` or a whole configuration.
A field that knows its label and unit words its own errors
(:meth:`app.editors.field_editors.FieldSpec.explain`).
"""

from __future__ import annotations

import re
from decimal import Decimal
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

#: Bound kinds of pydantic errors, as the words of a sentence ("must be at least 1").
BOUND_WORDS = {"greater_than_equal": ("at least", "ge"), "less_than_equal": ("at most", "le"),
               "greater_than": ("above", "gt"), "less_than": ("below", "lt")}
_IDENT = re.compile(r"\b(?:rig\.(?:radar|tof)\.|dsp\.)?([a-z][a-z0-9]*(?:_[a-z0-9]+)+)\b")
#: Units of the model's field-name suffixes (``start_frequency_hz`` is in Hz).
SUFFIX_UNITS = {"hz": "Hz", "s": "s", "m": "m", "mm": "mm", "deg": "°", "dbm": "dBm",
                "db": "dB", "dbi": "dBi", "dbc": "dBc", "mps": "m/s", "dps": "°/s", "m2": "m²",
                "v": "V"}
#: SI prefixes used for quantities in messages (Hz, s and m only).
_PREFIXES = [(1e9, "G"), (1e6, "M"), (1e3, "k"), (1.0, ""), (1e-3, "m"), (1e-6, "µ"),
             (1e-9, "n")]
_PREFIXED_UNITS = ("Hz", "s", "m")
_NUM = r"-?\d+(?:\.\d+)?(?:e[+-]?\d+)?"
_INTERVAL = re.compile(rf"(?P<open>[\[(])(?P<a>{_NUM}), (?P<b>{_NUM})(?P<close>[\])]) "
                       r"(?P<unit>Hz|s|m)(?![\w/²])")
_QUANTITY = re.compile(rf"(?<![\w.])(?P<n>{_NUM})(?P<close>[\])]?) (?P<unit>Hz|s|m)(?![\w/²])")
_EXPONENT = re.compile(r"(?<![\w.])-?\d+(?:\.\d+)?e[+-]?\d+\b")


def format_number(value: float, *, digits: int = 6) -> str:
    """``value`` as plain decimals, ``digits`` significant at most: never ``3e+11``."""
    if isinstance(value, int) or (isinstance(value, float) and value.is_integer()
                                  and abs(value) < 1e15):
        return str(int(value))
    rounded = Decimal(f"{value:.{digits}g}").normalize()
    text = format(rounded, "f")
    return "0" if text in ("-0", "0") else text


def _prefix(value: float, unit: str) -> tuple[float, str]:
    if unit not in _PREFIXED_UNITS or value == 0:
        return 1.0, ""
    for factor, prefix in _PREFIXES:
        if abs(value) >= factor * (1 - 1e-12):
            return factor, prefix
    return _PREFIXES[-1]


def quantity(value: float, unit: str, *, factor: tuple[float, str] | None = None) -> str:
    """``"60 GHz"``: a value in SI ``unit`` with an SI prefix (Hz, s, m) and plain digits."""
    scale, prefix = factor if factor is not None else _prefix(value, unit)
    shown = float(Decimal(repr(float(value))) / Decimal(repr(scale)))
    return f"{format_number(shown)} {prefix}{unit}".rstrip()


def humanize_quantities(text: str) -> str:
    """Quantities in a core message in the user's units: ``6e+10 Hz`` reads ``60 GHz``."""
    def interval(m: re.Match[str]) -> str:
        a, b, unit = float(m["a"]), float(m["b"]), m["unit"]
        factor = _prefix(max(abs(a), abs(b)), unit)
        return f"{m['open']}{quantity(a, unit, factor=factor)}, " \
               f"{quantity(b, unit, factor=factor)}{m['close']}"

    text = _INTERVAL.sub(interval, text)
    text = _QUANTITY.sub(lambda m: quantity(float(m["n"]), m["unit"]) + m["close"], text)
    return _EXPONENT.sub(lambda m: format_number(float(m.group(0))), text)


def in_words(text: str) -> str:
    """Model field names (``chirp_time_s``) as the GUI's words, quantities in units."""
    return humanize_quantities(
        _IDENT.sub(lambda m: FIELD_WORDS.get(m.group(1), m.group(0)), text))


def _field_name(loc: tuple[Any, ...]) -> str | None:
    names = [p for p in loc if isinstance(p, str)]
    return names[-1] if names else None


def unit_of(name: str) -> str:
    """The unit a model field name's suffix says (``bandwidth_hz`` → Hz; ``""`` if none)."""
    suffix = name.rsplit("_", 1)[-1] if "_" in name else ""
    return SUFFIX_UNITS.get(suffix, "")


def plain_name(name: str) -> str:
    """A model field name without its unit suffix, in words: ``size_m`` → ``size``."""
    if unit_of(name):
        name = name.rsplit("_", 1)[0]
    return name.replace("_", " ")


def _value(value: Any, unit: str = "") -> str:
    if isinstance(value, bool) or not isinstance(value, (int, float, str)):
        return str(value) if isinstance(value, bool) else ""
    if isinstance(value, str):
        return value
    return quantity(value, unit) if unit else format_number(value)


def bound_sentence(label: str, err: dict[str, Any], show: Any, unit: str = "") -> str | None:
    """"Bandwidth must be above 0 GHz (got -1 GHz)" for a bound error, else None.

    ``show`` turns a model (SI) value into the text shown, without the unit.
    """
    kind = err.get("type", "")
    if kind not in BOUND_WORDS:
        return None
    word, key = BOUND_WORDS[kind]
    limit = (err.get("ctx") or {}).get(key)
    unit = f" {unit}" if unit else ""
    got = err.get("input")
    got_text = f" (got {show(got)}{unit})" if isinstance(got, (int, float)) else ""
    return f"{label} must be {word} {show(limit)}{unit}{got_text}"


def describe_error(err: dict[str, Any]) -> str:
    """One pydantic error as a sentence (no quoted dicts or lists), units from the name."""
    name = _field_name(tuple(err.get("loc", ())))
    unit = unit_of(name or "")
    words = FIELD_WORDS.get(name or "") or plain_name(name or "")
    # One prefix for the limit and the value, chosen by the larger: "above 0 GHz (got -1 GHz)".
    numbers = [abs(float(v)) for v in (*(err.get("ctx") or {}).values(), err.get("input"))
               if isinstance(v, (int, float)) and not isinstance(v, bool)]
    factor = _prefix(max(numbers, default=0.0), unit)
    sentence = bound_sentence(
        words, err, lambda v: quantity(v, unit, factor=factor).rsplit(" ", 1)[0] if unit
        else format_number(v), f"{factor[1]}{unit}")
    if sentence is not None:
        return sentence
    value = _value(err.get("input"), unit)
    got = f" (got {value})" if value else ""
    message = str(err.get("msg", "")).removeprefix("Value error, ")
    if isinstance(err.get("input"), (dict, list)):
        # A rule across fields (a model validator): its message names the fields, the
        # project's checks as "@<field path>: …" (simcore.scene.model.Project).
        if message.startswith("@") and ": " in message:
            message = message[1:]
        return in_words(message)
    return f"{words}: {in_words(message)}{got}" if words else in_words(message) + got


def describe_validation_error(exc: ValidationError) -> list[str]:
    """Every problem of a pydantic error, one sentence each."""
    return [describe_error(dict(err)) for err in exc.errors()]


def describe_problem(line: str) -> str:
    """A :func:`simcore.preflight.check` line (``field: message``) in the GUI's words."""
    return in_words(line)


__all__ = ["BOUND_WORDS", "FIELD_WORDS", "bound_sentence", "describe_error", "describe_problem",
           "describe_validation_error", "format_number", "humanize_quantities", "in_words",
           "plain_name", "quantity", "unit_of"]
