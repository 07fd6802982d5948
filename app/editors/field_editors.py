"""Declarative editors for project fields, and the one path every field edit takes.

:func:`commit_value` is that path, used by every editor of the GUI (timeline and seed,
sensors, link budget, DSP, the Inspector's objects, materials): a shown value is turned
into SI exactly as typed (decimal scaling: 2 GHz is stored as 2e9, not 1999999999.9999998),
checked against the field's own limits, then written through the document, which validates
the whole project; a refusal is shown at the field — red frame, and a sentence in the
field's label and unit ("Start frequency must be below 300 GHz (got 5000 GHz)") — and
nothing is committed. Text that is no number is refused the same way
(:func:`bind_number_box`). An accepted edit is one undo step in the user's words
("Set bandwidth to 2 GHz").

A :class:`FieldSpec` names a field of the project (``rig.radar.tx_power_dbm``), its label,
the unit shown, the scale from SI to that unit and a tooltip; :class:`FieldForm` builds a
form of such rows, shows the project's values, and writes an edit through
:meth:`ProjectDocument.set_value` — so every value passes the core's validation (a refused
value stays in its field with the reason, like every editor of the GUI) and is one undo
step named after the field. The tooltip states the range the core accepts, read from the
model's own constraints, so GUI and core never disagree.
"""

from __future__ import annotations

import typing
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from decimal import Decimal
from typing import Any

import annotated_types as at
from pydantic import BaseModel
from PyQt6.QtCore import QSignalBlocker, pyqtSignal
from PyQt6.QtWidgets import QCheckBox, QComboBox, QFormLayout, QWidget

