"""Array analysis beside the antenna board: the virtual array and its beam pattern.

The beam pattern is the array factor of the virtual array (TDM-MIMO: one element at
``p_tx + p_rx`` per Tx/Rx pair, the positions the DSP's angle estimators use),

``AF(u) = |Σ_i w_i exp(j 2π p_i·u / λ)|² / |Σ_i w_i|²``  (dB, 0 dB = the main lobe's peak),

with ``u = (sin az cos el, −sin el, cos az cos el)`` in the radar's optical frame (board x
right, y down, boresight z; azimuth positive towards +x, elevation positive up) and the
steering weights ``w_i = exp(−j 2π p_i·u₀ / λ)`` that point the main lobe at ``u₀``.
Element patterns are left out: the array factor alone shows where grating lobes appear.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pyqtgraph as pg
from numpy.typing import NDArray
from PyQt6.QtCore import Qt
from PyQt6.QtWidgets import QHBoxLayout, QLabel, QVBoxLayout, QWidget

from app.document.document import ProjectDocument
from app.document.sensors import current_radar, has_kind
from app.widgets.inputs import spin
from simcore.scene.radar_config import RadarConfig

#: Angles of the pattern cuts (degrees).
CUT_DEG = np.linspace(-90.0, 90.0, 721)
#: Floor of the pattern plots (dB).
FLOOR_DB = -40.0
#: A side lobe within this much of the main lobe counts as a grating lobe (dB).
GRATING_LOBE_DB = 3.0
VIRTUAL_COLOUR = "#ffd54a"


def direction(az_deg: NDArray[np.floating] | float, el_deg: NDArray[np.floating] | float
              ) -> NDArray[np.float64]:
    """Unit direction vectors of azimuth/elevation pairs in the radar's optical frame.

    Parameters
    ----------
    az_deg, el_deg : ndarray or float
        Azimuth (positive towards board +x) and elevation (positive up, board −y), degrees;
        broadcast against each other to shape ``(...)``.

    Returns
    -------
    u : ndarray, shape (..., 3)
        ``(sin az cos el, −sin el, cos az cos el)``.
    """
    az, el = np.broadcast_arrays(np.radians(az_deg), np.radians(el_deg))
    return np.stack([np.sin(az) * np.cos(el), -np.sin(el), np.cos(az) * np.cos(el)], axis=-1)


def virtual_positions_mm(tx_mm: NDArray[np.floating], rx_mm: NDArray[np.floating]
                         ) -> NDArray[np.float64]:
    """Virtual-array positions ``p_tx + p_rx`` on the board.

    Parameters
    ----------
    tx_mm : ndarray, shape (tx, 2)
    rx_mm : ndarray, shape (rx, 2)
        Board positions (mm, x right, y down).

    Returns
    -------
    ndarray, shape (tx * rx, 2)
        Tx-major (channel ``t * n_rx + r``), mm.
    """
    tx = np.asarray(tx_mm, dtype=np.float64).reshape(-1, 2)
    rx = np.asarray(rx_mm, dtype=np.float64).reshape(-1, 2)
    return (tx[:, None, :] + rx[None, :, :]).reshape(-1, 2)


def array_factor_db(positions_mm: NDArray[np.floating], wavelength_m: float,
                    az_deg: NDArray[np.floating] | float, el_deg: NDArray[np.floating] | float,
                    *, steer_az_deg: float = 0.0, steer_el_deg: float = 0.0,
                    floor_db: float = -300.0) -> NDArray[np.float64]:
    """Normalised power array factor of elements at ``positions_mm`` (dB).

    Parameters
    ----------
    positions_mm : ndarray, shape (n, 2)
        Element positions on the board (mm).
    wavelength_m : float
        Wavelength (m).
    az_deg, el_deg : ndarray or float
        Directions to evaluate (degrees), broadcast to shape ``(...)``.
    steer_az_deg, steer_el_deg : float
        Direction the steering phases point the main lobe at (degrees).
    floor_db : float
        Lowest value returned.

    Returns
    -------
    ndarray, shape (...)
        ``10 log10(|Σ w_i exp(j 2π p_i·u/λ)|² / n²)``; 0 dB in the steering direction.

    Examples
    --------
    Two elements one wavelength apart cancel at 30° (path difference λ/2):

    >>> lam = 0.005
    >>> float(array_factor_db([[0.0, 0.0], [5.0, 0.0]], lam, 30.0, 0.0)) < -100
    True
    >>> float(array_factor_db([[0.0, 0.0], [5.0, 0.0]], lam, 0.0, 0.0))
    0.0
    """
    p = np.zeros((len(np.atleast_2d(positions_mm)), 3))
    p[:, :2] = np.asarray(positions_mm, dtype=np.float64).reshape(-1, 2) * 1e-3
    k = 2.0 * np.pi / wavelength_m
    u = direction(az_deg, el_deg)
    u0 = direction(steer_az_deg, steer_el_deg)
    weights = np.exp(-1j * k * (p @ u0))
    field = np.exp(1j * k * (u @ p.T)) @ weights
    power = np.abs(field) ** 2 / len(p) ** 2
    return np.asarray(np.maximum(10.0 * np.log10(np.maximum(power, 1e-300)), floor_db))


def lobe_peaks(angles_deg: NDArray[np.floating], pattern_db: NDArray[np.floating], *,
               within_db: float = GRATING_LOBE_DB) -> NDArray[np.float64]:
    """Angles of the local maxima of a pattern cut within ``within_db`` of its peak.

    Parameters
    ----------
    angles_deg, pattern_db : ndarray, shape (n,)
        A pattern cut.

    Returns
    -------
    ndarray, shape (k,)
        Angles of the lobes (degrees), the main lobe included; the ends of the cut count
        when the pattern rises towards them.
    """
    a = np.asarray(pattern_db, dtype=np.float64)
    padded = np.concatenate([[-np.inf], a, [-np.inf]])
    is_peak = (padded[1:-1] >= padded[:-2]) & (padded[1:-1] > padded[2:])
    is_peak &= a >= a.max() - within_db
    return np.asarray(angles_deg, dtype=np.float64)[is_peak]

#: Colours of the pattern's azimuth and elevation cuts (named in the plot's title).
AZ_COLOUR, EL_COLOUR = "#ffb74d", "#81c784"


@dataclass(frozen=True)
class ArrayPattern:
    """The virtual array of a radar configuration and its pattern cuts.

    Attributes
    ----------
    tx_mm, rx_mm, virtual_mm : ndarray, shape (n, 2)
        Board positions (mm); ``virtual_mm`` is tx-major.
    wavelength_m : float
        Wavelength at the chirp's centre frequency.
    angles_deg : ndarray, shape (a,)
        Angles of both cuts.
    azimuth_db, elevation_db : ndarray, shape (a,)
        Azimuth cut at the steering elevation and elevation cut at the steering azimuth.
    azimuth_lobes_deg, elevation_lobes_deg : ndarray
        Lobes within :data:`GRATING_LOBE_DB` of the main lobe (the main lobe included).
    """

    tx_mm: NDArray[np.float64]
    rx_mm: NDArray[np.float64]
    virtual_mm: NDArray[np.float64]
    wavelength_m: float
    steer_az_deg: float
    steer_el_deg: float
    angles_deg: NDArray[np.float64]
    azimuth_db: NDArray[np.float64]
    elevation_db: NDArray[np.float64]
    azimuth_lobes_deg: NDArray[np.float64]
    elevation_lobes_deg: NDArray[np.float64]

    def grating_lobes(self) -> dict[str, NDArray[np.float64]]:
        """Lobes other than the main one, per cut ("azimuth", "elevation"), degrees."""
        out = {}
        for name, lobes, steer in (("azimuth", self.azimuth_lobes_deg, self.steer_az_deg),
                                   ("elevation", self.elevation_lobes_deg, self.steer_el_deg)):
            if len(lobes):
                main = lobes[np.argmin(np.abs(lobes - steer))]
                out[name] = lobes[lobes != main]
            else:
                out[name] = lobes
        return out


def array_pattern(config: RadarConfig, *, steer_az_deg: float = 0.0, steer_el_deg: float = 0.0,
                  angles_deg: NDArray[np.floating] = CUT_DEG) -> ArrayPattern:
    """Virtual array and azimuth/elevation pattern cuts of a radar configuration."""
    tx = np.array([a.position_mm for a in config.tx], dtype=np.float64).reshape(-1, 2)
    rx = np.array([a.position_mm for a in config.rx], dtype=np.float64).reshape(-1, 2)
    virtual = virtual_positions_mm(tx, rx)
    lam = config.wavelength_m
    angles = np.asarray(angles_deg, dtype=np.float64)
    az_cut = array_factor_db(virtual, lam, angles, steer_el_deg, steer_az_deg=steer_az_deg,
                             steer_el_deg=steer_el_deg, floor_db=FLOOR_DB)
    el_cut = array_factor_db(virtual, lam, steer_az_deg, angles, steer_az_deg=steer_az_deg,
                             steer_el_deg=steer_el_deg, floor_db=FLOOR_DB)
    return ArrayPattern(tx, rx, virtual, lam, steer_az_deg, steer_el_deg, angles, az_cut,
                        el_cut, lobe_peaks(angles, az_cut), lobe_peaks(angles, el_cut))


class ArrayAnalysisView(QWidget):
    """The azimuth/elevation beam pattern of the virtual array, updated live.

    (The board, :class:`~app.editors.antenna_editor.AntennaBoardView`, draws the virtual array.)
    Listens to the document: every antenna edit (each step of a drag included) redraws
    the pattern. The steering direction is a setting of this view, not of the project.
    """

    def __init__(self, document: ProjectDocument, parent: QWidget | None = None):
        super().__init__(parent)
        self.document = document
        self.pattern: ArrayPattern | None = None
        self._key: tuple | None = None
        layout = QVBoxLayout(self)
        layout.setContentsMargins(0, 0, 0, 0)
        plots = QHBoxLayout()
        self.pattern_plot = pg.PlotWidget()
        self.pattern_plot.setToolTip(
            "Beam pattern: array factor of the virtual array |Σ w exp(j2π p·u/λ)|², dB "
            "(0 dB = main lobe), azimuth cut (orange) and elevation cut (green). Triangles: "
            f"grating lobes (other lobes within {GRATING_LOBE_DB:g} dB of the main lobe). "
            "Shaded: the radar's horizontal field of view.")
        pp = self.pattern_plot.getPlotItem()
        # The title names the curves in their colours: a legend inside the view hid the
        # side lobes in a narrow dock, one under the axis took the plot's height (issue #34).
        # Short, because a title wider than the plot widens the plot past its widget's edge.
        pp.setTitle(f"<span style='color:{AZ_COLOUR}'>— azimuth</span>&nbsp;&nbsp;"
                    f"<span style='color:{EL_COLOUR}'>‐ ‐ elevation</span>", size="8pt")
        pp.setLabel("bottom", "angle", "°")
        pp.setLabel("left", "gain", "dB")
        pp.setXRange(-90, 90, padding=0)
        pp.setYRange(FLOOR_DB, 2, padding=0)
        pp.hideButtons()
        pp.setMenuEnabled(False)
        pp.showGrid(x=True, y=True, alpha=0.25)
        self.fov_region = pg.LinearRegionItem((-50, 50), movable=False,
                                              brush=pg.mkBrush(255, 255, 255, 18),
                                              pen=pg.mkPen(None))
        pp.addItem(self.fov_region)
        self.az_curve = pp.plot(pen=pg.mkPen(AZ_COLOUR, width=2), name="azimuth")
        self.el_curve = pp.plot(pen=pg.mkPen(EL_COLOUR, width=1.5, style=Qt.PenStyle.DashLine),
                                name="elevation")
        self.lobe_marks = pg.ScatterPlotItem(size=11, symbol="t1", pen=pg.mkPen("#ff5252"),
                                             brush=pg.mkBrush("#ff5252"))
        pp.addItem(self.lobe_marks)
        plots.addWidget(self.pattern_plot, 1)
        layout.addLayout(plots, 1)
        row = QHBoxLayout()
        self.steer_az = spin(minimum=-90, maximum=90, decimals=1, step=5, suffix="°",
                             tooltip="Steering azimuth: phases w = exp(−j2π p·u₀/λ) point the "
                                     "main lobe at this azimuth (analysis only; the project "
                                     "is not changed)")
        self.steer_el = spin(minimum=-90, maximum=90, decimals=1, step=5, suffix="°",
                             tooltip="Steering elevation (analysis only)")
        for box in (self.steer_az, self.steer_el):
            box.valueChanged.connect(lambda _v: self.refresh())
        row.addWidget(QLabel("steer az"))
        row.addWidget(self.steer_az)
        row.addWidget(QLabel("el"))
        row.addWidget(self.steer_el)
        self.summary = QLabel("")
        self.summary.setWordWrap(True)
        self.summary.setStyleSheet("color: #9aa4ae;")
        row.addStretch(1)
        layout.addLayout(row)
        layout.addWidget(self.summary)
        document.projectChanged.connect(self.refresh)
        document.currentSensorChanged.connect(self.refresh)
        self.refresh()

    def refresh(self, *_: object) -> None:
        """Recompute the virtual array and the pattern from the document's radar."""
        if not has_kind(self.document.project, "radar"):
            self.setEnabled(False)  # a ToF-only project: nothing to edit here
            self._key = None
            return
        self.setEnabled(True)
        radar = current_radar(self.document)
        key = (tuple(a.position_mm for a in radar.tx), tuple(a.position_mm for a in radar.rx),
               radar.wavelength_m, radar.render_fov_h_deg, self.steer_az.value(),
               self.steer_el.value())
        if key == self._key:
            return  # an edit elsewhere (objects, materials): nothing to redraw
        self._key = key
        pat = array_pattern(radar, steer_az_deg=self.steer_az.value(),
                            steer_el_deg=self.steer_el.value())
        self.pattern = pat
        self.az_curve.setData(pat.angles_deg, pat.azimuth_db)
        self.el_curve.setData(pat.angles_deg, pat.elevation_db)
        half_fov = 0.5 * radar.render_intrinsics().fov_h_deg
        self.fov_region.setRegion((-half_fov, half_fov))
        grating = pat.grating_lobes()
        spots = []
        for name, curve in (("azimuth", pat.azimuth_db), ("elevation", pat.elevation_db)):
            for a in grating[name]:
                spots.append((a, float(np.interp(a, pat.angles_deg, curve)) + 1.5))
        self.lobe_marks.setData(pos=np.array(spots).reshape(-1, 2))
        n_unique = len(np.unique(np.round(pat.virtual_mm, 6), axis=0))
        text = (f"{len(pat.virtual_mm)} virtual elements ({n_unique} distinct), "
                f"λ = {pat.wavelength_m * 1e3:.3f} mm")
        lobes = [f"{name} {', '.join(f'{a:+.0f}°' for a in grating[name])}"
                 for name in grating if len(grating[name])]
        if lobes:
            text += " — grating lobes: " + "; ".join(lobes)
            self.summary.setStyleSheet("color: #ff6e6e;")
        else:
            self.summary.setStyleSheet("color: #9aa4ae;")
        self.summary.setText(text)
