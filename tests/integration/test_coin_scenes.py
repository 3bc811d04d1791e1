"""The rolling coin through its FMU (our master and fmpy's, Co-Simulation and Model
Exchange), the coin scenes' figures, and every new FMU's validation."""
import math

import numpy as np
import pytest
from fmpy.validation import validate_fmu

from assemblies import Assembly, cosimulate
from assemblies.scenes.coin_plot import plot_coin
from assemblies.scenes.coin import COIN_SCENES
from components.bodies.rigid_bodies import Skate, TorqueFreeBody, WobblingDisk
from components.bodies.rolling_coin import RollingCoin
from fmus import build_fmu

from conftest import simulate_in_fmpy

G, R = 9.81, 1.0
V_CRITICAL = math.sqrt(G * R / 3)  # thin uniform disk; derived in tests/unit/test_rolling_coin.py


@pytest.mark.parametrize("cls", [RollingCoin, TorqueFreeBody, WobblingDisk, Skate])
def test_fmu_validates_cleanly(cls, tmp_path):
    assert validate_fmu(str(build_fmu(cls(), tmp_path / f"{cls.__name__}.fmu"))) == []


def _coin_run(stop_time, **starts):
    asm = Assembly("coin")
    asm.add("coin", RollingCoin(m=1.0, R=R, g=G, **starts))
    return cosimulate(asm, stop_time=stop_time, step=0.01, tolerance=1e-12,
                      record=["coin.theta", "coin.lean", "coin.E", "coin.v_C_x", "coin.v_C_y",
                              "coin.v_C_z", "coin.x_C", "coin.y_C", "coin.x", "coin.y"])


def test_energy_and_no_slip_hold_over_ten_seconds_of_general_rolling():
    """A wandering, nutating start (not a steady motion)."""
    res = _coin_run(10.0, theta=1.1, phi_dot=1.5, theta_dot=0.8, psi_dot=-6.0)
    assert res.settings["terminated"] is None
    lean = res["coin.lean"]
    assert lean.max() - lean.min() > 0.05  # it nutates: not a trivially steady run
    E = res["coin.E"]
    assert np.abs(E - E[0]).max() < 1e-9 * abs(E[0])
    assert max(np.abs(res[f"coin.v_C_{k}"]).max() for k in "xyz") < 1e-9


@pytest.mark.parametrize("fmi_type", ["CoSimulation", "ModelExchange"])
def test_fmpy_runs_the_coin(fmi_type):
    coin = RollingCoin(theta=1.1, phi_dot=1.5, theta_dot=0.8, psi_dot=-6.0)
    res = simulate_in_fmpy(coin, fmi_type, 10.0, 0.01, tolerance=1e-10,
                           output=["theta", "E", "v_C_x", "v_C_y"])
    assert res["time"][-1] == pytest.approx(10.0)
    E = res["E"]
    assert np.abs(E - E[0]).max() < 1e-7 * abs(E[0])
    reference = _coin_run(10.0, theta=1.1, phi_dot=1.5, theta_dot=0.8, psi_dot=-6.0)
    assert np.abs(res["theta"] - reference["coin.theta"]).max() < 1e-5


@pytest.mark.parametrize("ratio", [1.1, 0.9])
def test_upright_rolling_is_stable_only_above_the_critical_speed(ratio):
    lean0 = 1e-3
    res = _coin_run(20.0, theta=math.pi / 2 - lean0, phi_dot=0.0, theta_dot=0.0,
                    psi_dot=-ratio * V_CRITICAL / R)
    largest = np.abs(res["coin.lean"]).max()
    if ratio > 1:  # bounded, never past the linear prediction's |2 k / (k - b/W^2) - 1| ~ 10.5
        assert res.settings["terminated"] is None and largest < 12 * lean0
    else:  # grows out of the linear range (e^(1.2 t)): it leans over or falls flat
        assert largest > 0.3


def steady_precession_slow_root(theta, spin):
    """(5/4) s c phi'^2 + (3/2) s psi' phi' + (g/R) c = 0, derived in test_rolling_coin."""
    s, c = math.sin(theta), math.cos(theta)
    return min(np.roots([1.25 * s * c, 1.5 * s * spin, G / R * c]).real, key=abs)


def test_steady_circular_rolling_keeps_its_lean():
    theta, spin = math.pi / 3, -8.0
    precession = steady_precession_slow_root(theta, spin)
    res = _coin_run(10.0, theta=theta, phi_dot=precession, theta_dot=0.0, psi_dot=spin)
    assert np.abs(res["coin.theta"] - theta).max() < 1e-6
    # the test has teeth: 0.1 % off the relation, the lean wanders 50 times as far
    off = _coin_run(10.0, theta=theta, phi_dot=precession * 1.001, theta_dot=0.0, psi_dot=spin)
    assert np.abs(off["coin.theta"] - theta).max() > 2e-5


