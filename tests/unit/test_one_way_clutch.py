"""OneWayClutch (and Clutch's free state) against closed forms of MSL's documented law.

MSL's OneWayClutch is a clutch in parallel with a freewheel: ``w_rel = flange_b.w -
flange_a.w >= 0``; overrunning (``w_rel > 0``) it slides with ``cgeo mu fn`` (none while
free, ``f_normalized <= 0``), at ``w_rel = 0`` it locks and holds against any backward
torque. The driver here is a speed source (MSL Speed, exact = false), whose motion does
not depend on the clutch's torque, so every master runs it without a loop.
"""
import math

import numpy as np
import pytest
from fmpy.validation import validate_fmu
from scipy.optimize import brentq

from assemblies import Assembly, cosimulate, simulate_me, simulate_monolithic
from components.rotational.friction import Clutch, OneWayClutch
from components.sources.rotational import ConstantTorque, Speed
from components.sources.signals import Constant, Step
from components.sources.table import TimeTable
from fmus import build_fmu

TOL = 1e-9
ACC = 100 * TOL  # an event time or a state at it (scene.solver_accuracy's rule)
MODES = ("me", "monolithic", "cosim")


def _run(asm, mode, stop, step, record):
    if mode == "me":
        return simulate_me(asm, stop, step, TOL, record=record)
    if mode == "monolithic":
        return simulate_monolithic(asm, stop, step, TOL, record=record)
    return cosimulate(asm, stop, step, TOL, record=record, event_sync=True)


def _events(res, instance):
    ev = res.events.get(instance)
    if ev is None:
        return []
    return list(zip(np.asarray(ev["time"]), np.asarray(ev[f"{instance}.mode"])))


def _driven_by_speed(clutch, w_driver, ref, press, load=None):
    """`clutch` driven by a speed source following `ref`, engaged by `press`."""
    asm = Assembly("one_way")
    asm.add("ref", ref)
    asm.add("press", press)
    asm.add("driver", Speed(f_crit=5.0, w=w_driver))
    asm.add("owc", clutch)
    asm.connect("ref.y", "driver.w_ref")
    asm.connect("driver.flange", "owc.flange_a")
    asm.connect("press.y", "owc.f_normalized")
    if load is not None:
        asm.add("load", ConstantTorque(tau_constant=-load))
        asm.connect("load.flange", "owc.flange_b")
    return asm


@pytest.mark.parametrize("mode", MODES)
def test_engaged_it_brakes_an_overrunning_load_and_then_holds_it_against_any_backward_torque(mode):
    """Driver at constant W, driven side J at w0 > W, a load torque T braking it: sliding
    forward, J w' = -(F + T) with F = cgeo mu fn, so it reaches W at J (w0 - W) / (F + T)
    having lost F (w0 - W) t_lock / 2 to friction; then it stays locked, although T is
    beyond the clutch's static limit peak F: the freewheel takes it (a Clutch slides)."""
    W, w0, J, F, T, peak = 2.0, 5.0, 0.5, 3.0, 4.0, 1.2
    assert T > peak * F

    def assembly(cls):
        return _driven_by_speed(cls(J=J, w=w0, fn_max=F / 0.5, peak=peak), W, Constant(k=W),
                                Constant(k=1.0), load=T)
    t_lock = J * (w0 - W) / (F + T)
    res = _run(assembly(OneWayClutch), mode, 1.0, 0.05,
               ["owc.w", "owc.mode", "owc.W_loss", "owc.tau", "owc.w_rel"])
    assert [q for _, q in _events(res, "owc")] == [0]
    assert abs(_events(res, "owc")[0][0] - t_lock) < ACC
    t = np.asarray(res["time"])
    w = np.maximum(w0 - (F + T) / J * t, W)
    assert np.abs(res["owc.w"] - w).max() < ACC * w0
    assert np.all(np.asarray(res["owc.w_rel"])[t > t_lock] == 0.0)  # locked: exactly
    # locked, the clutch carries the whole load: tau = flange_b.tau = -T
    np.testing.assert_allclose(res["owc.tau"][t > t_lock], -T, atol=1e-9)
    assert abs(float(res["owc.W_loss"][-1]) - F * (w0 - W) * t_lock / 2) < ACC * J * w0**2
    if mode == "me":  # the same load makes a two-way clutch slide backward after the lock
        res = _run(assembly(Clutch), mode, 1.0, 0.05, ["owc.w", "owc.mode"])
        assert [q for _, q in _events(res, "owc")] == [-1]
        assert float(res["owc.w"][-1]) < W - 1.0


