"""Our FMUs in fmpy's own simulate_fmu, Model Exchange (CVode) and Co-Simulation."""
import math

import numpy as np
import pytest

from components import SpringBlock

from conftest import FRICTION_DAMPING_TURNING, exact_friction_damping, simulate_in_fmpy

TURNING = FRICTION_DAMPING_TURNING


def _damping_block():
    return SpringBlock(m=1, k=1, g=1, mu_k=0.6, mu_s=0.6, x=6.55)


@pytest.mark.parametrize("fmi_type, atol", [("CoSimulation", 1e-8), ("ModelExchange", 1e-6)])
def test_friction_damping_in_fmpy(fmi_type, atol):
    res = simulate_in_fmpy(_damping_block(), fmi_type, stop_time=18.0, output_interval=0.01,
                           output=["x", "v", "mode"])
    t, x = res["time"], res["x"]
    assert np.abs(x - exact_friction_damping(t)).max() < atol
    late = t > 5 * math.pi + 0.05
    assert np.all(res["mode"][late] == 0) and np.all(res["v"][late] == 0.0)


def test_model_exchange_locates_turning_points_as_events():
    res = simulate_in_fmpy(_damping_block(), "ModelExchange", stop_time=18.0, output_interval=0.5,
                           output=["x", "mode"])
    t, x = res["time"], res["x"]
    # fmpy records a row before and after every event; the events are the turning points
    duplicates = [i for i in range(1, len(t)) if t[i] == t[i - 1]]
    event_times = sorted({t[i] for i in duplicates})
    np.testing.assert_allclose(event_times, [math.pi * n for n in range(1, 6)], atol=1e-6)
    np.testing.assert_allclose([x[i] for i in duplicates], TURNING[1:], atol=1e-6)
