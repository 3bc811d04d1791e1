"""The engine's Model Exchange master on foreign models that break its habits: stiff
kinetics the automatic method must notice in time, directional derivatives that lie,
outputs cached by the set calls, a stop time the output grid can miss.

Each model is a hand-written FMU (tests/handmade/me_*/), each result is checked
against an independent reference: scipy's implicit solvers, a closed form.
"""
import json
import subprocess
import sys
import warnings

import numpy as np
import pytest
from fmpy.validation import validate_fmu
from scipy.integrate import solve_ivp

from assemblies import FMU, Assembly, AssemblyError, EngineError, simulate_me
from assemblies.engine import me as me_engine

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


@pytest.mark.parametrize("jacobian", ["auto", "fd"])
@pytest.mark.parametrize("tolerance", [1e-3, 1e-4, 1e-6])
def test_robertsons_kinetics_run_under_the_automatic_method(tolerance, jacobian):
    """At a loose tolerance y2 (~3e-5) lies below the absolute tolerance: DOPRI5's
    stability-bound steps ring it negative within a few steps, where y2' = -3e7 y2^2
    runs away. Hairer's 15 votes came too late (the run died of a step underflow at
    t = 0.0087); the Jacobian's check after each vote switches to RODAS3 in time."""
    times = np.arange(0.0, 40.0 + 1e-9, 4.0)
    reference = solve_ivp(robertson, (0.0, 40.0), [1.0, 0.0, 0.0], method="Radau",
                          rtol=1e-10, atol=1e-14, jac=robertson_jacobian, t_eval=times).y
    # the published values at t = 40 (Hairer & Wanner), which scipy's reproduces
    assert reference[:, -1] == pytest.approx([0.7158, 9.185e-6, 0.2842], rel=2e-4)
    result = simulate_me(alone("me_robertson", "rob"), 40.0, 4.0, tolerance=tolerance,
                         jacobian=jacobian)
    assert result.settings["method"] == "auto" and result.settings["method_switches"] >= 1
    np.testing.assert_allclose(result["time"], times, rtol=0, atol=1e-12)
    for k in range(3):
        # the solver's tolerance is relative and absolute alike; the global error stays
        # within a few local tolerances on this decaying problem
        np.testing.assert_allclose(result[f"rob.y{k + 1}"], reference[k], rtol=5 * tolerance,
                                   atol=tolerance)


# --- outputs an exporter computes in its set calls -----------------------------------

def test_cached_fmu_is_valid():
    assert validate_fmu(str(handmade_fmu("me_cached"))) == []


@pytest.mark.parametrize("method", ["auto", "DOPRI5", "RODAS3"])
def test_outputs_computed_in_set_time_alone_are_read_fresh_at_every_row(method):
    """me_cached computes its outputs in fmi2SetTime from the states it holds then: after
    time-then-states it reports the states of the point set before (the last stage).
    The rows set time and states once more before reading; pos = cos 2t exactly as
    the FMU whose outputs follow every call (cache_outputs = 0) gives it."""
    times = np.arange(0.0, 3.0 + 1e-9, 0.1)
    for cache in (1, 0):
        result = simulate_me(alone("me_cached", "osc", cache_outputs=cache), 3.0, 0.1,
                             tolerance=1e-8, method=method, record=["osc.pos", "osc.energy"])
        np.testing.assert_allclose(result["time"], times, rtol=0, atol=1e-12)
        np.testing.assert_allclose(result["osc.pos"], np.cos(2.0 * times), rtol=0, atol=1e-6)
        np.testing.assert_allclose(result["osc.energy"], 2.0, rtol=1e-6)


# --- the stop time's row -------------------------------------------------------------

@pytest.mark.parametrize("tolerance", [1e-10, 1e-11])
@pytest.mark.parametrize("record", [["osc.x", "osc.v"], ["osc.pos"]])
def test_the_stop_times_row_is_there_when_capped_steps_sum_short_of_it(tolerance, record):
    """An indicator that moves with time caps the steps at the output interval; 290
    steps of 0.01 summed from 0 end 4e-16 short of 2.9, which the loop took for the
    stop time: the run ended without the row at 2.9 (290 rows of 291), whether the rows
    come from the states alone (x, v) or from the FMU (pos)."""
    stop, step = 2.9, 0.01
    n = 291
    result = simulate_me(alone("me_cached", "osc", cache_outputs=0), stop, step,
                         tolerance=tolerance, record=record)
    t = result["time"]
    assert len(t) == n and t[-1] == stop
    np.testing.assert_allclose(result[record[0]], np.cos(2.0 * t), rtol=0, atol=1e-8)


# --- directional derivatives that lie ------------------------------------------------

def pair_closed_form(t, a=1.0, b=1000.0):
    return np.exp(-a * t), b / (b - a) * (np.exp(-a * t) - np.exp(-b * t))


def test_dd_fmu_is_valid():
    assert validate_fmu(str(handmade_fmu("me_dd"))) == []


