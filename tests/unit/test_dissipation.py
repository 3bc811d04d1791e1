"""NutationDamperBody (seed 8.3.1): its equations against the conservation laws that hold
at every state, its linearisation against the scene's hand-derived one, and what it does
without the damper."""
import math
import re

import casadi as ca
import numpy as np
import pytest

from assemblies import Assembly
from assemblies.engine.me import simulate_me
from assemblies.scenes.bodies_seed import nutation_decay_rate
from components import ComponentError, NutationDamperBody, flatten

STATES = ["q0", "q1", "q2", "q3", "w_x", "w_y", "w_z", "s_x", "s_y", "s_z", "W_d"]


def _model(**values):
    model = flatten(NutationDamperBody(**values))
    f = model.functions()
    _, q, _, p = model.start_vectors()
    names = [v.name for v in model.states]
    assert names == STATES  # the order the checks below index by

    def rates(x):
        return np.array(f["ode"](0.0, x, q, [], p)).ravel()

    def outputs(x):
        y = np.array(f["out"](0.0, x, q, [], p)).ravel()
        return dict(zip([v.name for v in model.outputs], y))
    return model, rates, outputs


def _random_states(n, seed=3):
    rng = np.random.default_rng(seed)
    for _ in range(n):
        q = rng.normal(size=4)
        yield np.concatenate([q / np.linalg.norm(q), rng.normal(size=6), [0.0]])


@pytest.mark.parametrize("values", [{}, dict(I_xx=3.0, I_yy=2.0, I_zz=1.5, J=0.2, c=2.0)])
def test_internal_torques_keep_H_and_take_energy_at_c_sigma_squared(values):
    """At any state: dh/dt + w x h = 0 in body axes (no external torque), and
    dT/dt = -c |sigma|^2 = -W_d' (the film's loss), from the model's own derivatives."""
    _, rates, outputs = _model(**values)
    body = NutationDamperBody(**values).values
    I = np.array([body["I_xx"], body["I_yy"], body["I_zz"]])
    J, c = body["J"], body["c"]
    for x in _random_states(5):
        xdot = rates(x)
        w, s, dw, ds = x[4:7], x[7:10], xdot[4:7], xdot[7:10]
        h = I * w + J * (w + s)
        dh = I * dw + J * (dw + ds)
        np.testing.assert_allclose(dh + np.cross(w, h), 0.0, atol=1e-12)
        dT = (I * w) @ dw + J * (w + s) @ (dw + ds)
        assert dT == pytest.approx(-c * s @ s, rel=1e-12, abs=1e-14)
        assert xdot[10] == pytest.approx(c * s @ s, rel=1e-12, abs=1e-14)
        out = outputs(x)
        assert out["P_d"] == pytest.approx(c * s @ s, rel=1e-12)
        assert out["T"] == pytest.approx((I * w) @ w / 2 + J * (w + s) @ (w + s) / 2, rel=1e-12)
        assert out["H"] == pytest.approx(np.linalg.norm(h), rel=1e-12)


def test_spin_about_any_principal_axis_with_the_sphere_along_is_an_equilibrium():
    _, rates, _ = _model()
    for axis in range(3):
        x = np.zeros(11)
        x[0], x[4 + axis] = 1.0, 1.7
        np.testing.assert_allclose(rates(x)[4:10], 0.0, atol=1e-15)


@pytest.mark.parametrize("values, angle_axis", [({}, 2), (dict(I_xx=3.0, I_yy=2.0, I_zz=1.5), 0),
                                                (dict(I_xx=1.0, I_yy=2.5, I_zz=2.0), 1)])
def test_beta_is_the_angle_of_H_from_the_major_axis(values, angle_axis):
    _, _, outputs = _model(**values)
    body = NutationDamperBody(**values).values
    I = np.array([body["I_xx"], body["I_yy"], body["I_zz"]]) + body["J"]
    x = np.zeros(11)
    x[0] = 1.0
    x[4:7] = [0.3, -0.2, 0.5]
    h = I * x[4:7]
    expected = math.acos(abs(h[angle_axis]) / np.linalg.norm(h))
    assert outputs(x)["beta"] == pytest.approx(expected, rel=1e-12)
    x[4:7] = 0.0
    x[4 + angle_axis] = -2.0  # spin along minus the major axis: the same line
    assert outputs(x)["beta"] == 0.0


def test_hand_linearisation_matches_the_models_jacobian():
    """nutation_decay_rate (the scene's reference) from its hand-derived 4 x 4 system,
    against the eigenvalues of the model's own Jacobian at pure major-axis spin."""
    for values in ({}, dict(I_xx=2.0, I_yy=1.2, I_zz=2.9, J=0.3, c=0.1),
                   dict(I_xx=2.8, I_yy=1.0, I_zz=2.0, J=0.4, c=1.5)):
        body = NutationDamperBody(**values)
        p = body.values
        I = (p["I_xx"], p["I_yy"], p["I_zz"])
        major = int(np.argmax(I))
        model = flatten(body)
        _, q, _, pv = model.start_vectors()
        x = ca.SX.sym("x", 11)
        xdot = model.functions()["ode"](0.0, x, q, [], pv)
        jac = ca.Function("rates_jacobian", [x], [ca.jacobian(xdot, x)])
        H = 1.3
        spin = np.zeros(11)
        spin[0], spin[4 + major] = 1.0, H / (I[major] + p["J"])
        rates = np.array(jac(spin))[4:10, 4:10]  # the attitude and W_d do not feed back
        slowest = -max(e.real for e in np.linalg.eigvals(rates) if abs(e) > 1e-9)
        assert nutation_decay_rate(I, p["J"], p["c"], H, major) == pytest.approx(slowest, rel=1e-10)


def _run(stop_time, **values):
    asm = Assembly("damper")
    asm.add("body", NutationDamperBody(**values))
    return simulate_me(asm, stop_time=stop_time, step=0.1, tolerance=1e-12,
                       record=["body.T", "body.beta", "body.H", "body.W_d"])


def test_without_the_film_nothing_is_lost_and_minor_axis_spin_stays():
    """c = 0: the sphere keeps its own spin and the body turns torque-free: T is constant
    and spin about the minor axis is stable (seed 8.3.1): the dissipation does the turning."""
    res = _run(200.0, c=0.0)
    T = res["body.T"]
    assert np.abs(T / T[0] - 1).max() < 1e-9
    assert np.abs(res["body.W_d"]).max() == 0.0
    assert res["body.beta"].min() > 1.3  # H stays near the minor axis, ~pi/2 from the major


def test_with_the_film_it_ends_about_the_major_axis():
    res = _run(400.0)
    T, beta = res["body.T"], res["body.beta"]
    H = res["body.H"][0]
    assert np.all(np.diff(T) <= 1e-13 * T[0])
    assert T[-1] == pytest.approx(H**2 / (2 * (3.0 + 0.5)), rel=1e-8)
    assert beta[0] > 1.4 and beta[-1] < 1e-6


@pytest.mark.parametrize("values, broken", [
    (dict(I_xx=1.0, I_yy=1.0, I_zz=2.5), "I_zz <= I_xx + I_yy"),
    (dict(J=0.0), "J (moment of inertia of the damper sphere, kg.m2) must be > 0"),
    (dict(c=-1.0), "c (viscous coefficient between sphere and body, N.m.s/rad) must be >= 0"),
])
def test_unphysical_parameters_are_refused(values, broken):
    with pytest.raises(ComponentError, match=re.escape(broken)):
        NutationDamperBody(**values)
