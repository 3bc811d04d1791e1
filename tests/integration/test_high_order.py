"""The engine's 8th-order explicit method (issue 27): "auto" takes DOP853 instead of
DOPRI5 at tolerances up to 1e-8 (engine.h, ENG_HIGH_ORDER_TOLERANCE), "DOP853" asks for
it at any; a run says which it took, and on the rolling coin it meets the independent
Lagrange coin with fewer evaluations than DOPRI5 at the same tolerance."""
import numpy as np
import pytest

from assemblies.engine import me as engine
from assemblies.scenes import scene
from coin_reference import tilt_of

STOP, STEP = 4.0, 0.01


def _coin_run(tol, method):
    asm = scene("coin_rolling").build()
    return asm, engine.prepare_monolithic(asm, STOP, STEP, tol, record=["coin.theta"],
                                          method=method)()


@pytest.mark.parametrize("tol, method, explicit", [
    (1e-7, "auto", "DOPRI5"), (1e-8, "auto", "DOP853"), (1e-10, "auto", "DOP853"),
    (1e-4, "DOP853", "DOP853"), (1e-10, "DOPRI5", "DOPRI5"), (1e-8, "RODAS3", None)])
def test_the_run_says_which_explicit_method_it_took(tol, method, explicit):
    _, res = _coin_run(tol, method)
    assert res.settings["method"] == method
    assert res.settings["explicit_method"] == explicit


def test_dop853_meets_the_lagrange_coin_with_fewer_evaluations():
    """Tolerance 1e-10 over 4 s: both methods within 10x the tolerance of the Lagrange
    coin (tests/coin_reference.py; measured 1.5e-10 DOPRI5, 8.5e-11 DOP853), DOP853 with
    at most 0.6 of DOPRI5's evaluations (measured 601 against 1477: its three extra
    stages per step for the rows inside every step counted)."""
    asm, high = _coin_run(1e-10, "auto")
    _, low = _coin_run(1e-10, "DOPRI5")
    exact = tilt_of(asm.component("coin"), high["time"])
    for res in (high, low):
        assert np.max(np.abs(res["coin.theta"] - exact)) < 1e-9
    assert high.settings["rhs_calls"] < 0.6 * low.settings["rhs_calls"]


def test_under_a_step_cap_auto_keeps_dopri5():
    """moving_table's shaken table moves the static margin while the block sticks, so
    its steps are capped at the output interval (me.py, step_limit_needed): there
    DOP853's long steps are impossible and its accuracy wasted (1,088 steps with either
    method at 1e-8, DOP853 with 1.7x DOPRI5's evaluations when this was written), and
    "auto" keeps DOPRI5; "DOP853" still takes it."""
    sc = scene("moving_table")
    kept = engine.simulate_monolithic(sc.build(), sc.stop_time, sc.step, 1e-8,
                                      record=sc.record)
    forced = engine.simulate_monolithic(sc.build(), sc.stop_time, sc.step, 1e-8,
                                        record=sc.record, method="DOP853")
    assert kept.settings["explicit_method"] == "DOPRI5"
    assert forced.settings["explicit_method"] == "DOP853"
    assert forced.settings["rhs_calls"] > kept.settings["rhs_calls"]


def test_where_events_come_every_few_steps_auto_goes_back_to_dopri5():
    """A Burridge-Knopoff chain of 20 blocks over 75 s at 1e-10: 268 slips in about 2,100
    steps. DOP853 would restart at each with a 12-stage step that the next event cuts
    short (784 steps, 1.3x DOPRI5's evaluations when this was written); "auto" leaves it
    for DOPRI5 once events come every 3 steps or more often, and then costs what DOPRI5
    does."""
    from assemblies.scenes.burridge_knopoff import SCENE_CHAIN, fault_chain
    sc = scene("burridge_knopoff")
    asm = fault_chain(20, **{k: v for k, v in SCENE_CHAIN.items() if k != "n"})
    auto = engine.simulate_me(asm, 75.0, sc.step, 1e-10)
    low = engine.simulate_me(asm, 75.0, sc.step, 1e-10, method="DOPRI5")
    high = engine.simulate_me(asm, 75.0, sc.step, 1e-10, method="DOP853")
    assert auto.settings["explicit_method"] == "DOP853, then DOPRI5 (events every few steps)"
    assert high.settings["rhs_calls"] > 1.2 * low.settings["rhs_calls"]
    assert auto.settings["rhs_calls"] < 1.05 * low.settings["rhs_calls"]
