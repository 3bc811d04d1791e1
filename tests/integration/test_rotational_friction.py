"""Brake, bearing friction and clutch: exact stick/slip against closed forms, in each mode.

References written from MSL's documented friction law (sliding torque cgeo mu(w) fn
opposing the relative motion, stuck while the torque needed stays within peak cgeo
mu(0) fn), integrated by hand: constant deceleration, an exponential for a linear
mu(w), break-away on a torque ramp, a clutch engaging a load at constant slip torque
(which dissipates exactly the kinetic energy it gives the load).
"""
import math

import numpy as np
import pytest

from assemblies import Assembly, cosimulate, simulate_me, simulate_monolithic
from components import ComponentError
from components.rotational.friction import BearingFriction, Brake, Clutch
from components.sources.rotational import ConstantTorque, Speed, Torque
from components.sources.signals import Constant, Ramp, Step

TOL = 1e-9
MODES = ("me", "monolithic", "cosim")


def _run(asm, mode, stop, step, record, extrapolation=0):
    if mode == "me":
        return simulate_me(asm, stop, step, TOL, record=record)
    if mode == "monolithic":
        return simulate_monolithic(asm, stop, step, TOL, record=record)
    # held inputs are exact for steps on the communication grid, linear extrapolation for
    # a ramp; either is wrong for one exchange step on the other kind
    return cosimulate(asm, stop, step, TOL, record=record, extrapolation=extrapolation,
                      event_sync=True)


def _event_times(res, instance, column):
    ev = res.events.get(instance)
    if ev is None:
        return []
    return list(zip(np.asarray(ev["time"]), np.asarray(ev[column])))


# an event time or a state at it: 100 x the tolerance (scene.solver_accuracy's rule)
ACC = 100 * TOL


@pytest.mark.parametrize("mode", MODES)
def test_a_brake_stops_an_inertia_at_constant_torque_and_holds_it(mode):
    """Engaged at t1 by a step of f_normalized, the brake decelerates J at cgeo mu fn / J:
    w = w0 - (t - t1) cgeo mu fn_max / J until it stops at t1 + J w0 / (cgeo mu fn_max);
    then a torque below peak cgeo mu fn_max cannot move it. The loss is J w0^2 / 2 plus
    nothing once stuck (a held torque does no work)."""
    J, w0, mu, cgeo, fn_max, t1, held = 0.5, 10.0, 0.4, 0.2, 50.0, 0.2, 1.5
    asm = Assembly("brake")
    asm.add("push", Step(height=1.0, startTime=t1))
    asm.add("brake", Brake(J=J, w=w0, **{"mu_pos[1,2]": mu}, cgeo=cgeo, fn_max=fn_max,
                           peak=1.2))
    asm.add("load", ConstantTorque(tau_constant=held))
    asm.connect("push.y", "brake.f_normalized")
    asm.connect("load.flange", "brake.flange_a")
    # the held torque also accelerates the shaft before the brake engages
    w1 = w0 + held / J * t1
    decel = (cgeo * mu * fn_max - held) / J
    t_stop = t1 + w1 / decel
    assert held < 1.2 * cgeo * mu * fn_max
    res = _run(asm, mode, 3.0, 0.01, ["brake.w", "brake.mode", "brake.W_loss", "load.W",
                                      "brake.E"])
    stops = [t for t, q in _event_times(res, "brake", "brake.mode") if q == 0]
    assert stops and abs(stops[0] - t_stop) < ACC * 10, (stops, t_stop)
    t = np.asarray(res["time"])
    w = np.where(t < t1, w0 + held / J * t, np.maximum(w1 - decel * (t - t1), 0.0))
    assert np.abs(res["brake.w"] - w).max() < ACC * w0
    assert float(res["brake.w"][-1]) == 0.0  # stuck means exactly at rest
    # energy: work of the held torque + initial kinetic = kinetic + friction loss
    balance = J * w0**2 / 2 + np.asarray(res["load.W"]) - np.asarray(res["brake.E"]) \
        - np.asarray(res["brake.W_loss"])
    assert np.abs(balance).max() < ACC * J * w0**2


@pytest.mark.parametrize("mode", MODES)
def test_a_speed_dependent_mu_table_gives_an_exponential_run_down(mode):
    """mu(w) = mu0 + k w (two rows): J w' = -c (mu0 + k w), c = cgeo fn / J, so
    w + mu0/k = (w0 + mu0/k) exp(-c k t); it stops at ln(1 + k w0 / mu0) / (c k)."""
    J, w0, mu0, k, fn = 0.2, 5.0, 0.3, 0.05, 2.0
    asm = Assembly("rundown")
    asm.add("on", Constant(k=1.0))
    asm.add("brake", Brake(J=J, w=w0, rows=2, fn_max=fn, **{
        "mu_pos[1,1]": 0.0, "mu_pos[1,2]": mu0, "mu_pos[2,1]": 1.0, "mu_pos[2,2]": mu0 + k}))
    asm.connect("on.y", "brake.f_normalized")
    c = fn / J
    t_stop = math.log(1 + k * w0 / mu0) / (c * k)
    res = _run(asm, mode, 1.2 * t_stop, t_stop / 50, ["brake.w", "brake.mode"])
    t = np.asarray(res["time"])
    w = np.maximum((w0 + mu0 / k) * np.exp(-c * k * t) - mu0 / k, 0.0)
    assert np.abs(res["brake.w"] - w).max() < ACC * w0
    stops = [t for t, q in _event_times(res, "brake", "brake.mode") if q == 0]
    assert stops and abs(stops[0] - t_stop) < ACC * 10