from app.document.document import EditError, ProjectDocument
from app.document.validation import BOUND_WORDS, format_number, in_words
from app.widgets.inputs import (
    BIG,
    INT_MAX,
    IntBox,
    NumberBox,
    clear_field_error,
    int_spin,
    set_quietly,
    show_field_error,
    spin,
)
from simcore.scene import Project, fieldpath
from simcore.scene.materials import load_material_library


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
    kind : {"float", "int", "bool", "choice", "vector"}
        ``"vector"``: a tuple of floats, one box per component (``components``).
    scale : float
        Shown value per SI value (``1e-3`` shows Hz as kHz); conversions are decimal, so a
        value typed round-trips exactly.
    decimals, step : number
        Float boxes' precision and arrow step (shown units).
    choices : tuple of str
        Items of a ``"choice"`` field.
    off_text : str
        For an optional field (``None`` allowed): the box's lowest value stands for
        ``None`` and reads ``off_text``.
    minimum, maximum : float, optional
        Limits of the GUI beyond the model's (SI), refused like the model's.
    components : tuple of str
        Names of a vector's components (``("x", "y", "z")``).
    dimensions : bool
        A vector of sizes: reads "1.2 × 1.4 × 0.04 m" (others read "(3, 0.5, 1) m").
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
    minimum: float | None = None
    maximum: float | None = None
    components: tuple[str, ...] = ("x", "y", "z")
    dimensions: bool = False

    @property
    def name(self) -> str:
        """The field's own name (last part of the path)."""
        return self.path.rsplit(".", 1)[-1]

    @property
    def unit_suffix(self) -> str:
        """The unit as it follows a number: " GHz", "°" (no space), or ""."""
        if not self.unit:
            return ""
        return self.unit if self.unit in ("°", "°/s", "×") else f" {self.unit}"

    @property
    def title(self) -> str:
        """The label as a sentence starts: "Start frequency"."""
        return self.label[:1].upper() + self.label[1:]

    def to_si(self, shown: Any) -> Any:
        """The model value of a shown value: exact decimal scaling (2 GHz → 2e9)."""
        if shown is None or self.kind in ("bool", "choice"):
            return shown
        if self.kind == "int":
            return int(shown)
        if self.kind == "vector":
            return tuple(self._scalar_to_si(v) for v in shown)
        return self._scalar_to_si(shown)

    def _scalar_to_si(self, shown: float) -> float:
        if self.scale == 1.0:
            return float(shown)
        return float(Decimal(repr(float(shown))) / Decimal(repr(float(self.scale))))

    def to_shown(self, si: float) -> float:
        """The shown value of a model value (SI), by decimal scaling."""
        if self.scale == 1.0 or self.kind == "int":
            return si
        return float(Decimal(repr(float(si))) * Decimal(repr(float(self.scale))))

    def number(self, si: float) -> str:
        """A model value as the field shows it, without the unit: "2", "0.5"."""
        return format_number(self.to_shown(si))

    def text(self, si: Any) -> str:
        """A model value in words with the unit: "2 GHz", "1.2 × 0.7 × 0.03 m", "on"."""
        unit = self.unit_suffix
        if si is None:
            return self.off_text or "off"
        if isinstance(si, bool):
            return "on" if si else "off"
        if isinstance(si, str):
            return si
        if isinstance(si, Sequence):
            parts = [self.number(v) for v in si]
            if self.dimensions:
                return " × ".join(parts) + unit
            return f"({', '.join(parts)}){unit}"
        return f"{self.number(si)}{unit}"

    def undo_text(self, si: Any, subject: str = "") -> str:
        """"Set bandwidth to 2 GHz", "Set size of desk1_top to 1 × 2 × 0.5 m"."""
        of = f" of {subject}" if subject else ""
        return f"Set {self.label}{of} to {self.text(si)}"

    def _component(self, index: int | None) -> str:
        if index is None or not 0 <= index < len(self.components):
            return self.title
        return f"{self.title} ({self.components[index]})"

    def limit_problem(self, si: Any) -> str | None:
        """The GUI's own limits (:attr:`minimum`, :attr:`maximum`) broken by ``si``, if any."""
        values = si if isinstance(si, tuple) else (si,)
        for i, v in enumerate(values):
            if not isinstance(v, (int, float)) or isinstance(v, bool):
                continue
            index = i if isinstance(si, tuple) else None
            for limit, kind in ((self.minimum, "greater_than_equal"),
                                (self.maximum, "less_than_equal")):
                bad = limit is not None and (v < limit if kind.startswith("g") else v > limit)
                if bad:
                    return self.bound_message(
                        {"type": kind, "ctx": {BOUND_WORDS[kind][1]: limit}, "input": v},
                        index)
        return None

    def bound_message(self, err: dict[str, Any], index: int | None = None) -> str | None:
        """"Size (x) must be above 0 m (got 0 m)" for a bound error of this field."""
        kind = err.get("type", "")
        if kind not in BOUND_WORDS:
            return None
        word, key = BOUND_WORDS[kind]
        unit = self.unit_suffix
        limit = (err.get("ctx") or {}).get(key)
        if not isinstance(limit, (int, float)):
            return None
        got = err.get("input")
        got_text = f" (got {self.number(got)}{unit})" if isinstance(got, (int, float)) else ""
        return f"{self._component(index)} must be {word} {self.number(limit)}{unit}{got_text}"

    def explain(self, exc: EditError) -> str:
        """Why an edit of this field was refused, in its label and unit.

        An error of this field itself reads "Tx power must be at most 60 dBm (got 75 dBm)";
        a rule across fields keeps the model's sentence (in the GUI's words and units).
        """
        for err in exc.errors:
            loc = tuple(err.get("loc", ()))
            names = [p for p in loc if isinstance(p, str)]
            if not names or names[-1] != self.name:
                continue
            index = loc[-1] if loc and isinstance(loc[-1], int) else None
            message = self.bound_message(err, index)
            if message is None:
                got = err.get("input")
                text = str(err.get("msg", "")).removeprefix("Value error, ")
                shown = f" (got {self.text(got)})" if isinstance(got, (int, float)) else ""
                message = f"{self._component(index)}: {in_words(text)}{shown}"
            return message
        return in_words(str(exc))

    def refusal(self, text: str, box: QWidget, index: int | None = None) -> str:
        """Why typed ``text`` is no value for ``box`` (not a number, or beyond the box)."""
        from app.widgets.inputs import parse_number

        value = parse_number(text)
        whole = isinstance(box, IntBox)
        if value is None or (whole and not value.is_integer()):
            what = "a whole number" if whole else "a number"
            return f"{self._component(index)}: “{text}” is not {what}"
        assert isinstance(box, IntBox | NumberBox)
        kind = "less_than_equal" if value > box.maximum() else "greater_than_equal"
        limit = box.maximum() if value > box.maximum() else box.minimum()
        unit = self.unit_suffix
        return (f"{self._component(index)} must be {BOUND_WORDS[kind][0]} "
                f"{format_number(limit)}{unit} (got {text}{unit})")


