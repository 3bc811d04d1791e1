"""Seed 8.1, 8.2 and 9.6: each small body against the seed's equation and its frequency."""
import math

import numpy as np
import pytest
from fmpy.validation import validate_fmu

from assemblies.scenes.axle import period_from_crossings
from components import ComponentError, flatten
from components.bodies.seed_bodies import HemisphericalShell, InclinedCylinder, RodOnRollers
from fmus import build_fmu

from conftest import simulate_in_fmpy

G = 9.81


def derivatives(component, x):
    model = flatten(component)
    f = model.functions()
    _, q, _, p = model.start_vectors()
    xdot = np.array(f["ode"](0.0, x, q, [], p)).ravel()
    y = np.array(f["out"](0.0, x, q, [], p)).ravel()
    return xdot, dict(zip([v.name for v in model.outputs], y))


@pytest.mark.parametrize("alpha", [0.0, 0.3, -0.7, 1.2])
def test_cylinder_accelerates_at_two_thirds_g_sin_alpha(alpha):
    xdot, out = derivatives(InclinedCylinder(alpha=alpha, m=3.0, R=0.2), [0.5, 1.0])
    assert xdot[1] == pytest.approx(2 / 3 * G * math.sin(alpha), rel=1e-14, abs=1e-15)  # Eq. 8.2
    # no slip needs friction F with J phi'' = F R: F = (m R^2 / 2)(a / R) / R = m a / 2
    assert out["f_friction"] == pytest.approx(3.0 * xdot[1] / 2, rel=1e-14, abs=1e-15)
    assert out["phi"] == pytest.approx(0.5 / 0.2)


def test_cylinder_fmu_falls_as_a_parabola():
    cyl = InclinedCylinder(alpha=0.4)
    res = simulate_in_fmpy(cyl, "CoSimulation", 2.0, 0.1)
    a = 2 / 3 * G * math.sin(0.4)
    np.testing.assert_allclose(res["s"], a * res["time"] ** 2 / 2, rtol=1e-9, atol=1e-12)


def seed_shell_residual(contact, phi, w, dw, R):
    """The seed's printed nonlinear equations of 8.2, divided by m R^2."""
    if contact == "rolling":
        return 5 / 3 * dw - dw * math.cos(phi) + w**2 * math.sin(phi) / 2 + G / (2 * R) * math.sin(phi)
    return (13 / 24 * dw - dw * math.cos(2 * phi) / 8 + w**2 * math.sin(2 * phi) / 8
            + G / (2 * R) * math.sin(phi))


@pytest.mark.parametrize("contact", ["rolling", "frictionless"])
def test_shell_equation_is_the_seeds(contact):
    shell = HemisphericalShell(contact=contact, m=2.0, R=0.6)
    for phi, w in ((0.0, 0.0), (0.4, -1.3), (-1.2, 2.0), (1.5, 0.1)):
        xdot, _ = derivatives(shell, [phi, w, 0.0])
        assert xdot[0] == w
        assert seed_shell_residual(contact, phi, w, xdot[1], 0.6) == pytest.approx(0.0, abs=1e-12)


@pytest.mark.parametrize("contact, omega_sq", [("rolling", 3 / 4), ("frictionless", 6 / 5)])
def test_shell_small_oscillations_have_the_seeds_frequency(contact, omega_sq):
    R = 0.5
    shell = HemisphericalShell(contact=contact, R=R, phi=1e-3)
    res = simulate_in_fmpy(shell, "CoSimulation", 10.0, 0.01, tolerance=1e-12)
    T = period_from_crossings(res["time"], res["phi"], res["w"])
    assert 2 * math.pi / T == pytest.approx(math.sqrt(omega_sq * G / R), rel=1e-6)
    E = res["E"]
    assert np.abs(E - E[0]).max() < 1e-10 * E[0]


def test_rod_on_rollers_is_a_harmonic_oscillator():
    mu, D, m = 0.3, 1.0, 2.0
    xdot, out = derivatives(RodOnRollers(mu=mu, D=D, m=m), [0.2, 0.0])
    assert xdot[1] == pytest.approx(-2 * G * mu / D * 0.2, rel=1e-14)  # seed 9.6, example 3
    assert out["N_1"] + out["N_2"] == pytest.approx(m * G, rel=1e-14)
    rod = RodOnRollers(mu=mu, D=D, x=0.2)
    res = simulate_in_fmpy(rod, "CoSimulation", 5.0, 0.05)
    w = math.sqrt(2 * G * mu / D)
    np.testing.assert_allclose(res["x"], 0.2 * np.cos(w * res["time"]), atol=1e-8)
    assert np.all(res["margin"] > 0)


def test_rod_run_ends_where_it_leaves_the_rollers(capfd):
    """x = x0 cos(w t) + (v0 / w) sin(w t) = A cos(w t - phase) reaches D/2 = 0.5 at a time solved
    here."""
    mu, D, x0, v0 = 0.3, 1.0, 0.4, 2.0
    w = math.sqrt(2 * G * mu / D)
    amplitude, phase = math.hypot(x0, v0 / w), math.atan2(v0 / w, x0)
    t_leave = (phase - math.acos(0.5 / amplitude)) / w  # first time on the way up
    res = simulate_in_fmpy(RodOnRollers(mu=mu, D=D, x=x0, v=v0), "ModelExchange", 5.0, 0.01)
    assert res["time"][-1] == pytest.approx(t_leave, abs=1e-6)
    assert "the rod left" in capfd.readouterr().out


def test_rod_must_span_the_rollers():
    with pytest.raises(ComponentError, match="L > D"):
        RodOnRollers(L=1.0, D=1.5)


BODIES = [InclinedCylinder(alpha=0.3), HemisphericalShell(phi=0.2),
          HemisphericalShell(contact="frictionless", phi=0.2), RodOnRollers(x=0.1)]


@pytest.mark.parametrize("body", BODIES, ids=["cylinder", "shell-rolling", "shell-frictionless",
                                              "rod"])
def test_every_seed_body_fmu_validates_and_runs_in_fmpy(body):
    assert validate_fmu(str(build_fmu(body))) == []
    me = simulate_in_fmpy(body, "ModelExchange", 2.0, 0.1)
    cs = simulate_in_fmpy(body, "CoSimulation", 2.0, 0.1)
    first_state = body.states[0].name
    np.testing.assert_allclose(np.interp(cs["time"], me["time"], me[first_state]), cs[first_state],
                               rtol=1e-6, atol=1e-8)