@pytest.mark.parametrize("method", ["auto", "RODAS3"])
@pytest.mark.parametrize("dd_mode, why", [(1, "disagree with differences"), (2, "failed")])
def test_broken_directional_derivatives_are_caught_and_left_for_differences(method, dd_mode,
                                                                            why):
    """me_dd's d x2'/d x2 comes back +b instead of -b (dd_mode 1), or its call fails
    (2). The automatic choice compares them with central differences at t = 0, warns
    once naming the instance, and takes finite differences: the closed form to the
    tolerance. (Trusted, the wrong values make RODAS3 crawl: 199942 steps against 625.)"""
    with pytest.warns(me_engine.JacobianFallback) as caught:
        result = simulate_me(alone("me_dd", "pair", dd_mode=dd_mode), 2.0, 0.1,
                             tolerance=1e-8, method=method)
    assert len(caught) == 1
    line = str(caught[0].message)
    assert "\n" not in line and "pair: its directional derivatives" in line and why in line
    s = result.settings
    assert s["jacobian"] == "finite differences" and why in s["jacobian_note"]
    x1, x2 = pair_closed_form(result["time"])
    np.testing.assert_allclose(result["pair.x1"], x1, rtol=0, atol=1e-7)
    np.testing.assert_allclose(result["pair.x2"], x2, rtol=0, atol=1e-7)


def test_right_directional_derivatives_pass_the_probe_silently():
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        result = simulate_me(alone("me_dd", "pair", dd_mode=0), 2.0, 0.1, tolerance=1e-8)
    assert result.settings["jacobian"] == "directional derivatives"
    assert result.settings["jacobian_note"] is None
    x1, x2 = pair_closed_form(result["time"])
    np.testing.assert_allclose(result["pair.x2"], x2, rtol=0, atol=1e-7)


def test_the_jacobian_setting_forces_either():
    """'fd' never calls them; 'exact' trusts them without a probe, and a failing call
    then fails the run in one line naming the instance."""
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        fd = simulate_me(alone("me_dd", "pair", dd_mode=0), 2.0, 0.1, jacobian="fd")
        exact = simulate_me(alone("me_dd", "pair", dd_mode=1), 0.2, 0.1, jacobian="exact",
                            method="auto")
    assert fd.settings["jacobian"] == "finite differences"
    assert fd.settings["jacobian_setting"] == "fd"
    assert exact.settings["jacobian"] == "directional derivatives"
    with pytest.raises(EngineError) as failed:
        simulate_me(alone("me_dd", "pair", dd_mode=2), 2.0, 0.1, jacobian="exact",
                    method="RODAS3")
    message = str(failed.value)
    assert "\n" not in message and "pair" in message and "jacobian='exact'" in message
    with pytest.raises(AssemblyError, match="jacobian must be one of auto, fd, exact"):
        simulate_me(alone("me_dd", "pair"), 2.0, 0.1, jacobian="numeric")
    with pytest.raises(AssemblyError, match="jacobian='exact': osc's FMU gives no directional"):
        simulate_me(alone("me_cached", "osc"), 1.0, 0.1, jacobian="exact")


def test_the_command_line_takes_the_jacobian_setting(tmp_path):
    def mechfmu(*args):
        return subprocess.run([sys.executable, "-m", "assemblies.cli", *args],
                              capture_output=True, text=True, cwd=tmp_path)

    proc = mechfmu("run", "stick_slip", "--stop-time", "14", "--step", "0.5", "--mode", "me",
                   "--jacobian", "fd", "--out", str(tmp_path))
    assert proc.returncode == 0, proc.stderr
    settings = json.loads((tmp_path / "stick_slip.json").read_text())["settings"]
    assert settings["jacobian"] == "finite differences" and settings["jacobian_setting"] == "fd"
    proc = mechfmu("run", "stick_slip", "--engine", "fmpy", "--jacobian", "exact")
    lines = proc.stderr.strip().splitlines()
    assert proc.returncode != 0 and "Traceback" not in proc.stderr and len(lines) == 1
    assert "jacobian (--jacobian) applies to the compiled engine" in lines[0]


@pytest.mark.parametrize("method", ["DOPRI5", "RODAS3"])
def test_the_stop_times_row_is_there_after_an_event_a_sliver_before_it(method):
    """An event 3e-13 s before the stop time leaves a sliver the loop takes for the stop
    time (it is within its 1e-12 relative round-off): the row at the stop time comes
    from the states there, not never."""
    stop = 1.0
    result = simulate_me(alone("me_cached", "osc", cache_outputs=0, t_cross=stop - 3e-13),
                         stop, 0.1, tolerance=1e-10, method=method, record=["osc.pos"])
    t = result["time"]
    assert len(t) == 11 and t[-1] == stop
    np.testing.assert_allclose(result["osc.pos"], np.cos(2.0 * t), rtol=0, atol=1e-8)
    events = result.events["osc"]["time"]
    assert len(events) == 1 and stop - 1e-12 < events[0] < stop


def test_only_foreign_fmus_pay_for_the_distrust():
    """Our own FMUs' outputs follow every set call and their directional derivatives are
    CasADi's: no probe, no second set before a row (the non-stiff scenes keep their
    cost); a foreign one gets both."""
    from assemblies.engine.prepare import prepared, prepared_path
    from components import SpringBlock
    assert prepared(SpringBlock(), 3).ours
    assert not prepared_path(str(handmade_fmu("me_dd"))).ours
