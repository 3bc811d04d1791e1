"""MSL's rotational elements, sources and sensors against closed forms, in each mode.

Each assembly below has an analytic solution written from the elements' documented
equations (MSL's), not from our code: a gear's reflected stiffness, an inertia spun up
against a damper, a quadratic drag, a filtered speed source. Energy balances use the
work and loss states the sources and dampers integrate.
"""
import math

import numpy as np
import pytest

from assemblies import Assembly, cosimulate, simulate_me, simulate_monolithic
from components import ComponentError
from components.rotational.elements import Damper, Spring
from components.rotational.rigid import Fixed, IdealGear, Inertia
from components.sensors.rotational import AngleSensor, PowerSensor, SpeedSensor, TorqueSensor
from components.sources.rotational import ConstantTorque, QuadraticSpeedDependentTorque, Speed
from components.sources.signals import Constant

TOL = 1e-8
MODES = ("me", "monolithic", "cosim")


def _run(asm, mode, stop, step, record):
    if mode == "me":
        return simulate_me(asm, stop, step, TOL, record=record)
    if mode == "monolithic":
        return simulate_monolithic(asm, stop, step, TOL, record=record)
    return cosimulate(asm, stop, 1e-3, TOL, record=record, extrapolation=2)


# cosim exchanges at 1 ms with quadratic extrapolation of the inputs: its coupling error
# on these smooth motions is a few 1e-6 (a property of the exchange step, not of the FMUs)
ACCURACY = {"me": 1e-6, "monolithic": 1e-6, "cosim": 1e-4}


@pytest.mark.parametrize("mode", MODES)
def test_a_gear_reflects_the_spring_stiffness_by_ratio_squared(mode):
    """J phi'' = -c phi / ratio^2 (phi_b = phi_a / ratio, tau_a = -tau_b / ratio): the
    inertia oscillates at sqrt(c / (J ratio^2)); the torque and power sensors between
    gear and spring read the spring's reaction and its power, the angle sensor phi."""
    J, c, ratio, phi0 = 0.5, 200.0, 4.0, 0.3
    asm = Assembly("gear")
    asm.add("rotor", Inertia(J=J, phi=phi0))
    asm.add("gear", IdealGear(ratio=ratio))
    asm.add("torque", TorqueSensor())
    asm.add("power", PowerSensor())
    asm.add("spring", Spring(c=c))
    asm.add("wall", Fixed())
    asm.add("angle", AngleSensor())
    for a, b in (("rotor.flange_b", "gear.flange_a"), ("gear.flange_b", "torque.flange_a"),
                 ("torque.flange_b", "power.flange_a"), ("power.flange_b", "spring.flange_a"),
                 ("spring.flange_b", "wall.flange"), ("rotor.flange_a", "angle.flange")):
        asm.connect(a, b)
    omega = math.sqrt(c / (J * ratio**2))
    stop = 2 * math.pi / omega * 1.25
    res = _run(asm, mode, stop, stop / 100, ["rotor.phi", "rotor.w", "torque.tau", "power.power",
                                              "angle.phi"])
    t = np.asarray(res["time"])
    phi = phi0 * np.cos(omega * t)
    w = -phi0 * omega * np.sin(omega * t)
    acc = ACCURACY[mode]
    assert np.abs(res["rotor.phi"] - phi).max() < acc * 10
    # the shaft after the gear turns phi / ratio; the spring, twisted by -phi / ratio,
    # pushes back with c phi / ratio, the cut torque at the sensors' flange_a (MSL's
    # tau = flange_a.tau, power = flange_a.tau w)
    assert np.abs(res["torque.tau"] - c * phi / ratio).max() < acc * 10 * c
    assert np.abs(res["power.power"] - c * phi / ratio * (w / ratio)).max() < acc * 10 * c
    np.testing.assert_allclose(res["angle.phi"], res["rotor.phi"], atol=1e-12)