def _filtered(rows, k, t):
    """Exact response of w' = k (w_ref - w), w(0) = 0, to a piecewise linear w_ref."""
    w, t0 = 0.0, 0.0
    for (ta, ya), (tb, yb) in zip(rows, rows[1:]):
        s = (yb - ya) / (tb - ta)
        end = min(t, tb)
        w = ya + s * (end - ta) - s / k + (w - ya + s / k) * math.exp(-k * (end - t0))
        t0 = end
        if t <= tb:
            return w
    return w


# a co-simulation holds the driver's motion over each exchange step: the catch of a driver
# whose speed changes is then located to the step, not to the tolerance
@pytest.mark.parametrize("mode", ("me", "monolithic"))
def test_disengaged_it_is_a_freewheel_the_load_keeps_the_fastest_speed_it_was_given(mode):
    """f_normalized = 0: no friction, only the freewheel. The driver's speed rises past
    the load's w0 and falls back: the load keeps w0 until the driver catches it (lock:
    the freewheel pushes it), turns with it up to the driver's peak, then keeps that
    peak speed (the driver falls behind: free again). So w_load(t) = max(w0, max over
    s <= t of w_driver(s)), and nothing is dissipated."""
    rows = [(0.0, 0.0), (0.2, 0.0), (0.7, 4.0), (1.2, 0.0), (2.0, 0.0)]
    k, w0, J = 2 * math.pi * 5.0, 1.5, 0.3
    asm = _driven_by_speed(OneWayClutch(J=J, w=w0, fn_max=10.0), 0.0, TimeTable(table=rows),
                           Constant(k=0.0))
    res = _run(asm, mode, 1.5, 0.01, ["owc.w", "owc.mode", "owc.W_loss", "driver.w"])
    t_catch = brentq(lambda t: _filtered(rows, k, t) - w0, 0.2, 0.7, xtol=1e-14)
    t_peak = brentq(lambda t: _filtered(rows, k, t) - (4.0 - 8.0 * (t - 0.7)), 0.7, 1.2,
                    xtol=1e-14)  # the filter's output meets its input: w' = 0
    changes = _events(res, "owc")
    assert [q for _, q in changes] == [0, 1], changes
    assert abs(changes[0][0] - t_catch) < ACC and abs(changes[1][0] - t_peak) < ACC * 10
    t = np.asarray(res["time"])
    driver = np.array([_filtered(rows, k, x) for x in t])
    expected = np.where(t < t_catch, w0, np.where(t < t_peak, driver, _filtered(rows, k, t_peak)))
    assert np.abs(res["owc.w"] - expected).max() < ACC * 10
    assert float(np.abs(res["owc.W_loss"]).max()) == 0.0