@pytest.mark.parametrize("mode", MODES)
def test_bearing_friction_breaks_away_at_peak_times_its_static_torque(mode):
    """A torque ramp s t on a shaft in a bearing: stuck until s t = peak tau0, then
    J w' = s t - tau0 (constant tau_pos): w = (s/2 (t^2 - tb^2) - tau0 (t - tb)) / J."""
    J, tau0, peak, slope = 0.1, 0.8, 1.5, 2.0
    asm = Assembly("breakaway")
    asm.add("ramp", Ramp(height=slope * 2.0, duration=2.0))
    asm.add("motor", Torque())
    asm.add("bearing", BearingFriction(J=J, peak=peak, **{"tau_pos[1,2]": tau0}))
    asm.connect("ramp.y", "motor.tau")
    asm.connect("motor.flange", "bearing.flange_a")
    tb = peak * tau0 / slope
    res = _run(asm, mode, 1.0, 0.01, ["bearing.w", "bearing.mode", "bearing.tau"], 1)
    slips = [t for t, q in _event_times(res, "bearing", "bearing.mode") if q == 1]
    assert slips and abs(slips[0] - tb) < ACC * 10, (slips, tb)
    t = np.asarray(res["time"])
    w = np.where(t < tb, 0.0, (slope / 2 * (t**2 - tb**2) - tau0 * (t - tb)) / J)
    assert np.abs(res["bearing.w"] - w).max() < ACC * 10
    # stuck, the bearing holds exactly the applied torque
    before = t < tb - 1e-6
    np.testing.assert_allclose(res["bearing.tau"][before], slope * t[before], atol=1e-9)


@pytest.mark.parametrize("mode", MODES)
def test_a_clutch_engages_a_load_and_loses_the_energy_it_gives_it(mode):
    """A driver at speed W (MSL Speed, settled long before), a load J at rest; engaged at
    t1 the clutch slips with torque cgeo mu fn, so w_load = cgeo mu fn (t - t1) / J until it
    locks at t1 + J W / (cgeo mu fn); the friction loss then equals the load's kinetic
    energy J W^2 / 2 (the classic half of the work the driver did)."""
    W, J, mu, cgeo, fn, t1 = 20.0, 0.05, 0.5, 0.1, 10.0, 0.5
    asm = Assembly("engage")
    asm.add("ref", Constant(k=W))
    asm.add("driver", Speed(f_crit=50.0))
    asm.add("press", Step(startTime=t1))
    asm.add("clutch", Clutch(J=J, cgeo=cgeo, fn_max=fn, **{"mu_pos[1,2]": mu}))
    asm.connect("ref.y", "driver.w_ref")
    asm.connect("driver.flange", "clutch.flange_a")
    asm.connect("press.y", "clutch.f_normalized")
    t_lock = t1 + J * W / (cgeo * mu * fn)
    res = _run(asm, mode, t_lock + 0.5, 0.01, ["clutch.w", "clutch.mode", "clutch.W_loss",
                                               "clutch.E", "clutch.w_rel"])
    locks = [t for t, q in _event_times(res, "clutch", "clutch.mode") if q == 0]
    # the driver's filter leaves W exp(-2 pi 50 t1) = 1e-67 of its step: nothing
    assert locks and abs(locks[-1] - t_lock) < ACC * 10, (locks, t_lock)
    t = np.asarray(res["time"])
    w = np.where(t < t1, 0.0, np.minimum(cgeo * mu * fn * (t - t1) / J, W))
    assert np.abs(res["clutch.w"] - w).max() < ACC * W * 10
    assert abs(float(res["clutch.W_loss"][-1]) - J * W**2 / 2) < ACC * J * W**2
    assert float(res["clutch.w_rel"][-1]) == 0.0


def test_a_friction_table_must_rise():
    with pytest.raises(ComponentError, match=r"Brake 'b': parameters violate mu_pos speeds "
                                             r"strictly increasing"):
        Brake("b", rows=2, **{"mu_pos[2,1]": 0.0})


def test_rows_set_after_construction_sizes_the_table():
    """`--param clutch.rows=2` sets the option on a built instance: the table gets its
    second row (speed 1 rad/s by default, MSL's value), the first keeps what was set,
    and shrinking drops the row again; a value for the new row is then accepted."""
    c = Clutch("c", **{"mu_pos[1,2]": 0.3})
    c.set("rows", 2)
    c.set("mu_pos[2,2]", 0.2)
    c.validate()
    assert (c.values["mu_pos[1,2]"], c.values["mu_pos[2,1]"], c.values["mu_pos[2,2]"]) == (0.3, 1.0, 0.2)
    c.set("rows", 1)
    assert "mu_pos[2,1]" not in c.values and c.values["mu_pos[1,2]"] == 0.3


