"""RollingCoin's equations against an independent Lagrange-multiplier derivation and the
linearised and steady motions worked out here by hand (seed chapter 6)."""
import math

import casadi as ca
import numpy as np
import pytest

from components import ComponentError
from components.dae import flatten
from components.bodies.rolling_coin import RollingCoin, rotation_313

from coin_reference import accelerations, energy, jacobian_complex_step

# state layout of the flattened coin
X, Y, PHI, THETA, PSI, PHI_D, THETA_D, PSI_D = range(8)


def _evaluate(coin, angles_and_rates):
    model = flatten(coin)
    f = model.functions()
    _, q, u, p = model.start_vectors()
    x = np.concatenate([[0.3, -0.2], angles_and_rates])
    xdot = np.array(f["ode"](0.0, x, q, u, p)).ravel()
    out = dict(zip([v.name for v in model.outputs], np.array(f["out"](0.0, x, q, u, p)).ravel()))
    return xdot, out


def test_accelerations_and_contact_force_agree_with_lagrange_multipliers():
    """Newton–Euler about C (6.4–6.5, the component) against Lagrange with multipliers
    (5.17–5.18, tests/coin_reference.py) on random states away from the flat coin."""
    m, R, g = 1.3, 0.7, 9.0
    coin = RollingCoin(m=m, R=R, g=g)
    rng = np.random.default_rng(4)
    for _ in range(25):
        state = np.concatenate([[rng.uniform(-3, 3), rng.uniform(0.15, math.pi - 0.15),
                                 rng.uniform(-3, 3)], rng.uniform(-6, 6, 3)])
        xdot, out = _evaluate(coin, state)
        ddq, force = accelerations(state, m, R, g)
        scale = np.abs(ddq).max()
        assert np.abs(xdot[PHI_D:] - ddq).max() < 1e-10 * max(scale, 1.0)
        F = np.array([out["F_x"], out["F_y"], out["N"]])
        assert np.abs(F - force).max() < 1e-10 * np.abs(force).max()
        assert out["E"] == pytest.approx(energy(state, m, R, g), rel=1e-12)
        # 6.1-6.3 against the seed's vector form omega x r_G/C, evaluated independently
        assert max(abs(out[f"v_C_{k}"]) for k in "xyz") < 1e-12 * max(1.0, np.abs(state).max())


def test_inertia_is_the_seeds_matrix_with_its_garbled_entry_derived():
    """I_cm = R_f diag(1, 1, 2) m R^2/4 R_f^T: every printed entry of the seed but (1,2),
    which for I = I_d 1 + (I_a - I_d) n n^T, n = (s_t s_f, -s_t c_f, c_t), is
    -(m R^2/4) s_t^2 s_f c_f."""
    phi, theta, psi = 0.7, 1.1, -2.3
    Rf = np.array(ca.DM(rotation_313(phi, theta, psi)))
    I = Rf @ np.diag([1.0, 1.0, 2.0]) @ Rf.T  # in units of m R^2 / 4
    st, ct, sf, cf = math.sin(theta), math.cos(theta), math.sin(phi), math.cos(phi)
    seed = np.array([[1 + st**2 * sf**2, -st**2 * sf * cf, st * sf * ct],
                     [-st**2 * sf * cf, 1 + st**2 * cf**2, -st * cf * ct],
                     [st * sf * ct, -st * cf * ct, 1 + ct**2]])
    np.testing.assert_allclose(I, seed, atol=1e-15)
    assert abs(I[0, 1] - (cf * sf * ct**2 - 4)) > 1  # the seed's printed entry is not it


def _lean_stiffness(jacobian):
    """For d/dt (theta, phi', theta') = J (.), det(lambda - J) = lambda^3 + c lambda when
    trace and determinant vanish; c > 0 is an oscillation, c < 0 a fall. c is the sum of
    the principal 2x2 minors."""
    assert abs(np.trace(jacobian)) < 1e-9 and abs(np.linalg.det(jacobian)) < 1e-9
    return (np.trace(jacobian) ** 2 - np.trace(jacobian @ jacobian)) / 2


