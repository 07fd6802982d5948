"""Radar–radar interference in a frame: every other radar of the project as an aggressor.

For a victim radar's frame (its configuration as it transmits in that frame, its world
pose and its start time) every other radar on any rig of the project is an aggressor.
Each aggressor transmits frames ``n`` at ``n × period + trigger_offset_s`` on the
timeline's clock, each with its own hopping channel and chirp jitter
(:mod:`simcore.sensors.radar.transmit`); every aggressor frame that overlaps the victim's
frame in time adds its chirps, over the direct path (both radars' poses at that time) and,
when the victim's ``multipath_order`` ≥ 1, over the victim's scatterers (bistatic
aggressor → scatterer → victim), mixed with the victim's chirps and filtered by its IF
chain (:func:`simcore.sensors.radar.interference.mix_paths`).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from simcore.scene.model import Rig
from simcore.scene.radar_config import RadarConfig
from simcore.sensors.placement import sensor_state
from simcore.sensors.radar.interference import (
    PathSet,
    direct_paths,
    interference_to_noise_db,
    mix_paths,
    reflected_paths,
)
from simcore.sensors.radar.scatterers import Scatterers
from simcore.sensors.radar.transmit import frame_period_s, frame_transmit_config


@dataclass(frozen=True)
class FrameInterference:
    """The interference in one victim frame.

    Attributes
    ----------
    cube : ndarray, shape (chirps, tx*rx, samples), complex128
        To add to the victim's noise-free IF before its receiver (FS).
    inr_db : float
        Interference-to-noise ratio (:func:`interference_to_noise_db`).
    aggressor_frames : int
        Aggressor frames that overlapped the victim's frame.
    """

    cube: NDArray[np.complex128]
    inr_db: float
    aggressor_frames: int


def frame_interference(others: Sequence[tuple[str, Rig, RadarConfig]], victim_rig: Rig,
                       victim_config: RadarConfig, victim_start_s: float, *,
                       frame_rate_hz: float, scatterers: Scatterers | None = None
                       ) -> FrameInterference | None:
    """The other radars' signals in a frame of a victim radar; None without other radars.

    Parameters
    ----------
    others : sequence of (str, Rig, RadarConfig)
        The aggressors: every other radar with the rig that carries it
        (:func:`simcore.sensors.radar.sensor.aggressors`).
    victim_rig : Rig
        The rig that carries the victim radar (its pose and motion).
    victim_config : RadarConfig
        Its configuration as it transmits in this frame
        (:func:`~simcore.sensors.radar.transmit.frame_transmit_config`).
    victim_start_s : float
        Start of the victim's first chirp (s, timeline clock).
    frame_rate_hz : float
        The timeline's frame rate (each radar's frame period is a multiple of its period).
    scatterers : Scatterers, optional
        The victim's scatterers of the frame: with ``multipath_order`` ≥ 1 the aggressors
        also reach the victim over them.
    """
    if not others:
        return None
    rate = frame_rate_hz
    v_state = sensor_state(victim_rig, victim_config, victim_start_s)
    v_end = victim_start_s + victim_config.frame_duration_s
    cube = np.zeros((victim_config.chirps_per_frame,
                     len(victim_config.tx) * len(victim_config.rx),
                     victim_config.samples_per_chirp), np.complex128)
    n_frames = 0
    reflect = victim_config.multipath_order > 0 and scatterers is not None
    for _, rig, cfg in others:
        period = frame_period_s(cfg, rate)
        first = math.floor((victim_start_s - cfg.trigger_offset_s - cfg.frame_duration_s)
                           / period)
        last = math.floor((v_end - cfg.trigger_offset_s) / period)
        for n in range(max(first, 0), last + 1):
            a_start = n * period + cfg.trigger_offset_s
            a_cfg = frame_transmit_config(cfg, n)
            if (a_start + a_cfg.chirp_start_times_s().max() + a_cfg.chirp_time_s
                    < victim_start_s or a_start > v_end):
                continue
            a_state = sensor_state(rig, cfg, a_start)
            vel_v, vel_a = v_state.velocity_mps, a_state.velocity_mps
            sets = [direct_paths(victim_config, v_state.transform, a_cfg, a_state.transform,
                                 victim_velocity_mps=vel_v, aggressor_velocity_mps=vel_a)]
            if reflect:
                assert scatterers is not None
                sets.append(reflected_paths(victim_config, v_state.transform, a_cfg,
                                            a_state.transform, scatterers,
                                            victim_velocity_mps=vel_v,
                                            aggressor_velocity_mps=vel_a))
            starts = a_cfg.chirp_start_times_s() + (a_start - victim_start_s)
            cube += mix_paths(victim_config, a_cfg, PathSet.concatenate(sets),
                              aggressor_starts_s=starts)
            n_frames += 1
    return FrameInterference(cube, interference_to_noise_db(cube, victim_config), n_frames)


__all__ = ["FrameInterference", "frame_interference"]
