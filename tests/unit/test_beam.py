"""The assumed-modes cantilever against the seed (7.5), closed-form integrals and the exact beam."""
import math

import numpy as np
import pytest
from fmpy.validation import validate_fmu
from scipy.linalg import eigh
from scipy.optimize import brentq

from components import ComponentError, flatten
from components.bodies.beam import AssumedModesBeam
from components.bodies.beam_shapes import shape_basis
from components.sources.force import ConstantForce
from fmus import build_fmu

# literature values of (βL)² for the clamped-free beam, as the issue quotes them
CANTILEVER = [3.51602, 22.0345, 61.6972, 120.902]


def seed_matrices(EI, L, m, k):
    """M and K exactly as the seed prints them for x²/L², x³/L³."""
    mass = m * np.array([[1 / 5, 1 / 6], [1 / 6, 1 / 7]])
    e = EI / L**3
    return mass, np.array([[4 * e + k, 6 * e + k], [6 * e + k, 12 * e + k]])


def tip_spring_roots(kappa, count):
    """λ = βL of a cantilever with tip spring κ = k L³/EI, derived here.

    w = A (cosh - cos) + B (sinh - sin) is clamped at 0; at L, w'' = 0 and
    EI w''' = k w (the spring pushes back on the shear) give the determinant
    λ³ (1 + cosh λ cos λ) - κ (cos λ sinh λ - cosh λ sin λ) = 0, divided by cosh λ.
    """
    def f(lam):
        return lam**3 * (1 / math.cosh(lam) + math.cos(lam)) - kappa * (
            math.cos(lam) * math.tanh(lam) - math.sin(lam))
    grid = np.linspace(0.05, (count + 1) * math.pi, 4000)
    roots = [brentq(f, a, b, xtol=1e-14) for a, b in zip(grid, grid[1:]) if f(a) * f(b) < 0]
    return np.array(roots[:count])


def test_poly2_matrices_are_the_seeds():
    basis = shape_basis("poly2", 1)
    mass, stiffness = seed_matrices(1.0, 1.0, 1.0, 0.0)
    np.testing.assert_allclose(basis.mass, mass, rtol=1e-14)
    np.testing.assert_allclose(basis.stiffness, stiffness, rtol=1e-14)


@pytest.mark.parametrize("n_modes", [4, 64])
def test_sine_integrals_match_closed_forms(n_modes):
    """∫ξ⁴, ∫ξ² sin², (φ0'')(φk'') and (φk'')² integrated by hand: quadrature is exact."""
    basis = shape_basis("sine", n_modes)
    k = np.arange(1, n_modes + 1) * math.pi
    assert basis.mass[0, 0] == pytest.approx(1 / 5, rel=1e-14)
    np.testing.assert_allclose(np.diag(basis.mass)[1:], 1 / 6 - 1 / (4 * k**2), rtol=1e-13)
    assert basis.stiffness[0, 0] == pytest.approx(4.0, rel=1e-14)
    sign = (-1.0) ** np.arange(1, n_modes + 1)
    np.testing.assert_allclose(basis.stiffness[0, 1:], 2 * k * sign, rtol=1e-12)
    np.testing.assert_allclose(np.diag(basis.stiffness)[1:], k**4 / 6 + 11 / 4 * k**2, rtol=1e-13)
    # ∫ ξ³ sin(kξ) dξ on [0, 1] with k = nπ: (-1)^(n+1) (1/k - 6/k³)
    np.testing.assert_allclose(basis.mass[0, 1:], -sign * (1 / k - 6 / k**3), rtol=1e-12, atol=1e-16)


def test_poly2_frequencies_are_the_seeds():
    omega = AssumedModesBeam(basis="poly2", EI=1.0, L=1.0, m=1.0).natural_frequencies()
    assert omega[0] == pytest.approx(3.533, abs=5e-4)
    assert omega[1] == pytest.approx(34.8, abs=0.05)


@pytest.mark.parametrize("k_tip", [0.0, 0.7, 13.0, 450.0])
def test_poly2_with_tip_spring_has_the_seeds_closed_form(k_tip):
    EI, L, m = 2.5, 0.8, 1.7
    root = math.sqrt(9984 * EI**2 + 64 * EI * k_tip * L**3 + k_tip**2 * L**6)
    seed = [(612 * EI + 6 * k_tip * L**3 + s * 6 * root) / (L**3 * m) for s in (-1, 1)]
    omega = AssumedModesBeam(basis="poly2", EI=EI, L=L, m=m, k_tip=k_tip).natural_frequencies()
    np.testing.assert_allclose(omega**2, seed, rtol=1e-12)


