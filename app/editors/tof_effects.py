"""The ToF camera's effect switches: one checkbox per physical effect, each with a tooltip.

Each box sets ``rig.tof.<name>`` (bool) through the sensor editor's setter; the physics of
each is in ``docs/physics_tof.md``.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from PyQt6.QtWidgets import QCheckBox, QGridLayout, QGroupBox, QWidget

from app.widgets.inputs import set_quietly

#: (field, label, tooltip) of every ToF effect switch.
TOF_EFFECTS: tuple[tuple[str, str, str], ...] = (
    ("multipath", "multipath",
     "Multipath interference: light reaching a pixel via a second (diffuse) surface; "
     "concave corners read too far"),
    ("specular", "specular (metal, glossy)",
     "Specular near-IR inter-reflections (GGX lobe, up to a triple bounce): a metal corner "
     "reflector returns its apex range"),
    ("motion_artifacts", "motion artefacts",
     "Each of the four correlation samples at its own capture time: moving edges and "
     "moving surfaces show per-sample phase errors"),
    ("wiggling", "wiggling",
     "Cyclic depth error from the 3rd/5th harmonics of the modulation waveform "
     "(a sin 4φ error, period a quarter of the unambiguous range)"),
    ("distortion", "lens distortion",
     "Brown–Conrady radial and tangential lens distortion of the rays the pixels see"),
    ("vignetting", "vignetting",
     "Natural vignetting: collected light falls off as cos⁴ of the off-axis angle"),
    ("stray_light", "stray light (PSF)",
     "Light scattered inside the lens (long-tail PSF on the complex correlation images): "
     "a bright near object pulls far pixels' depth"),
    ("ambient_light", "ambient light",
     "Sunlight/lamps at the illumination wavelength: offset, shot noise and saturation"),
    ("background_suppression", "background suppression (SBI)",
     "The pixel drains the ambient charge before saturation; its shot noise remains"),
    ("ideal", "ideal sensor (no noise)",
     "Validation and ground truth: no shot or read noise and no ADC quantisation "
     "(the optics and the other effects stay as set)"),
)


class TofEffectsBox(QGroupBox):
    """Checkboxes for the ToF effect switches."""

    def __init__(self, setter: Callable[..., None],
                 parent: QWidget | None = None):
        super().__init__("Effects", parent)
        grid = QGridLayout(self)
        grid.setContentsMargins(4, 4, 4, 4)
        self.boxes: dict[str, QCheckBox] = {}
        for i, (field, label, tip) in enumerate(TOF_EFFECTS):
            box = QCheckBox(label)
            box.setToolTip(tip)
            box.toggled.connect(
                lambda on, f=field, b=box, name=label: setter(
                    f"rig.tof.{f}", bool(on), b,
                    text=f"{'Turn on' if on else 'Turn off'} ToF {name.lower()}"))
            grid.addWidget(box, i // 2, i % 2)
            self.boxes[field] = box

    def refresh(self, tof: Any) -> None:
        """Show the switches of a :class:`~simcore.scene.tof_config.TofCameraConfig`."""
        for field, box in self.boxes.items():
            set_quietly(box, getattr(tof, field))
