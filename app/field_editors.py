"""Declarative editors for project fields: one row per field, bound by its field path.

A :class:`FieldSpec` names a field of the project (``rig.radar.tx_power_dbm``), its label,
the unit shown, the scale from SI to that unit and a tooltip; :class:`FieldForm` builds a
form of such rows, shows the project's values, and writes an edit through
:meth:`ProjectDocument.set_value` — so every value passes the core's validation (a refused
value stays in its field with the reason, like every editor of the GUI) and is one undo
step named after the field. The tooltip states the range the core accepts, read from the
model's own constraints, so GUI and core never disagree.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import annotated_types as at
from pydantic import BaseModel
from PyQt6.QtCore import QSignalBlocker, pyqtSignal
from PyQt6.QtWidgets import QCheckBox, QComboBox, QFormLayout, QWidget

from app.document import ProjectDocument
from app.widgets import BIG, INT_MAX, int_spin, set_quietly, spin, try_edit
from simcore.scene import Project, fieldpath


@dataclass(frozen=True)
class FieldSpec:
    """One editable field.

    Attributes
    ----------
    path : str
        Field path in the project (:mod:`simcore.scene.fieldpath` syntax).
    label, unit : str
        Row label and the unit shown in the box (``""`` for none).
    tip : str
        What the field does (the tooltip adds the accepted range).
    kind : {"float", "int", "bool", "choice"}
    scale : float
        Shown value per SI value (``1e-3`` shows Hz as kHz).
    decimals, step : number
        Float boxes' precision and arrow step (shown units).
    choices : tuple of str
        Items of a ``"choice"`` field.
    off_text : str
        For an optional field (``None`` allowed): the box's lowest value stands for
        ``None`` and reads ``off_text``.
    """

    path: str
    label: str
    unit: str = ""
    tip: str = ""
    kind: str = "float"
    scale: float = 1.0
    decimals: int = 2
    step: float = 1.0
    choices: tuple[str, ...] = ()
    off_text: str = ""

    @property
    def name(self) -> str:
        """The field's own name (last part of the path)."""
        return self.path.rsplit(".", 1)[-1]


def model_bounds(model: type[BaseModel], name: str) -> tuple[float | None, float | None]:
    """The (lower, upper) bounds the model puts on field ``name`` (None: unbounded)."""
    lo: float | None = None
    hi: float | None = None
    for meta in model.model_fields[name].metadata:
        if isinstance(meta, at.Ge | at.Gt):
            lo = float(meta.ge if isinstance(meta, at.Ge) else meta.gt)
        elif isinstance(meta, at.Le | at.Lt):
            hi = float(meta.le if isinstance(meta, at.Le) else meta.lt)
    return lo, hi


def _owner(project: Project, path: str) -> BaseModel:
    parent = path.rsplit(".", 1)[0]
    owner = fieldpath.get(project, parent)
    assert isinstance(owner, BaseModel)
    return owner


def range_text(spec: FieldSpec, bounds: tuple[float | None, float | None]) -> str:
    """``"range −100 … 60 dBm"`` in the shown unit, or ``""`` when unbounded."""
    lo, hi = bounds
    if lo is None and hi is None:
        return ""

    def fmt(v: float | None) -> str:
        return "…" if v is None else f"{v * spec.scale:g}".replace("-", "−")

    unit = f" {spec.unit}" if spec.unit else ""
    return f"accepted: {fmt(lo)} to {fmt(hi)}{unit}"


