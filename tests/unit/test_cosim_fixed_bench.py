"""benchmarks/cosim_fixed.py: the fixed-step cost at a given error and the ratio ranges.

Fixed steps of a method of order p have error C h^p and cost K / h, so between two
measured runs the cost at an error is a power law in it: the interpolation must give
that power law exactly, and nothing outside the runs measured.
"""
import math

from benchmarks.cosim_fixed import fixed_cost_at, ratio_range


def _fixed(h, order=2, c=3.0, k=0.01):
    return {"mode": "fixed", "error": c * h**order, "cpu_s": k / h}


def test_the_fixed_cost_at_an_error_follows_the_power_law_between_runs():
    records = [_fixed(h) for h in (0.1, 0.05, 0.025)] + [{"mode": "cosim", "error": 1e-9,
                                                        "cpu_s": 1.0}]
    h = 0.07  # between the first two runs
    assert math.isclose(fixed_cost_at(records, 3.0 * h**2), 0.01 / h, rel_tol=1e-12)
    assert math.isnan(fixed_cost_at(records, 3.0 * 0.2**2))    # coarser than every run
    assert math.isnan(fixed_cost_at(records, 3.0 * 0.01**2))   # finer than every run


def test_a_ratio_range_is_the_extremes_over_the_repeats():
    a, b = {"cpu_s": 2.0, "cpu_samples": [1.8, 2.0, 2.4]}, {"cpu_s": 1.0, "cpu_samples": [0.9, 1.2]}
    assert ratio_range(a, b) == (1.8 / 1.2, 2.4 / 0.9)
