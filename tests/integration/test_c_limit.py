"""c_limit, the benchmark floor (benchmarks/c_limit.c): the generated model under the
runtime's DOPRI5 and event location with nothing around it must still be right, or the
ratios measured against it mean nothing. Checked against the seed's closed forms."""
from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.interpolate import CubicHermiteSpline
from scipy.special import ellipk

from assemblies.masters.monolithic import composite
from assemblies.scenes import scene
from assemblies.scenes.references import friction_damping_turning_points, stick_slip_first_cycle
from benchmarks import analysis
from benchmarks.c_limit import CLimit
from benchmarks.references import axle_inertia, axle_potential


def _mode_changes(events, mode):
    """(t, row index) of the located events after which `mode` differs from before."""
    changes, previous = [], 0.0
    for i, (t, q) in enumerate(zip(events["time"], events[mode])):
        if q != previous:
            changes.append(i)
        previous = q
    return changes


def test_stick_slip_first_cycle_matches_the_seed():
    asm = scene("stick_slip").build()
    p, v = asm.component("block").values, asm.component("driver").values["v"]
    t1, t2, x2 = stick_slip_first_cycle(p["m"], p["k"], p["g"], p["mu_k"], p["mu_s"], v)
    assert abs(t1 - 8.0) < 1e-12 and abs(t2 - 12.06888787) < 1e-8  # seed 9.2
    limit = CLimit(composite(asm), "block.x")
    values, work, events = limit.run(np.array([0.0, 4.0, t2, 20.0]), 1e-10, max_events=8)
    slip, stick = _mode_changes(events, "block.mode")[:2]
    assert events["block.mode"][slip] != 0 and events["block.mode"][stick] == 0
    assert abs(events["time"][slip] - t1) < 1e-8
    assert abs(events["time"][stick] - t2) < 1e-8
    assert abs(events["block.x"][stick] - x2) < 1e-8
    assert abs(values[2, 0] - x2) < 1e-8        # sampled at t2 from the dense output
    assert values[1, 0] == 0.0                  # stuck at rest until t1
    assert work["steps"] < 1000                 # free steps: none forced by the outputs


def test_friction_damping_turning_points():
    asm = scene("friction_damping").build()
    p, x0 = asm.component("block").values, asm.component("block").starts["x"]
    reference = friction_damping_turning_points(p["m"], p["k"], p["g"], p["mu_k"], x0)
    limit = CLimit(composite(asm), "block.x")
    times = np.linspace(0.0, 20.0, 201)
    values, _, events = limit.run(times, 1e-10, max_events=20)
    turns = _mode_changes(events, "block.mode")
    assert len(turns) == len(reference) - 1  # every turning point after the start, no more
    for i, (t_ref, x_ref) in zip(turns, reference[1:]):
        assert abs(events["time"][i] - t_ref) < 1e-8
        assert abs(events["block.x"][i] - x_ref) < 1e-8
    # stuck for good at the last turning point
    assert np.all(np.abs(values[times > reference[-1][0] + 1e-6, 0] - reference[-1][1]) < 1e-8)


def test_axle_pendulum_period_is_the_elliptic_integral():
    body = scene("axle_pendulum").build().component("body")
    p = body.values
    r, n = (p["r_x"], p["r_y"], p["r_z"]), (p["n_x"], p["n_y"], p["n_z"])
    I_cm = [[p["I_xx"], p["I_xy"], p["I_xz"]], [p["I_xy"], p["I_yy"], p["I_yz"]],
            [p["I_xz"], p["I_yz"], p["I_zz"]]]
    rho, delta = axle_potential(p["m"], p["g"], r, n)
    omega0 = math.sqrt(rho / axle_inertia(p["m"], I_cm, r, n))
    theta_eq = math.remainder(delta + math.pi, 2 * math.pi)
    amplitude = abs(body.starts["theta"] - theta_eq)
    period = 4 * ellipk(math.sin(amplitude / 2) ** 2) / omega0   # scipy's ellipk takes m = k^2

    limit = CLimit(body, ["theta", "omega"])
    times = np.linspace(0.0, 3.5 * period, 4001)
    values, _, _ = limit.run(times, 1e-11)
    # upward crossings of the equilibrium, on the cubic Hermite fit of (theta, omega)
    spline = CubicHermiteSpline(times, values[:, 0] - theta_eq, values[:, 1])
    ups = [t for t in spline.roots(extrapolate=False) if spline(t, 1) > 0]
    assert len(ups) == 3
    for a, b in zip(ups, ups[1:]):
        assert abs((b - a) - period) < 1e-8 * period
    # the swing keeps its amplitude: the largest excursion is the start
    assert abs(np.max(np.abs(values[:, 0] - theta_eq)) - amplitude) < 1e-6


def test_target_ratio_interpolates_on_the_work_precision_curve():
    """Wall at error 1e-6, interpolated log-log between the two tolerances that bracket it:
    errors 1e-5 and 1e-7 at 1 ms and 4 ms put 1e-6 at their geometric mean, 2 ms."""
    def rec(method, tol, error, wall):
        return dict(scene="stick_slip", method=method, tolerance=tol, error=error, wall_s=wall,
                    rhs_evals=None, steps=None)
    records = [rec("c_limit", 1e-6, 1e-5, 1e-3), rec("c_limit", 1e-8, 1e-7, 4e-3),
               rec("engine_me", 1e-6, 1e-5, 2e-3), rec("engine_me", 1e-8, 1e-7, 8e-3),
               rec("scipy_LSODA", 1e-6, 1e-7, 0.5), rec("scipy_LSODA", 1e-8, 1e-9, 0.9)]
    assert math.isclose(analysis.wall_at_error(records, "stick_slip", "c_limit"), 2e-3)
    assert analysis.wall_at_error(records, "stick_slip", "scipy_LSODA") == 0.5
    public, scipy = analysis.limit_targets(records)
    assert public["target"] == "public/c_limit" and math.isclose(public["ratio"], 2.0)
    assert public["met"] and public["note"] is None
    assert math.isclose(scipy["ratio"], 0.5 / 4e-3) and scipy["met"]


def test_bad_column_is_refused_by_name():
    with pytest.raises(KeyError, match="'nope' is not a state or output"):
        CLimit(scene("axle_pendulum").build().component("body"), "nope")


def test_a_model_that_ends_its_run_stops_there():
    """A mass dropped from 2 m ends the run on the ground at t = sqrt(2 h / g): the rows
    after that are NaN, the ones before follow h = 2 - g t^2 / 2."""
    from conftest import drop_component

    drop = drop_component()(name="drop")
    limit = CLimit(drop, "h")
    times = np.linspace(0.0, 1.0, 101)
    values, _, events = limit.run(times, 1e-10, max_events=4)
    t_ground = math.sqrt(2 * 2.0 / 9.81)
    assert abs(events["time"][0] - t_ground) < 1e-9
    before = times < t_ground
    assert np.allclose(values[before, 0], 2.0 - 9.81 * times[before] ** 2 / 2, atol=1e-9)
    assert np.all(np.isnan(values[times > t_ground, 0]))
