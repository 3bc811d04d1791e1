"""The numba baselines (scipy_numba_*) integrate the same hand-written physics as the numpy
ones: the compiled right-hand sides agree with them to round-off, and a whole stick-slip
run with the compiled sliding law gives the same phases and values."""
from __future__ import annotations

import numpy as np
import pytest

from benchmarks import baselines

pytest.importorskip("numba")


def test_compiled_right_hand_sides_match_numpy():
    rng = np.random.default_rng(7)
    coin = baselines.jitted(baselines.coin_derivatives)
    axle = baselines.jitted(baselines.axle_rhs)
    r, n = np.array([0.1, -0.2, 0.3]), np.array([0.0, 0.6, 0.8])
    for _ in range(20):
        y = rng.uniform(0.2, 1.2, 8)
        assert np.allclose(coin(y, 0.3, 0.05, 9.81), baselines.coin_derivatives(y, 0.3, 0.05, 9.81),
                           rtol=1e-13, atol=1e-13)
        args = (y[:2], 2.0, 0.3, r, n, np.cross(n, r), float(n @ r))
        assert np.allclose(axle(*args), baselines.axle_rhs(*args), rtol=1e-14, atol=0)


def test_compiled_stick_slip_run_matches_numpy():
    block = baselines.CoulombBlock(1.0, 10.0, 9.81, 0.3, 0.5, s_end=lambda t: 0.1 * t)
    times = np.arange(201) * 0.1
    plain = baselines.coulomb_block(block, 0.0, 0.0, times, "DOP853", 1e-8)
    jit = baselines.coulomb_block(block, 0.0, 0.0, times, "DOP853", 1e-8, jit_speed=0.1)
    assert plain[1:] == jit[1:]  # the same steps and evaluations: the same phases
    assert np.allclose(plain[0], jit[0], rtol=1e-12, atol=1e-14)
