"""Seed 9.4: dry-friction damping, amplitudes falling by 2 mu m g / k per half period."""
import math

import pytest
from scipy.integrate import solve_ivp

from assemblies import run_scene

SEED_TURNING_POINTS = [6.55, -5.35, 4.15, -2.95, 1.75, -0.55]  # printed in 9.4


def _figures(res):
    return {f.name: f for f in res.figures}


def test_coulomb_turning_points_and_final_stick():
    res = run_scene("friction_damping", stop_time=25.0, step=0.1)
    figures = _figures(res)
    for n, amplitude in enumerate(SEED_TURNING_POINTS):
        assert abs(figures[f"A{n}"].measured - amplitude) < 1e-6
        if n:
            assert abs(figures[f"t_A{n}"].measured - n * math.pi) < 1e-6
    # stuck at -0.55 for good: no event after 5 pi, and the position never moves again
    assert max(res.events["block"]["time"]) < 5 * math.pi + 1e-6
    late = res["time"] > 5 * math.pi + 1e-6
    assert abs(res["block.x"][late] + 0.55).max() < 1e-6
    assert (res["block.v"][late] == 0.0).all()
    assert all(f.passed for f in res.figures), res.figures


@pytest.mark.parametrize("step", [1.0, 5.0])
def test_coulomb_is_step_independent(step):
    figures = _figures(run_scene("friction_damping", stop_time=20.0, step=step))
    for n, amplitude in enumerate(SEED_TURNING_POINTS):
        assert abs(figures[f"A{n}"].measured - amplitude) < 1e-6


def smooth_law_turning_points(law, eps, t_end, m=1.0, k=1.0, g=1.0, mu=0.6, x0=6.55):
    """(t, x) where x' = 0 for the block under a smooth law with mu_s = mu_k (Eq. 9.5 is
    then Eq. 9.7, mu tanh(3 x' / eps)), solved here by solve_ivp to 1e-12 with its own
    event location: an independent reference for the smooth model itself."""
    def rhs(t, y):
        return [y[1], (-k * y[0] - mu * m * g * math.tanh(3 * y[1] / eps)) / m]

    def rest(t, y):
        return y[1]
    sol = solve_ivp(rhs, (0.0, t_end), [x0, 0.0], method="DOP853", events=rest,
                    rtol=1e-12, atol=1e-14)
    # the release itself is a zero of x' at t = 0 (solve_ivp may report it or not)
    return [(0.0, x0)] + [(t, y[0]) for t, y in zip(sol.t_events[0], sol.y_events[0])
                          if t > 1e-9]


@pytest.mark.parametrize("law", ["tanh", "smooth"])
@pytest.mark.parametrize("mode", ["cosim", "me", "monolithic"])
def test_smooth_laws_pass_every_figure_in_every_mode(law, mode):
    """README's snippet: run_scene("friction_damping", params={"block.friction": "tanh"})
    passes every figure against exact Coulomb, in every mode, because the turning points
    are located (their error is the solver's plus the law's own, stated difference)."""
    res = run_scene("friction_damping", mode=mode, params={"block.friction": law})
    failed = [(f.name, f.error, f.bound) for f in res.figures if not f.passed]
    assert len(res.figures) == 12 and not failed, failed


@pytest.mark.parametrize("step", [0.1, 1.0])
def test_turning_point_times_are_located_not_sampled(step):
    """Under the tanh law the block never stops, so no event lies at x' = 0: the turning
    points must still come out to the solver's accuracy, whatever the output step (a
    value read off the grid errs by up to a step; a located one by ~tolerance)."""
    res = run_scene("friction_damping", stop_time=16.0, step=step,
                    params={"block.friction": "tanh", "block.eps": 1e-3})
    figures = _figures(res)
    exact = smooth_law_turning_points("tanh", 1e-3, 16.0)
    assert len(exact) >= 6
    for n, (t, x) in enumerate(exact[:6]):
        if n:
            assert abs(figures[f"t_A{n}"].measured - t) < 1e-7, n  # 1e-6 of the step and less
        assert abs(figures[f"A{n}"].measured - x) < 1e-8, n
        # and the law's difference from Coulomb's, which the figures allow for, is real:
        # the located times differ from n pi by more than the solver's error
    assert abs(figures["t_A5"].measured - 5 * math.pi) > 1e-6
    assert all(f.passed for f in res.figures), [(f.name, f.error, f.bound) for f in res.figures]


@pytest.mark.parametrize("mode", ["cosim", "me", "monolithic"])
def test_tanh_law_passes_every_figure_with_the_fmpy_engine(mode):
    res = run_scene("friction_damping", mode=mode, engine="fmpy",
                    params={"block.friction": "tanh"})
    failed = [(f.name, f.error, f.bound) for f in res.figures if not f.passed]
    assert len(res.figures) == 12 and not failed, failed