@pytest.mark.parametrize("mode", MODES)
def test_constant_torque_spins_an_inertia_up_against_a_damper(mode):
    """J w' = tau - d w from rest: w = tau/d (1 - exp(-d t / J)); the work the source
    did equals the kinetic energy plus what the damper dissipated (both integrated by
    their own states: to the solver's accuracy)."""
    J, d, tau = 2.0, 3.0, 1.5
    asm = Assembly("spin_up")
    asm.add("drive", ConstantTorque(tau_constant=tau))
    asm.add("rotor", Inertia(J=J))
    asm.add("damper", Damper(d=d))
    asm.add("wall", Fixed())
    asm.connect("drive.flange", "rotor.flange_a")
    asm.connect("rotor.flange_b", "damper.flange_a")
    asm.connect("damper.flange_b", "wall.flange")
    res = _run(asm, mode, 3.0, 0.05, ["rotor.w", "rotor.E", "drive.W", "damper.W_loss"])
    t = np.asarray(res["time"])
    w = tau / d * (1 - np.exp(-d * t / J))
    acc = ACCURACY[mode]
    assert np.abs(res["rotor.w"] - w).max() < 10 * acc
    balance = np.asarray(res["drive.W"]) - np.asarray(res["rotor.E"]) - np.asarray(res["damper.W_loss"])
    assert np.abs(balance).max() < 10 * acc * max(1.0, float(np.max(res["drive.W"])))
    assert float(res["damper.W_loss"][-1]) > 0.1  # the balance is not trivially 0 = 0


@pytest.mark.parametrize("mode", MODES)
def test_quadratic_drag_slows_an_inertia_as_1_over_t(mode):
    """J w' = tau_nominal (w / w_nominal)^2 sign(w) with tau_nominal < 0 (TorqueDirection
    false): w = w0 / (1 + k w0 t), k = -tau_nominal / (J w_nominal^2); the drag's work is
    the kinetic energy lost."""
    J, tau_n, w_n, w0 = 0.5, -2.0, 10.0, 8.0
    asm = Assembly("drag")
    asm.add("rotor", Inertia(J=J, w=w0))
    asm.add("fan", QuadraticSpeedDependentTorque(tau_nominal=tau_n, w_nominal=w_n,
                                                 TorqueDirection="false"))
    asm.add("speed", SpeedSensor())
    asm.connect("rotor.flange_a", "fan.flange")
    asm.connect("rotor.flange_b", "speed.flange")
    res = _run(asm, mode, 4.0, 0.05, ["rotor.w", "rotor.E", "fan.W", "speed.w"])
    t = np.asarray(res["time"])
    k = -tau_n / (J * w_n**2)
    acc = ACCURACY[mode]
    assert np.abs(res["rotor.w"] - w0 / (1 + k * w0 * t)).max() < 10 * acc * w0
    np.testing.assert_allclose(res["speed.w"], res["rotor.w"], atol=1e-12)
    lost = J * w0**2 / 2 - np.asarray(res["rotor.E"])
    assert np.abs(-np.asarray(res["fan.W"]) - lost).max() < 10 * acc * J * w0**2


@pytest.mark.parametrize("mode", MODES)
def test_a_speed_source_follows_its_reference_through_msl_first_order_filter(mode):
    """MSL Speed (exact = false): w' = (w_ref - w) w_crit, so w = w_ref (1 - exp(-w_crit t))
    whatever it drives (here an inertia through a spring: the source takes the torque)."""
    w_ref, f_crit = 3.0, 2.0
    asm = Assembly("speed_source")
    asm.add("ref", Constant(k=w_ref))
    asm.add("motor", Speed(f_crit=f_crit))
    asm.add("shaft", Spring(c=50.0))
    asm.add("load", Inertia(J=0.2))
    asm.connect("ref.y", "motor.w_ref")
    asm.connect("motor.flange", "shaft.flange_a")
    asm.connect("shaft.flange_b", "load.flange_a")
    res = _run(asm, mode, 1.0, 0.02, ["motor.w", "load.w"])
    t = np.asarray(res["time"])
    w = w_ref * (1 - np.exp(-2 * math.pi * f_crit * t))
    assert np.abs(res["motor.w"] - w).max() < 10 * ACCURACY[mode] * w_ref
    assert float(np.max(np.abs(res["load.w"]))) > 1.0  # the load was driven


@pytest.mark.parametrize("ratio, words", [
    (0.0, r"IdealGear 'gear': parameters violate ratio != 0"),
])
def test_a_gear_of_ratio_zero_is_one_line(ratio, words):
    with pytest.raises(ComponentError, match=words):
        IdealGear("gear", ratio=ratio)


def test_an_inertia_of_zero_is_one_line():
    with pytest.raises(ComponentError, match=r"Inertia 'rotor': parameter J = 0 is not allowed; "
                                             r"J \(moment of inertia, kg.m2\) must be > 0"):
        Inertia("rotor", J=0.0)