def test_a_coin_that_falls_flat_ends_the_run_with_the_message(tmp_path):
    """Released leaning, at rest: it falls; the run stops where sin(theta) = sin(theta_min)."""
    res = _coin_run(5.0, theta=0.5, phi_dot=0.0, theta_dot=0.0, psi_dot=0.0)
    end = res.settings["terminated"]
    assert end["instance"] == "coin" and "coin fell flat at t = " in end["message"]
    assert 0 < end["time"] < 5.0
    assert res["coin.theta"][-1] == pytest.approx(0.01, abs=1e-8)  # theta_min, located
    for column in res.columns:
        assert np.all(np.isfinite(res[column])), column
    E = res["coin.E"]
    assert np.abs(E - E[0]).max() < 1e-9 * abs(E[0])
    plot_coin(res, "falls flat", tmp_path / "fall.png")
    assert (tmp_path / "fall.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_model_exchange_importer_is_told_the_coin_fell(capfd):
    res = simulate_in_fmpy(RollingCoin(theta=0.5, phi_dot=0.0, psi_dot=0.0), "ModelExchange",
                           stop_time=5.0, output_interval=0.01, output=["theta", "E"])
    assert np.all(np.isfinite(res["theta"])) and np.all(np.isfinite(res["E"]))
    assert res["theta"][-1] == pytest.approx(0.01, abs=1e-6)
    assert "coin fell flat at t = " in capfd.readouterr().out


@pytest.mark.parametrize("name", sorted(COIN_SCENES))
def test_scene_figures_meet_their_references(name, tmp_path):
    sc = COIN_SCENES[name]
    asm = sc.build()
    res = cosimulate(asm, sc.stop_time, sc.step, sc.tolerance, record=sc.record)
    figures = {f.name: f for f in sc.figures(res, asm)}
    limits = {"E_drift": 1e-9, "v_C_max": 1e-9, "lean_drift": 1e-6, "H_drift": 1e-10,
              "T_drift": 1e-10, "constraint": 1e-10, "theta_end": 1e-8, "flipped": 0.05,
              "r_contact": 1e-8 * figures.get("r_contact", figures[next(iter(figures))]).reference,
              # nonlinear corrections of a 1e-2 rad wobble shift the frequency by ~1e-4
              "v_crit": 1e-3 * V_CRITICAL, "lean_max": 0.01, "growth": 1e-4}
    for f in figures.values():
        assert f.error <= limits[f.name], f
        assert f.passed, f
    if name.startswith("coin"):
        plot_coin(res, name, tmp_path / f"{name}.png")


@pytest.mark.parametrize("step", [0.01, 2.0])
def test_flip_growth_crossing_is_interpolated_within_its_stated_accuracy(step):
    """torque_free_flip's growth rate comes from where w_x reaches 10 xi0, located on the
    cubic Hermite interpolant of w_x with Euler's w_x' (seed 8.3); its accuracy states the
    interpolant's O((lam h)^4) error, so an output step of 2 s (a third of the time to
    the crossing) still meets it, against the closed form lam = W sqrt((I_yy - I_xx)
    (I_zz - I_yy) / (I_xx I_zz)) = 1 / sqrt(3)."""
    from assemblies.run import run_scene_full
    growth = next(f for f in run_scene_full("torque_free_flip", stop_time=10.0,
                                            step=step).figures if f.name == "growth")
    assert growth.reference == pytest.approx(1 / math.sqrt(3), rel=1e-14)
    assert growth.passed, (growth.measured, growth.error, growth.bound)
    assert growth.error < 0.01 * growth.reference


@pytest.mark.parametrize("name", ["coin_rolling", "coin_upright", "coin_circle"])
def test_joined_run_of_a_coin_that_can_fall_passes(name):
    """The coin can end a run (it falls flat): its joined FMU carries that, and the scene
    runs in monolithic mode with every figure passing."""
    from assemblies.run import run_scene_full
    run = run_scene_full(name, mode="monolithic")
    assert run.passed, run.table()
    assert run.result.settings["scheme"] == "monolithic"
    assert run.result.settings["terminated"] is None  # the scenes' coins keep rolling


def test_coin_circle_without_turning_runs_and_its_circle_figure_fails():
    """phi' = 0: the contact point runs along a straight line (a circle of infinite
    radius; the lean is then no steady motion). The run goes through and the circle figure
    fails, where the steady-motion relation divided by phi' and ended in a traceback."""
    from assemblies.run import run_scene_full
    run = run_scene_full("coin_circle", stop_time=1.0, params={"coin.phi_dot": 0.0}, plot=False)
    r_contact = next(f for f in run.figures if f.name == "r_contact")
    assert r_contact.reference == math.inf and not r_contact.passed
