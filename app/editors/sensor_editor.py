"""Sensor editor: ToF camera and radar configuration with presets and derived quantities.

The radar box shows live what the waveform and array imply — range resolution, maximum
range, velocity resolution and maximum, angle resolution — and warns (in red) where the
scene aliases: objects beyond the unambiguous range, faster than the unambiguous velocity,
or element spacings above λ/2 (grating lobes).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np
from PyQt6.QtCore import QSignalBlocker, Qt, pyqtSignal
from PyQt6.QtGui import QValidator
from PyQt6.QtWidgets import (
    QCheckBox,
    QComboBox,
    QFormLayout,
    QGroupBox,
    QHBoxLayout,
    QLabel,
    QScrollArea,
    QTabWidget,
    QVBoxLayout,
    QWidget,
)

from app.document.document import ProjectDocument
from app.document.sensors import KIND_WORDS, sensor_path, sensor_states
from app.editors.field_editors import (
    DETECTION,
    LINK_BUDGET,
    PROCESSING,
    PRODUCTS,
    TOF_INTERFERENCE,
    TOF_MULTIPATH,
    FieldForm,
    FieldSpec,
    bind_number_box,
    commit_path,
)
from app.editors.rig_editor import RigSensorList
from app.editors.tof_effects import TofEffectsBox
from app.widgets.inputs import (
    BIG,
    INT_MAX,
    NumberBox,
    VectorEdit,
    int_spin,
    set_quietly,
    show_field_error,
    spin,
    try_edit,
)
from app.widgets.wrap_row import WrapRow
from simcore.scene import Project, fieldpath
from simcore.scene.radar_config import SPEED_OF_LIGHT, RadarConfig, aliasing_warnings
from simcore.scene.radar_presets import RADAR_PRESETS
from simcore.scene.snapshot import take_snapshot


def radar_presets() -> dict[str, Callable[..., RadarConfig]]:
    """Named radar presets (:mod:`simcore.scene.radar_presets`)."""
    return dict(RADAR_PRESETS)


def tof_presets() -> dict[str, Callable[[], Any]]:
    """Named ToF camera presets, the device library's cameras included."""
    from simcore.scene.device_cameras import CAMERA_PRESETS
    from simcore.scene.tof_config import TOF_PRESETS

    return {**TOF_PRESETS, **CAMERA_PRESETS}


def device_description(name: str) -> str:
    """'Vendor model: one line' of a device preset (docs/devices.md), '' for other presets."""
    from simcore.scene.devices import DEVICES

    device = DEVICES.get(name)
    return f"{device.title}: {device.description}" if device is not None else ""


def describe_presets(combo: QComboBox, label: QLabel) -> None:
    """Give each device in a preset list its description as tooltip; show the current one."""
    for i in range(combo.count()):
        text = device_description(combo.itemText(i))
        if text:
            combo.setItemData(i, text, Qt.ItemDataRole.ToolTipRole)
    label.setText(device_description(combo.currentText()))


def angle_resolution_deg(config: RadarConfig) -> tuple[float | None, float | None]:
    """Approximate azimuth and elevation resolution λ / (N d) of the virtual array (°)."""
    virt = np.zeros((0, 2))
    tx = np.array([a.position_mm for a in config.tx], dtype=float) * 1e-3
    rx = np.array([a.position_mm for a in config.rx], dtype=float) * 1e-3
    virt = (tx[:, None, :] + rx[None, :, :]).reshape(-1, 2)
    out: list[float | None] = []
    for axis in (0, 1):
        coords = np.unique(np.round(virt[:, axis], 9))
        if len(coords) < 2:
            out.append(None)
            continue
        d = float(np.min(np.diff(coords)))
        aperture = float(coords[-1] - coords[0]) + d
        out.append(float(np.rad2deg(config.wavelength_m / aperture)))
    return out[0], out[1]


def scene_radial_extent(project: Project, t: float = 0.0, radar_name: str = "radar"
                        ) -> tuple[np.ndarray, np.ndarray]:
    """Ranges (m) and radial velocities (m/s) of the object origins seen from a radar."""
    snap = take_snapshot(project, t)
    radar = sensor_states(project, t)[radar_name]
    ranges, velocities = [], []
    for state in snap.objects:
        d = state.origin - radar.position
        r = float(np.linalg.norm(d))
        if r < 1e-6:
            continue
        u = d / r
        # Only what lies in front of the radar matters.
        if float(u @ radar.rotation[:, 2]) <= 0:
            continue
        ranges.append(r)
        velocities.append(float((state.velocity_mps - radar.velocity_mps) @ u))
    return np.array(ranges), np.array(velocities)


