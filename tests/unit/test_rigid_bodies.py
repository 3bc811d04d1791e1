"""TorqueFreeBody, WobblingDisk and Skate through their FMUs against the seed's analysis
(8.3, 8.4, 5.5) and closed forms worked out here."""
import math
import re

import numpy as np
import pytest

from components import ComponentError
from components.bodies.rigid_bodies import Skate, TorqueFreeBody, WobblingDisk

from conftest import simulate_in_fmpy

INERTIAS = dict(I_xx=1.0, I_yy=2.0, I_zz=3.0)


def _spin(axis, rate, nudge, stop_time=20.0, fmi_type="CoSimulation"):
    w = {"w_x": nudge, "w_y": nudge, "w_z": nudge}
    w[f"w_{axis}"] = rate
    body = TorqueFreeBody(**INERTIAS, **w)
    return simulate_in_fmpy(body, fmi_type, stop_time, 0.01, tolerance=1e-12,
                            output=["w_x", "w_y", "w_z", "H", "T", "H_X", "H_Y", "H_Z",
                                    "q_norm_error"])


@pytest.mark.parametrize("axis", ["x", "z"])
def test_spin_about_the_least_and_greatest_axes_stays_near_pure_spin(axis):
    res = _spin(axis, 2.0, 1e-3)
    others = [res[f"w_{a}"] for a in "xyz" if a != axis]
    assert max(np.abs(w).max() for w in others) < 1e-2  # bounded, a few times the nudge
    assert np.abs(res[f"w_{axis}"] - 2.0).max() < 1e-4


def test_spin_about_the_intermediate_axis_departs_at_the_linearised_rate():
    """Eqs. 8.3-8.5 about w = (0, W, 0): xi_x' = -(I_zz - I_yy)/I_xx W xi_z,
    xi_z' = -(I_yy - I_xx)/I_zz W xi_x, so xi_x'' = lambda^2 xi_x with
    lambda^2 = W^2 (I_yy - I_xx)(I_zz - I_yy) / (I_xx I_zz); from xi_z(0) = 0,
    xi_x = xi_0 cosh(lambda t) while it stays small."""
    W, xi0 = 1.0, 1e-7
    body = TorqueFreeBody(**INERTIAS, w_x=xi0, w_y=W, w_z=0.0)
    res = simulate_in_fmpy(body, "CoSimulation", 20.0, 0.01, tolerance=1e-12,
                           output=["w_x", "w_y", "w_z"])
    p = INERTIAS
    lam = W * math.sqrt((p["I_yy"] - p["I_xx"]) * (p["I_zz"] - p["I_yy"]) / (p["I_xx"] * p["I_zz"]))
    t, wx = res["time"], res["w_x"]
    linear = wx < 1e-3  # nonlinear corrections ~ (w_x / W)^2 stay below 1e-6
    assert t[linear][-1] > 15.0  # a growth of e^8.7 at least is compared
    predicted = xi0 * np.cosh(lam * t[linear])
    assert np.abs(wx[linear] / predicted - 1).max() < 1e-5
    assert wx.max() > 1e-3  # and it does depart


def test_angular_momentum_and_energy_are_conserved_through_a_flip():
    res = _spin("y", 1.0, 1e-3, stop_time=30.0)
    assert res["w_y"].min() < -0.9  # the body turned over (Dzhanibekov)
    H0 = res["H"][0]
    assert np.abs(res["H"] - H0).max() < 1e-10 * H0
    assert np.abs(res["T"] - res["T"][0]).max() < 1e-10 * res["T"][0]
    # the attitude carries H fixed in the ground frame, not only its magnitude
    for axis in "XYZ":
        assert np.abs(res[f"H_{axis}"] - res[f"H_{axis}"][0]).max() < 1e-9 * H0
    assert np.abs(res["q_norm_error"]).max() < 1e-10


def test_model_exchange_agrees():
    me = _spin("y", 1.0, 1e-3, stop_time=5.0, fmi_type="ModelExchange")
    cs = _spin("y", 1.0, 1e-3, stop_time=5.0)
    assert np.abs(me["w_x"] - cs["w_x"]).max() < 1e-7
    assert np.abs(me["H_X"] - cs["H_X"]).max() < 1e-7


