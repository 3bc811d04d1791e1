"""Seed 9.4: dry-friction damping, amplitudes falling by 2 mu m g / k per half period."""
import math

import pytest

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


def test_tanh_law_matches_to_plotting_accuracy():
    res = run_scene("friction_damping", stop_time=17.0, step=0.05,
                    params={"block.friction": "tanh", "block.eps": 1e-3})
    figures = _figures(res)
    for n, amplitude in enumerate(SEED_TURNING_POINTS):
        assert abs(figures[f"A{n}"].measured - amplitude) < 1e-2
        if n:
            assert abs(figures[f"t_A{n}"].measured - n * math.pi) < 1e-2
