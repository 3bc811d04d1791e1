"""The engine's Model Exchange master on foreign models that break its habits: stiff
kinetics the automatic method must notice in time, directional derivatives that lie,
outputs cached by the set calls, a stop time the output grid can miss.

Each model is a hand-written FMU (tests/handmade/me_*/), each result is checked
against an independent reference: scipy's implicit solvers, a closed form.
"""
import numpy as np
import pytest
from fmpy.validation import validate_fmu
from scipy.integrate import solve_ivp

from assemblies import FMU, Assembly, simulate_me

from handmade_fmus import handmade_fmu


def alone(name: str, instance: str, **values) -> Assembly:
    asm = Assembly(name)
    asm.add(instance, FMU(handmade_fmu(name), **values))
    return asm


# --- Robertson's kinetics ------------------------------------------------------------

def robertson(t, y):
    return [-0.04 * y[0] + 1e4 * y[1] * y[2],
            0.04 * y[0] - 1e4 * y[1] * y[2] - 3e7 * y[1] ** 2,
            3e7 * y[1] ** 2]


def robertson_jacobian(t, y):
    return [[-0.04, 1e4 * y[2], 1e4 * y[1]],
            [0.04, -1e4 * y[2] - 6e7 * y[1], -1e4 * y[1]],
            [0.0, 6e7 * y[1], 0.0]]


def test_robertson_fmu_is_valid():
    assert validate_fmu(str(handmade_fmu("me_robertson"))) == []


@pytest.mark.parametrize("tolerance", [1e-3, 1e-4, 1e-6])
def test_robertsons_kinetics_run_under_the_automatic_method(tolerance):
    """At a loose tolerance y2 (~3e-5) lies below the absolute tolerance: DOPRI5's
    stability-bound steps ring it negative within a few steps, where y2' = -3e7 y2^2
    runs away. Hairer's 15 votes came too late (the run died of a step underflow at
    t = 0.0087); the Jacobian's check after each vote switches to RODAS3 in time."""
    times = np.arange(0.0, 40.0 + 1e-9, 4.0)
    reference = solve_ivp(robertson, (0.0, 40.0), [1.0, 0.0, 0.0], method="Radau",
                          rtol=1e-10, atol=1e-14, jac=robertson_jacobian, t_eval=times).y
    # the published values at t = 40 (Hairer & Wanner), which scipy's reproduces
    assert reference[:, -1] == pytest.approx([0.7158, 9.185e-6, 0.2842], rel=2e-4)
    result = simulate_me(alone("me_robertson", "rob"), 40.0, 4.0, tolerance=tolerance)
    assert result.settings["method"] == "auto" and result.settings["method_switches"] >= 1
    np.testing.assert_allclose(result["time"], times, rtol=0, atol=1e-12)
    for k in range(3):
        # the solver's tolerance is relative and absolute alike; the global error stays
        # within a few local tolerances on this decaying problem
        np.testing.assert_allclose(result[f"rob.y{k + 1}"], reference[k], rtol=5 * tolerance,
                                   atol=tolerance)
