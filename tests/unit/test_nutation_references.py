"""nutation_references: the nutation damper's excess energy, its ripple series and the
linear motion, checked against their definitions (no run)."""
import math

import numpy as np
import pytest

from assemblies.scenes.nutation_references import (excess_energy, excess_form, linear_system,
                                                   nutation, ripple_tail, transverse_state)

I, J, C = (1.0, 2.0, 3.0), 0.5, 0.5


@pytest.mark.parametrize("rho, harmonics", [(0.015, 1), (0.015, 3), (0.3, 2), (0.8, 5)])
def test_ripple_tail_bounds_the_truncated_series_and_is_not_loose(rho, harmonics):
    theta = np.linspace(0, 2 * math.pi, 20001)
    s = math.sqrt(1 - rho**2)
    q = rho / (1 + s)
    series = np.log((1 + s) / 2) + sum(2 * (-1) ** (k + 1) * q**k * np.cos(k * theta) / k
                                       for k in range(1, harmonics + 1))
    left = np.abs(np.log1p(rho * np.cos(theta)) - series).max()
    assert left <= ripple_tail(rho, harmonics) <= 2 * left + 1e-15


@pytest.mark.parametrize("major", [0, 2])
def test_excess_energy_is_t_minus_the_least_energy_the_momentum_allows(major):
    rng = np.random.default_rng(7)
    moments = np.array(I) if major == 2 else np.array(I[::-1])
    w, sigma = rng.normal(size=(50, 3)), rng.normal(size=(50, 3))
    h = moments * w + J * (w + sigma)
    T = ((moments * w * w).sum(axis=1) + J * ((w + sigma) ** 2).sum(axis=1)) / 2
    least = (h**2).sum(axis=1) / (2 * (moments[major] + J))
    np.testing.assert_allclose(excess_energy(moments, J, major, w, h), T - least, rtol=1e-12)
    # without the sphere's axial slip the excess is the transverse form y^T Q y
    sigma[:, major] = 0.0
    h = moments * w + J * (w + sigma)
    y = transverse_state(major, w, h, moments, J)
    Q = excess_form(moments, J, major)
    np.testing.assert_allclose(np.einsum("ij,jk,ik->i", y, Q, y),
                               excess_energy(moments, J, major, w, h), rtol=1e-10)


def test_nutation_ripple_ratio_is_that_of_the_linear_motion():
    """dT on the slow pair alone swings between a (1 - rho) and a (1 + rho) times its
    exponential: integrate the linear system from the slow eigenvector and compare."""
    from scipy.linalg import expm
    H = 1.5
    lin = nutation(I, J, C, H, 2)
    M, A = linear_system(I, J, C, H, 2)
    G = np.linalg.solve(M, A)
    lam, vec = np.linalg.eig(G)
    v = vec[:, np.argmax(lam.real)]
    y0 = (v + v.conj()).real
    Q = excess_form(I, J, 2)
    t = np.linspace(0, math.pi / lin.omega, 2001)
    dT = np.array([(expm(G * s) @ y0) @ Q @ (expm(G * s) @ y0) for s in t]) * np.exp(2 * lin.rate * t)
    assert (dT.max() - dT.min()) / (dT.max() + dT.min()) == pytest.approx(lin.rho, rel=1e-6)