class FieldForm(QWidget):
    """A form of :class:`FieldSpec` rows bound to the document's project.

    Signals
    -------
    editFailed(str)
        An edit was refused and no field could show why.
    """

    editFailed = pyqtSignal(str)

    def __init__(self, document: ProjectDocument, specs: list[FieldSpec],
                 parent: QWidget | None = None):
        super().__init__(parent)
        self.document = document
        self.specs = specs
        self.widgets: dict[str, Any] = {}
        self.form = QFormLayout(self)
        self.form.setContentsMargins(4, 4, 4, 4)
        project = document.project
        for spec in specs:
            w = self._make(spec, project)
            self.form.addRow(spec.label, w)
            self.widgets[spec.path] = w
        document.projectChanged.connect(self.refresh)
        self.refresh()

    def _make(self, spec: FieldSpec, project: Project) -> QWidget:
        owner = type(_owner(project, spec.path))
        bounds = model_bounds(owner, spec.name)
        tip = "; ".join(t for t in (spec.tip, range_text(spec, bounds)) if t)
        w: Any
        if spec.kind == "bool":
            w = QCheckBox()
            w.setToolTip(tip)
            w.toggled.connect(lambda on, s=spec, w=w: self._set(s, bool(on), w))
        elif spec.kind == "choice":
            w = QComboBox()
            w.addItems(list(spec.choices))
            w.setToolTip(tip)
            w.activated.connect(lambda _i, s=spec, w=w: self._set(s, w.currentText(), w))
        elif spec.kind == "int":
            # The box's range is wide: the model decides and says why at the field.
            lo = -1 if spec.off_text else -INT_MAX
            w = int_spin(minimum=lo, maximum=INT_MAX, suffix=spec.unit, tooltip=tip)
            if spec.off_text:
                w.setMinimum(int(bounds[0] or 0) - 1)
                w.setSpecialValueText(spec.off_text)
            w.valueChanged.connect(lambda v, s=spec, w=w: self._set(s, self._from_box(s, w, v), w))
        else:
            w = spin(minimum=-BIG, maximum=BIG, decimals=spec.decimals, step=spec.step,
                     suffix=spec.unit, tooltip=tip)
            if spec.off_text:
                w.setMinimum((bounds[0] if bounds[0] is not None else 0.0) * spec.scale
                             - spec.step)
                w.setSpecialValueText(spec.off_text)
            w.valueChanged.connect(lambda v, s=spec, w=w: self._set(s, self._from_box(s, w, v), w))
        w.setObjectName(spec.name)
        return w

    @staticmethod
    def _from_box(spec: FieldSpec, box: Any, value: float) -> Any:
        if spec.off_text and value == box.minimum():
            return None
        return int(value) if spec.kind == "int" else float(value) / spec.scale

    def _set(self, spec: FieldSpec, value: Any, widget: QWidget) -> None:
        """Write one field; a refused value stays in ``widget`` with the reason."""
        text = f"Set {spec.label}"
        try_edit(self.editFailed.emit,
                 lambda: self.document.set_value(spec.path, value, text=text),
                 self.refresh, field=widget)

    def value(self, path: str) -> Any:
        """The project's value of ``path`` (SI)."""
        return fieldpath.get(self.document.project, path)

    def refresh(self, *_: object) -> None:
        """Show the project's values."""
        for spec in self.specs:
            w = self.widgets[spec.path]
            v = self.value(spec.path)
            if spec.kind == "choice":
                with QSignalBlocker(w):
                    w.setCurrentText(str(v))
            elif spec.kind == "bool":
                set_quietly(w, bool(v))
            elif v is None:
                set_quietly(w, w.minimum())
            else:
                set_quietly(w, v if spec.kind == "int" else v * spec.scale)


#: The radar's link budget and receiver.
LINK_BUDGET = [
    FieldSpec("rig.radar.tx_power_dbm", "Tx power", "dBm",
              "transmit power per Tx at the antenna port", step=1.0, decimals=1),
    FieldSpec("rig.radar.tx_gain_dbi", "Tx antenna gain", "dBi",
              "boresight gain of a Tx element", step=0.5, decimals=1),
    FieldSpec("rig.radar.rx_gain_dbi", "Rx antenna gain", "dBi",
              "boresight gain of an Rx element", step=0.5, decimals=1),
    FieldSpec("rig.radar.noise_figure_db", "noise figure", "dB",
              "receiver noise figure: sets the thermal noise floor", step=0.5, decimals=1),
    FieldSpec("rig.radar.if_gain_db", "IF gain", "dB",
              "voltage gain from the Rx antenna port (50 Ω) to the ADC input", step=1.0,
              decimals=1),
    FieldSpec("rig.radar.adc_bits", "ADC bits", "bit", "ADC resolution (off: no quantization)",
              kind="int", off_text="off (no quantization)"),
    FieldSpec("rig.radar.adc_full_scale_v", "ADC full scale", "V",
              "peak ADC input voltage of the largest code", step=0.1, decimals=3),
    FieldSpec("rig.radar.leakage_dbc", "Tx→Rx leakage", "dBc",
              "leakage power at the Rx port relative to the Tx power (off: none)", step=1.0,
              decimals=1, off_text="off (no leakage)"),
    # --- issue #35 (calibration against a real BGT60TR13C) ---
    FieldSpec("rig.radar.leakage_path_mm", "leakage path", "mm",
              "electrical length of the direct Tx→Rx coupling (off: the board distance "
              "between the elements)", step=1.0, decimals=1, off_text="board distance"),
    FieldSpec("rig.radar.adc_noise_fs", "noise after the filters", "mFS",
              "rms noise added after the IF filters (baseband amplifier, ADC), independent "
              "of the IF gain", scale=1e3, step=0.05, decimals=3),
    # --- end issue #35 ---
    FieldSpec("rig.radar.if_highpass_hz", "IF high-pass", "kHz",
              "IF high-pass cutoff (0: none)", scale=1e-3, step=10.0, decimals=1),
    FieldSpec("rig.radar.if_lowpass_hz", "IF low-pass", "kHz",
              "anti-aliasing low-pass cutoff (0: none)", scale=1e-3, step=50.0, decimals=1),
    FieldSpec("rig.radar.speckle", "speckle", "",
              "random phase of each surface facet's diffuse part, fixed to the surface "
              "(rough-surface speckle)", kind="bool"),
    FieldSpec("rig.radar.multipath_order", "multipath order", "",
              "radar ghosts via flat metal reflectors (image method): 0 none, 1 one "
              "bounce on the wall (either leg), 2 both legs; order 1 costs about 1.5× the "
              "synthesis, order 2 about 2.7×", kind="int"),
]

