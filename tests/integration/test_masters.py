"""The three masters against each other: me and monolithic agree to the tolerance, and
cosim converges to monolithic as the communication step shrinks, at the order the input
extrapolation allows."""
import math

import numpy as np
import pytest

from assemblies import Assembly, AssemblyError, run_scene
from assemblies.masters.cosim import cosimulate
from assemblies.masters.me import simulate_me
from assemblies.masters.monolithic import simulate_monolithic
from assemblies.scenes import scene
from assemblies.scenes.table import PERIOD
from components import AssumedModesBeam, ConstantSpeed, SpringBlock

# (scene, stop time): the table scenes over six periods of the table (12 friction events)
SHORT = {"stick_slip": 14.0, "friction_damping": 10.0,
         "moving_table": 6 * PERIOD, "conveyor": 6 * PERIOD}


def _run(name, master, stop, step, tolerance, **kw):
    sc = scene(name)
    return master(sc.build(), stop, step, tolerance, record=sc.record, **kw)


@pytest.mark.parametrize("name", list(SHORT))
def test_me_and_monolithic_agree_to_the_tolerance(name):
    # different solvers on purpose (explicit DOP853 on the FMUs, implicit Radau with the
    # exact Jacobian on the CasADi model): agreement is not one computation twice
    stop, step, tol = SHORT[name], SHORT[name] / 40, 1e-9
    me = _run(name, simulate_me, stop, step, tol, method="DOP853")
    mono = _run(name, simulate_monolithic, stop, step, tol, method="Radau")
    assert me.settings["events"] >= 2 and mono.settings["events"] >= 2
    scale = max(1.0, float(np.max(np.abs(mono["block.x"]))))
    np.testing.assert_allclose(me["block.x"], mono["block.x"], rtol=0, atol=100 * tol * scale)
    np.testing.assert_allclose(me["block.v"], mono["block.v"], rtol=0, atol=100 * tol * scale)
    np.testing.assert_array_equal(me["block.mode"], mono["block.mode"])


def test_the_monolithic_fmu_agrees_with_the_reference():
    stop = SHORT["moving_table"]
    fmu = _run("moving_table", simulate_monolithic, stop, stop / 40, 1e-10, engine="fmu")
    ref = _run("moving_table", simulate_monolithic, stop, stop / 40, 1e-10)
    # both are the Python masters' engine; the master says which ran an FMU
    assert fmu.settings["engine"] == ref.settings["engine"] == "fmpy"
    assert "as one FMU" in fmu.settings["master"] and "no FMU" in ref.settings["master"]
    np.testing.assert_allclose(fmu["block.s"], ref["block.s"], rtol=0, atol=1e-7)
    np.testing.assert_allclose(fmu["block.v"], ref["block.v"], rtol=0, atol=1e-7)


@pytest.mark.parametrize("name", ["stick_slip", "friction_damping"])
def test_cosim_is_exact_when_the_driver_moves_linearly(name):
    # a constant-speed driver is extrapolated exactly by the FMU's derivative inputs,
    # so the communication step adds no error at all
    stop = SHORT[name]
    ref = _run(name, simulate_monolithic, stop, 2.0, 1e-11)
    for step in (2.0, 0.5):
        co = _run(name, cosimulate, stop, step, 1e-11)
        stride = round(2.0 / step)
        np.testing.assert_allclose(co["block.x"][::stride], ref["block.x"], rtol=0, atol=1e-7)


def _convergence(name):
    steps = [PERIOD / 8 / 2**k for k in range(4)]
    stop = SHORT[name]
    ref = _run(name, simulate_monolithic, stop, steps[-1], 1e-12)
    errors = []
    for h in steps:
        co = _run(name, cosimulate, stop, h, 1e-12)
        mine = co["block.s"][::round(steps[0] / h)]
        exact = ref["block.s"][::round(steps[0] / steps[-1])]
        errors.append(float(np.max(np.abs(mine - exact))))
    return errors, [math.log2(a / b) for a, b in zip(errors, errors[1:])]


@pytest.mark.parametrize("name", ["moving_table", "conveyor"])
def test_cosim_converges_to_monolithic_at_first_order(name):
    # Theory for zero-order hold Jacobi: order 1. Our FMUs extrapolate the table's motion
    # quadratically (s, v, a), but the block's states are relative to the table, so each
    # communication point re-bases them on the new input: the block's absolute velocity
    # jumps by the extrapolation error of v, O(h^2), once per step -> O(h) globally.
    errors, orders = _convergence(name)
    assert all(a > b for a, b in zip(errors, errors[1:])), errors
    assert 0.8 < orders[-1] < 1.6, (errors, orders)
    assert errors[-1] < 0.05


def test_run_scene_modes():
    me = run_scene("friction_damping", mode="me", tolerance=1e-10)
    mono = run_scene("friction_damping", mode="monolithic", tolerance=1e-10)
    assert me.settings["scheme"] == "me" and mono.settings["scheme"] == "monolithic"
    assert max(f.error for f in me.figures) < 1e-8
    assert max(f.error for f in mono.figures) < 1e-8
    assert all(f.passed for f in me.figures + mono.figures)
    with pytest.raises(AssemblyError, match="mode must be one of cosim, me, monolithic"):
        run_scene("friction_damping", mode="jacobian")


def test_moving_table_decay_rate_is_the_seeds():
    res = run_scene("moving_table", mode="monolithic")
    rate = {f.name: f for f in res.figures}["decay_rate"]
    assert abs(rate.reference - 0.1273) < 1e-4
    # the seed's rate holds for V << U omega and small mu g/(U omega^2) = 0.01
    assert abs(rate.measured - rate.reference) < 0.01 * rate.reference
    assert all(f.passed for f in res.figures), res.figures


def test_the_engines_me_solves_the_loop_of_a_block_riding_on_a_beam_tip():
    # a block riding on a beam tip: the tip's acceleration depends on the force on it,
    # which depends (through the block's inertia) on that acceleration. The compiled
    # engine's me solves the loop at every evaluation (it refused it before); the fmpy me
    # master solves it by its own Newton and the monolithic master in the joined
    # equations: all three agree to the solvers' accuracy while the block slides
    from assemblies.engine.me import simulate_me as c_simulate_me
    from assemblies.engine.me import simulate_monolithic as c_simulate_monolithic
    asm = Assembly("loop")
    asm.add("beam", AssumedModesBeam(basis="poly2", mode1_c=0.01))
    asm.add("anchor", ConstantSpeed(v=0.0))
    asm.add("block", SpringBlock(k=0.0, v=5.0))
    asm.connect("anchor.flange", "block.flange_a")
    asm.connect("beam.tip", "block.support")
    record = ["beam.w_tip", "block.x", "block.v", "beam.tip.a"]
    engine = c_simulate_me(asm, 0.3, 0.01, tolerance=1e-9, record=record)
    assert engine.settings["algebraic_loops"] == [
        "between FMUs beam, block: beam.tip.a => block.support.a -> "
        "block.support.f => beam.tip.f"]
    reference = simulate_me(asm, 0.3, 0.01, tolerance=1e-9, record=record)
    joined = c_simulate_monolithic(asm, 0.3, 0.01, tolerance=1e-9, record=record)
    for name in record:
        scale = 1.0 + np.max(np.abs(reference[name]))
        np.testing.assert_allclose(engine[name], reference[name], rtol=0, atol=1e-7 * scale)
        np.testing.assert_allclose(engine[name], joined[name], rtol=0, atol=1e-7 * scale)
