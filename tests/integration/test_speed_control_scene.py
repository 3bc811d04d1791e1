"""The speed_control scene: a foreign PI controller FMU (CasADi's FMI 3 ME export) holds a
block sliding against kinetic Coulomb friction at a set speed.

The scene's references (assemblies/scenes/pi_controller.py) are checked here on their own
against scipy's solve_ivp on the loop written out as an ODE, and the scene is run from
Python and from the command line: its default mode is 'me', the modes that cannot run a
Model-Exchange-only FMU are refused in one line.
"""
import subprocess
import sys

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from assemblies import AssemblyError
from assemblies.run import run_scene_full
from assemblies.scenes import SCENES
from assemblies.scenes.pi_controller import (pi_error_envelope, pi_first_turning_point,
                                             pi_on_sliding_mass)
from assemblies.scenes.speed_control import BLOCK, CONTROLLER

SCENE_LOOP = dict(m=BLOCK["m"], friction=BLOCK["mu_k"] * BLOCK["m"] * BLOCK["g"], **CONTROLLER)
# a second loop, other numbers everywhere (still underdamped: k < 4 m / Ti)
OTHER_LOOP = dict(m=2.5, friction=1.7, v_ref=0.8, k=3.0, Ti=1.5, v0=0.2)


def written_out(loop, t_eval):
    """The loop as the ODE it is, m v' = k (v_ref - v + I/Ti) - friction, I' = v_ref - v,
    solved by scipy at rtol 1e-12: (v, f, I) at t_eval."""
    m, fk, v_ref, k, Ti = (loop[n] for n in ("m", "friction", "v_ref", "k", "Ti"))

    def rhs(t, y):
        v, integral = y
        return [(k * (v_ref - v + integral / Ti) - fk) / m, v_ref - v]

    sol = solve_ivp(rhs, (0.0, t_eval[-1]), [loop.get("v0", 0.0), 0.0], method="DOP853",
                    t_eval=t_eval, rtol=1e-12, atol=1e-14)
    v, integral = sol.y
    return v, k * (v_ref - v + integral / Ti), integral


@pytest.mark.parametrize("loop", [SCENE_LOOP, OTHER_LOOP], ids=["scene", "other"])
def test_hand_solved_loop_matches_the_written_out_ode(loop):
    t = np.linspace(0.0, 25.0, 2501)
    v_ode, f_ode, integral = written_out(loop, t)
    v, f = pi_on_sliding_mass(t, **loop)
    assert np.abs(v - v_ode).max() < 1e-8
    assert np.abs(f - f_ode).max() < 1e-8
    assert v_ode[1:].min() > 0  # sliding forward throughout: the closed form's premise
    # the error stays inside its envelope, and the integral settles at Ti friction / k
    e_bound = np.array([pi_error_envelope(ti, **loop) for ti in t])
    assert np.all(np.abs(loop["v_ref"] - v_ode) <= e_bound + 1e-10)
    if loop is SCENE_LOOP:
        assert abs(integral[-1] - loop["Ti"] * loop["friction"] / loop["k"]) < 1e-8


@pytest.mark.parametrize("loop", [SCENE_LOOP, OTHER_LOOP], ids=["scene", "other"])
def test_first_turning_point_is_where_the_ode_speed_peaks(loop):
    """The ODE's first v' = 0 (an event located by scipy) and the speed there."""
    m, fk, v_ref, k, Ti = (loop[n] for n in ("m", "friction", "v_ref", "k", "Ti"))

    def rhs(t, y):
        return [(k * (v_ref - y[0] + y[1] / Ti) - fk) / m, v_ref - y[0]]

    def turning(t, y):
        return rhs(t, y)[0]
    turning.terminal = True

    sol = solve_ivp(rhs, (0.0, 20.0), [loop.get("v0", 0.0), 0.0], method="DOP853",
                    events=turning, rtol=1e-12, atol=1e-14)
    t_peak, v_peak = pi_first_turning_point(**loop)
    assert abs(sol.t_events[0][0] - t_peak) < 1e-8
    assert abs(sol.y_events[0][0][0] - v_peak) < 1e-8
    assert v_peak > v_ref  # from below the set point, the first turn is an overshoot


def test_scene_runs_in_its_own_mode_and_its_figures_pass():
    assert SCENES["speed_control"].mode == "me"
    run = run_scene_full("speed_control")
    assert run.result.settings["scheme"] == "me"
    figures = {f.name: f for f in run.figures}
    assert set(figures) == {"v_loop", "f_loop", "v_peak", "v_end", "f_end", "not_sliding"}
    assert all(f.passed for f in run.figures), run.table()
    # every accuracy stated, none wider than 100 x the tolerance plus the stated terms
    assert all(0 <= f.bound < 1e-7 for f in run.figures)
    assert figures["v_peak"].reference == pytest.approx(pi_first_turning_point(**SCENE_LOOP)[1],
                                                        abs=1e-15)


def test_the_figures_follow_parameters_set_on_the_run():
    """--param reaches the foreign instance and the block; the references are read from
    the assembly, so they follow (v_ref 0.6, a heavier block, less friction)."""
    run = run_scene_full("speed_control", params={"ctrl.v_ref": 0.6, "block.m": 1.5,
                                                  "block.mu_k": 0.05, "block.mu_s": 0.08},
                         stop_time=30.0, step=0.05)
    figures = {f.name: f for f in run.figures}
    assert all(f.passed for f in run.figures), run.table()
    assert figures["v_end"].reference == 0.6
    assert figures["f_end"].reference == pytest.approx(0.05 * 1.5 * 9.81, rel=1e-15)


@pytest.mark.parametrize("mode", ["cosim", "monolithic"])
def test_modes_that_cannot_run_the_controller_are_refused(mode):
    with pytest.raises(AssemblyError, match=rf"mode '{mode}'.*instance 'ctrl'.*"
                                            r"run it with mode 'me'"):
        run_scene_full("speed_control", mode=mode)


def mechfmu(*args, cwd=None):
    return subprocess.run([sys.executable, "-m", "assemblies.cli", *args], capture_output=True,
                          text=True, cwd=cwd)


def test_command_line_runs_it_without_a_mode_and_refuses_the_others_in_one_line(tmp_path):
    proc = mechfmu("run", "speed_control", "--out", str(tmp_path))
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.splitlines()[-1] == "all 6 figures pass"
    for mode in ("cosim", "monolithic"):
        proc = mechfmu("run", "speed_control", "--mode", mode, "--out", str(tmp_path))
        assert proc.returncode == 2
        assert "Traceback" not in proc.stderr
        lines = proc.stderr.strip().splitlines()
        assert len(lines) == 1 and "run it with mode 'me'" in lines[0], proc.stderr