def test_the_monolithic_master_solves_the_loop_of_a_locked_clutch():
    """J1 driven by a torque, the clutch's driven side J2 locked to it: one body, so
    both accelerate at tau / (J1 + J2) and the clutch carries J2 tau / (J1 + J2); with a
    torque beyond the clutch's peak the two slide apart at their own rates. Both are the
    algebraic loop J1.a -> clutch.flange_a.tau -> J1.a, solved per mode of the clutch."""
    from components.rotational.rigid import Inertia
    for tau, locked in ((2.0, True), (50.0, False)):
        asm = Assembly("lock")
        asm.add("drive", ConstantTorque(tau_constant=tau))
        asm.add("J1", Inertia(J=1.0))
        asm.add("on", Constant(k=1.0))
        asm.add("clutch", Clutch(J=3.0, fn_max=20.0, peak=1.1))  # slips above 0.55 * 20 * 4/3
        asm.connect("drive.flange", "J1.flange_a")
        asm.connect("J1.flange_b", "clutch.flange_a")
        asm.connect("on.y", "clutch.f_normalized")
        res = simulate_monolithic(asm, 1.0, 0.1, TOL, record=["J1.w", "clutch.w", "clutch.tau"])
        if locked:
            np.testing.assert_allclose(res["J1.w"], tau / 4.0 * res["time"], atol=1e-9)
            np.testing.assert_allclose(res["clutch.w"], res["J1.w"], atol=1e-12)
            np.testing.assert_allclose(res["clutch.tau"], -3.0 * tau / 4.0, atol=1e-9)
        else:  # sliding forward from the start: J1 gets tau - 10, the driven side 10
            t = np.asarray(res["time"])[1:]
            np.testing.assert_allclose(res["J1.w"][1:], (tau - 10.0) * t, atol=1e-9)
            np.testing.assert_allclose(res["clutch.w"][1:], 10.0 / 3.0 * t, atol=1e-9)


@pytest.mark.parametrize("engine", ("reference", "c"))
def test_a_locked_clutch_behind_a_sliding_one_stays_locked(engine):
    """J1 spinning free at W1, the clutches' driven sides J2 and J3 at w0 < W1: clutch1
    slides with torque T = cgeo mu fn, and clutch2 (engaged, carrying J3 T / (J2 + J3),
    far below its limit) holds J2 and J3 together, so J1 runs down at T / J1 and J2 = J3
    speed up at T / (J2 + J3) (run until just before clutch1 would lock). In floating
    point W1 + (w0 - W1) != w0 (10.1, 0.01): a jump that rewrote J2's speed that way
    when clutch1 started sliding made clutch2 read the rounding as a relative speed,
    slide, stop at once and chatter near t = 0 (issue 28, the nudged CoupledClutches)."""
    from assemblies.masters.monolithic import simulate_monolithic as reference
    from components.rotational.rigid import Inertia
    W1, w0, J1, J2, J3, mu, cgeo, fn = 10.1, 0.01, 1.0, 1.0, 1.0, 0.5, 1.0, 2.0
    asm = Assembly("held")
    asm.add("J1", Inertia(J=J1, w=W1))
    asm.add("on", Constant(k=1.0))
    asm.add("clutch1", Clutch(J=J2, w=w0, cgeo=cgeo, fn_max=fn, **{"mu_pos[1,2]": mu}))
    asm.add("clutch2", Clutch(J=J3, w=w0, cgeo=cgeo, fn_max=10 * fn, **{"mu_pos[1,2]": mu}))
    asm.connect("J1.flange_b", "clutch1.flange_a")
    asm.connect("clutch1.flange_b", "clutch2.flange_a")
    asm.connect("on.y", "clutch1.f_normalized")
    asm.connect("on.y", "clutch2.f_normalized")
    T = cgeo * mu * fn
    stop = 0.9 * (W1 - w0) / (T / J1 + T / (J2 + J3))  # clutch1 locks at 1 / 0.9 of it
    record = ["J1.w", "clutch1.w", "clutch2.w", "clutch1.mode", "clutch2.mode"]
    run = reference if engine == "reference" else simulate_monolithic
    res = run(asm, stop, stop / 10, TOL, record=record)
    t = np.asarray(res["time"])
    assert np.all(np.asarray(res["clutch1.mode"]) == -1)
    assert np.all(np.asarray(res["clutch2.mode"]) == 0)
    assert "clutch2" not in res.events  # no event of clutch2: it never left its lock
    np.testing.assert_array_equal(res["clutch2.w"], res["clutch1.w"])
    np.testing.assert_allclose(res["clutch1.w"], w0 + T / (J2 + J3) * t, atol=ACC * W1)
    np.testing.assert_allclose(res["J1.w"], W1 - T / J1 * t, atol=ACC * W1)
