"""Inspector rows of a person's motion block: posture, walk, gesture, vital signs, BVH.

The scene editor's inspector shows height and build like any geometry field; these rows
add the ``geometry.motion`` block (:class:`simcore.scene.people.PersonMotion`). Every
edit goes through the document (undoable); a refused value is shown at its field.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from PyQt6.QtCore import QSignalBlocker
from PyQt6.QtWidgets import QComboBox, QFormLayout, QLineEdit, QSpinBox, QWidget

from app.widgets.inputs import set_quietly, spin

GESTURES = ("none", "wave", "swipe_left", "swipe_right", "push", "pull", "circle")
Setter = Callable[[str, Any, str, QWidget | None], None]


def _combo(items: tuple[str, ...], tip: str) -> QComboBox:
    box = QComboBox()
    box.addItems(list(items))
    box.setToolTip(tip)
    return box


def _quiet(widget: QWidget, value: Any) -> None:
    if isinstance(widget, QComboBox):
        with QSignalBlocker(widget):
            widget.setCurrentText(str(value))
    else:
        set_quietly(widget, value)


class PersonMotionRows:
    """The rows (added to ``form``) and how they read and write a person's motion."""

    def __init__(self, form: QFormLayout, set_value: Setter):
        self._set = set_value
        self.geometry: Any = None
        w: dict[str, QWidget] = {}
        w["posture"] = _combo(("standing", "sitting", "lying"), "body posture")
        w["speed"] = spin(minimum=0.0, maximum=10.0, decimals=2, step=0.1, suffix="m/s",
                          tooltip="walking speed (0: no walk); the model refuses speeds "
                                  "beyond Boulic's range (v / leg length ≤ 2.3)")
        w["path"] = _combo(("straight", "keyframes"),
                           "straight: along the heading; keyframes: through the motion's "
                           "keyframe positions at this speed")
        w["gesture"] = _combo(GESTURES, "hand gesture")
        w["hand"] = _combo(("right", "left"), "hand that gestures")
        w["gesture_s"] = spin(minimum=0.06, maximum=1e4, decimals=2, step=0.5, suffix="s",
                              tooltip="gesture duration (all repetitions)")
        reps = QSpinBox()
        reps.setRange(1, 1000)
        reps.setToolTip("gesture repetitions")
        w["reps"] = reps
        w["breath_hz"] = spin(minimum=0.0, maximum=2.0, decimals=3, step=0.01, suffix="Hz",
                              tooltip="breathing rate (0 with 0 mm: no vital signs)")
        w["breath_mm"] = spin(minimum=0.0, maximum=50.0, decimals=2, step=0.5, suffix="mm",
                              tooltip="breathing: peak chest displacement from the mean")
        w["heart_hz"] = spin(minimum=0.0, maximum=4.0, decimals=3, step=0.05, suffix="Hz",
                             tooltip="heart rate")
        w["heart_mm"] = spin(minimum=0.0, maximum=5.0, decimals=3, step=0.05, suffix="mm",
                             tooltip="heartbeat: peak chest displacement from the mean")
        w["sway"] = spin(minimum=0.0, maximum=100.0, decimals=2, step=0.5, suffix="mm",
                         tooltip="slow random body sway amplitude")
        bvh = QLineEdit()
        bvh.setPlaceholderText("BVH file, relative to the project (empty: none)")
        bvh.setToolTip("motion capture clip (CMU joint names); drives the whole body")
        w["bvh"] = bvh
        labels = {"posture": "posture", "speed": "walk speed", "path": "walk path",
                  "gesture": "gesture", "hand": "gesture hand", "gesture_s": "gesture time",
                  "reps": "repetitions", "breath_hz": "breathing rate",
                  "breath_mm": "breathing ampl.", "heart_hz": "heart rate",
                  "heart_mm": "heartbeat ampl.", "sway": "sway", "bvh": "BVH clip"}
        for key, widget in w.items():
            form.addRow(labels[key], widget)
        self.widgets = w
        w["posture"].currentTextChanged.connect(  # type: ignore[attr-defined]
            lambda v: self._set("geometry.motion.posture", v, "Set posture", w["posture"]))
        for key in ("speed",):
            w[key].valueChanged.connect(lambda _v: self._walk())  # type: ignore[attr-defined]
        w["path"].currentTextChanged.connect(lambda _v: self._walk())  # type: ignore[attr-defined]
        for key in ("gesture", "hand"):
            w[key].currentTextChanged.connect(  # type: ignore[attr-defined]
                lambda _v: self._gesture())
        w["gesture_s"].valueChanged.connect(lambda _v: self._gesture())  # type: ignore[attr-defined]
        reps.valueChanged.connect(lambda _v: self._gesture())
        for key in ("breath_hz", "breath_mm", "heart_hz", "heart_mm"):
            w[key].valueChanged.connect(lambda _v: self._vitals())  # type: ignore[attr-defined]
        w["sway"].valueChanged.connect(  # type: ignore[attr-defined]
            lambda v: self._set("geometry.motion.sway_mm", float(v), "Set sway", w["sway"]))
        bvh.editingFinished.connect(self._bvh)

    # ------------------------------------------------------------------ write
    def _walk(self) -> None:
        speed = float(self.widgets["speed"].value())  # type: ignore[attr-defined]
        path = self.widgets["path"].currentText()  # type: ignore[attr-defined]
        value = None if speed <= 0 else {"speed_mps": speed, "path": path}
        self._set("geometry.motion.walk", value, "Set walk", self.widgets["speed"])

    def _gesture(self) -> None:
        w = self.widgets
        kind = w["gesture"].currentText()  # type: ignore[attr-defined]
        value = None if kind == "none" else {
            "kind": kind, "hand": w["hand"].currentText(),  # type: ignore[attr-defined]
            "duration_s": float(w["gesture_s"].value()),  # type: ignore[attr-defined]
            "repetitions": int(w["reps"].value())}  # type: ignore[attr-defined]
        self._set("geometry.motion.gesture", value, "Set gesture", w["gesture"])

    def _vitals(self) -> None:
        w = self.widgets
        v = {"breathing_rate_hz": w["breath_hz"].value(),  # type: ignore[attr-defined]
             "breathing_amplitude_mm": w["breath_mm"].value(),  # type: ignore[attr-defined]
             "heart_rate_hz": w["heart_hz"].value(),  # type: ignore[attr-defined]
             "heart_amplitude_mm": w["heart_mm"].value()}  # type: ignore[attr-defined]
        value = None if not any(v.values()) else {k: float(x) for k, x in v.items()}
        self._set("geometry.motion.vital_signs", value, "Set vital signs", w["breath_hz"])

    def _bvh(self) -> None:
        text = self.widgets["bvh"].text().strip()  # type: ignore[attr-defined]
        value = {"path": text} if text else None
        self._set("geometry.motion.bvh", value, "Set BVH clip", self.widgets["bvh"])

    # ------------------------------------------------------------------ read
    def show(self, geometry: Any) -> None:
        """Show a person geometry's motion block without emitting edits."""
        m, w = geometry.motion, self.widgets
        _quiet(w["posture"], m.posture)
        _quiet(w["speed"], m.walk.speed_mps if m.walk else 0.0)
        _quiet(w["path"], m.walk.path if m.walk else "straight")
        g = m.gesture
        _quiet(w["gesture"], g.kind if g else "none")
        _quiet(w["hand"], g.hand if g else "right")
        _quiet(w["gesture_s"], g.duration_s if g else 2.0)
        _quiet(w["reps"], g.repetitions if g else 2)
        vs = m.vital_signs
        _quiet(w["breath_hz"], vs.breathing_rate_hz if vs else 0.0)
        _quiet(w["breath_mm"], vs.breathing_amplitude_mm if vs else 0.0)
        _quiet(w["heart_hz"], vs.heart_rate_hz if vs else 0.0)
        _quiet(w["heart_mm"], vs.heart_amplitude_mm if vs else 0.0)
        _quiet(w["sway"], m.sway_mm)
        _quiet(w["bvh"], m.bvh.path if m.bvh else "")
