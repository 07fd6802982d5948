"""The GUI's models without a display: the document (edits, undo history, selection).

``ProjectDocument`` is a QObject with no widgets, so it runs under Qt's ``offscreen``
platform: these tests are in the core group and need no X server.
"""

from __future__ import annotations

import pytest

pytest.importorskip("PyQt6")

import os  # noqa: E402
from collections.abc import Iterator  # noqa: E402

from PyQt6 import sip  # noqa: E402
from PyQt6.QtGui import QGuiApplication  # noqa: E402

from app.document.document import RIG, EditError, ProjectDocument  # noqa: E402
from simcore.resources import example_path  # noqa: E402
from simcore.scene import load_project  # noqa: E402


@pytest.fixture(scope="module")
def qapp() -> QGuiApplication:
    if QGuiApplication.instance() is None:
        os.environ.setdefault("QT_QPA_PLATFORM", "offscreen")
    app = QGuiApplication.instance() or QGuiApplication([])
    assert isinstance(app, QGuiApplication)
    return app


@pytest.fixture
def doc(qapp: QGuiApplication) -> Iterator[ProjectDocument]:
    document = ProjectDocument(load_project(example_path("point_targets")))
    yield document
    # Destroy it now, quietly: its undo stack signals "clean" while it is torn down.
    document.undo_stack.blockSignals(True)
    sip.delete(document)


def test_edits_undo_and_redo_as_one_step_each(doc: ProjectDocument) -> None:
    before = doc.project.objects[0].pose.position_m
    changed: list[object] = []
    doc.projectChanged.connect(changed.append)
    doc.set_value("objects[0].pose.position_m", [1.0, 2.0, 3.0], text="Move corner")
    assert doc.project.objects[0].pose.position_m == (1.0, 2.0, 3.0)
    assert doc.is_dirty and len(changed) == 1
    assert doc.undo_stack.undoText() == "Move corner"
    doc.undo_stack.undo()
    assert doc.project.objects[0].pose.position_m == before
    assert not doc.is_dirty
    doc.undo_stack.redo()
    assert doc.project.objects[0].pose.position_m == (1.0, 2.0, 3.0)


def test_drags_merge_into_one_undo_step(doc: ProjectDocument) -> None:
    for x in (1.0, 1.1, 1.2):
        doc.set_value("objects[0].pose.position_m", [x, 0.0, 1.0], merge_key="drag")
    doc.end_merge()
    assert doc.undo_stack.count() == 1
    doc.undo_stack.undo()
    assert doc.project == load_project(example_path("point_targets"))


def test_an_invalid_edit_is_refused_and_leaves_no_undo_step(doc: ProjectDocument) -> None:
    with pytest.raises(EditError, match=r"chirps / frame must be at least 1 \(got 0\)") as info:
        doc.set_value("rig.radar.chirps_per_frame", 0)
    assert doc.undo_stack.count() == 0 and not doc.is_dirty
    # The model's own error rides along, for the field to word in its unit.
    (err,) = info.value.errors
    assert err["loc"] == ("rig", "radar", "chirps_per_frame") and err["input"] == 0


def test_default_undo_text_is_in_words(doc: ProjectDocument) -> None:
    doc.set_value("rig.radar.bandwidth_hz", 2e9)
    assert doc.undo_stack.text(0) == "Set bandwidth"


def test_selection_follows_the_objects(doc: ProjectDocument) -> None:
    seen: list[object] = []
    doc.selectionChanged.connect(seen.append)
    first = doc.project.objects[0].id
    doc.select(first)
    assert doc.selection == first and doc.selected_index() == 0
    doc.select(RIG)
    assert doc.selected_index() is None
    doc.select(first)
    doc.edit("Delete", lambda d: d["objects"].pop(0))
    assert doc.selection is None, "deleting the selected object clears the selection"
    assert seen[-1] is None


def test_time_controller_clamps_steps_and_waits_for_each_frame(doc: ProjectDocument) -> None:
    from app.widgets.time_controls import TimeController

    time = TimeController(doc)
    n = doc.project.timeline.n_frames            # point_targets: 10 frames at 10 Hz
    assert n == round(doc.project.timeline.duration_s * doc.project.timeline.frame_rate_hz)
    time.set_index(n + 5)
    assert time.index == n - 1 and time.time_s == pytest.approx((n - 1) / 10.0)
    time.set_index(-3)
    assert time.index == 0
    time.step(2)
    assert time.index == 2 and time.next_index == 3
    # While a frame is being computed, a playback tick is remembered, not skipped ahead.
    time._tick()
    assert time.index == 2
    time._timer.start(1000)   # playing, without waiting for real ticks
    shown: list[int] = []
    time.frameShown.connect(shown.append)
    time.frame_done()         # the frame of index 2 is shown: the pending tick moves on
    assert shown == [2] and time.index == 3
    time.set_playing(False)
    # A shorter timeline clamps the index.
    doc.set_value("timeline.duration_s", 0.2)
    assert time.index == 1
