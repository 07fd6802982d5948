"""ToF–ToF interference against a four-phase correlation integrated numerically here.

Two AMCW cameras side by side (10 cm apart) face a wall 2 m away. The victim pixel looking
straight at the wall receives its own light over 2·D and the aggressor's over
√(D² + b²) + D. The reference: the four phase images ``I_k = (1/T) ∫ L(t) cos(2π f_v t −
kπ/2) dt`` of the received light ``L(t)`` summed on a fine time grid, and the phasor
``Σ_k I_k e^{jkπ/2}``: independent of the closed form in the module.
"""

from __future__ import annotations

import numpy as np
import pytest

from simcore.scene.tof_config import SPEED_OF_LIGHT
from simcore.sensors.tof.interference import (
    cross_correlation_factor,
    extra_shot_noise_variance,
    interfered_phasor,
    phasor_depth_m,
)

D, B, F_V, T = 2.0, 0.1, 20e6, 1e-6
OWN_PATH, AGG_PATH = 2 * D, np.hypot(D, B) + D


def four_phase(f_a: float, theta: float, overlap: float, a_own: float = 1.0,
               a_agg: float = 0.8) -> complex:
    t = (np.arange(200_000) + 0.5) * (T / 200_000)
    light = a_own * (1 + np.cos(2 * np.pi * F_V * (t - OWN_PATH / SPEED_OF_LIGHT)))
    on = t < overlap * T
    light = light + on * a_agg * (1 + np.cos(2 * np.pi * f_a * (t - AGG_PATH / SPEED_OF_LIGHT)
                                             - theta))
    psi = np.arange(4) * np.pi / 2
    i_k = [np.mean(light * np.cos(2 * np.pi * F_V * t - p)) for p in psi]
    return complex(np.sum(np.array(i_k) * 2 * np.exp(1j * psi)) / 2)


@pytest.mark.parametrize(("f_a", "theta", "overlap"), [
    (F_V, 0.0, 1.0), (F_V, 1.3, 1.0), (F_V + 1e6, 0.4, 1.0), (F_V + 0.37e6, 0.0, 1.0),
    (F_V, 0.7, 0.0), (F_V, 0.7, 0.5)])
def test_phasor_matches_the_four_phase_correlation(f_a: float, theta: float,
                                                   overlap: float) -> None:
    ref = four_phase(f_a, theta, overlap)
    got = interfered_phasor(1.0, OWN_PATH, 0.8, AGG_PATH, victim_frequency_hz=F_V,
                            aggressor_frequency_hz=f_a, exposure_s=T,
                            aggressor_phase_rad=theta, overlap_fraction=overlap)
    # The closed form drops the sum-frequency term, bounded by A_a / (π (f_a + f_v) T)
    # (zero when (f_a + f_v) T is an integer).
    assert abs(complex(got) - ref) < 1e-3 * abs(ref) + 0.8 / (np.pi * (f_a + F_V) * T)


def test_same_frequency_biases_depth_other_frequency_and_multiplexing_do_not() -> None:
    def depth(f_a: float, overlap: float) -> float:
        return float(phasor_depth_m(interfered_phasor(
            1.0, OWN_PATH, 0.8, AGG_PATH, victim_frequency_hz=F_V, aggressor_frequency_hz=f_a,
            exposure_s=T, aggressor_phase_rad=1.0, overlap_fraction=overlap), F_V))
    same, other, mux = depth(F_V, 1.0), depth(F_V + 1e6, 1.0), depth(F_V, 0.0)
    print(f"depth at {D} m: same frequency {same:.4f} m, Δf = 1 MHz {other:.4f} m, "
          f"multiplexed {mux:.4f} m")
    assert abs(same - D) > 0.1
    assert abs(other - D) < 1e-9 and abs(mux - D) < 1e-9
    # Non-integer Δf·T: the cross term is bounded by 1 / (π Δf T).
    c = cross_correlation_factor(F_V, F_V + 10.37e6, exposure_s=T)
    assert abs(c) <= 1 / (np.pi * 10.37) + 1e-12
    assert extra_shot_noise_variance(5.0, overlap_fraction=0.0) == 0.0
    assert extra_shot_noise_variance(5.0) == 5.0
