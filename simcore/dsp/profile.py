"""A range profile consistent with the detector: the processed map integrated over Doppler.

The chirp-averaged range spectrum of the raw cube (``RadarProducts.range_profile_db``) is
not what the detector sees: static clutter removal, TDM compensation and the Doppler
window act on the range–Doppler map. :func:`processed_range_profile` integrates that map
over Doppler (mean power), and :func:`range_profile_cfar` runs a 1-D CFAR along range on the
result, so curve and threshold are on one scale and a peak above the threshold is what a
1-D detector on this profile would report.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from simcore.dsp.cfar import cfar_1d
from simcore.scene.dsp_config import CfarMethod


@dataclass(frozen=True)
class ProfileCfar:
    """A processed range profile and its own 1-D CFAR threshold.

    Attributes
    ----------
    profile_db : ndarray, shape (range,), float32
        Mean power over Doppler bins of the range–Doppler power map (dB).
    threshold_db : ndarray, shape (range,), float32
        1-D CFAR threshold along range on the same scale (dB).
    detections : ndarray, shape (range,), bool
        Range bins where the profile exceeds the threshold.
    """

    profile_db: NDArray[np.float32]
    threshold_db: NDArray[np.float32]
    detections: NDArray[np.bool_]


def processed_range_profile(range_doppler_power: ArrayLike) -> NDArray[np.float64]:
    """Mean power over Doppler of a range–Doppler power map.

    Parameters
    ----------
    range_doppler_power : array_like, shape (doppler, range)
        Linear power of the processed map (square-law, channels integrated).

    Returns
    -------
    ndarray, shape (range,), float64
        Linear power per range bin.

    Examples
    --------
    >>> processed_range_profile([[1.0, 4.0], [3.0, 0.0]])
    array([2., 2.])
    """
    power = np.asarray(range_doppler_power, dtype=np.float64)
    if power.ndim != 2:
        raise ValueError(f"range_doppler_power must be (doppler, range), got {power.shape}")
    return np.asarray(power.mean(axis=0))


def range_profile_cfar(range_doppler_db: ArrayLike, *, method: CfarMethod = "ca",
                       train: int = 8, guard: int = 2, pfa: float = 1e-6,
                       rank: float = 0.75, n_integrated: int = 1) -> ProfileCfar:
    """Processed range profile of a range–Doppler map (dB) and its 1-D CFAR threshold.

    Parameters
    ----------
    range_doppler_db : array_like, shape (doppler, range)
        Range–Doppler map in dB (power, channels integrated).
    method, train, guard, pfa, rank : keyword-only
        CFAR detector, training and guard cells on each side, false-alarm rate and OS rank
        (as :func:`simcore.dsp.cfar.cfar_1d`).
    n_integrated : int, keyword-only
        Independent looks averaged into each profile value (channels × chirps for noise;
        the Gamma(L) noise law of the threshold factor). Zero-padded Doppler bins are not
        independent: pass the number of chirps, not of Doppler bins.

    Returns
    -------
    ProfileCfar

    Examples
    --------
    One range bin 30 dB above a flat noise floor of 0 dB in every Doppler bin:

    >>> rd = np.zeros((4, 40))
    >>> rd[:, 20] = 30.0
    >>> res = range_profile_cfar(rd, method="ca", train=8, guard=2, pfa=1e-4)
    >>> np.flatnonzero(res.detections), round(float(res.profile_db[20]), 1)
    (array([20]), 30.0)
    """
    db = np.asarray(range_doppler_db, dtype=np.float64)
    power = processed_range_profile(10.0 ** (db / 10.0))
    res = cfar_1d(power, method=method, train=train, guard=guard, pfa=pfa, rank=rank,
                  n_integrated=max(int(n_integrated), 1))
    tiny = np.finfo(np.float64).tiny
    return ProfileCfar(
        profile_db=(10.0 * np.log10(np.maximum(power, tiny))).astype(np.float32),
        threshold_db=(10.0 * np.log10(np.maximum(res.threshold.astype(np.float64), tiny))
                      ).astype(np.float32),
        detections=np.asarray(res.detections, dtype=bool),
    )


__all__ = ["ProfileCfar", "processed_range_profile", "range_profile_cfar"]