def _upright_jacobians(spin, m, R, g):
    """Linearisation about straight upright rolling (theta = pi/2, phi' = theta' = 0,
    psi' = -spin), in (theta, phi', theta'), from the reference and from the component."""
    def reference_rates(z):
        ddq, _ = accelerations(np.array([0, z[0], 0, z[1], z[2], -spin], dtype=complex), m, R, g)
        return np.array([z[2], ddq[0], ddq[1]])

    reference = jacobian_complex_step(reference_rates, [math.pi / 2, 0.0, 0.0])
    model = flatten(RollingCoin(m=m, R=R, g=g))
    f = model.functions()
    _, q, u, p = model.start_vectors()
    x0 = np.array([0, 0, 0, math.pi / 2, 0, 0, 0, -spin])
    picked = [THETA, PHI_D, THETA_D]
    full = np.array(f["jac"](0.0, x0, q, u, p))  # CasADi's exact d(xdot)/dx
    return reference, full[np.ix_(picked, picked)]


@pytest.mark.parametrize("m, R, g", [(1.0, 1.0, 9.81), (0.3, 0.05, 9.81)])
def test_critical_speed_of_upright_rolling_is_sqrt_g_R_over_3(m, R, g):
    """c(Omega) is affine in Omega^2 (gyroscopic coupling ~ Omega^2, gravity constant):
    two spins give its slope and offset, c = 0 the critical speed, which must be
    v^2 = g R / 3 (thin uniform disk, I_d = m R^2/4, I_a = m R^2/2)."""
    for source in (0, 1):  # reference model, then the component
        spins = (1.0 / R, 5.0 / R, 9.0 / R)
        c = [_lean_stiffness(_upright_jacobians(w, m, R, g)[source]) for w in spins]
        slope = (c[1] - c[0]) / (spins[1] ** 2 - spins[0] ** 2)
        offset = c[0] - slope * spins[0] ** 2
        assert c[2] == pytest.approx(offset + slope * spins[2] ** 2, rel=1e-10)  # affine
        v_critical_squared = R**2 * (-offset / slope)
        assert v_critical_squared == pytest.approx(g * R / 3, rel=1e-10)


def steady_precessions(theta, spin, R, g):
    """Steady rolling at constant theta, spin psi' and precession phi' (theta' = 0).

    Put phi = 0. Then n = (0, -s, c), omega = (0, -psi' s, phi' + psi' c),
    r_G/C = R (0, c, s), v_G = omega x r_G/C = -R (psi' + phi' c) i =: V i. Everything
    turns about the vertical at phi', so a_G = phi' k x v_G = phi' V j and
    dH_G/dt = phi' k x H_G, H_G = I_d omega + (I_a - I_d)(n.omega) n. Angular momentum
    about G, i-part, with F = m a_G + m g k at C = G - r_G/C:
        phi' s [I_a psi' + (I_a - I_d) c phi'] = R s m phi' V - R c m g,
    i.e. for the disk (divide by m R^2): (5/4) s c phi'^2 + (3/2) s psi' phi' + (g/R) c = 0.
    """
    s, c = math.sin(theta), math.cos(theta)
    return tuple(np.roots([1.25 * s * c, 1.5 * s * spin, g / R * c]).real)


def test_steady_circular_rolling_relation_zeroes_every_acceleration():
    for theta, spin in ((math.pi / 3, -8.0), (1.2, 5.0), (2.0, -6.0)):
        roots = steady_precessions(theta, spin, 1.0, 9.81)
        assert len(roots) == 2
        for phi_d in roots:
            state = np.array([0.4, theta, -1.0, phi_d, 0.0, spin])
            ddq, _ = accelerations(state)
            assert np.abs(ddq).max() < 1e-12 * max(1.0, phi_d**2)
            xdot, _ = _evaluate(RollingCoin(), state)
            assert np.abs(xdot[PHI_D:]).max() < 1e-12 * max(1.0, phi_d**2)
        # and off the relation the lean does accelerate
        ddq, _ = accelerations(np.array([0.4, theta, -1.0, roots[0] * 1.01, 0.0, spin]))
        assert abs(ddq[1]) > 1e-3


def test_z_follows_theta_and_is_not_a_start_value():
    with pytest.raises(ComponentError, match=r"unknown name 'z'.*settable names: m, R, g"):
        RollingCoin(name="coin", z=0.5)
    _, out = _evaluate(RollingCoin(R=0.2), [0.0, 0.9, 0.0, 0.0, 0.0, 0.0])
    assert out["z"] == pytest.approx(0.2 * math.sin(0.9), rel=1e-15)


@pytest.mark.parametrize("value", [0.0, -0.1, 0.6, math.nan])
def test_fall_threshold_is_checked(value):
    with pytest.raises(ComponentError, match=r"RollingCoin 'coin'.*theta_min.*> 0 and <= 0.5"):
        RollingCoin(name="coin", theta_min=value)
