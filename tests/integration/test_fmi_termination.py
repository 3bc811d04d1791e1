"""A foreign FMU that ends the run the FMI way ends it there, in every master, with the
rows so far and ``settings["terminated"]`` naming the instance and the time.

FMI 2 Co-Simulation: doStep answers fmi2Discard, fmi2GetBooleanStatus(fmi2Terminated)
says true and fmi2GetRealStatus(fmi2LastSuccessfulTime) where it stopped (stair2);
FMI 3 Co-Simulation: terminateSimulation, with fmi3OK or fmi3Discard (term_stair3);
FMI 2 Model Exchange: terminateSimulation from fmi2NewDiscreteStates or
fmi2CompletedIntegratorStep (term_me2). The references are fmpy's simulate_fmu on the
same FMU and the closed forms of the hand-written models (tests/handmade/).
"""
import math
import warnings

import numpy as np
import pytest
from fmpy import simulate_fmu

from assemblies import FMU, Assembly, cosimulate, export_fmu, simulate_me
from assemblies.engine.cosim import DEFAULT_SCHEME
from assemblies.experiment import FixedStepFallback
from assemblies.masters.cosim import cosimulate as reference_cosimulate

from handmade_fmus import handmade_fmu

T_END = 5.0  # where both staircases end


def staircase(name: str, **values):
    asm = Assembly("stairs")
    asm.add("stair", FMU(handmade_fmu(name), **values))
    return asm


