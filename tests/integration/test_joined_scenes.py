"""Scenes that join elements (issue 6): their figures against analytic values and
conservation laws, me against monolithic, and cosim converging to monolithic."""
import math

import numpy as np
import pytest

from assemblies import run_scene
from assemblies.masters.cosim import cosimulate
from assemblies.masters.me import simulate_me
from assemblies.masters.monolithic import simulate_monolithic
from assemblies.scenes import scene

# (scene, stop time, compared column): long enough to hold every stick and slip event
# of the start (two_block_belt: both slip, block1 re-sticks at 5.5 s, slips at 6.1 s;
# axle_motor: the disk swings, reverses twice and sticks at 6.1 s)
SHORT = {"two_block_belt": (12.0, "block1.s"), "axle_motor": (6.4, "body.theta")}


def _run(name, master, stop, step, tolerance, **kw):
    sc = scene(name)
    return master(sc.build(), stop, step, tolerance, record=sc.record, **kw)


def _figures(name):
    return {f.name: f for f in run_scene(name, mode="monolithic").figures}


def test_two_block_belt_figures():
    figures = _figures("two_block_belt")
    assert figures["t_slip"].error < 1e-9  # an event time: located to solver tolerance
    # the sliding equilibrium K s = mu_k m g, reached as the transient decays like
    # exp(-d t / 2m) = exp(-7.5) of its 0.25 m start by t = 300 s
    assert figures["s1_end"].error < 2e-4 and figures["s2_end"].error < 2e-4
    assert all(f.passed for f in figures.values()), figures


def test_axle_motor_figures():
    figures = _figures("axle_motor")
    assert figures["phi_rel"].error < 1e-8  # the rotor at rest: the shaft carries tau_stall
    assert figures["hold_excess"].measured == 0.0  # Coulomb bearing holds the disk
    # motor work = stored energy + losses; the losses by the trapezoid rule on 0.01 s samples
    W = figures["W_motor"]
    assert W.measured > 1.0 and W.error < 1e-5 * W.measured
    assert all(f.passed for f in figures.values()), figures


def test_axle_motor_runs_without_bearing_friction():
    """body.bearing_friction=none, a value `mechfmu show` lists, leaves the body without
    mode and bearing torque: the scene ran into "cannot record 'body.mode'"; now the
    energy balance (no bearing loss) still holds, and the figures that need a bearing
    to hold the disk fail instead of the run."""
    figures = {f.name: f for f in run_scene("axle_motor", stop_time=3.0,
                                            params={"body.bearing_friction": "none"}).figures}
    assert figures["W_motor"].passed and figures["W_motor"].measured > 0.1, figures
    assert math.isnan(figures["phi_rel"].bound)


@pytest.mark.parametrize("name", list(SHORT))
def test_me_and_monolithic_agree_to_the_tolerance(name):
    stop, column = SHORT[name]
    tol = 1e-9
    me = _run(name, simulate_me, stop, stop / 64, tol, method="DOP853")
    mono = _run(name, simulate_monolithic, stop, stop / 64, tol, method="Radau")
    assert me.settings["events"] >= 3 and me.settings["events"] == mono.settings["events"]
    np.testing.assert_allclose(me[column], mono[column], rtol=0, atol=100 * tol)


@pytest.mark.parametrize("name", list(SHORT))
def test_cosim_converges_to_monolithic_at_first_order(name):
    # Theory, zero-order hold Jacobi: order 1. Motion inputs are extrapolated by the FMUs
    # (s with v, a), but the forces the springs return are held over each step, and
    # that O(h) force error drives the masses: first order globally (measured
    # two_block_belt 1.23 1.27 1.36 1.02, axle_motor 1.32 1.19 1.07 for h = 0.4 .. 0.025
    # and 0.1 .. 0.0125; a 0.2 s step is unstable for axle_motor's shaft, h omega = 1.4)
    stop, column = SHORT[name]
    steps = [0.1 / 2**k for k in range(4)]
    ref = _run(name, simulate_monolithic, stop, steps[-1], 1e-12)
    errors = []
    for h in steps:
        co = _run(name, cosimulate, stop, h, 1e-12)
        stride = round(h / steps[-1])
        errors.append(float(np.max(np.abs(co[column] - ref[column][::stride]))))
    orders = [math.log2(a / b) for a, b in zip(errors, errors[1:])]
    assert all(a > b for a, b in zip(errors, errors[1:])), errors
    assert 0.8 < orders[-1] < 1.6, (errors, orders)