def radar_warnings(project: Project, extent: tuple[np.ndarray, np.ndarray] | None = None,
                   radar_name: str = "radar") -> list[str]:
    """Aliasing and array warnings for one radar of the project (empty if none).

    ``extent`` is :func:`scene_radial_extent` of the project when already known.
    """
    cfg = project.sensor_config(radar_name)
    assert isinstance(cfg, RadarConfig)
    ranges, velocities = (scene_radial_extent(project, radar_name=radar_name) if extent is None
                          else extent)
    return aliasing_warnings(cfg, ranges_m=ranges, radial_velocities_mps=velocities)


class PfaSpin(NumberBox):
    """A false-alarm rate shown as ``1e-06`` (the box's value is −log10 Pfa).

    Text that is no rate between 0 and 1 is refused with ``textRefused``, like every box.
    """

    def __init__(self, parent: QWidget | None = None):
        super().__init__(parent)
        self.setRange(0.01, 300.0)
        self.setDecimals(9)  # the exponent: Pfa to 1e-8 relative
        self.setSingleStep(0.5)
        self.setKeyboardTracking(False)
        self.setPrefix("Pfa = ")

    def textFromValue(self, value: float) -> str:  # noqa: N802, D102 - Qt API
        return f"{10.0 ** -value:.3g}"

    def valueFromText(self, text: str) -> float:  # noqa: N802, D102 - Qt API
        try:
            pfa = float(text.removeprefix(self.prefix()).strip())
        except ValueError:
            return self.value()
        return float(-np.log10(pfa)) if 0 < pfa < 1 else self.value()

    def validate(self, text: str, pos: int) -> tuple[QValidator.State, str, int]:  # noqa: D102
        body = text.removeprefix(self.prefix()).strip()
        try:
            pfa = float(body)
        except ValueError:
            return QValidator.State.Intermediate, text, pos
        ok = 0 < pfa < 1
        return (QValidator.State.Acceptable if ok else QValidator.State.Intermediate), text, pos

    def _state(self, text: str) -> QValidator.State:
        return self.validate(text, 0)[0]

    @staticmethod
    def refusal(text: str) -> str:
        """Why ``text`` is no false-alarm rate."""
        try:
            value = float(text.strip())
        except ValueError:
            return f"False-alarm rate: “{text}” is not a number"
        return f"False-alarm rate must be between 0 and 1, e.g. 1e-6 (got {value:g})"


#: The waveform's fields (shown in GHz, µs, MHz; decimal conversion keeps typed values).
RADAR_FIELDS: list[FieldSpec] = [
    FieldSpec("rig.radar.start_frequency_hz", "start frequency", "GHz",
              "chirp start frequency f_c", scale=1e-9, decimals=3),
    FieldSpec("rig.radar.bandwidth_hz", "bandwidth", "GHz", "swept bandwidth B of one chirp",
              scale=1e-9, decimals=3),
    FieldSpec("rig.radar.chirp_time_s", "chirp time", "µs", "ramp duration T_c", scale=1e6),
    FieldSpec("rig.radar.sample_rate_hz", "ADC sample rate", "MHz", "IF sampling rate f_s",
              scale=1e-6, decimals=3),
    FieldSpec("rig.radar.chirp_repetition_time_s", "chirp repetition", "µs",
              "time between successive chirp starts T_r (per Tx slot)", scale=1e6),
]
TOF_FIELDS: list[FieldSpec] = [
    FieldSpec("rig.tof.fov_h_deg", "horizontal FOV", "°", "full horizontal field of view"),
    FieldSpec("rig.tof.fov_v_deg", "vertical FOV", "°", "full vertical field of view"),
]
#: The other fields of the sensor tabs, by attribute name of their widget.
SENSOR_FIELDS: dict[str, FieldSpec] = {
    "tof_width": FieldSpec("rig.tof.width", "width", "px", kind="int"),
    "tof_height": FieldSpec("rig.tof.height", "height", "px", kind="int"),
    "tof_ss": FieldSpec("rig.tof.supersampling", "supersampling", "×", kind="int"),
    "tof_pos": FieldSpec("rig.tof.pose_on_rig.position_m", "camera position on the rig", "m",
                         kind="vector"),
    "tof_rot": FieldSpec("rig.tof.pose_on_rig.rotation_deg", "camera rotation on the rig",
                         "°", kind="vector"),
    "samples": FieldSpec("rig.radar.samples_per_chirp", "samples / chirp", kind="int"),
    "chirps": FieldSpec("rig.radar.chirps_per_frame", "chirps / frame", kind="int"),
    "render_fov": FieldSpec("rig.radar.render_fov_h_deg", "render FOV", "°"),
    "render_w": FieldSpec("rig.radar.render_width", "render width", "px", kind="int"),
    "render_h": FieldSpec("rig.radar.render_height", "render height", "px", kind="int"),
    "radar_pos": FieldSpec("rig.radar.pose_on_rig.position_m", "radar position on the rig",
                           "m", kind="vector"),
    "radar_rot": FieldSpec("rig.radar.pose_on_rig.rotation_deg", "radar rotation on the rig",
                           "°", kind="vector"),
    "min_range": FieldSpec("dsp.min_range_m", "min detection range", "m"),
    "pfa": FieldSpec("dsp.cfar_pfa", "false-alarm rate"),
    "tof_f": FieldSpec("rig.tof.modulation_frequencies_hz", "modulation frequency", "MHz",
                       kind="vector", scale=1e-6, components=("f1", "f2")),
}


