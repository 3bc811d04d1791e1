"""prepare_me and prepare_monolithic (issue 27): the checks and look-ups once, then a run
per call. Each call reads the parameters the instances have then, so a parameter study
that changes them between calls follows the exact Coulomb solution (seed 9.2) of each
set, and a bad argument is refused where the run is prepared, as simulate_* refuses it."""
import numpy as np
import pytest

from assemblies import AssemblyError
from assemblies.engine import me as engine
from assemblies.scenes import scene
from conftest import SEED_94_SPEED, coulomb_drag_reference

STOP, STEP = 30.0, 0.1
PREPARE = {"me": engine.prepare_me, "monolithic": engine.prepare_monolithic}


def _exact(block, times):
    p = block.values
    _, x = coulomb_drag_reference(p["m"], p["k"], p["g"], p["mu_k"], p["mu_s"],
                                  SEED_94_SPEED, times[-1])
    return x(times)


@pytest.mark.parametrize("mode", list(PREPARE))
def test_each_call_runs_with_the_parameters_of_then(mode):
    asm = scene("stick_slip").build()
    block = asm.component("block")
    assert asm.component("driver").values["v"] == SEED_94_SPEED
    run = PREPARE[mode](asm, STOP, STEP, 1e-9, record=["block.x"])
    first = run()
    times = np.asarray(first["time"])
    before = _exact(block, times)
    assert np.max(np.abs(first["block.x"] - before)) < 1e-6
    block.set("mu_k", 0.2)  # a wider slip: another solution from the first slip on
    block.set("k", 2.0)
    second = run()
    after = _exact(block, times)
    assert np.max(np.abs(after - before)) > 0.1  # the two sets differ plainly
    assert np.max(np.abs(second["block.x"] - after)) < 1e-6
    assert second.settings["events"] != first.settings["events"] or \
        second.events["block"]["time"][0] != first.events["block"]["time"][0]


@pytest.mark.parametrize("mode", list(PREPARE))
def test_a_bad_argument_is_refused_when_preparing(mode):
    asm = scene("stick_slip").build()
    with pytest.raises(AssemblyError, match=r"tolerance .*\(tolerance=, --tolerance\)"):
        PREPARE[mode](asm, STOP, STEP, 2.0)
    with pytest.raises(AssemblyError, match="method must be one of"):
        PREPARE[mode](asm, STOP, STEP, 1e-6, method="Euler")


@pytest.mark.parametrize("mode", list(PREPARE))
def test_calls_of_one_plan_with_other_settings_keep_their_own(mode):
    """Two prepared calls of one assembly share its plan (and the engine's description of
    the run, whose per-run fields a call sets only where they changed): called in turn,
    each runs its own stop time and tolerance, the exact solution to its tolerance, and
    each result keeps its own counts after the other has run."""
    asm = scene("stick_slip").build()
    block = asm.component("block")
    loose = PREPARE[mode](asm, STOP, STEP, 1e-5, record=["block.x"])
    tight = PREPARE[mode](asm, STOP / 2, STEP / 2, 1e-10, record=["block.x"])
    results = [call() for call in (loose, tight, loose, tight)]
    for result, stop, step, tol in zip(results, [STOP, STOP / 2] * 2, [STEP, STEP / 2] * 2,
                                       [1e-5, 1e-10] * 2):
        times = np.asarray(result["time"])
        assert times[-1] == pytest.approx(stop) and times[1] - times[0] == pytest.approx(step)
        assert result.settings["tolerance"] == tol
        # 4.8 and 1.2 times the tolerance measured: the solver's local tolerance over the
        # slips. The tight call run at the loose tolerance would be 5e5 times off; the
        # loose one at the tight tolerance, as dear as the tight (rhs_calls, below)
        assert np.max(np.abs(result["block.x"] - _exact(block, times))) < 10 * tol
    assert results[0].settings["rhs_calls"] < results[1].settings["rhs_calls"]
    assert results[0].settings["rhs_calls"] == results[2].settings["rhs_calls"]
    assert results[1].settings["steps"] == results[3].settings["steps"]


@pytest.mark.parametrize("mode", list(PREPARE))
def test_settings_read_after_the_next_call_are_still_their_own(mode):
    """A result's settings are made when first read (Result.settings), from what its run
    kept: read after the plan's next run (which reuses its buffers and statistics), they
    are the counts of their own run, as a run with those parameters reads them at once."""
    keys = ("steps", "events", "rhs_calls", "rejected", "stop_time")
    asm = scene("stick_slip").build()
    block = asm.component("block")
    run = PREPARE[mode](asm, STOP, STEP, 1e-9, record=["block.x"])
    first = run()  # settings not read yet
    mu_k = block.values["mu_k"]
    block.set("mu_k", 0.2)
    second = run()
    second_counts = [second.settings[k] for k in keys]
    first_counts = [first.settings[k] for k in keys]
    block.set("mu_k", mu_k)
    again = PREPARE[mode](asm, STOP, STEP, 1e-9, record=["block.x"])()
    assert [again.settings[k] for k in keys] == first_counts
    assert first_counts != second_counts  # the two runs differ, so a mix-up would show
