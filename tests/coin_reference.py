"""An independent rolling coin for the tests: Lagrange with multipliers (seed 5.17–5.18), numpy.

Nothing here comes from components/: the kinetic energy is written in body axes, where
an axisymmetric coin needs no rotation matrix,

    T = m/2 (x'^2 + y'^2 + z'^2) + I_d/2 (theta'^2 + sin^2(theta) phi'^2)
        + I_a/2 (psi' + cos(theta) phi')^2,         V = m g z,

with q = (x, y, z, phi, theta, psi) and the three constraints 6.1–6.3 as A(q) q' = 0.
Lagrange's equations give M q'' + h = A^T lambda; with A q'' + A' q' = 0 that is one
linear system for (q'', lambda). Because the x, y, z rows of A are the identity, lambda is
the contact force F. Everything is written so that complex numbers pass through
(complex-step derivatives in the linearisations).
"""
from __future__ import annotations

import numpy as np


def constraint_matrix(phi, theta, R):
    """Rows of Eqs. 6.1–6.3 as printed in the seed, columns (x, y, z, phi, theta, psi)."""
    cf, sf, ct, st = np.cos(phi), np.sin(phi), np.cos(theta), np.sin(theta)
    zero, one = 0 * phi, 0 * phi + 1
    return np.array([
        [one, zero, zero, R * cf * ct, -R * st * sf, R * cf],
        [zero, one, zero, R * sf * ct, R * st * cf, R * sf],
        [zero, zero, one, zero, -R * ct, zero]])


def constraint_rate_times_velocity(phi, theta, phi_d, theta_d, psi_d, R):
    """(d/dt A) q', differentiated by hand from the rows above."""
    cf, sf, ct, st = np.cos(phi), np.sin(phi), np.cos(theta), np.sin(theta)
    return np.array([
        R * (-sf * ct * phi_d - cf * st * theta_d) * phi_d
        + R * (-ct * sf * theta_d - st * cf * phi_d) * theta_d - R * sf * phi_d * psi_d,
        R * (cf * ct * phi_d - sf * st * theta_d) * phi_d
        + R * (ct * cf * theta_d - st * sf * phi_d) * theta_d + R * cf * phi_d * psi_d,
        R * st * theta_d**2])


def accelerations(state, m=1.0, R=1.0, g=9.81):
    """(phi'', theta'', psi'', F) at state = (phi, theta, psi, phi', theta', psi')."""
    phi, theta, _psi, phi_d, theta_d, psi_d = state
    I_d, I_a = m * R**2 / 4, m * R**2 / 2
    s, c = np.sin(theta), np.cos(theta)
    M = np.zeros((6, 6), dtype=np.result_type(theta, phi_d, float))
    M[0, 0] = M[1, 1] = M[2, 2] = m
    M[3:, 3:] = [[I_d * s**2 + I_a * c**2, 0, I_a * c], [0, I_d, 0], [I_a * c, 0, I_a]]
    # h = (d/dt dT/dq') - M q'' - dT/dq + dV/dq, term by term from T above
    h = np.array([0 * s, 0 * s, m * g + 0 * s,
                  2 * (I_d - I_a) * s * c * theta_d * phi_d - I_a * s * theta_d * psi_d,
                  -(I_d - I_a) * s * c * phi_d**2 + I_a * s * phi_d * psi_d,
                  -I_a * s * theta_d * phi_d])
    A = constraint_matrix(phi, theta, R)
    K = np.zeros((9, 9), dtype=M.dtype)
    K[:6, :6], K[:6, 6:], K[6:, :6] = M, -A.T, A
    rhs = np.concatenate([-h, -constraint_rate_times_velocity(phi, theta, phi_d, theta_d,
                                                               psi_d, R)])
    solution = np.linalg.solve(K, rhs)
    return solution[3:6], solution[6:9]


def energy(state, m=1.0, R=1.0, g=9.81):
    """T + V with the centre's velocity from the constraints."""
    phi, theta, _psi, phi_d, theta_d, psi_d = state
    v = -constraint_matrix(phi, theta, R)[:, 3:] @ np.array([phi_d, theta_d, psi_d])
    I_d, I_a = m * R**2 / 4, m * R**2 / 2
    T = (m * v @ v + I_d * (theta_d**2 + np.sin(theta)**2 * phi_d**2)
         + I_a * (psi_d + np.cos(theta) * phi_d)**2) / 2
    return T + m * g * R * np.sin(theta)


def jacobian_complex_step(f, x, h=1e-30):
    """df/dx to round-off: Im f(x + i h e_k) / h needs no difference of nearby numbers."""
    x = np.asarray(x, dtype=float)
    columns = []
    for k in range(len(x)):
        xc = x.astype(complex)
        xc[k] += 1j * h
        columns.append(np.imag(f(xc)) / h)
    return np.array(columns).T


def tilt_of(coin, times, tol=1e-13):
    """The tilt theta(t) at `times` of a mechfmu coin instance (its values m, R, g and its
    start angles and rates), from the equations above under scipy's DOP853 at `tol`."""
    from scipy.integrate import solve_ivp
    p = coin.values
    y0 = [coin.starts[k] for k in ("phi", "theta", "psi", "phi_dot", "theta_dot", "psi_dot")]
    return solve_ivp(lambda t, y: np.concatenate([y[3:], accelerations(y, p["m"], p["R"],
                                                                        p["g"])[0]]),
                     (0.0, float(times[-1])), y0, method="DOP853", rtol=tol, atol=tol,
                     t_eval=times).y[1]
