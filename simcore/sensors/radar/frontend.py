"""FMCW radar front end: scene snapshot + radar render → raw ADC cube, as plain functions.

Two steps, so that an antenna, waveform or receiver edit re-runs only the second (the
engine caches each step, :mod:`simcore.sensors.radar.sensor`):

1. :func:`radar_scatterers` — point scatterers from the radar render pass
   (:mod:`simcore.sensors.radar.scatterers`); depends on the scene, not on the antennas.
2. :func:`simulate_radar` — IF synthesis per Tx–Rx pair with finufft, then leakage, noise,
   high-pass and ADC (:mod:`simcore.sensors.radar.synthesis`, :func:`radar_output`).

The ADC cube is in units of the ADC full scale ("FS": ±1 = largest code) and shaped
``(chirps, tx*rx, samples)``: float32 for a real IF, complex64 for IQ. Channel
``t * n_rx + r`` is Tx ``t`` with Rx ``r``; in TDM-MIMO the Tx fire in turn within each
chirp slot group, so chirp ``m`` of Tx ``t`` starts at ``(m * n_tx + t) * T_r``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from simcore.render.buffers import RenderBuffers
from simcore.scene.radar_config import RadarConfig, aliasing_warnings
from simcore.sensors.radar.scatterers import Scatterers, scatterers_from_render
from simcore.sensors.radar.scene import RadarScene
from simcore.sensors.radar.synthesis import (
    ComplexCube,
    SynthesisMethod,
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
    transformed_scatterers : int
        Scatterers transformed for this frame (fewer than ``n_scatterers`` when the IF of
        a still background was re-used).
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
    transformed_scatterers: int = 0
    #: Interference-to-noise ratio of the other radars' signals (dB); None: no other radar.
    inr_db: float | None = None

    @property
    def virtual_positions_m(self) -> NDArray[np.float64]:
        """Virtual-array positions ``p_tx + p_rx`` of the channels, shape (tx*rx, 3), m."""
        return (self.tx_positions_m[:, None, :] + self.rx_positions_m[None, :, :]
                ).reshape(-1, 3)

    def hdf5_items(self) -> dict[str, tuple[NDArray[np.generic], str]]:
        """Per-frame datasets: HDF5 path → (array without the frame axis, unit)."""
        items: dict[str, tuple[NDArray[np.generic], str]] = {
            "/radar/adc": (self.adc, ADC_UNIT),
            "/radar/chirp_start_time": (self.chirp_start_s, "s"),
        }
        if self.inr_db is not None:
            items["/radar/inr_db"] = (np.asarray(self.inr_db, dtype=np.float64), "dB")
        return items


def radar_scatterers(scene: RadarScene, buffers: RenderBuffers, *, config: RadarConfig,
                     seed: int | None = None, pixels: NDArray[np.bool_] | None = None,
                     see_through: RenderBuffers | None = None) -> Scatterers:
    """Point scatterers of a frame (independent of antennas, waveform timing, receiver).

    Parameters
    ----------
    scene : RadarScene
        The radar's slice of the frame (objects, materials, snapshot, its own pose):
        ``RadarScene.from_project(project, snapshot, name)``.
    buffers : RenderBuffers
        The radar render of ``scene.snapshot``.
    config : RadarConfig
        Radar configuration (wavelength, speckle, facet grid).
    seed : int, optional
        Speckle realisation (default: ``scene.seed``).
    pixels : ndarray of bool, shape (H, W), optional
        Only the facets covering these render pixels (plus the analytic targets).
    see_through : RenderBuffers, optional
        The radar render without its partially transparent objects
        (:meth:`RadarSensor.see_through`): what lies behind them, attenuated.
    """
    return scatterers_from_render(
        scene, buffers, wavelength_m=config.wavelength_m,
        facets=config.facet_intrinsics(), speckle=config.speckle,
        seed=scene.seed if seed is None else seed, pixels=pixels, see_through=see_through,
        polarization=config.polarization)


def radar_output(ideal: ComplexCube, config: RadarConfig, *, rng: np.random.Generator,
                 time_s: float, n_scatterers: int, transformed: int | None = None,
                 inr_db: float | None = None) -> RadarOutput:
    """The receiver over a noise-free IF cube: leakage, noise, high-pass, ADC.

    Parameters
    ----------
    ideal : ndarray, shape (chirps, tx*rx, samples), complex128
        Noise-free complex IF (FS), from :func:`simcore.sensors.radar.synthesis.synthesize_if`.
    config : RadarConfig
        The radar.
    rng : numpy.random.Generator
        Source of the receiver noise (seed it for reproducible frames).
    time_s : float
        Frame timestamp (s): the start of the first chirp.
    n_scatterers, transformed : int
        Scatterers in the frame, and how many were transformed (default all).
    """
    adc, clipped = receiver_chain(ideal, config, rng)
    return RadarOutput(
        adc=adc,
        time_s=float(time_s),
        chirp_start_s=time_s + config.chirp_start_times_s(),
        sample_rate_hz=config.sample_rate_hz,
        complex_iq=config.complex_iq,
        tx_positions_m=config.tx_positions_m(),
        rx_positions_m=config.rx_positions_m(),
        n_scatterers=n_scatterers,
        clipped_samples=clipped,
        transformed_scatterers=n_scatterers if transformed is None else transformed,
        inr_db=inr_db,
    )


def simulate_radar(scatterers: Scatterers, config: RadarConfig, *, rng: np.random.Generator,
                   method: SynthesisMethod = "nufft") -> RadarOutput:
    """Raw ADC data of a frame from its scatterers: IF synthesis, then the receiver.

    Parameters
    ----------
    scatterers : Scatterers
        From :func:`radar_scatterers`.
    config : RadarConfig
        The radar.
    rng : numpy.random.Generator
        Source of the receiver noise (seed it for reproducible frames).
    method : {"nufft", "direct"}
        IF synthesis: finufft (fast) or the literal sum (the reference; slow).

    Returns
    -------
    RadarOutput
    """
    if method == "nufft":
        ideal = synthesize_if(scatterers, config)
    elif method == "direct":
        ideal = synthesize_if_direct(scatterers, config)
    else:
        raise ValueError(f"unknown synthesis method {method!r}; use 'nufft' or 'direct'")
    return radar_output(ideal, config, rng=rng, time_s=scatterers.time_s,
                        n_scatterers=len(scatterers))


def radar_warnings(config: RadarConfig, buffers: RenderBuffers) -> list[str]:
    """Aliasing and layout warnings for the scene seen in ``buffers``."""
    valid = buffers.valid
    return aliasing_warnings(config, ranges_m=buffers.range_m[valid],
                             radial_velocities_mps=buffers.radial_velocity_mps[valid])