#: CFAR cells and the detector options beside the main DSP choices.
DETECTION = [
    FieldSpec("dsp.cfar_guard_range", "guard cells (range)", "cells",
              "cells on each side of the cell under test left out of the noise estimate",
              kind="int"),
    FieldSpec("dsp.cfar_train_range", "training cells (range)", "cells",
              "cells on each side averaged (or ranked) into the noise estimate", kind="int"),
    FieldSpec("dsp.cfar_guard_doppler", "guard cells (Doppler)", "cells",
              "guard cells along Doppler (2-D CFAR)", kind="int"),
    FieldSpec("dsp.cfar_train_doppler", "training cells (Doppler)", "cells",
              "training cells along Doppler (2-D CFAR)", kind="int"),
    FieldSpec("dsp.cfar_os_rank", "OS rank", "",
              "ordered-statistic CFAR: rank as a fraction of the training cells", step=0.05),
    FieldSpec("dsp.peak_grouping", "peak grouping", "",
              "local_max: a hit must be the maximum of its neighbourhood; cluster: one per "
              "connected group; none: every hit", kind="choice",
              choices=("local_max", "cluster", "none")),
    FieldSpec("dsp.max_detections", "max detections", "", "strongest detections kept",
              kind="int"),
    FieldSpec("dsp.interpolate_peaks", "sub-bin interpolation", "",
              "parabolic refinement of range and velocity", kind="bool"),
]

#: Range, Doppler and angle processing options.
PROCESSING = [
    FieldSpec("dsp.remove_dc", "remove DC", "", "subtract each chirp's mean before the "
              "range FFT", kind="bool"),
    FieldSpec("dsp.range_window_sidelobe_db", "range window sidelobes", "dB",
              "sidelobe level of a Chebyshev range window", step=5.0, decimals=0),
    FieldSpec("dsp.doppler_window_sidelobe_db", "Doppler window sidelobes", "dB",
              "sidelobe level of a Chebyshev Doppler window", step=5.0, decimals=0),
    FieldSpec("dsp.tdm_doppler_compensation", "TDM Doppler compensation", "",
              "correct the phase a moving target gains between Tx slots", kind="bool"),
    FieldSpec("dsp.azimuth_min_deg", "azimuth from", "°", "start of the azimuth scan",
              step=5.0, decimals=1),
    FieldSpec("dsp.azimuth_max_deg", "azimuth to", "°", "end of the azimuth scan", step=5.0,
              decimals=1),
    FieldSpec("dsp.azimuth_step_deg", "azimuth step", "°", "azimuth scan step", step=0.5,
              decimals=2),
    FieldSpec("dsp.angle_fft_size", "angle FFT size", "", "zero-padded size of the angle FFT",
              kind="int"),
]

__all__ = ["DETECTION", "LINK_BUDGET", "PROCESSING", "FieldForm", "FieldSpec", "model_bounds",
           "range_text"]