def quietly(run, *args, **kwargs):
    """A run whose FixedStepFallback (a stateless FMU asked for adaptive steps) is not
    the point of the test."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", FixedStepFallback)
        return run(*args, **kwargs)


def assert_ends_at_five(res, fmpy_rows=None):
    """Rows every 0.5 s up to t = 5 and none after; the counter is floor(t)."""
    expected = np.arange(0.0, T_END + 0.25, 0.5)
    np.testing.assert_allclose(res["time"], expected, rtol=0, atol=1e-12)
    np.testing.assert_array_equal(res["stair.counter"], np.floor(expected + 1e-9))
    end = res.settings["terminated"]
    assert end["instance"] == "stair" and end["time"] == pytest.approx(T_END, abs=1e-12)
    if fmpy_rows is not None:  # fmpy keeps the same rows
        np.testing.assert_allclose(res["time"], fmpy_rows["time"], rtol=0, atol=1e-12)
        np.testing.assert_array_equal(res["stair.counter"], fmpy_rows["counter"])


@pytest.mark.parametrize("run, scheme", [
    (cosimulate, {}), (cosimulate, DEFAULT_SCHEME), (reference_cosimulate, {}),
    (reference_cosimulate, DEFAULT_SCHEME)])
def test_fmi2_discard_with_terminated_keeps_the_rows_like_fmpy(run, scheme):
    path = handmade_fmu("stair2")
    reference = simulate_fmu(str(path), stop_time=10.0, output_interval=0.5)
    res = quietly(run, staircase("stair2"), stop_time=10.0, step=0.5, **scheme)
    assert_ends_at_five(res, reference)


@pytest.mark.parametrize("discard", [0, 1])
@pytest.mark.parametrize("run", [cosimulate, reference_cosimulate])
def test_fmi3_terminate_simulation_keeps_the_rows(run, discard):
    """fmpy reads terminateSimulation only from a doStep that returns fmi3OK; with
    fmi3Discard (the standard allows both) the closed form is the reference."""
    res = quietly(run, staircase("term_stair3", discard=discard), stop_time=10.0, step=0.5,
                  **DEFAULT_SCHEME)
    reference = None
    if not discard:
        reference = simulate_fmu(str(handmade_fmu("term_stair3")), stop_time=10.0,
                                 output_interval=0.5)
    assert_ends_at_five(res, reference)


def test_the_last_row_is_where_the_model_stopped_not_the_step_end():
    """A step of 0.75 s over t = 5: the FMU stops at 5 (fmi2LastSuccessfulTime), and the
    last row says 5, not 5.25."""
    for run in (cosimulate, reference_cosimulate):
        res = run(staircase("stair2"), stop_time=10.0, step=0.75)
        assert res["time"][-1] == pytest.approx(T_END, abs=1e-12)
        assert res["stair.counter"][-1] == 5 and res["time"][-2] == pytest.approx(4.5)


def test_an_assembly_fmu_ends_its_run_the_fmi2_way_when_a_member_does(tmp_path):
    """The exported assembly's doStep answers Discard with fmi2Terminated at the member's
    end (its runtime, fmus/runtime/fmi2.c); fmpy keeps the rows up to there."""
    path = quietly(export_fmu, staircase("stair2"), tmp_path / "stairs.fmu", fmi=2,
                   outputs=["stair.counter"], stop_time=10.0, step=0.5)
    rows = simulate_fmu(str(path), stop_time=10.0, output_interval=0.5)
    np.testing.assert_allclose(rows["time"], np.arange(0.0, T_END + 0.25, 0.5), atol=1e-12)
    assert rows["stair.counter"][-1] == 5


G, H0 = 9.81, 2.0
T_HIT = math.sqrt(2 * H0 / G)


@pytest.mark.parametrize("how", [0, 1])
def test_fmi2_model_exchange_ends_the_run_where_it_asks(how):
    """how = 0: at the state event of its indicator h, from fmi2NewDiscreteStates;
    how = 1: from fmi2CompletedIntegratorStep, at the first step end with h <= 0."""
    asm = Assembly("drop")
    asm.add("mass", FMU(handmade_fmu("term_me2"), how=how))
    res = simulate_me(asm, 2.0, 0.01, 1e-10)
    end = res.settings["terminated"]
    assert end["instance"] == "mass" and "hit the ground" in end["message"]
    if how == 0:
        assert end["time"] == pytest.approx(T_HIT, abs=1e-9)
        fmpy_rows = simulate_fmu(str(handmade_fmu("term_me2")), stop_time=2.0,
                                 output_interval=0.01)
        # (fmpy's CVode locates the event to its default tolerance)
        assert fmpy_rows["time"][-1] == pytest.approx(end["time"], abs=1e-5)
    else:  # a step end after the ground, and before the next output point
        assert T_HIT <= end["time"] < T_HIT + 0.01 + 1e-9
    # the rows so far, on the closed form h = h0 - g t^2 / 2, none after the end
    assert res["time"][-1] <= end["time"] and len(res["time"]) > 60
    np.testing.assert_allclose(res["mass.h"], H0 - G * res["time"] ** 2 / 2, atol=1e-8)


@pytest.mark.parametrize("run, scheme", [
    (cosimulate, {}), (cosimulate, DEFAULT_SCHEME), (reference_cosimulate, {}),
    (reference_cosimulate, DEFAULT_SCHEME)])
def test_an_fmu_that_rolls_back_ends_the_run_inside_a_step(run, scheme):
    """term_decay (x' = -x + sin t, exact steps, exact restore) ends the FMI 2 way at
    t_stop = 2.34, inside a step: the adaptive run keeps its scheme (the restore is
    exact) and, like fixed steps and fmpy, ends with a row at 2.34 on the closed form."""
    path = handmade_fmu("term_decay")
    asm = Assembly("decay")
    asm.add("dec", FMU(path, t_stop=2.34))
    with warnings.catch_warnings():
        warnings.simplefilter("error", FixedStepFallback)
        res = run(asm, stop_time=5.0, step=0.1, **scheme)
    assert res.settings["adaptive"] is bool(scheme)
    end = res.settings["terminated"]
    assert end["instance"] == "dec" and end["time"] == pytest.approx(2.34, abs=1e-12)
    fmpy_rows = simulate_fmu(str(path), stop_time=5.0, output_interval=0.1,
                             start_values={"t_stop": 2.34})
    np.testing.assert_allclose(res["time"], fmpy_rows["time"], rtol=0, atol=1e-12)
    t = res["time"]
    np.testing.assert_allclose(res["dec.y"], 1.5 * np.exp(-t) + 0.5 * (np.sin(t) - np.cos(t)),
                               rtol=0, atol=1e-12)
