"""The extrapolation a held input's step mean comes from, evaluated at the step's end
(assemblies.masters.extrapolation.end_value; cosim.c held_end_value): what the
coupling defect compares with the source's value there. Against the polynomials
themselves, on unevenly spaced points as adaptive steps leave them."""
import pytest

from assemblies.masters.extrapolation import end_value, step_mean


def _quadratic(t):
    return 0.3 - 1.7 * t + 2.5 * t * t


POINTS = [(t, _quadratic(t)) for t in (0.9, 1.25, 1.3)]


@pytest.mark.parametrize("h", [1e-3, 0.05, 0.7])
def test_order_two_reproduces_a_quadratic_at_the_end_of_any_step(h):
    assert end_value(POINTS, h, 2) == pytest.approx(_quadratic(1.3 + h), rel=1e-12, abs=1e-12)


def test_lower_orders_use_the_last_points_only():
    # order 1: the line through the last two points; order 0: the last value held
    (t1, y1), (t2, y2) = POINTS[-2:]
    line = y2 + (y2 - y1) / (t2 - t1) * 0.2
    assert end_value(POINTS, 0.2, 1) == pytest.approx(line, rel=1e-12)
    assert end_value(POINTS, 0.2, 0) == y2
    assert end_value(POINTS[-1:], 0.2, 2) == y2  # a first step: one point, held


def test_the_step_mean_is_the_same_polynomials_mean():
    # (the refactoring shares the fit: the mean of a quadratic over [t, t + h])
    t, h = 1.3, 0.4
    exact = (0.3 * h - 1.7 * ((t + h) ** 2 - t ** 2) / 2 + 2.5 * ((t + h) ** 3 - t ** 3) / 3) / h
    assert step_mean(POINTS, t, h, 2) == pytest.approx(exact, rel=1e-12)