def test_sine_basis_converges_to_the_cantilever():
    errors = []
    for n in (1, 2, 4, 8, 16, 32):
        omega = AssumedModesBeam(basis="sine", n_modes=n).natural_frequencies()
        errors.append([omega[i] / CANTILEVER[i] - 1 if i < len(omega) else math.inf for i in range(4)])
    errors = np.array(errors)
    assert np.all(errors > -5e-6)  # Ritz bounds from above, up to the rounding of the references
    for column in errors.T:
        finite = column[np.isfinite(column)]
        assert np.all(np.diff(finite) <= 0)
    assert np.all(errors[-1] < 1.5e-3)
    # one more halving of the error per doubling of N: the 1/N rate of this basis
    assert np.all((errors[-2] / errors[-1] > 1.6) & (errors[-2] / errors[-1] < 3.0))


@pytest.mark.parametrize("kappa", [10.0, 100.0])
def test_sine_basis_converges_to_the_tip_spring_roots(kappa):
    exact = tip_spring_roots(kappa, 4) ** 2
    assert exact[0] > CANTILEVER[0]  # the spring stiffens the first mode
    previous = np.full(4, np.inf)
    for n in (4, 8, 16, 32):
        omega = AssumedModesBeam(basis="sine", n_modes=n, k_tip=kappa).natural_frequencies()[:4]
        error = omega / exact - 1
        assert np.all(error > 0) and np.all(error <= previous)
        previous = error
    assert np.all(previous < 1.5e-3)


def test_static_tip_deflection():
    F, EI, L = 0.3, 2.0, 1.5
    exact = F * L**3 / (3 * EI)
    # the exact static shape is a cubic: poly2 holds it, with or without the tip spring
    assert AssumedModesBeam(basis="poly2", EI=EI, L=L).static_tip_deflection(F) == pytest.approx(
        exact, rel=1e-13)
    assert AssumedModesBeam(basis="poly2", EI=EI, L=L, k_tip=5.0).static_tip_deflection(F) == (
        pytest.approx(F / (3 * EI / L**3 + 5.0), rel=1e-13))
    errors = [1 - AssumedModesBeam(basis="sine", n_modes=n, EI=EI, L=L).static_tip_deflection(F) / exact
              for n in (2, 4, 8, 16, 32)]
    assert all(e > 0 for e in errors) and errors == sorted(errors, reverse=True)
    assert errors[-1] < 3e-3 and 1.6 < errors[-2] / errors[-1] < 3.0  # the basis's 1/N rate


def _flat_poly2(**values):
    model = flatten(AssumedModesBeam(basis="poly2", coordinates="assumed", **values))
    f = model.functions()
    _, q, _, p = model.start_vectors()

    def evaluate(x, force):
        out = dict(zip([v.name for v in model.outputs],
                       np.array(f["out"](0.0, x, q, [force], p)).ravel()))
        return np.array(f["ode"](0.0, x, q, [force], p)).ravel(), out, np.array(f["jac"](0.0, x, q, [force], p))
    return evaluate


def test_flattened_equations_are_lagranges_with_rayleigh_damping():
    EI, L, m, k, alpha, beta = 2.0, 1.5, 3.0, 4.0, 0.1, 0.01
    evaluate = _flat_poly2(EI=EI, L=L, m=m, k_tip=k, alpha=alpha, beta=beta)
    mass, stiffness = seed_matrices(EI, L, m, k)
    a, a_dot, force = np.array([0.1, -0.2]), np.array([0.3, 0.05]), 0.7
    xdot, out, _ = evaluate(np.concatenate([a, a_dot]), force)
    accel = np.linalg.solve(mass, force - (alpha * mass + beta * stiffness) @ a_dot - stiffness @ a)
    np.testing.assert_allclose(xdot, np.concatenate([a_dot, accel]), rtol=1e-13)
    assert out["w_tip"] == out["tip.s"] == pytest.approx(a.sum(), rel=1e-15)
    assert out["tip.v"] == pytest.approx(a_dot.sum(), rel=1e-15)
    assert out["tip.a"] == pytest.approx(accel.sum(), rel=1e-13)
    assert out["slope_tip"] == pytest.approx((2 * a[0] + 3 * a[1]) / L, rel=1e-15)
    energy = a_dot @ mass @ a_dot / 2 + a @ stiffness @ a / 2
    assert out["E"] == pytest.approx(energy, rel=1e-14)


