"""FMUs from other tools in the compiled engine, checked against the closed loop solved by
hand (assemblies/scenes/pi_controller.py, re-exported by tests/foreign_fmus.py).

The loop: a PI speed controller (the foreign FMU) reads a mass's speed through our
``SpeedSensor`` and pushes it through our ``Force``; the mass (``MassWithFriction``,
m = 1 kg, mu_k = mu_s = 0.3, g = 1 m/s2: kinetic friction 0.3 N) starts at rest, breaks
away at t = 0 (the controller's first force, 2 N, beats the static 0.3 N) and slides
forward throughout (v > 0.95 m/s after the first second). With k = 2 N.s/m, Ti = 0.5 s the
speed error obeys e'' + 2 e' + 4 e = 0: underdamped, settling on v_ref = 1 m/s.
"""
import warnings

import numpy as np
import pytest

from assemblies import FMU, Assembly, cosimulate, simulate_me
from assemblies.engine.cosim import FixedStepFallback
from assemblies.scenes.speed_control import pi_speed_loop
from components import MassWithFriction

from foreign_fmus import euler_pi_on_sliding_mass, pi_on_sliding_mass, pythonfmu_pi_fmu

LOOP = dict(m=1.0, friction=0.3, v_ref=1.0, k=2.0, Ti=0.5)  # the FMUs' own defaults
STOP = 20.0  # e decays as exp(-t): 2e-9 left at the end


def pi_loop(controller) -> Assembly:
    return pi_speed_loop("pi_loop", FMU(controller),
                         MassWithFriction(m=LOOP["m"], g=1.0, mu_k=0.3, mu_s=0.3))


def test_casadi_model_exchange_controller_joins_the_one_integrator(casadi_pi):
    """mode 'me': the CasADi FMU's state (the error integral) is integrated with the
    mass's by the engine's DOPRI5 at tolerance 1e-10. Asserted: speed and force within
    1e-8 of the closed form at every output point (100 x the tolerance, the accuracy the
    project's scene figures state for the solver; measured 1.1e-10 and 2.2e-10), the
    block sliding forward throughout, the speed settled on the set point."""
    res = simulate_me(pi_loop(casadi_pi), STOP, 0.1, 1e-10)
    v, f = pi_on_sliding_mass(res["time"], **LOOP)
    assert np.abs(res["block.v_abs"] - v).max() < 1e-8
    assert np.abs(res["ctrl.f"] - f).max() < 1e-8
    assert np.all(res["block.mode"] == 1)
    assert abs(res["block.v_abs"][-1] - LOOP["v_ref"]) < 1e-8
    assert abs(res["ctrl.f"][-1] - LOOP["friction"]) < 1e-8  # all the force goes to friction


def test_a_parameter_set_on_the_foreign_instance_reaches_its_fmu(casadi_pi):
    asm = pi_loop(casadi_pi)
    asm.set("ctrl.v_ref", 0.5)
    res = simulate_me(asm, STOP, 1.0, 1e-10, record=["block.v_abs", "ctrl.I"])
    assert abs(res["block.v_abs"][-1] - 0.5) < 1e-8
    # a local variable of the FMU can be recorded by name; at rest I holds Ti friction / k
    assert abs(res["ctrl.I"][-1] - LOOP["Ti"] * LOOP["friction"] / LOOP["k"]) < 1e-8


def test_pythonfmu_co_simulation_controller_is_forward_euler_on_the_loop(pythonfmu_pi):
    """mode 'cosim', pythonfmu's FMI 2 CS FMU (canGetAndSetFMUstate false). Asking for
    adaptive steps falls back to fixed ones, with a warning and a note in the settings.
    With inputs held over each step (extrapolation 0, Jacobi) the coupled system is
    exactly forward Euler on (v, I) (see euler_pi_on_sliding_mass): asserted to 1e-12,
    round-off (measured 7e-16). Against the continuous closed form the error is first
    order in the step: asserted below h (measured 0.80 h) and halving with h (ratio
    in 1.9..2.1, measured 2.01)."""
    errors = []
    for h in (0.01, 0.005):
        with pytest.warns(FixedStepFallback, match=r"adaptive co-simulation rolls steps back, "
                                                   r"but FMU instance 'ctrl' cannot get and "
                                                   r"set its state"):
            res = cosimulate(pi_loop(pythonfmu_pi), STOP, h, 1e-10, adaptive=True,
                             extrapolation=0)
        assert not res.settings["adaptive"] and "fixed communication steps" in \
            res.settings["fallback"]
        v_euler, f_euler = euler_pi_on_sliding_mass(len(res["time"]) - 1, h, **LOOP)
        assert np.abs(res["block.v_abs"] - v_euler).max() < 1e-12
        assert np.abs(res["ctrl.f"] - f_euler).max() < 1e-12
        v, _ = pi_on_sliding_mass(res["time"], **LOOP)
        errors.append(np.abs(res["block.v_abs"] - v).max())
        assert errors[-1] < h
        assert abs(res["block.v_abs"][-1] - LOOP["v_ref"]) < 1e-8
    assert 1.9 < errors[0] / errors[1] < 2.1


def test_adaptive_co_simulation_rolls_a_foreign_fmu_back_through_its_state():
    """pythonfmu built with --handle-state can get and set its state (its variables as
    JSON), so adaptive steps with rollback run on it. Asserted: no fallback, the global
    error in v below the step tolerance 1e-5 (measured 1.7e-6; 0.14 and 0.5 of tol at
    1e-4 and 1e-6: the controller bounds each step's error, the loop's decay keeps the
    sum from growing)."""
    tol = 1e-5
    with warnings.catch_warnings():
        warnings.simplefilter("error", FixedStepFallback)
        res = cosimulate(pi_loop(pythonfmu_pi_fmu(handle_state=True)), STOP, 0.1, 1e-10,
                         adaptive=True, extrapolation=1, tol=tol)
    assert res.settings["adaptive"] and res.settings["fallback"] is None
    v, _ = pi_on_sliding_mass(res["time"], **LOOP)
    assert np.abs(res["block.v_abs"] - v).max() < tol


def test_an_unconnected_input_keeps_the_start_value_it_is_given(casadi_pi):
    asm = Assembly("lone")
    asm.add("ctrl", FMU(casadi_pi, v=0.5))  # e = 0.5 held: I = 0.5 t, f = 2 (0.5 + 2 I)
    res = simulate_me(asm, 1.0, 0.5, 1e-10, record=["ctrl.f", "ctrl.I"])
    assert np.allclose(res["ctrl.I"], [0.0, 0.25, 0.5], rtol=0, atol=1e-12)
    assert np.allclose(res["ctrl.f"], [1.0, 2.0, 3.0], rtol=0, atol=1e-12)
