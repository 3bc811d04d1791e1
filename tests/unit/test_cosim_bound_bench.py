"""benchmarks/cosim_bound.py: the equidistribution bound's arithmetic against cases with
a known answer (a constant local error density; a two-piece density minimised by brute
force), and the density recovered from a run whose error grows by a known law."""
import math

import numpy as np
import pytest
from scipy.optimize import minimize_scalar

from benchmarks.cosim_bound import (equidistributed_steps, local_error_density,
                                    order_fit)


@pytest.mark.parametrize("p", [1.0, 2.0, 3.0])
def test_a_constant_density_needs_exactly_the_uniform_steps(p):
    c, T, err = 4.0e-3, 20.0, 1e-6
    h_uniform = (err / (c * T)) ** (1.0 / p)       # C T h^p = err
    dt = np.full(50, T / 50)
    assert math.isclose(equidistributed_steps(np.full(50, c), dt, p, err), T / h_uniform,
                        rel_tol=1e-12)


def test_a_two_piece_density_needs_the_fewest_steps_any_two_step_sizes_can_take():
    # C1 on [0, T1], C2 on [T1, T1 + T2]: every pair (h1, h2) spending the error budget
    # exactly; the least T1/h1 + T2/h2 found by a scalar search must equal the formula
    p, c1, c2, t1, t2, err = 2.0, 1.0, 1e-3, 2.0, 8.0, 1e-6

    def steps(log_h1):
        h1 = math.exp(log_h1)
        left = err - c1 * t1 * h1 ** p
        if left <= 0:
            return math.inf
        h2 = (left / (c2 * t2)) ** (1.0 / p)
        return t1 / h1 + t2 / h2
    best = minimize_scalar(steps, bounds=(math.log(1e-8), math.log((err / (c1 * t1)) ** 0.5) - 1e-9),
                           method="bounded", options={"xatol": 1e-12})
    formula = equidistributed_steps([c1, c2], [t1, t2], p, err)
    assert math.isclose(formula, best.fun, rel_tol=1e-6)
    # and it is fewer than uniform steps spending the same budget
    uniform = (t1 + t2) / (err / (c1 * t1 + c2 * t2)) ** (1.0 / p)
    assert formula < 0.5 * uniform


def test_the_density_is_recovered_from_an_error_growing_by_a_known_law():
    h, p = 1e-3, 2.0
    t = np.linspace(0.0, 10.0, 101)
    density = 1.0 + np.sin(t[:-1]) ** 2          # C_j per interval
    error = np.concatenate([[0.0], np.cumsum(density * h ** p * np.diff(t))])
    error[60:] *= -1                             # a sign flip keeps |error|'s envelope...
    c, dt = local_error_density(t, np.abs(error), h, p)
    assert np.allclose(c, density, rtol=1e-12)
    drop = np.abs(error).copy()
    drop[40:45] = 0.0                            # ...an error that falls adds nothing
    c, _ = local_error_density(t, drop, h, p)
    assert np.all(c >= 0) and np.all(c[39:44] == 0.0)


def test_the_order_is_the_slope_of_log_error_against_log_h():
    hs = np.array([0.1, 0.05, 0.025, 0.0125])
    assert math.isclose(order_fit(hs, 3.0 * hs ** 2.0), 2.0, rel_tol=1e-12)


def test_bad_arguments_are_refused():
    with pytest.raises(ValueError, match="p > 0"):
        equidistributed_steps([1.0], [1.0], 0.0, 1e-6)
    with pytest.raises(ValueError, match="C >= 0"):
        equidistributed_steps([-1.0], [1.0], 2.0, 1e-6)