def commit_value(spec: FieldSpec, shown: Any, widget: QWidget,
                 apply: Callable[[Any, str], object], *, text: str | None = None,
                 subject: str = "") -> bool:
    """The one path of a field edit: convert, check, write; or refuse at the field.

    Parameters
    ----------
    spec : FieldSpec
        The field: label, unit, scale and limits.
    shown : object
        The value as the field shows it (``None`` for "off").
    widget : QWidget
        The field: marked with the reason when refused, cleared when accepted.
    apply : callable
        ``apply(value, undo_text)`` writes the model (SI) value as one undo step and raises
        :class:`EditError` to refuse it.
    text, subject : str
        Undo text (default :meth:`FieldSpec.undo_text` naming ``subject``).

    Returns
    -------
    bool
        True when the value was accepted; nothing is committed otherwise.
    """
    value = spec.to_si(shown)
    problem = spec.limit_problem(value)
    if problem is None:
        try:
            apply(value, text or spec.undo_text(value, subject))
        except EditError as exc:
            problem = spec.explain(exc)
        else:
            clear_field_error(widget)
            return True
    show_field_error(widget, problem)
    return False


def commit_path(document: ProjectDocument, spec: FieldSpec, shown: Any, widget: QWidget, *,
                path: str | None = None, text: str | None = None, subject: str = "") -> bool:
    """:func:`commit_value` of field ``path`` (default ``spec.path``) of the project."""
    target = path or spec.path
    return commit_value(spec, shown, widget,
                        lambda v, t: document.set_value(target, v, text=t), text=text,
                        subject=subject)


def bind_number_box(box: QWidget, spec: FieldSpec, field: QWidget | None = None,
                    index: int | None = None) -> None:
    """Refuse text typed into ``box`` that is no value, at ``field`` (default the box).

    ``index``: the box is component ``index`` of a vector field.
    """
    if not isinstance(box, IntBox | NumberBox):
        return
    box.refusing = True
    target = field if field is not None else box
    box.textRefused.connect(
        lambda text: show_field_error(target, spec.refusal(text, box, index)))


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


def _model_in(annotation: Any) -> type[BaseModel] | None:
    """The model class an annotation holds: ``X``, ``X | None``, ``list[X]``, ``dict[k, X]``."""
    if isinstance(annotation, type) and issubclass(annotation, BaseModel):
        return annotation
    for arg in reversed(typing.get_args(annotation)):  # dict[str, X]: the value type
        found = _model_in(arg)
        if found is not None:
            return found
    return None


def _owner(project: Project, path: str) -> type[BaseModel]:
    """The model class that holds the field ``path`` names.

    Read from the model's field types, not from the project: the owner of
    ``rig.tof.frame_rate_hz`` is :class:`TofCameraConfig` also in a project whose first
    rig has no ToF camera (``rig.tof`` null).
    """
    parts = fieldpath.parse(path)
    owner: type[BaseModel] = type(project)
    for part in parts[:-1]:
        if isinstance(part, int):
            continue  # a list's items: the list field's annotation gave their class
        field = owner.model_fields.get(part)
        found = None if field is None else _model_in(field.annotation)
        if found is None:
            node = fieldpath.get(project, fieldpath.format_path(parts[:-1]))
            assert isinstance(node, BaseModel)
            return type(node)
        owner = found
    return owner


