"""What a radar transmits in one of its frames: chirp start jitter and frequency hopping.

Transmit-side interference mitigation (``docs/interference.md``). Each radar draws, per
frame of its own, a hopping channel ``c`` (``0 … hop_channels − 1``) and a start delay for
every chirp (uniform in ``[0, chirp_jitter_s)``) from ``numpy.random.default_rng((
transmit_seed, frame_number))``. The same draw serves the radar's own synthesis (its
echoes) and every other radar that receives it as an aggressor, so both sides agree.
:func:`frame_transmit_config` returns the frame's configuration: the start frequency
hopped, and the chirp start times (:meth:`RadarConfig.chirp_start_times_s`) jittered.

With both off (the defaults) the frame's configuration is the configuration itself.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from simcore.scene.radar_config import RadarConfig


def transmit_draw(config: RadarConfig, frame_number: int
                  ) -> tuple[int, NDArray[np.float64]]:
    """The hopping channel and the chirp start delays of one frame.

    Parameters
    ----------
    config : RadarConfig
        The radar (``chirp_jitter_s``, ``hop_channels``, ``transmit_seed``).
    frame_number : int
        The radar's own frame count (:func:`frame_number`).

    Returns
    -------
    channel : int
        Hopping channel (0 without hopping).
    delays_s : ndarray, shape (chirps, tx), float64
        Extra start delay of every chirp, TDM order (zeros without jitter).
    """
    n = config.chirps_per_frame * len(config.tx)
    if config.chirp_jitter_s <= 0 and config.hop_channels <= 1:
        return 0, np.zeros((config.chirps_per_frame, len(config.tx)))
    rng = np.random.default_rng((int(config.transmit_seed), int(frame_number) & 0x7FFFFFFF))
    channel = int(rng.integers(config.hop_channels))
    delays = rng.uniform(0.0, config.chirp_jitter_s, n) if config.chirp_jitter_s > 0 \
        else np.zeros(n)
    return channel, delays.reshape(config.chirps_per_frame, len(config.tx))


def frame_transmit_config(config: RadarConfig, frame_number: int) -> RadarConfig:
    """The configuration of one frame: start frequency hopped, chirp starts jittered.

    Returns ``config`` itself when neither mitigation is on.
    """
    if config.chirp_jitter_s <= 0 and config.hop_channels <= 1:
        return config
    channel, delays = transmit_draw(config, frame_number)
    out = config.model_copy(update={
        "start_frequency_hz": config.start_frequency_hz + channel * config.hop_step_hz})
    out._chirp_delays_s = delays.reshape(-1)
    return out


def transmit_key(config: RadarConfig) -> bytes:
    """What a frame copy adds to its configuration's JSON (for cache keys)."""
    delays = config._chirp_delays_s
    return b"" if delays is None else np.ascontiguousarray(delays).tobytes()


def frame_period_s(config: RadarConfig, timeline_rate_hz: float) -> float:
    """The radar's frame period on the timeline's clock (s)."""
    return config.frame_divider(timeline_rate_hz) / timeline_rate_hz


def frame_number(config: RadarConfig, time_s: float, timeline_rate_hz: float) -> int:
    """The radar's own frame count of the frame that starts at or before ``time_s``.

    Frame ``n`` starts at ``n × period + trigger_offset_s``.
    """
    period = frame_period_s(config, timeline_rate_hz)
    return int(math.floor((time_s - config.trigger_offset_s) / period + 1e-9))


__all__ = ["frame_number", "frame_period_s", "frame_transmit_config", "transmit_draw",
           "transmit_key"]
