"""The compiled engine's Model Exchange and monolithic modes (engine="c").

Checked against the fmpy-driven reference masters (different solvers: DOP853 / scipy
there, the runtime's DOPRI5 here), against exact piecewise solutions (seed 9.2 and 9.4,
and a block on a shaking table whose reverse slip is shorter than a solver step), and
FMI 2 against FMI 3.
"""
import math
import os
import signal

import numpy as np
import pytest
from scipy.optimize import brentq

from assemblies import Assembly, AssemblyError, SimulationError
from assemblies.engine.me import simulate_me, simulate_monolithic
from assemblies.masters.me import simulate_me as fmpy_simulate_me
from assemblies.masters.monolithic import simulate_monolithic as reference_monolithic
from assemblies.run import run_scene_full
from assemblies.scenes import scene
from assemblies.scenes.table import PERIOD
from components import ConstantSpeed, SpringBlock
from components.sources.motion import SineMotion

from conftest import SEED_94, SEED_94_SPEED, coulomb_drag_reference, exact_friction_damping

# (scene, stop time): long enough for several friction events each, short for fmpy
SHORT = {"stick_slip": 14.0, "friction_damping": 10.0, "moving_table": 6 * PERIOD,
         "two_block_belt": 8.0}


def _run(name, master, tolerance, **kw):
    sc = scene(name)
    stop = SHORT[name]
    return master(sc.build(), stop, stop / 40, tolerance, record=sc.record, **kw)


def _assert_same(engine, reference, tolerance):
    assert engine.columns == reference.columns
    scale = max(1.0, max(float(np.max(np.abs(reference[c]))) for c in reference.columns))
    for c in reference.columns:
        if c.endswith(".mode"):
            np.testing.assert_array_equal(engine[c], reference[c], err_msg=c)
        else:
            np.testing.assert_allclose(engine[c], reference[c], rtol=0,
                                       atol=100 * tolerance * scale, err_msg=c)


@pytest.mark.parametrize("name", list(SHORT))
def test_me_equals_the_fmpy_me_master(name):
    tol = 1e-9
    engine = _run(name, simulate_me, tol)
    reference = _run(name, fmpy_simulate_me, tol)
    assert engine.settings["engine"] == "c" and engine.settings["scheme"] == "me"
    assert engine.settings["events"] >= 2
    _assert_same(engine, reference, tol)
    # the same instances report events, at the same times (the fmpy master may report one
    # event twice where an indicator restarts at zero: compare the distinct times)
    assert sorted(engine.events) == sorted(reference.events)
    for inst in engine.events:
        ours = engine.events[inst]["time"]
        theirs = np.unique(np.round(reference.events[inst]["time"], 6))
        np.testing.assert_allclose(np.unique(np.round(ours, 6)), theirs, atol=2e-6)


@pytest.mark.parametrize("name", list(SHORT))
def test_monolithic_equals_the_reference_monolithic_master(name):
    tol = 1e-9
    engine = _run(name, simulate_monolithic, tol)
    reference = _run(name, reference_monolithic, tol)
    assert engine.settings["scheme"] == "monolithic" and engine.settings["engine"] == "c"
    _assert_same(engine, reference, tol)
    assert sorted(engine.events) == sorted(reference.events)


def test_stick_slip_is_the_exact_coulomb_solution():
    sc = scene("stick_slip")
    res = simulate_me(sc.build(), 20.0, 0.05, 1e-10, record=sc.record)
    phases, x_exact = coulomb_drag_reference(**SEED_94, v=SEED_94_SPEED, t_end=20.0)
    assert np.abs(res["block.x"] - x_exact(res["time"])).max() < 1e-8
    # every phase change is an event at the exact time, with the mode it starts
    ev = res.events["block"]
    starts = [(t0, 1 if kind == "slide" else 0) for kind, t0, _ in phases if t0 > 0]
    assert len(ev["time"]) == len(starts)
    for (t, mode), (t_ref, mode_ref) in zip(zip(ev["time"], ev["block.mode"]), starts):
        assert abs(t - t_ref) < 1e-8 and mode == mode_ref


@pytest.mark.parametrize("method", ["DOPRI5", "DOP853", "RODAS3"])
def test_friction_damping_is_the_exact_solution(method):
    sc = scene("friction_damping")
    res = simulate_monolithic(sc.build(), 20.0, 0.05, 1e-10, record=sc.record, method=method)
    assert np.abs(res["block.x"] - exact_friction_damping(res["time"])).max() < 1e-7
    assert res.settings["method"] == method


