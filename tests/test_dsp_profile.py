"""The GUI's processed range profile and its 1-D CFAR threshold (simcore.dsp.profile)."""

import numpy as np
import pytest
from numpy.testing import assert_allclose, assert_array_equal

from simcore.dsp.profile import processed_range_profile, range_profile_cfar


def test_profile_is_the_mean_power_over_doppler():
    rd = np.array([[1.0, 10.0, 100.0], [3.0, 30.0, 0.0]])
    assert_allclose(processed_range_profile(rd), [2.0, 20.0, 50.0])
    with pytest.raises(ValueError, match="doppler, range"):
        processed_range_profile(np.ones(3))


def test_a_target_above_the_floor_is_the_only_hit_and_the_threshold_is_alpha_times_noise():
    rd_db = np.zeros((16, 64))
    rd_db[:, 30] = 20.0
    res = range_profile_cfar(rd_db, method="ca", train=8, guard=2, pfa=1e-4)
    assert_array_equal(np.flatnonzero(res.detections), [30])
    # Flat unit noise: CA threshold = alpha · 1 with alpha = N (pfa^(-1/N) − 1), N = 16.
    alpha = 16 * (1e-4 ** (-1 / 16) - 1)
    assert_allclose(res.threshold_db[10], 10 * np.log10(alpha), atol=1e-4)
    assert_allclose(res.profile_db[30], 20.0, atol=1e-5)


def test_false_alarm_rate_on_integrated_noise_matches_the_request():
    rng = np.random.default_rng(7)
    looks, pfa = 8, 1e-2
    # Each Doppler row an independent exponential look: the profile is Gamma(looks).
    power = rng.exponential(size=(looks, 200_000))
    res = range_profile_cfar(10 * np.log10(power), method="ca", train=16, guard=2, pfa=pfa,
                             n_integrated=looks)
    rate = res.detections[40:-40].mean()
    assert 0.6 * pfa < rate < 1.5 * pfa