@pytest.mark.parametrize("mode", MODES)
def test_a_clutch_with_no_normal_force_neither_sticks_nor_slips(mode):
    """MSL's free state (f_normalized <= 0): fn = 0, no torque, no loss, whatever the
    relative speed does. The driver's speed passes the driven side's both ways; the
    driven side keeps w0 exactly, and the clutch reports MSL's fn = 0 (not fn_max
    f_normalized). (Each pass used to end a 'slide' and set the driven speed to the
    driver's: 5e-13 rad/s off in me, 0.2 rad/s in a co-simulation holding the driver's
    speed over a step.)"""
    rows = [(0.0, 0.0), (0.5, 4.0), (1.0, 0.0)]
    w0 = 1.5
    asm = _driven_by_speed(Clutch(J=0.3, w=w0, fn_max=10.0), 0.0, TimeTable(table=rows),
                           Constant(k=-0.5))
    res = _run(asm, mode, 1.0, 0.01, ["owc.w", "owc.tau", "owc.W_loss", "owc.fn", "driver.w"])
    assert np.asarray(res["driver.w"]).max() > w0 + 1 and float(res["driver.w"][-1]) < w0
    assert np.all(np.asarray(res["owc.w"]) == w0)
    for column in ("owc.tau", "owc.W_loss", "owc.fn"):
        assert np.all(np.asarray(res[column]) == 0.0), column


def test_starting_with_the_driven_side_behind_the_driver_ends_the_run_and_says_why():
    asm = _driven_by_speed(OneWayClutch(J=0.5, w=1.0), 2.0, Constant(k=2.0), Constant(k=1.0))
    res = simulate_me(asm, 1.0, 0.1, TOL, record=["owc.w"])
    stop = res.settings["terminated"]
    assert stop["instance"] == "owc" and stop["time"] == 0.0
    assert "w_rel = flange_b.w - flange_a.w < 0" in stop["message"]


@pytest.mark.parametrize("version", (2, 3))
def test_the_fmu_validates_in_fmi2_and_fmi3_with_both_interfaces(version, tmp_path):
    from fmpy import read_model_description
    path = build_fmu(OneWayClutch(), tmp_path / "owc.fmu", fmi_version=version)
    assert validate_fmu(str(path)) == []
    md = read_model_description(str(path))
    assert md.modelExchange and md.coSimulation


@pytest.mark.parametrize("mode", MODES)
def test_a_free_clutch_at_rest_engages_sliding_the_way_its_driver_has_since_gone(mode):
    """MSL's free clutch takes, when pressed, the direction of w_rel at that moment. Here
    both sides start at rest, free (nothing pushes either way: the mode is 0, not a
    direction); the driver jumps into motion at 0.1 s (its acceleration a step) and the clutch is pressed at 0.5 s, the
    driven side then behind: it slides backward, J w' = cgeo mu fn forward, so
    w = F/J (t - 0.5) until it meets the driver, then locks. (A free clutch at rest took
    +1, whose indicator w_rel sat at 0 and left it downward without an event: in a
    co-simulation, CoupledClutches' clutch3 slid the wrong way once pressed at 0.9 s.)"""
    k, J, F, W = 2 * math.pi * 5.0, 1.0, 10.0, 2.0
    asm = _driven_by_speed(Clutch(J=J, w=0.0, fn_max=2 * F), 0.0,
                           Step(height=W, startTime=0.1), Step(startTime=0.5))
    res = _run(asm, mode, 1.0, 0.01, ["owc.w", "owc.mode", "driver.w"])
    # the driver's speed, filtered (w' = k (w_ref - w)) after w_ref steps to W at 0.1 s
    t_lock = brentq(lambda t: F / J * (t - 0.5) - W * (1 - math.exp(-k * (t - 0.1))),
                    0.5, 1.0, xtol=1e-14)
    t, w = np.asarray(res["time"]), np.asarray(res["owc.w"])
    sliding = (t > 0.5) & (t < t_lock)
    assert sliding.sum() > 2
    np.testing.assert_allclose(w[sliding], F / J * (t[sliding] - 0.5), atol=ACC * 10)
    assert np.all(w[t < 0.5] == 0.0)
    locks = [te for te, q in _events(res, "owc") if q == 0 and te > 0.5]
    # co-simulated, the driver's motion is held over an exchange step: the lock to a step
    assert locks and abs(locks[0] - t_lock) < (0.01 if mode == "cosim" else ACC), (locks, t_lock)
