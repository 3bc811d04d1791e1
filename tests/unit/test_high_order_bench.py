"""benchmarks/high_order.py's interpolation: evaluations for an error between two
tolerances, exact on a power law (a method of order p costs ~ error^(-1/p)), and none
outside the curve."""
import pytest

from benchmarks.high_order import evaluations_at


def test_a_power_law_is_interpolated_exactly():
    cost = lambda e: 100.0 * e ** (-1 / 5)  # noqa: E731  order 5: cost ~ error^(-1/5)
    points = [(tol, 10 * tol, cost(10 * tol)) for tol in (1e-4, 1e-6, 1e-8)]
    for error in (3e-4, 1e-5, 2.5e-7, 1e-7):
        assert evaluations_at(points, error) == pytest.approx(cost(error), rel=1e-12)


def test_an_error_outside_the_curve_has_no_count():
    points = [(1e-4, 1e-3, 100), (1e-6, 1e-5, 300)]
    assert evaluations_at(points, 1e-2) is None
    assert evaluations_at(points, 1e-6) is None