def range_text(spec: FieldSpec, bounds: tuple[float | None, float | None]) -> str:
    """``"range −100 … 60 dBm"`` in the shown unit, or ``""`` when unbounded."""
    lo, hi = bounds
    if lo is None and hi is None:
        return ""

    def fmt(v: float | None) -> str:
        return "…" if v is None else spec.number(v).replace("-", "−")

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
                 parent: QWidget | None = None, *,
                 path_map: Callable[[str], str] | None = None):
        super().__init__(parent)
        self.document = document
        self.specs = specs
        #: Maps a spec's path to the field edited now (the selected sensor's, issue #30).
        self.path_map = path_map
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
        owner = _owner(project, spec.path)
        lo, hi = model_bounds(owner, spec.name)
        bounds = (spec.minimum if spec.minimum is not None else lo,
                  spec.maximum if spec.maximum is not None else hi)
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
        bind_number_box(w, spec)
        return w

    @staticmethod
    def _from_box(spec: FieldSpec, box: Any, value: float) -> Any:
        """The shown value of a box (None: its lowest value, "off")."""
        if spec.off_text and value == box.minimum():
            return None
        return int(value) if spec.kind == "int" else float(value)

    def path_of(self, spec: FieldSpec) -> str:
        """The project field that ``spec``'s row edits now."""
        return spec.path if self.path_map is None else self.path_map(spec.path)

    def _set(self, spec: FieldSpec, shown: Any, widget: QWidget) -> None:
        """Write one field (shown value); a refused value stays in ``widget`` with why."""
        commit_path(self.document, spec, shown, widget, path=self.path_of(spec))

    def value(self, path: str) -> Any:
        """The project's value of ``path`` (SI)."""
        return fieldpath.get(self.document.project, path)

    def refresh(self, *_: object) -> None:
        """Show the project's values; a row whose field the project lacks is disabled.

        (The ToF rows of a project without a ToF camera, the radar rows without a radar.)
        """
        for spec in self.specs:
            w = self.widgets[spec.path]
            try:
                v = self.value(self.path_of(spec))
            except (fieldpath.FieldPathError, KeyError):
                w.setEnabled(False)
                continue
            w.setEnabled(True)
            if spec.kind == "choice":
                with QSignalBlocker(w):
                    w.setCurrentText(str(v))
            elif spec.kind == "bool":
                set_quietly(w, bool(v))
            elif v is None:
                set_quietly(w, w.minimum())
            else:
                set_quietly(w, v if spec.kind == "int" else spec.to_shown(v))


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
              "radar ghosts via every smooth planar face (image method, Fresnel at the "
              "path's angle): 0 none; 1 one bounce on either leg, the room's edges "
              "(two faces); 2 also both legs, two different faces, the room's corners",
              kind="int"),
    FieldSpec("rig.radar.polarization", "polarisation", "",
              "linear polarisation of the antennas (V: board y, H: board x): the Fresnel "
              "TE/TM mix of every multipath bounce", kind="choice", choices=("V", "H")),
    FieldSpec("rig.radar.ideal", "ideal sensor", "",
              "no receiver noise and no ADC quantisation (validation, ground truth)",
              kind="bool"),
    FieldSpec("rig.radar.rig_front_width_m", "rig front width", "mm",
              "width of the rig's own front around the antennas (board or radome), which "
              "returns a flat metal reflector's echo to it once more: an echo at twice the "
              "reflector's range with multipath order ≥ 1 (0: no rig front)", scale=1e3,
              step=1.0, decimals=1),
    FieldSpec("rig.radar.rig_front_height_m", "rig front height", "mm",
              "height of the rig's own front (0: no rig front)", scale=1e3, step=1.0,
              decimals=1),
    FieldSpec("rig.radar.rig_front_material", "rig front material", "",
              "material of the rig's front: its radar reflection coefficient",
              kind="choice", choices=tuple(load_material_library(copy=False))),
    # --- issue #30: transmit-side interference mitigation (docs/interference.md) ---
    FieldSpec("rig.radar.chirp_jitter_s", "chirp start jitter", "µs",
              "random extra delay of each chirp's start, uniform in [0, jitter), new every "
              "frame: spreads an equal-slope radar's ghost (0: off)", scale=1e6, step=0.5,
              decimals=3),
    FieldSpec("rig.radar.hop_step_hz", "hopping step", "MHz",
              "frequency hopping per frame: start frequency + channel × step", scale=1e-6,
              step=50.0, decimals=1),
    FieldSpec("rig.radar.hop_channels", "hopping channels", "",
              "channels to hop among, one drawn per frame (1: no hopping)", kind="int"),
    FieldSpec("rig.radar.transmit_seed", "jitter/hopping seed", "",
              "seed of this radar's jitter and hopping sequence (equal seeds hop in step)",
              kind="int"),
]
#: A ToF camera's multipath model (docs/physics_tof.md), beside its on/off switch.
TOF_MULTIPATH = [
    FieldSpec("rig.tof.multipath_model", "multipath model", "",
              "screen: one bounce from the surfaces the camera sees (fast); room: every "
              "bounce from every surface of the scene, with occlusion (surfel radiosity)",
              kind="choice", choices=("screen", "room")),
    FieldSpec("rig.tof.multipath_surfel_m", "surfel size", "m",
              "room model: the scene's surfaces are cut into triangles of at most this edge "
              "(smaller: finer and slower)", step=0.05, decimals=3),
    FieldSpec("rig.tof.multipath_bounces", "bounces", "",
              "room model: indirect bounces summed (1: one bounce; 0: all, to convergence)",
              kind="int"),
    FieldSpec("rig.tof.multipath_moving", "moving objects", "",
              "room model with moving objects: first_order keeps the still room's exact "
              "solution and adds what they change to first order (fast); exact recomputes "
              "every pair each frame (seconds a frame)", kind="choice",
              choices=("first_order", "exact")),
]
#: A ToF camera's interference mitigation (issue #30, docs/interference.md).
TOF_INTERFERENCE = [
    FieldSpec("rig.tof.hop_step_hz", "hopping step", "MHz",
              "modulation frequency hopping per frame: every frequency + channel × step "
              "(another camera on another frequency only adds shot noise)", scale=1e-6,
              step=0.5, decimals=3),
    FieldSpec("rig.tof.hop_channels", "hopping channels", "",
              "channels to hop among, one drawn per frame (1: no hopping)", kind="int"),
    FieldSpec("rig.tof.hop_seed", "hopping seed", "",
              "seed of this camera's hopping sequence (equal seeds hop in step)", kind="int"),
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
    FieldSpec("dsp.interference_mitigation", "interference mitigation", "",
              "radar interference bursts before the range FFT: zero or interpolate the "
              "samples hit (off: none)", kind="choice", choices=("off", "zero", "interpolate")),
    FieldSpec("dsp.interference_threshold", "burst threshold", "σ",
              "a sample is hit when its first difference exceeds this many robust standard "
              "deviations", step=0.5, decimals=1),
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
    FieldSpec("dsp.angle_peaks_within_db", "angle peaks within", "dB",
              "targets in one range–Doppler cell: further azimuth peaks within this of the "
              "largest are detections too (off: one per cell)", step=1.0, decimals=1,
              off_text="off (one per cell)"),
    FieldSpec("dsp.azimuth_min_deg", "azimuth from", "°", "start of the azimuth scan",
              step=5.0, decimals=1),
    FieldSpec("dsp.azimuth_max_deg", "azimuth to", "°", "end of the azimuth scan", step=5.0,
              decimals=1),
    FieldSpec("dsp.azimuth_step_deg", "azimuth step", "°", "azimuth scan step", step=0.5,
              decimals=2),
    FieldSpec("dsp.angle_fft_size", "angle FFT size", "", "zero-padded size of the angle FFT",
              kind="int"),
]

