"""CFAR detectors: thresholds against closed forms, measured false-alarm and detection rates.

Noise is complex Gaussian (power ~ exponential, or Gamma(L) after averaging L channels);
the target of the detection test is non-fluctuating (Swerling 0: constant amplitude,
random phase) at 15 dB SNR (target power / mean noise power in its cell).
"""

from __future__ import annotations

from math import comb

import numpy as np
import pytest

from simcore.dsp import cfar_1d, cfar_2d, cfar_threshold_factor, group_peaks
from simcore.dsp.cfar import os_rank, suppress_sidelobes

PFA = 1e-3
SHAPE = (1000, 1000)  # 10^6 cells


def noise_power(shape: tuple[int, int], *, seed: int, n_integrated: int = 1) -> np.ndarray:
    rng = np.random.default_rng(seed)
    acc = np.zeros(shape)
    for _ in range(n_integrated):
        z = (rng.standard_normal(shape) + 1j * rng.standard_normal(shape)) / np.sqrt(2)
        acc += np.abs(z) ** 2
    return acc / n_integrated


@pytest.mark.parametrize("pfa", [1e-3, 1e-6, 1e-9])
def test_threshold_factors_match_closed_forms(pfa: float) -> None:
    n = 16
    a, mean = cfar_threshold_factor("ca", n_training=n, pfa=pfa)
    assert (1 + a / n) ** -n == pytest.approx(pfa, rel=1e-6)
    assert mean == pytest.approx(1.0, rel=1e-9)
    n, k = 24, 18
    a, mean = cfar_threshold_factor("os", n_training=n, pfa=pfa, k=k)
    assert np.prod([(n - i) / (n - i + a) for i in range(k)]) == pytest.approx(pfa, rel=1e-6)
    assert mean == pytest.approx(sum(1 / i for i in range(n - k + 1, n + 1)), rel=1e-6)
    half = 8  # GO/SO: threshold alpha * max/min of the half means; t = alpha / half
    a_so, _ = cfar_threshold_factor("so", n_training=half, pfa=pfa)
    a_go, _ = cfar_threshold_factor("go", n_training=half, pfa=pfa)

    def so(t: float) -> float:
        return 2 * sum(comb(half - 1 + j, j) * (2 + t) ** -(half + j) for j in range(half))

    assert so(a_so / half) == pytest.approx(pfa, rel=1e-6)
    assert 2 * (1 + a_go / half) ** -half - so(a_go / half) == pytest.approx(pfa, rel=1e-6)
    # CA with L = 3 integrated channels (closed form of the Gamma-law CA-CFAR).
    big_l, n = 3, 16
    a, _ = cfar_threshold_factor("ca", n_training=n, pfa=pfa, n_integrated=big_l)
    closed = sum(comb(n * big_l + j - 1, j) * (a / n) ** j * (1 + a / n) ** -(n * big_l + j)
                 for j in range(big_l))
    assert closed == pytest.approx(pfa, rel=1e-6)


CASES = [
    ("ca", 1, 1), ("os", 1, 1), ("go", 1, 1), ("so", 1, 1),
    ("ca", 2, 1), ("os", 2, 1), ("os", 2, 3),
]


@pytest.mark.parametrize(("method", "dims", "n_integrated"), CASES)
def test_false_alarm_rate_on_a_million_noise_cells(method: str, dims: int,
                                                   n_integrated: int) -> None:
    power = noise_power(SHAPE, seed=100 + dims, n_integrated=n_integrated)
    if dims == 1:
        res = cfar_1d(power, method=method, train=8, guard=2, pfa=PFA,  # type: ignore[arg-type]
                      n_integrated=n_integrated, axis=-1)
    else:
        res = cfar_2d(power, method=method, train=(4, 8), guard=(1, 2),  # type: ignore[arg-type]
                      pfa=PFA, n_integrated=n_integrated, circular=(True, False))
    measured = float(np.mean(res.detections))
    print(f"{method}-{dims}D L={n_integrated}: requested {PFA:.1e}, measured {measured:.3e} "
          f"(ratio {measured / PFA:.2f}, N={res.n_training})")
    assert res.detections.size >= 1_000_000
    assert 0.5 * PFA <= measured <= 2.0 * PFA
    # The noise estimate is unbiased enough to call SNR from it.
    assert float(np.median(res.noise)) == pytest.approx(1.0, rel=0.15)


@pytest.mark.parametrize(("method", "dims"), [("ca", 1), ("os", 1), ("ca", 2), ("os", 2)])
def test_detection_probability_at_15_db_snr(method: str, dims: int) -> None:
    rng = np.random.default_rng(7)
    shape = (500, 1000)
    z = (rng.standard_normal(shape) + 1j * rng.standard_normal(shape)) / np.sqrt(2)
    spacing = 25  # > window extent (2 * (8 + 2) + 1 = 21 along range, 11 along Doppler)
    rows = np.arange(12, shape[0] - 12, spacing)
    cols = np.arange(12, shape[1] - 12, spacing)
    rr, cc = np.meshgrid(rows, cols, indexing="ij")
    snr = 10 ** (15 / 10)
    z[rr, cc] += np.sqrt(snr) * np.exp(2j * np.pi * rng.random(rr.shape))
    power = np.abs(z) ** 2
    pfa = 1e-4
    if dims == 1:
        res = cfar_1d(power, method=method, train=8, guard=2, pfa=pfa)  # type: ignore[arg-type]
    else:
        res = cfar_2d(power, method=method, train=(4, 8), guard=(1, 2),  # type: ignore[arg-type]
                      pfa=pfa)
    pd = float(np.mean(res.detections[rr, cc]))
    print(f"{method}-{dims}D: Pd at 15 dB = {pd:.3f} over {rr.size} targets (pfa {pfa:g})")
    assert rr.size >= 500
    assert pd >= 0.90


def test_os_rank_and_edges() -> None:
    assert os_rank(16, 0.75) == 12 and os_rank(16, 0.01) == 1 and os_rank(16, 1.0) == 16
    # A lone strong cell at the very edge of a non-circular axis is still detected
    # (mirrored training cells), and wraps around on a circular one.
    p = np.ones((8, 64))
    p[0, 0] = 1e4
    assert cfar_2d(p, method="ca", train=(2, 4), guard=(1, 1), pfa=1e-6).detections[0, 0]
    res = cfar_1d(p, method="os", train=4, guard=1, pfa=1e-6, axis=0, circular=True)
    assert res.detections[0, 0] and res.detections.sum() == 1


def test_peak_grouping_and_sidelobe_suppression() -> None:
    p = np.full((16, 32), 1e-9)
    p[8, 10] = 1.0
    p[7:10, 9:12] += 0.5  # spread of one target
    p[3, 10] = 1e-6 * 3  # a "sidelobe" 55 dB below, same range bin
    p[12, 25] = 0.2  # a second, weaker target elsewhere
    hits = p > 1e-6
    local = group_peaks(p, hits, method="local_max", neighbourhood=(3, 3))
    assert set(zip(*np.nonzero(local), strict=True)) == {(8, 10), (3, 10), (12, 25)}
    cluster = group_peaks(p, hits, method="cluster")
    assert set(zip(*np.nonzero(cluster), strict=True)) == {(8, 10), (3, 10), (12, 25)}
    assert group_peaks(p, hits, method="none").sum() == hits.sum()
    kept = suppress_sidelobes(p, local, axis=0, sidelobe_db=-60.0, margin_db=6.0)
    assert set(zip(*np.nonzero(kept), strict=True)) == {(8, 10), (12, 25)}
