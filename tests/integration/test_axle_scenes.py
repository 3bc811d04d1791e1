"""The rigid body on an axle as an FMU: seed 8.5's disk swinging, in fmpy and in the scene."""
import math

import numpy as np
import pytest
from fmpy.validation import validate_fmu
from scipy.integrate import quad

from assemblies import cosimulate
from assemblies.scenes.axle import AXLE_SCENES, period_from_crossings, seed_disk
from components.bodies.axle import RigidBodyOnAxle
from fmus import build_fmu

from conftest import simulate_in_fmpy

G = 9.81
OMEGA0 = math.sqrt(4 * G / 7)  # seed 8.5 with R = 1


def pendulum_period_by_quadrature(omega0, amplitude):
    """Energy integral of theta'' = -omega0^2 sin(theta), which is the disk's exact equation
    (test_seed_disk_full_equation_is_a_pendulum): with theta = 2 asin(k sin u), k =
    sin(amplitude/2), T = (4/omega0) int_0^{pi/2} du / sqrt(1 - k^2 sin^2 u)."""
    k = math.sin(amplitude / 2)
    value, _ = quad(lambda u: 1 / math.sqrt(1 - (k * math.sin(u)) ** 2), 0, math.pi / 2,
                    epsabs=0, epsrel=1e-13)
    return 4 * value / omega0


def swing(theta0, fmi_type="CoSimulation", stop_time=12.0, step=0.01, tolerance=1e-12, **kw):
    body = seed_disk(theta0=theta0, **kw)
    return body, simulate_in_fmpy(body, fmi_type, stop_time, step, tolerance=tolerance)


def test_small_amplitude_run_gives_the_seed_frequency():
    _, res = swing(1e-3)
    T = period_from_crossings(res["time"], res["theta"], res["omega"])
    assert abs(2 * math.pi / T / OMEGA0 - 1) < 1e-6


@pytest.mark.parametrize("fmi_type, drift", [("CoSimulation", 1e-8), ("ModelExchange", 1e-6)])
def test_energy_is_conserved_without_friction(fmi_type, drift):
    _, res = swing(1.0, fmi_type, tolerance=1e-10)
    E0 = 9.81 * 0.5 * (1 - math.cos(1.0))  # released from rest: all potential, m g z_G
    assert res["E"][0] == pytest.approx(E0, rel=1e-14)
    assert np.abs(res["E"] - E0).max() < drift * E0


def test_large_amplitude_period_is_the_pendulum_period():
    _, small = swing(1e-3)
    _, large = swing(2.0)
    T_small = period_from_crossings(small["time"], small["theta"], small["omega"])
    T_large = period_from_crossings(large["time"], large["theta"], large["omega"])
    assert T_large > T_small * 1.2  # 2 rad: the seed's linearisation is far off
    assert T_large == pytest.approx(pendulum_period_by_quadrature(OMEGA0, 2.0), rel=1e-8)


@pytest.mark.parametrize("fmi_type", ["CoSimulation", "ModelExchange"])
def test_bearing_reaction_balances_gravity_and_inertia_of_G(fmi_type):
    """R - m g k = m a_G, with a_G from the recorded theta, omega and axle.a (R = 1, m = 2)."""
    m = 2.0
    _, res = swing(2.5, fmi_type, stop_time=6.0, step=0.05, tolerance=1e-8, m=m)
    th, w, a = res["theta"], res["omega"], res["axle.a"]
    s = math.sqrt(0.5)
    n = np.array([0.0, s, s])
    # r(theta) = cos r0 + sin (n x r0) + (1 - cos) (n.r0) n with r0 = j, n x j = -s i
    r = (np.outer(np.cos(th), [0, 1, 0]) + np.outer(np.sin(th), [-s, 0, 0])
         + np.outer((1 - np.cos(th)) * s, n))
    n_x_r = np.cross(n, r)
    a_G = a[:, None] * n_x_r + (w**2)[:, None] * np.cross(n, n_x_r)
    reaction = np.column_stack([res["R_x"], res["R_y"], res["R_z"]])
    residual = reaction - m * a_G - m * G * np.array([0.0, 0.0, 1.0])
    assert np.abs(residual).max() < 1e-9
    assert np.abs(res["axle.a"] + OMEGA0**2 * np.sin(th)).max() < 1e-9  # the pendulum law


def test_coulomb_bearing_loses_tau_c_times_the_swept_angle():
    """Between two turning points (omega = 0, located as events) all energy lost is friction
    work: V(theta_k) - V(theta_k+1) = tau_c |theta_k+1 - theta_k|; at the end it sticks
    where gravity's torque is within tau_c."""
    tau_c, k = 0.4, 9.81 / 2  # V = k (1 - cos theta) for the disk with m = R = 1
    body = seed_disk(theta0=1.5, bearing_friction="coulomb", tau_c=tau_c)
    res = simulate_in_fmpy(body, "ModelExchange", 20.0, 0.05, tolerance=1e-10)
    t, th, mode = res["time"], res["theta"], res["mode"]
    turning = [th[0]] + [th[i] for i in range(1, len(t)) if t[i] == t[i - 1]
                         and mode[i] != mode[i - 1]]
    assert len(turning) >= 4
    for a, b in zip(turning, turning[1:]):
        if a != b:
            assert k * (math.cos(b) - math.cos(a)) == pytest.approx(tau_c * abs(b - a), abs=1e-6)
    assert mode[-1] == 0 and res["omega"][-1] == 0.0
    assert k * abs(math.sin(th[-1])) <= tau_c


VARIANTS = [(profile.name, law) for profile in RigidBodyOnAxle.profiles
            for law in ("none", "coulomb")]


@pytest.mark.parametrize("profile, law", VARIANTS, ids=[f"{p}-{law}" for p, law in VARIANTS])
def test_every_axle_fmu_validates_and_runs_in_fmpy(profile, law):
    body = seed_disk(theta0=0.5, profile=profile, bearing_friction=law, tau_c=0.2, c=0.05)
    assert validate_fmu(str(build_fmu(body))) == []
    runs = {t: simulate_in_fmpy(body, t, 3.0, 0.1, tolerance=1e-10)
            for t in ("ModelExchange", "CoSimulation")}
    me, cs = runs["ModelExchange"], runs["CoSimulation"]
    # Model Exchange adds a row before and after each event; theta is continuous there
    np.testing.assert_allclose(np.interp(cs["time"], me["time"], me["theta"]), cs["theta"], atol=1e-5)


def run_axle_scene(**params):
    sc = AXLE_SCENES["axle_pendulum"]
    asm = sc.build()
    for key, value in params.items():
        asm.set(key, value)
    res = cosimulate(asm, sc.stop_time, sc.step, sc.tolerance, record=sc.record)
    return {f.name: f for f in sc.figures(res, asm)}, res


def test_axle_pendulum_scene_figures():
    figures, res = run_axle_scene()
    assert "body.theta" in res and res["body.theta"][0] == 1.0
    assert figures["omega0"].error < 1e-12 * OMEGA0
    assert figures["T"].reference == pytest.approx(pendulum_period_by_quadrature(OMEGA0, 1.0),
                                                   rel=1e-13)
    assert figures["T"].error < 1e-8
    assert figures["E_drift"].error < 1e-8
    assert all(f.passed for f in figures.values()), figures


def test_axle_pendulum_takes_theta0():
    figures, res = run_axle_scene(**{"body.theta0": 0.2})
    assert res["body.theta"][0] == 0.2
    assert figures["T"].error < 1e-8
    with pytest.raises(ValueError, match="not a number"):
        run_axle_scene(**{"body.theta0": "wide"})