def test_fmi2_fmus_give_the_fmi3_result():
    sc = scene("stick_slip")
    three = simulate_me(sc.build(), 14.0, 0.1, 1e-10, record=sc.record, fmi_version=3)
    two = simulate_me(sc.build(), 14.0, 0.1, 1e-10, record=sc.record, fmi_version=2)
    for c in three.columns:
        np.testing.assert_allclose(two[c], three[c], rtol=0, atol=1e-12, err_msg=c)
    np.testing.assert_allclose(two.events["block"]["time"], three.events["block"]["time"],
                               rtol=0, atol=1e-12)


# --- a reverse slip shorter than one solver step ------------------------------------
# A block slides forward (relative velocity w > 0, mode +1) on a table moving as
# U sin(omega t). w' = -mu g - a_table(t) while sliding forward and mu g - a_table(t)
# while sliding backward. The start velocity is chosen so that w, sliding forward,
# would dip to -DELTA below zero around the table's second acceleration minimum: it
# reaches zero at t1 while the table's acceleration exceeds mu g, so the block slips
# backward, and it comes back to zero a few ms later at t2 (the backward slide ends and
# the table's deceleration makes it slide forward again at once). The backward slide is
# shorter than the solver's step: the indicator (-w while sliding backward) leaves zero
# at t1 and returns within one step, so a sign check at step ends sees nothing.
U, OMEGA, MU, G, DELTA = 0.1, 20.0, 0.4, 1.0, 4e-3
OUTPUT_STEP = 0.1  # the engine's steps are at most one output interval: keep it long


def _v_table(t):
    return U * OMEGA * np.cos(OMEGA * t)


T_DIP = (math.asin(MU * G / (U * OMEGA**2)) + 2 * math.pi) / OMEGA  # minimum of w sliding forward
W0 = -DELTA + MU * G * T_DIP + (_v_table(T_DIP) - _v_table(0.0))
STOP = T_DIP + 0.1


def _shaken_block() -> Assembly:
    asm = Assembly("shaken_block")
    asm.add("table", SineMotion(U=U, omega=OMEGA))
    asm.add("anchor", ConstantSpeed(v=0.0))
    asm.add("block", SpringBlock(m=1.0, k=0.0, g=G, mu_k=MU, mu_s=MU, v=W0))
    asm.connect("anchor.flange", "block.flange_a")
    asm.connect("table.flange", "block.support")
    return asm


def _exact_brief_slip():
    """(t1, t2) from the closed-form velocity of each slide, by bracketing its zero."""
    def w_forward(t):
        return W0 - MU * G * t - (_v_table(t) - _v_table(0.0))

    t1 = brentq(w_forward, T_DIP - 0.02, T_DIP, xtol=1e-15, rtol=1e-15)
    assert -U * OMEGA**2 * math.sin(OMEGA * t1) > MU * G  # the table outruns static friction

    def w_backward(t):
        return MU * G * (t - t1) - (_v_table(t) - _v_table(t1))

    # w < 0 just after t1 (it slides backward); its next zero ends the backward slide
    grid = np.linspace(t1 + 1e-6, t1 + 0.05, 5001)
    k = next(i for i in range(1, len(grid)) if w_backward(grid[i]) >= 0 > w_backward(grid[i - 1]))
    t2 = brentq(w_backward, grid[k - 1], grid[k], xtol=1e-15, rtol=1e-15)
    # at t2 the table decelerates faster than friction can hold the block: forward again
    assert U * OMEGA**2 * math.sin(OMEGA * t2) > MU * G
    # and sliding forward from t2 it does not stop again before STOP
    ts = np.linspace(t2 + 1e-6, STOP, 2001)
    assert np.all(-MU * G * (ts - t2) - (_v_table(ts) - _v_table(t2)) > 0)
    return t1, t2


@pytest.mark.parametrize("mode", ["me", "monolithic"])
@pytest.mark.parametrize("tolerance", [1e-8, 1e-6])
def test_a_reverse_slip_shorter_than_a_step_is_found(mode, tolerance):
    t1, t2 = _exact_brief_slip()
    run = simulate_me if mode == "me" else simulate_monolithic
    res = run(_shaken_block(), STOP, OUTPUT_STEP, tolerance)
    # the slip is shorter than the mean solver step, so the steps cannot resolve it; at
    # 1e-6 it is shorter than the spacing of the 4 interior samples too, and the
    # polynomial through the samples is what finds it
    assert t2 - t1 < STOP / res.settings["steps"]
    if tolerance == 1e-6:
        assert t2 - t1 < STOP / res.settings["steps"] / 5
    ev = res.events["block"]
    assert list(ev["block.mode"]) == [-1, 1]
    np.testing.assert_allclose(ev["time"], [t1, t2], rtol=0, atol=10 * tolerance)
    # the block then slides forward to the end: the relative velocity is positive
    assert res["block.mode"][-1] == 1 and res["block.v"][-1] > 0


