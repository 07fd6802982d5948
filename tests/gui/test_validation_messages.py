"""Refusal messages are sentences with the GUI's field names, never quoted configurations."""

from __future__ import annotations

import pytest
from pydantic import ValidationError

from app.document.validation import (
    describe_validation_error,
    format_number,
    humanize_quantities,
    in_words,
)
from simcore.resources import EXAMPLES_DIR
from simcore.scene import Project, load_project

pytestmark = pytest.mark.gui


def _errors(**radar: float) -> list[str]:
    data = load_project(EXAMPLES_DIR / "office.json").model_dump()
    data["rig"]["radar"].update(radar)
    with pytest.raises(ValidationError) as info:
        Project.model_validate(data)
    return describe_validation_error(info.value)


@pytest.mark.parametrize(("radar", "expected"), [
    ({"chirps_per_frame": 0}, "chirps / frame must be at least 1 (got 0)"),
    ({"chirps_per_frame": 10**9}, "chirps / frame must be at most 1024 (got 1000000000)"),
    ({"bandwidth_hz": -1.0}, "bandwidth must be above 0 Hz (got -1 Hz)"),
    ({"start_frequency_hz": 5e12}, "start frequency must be below 300 GHz (got 5000 GHz)"),
    ({"chirp_time_s": 500e-6},
     "chirp repetition time (300.0 µs) is shorter than chirp time (500.0 µs)"),
])
def test_messages_in_words(radar, expected):
    messages = _errors(**radar)
    assert expected in messages, messages
    assert not any("{" in m or "_hz" in m or "_s " in m for m in messages), messages


def test_cross_field_rule_names_fields_in_words():
    (message,) = _errors(bandwidth_hz=150e9)
    # Quantities in units with SI prefixes, never "1.5e+11 Hz".
    assert message == ("bandwidth = 150 GHz is more than 0.5 × start frequency (60 GHz); "
                       "allowed (0 GHz, 30 GHz]"), message


def test_in_words_keeps_unknown_names():
    assert in_words("rig.radar.chirp_time_s and foo_bar") == "chirp time and foo_bar"


@pytest.mark.parametrize(("text", "expected"), [
    ("allowed [1e+06, 1e+08] Hz", "allowed [1 MHz, 100 MHz]"),
    ("chirp time = 0.000256 s", "chirp time = 256 µs"),
    ("at most 3e+11", "at most 300000000000"),
    ("300.0 µs and 6.4 m and 2 m/s", "300.0 µs and 6.4 m and 2 m/s"),
])
def test_quantities_read_in_units(text, expected):
    assert humanize_quantities(text) == expected


@pytest.mark.parametrize(("value", "expected"), [
    (1999999999.9999998, "2000000000"), (0.1 + 0.2, "0.3"), (-1.0, "-1"), (1e-7, "0.0000001"),
    (58.3, "58.3"),
])
def test_numbers_have_no_exponents(value, expected):
    assert format_number(value) == expected