@pytest.mark.parametrize("values, broken", [
    (dict(I_xx=1.0, I_yy=1.0, I_zz=2.5), "I_zz <= I_xx + I_yy"),
    (dict(I_xx=4.0, I_yy=1.0, I_zz=2.0), "I_xx <= I_yy + I_zz"),
    (dict(I_xx=1.0, I_yy=3.5, I_zz=2.0), "I_yy <= I_zz + I_xx"),
])
def test_inertias_must_obey_the_triangle_inequalities(values, broken):
    with pytest.raises(ComponentError, match=re.escape(broken)):
        TorqueFreeBody(**values)
    TorqueFreeBody(I_xx=1.0, I_yy=1.0, I_zz=2.0)  # a flat disk is on the boundary: allowed


def test_wobble_rate_is_twice_the_spin_rate_for_small_wobble():
    """A disk thrown with H along X, its axis theta0 off X. At phi = psi = 0 the ground X
    axis is (cos th, -sin th, 0) in body axes, so omega_body = I^-1 H =
    H (cos th / (2 I_s), -sin th / I_s, 0). The (1,3,1) rates that give it:
    phi' = H / I_s, theta' = 0, psi' = -H cos(th) / (2 I_s)."""
    I_s, H = 0.25, 0.5
    for theta0 in (0.01, 0.3):
        disk = WobblingDisk(I_s=I_s, theta=theta0, phi_dot=H / I_s, theta_dot=0.0,
                            psi_dot=-H * math.cos(theta0) / (2 * I_s))
        res = simulate_in_fmpy(disk, "CoSimulation", 10.0, 0.01, tolerance=1e-12,
                               output=["theta", "spin", "n_Y", "n_Z", "T"])
        t = res["time"]
        wobble_angle = np.unwrap(np.arctan2(res["n_Z"], res["n_Y"]))
        wobble_rate = np.polyfit(t, wobble_angle, 1)[0]
        spin = res["spin"]
        assert np.abs(spin - spin[0]).max() < 1e-10 and np.abs(res["theta"] - theta0).max() < 1e-10
        ratio = wobble_rate / spin[0]
        assert ratio == pytest.approx(2 / math.cos(theta0), rel=1e-9)  # seed's steady wobble
        if theta0 < 0.05:
            assert ratio == pytest.approx(2.0, abs=2 * theta0**2)  # "twice the spin rate"
        assert np.abs(res["T"] - res["T"][0]).max() < 1e-10 * res["T"][0]


def test_wobbling_disk_is_the_torque_free_disk():
    """The same throw as a TorqueFreeBody (I = diag(2, 1, 1) I_s, quaternion attitude):
    the disk axis must trace the same cone in the same time."""
    I_s, H, theta0 = 0.25, 0.5, 0.2
    disk = WobblingDisk(I_s=I_s, theta=theta0, phi_dot=H / I_s, psi_dot=-H * math.cos(theta0) / (2 * I_s))
    body = TorqueFreeBody(I_xx=2 * I_s, I_yy=I_s, I_zz=I_s,
                          q0=math.cos(theta0 / 2), q1=0.0, q2=0.0, q3=math.sin(theta0 / 2),
                          w_x=H * math.cos(theta0) / (2 * I_s), w_y=-H * math.sin(theta0) / I_s, w_z=0.0)
    a = simulate_in_fmpy(disk, "CoSimulation", 5.0, 0.05, tolerance=1e-12, output=["n_X", "n_Y", "n_Z"])
    b = simulate_in_fmpy(body, "CoSimulation", 5.0, 0.05, tolerance=1e-12, output=["x_X", "x_Y", "x_Z"])
    for axis in "XYZ":
        assert np.abs(a[f"n_{axis}"] - b[f"x_{axis}"]).max() < 1e-9


