"""Refusal messages are sentences with the GUI's field names, never quoted configurations."""

from __future__ import annotations

import pytest
from pydantic import ValidationError

from app.validation import describe_validation_error, in_words
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
    ({"chirps_per_frame": 0}, "chirps / frame must be ≥ 1 (got 0)"),
    ({"chirps_per_frame": 10**9}, "chirps / frame must be ≤ 1024 (got 1000000000)"),
    ({"bandwidth_hz": -1.0}, "bandwidth must be > 0 (got -1)"),
    ({"chirp_time_s": 500e-6},
     "chirp repetition time (300.0 µs) is shorter than chirp time (500.0 µs)"),
])
def test_messages_in_words(radar, expected):
    messages = _errors(**radar)
    assert expected in messages, messages
    assert not any("{" in m or "_hz" in m or "_s " in m for m in messages), messages


def test_cross_field_rule_names_fields_in_words():
    (message,) = _errors(bandwidth_hz=150e9)
    assert message.startswith("bandwidth = 1.5e+11 Hz"), message
    assert "start frequency" in message and "{" not in message


def test_in_words_keeps_unknown_names():
    assert in_words("rig.radar.chirp_time_s and foo_bar") == "chirp time and foo_bar"