def test_modal_damping_gives_every_mode_its_ratio():
    EI, L, m, zeta = 2.0, 1.5, 3.0, 0.07
    evaluate = _flat_poly2(EI=EI, L=L, m=m, zeta=zeta)
    mass, stiffness = seed_matrices(EI, L, m, 0.0)
    _, _, jac = evaluate(np.zeros(4), 0.0)
    damping = -mass @ jac[2:, 2:]  # a'' = -M⁻¹ C a' + ...
    eigenvalues, modes = eigh(stiffness, mass)
    np.testing.assert_allclose(modes.T @ damping @ modes, np.diag(2 * zeta * np.sqrt(eigenvalues)),
                               atol=1e-12 * np.sqrt(eigenvalues[-1]))


def test_options_redeclare_the_coordinates_and_keep_starts():
    # options given last still apply first
    beam = AssumedModesBeam(a1=0.2, n_modes=2, coordinates="assumed")
    assert [s.name for s in beam.states] == ["a0", "a1", "a2", "a0_dot", "a1_dot", "a2_dot"]
    assert beam.starts["a1"] == 0.2
    beam.set("n_modes", 5)
    assert len(beam.states) == 12 and beam.starts["a1"] == 0.2 and beam.starts["a5"] == 0.0
    beam.set("basis", "poly2")
    assert [s.name for s in beam.states] == ["a1", "a2", "a1_dot", "a2_dot"]
    assert len(flatten(beam).states) == 4


def test_release_from_static_shape_follows_later_changes():
    beam = AssumedModesBeam(w_tip0=0.05, EI=3.0, coordinates="assumed")
    for change in ({}, {"n_modes": 9}, {"k_tip": 20.0}, {"basis": "poly2"}):
        for key, value in change.items():
            beam.set(key, value)
        beam.validate()
        basis = beam.basis()
        a = np.array([beam.starts[n] for n in basis.names])
        assert basis.tip_value @ a == pytest.approx(0.05, rel=1e-14)
        # at rest under a tip load alone: K a is parallel to φ(L)
        load = beam.matrices()[1] @ a
        np.testing.assert_allclose(load, basis.tip_value * load[0], atol=1e-12 * abs(load[0]))
        assert all(beam.starts[f"{n}_dot"] == 0.0 for n in basis.names)


@pytest.mark.parametrize("values, words", [
    ({"EI": 0.0}, ["EI", "> 0"]), ({"m": -1.0}, ["m", "> 0"]), ({"k_tip": -1.0}, ["k_tip", ">= 0"]),
    ({"zeta": -0.1}, ["zeta", ">= 0"]), ({"n_modes": 0}, ["n_modes", "from 1 to 128"]),
    ({"n_modes": 2.5}, ["n_modes", "from 1 to 128"]), ({"basis": "chebyshev"}, ["poly2, sine"]),
    ({"w_tip0": "far"}, ["w_tip0", "not a number"]), ({"a7": 1.0}, ["unknown name 'a7'", "w_tip0"]),
    # the modal formulation's own settings
    ({"n_modes": "auto", "coordinates": "assumed"}, ["n_modes = 'auto'", "coordinates = 'modal'"]),
    ({"coordinates": "modal", "accuracy": 2.0}, ["accuracy", "between 0 and 1"]),
    ({"coordinates": "eigen"}, ["coordinates", "assumed, modal"]),
    ({"n_modes": 129}, ["n_modes", "from 1 to 128 or 'auto'"]),
    ({"coordinates": "modal", "a2_dot": "fast"}, ["a2_dot", "not a number"]),
])
def test_bad_values_give_one_line_errors(values, words):
    with pytest.raises(ComponentError) as err:
        AssumedModesBeam(name="beam", **values)
    text = str(err.value)
    assert "AssumedModesBeam 'beam'" in text and "\n" not in text
    for word in words:
        assert word in text


def test_constant_force_pushes_what_it_is_connected_to():
    model = flatten(ConstantForce(F=2.5))
    # (s, v, a of the flange, then a's rate inputs, which no equation reads)
    y = np.array(model.functions()["out"](0.0, [], [], [0.1, 0.2, 0.3, 0, 0, 0], [2.5])).ravel()
    assert [v.name for v in model.outputs] == ["flange.f"] and list(y) == [-2.5]


@pytest.mark.parametrize("component", [AssumedModesBeam(basis="poly2", coordinates="assumed"),
                                       AssumedModesBeam(basis="poly2"),
                                       AssumedModesBeam(basis="sine", n_modes=1),
                                       AssumedModesBeam(basis="sine", n_modes=4, zeta=0.1),
                                       ConstantForce()],
                         ids=["poly2_assumed", "poly2", "sine1", "sine4", "force"])
def test_fmus_validate_cleanly(component, tmp_path):
    assert validate_fmu(str(build_fmu(component, tmp_path / "model.fmu"))) == []