def skate_heading(t, theta0, u0, omega0, m, J, L):
    """Closed form of the seed's skate. With u = v_P . e and omega = theta', momentum along
    e and angular momentum about G give u' = -L omega^2, (J + m L^2) omega' = m L u omega;
    so u^2 + K omega^2 = V^2 (K = (J + m L^2)/m: energy), u = -V tanh(a (t - t0)),
    |omega| = (V / sqrt K) sech(a (t - t0)), a = L V / K, tanh(a t0) = u0 / V, and
    theta = theta0 + sign(omega0) (sqrt K / L) [gd(a (t - t0)) + gd(a t0)],
    gd(s) = atan(sinh s). Heading settles at theta0 + sign(omega0) (sqrt K / L)(pi/2 + gd(a t0))."""
    K = (J + m * L**2) / m
    V = math.sqrt(u0**2 + K * omega0**2)
    a = L * V / K
    t0 = math.atanh(u0 / V) / a
    sign, gd = math.copysign(1.0, omega0), lambda s: np.arctan(np.sinh(s))
    theta = theta0 + sign * math.sqrt(K) / L * (gd(a * (t - t0)) + gd(a * t0))
    settled = theta0 + sign * math.sqrt(K) / L * (math.pi / 2 + gd(a * t0))
    return theta, settled


def skate_start(theta, u, omega, L):
    """G's velocity from the blade speed u of P and omega: v_G = u e - L omega (k x e)."""
    return dict(theta=theta, omega=omega, v_x=u * math.cos(theta) + L * omega * math.sin(theta),
                v_y=u * math.sin(theta) - L * omega * math.cos(theta))


def test_skate_conserves_energy_and_constraint_and_its_heading_settles():
    m, J, L = 1.0, 0.1, 0.5
    theta0, u0, omega0 = 0.3, 1.0, 1.5
    skate = Skate(m=m, J=J, L=L, **skate_start(theta0, u0, omega0, L))
    res = simulate_in_fmpy(skate, "CoSimulation", 20.0, 0.01, tolerance=1e-12,
                           output=["theta", "omega", "u", "E", "constraint"])
    theta, settled = skate_heading(res["time"], theta0, u0, omega0, m, J, L)
    assert np.abs(res["theta"] - theta).max() < 1e-8
    assert abs(res["theta"][-1] - settled) < 1e-6  # settled: e^(-a 20) is far below
    assert abs(res["omega"][-1]) < 1e-6 and res["u"][-1] < 0  # ends sliding G first
    E = res["E"]
    assert np.abs(E - E[0]).max() < 1e-10 * E[0]
    assert np.abs(res["constraint"]).max() < 1e-10
    me = simulate_in_fmpy(skate, "ModelExchange", 20.0, 0.01, tolerance=1e-10, output=["theta"])
    assert abs(me["theta"][-1] - settled) < 1e-5


def test_wobbling_disk_runs_in_model_exchange():
    disk = WobblingDisk(theta=0.2, phi_dot=2.0, psi_dot=-math.cos(0.2))
    me = simulate_in_fmpy(disk, "ModelExchange", 5.0, 0.05, tolerance=1e-10, output=["n_Y", "n_Z"])
    cs = simulate_in_fmpy(disk, "CoSimulation", 5.0, 0.05, tolerance=1e-10, output=["n_Y", "n_Z"])
    assert me["time"][-1] == pytest.approx(5.0)
    assert np.abs(me["n_Y"] - cs["n_Y"]).max() < 1e-6 and np.abs(me["n_Z"] - cs["n_Z"]).max() < 1e-6


def test_wobbling_disk_ends_cleanly_at_its_singularity():
    """Axis driven onto X (theta -> 0): the run stops with a message, never NaN."""
    import numpy as np

    from assemblies import Assembly, cosimulate
    from components import WobblingDisk

    asm = Assembly("wobble")
    asm.add("disk", WobblingDisk(theta=0.2, theta_dot=-1.0, phi_dot=0.0, psi_dot=0.0))
    res = cosimulate(asm, stop_time=2.0, step=0.05, tolerance=1e-10)
    end = res.settings["terminated"]
    assert end is not None and "singular" in end["message"]
    assert abs(end["time"] - (0.2 - 1e-3)) < 1e-6  # theta' stays -1 with no wobble or spin
    assert all(np.isfinite(res[c]).all() for c in res.columns)