def test_without_interior_samples_the_reverse_slip_goes_unseen():
    # what a sign check at step ends does: the relative velocity dips below zero and
    # comes back inside one step, so neither the backward slip nor its end is seen (with
    # a shorter step it may catch the start and miss the end); the interior samples of
    # the test above are what find both
    res = simulate_me(_shaken_block(), STOP, OUTPUT_STEP, 1e-8, event_subsamples=0)
    modes = list(res.events["block"]["block.mode"]) if "block" in res.events else []
    assert modes != [-1, 1]


# --- errors, progress and interruption ------------------------------------------------
def test_an_fmu_error_is_a_simulation_error_with_the_fmus_message():
    asm = scene("stick_slip").build()
    asm.component("block").values["mu_k"] = 0.9  # past mu_s: the FMU refuses it
    with pytest.raises(SimulationError, match=r"block: .*mu_k <= mu_s"):
        simulate_me(asm, 1.0, 0.1)


def test_bad_arguments_are_named():
    asm = scene("stick_slip").build()
    with pytest.raises(AssemblyError, match="cannot record 'block.nope'"):
        simulate_me(asm, 1.0, 0.1, record=["block.nope"])
    with pytest.raises(AssemblyError, match="method must be one of DOPRI5, RODAS3"):
        simulate_me(asm, 1.0, 0.1, method="Euler")


def test_ctrl_c_stops_the_run_and_keeps_what_was_computed():
    calls = []

    def progress(t):
        calls.append(t)
        os.kill(os.getpid(), signal.SIGINT)  # as a user pressing Ctrl-C

    sc = scene("moving_table")
    before = signal.getsignal(signal.SIGINT)  # the interpreter's (ignored in a background job)
    res = simulate_me(sc.build(), 5000.0, 0.1, 1e-10, record=sc.record, progress=progress)
    assert calls and res.settings["interrupted"]
    n = len(res["time"])
    assert 1 < n < 50001 and res["time"][-1] <= calls[-1] + 1e-9
    assert np.all(np.isfinite(res["block.v"]))
    # the handler is restored: the interpreter's own Ctrl-C behaviour is back
    assert signal.getsignal(signal.SIGINT) is before


def test_a_model_that_ends_the_run_ends_it_at_its_event():
    from conftest import drop_component
    asm = Assembly("drop")
    asm.add("mass", drop_component()(g=9.81, h=2.0))
    res = simulate_me(asm, 2.0, 0.01, 1e-10)
    t_ground = math.sqrt(2 * 2.0 / 9.81)  # h = 2 - g t^2 / 2
    term = res.settings["terminated"]
    assert term["instance"] == "mass" and "hit the ground" in term["message"]
    assert abs(term["time"] - t_ground) < 1e-9
    # the table stops at the end of the run: rows up to the event, none after
    assert res["time"][-1] <= t_ground < res["time"][-1] + 0.01
    assert np.all(res["mass.h"] >= -1e-9)


def test_a_model_without_indicators_steps_freely_and_keeps_its_period():
    """Nothing to miss between samples, so no step is capped at the output interval
    (seed 8.5's disk on an axle: the period against the elliptic-integral closed form)."""
    run = run_scene_full("axle_pendulum")
    settings = run.result.settings
    assert settings["steps"] < settings["stop_time"] / settings["step"]  # fewer than outputs
    assert run.passed, [(f.name, f.error, f.bound) for f in run.figures]


def test_steps_are_capped_only_where_an_indicator_can_move_while_the_states_stand_still():
    from assemblies.engine.me import step_limit_needed
    from short_slip import short_slip_assembly
    assert not step_limit_needed(scene("coin_rolling").build())  # its own states alone
    # the driver's travel is a state (travel' = v): the margin moves with states the
    # solver integrates, affinely while the block sticks, so no excursion hides in a step
    assert not step_limit_needed(scene("stick_slip").build())
    assert step_limit_needed(short_slip_assembly())  # the table's shaking, written in time


def test_rows_of_states_alone_are_the_values_the_fmu_reports():
    """Where every recorded column is a state, rows are written from the solution
    without setting the FMUs to each output point; the FMU reports exactly those values
    where it is asked (a column it computes, the energy, makes the engine ask)."""
    asm = scene("axle_pendulum").build()
    alone = simulate_me(asm, 5.0, 0.01, 1e-8, record=["body.theta", "body.omega"])
    asked = simulate_me(asm, 5.0, 0.01, 1e-8, record=["body.theta", "body.omega", "body.E"])
    for column in ("body.theta", "body.omega"):
        np.testing.assert_array_equal(alone[column], asked[column], err_msg=column)
    # and the energy the FMU computes at those points is conserved (no friction)
    assert np.ptp(np.asarray(asked["body.E"])) < 1e-6 * abs(asked["body.E"][0])