#: Micro-Doppler spectrogram and vital-sign options (issue 29; docs/dsp.md).
PRODUCTS = [
    FieldSpec("dsp.spectrogram_mode", "spectrogram", "",
              "frame: one Doppler spectrum per frame (any gap between frames); stft: a "
              "short-time FFT over consecutive frames' chirps, never across a gap",
              kind="choice", choices=("frame", "stft")),
    FieldSpec("dsp.spectrogram_window", "spectrogram window", "", "slow-time window",
              kind="choice", choices=("hann", "hamming", "blackman", "blackmanharris",
                                      "chebyshev", "none")),
    FieldSpec("dsp.spectrogram_segment_chirps", "STFT segment", "chirps",
              "STFT window length (off: the chirps of one frame)", kind="int",
              off_text="chirps per frame"),
    FieldSpec("dsp.spectrogram_overlap", "STFT overlap", "",
              "fraction of a segment shared with the next", step=0.05),
    FieldSpec("dsp.spectrogram_clutter_removal", "spectrogram clutter removal", "",
              "subtract each segment's mean: hides what does not move", kind="bool"),
    FieldSpec("dsp.spectrogram_history_s", "spectrogram history", "s",
              "seconds shown by the Micro-Doppler panel", step=1.0, decimals=1),
    FieldSpec("dsp.vitals_static_offset", "vital signs: clutter", "",
              "circle: phase about a fitted circle's centre (static clutter in the chest's "
              "bin); mean: about the mean; none: raw phase", kind="choice",
              choices=("circle", "mean", "none")),
    FieldSpec("dsp.vitals_window_s", "vital signs: window", "s",
              "seconds of data per breathing/heart-rate estimate", step=5.0, decimals=1),
    FieldSpec("dsp.vitals_channel", "vital signs: channel", "",
              "virtual channel whose phase is used", kind="int"),
]

__all__ = ["DETECTION", "LINK_BUDGET", "PROCESSING", "PRODUCTS", "TOF_INTERFERENCE",
           "FieldForm", "FieldSpec", "bind_number_box", "commit_path", "commit_value",
           "model_bounds", "range_text"]
