"""FMCW radar front end: scene snapshot + radar render → raw ADC cube.

Two stages, so that an antenna, waveform or receiver edit re-runs only the second:

1. :meth:`RadarFrontEnd.scatterers` — point scatterers from the radar render pass
   (:mod:`simcore.sensors.radar.scatterers`); depends on the scene, not on the antennas.
2. :meth:`RadarFrontEnd.synthesize` — IF synthesis per Tx–Rx pair and chirp with finufft,
   then leakage, noise, high-pass and ADC (:mod:`simcore.sensors.radar.synthesis`).

The ADC cube is in units of the ADC full scale ("FS": ±1 = largest code) and shaped
``(chirps, tx*rx, samples)``: float32 for a real IF, complex64 for IQ. Channel
``t * n_rx + r`` is Tx ``t`` with Rx ``r``; in TDM-MIMO the Tx fire in turn within each
chirp slot group, so chirp ``m`` of Tx ``t`` starts at ``(m * n_tx + t) * T_r``.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from simcore.render.buffers import RenderBuffers
from simcore.scene.materials import DualBandMaterial
from simcore.scene.model import Project
from simcore.scene.project_io import material_table
from simcore.scene.radar_config import RadarConfig, aliasing_warnings
from simcore.scene.snapshot import SceneSnapshot
from simcore.sensors.radar.scatterers import KIND_FACET, Scatterers, scatterers_from_render
from simcore.sensors.radar.synthesis import (
    ComplexCube,
    PreparedScatterers,
    SynthesisMethod,
    check_wavelength,
    prepare,
    receiver_chain,
    synthesize_if,
    synthesize_if_direct,
)

#: Unit string of ADC values (fraction of the ADC full scale).
ADC_UNIT = "FS"


@dataclass(frozen=True)
class RadarOutput:
    """One frame of raw radar data.

    Attributes
    ----------
    adc : ndarray, shape (chirps, tx*rx, samples)
        ADC samples in FS (±1 = ADC full scale); float32 (real IF) or complex64 (IQ).
    time_s : float
        Frame timestamp = start of the first chirp (s), shared with the other sensors.
    chirp_start_s : ndarray, shape (chirps, tx), float64
        Absolute start time of every chirp of every Tx (s).
    sample_rate_hz : float
        ADC sample rate (Hz); sample ``n`` is taken ``n / sample_rate_hz`` after its
        chirp's start.
    complex_iq : bool
        Whether ``adc`` is complex IQ.
    tx_positions_m, rx_positions_m : ndarray, shape (tx, 3) and (rx, 3)
        Antenna positions in the radar optical frame (m).
    n_scatterers : int
        Scatterers that contributed.
    clipped_samples : int
        ADC values (I and Q separately) clipped at full scale.
    """

    adc: NDArray[np.float32] | NDArray[np.complex64]
    time_s: float
    chirp_start_s: NDArray[np.float64]
    sample_rate_hz: float
    complex_iq: bool
    tx_positions_m: NDArray[np.float64]
    rx_positions_m: NDArray[np.float64]
    n_scatterers: int
    clipped_samples: int

    @property
    def virtual_positions_m(self) -> NDArray[np.float64]:
        """Virtual-array positions ``p_tx + p_rx`` of the channels, shape (tx*rx, 3), m."""
        return (self.tx_positions_m[:, None, :] + self.rx_positions_m[None, :, :]
                ).reshape(-1, 3)

    def hdf5_items(self) -> dict[str, tuple[NDArray[np.generic], str]]:
        """Per-frame datasets: HDF5 path → (array without the frame axis, unit)."""
        return {
            "/radar/adc": (self.adc, ADC_UNIT),
            "/radar/chirp_start_time": (self.chirp_start_s, "s"),
        }


class RadarFrontEnd:
    """The radar of a project: scatterers from renders, then raw ADC data.

    Parameters
    ----------
    project : Project
        The project; its current ``rig.radar`` is used unless ``config`` is given, so edits
        of the project apply to the next call.
    config : RadarConfig, optional
        A radar configuration to use instead of the project's.
    speckle_seed : int, optional
        Speckle realisation of rough surfaces (default: the project's seed).
    """

    def __init__(self, project: Project, *, config: RadarConfig | None = None,
                 speckle_seed: int | None = None):
        self.project = project
        self._config = config
        self.speckle_seed = project.seed if speckle_seed is None else speckle_seed
        self._cache: tuple[NDArray[np.int32], tuple[object, ...], Scatterers] | None = None
        self._material_cache: tuple[list[str], dict[str, DualBandMaterial]] | None = None
        self._background: tuple[SceneSnapshot, RenderBuffers] | None = None
        self._bg_scatterers: tuple[tuple[object, ...], Scatterers, NDArray[np.int32]] | None = None
        self._bg_if: tuple[Scatterers, str, ComplexCube] | None = None
        #: Prepared arrays of the last few scatterer sets (background, frame, subsets).
        self._prepared: list[PreparedScatterers] = []
        #: Scatterers of the last frame synthesised over the background, and how many of
        #: them were transformed (0 when the background was not used), for benchmarks.
        self.last_transformed: int = 0

    @property
    def config(self) -> RadarConfig:
        """The radar configuration in use."""
        return self._config if self._config is not None else self.project.rig.radar

    def scatterers(self, snapshot: SceneSnapshot, buffers: RenderBuffers) -> Scatterers:
        """Point scatterers of a frame (independent of antennas, waveform timing, receiver).

        Parameters
        ----------
        snapshot : SceneSnapshot
            The frame's snapshot.
        buffers : RenderBuffers
            The radar render of ``snapshot``.
        """
        cfg = self.config
        return scatterers_from_render(self.project, snapshot, buffers,
                                      wavelength_m=cfg.wavelength_m,
                                      facets=cfg.facet_intrinsics(), speckle=cfg.speckle,
                                      seed=self.speckle_seed, materials=self._materials())

    def _materials(self) -> dict[str, DualBandMaterial]:
        """The project's material table, re-read only when its own materials change."""
        key = [m.model_dump_json() for m in self.project.materials]
        if self._material_cache is None or self._material_cache[0] != key:
            self._material_cache = (key, material_table(self.project))
        return self._material_cache[1]

    def _scatterer_key(self) -> tuple[object, ...]:
        cfg = self.config
        return (cfg.wavelength_m, cfg.speckle, self.speckle_seed, cfg.render_width,
                cfg.render_height, cfg.render_fov_h_deg)

    def cached_scatterers(self, snapshot: SceneSnapshot, buffers: RenderBuffers
                          ) -> Scatterers:
        """:meth:`scatterers`, re-used while the render, λ, speckle and facet grid are unchanged.

        The render is recognised by its arrays, so a render re-used for another frame time
        (a static scene, ``dataclasses.replace(buffers, time_s=...)``) re-uses the
        scatterers too, with that frame's ``time_s``.
        """
        key = self._scatterer_key()
        if (self._cache is not None and self._cache[0] is buffers.object_index
                and self._cache[1] == key):
            sc = self._cache[2]
            if sc.time_s != buffers.time_s:
                sc = dataclasses.replace(sc, time_s=float(buffers.time_s))
            return sc
        sc = self.scatterers(snapshot, buffers)
        self._cache = (buffers.object_index, key, sc)
        return sc

    # ------------------------------------------------------------------ static background
    def set_background(self, snapshot: SceneSnapshot | None, buffers: RenderBuffers | None
                       ) -> None:
        """Declare the radar render of the scene's *static* objects alone (or forget it).

        Valid while the radar does not move relative to those objects. The IF of the
        background's scatterers is computed once per radar configuration; a frame's IF is
        then that, minus the background scatterers the frame does not show (hidden by
        moving objects), plus the frame's own other scatterers (moving objects, analytic
        targets): ``y = y_bg − y(hidden) + y(others)``. Exact up to the NUFFT's tolerance
        and rounding, and a function of the frame and the background only (so runs stay
        reproducible whatever order frames are computed in).
        """
        self._background = None if snapshot is None or buffers is None else (snapshot, buffers)
        self._bg_scatterers = None
        self._bg_if = None

    def _background_scatterers(self) -> tuple[Scatterers, NDArray[np.int32]] | None:
        """Facet scatterers of the background and the index of each facet's first one."""
        if self._background is None:
            return None
        key = self._scatterer_key()
        if self._bg_scatterers is None or self._bg_scatterers[0] != key:
            sc = self.scatterers(*self._background)
            facets = sc.subset(sc.kind == KIND_FACET)
            assert facets.facet_key is not None
            cell = facets.facet_key // max(len(self.project.objects), 1)
            first = np.ones(len(cell), dtype=bool)
            first[1:] = cell[1:] != cell[:-1]
            n_cells = int(cell[-1]) + 1 if len(cell) else 0
            table = np.full(n_cells, -1, dtype=np.int32)
            table[cell[first]] = np.flatnonzero(first)
            self._bg_scatterers = (key, facets, table)
            self._bg_if = None
        return self._bg_scatterers[1], self._bg_scatterers[2]

    def _ideal_if_over_background(self, scatterers: Scatterers) -> ComplexCube | None:
        """IF of ``scatterers`` as background IF − hidden + others, or None if not worth it."""
        found = self._background_scatterers()
        if found is None or scatterers.facet_key is None or not len(found[0]):
            return None
        bg, table = found
        assert bg.facet_key is not None
        fk, bk = scatterers.facet_key, bg.facet_key
        # Background scatterer with the same key (same facet, same object), if any: the
        # first one of the same facet, else (several objects share a facet) a search.
        cell = fk // max(len(self.project.objects), 1)
        inside = (fk >= 0) & (cell < len(table))
        pos = np.where(inside, table[np.where(inside, cell, 0)], -1).astype(np.intp)
        same = (pos >= 0) & (bk[pos] == fk)
        other = np.flatnonzero(inside & (pos >= 0) & ~same)
        if len(other):
            hit = np.minimum(np.searchsorted(bk, fk[other]), len(bk) - 1)
            ok = bk[hit] == fk[other]
            pos[other[ok]] = hit[ok]
            same[other[ok]] = True
        # Equal keys and equal values: the same static surface patch as in the background
        # (a guard: both come from identical shading of the same pixel).
        same &= scatterers.rcs_m2 == bg.rcs_m2[pos]
        same &= scatterers.phase_rad == bg.phase_rad[pos]
        same &= scatterers.positions_m[:, 2] == bg.positions_m[pos, 2]
        shown = np.zeros(len(bg), dtype=bool)
        shown[pos[same]] = True
        others = np.flatnonzero(~same)
        hidden = np.flatnonzero(~shown)
        # Transforms needed either way for the moving scatterers; compare the static rest.
        if len(hidden) + len(others) > 0.5 * len(scatterers):
            return None
        return self._over_background(bg, bg.subset(hidden), scatterers.subset(others))

    def _over_background(self, bg: Scatterers, hidden: Scatterers, others: Scatterers
                         ) -> ComplexCube:
        """``y_bg − y(hidden) + y(others)``, the background's IF cached per configuration."""
        cfg = self.config
        config_key = cfg.model_dump_json()
        if self._bg_if is None or self._bg_if[0] is not bg or self._bg_if[1] != config_key:
            self._bg_if = (bg, config_key, self._synthesize(bg))
        out = self._bg_if[2].copy()
        if len(hidden):
            out -= self._synthesize(hidden)
        if len(others):
            out += self._synthesize(others)
        self.last_transformed = len(hidden) + len(others)
        return out

    def _synthesize(self, scatterers: Scatterers) -> ComplexCube:
        """:func:`synthesize_if` with the prepared arrays of recent scatterer sets kept."""
        prep = next((p for p in self._prepared if p.source is scatterers), None)
        if prep is None:
            prep = prepare(scatterers)
            self._prepared = [*self._prepared[-3:], prep]
        return synthesize_if(scatterers, self.config, prepared=prep)

    def ideal_if(self, scatterers: Scatterers, *, method: SynthesisMethod = "nufft"
                 ) -> ComplexCube:
        """Noise-free complex IF, shape (chirps, tx*rx, samples), FS (real IF = real part).

        ``method="direct"`` evaluates the exact sum (slow; the reference for tests). With a
        background (:meth:`set_background`), the NUFFT path transforms only what differs
        from it.
        """
        if method == "nufft":
            self.last_transformed = len(scatterers)
            if self._background is not None:
                check_wavelength(scatterers, self.config)
                out = self._ideal_if_over_background(scatterers)
                if out is not None:
                    return out
                self.last_transformed = len(scatterers)
            return self._synthesize(scatterers)
        if method == "direct":
            return synthesize_if_direct(scatterers, self.config)
        raise ValueError(f"unknown synthesis method {method!r}; use 'nufft' or 'direct'")

    def simulate_over_background(self, snapshot: SceneSnapshot, buffers: RenderBuffers,
                                 changed: NDArray[np.intp], *, rng: np.random.Generator
                                 ) -> RadarOutput | None:
        """Raw ADC data of a frame known to differ from the background only at ``changed``.

        ``changed`` are the flat indices of the render pixels whose triangle differs from
        the background's render (:func:`simcore.render.renderer.changed_pixels`); every
        other pixel holds the background's values. Only the facets touching them are
        computed: the background's there are subtracted, the frame's (and its analytic
        targets) added. Same data as :meth:`simulate` to rounding, without the frame's
        full set of scatterers. None when there is no background or it does not fit.
        """
        found = self._background_scatterers()
        bg_buffers = None if self._background is None else self._background[1]
        if found is None or bg_buffers is None or bg_buffers.shape != buffers.shape:
            return None
        bg = found[0]
        cfg = self.config
        check_wavelength(bg, cfg)
        h, w = buffers.shape
        facets = cfg.facet_intrinsics()
        step = h // facets.height if facets.height and h % facets.height == 0 else 0
        if step < 1 or w != facets.width * step:
            return None
        rows, cols = np.divmod(changed, w)
        cells = np.zeros(facets.height * facets.width, dtype=bool)
        cells[(rows // step) * facets.width + cols // step] = True
        if np.count_nonzero(cells) > cells.size // 2:
            return None
        grid = cells.reshape(facets.height, facets.width)
        pixels = np.repeat(np.repeat(grid, step, axis=0), step, axis=1) if step > 1 else grid
        others = scatterers_from_render(self.project, snapshot, buffers,
                                        wavelength_m=cfg.wavelength_m, facets=facets,
                                        speckle=cfg.speckle, seed=self.speckle_seed,
                                        materials=self._materials(), pixels=pixels)
        assert bg.facet_key is not None
        hidden = bg.subset(np.flatnonzero(
            np.take(cells, bg.facet_key // max(len(self.project.objects), 1))))
        ideal = self._over_background(bg, hidden, others)
        return self._output(ideal, time_s=float(snapshot.time_s),
                            n_scatterers=len(bg) - len(hidden) + len(others), rng=rng)

    def _output(self, ideal: ComplexCube, *, time_s: float, n_scatterers: int,
                rng: np.random.Generator) -> RadarOutput:
        cfg = self.config
        adc, clipped = receiver_chain(ideal, cfg, rng)
        return RadarOutput(
            adc=adc,
            time_s=time_s,
            chirp_start_s=time_s + cfg.chirp_start_times_s(),
            sample_rate_hz=cfg.sample_rate_hz,
            complex_iq=cfg.complex_iq,
            tx_positions_m=cfg.tx_positions_m(),
            rx_positions_m=cfg.rx_positions_m(),
            n_scatterers=n_scatterers,
            clipped_samples=clipped,
        )

    def synthesize(self, scatterers: Scatterers, *, rng: np.random.Generator,
                   method: SynthesisMethod = "nufft") -> RadarOutput:
        """Raw ADC data of a frame from its scatterers.

        Parameters
        ----------
        scatterers : Scatterers
            From :meth:`scatterers`.
        rng : numpy.random.Generator
            Source of the receiver noise (seed it for reproducible frames).
        method : {"nufft", "direct"}
            IF synthesis method.

        Returns
        -------
        RadarOutput
        """
        return self._output(self.ideal_if(scatterers, method=method),
                            time_s=scatterers.time_s, n_scatterers=len(scatterers), rng=rng)

    def simulate(self, snapshot: SceneSnapshot, buffers: RenderBuffers, *,
                 rng: np.random.Generator) -> RadarOutput:
        """Scatterers (cached per render) and synthesis in one call."""
        return self.synthesize(self.cached_scatterers(snapshot, buffers), rng=rng)

    def warnings(self, buffers: RenderBuffers) -> list[str]:
        """Aliasing and layout warnings for the scene seen in ``buffers``."""
        valid = buffers.valid
        return aliasing_warnings(self.config, ranges_m=buffers.range_m[valid],
                                 radial_velocities_mps=buffers.radial_velocity_mps[valid])