class SensorEditor(QScrollArea):
    """Edit the rigs and sensors, and the ToF camera and radar picked; derived quantities.

    The first page lists every rig and sensor (:class:`app.editors.rig_editor.RigSensorList`); the
    Radar, Link budget and ToF camera pages edit the radar and ToF camera picked there
    (:meth:`ProjectDocument.current_sensor`), the built-in ones until another is picked.
    """

    editFailed = pyqtSignal(str)

    def __init__(self, document: ProjectDocument, parent: QWidget | None = None):
        super().__init__(parent)
        self.document = document
        self.setWidgetResizable(True)
        body = QWidget()
        self.setWidget(body)
        outer = QVBoxLayout(body)
        outer.setContentsMargins(2, 2, 2, 2)
        self.tabs = QTabWidget()
        outer.addWidget(self.tabs)
        self.rigs = RigSensorList(document)  # issue #30: every rig and sensor
        self.rigs.editFailed.connect(self.editFailed)
        self.tabs.addTab(self.rigs, "Rigs and sensors")
        radar_page = WrapRow()  # the derived column wraps below when narrow (issue #34)
        radar_page.box.setContentsMargins(2, 2, 2, 2)
        radar_page.add(self._build_radar(), 1)
        radar_page.add(self._build_derived(), 1)
        self.tabs.addTab(radar_page, "Radar")
        self.tabs.addTab(self._build_link_budget(), "Link budget")
        self.tabs.addTab(self._build_dsp_page(), "Radar processing")
        self.tabs.addTab(self._build_tof(), "ToF camera")
        #: The pages of each sensor kind: disabled while the project has no such sensor.
        self.kind_pages = {"radar": [radar_page, *(self.tabs.widget(i) for i in (2, 3))],
                           "tof": [self.tabs.widget(4)]}
        self.tabs.setCurrentIndex(1)  # the Radar page first, as before issue #30
        self._extent_key: tuple[Any, ...] | None = None
        self._extent: tuple[np.ndarray, np.ndarray] = (np.zeros(0), np.zeros(0))
        document.projectChanged.connect(self.refresh)
        document.currentSensorChanged.connect(self.refresh)
        self.refresh()

    # --- construction -----------------------------------------------------------------
    def _which(self, kind: str) -> str:
        """“radar_b on rig2”: the sensor of ``kind`` edited now ("none": the project has none)."""
        name = self.document.current_sensor(kind)
        if name is None:
            return "none"
        return f"{name} on {self.document.project.sensor_rig(name).name}"

    def _build_tof(self) -> QWidget:
        box = self.tof_box = QGroupBox("ToF camera (AMCW)")
        form = QFormLayout(box)
        self.tof_preset = QComboBox()
        self.tof_preset.addItems(sorted(tof_presets()))
        self.tof_preset.setToolTip("Replace the camera settings by a preset (the mounting "
                                   "pose is kept)")
        self.tof_preset.activated.connect(lambda _i: self.apply_tof_preset(
            self.tof_preset.currentText()))
        form.addRow("preset", self.tof_preset)
        self.tof_device = QLabel("")
        self.tof_device.setWordWrap(True)
        form.addRow("device", self.tof_device)
        # Widget ranges are wide on purpose: the model decides and says why at the field.
        self.tof_width = int_spin(minimum=-INT_MAX, maximum=INT_MAX, suffix="px",
                                  tooltip="sensor columns")
        self._bind("tof_width", self.tof_width)
        self.tof_height = int_spin(minimum=-INT_MAX, maximum=INT_MAX, suffix="px",
                                   tooltip="sensor rows")
        self._bind("tof_height", self.tof_height)
        form.addRow("width", self.tof_width)
        form.addRow("height", self.tof_height)
        self.tof_widgets: dict[str, Any] = {}
        for spec in TOF_FIELDS:
            w = spin(minimum=-BIG, maximum=BIG, decimals=2, step=1.0, suffix=spec.unit,
                     tooltip=spec.tip)
            self._bind(spec, w)
            form.addRow(spec.label, w)
            self.tof_widgets[spec.name] = w
        self.tof_ss = int_spin(minimum=-INT_MAX, maximum=INT_MAX, suffix="×",
                               tooltip="sub-pixels per axis of the render (flying pixels)")
        self._bind("tof_ss", self.tof_ss)
        form.addRow("supersampling", self.tof_ss)
        self.tof_f1 = spin(minimum=-BIG, maximum=BIG, decimals=2, step=1.0, suffix="MHz",
                           tooltip="modulation frequency f1; unambiguous range c/(2 f1)")
        self.tof_f1.valueChanged.connect(lambda _v: self._set_frequencies(self.tof_f1))
        bind_number_box(self.tof_f1, SENSOR_FIELDS["tof_f"], index=0)
        self.tof_f2_on = QCheckBox("2nd frequency")
        self.tof_f2_on.setToolTip("Two-frequency phase unwrapping")
        self.tof_f2_on.toggled.connect(lambda _on: self._set_frequencies(self.tof_f2_on))
        self.tof_f2 = spin(minimum=-BIG, maximum=BIG, decimals=2, step=1.0, suffix="MHz",
                           tooltip="second modulation frequency f2")
        self.tof_f2.valueChanged.connect(lambda _v: self._set_frequencies(self.tof_f2))
        bind_number_box(self.tof_f2, SENSOR_FIELDS["tof_f"], index=1)
        form.addRow("modulation f1", self.tof_f1)
        row = QHBoxLayout()
        row.addWidget(self.tof_f2_on)
        row.addWidget(self.tof_f2, 1)
        form.addRow(row)
        self.tof_pos = VectorEdit(suffix="m", step=0.01,
                                  tooltip="camera position on the rig (m; x fwd, y left, z up)")
        self._bind("tof_pos", self.tof_pos)
        self.tof_rot = VectorEdit(suffix="°", decimals=1, step=5.0, minimum=-360, maximum=360,
                                  tooltip="camera rotation on the rig (°)")
        self._bind("tof_rot", self.tof_rot)
        form.addRow("position on rig", self.tof_pos)
        form.addRow("rotation on rig", self.tof_rot)
        self.tof_derived = QLabel("")
        self.tof_derived.setStyleSheet("color: #9aa4ae;")
        form.addRow(self.tof_derived)
        self.tof_effects = TofEffectsBox(self._set)
        form.addRow(self.tof_effects)
        self.tof_interference_form = FieldForm(self.document, TOF_MULTIPATH + TOF_INTERFERENCE,
                                               path_map=self._path)
        self.tof_interference_form.editFailed.connect(self.editFailed)
        form.addRow(self.tof_interference_form)
        return box

    def _build_radar(self) -> QWidget:
        box = self.radar_box = QGroupBox("Radar (FMCW)")
        form = QFormLayout(box)
        self.radar_preset = QComboBox()
        self.radar_preset.addItems(sorted(radar_presets()))
        self.radar_preset.setToolTip("Replace the radar settings (waveform, antennas) by a "
                                     "preset; the mounting pose and render grid are kept")
        self.radar_preset.activated.connect(lambda _i: self.apply_radar_preset(
            self.radar_preset.currentText()))
        form.addRow("preset", self.radar_preset)
        self.radar_device = QLabel("")
        self.radar_device.setWordWrap(True)
        form.addRow("device", self.radar_device)
        self.radar_widgets: dict[str, Any] = {}
        for spec in RADAR_FIELDS:
            w = spin(minimum=-BIG, maximum=BIG, decimals=spec.decimals, step=1.0,
                     suffix=spec.unit, tooltip=f"{spec.tip} ({spec.unit})")
            self._bind(spec, w)
            form.addRow(spec.label, w)
            self.radar_widgets[spec.name] = w
        self.samples = int_spin(minimum=-INT_MAX, maximum=INT_MAX,
                                tooltip="ADC samples per chirp N_s")
        self._bind("samples", self.samples)
        self.chirps = int_spin(minimum=-INT_MAX, maximum=INT_MAX,
                               tooltip="chirps per frame N_c (per Tx)")
        self._bind("chirps", self.chirps)
        form.addRow("samples / chirp", self.samples)
        form.addRow("chirps / frame", self.chirps)
        self.iq = QCheckBox("complex IQ sampling")
        self.iq.setToolTip("complex (IQ) IF instead of real: doubles the unambiguous range")
        self.iq.toggled.connect(lambda on: self._set(
            "rig.radar.complex_iq", bool(on), self.iq,
            text=f"Turn complex IQ sampling {'on' if on else 'off'}"))
        form.addRow(self.iq)
        self.render_fov = spin(minimum=-BIG, maximum=BIG, decimals=1, step=5, suffix="°",
                               tooltip="horizontal field of view of the radar render pass")
        self._bind("render_fov", self.render_fov)
        self.render_w = int_spin(minimum=-INT_MAX, maximum=INT_MAX, suffix="px",
                                 tooltip="radar render pass width (angular sampling)")
        self._bind("render_w", self.render_w)
        self.render_h = int_spin(minimum=-INT_MAX, maximum=INT_MAX, suffix="px",
                                 tooltip="radar render pass height")
        self._bind("render_h", self.render_h)
        form.addRow("render FOV", self.render_fov)
        grid = QHBoxLayout()
        grid.addWidget(self.render_w)
        grid.addWidget(self.render_h)
        form.addRow("render grid", grid)
        self.radar_pos = VectorEdit(suffix="m", step=0.01,
                                    tooltip="radar position on the rig (m; x fwd, y left, z up)")
        self._bind("radar_pos", self.radar_pos)
        self.radar_rot = VectorEdit(suffix="°", decimals=1, step=5.0, minimum=-360,
                                    maximum=360, tooltip="radar rotation on the rig (°)")
        self._bind("radar_rot", self.radar_rot)
        form.addRow("position on rig", self.radar_pos)
        form.addRow("rotation on rig", self.radar_rot)
        return box

    def _build_link_budget(self) -> QWidget:
        box = QGroupBox("Link budget and receiver")
        box.setToolTip("Transmit power, antenna gains and the receiver chain: they set the "
                       "signal and noise levels of the ADC data")
        layout = QVBoxLayout(box)
        self.link_form = FieldForm(self.document, LINK_BUDGET, path_map=self._path)
        self.link_form.editFailed.connect(self.editFailed)
        layout.addWidget(self.link_form)
        layout.addStretch(1)
        return box

    def _build_dsp_page(self) -> QWidget:
        page = WrapRow()  # three columns: they stack when the dock is narrow (issue #34)
        page.box.setContentsMargins(2, 2, 2, 2)
        page.add(self._build_dsp(), 1)
        self.detection_form = FieldForm(self.document, DETECTION)
        self.processing_form = FieldForm(self.document, PROCESSING)
        self.products_form = FieldForm(self.document, PRODUCTS)
        for title, form in (("Detection (CFAR cells)", self.detection_form),
                            ("Range, Doppler and angle options", self.processing_form),
                            ("Micro-Doppler and vital signs", self.products_form)):
            form.editFailed.connect(self.editFailed)
            box = QGroupBox(title)
            QVBoxLayout(box).addWidget(form)
            page.add(box, 1)
        return page

    def _build_dsp(self) -> QWidget:
        box = QGroupBox("Radar processing (DSP)")
        form = QFormLayout(box)
        self.dsp_combos: dict[str, QComboBox] = {}
        windows = ["none", "hann", "hamming", "blackman", "blackmanharris", "chebyshev"]
        for field, label, items, tip in (
                ("range_window", "range window", windows, "window of the range FFT"),
                ("doppler_window", "Doppler window", windows, "window of the Doppler FFT"),
                ("angle_method", "angle method", ["monopulse", "fft", "bartlett", "capon"],
                 "angle estimation of the detections"),
                ("cfar_method", "CFAR", ["ca", "go", "so", "os"],
                 "cell-averaging, greatest-of, smallest-of or ordered-statistic CFAR")):
            combo = QComboBox()
            combo.addItems(items)
            combo.setToolTip(tip)
            combo.activated.connect(lambda _i, f=field, c=combo, w=label: self._set(
                f"dsp.{f}", c.currentText(), c, text=f"Set {w} to {c.currentText()}"))
            form.addRow(label, combo)
            self.dsp_combos[field] = combo
        self.cfar_dims = QComboBox()
        self.cfar_dims.addItems(["2-D (range–Doppler)", "1-D (range)"])
        self.cfar_dims.setToolTip("CFAR on the range–Doppler map or along range only")
        self.cfar_dims.activated.connect(
            lambda i: self._set("dsp.cfar_dimensions", 2 if i == 0 else 1, self.cfar_dims,
                                text=f"Set CFAR to {self.cfar_dims.currentText()}"))
        form.addRow("CFAR dimensions", self.cfar_dims)
        self.pfa = PfaSpin()
        self.pfa.refusing = True
        self.pfa.textRefused.connect(
            lambda text: show_field_error(self.pfa, PfaSpin.refusal(text)))
        self.pfa.setToolTip("false-alarm probability per cell (0 < Pfa < 1), e.g. 1e-6; "
                            "the arrows step by half a decade")
        # Pfa to 6 significant digits: what the user typed, not 10 ** −6.52… rounded off.
        self.pfa.valueChanged.connect(lambda v: commit_path(
            self.document, SENSOR_FIELDS["pfa"],
            float(f"{10.0 ** -min(max(v, -300.0), 300.0):.6g}"), self.pfa))
        form.addRow("false-alarm rate", self.pfa)
        self.clutter = QCheckBox("static clutter removal")
        self.clutter.setToolTip("subtract the mean over chirps: keeps only what moves")
        self.clutter.toggled.connect(lambda on: self._set(
            "dsp.static_clutter_removal", bool(on), self.clutter,
            text=f"Turn static clutter removal {'on' if on else 'off'}"))
        form.addRow(self.clutter)
        self.min_range = spin(minimum=-BIG, maximum=BIG, decimals=2, step=0.05, suffix="m",
                              tooltip="detections closer than this are discarded (leakage)")
        self._bind("min_range", self.min_range)
        form.addRow("min detection range", self.min_range)
        return box

    def _build_derived(self) -> QWidget:
        box = QGroupBox("Derived radar quantities")
        layout = QVBoxLayout(box)
        self.derived = QLabel("")
        self.derived.setTextFormat(self.derived.textFormat().RichText)
        self.derived.setToolTip("Computed from the waveform and the antenna layout")
        layout.addWidget(self.derived)
        self.warnings = QLabel("")
        self.warnings.setWordWrap(True)
        self.warnings.setStyleSheet("color: #ff6b6b;")
        self.warnings.setToolTip("Aliasing and array warnings")
        layout.addWidget(self.warnings)
        layout.addStretch(1)
        return box

    # --- edits ------------------------------------------------------------------------
    def _bind(self, spec: FieldSpec | str, widget: Any) -> None:
        """Commit ``widget``'s edits to ``spec`` (a spec or a key of SENSOR_FIELDS)."""
        spec = SENSOR_FIELDS[spec] if isinstance(spec, str) else spec
        if isinstance(widget, VectorEdit):
            for i, box in enumerate(widget.boxes):
                bind_number_box(box, spec, widget, i)
            widget.edited.connect(lambda v: commit_path(self.document, spec, v, widget,
                                                        path=self._path(spec.path)))
        else:
            bind_number_box(widget, spec)
            widget.valueChanged.connect(lambda v: commit_path(self.document, spec, v, widget,
                                                              path=self._path(spec.path)))

    def _path(self, path: str) -> str:
        """``path`` of the built-in ToF camera or radar, for the sensor edited now.

        ``rig.radar.bandwidth_hz`` → ``rigs[0].sensors.radar_b.bandwidth_hz`` while the
        editor edits radar ``radar_b`` (issue #30); other paths are kept.
        """
        for kind in ("tof", "radar"):
            head = f"rig.{kind}."
            if path.startswith(head):
                name = self.document.current_sensor(kind)
                if name is not None:
                    return f"{sensor_path(self.document.project, name)}.{path[len(head):]}"
        return path

    def tof_config(self) -> Any:
        """The configuration of the ToF camera edited now (None: the project has none)."""
        name = self.document.current_sensor("tof")
        return None if name is None else self.document.project.sensor_config(name)

    def radar_config(self) -> Any:
        """The configuration of the radar edited now (None: the project has none)."""
        name = self.document.current_sensor("radar")
        return None if name is None else self.document.project.sensor_config(name)

    def _enable_pages(self, tof: Any, radar: Any) -> None:
        """Disable the pages of a kind the project has no sensor of (issue 40)."""
        for kind, config in (("tof", tof), ("radar", radar)):
            words = KIND_WORDS[kind]
            for page in self.kind_pages[kind]:
                i = self.tabs.indexOf(page)
                self.tabs.setTabEnabled(i, config is not None)
                self.tabs.setTabToolTip(i, "" if config is not None else
                                        f"The project has no {words}: add one on the "
                                        "Rigs and sensors page")
        if not self.tabs.isTabEnabled(self.tabs.currentIndex()):
            self.tabs.setCurrentIndex(0)

    def _set(self, path: str, value: Any, field: QWidget | None = None, *,
             text: str) -> None:
        """Set a choice or switch; a refused value stays in ``field``, marked with why."""
        try_edit(self.editFailed.emit,
                 lambda: self.document.set_value(self._path(path), value, text=text),
                 self.refresh, field=field)

    def _set_frequencies(self, field: QWidget) -> None:
        spec = SENSOR_FIELDS["tof_f"]
        shown = [self.tof_f1.value()]
        if self.tof_f2_on.isChecked():
            shown.append(self.tof_f2.value())
            # A third frequency (Kinect-type devices) has no box of its own: keep it.
            shown += [spec.to_shown(f)
                      for f in self.tof_config().modulation_frequencies_hz[2:]]
        commit_path(self.document, spec, shown, field, path=self._path(spec.path),
                    text=f"Set modulation frequencies to {spec.text(spec.to_si(shown))}")

    def apply_tof_preset(self, name: str) -> None:
        """Replace the ToF settings by preset ``name``, keeping the mounting pose."""
        cfg = tof_presets()[name]().model_dump()
        path = self._path("rig.tof.x").removesuffix(".x")

        def mutate(d: dict[str, Any]) -> None:
            old = fieldpath.get(d, path)
            for keep in ("pose_on_rig", "kind", "frame_rate_hz", "trigger_offset_s"):
                if keep in old:
                    cfg[keep] = old[keep]
            fieldpath.set_in(d, path, cfg)

        try_edit(self.editFailed.emit,
                 lambda: self.document.edit(f"ToF preset {name}", mutate), self.refresh,
                 field=self.tof_preset)

    def apply_radar_preset(self, name: str) -> None:
        """Replace the radar settings by preset ``name``, keeping pose and render grid."""
        cfg = radar_presets()[name]().model_dump()
        path = self._path("rig.radar.x").removesuffix(".x")

        def mutate(d: dict[str, Any]) -> None:
            old = fieldpath.get(d, path)
            for keep in ("pose_on_rig", "render_width", "render_height", "render_fov_h_deg",
                         "kind", "frame_rate_hz", "trigger_offset_s"):
                if keep in old:
                    cfg[keep] = old[keep]
            fieldpath.set_in(d, path, cfg)

        try_edit(self.editFailed.emit,
                 lambda: self.document.edit(f"Radar preset {name}", mutate), self.refresh,
                 field=self.radar_preset)

    # --- view -------------------------------------------------------------------------
    def refresh(self, *_: object) -> None:
        """Show the project's sensor settings and the derived quantities."""
        project = self.document.project
        tof, radar = self.tof_config(), self.radar_config()
        self._enable_pages(tof, radar)
        self.tof_box.setTitle(f"ToF camera (AMCW) — {self._which('tof')}")
        self.radar_box.setTitle(f"Radar (FMCW) — {self._which('radar')}")
        self.link_form.refresh()
        self.tof_interference_form.refresh()
        if tof is not None:
            self._show_tof(tof)
        if radar is not None:
            self._show_radar(radar)
        dsp = getattr(project, "dsp", None)
        if dsp is not None:
            for field, combo in self.dsp_combos.items():
                with QSignalBlocker(combo):
                    combo.setCurrentText(str(getattr(dsp, field)))
            with QSignalBlocker(self.cfar_dims):
                self.cfar_dims.setCurrentIndex(0 if dsp.cfar_dimensions == 2 else 1)
            set_quietly(self.pfa, -np.log10(dsp.cfar_pfa))
            set_quietly(self.clutter, dsp.static_clutter_removal)
            set_quietly(self.min_range, dsp.min_range_m)
        self.refresh_derived()

    def _show_tof(self, tof: Any) -> None:
        """Show the settings of the ToF camera edited now."""
        with QSignalBlocker(self.tof_preset):
            self.tof_preset.setCurrentText(tof.preset)
        describe_presets(self.tof_preset, self.tof_device)
        set_quietly(self.tof_width, tof.width)
        set_quietly(self.tof_height, tof.height)
        for name, w in self.tof_widgets.items():
            set_quietly(w, getattr(tof, name))
        set_quietly(self.tof_ss, tof.supersampling)
        freqs = tof.modulation_frequencies_hz
        tof_f = SENSOR_FIELDS["tof_f"]
        set_quietly(self.tof_f1, tof_f.to_shown(freqs[0]))
        set_quietly(self.tof_f2_on, len(freqs) > 1)
        set_quietly(self.tof_f2, tof_f.to_shown(freqs[1] if len(freqs) > 1 else freqs[0] * 0.8))
        self.tof_f2.setEnabled(len(freqs) > 1)
        self.tof_pos.set_value(tof.pose_on_rig.position_m)
        self.tof_rot.set_value(tof.pose_on_rig.rotation_deg)
        self.tof_effects.refresh(tof)
        self.tof_derived.setText(
            f"unambiguous range {tof.combined_unambiguous_range_m:.2f} m\n"
            f"render {tof.width * tof.supersampling}×{tof.height * tof.supersampling} px")

    def _show_radar(self, radar: Any) -> None:
        """Show the settings of the radar edited now."""
        with QSignalBlocker(self.radar_preset):
            self.radar_preset.setCurrentText(radar.preset)
        describe_presets(self.radar_preset, self.radar_device)
        for spec in RADAR_FIELDS:
            set_quietly(self.radar_widgets[spec.name], spec.to_shown(getattr(radar, spec.name)))
        set_quietly(self.samples, radar.samples_per_chirp)
        set_quietly(self.chirps, radar.chirps_per_frame)
        set_quietly(self.iq, radar.complex_iq)
        set_quietly(self.render_fov, radar.render_fov_h_deg)
        set_quietly(self.render_w, radar.render_width)
        set_quietly(self.render_h, radar.render_height)
        self.radar_pos.set_value(radar.pose_on_rig.position_m)
        self.radar_rot.set_value(radar.pose_on_rig.rotation_deg)

    def refresh_derived(self) -> None:
        """Recompute the derived radar quantities and warnings."""
        project = self.document.project
        radar = self.radar_config()
        name = self.document.current_sensor("radar")
        if radar is None or name is None:
            self.derived.setText("no radar")
            self.warnings.setVisible(False)
            return
        az, el = angle_resolution_deg(radar)
        lam = radar.wavelength_m
        rows = [
            ("wavelength λ", f"{lam * 1e3:.3f} mm"),
            ("half wavelength", f"{lam * 5e2:.3f} mm"),
            ("range resolution", f"{radar.range_resolution_m * 100:.2f} cm"),
            ("max range", f"{radar.max_range_m:.2f} m"),
            ("velocity resolution", f"{radar.velocity_resolution_mps:.3f} m/s"),
            ("max velocity", f"±{radar.max_velocity_mps:.2f} m/s"),
            ("azimuth resolution", "—" if az is None else f"≈ {az:.1f}°"),
            ("elevation resolution", "—" if el is None else f"≈ {el:.1f}°"),
            ("channels", f"{len(radar.tx)} Tx × {len(radar.rx)} Rx"),
            ("virtual channels", f"{len(radar.tx) * len(radar.rx)}"),
            ("chirp slope", f"{radar.slope_hz_per_s * 1e-12:.2f} MHz/µs"),
            ("frame duration", f"{radar.frame_duration_s * 1e3:.2f} ms"),
        ]
        self.derived.setText("<table>" + "".join(
            f"<tr><td style='color:#9aa4ae; padding-right:8px'>{k}</td><td>{v}</td></tr>"
            for k, v in rows) + "</table>")
        # The scene's ranges and velocities need a snapshot: only when the scene moved.
        rig = project.sensor_rig(name)
        key = (name, project.objects, rig.pose, rig.motion, radar.pose_on_rig)
        if key != self._extent_key:
            self._extent_key, self._extent = key, scene_radial_extent(project, radar_name=name)
        warnings = radar_warnings(project, self._extent, radar_name=name)
        self.warnings.setText("\n".join(f"⚠ {w}" for w in warnings))
        self.warnings.setVisible(bool(warnings))


__all__ = ["SPEED_OF_LIGHT", "SensorEditor", "angle_resolution_deg", "radar_warnings"]
