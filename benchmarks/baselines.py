"""The baseline an engineer writes by hand: numpy right-hand sides under scipy's solve_ivp.

Written from the physics (seed 9.2, 9.5, 7.5, 8.5, 6.1–6.5), not generated from our CasADi
models: that independence is what makes them a baseline. Dry friction is handled the
way one would by hand: terminal events at stick/slip and a restart with the mode
switched. Every runner returns (values at the output times, rhs evaluations, steps).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable

import numpy as np
from scipy.integrate import solve_ivp

METHODS = ("RK45", "DOP853", "Radau", "LSODA")


class _Counted:
    """A right-hand side that counts its calls (scipy's nfev misses finite-difference Jacobians
    for LSODA, so one counter serves every method alike)."""

    def __init__(self, fn):
        self.fn, self.calls = fn, 0

    def __call__(self, t, y):
        self.calls += 1
        return self.fn(t, y)


_JITTED: dict = {}


def jitted(fn):
    """`fn` compiled by numba (once per process): the baseline an engineer who knows
    numba writes. numba is an optional benchmark dependency (the `bench` extra)."""
    if fn not in _JITTED:
        try:
            import numba
        except ImportError:
            raise RuntimeError("the numba baselines need numba: pip install mechfmu[bench]") from None
        _JITTED[fn] = numba.njit(cache=False)(fn)
    return _JITTED[fn]


def _smooth(rhs, y0, times, method, tol, jac=None):
    counted = _Counted(rhs)
    # scipy's LSODA takes the Jacobian only as a callable
    extra = {"jac": lambda t, y: jac} if jac is not None and method in ("Radau", "LSODA") else {}
    sol = solve_ivp(counted, (times[0], times[-1]), y0, method=method, rtol=tol,
                    atol=tol * 1e-2, dense_output=True, **extra)
    if not sol.success:
        raise RuntimeError(f"solve_ivp {method}: {sol.message}")
    return sol.sol(times), counted.calls, len(sol.t) - 1


# --- spring-block with exact Coulomb friction (stick_slip, moving_table) -----------
@dataclass
class CoulombBlock:
    """m (a_sup + x'') = k (s_end - s_sup - x) + f, x relative to the support, |f| <= mu N."""
    m: float
    k: float
    g: float
    mu_k: float
    mu_s: float
    s_end: Callable[[float], float] = lambda t: 0.0     # spring end, absolute
    s_sup: Callable[[float], float] = lambda t: 0.0     # support, absolute
    a_sup: Callable[[float], float] = lambda t: 0.0     # support acceleration

    def applied(self, t, x):
        """Every force but friction, in the support's frame."""
        return self.k * (self.s_end(t) - self.s_sup(t) - x) - self.m * self.a_sup(t)

    def after_stop(self, t, x):
        """Mode once the relative velocity is zero: stuck unless the static limit is exceeded."""
        F, limit = self.applied(t, x), self.mu_s * self.m * self.g
        return 0 if abs(F) < limit else int(math.copysign(1, F))


def drag_slip_rhs(t, y, s, m, k, speed, mu_k_N):
    """Sliding with the spring's end dragged at `speed` (stick_slip), direction s."""
    return np.array([y[1], (k * (speed * t - y[0]) - s * mu_k_N) / m])


def coulomb_block(block: CoulombBlock, x0, v0, times, method, tol, jit_speed=None):
    """Integrate phase by phase; each phase ends at a terminal event (slip or stop).

    jit_speed: the block is dragged at this constant speed (stick_slip) and its sliding
    right-hand side is the numba-compiled drag_slip_rhs."""
    N = block.m * block.g
    slip_jit = jitted(drag_slip_rhs) if jit_speed is not None else None
    t, y = float(times[0]), np.array([x0, v0], dtype=float)
    mode = int(math.copysign(1, v0)) if v0 != 0 else block.after_stop(t, x0)
    out, nfev, steps = np.empty(len(times)), 0, 0
    while t < times[-1]:
        if mode == 0:
            def rhs(tt, yy):
                return np.zeros(2)
            # stuck: the margins of the static limit, both must stay positive
            ev_fwd = lambda tt, yy: block.mu_s * N - block.applied(tt, yy[0])
            ev_bwd = lambda tt, yy: block.mu_s * N + block.applied(tt, yy[0])
            events = [ev_fwd, ev_bwd]
        else:
            if slip_jit is not None:
                def rhs(tt, yy, s=float(mode)):
                    return slip_jit(tt, yy, s, block.m, block.k, jit_speed, block.mu_k * N)
            else:
                def rhs(tt, yy, s=mode):
                    return np.array([yy[1],
                                     (block.applied(tt, yy[0]) - s * block.mu_k * N) / block.m])
            events = [lambda tt, yy, s=mode: s * yy[1]]  # sliding stops where s v falls to 0
        for ev in events:
            ev.terminal, ev.direction = True, -1
        counted = _Counted(rhs)
        sol = solve_ivp(counted, (t, times[-1]), y, method=method, rtol=tol, atol=tol * 1e-2,
                        events=events, dense_output=True)
        if not sol.success:
            raise RuntimeError(f"solve_ivp {method}: {sol.message}")
        nfev, steps = nfev + counted.calls, steps + len(sol.t) - 1
        t_end = sol.t[-1]
        sel = (times >= t) & (times <= t_end)
        out[sel] = sol.sol(times[sel])[0]
        t, y = t_end, sol.y[:, -1].copy()
        if sol.status == 1:  # an event: switch the mode and restart
            if mode == 0:
                mode = 1 if sol.t_events[0].size else -1
            else:
                y[1] = 0.0
                mode = block.after_stop(t, y[0])
    return out, nfev, steps


# --- spring-block with the smooth law, seed Eq. 9.5 -----------------------------------
def smooth_block(m, k, g, mu_k, mu_s, eps, speed, times, method, tol):
    def rhs(t, y):
        s = y[1] / eps
        mu = mu_k * math.tanh(3 * s) + (mu_s - mu_k) * s * math.exp(0.5 - s * s / 2)
        return np.array([y[1], (k * (speed * t - y[0]) - mu * m * g) / m])

    values, nfev, steps = _smooth(rhs, np.zeros(2), times, method, tol)
    return values[0], nfev, steps


# --- the cantilever, M a'' + K a = 0 ----------------------------------------------------
def beam(M, K, tip, a0, times, method, tol):
    n = len(a0)
    A = np.linalg.solve(M, K)
    jac = np.block([[np.zeros((n, n)), np.eye(n)], [-A, np.zeros((n, n))]])

    def rhs(t, y):
        return np.concatenate([y[n:], -A @ y[:n]])

    values, nfev, steps = _smooth(rhs, np.concatenate([a0, np.zeros(n)]), times, method, tol,
                                  jac=jac)
    return tip @ values[:n], nfev, steps


# --- a rigid body on an inclined axle, J theta'' = -m g k.(n x r(theta)) ---------------
def axle_rhs(y, m_g, J_n, r, n, n_x_r, n_dot_r):
    c, s = math.cos(y[0]), math.sin(y[0])
    r_t = c * r + s * n_x_r + (1 - c) * n_dot_r * n      # Rodrigues
    torque = -m_g * (n[0] * r_t[1] - n[1] * r_t[0])      # (n x r_t)_z
    return np.array([y[1], torque / J_n])


def axle(m, g, J_n, r, n, theta0, times, method, tol, jit=False):
    r, n = np.asarray(r, float), np.asarray(n, float) / np.linalg.norm(n)
    n_x_r, n_dot_r = np.cross(n, r), float(n @ r)
    kernel = jitted(axle_rhs) if jit else axle_rhs

    def rhs(t, y):
        return kernel(y, m * g, J_n, r, n, n_x_r, n_dot_r)

    values, nfev, steps = _smooth(rhs, np.array([theta0, 0.0]), times, method, tol)
    return values[0], nfev, steps


# --- the rolling coin, seed ch. 6: Newton–Euler about the contact point ------------------
def coin_derivatives(state, m, R, g):
    """d/dt of (x, y, phi, theta, psi, phi', theta', psi') for a thin disk rolling on z = 0.

    By hand from seed 6.1–6.5 with (3,1,3) Euler angles q = (phi, theta, psi):
    v_G = -R J(q) q' (6.1–6.3), omega = W(q) q' (4.6), so a_G = -R (J q'' + J' q') and
    alpha = W q'' + W' q' (4.10). Angular momentum about C (6.5) with r = r_G/C then reads
        (I W - m R S(r) J) q'' = -m g r x e3 + m R r x (J' q') - I W' q' - omega x I omega,
    a 3x3 system. I_cm = I_d 1 + (I_a - I_d) n n^T, n = the coin's normal (axisymmetric).
    """
    _, _, phi, theta, _, phd, thd, psd = state
    cf, sf, ct, st = math.cos(phi), math.sin(phi), math.cos(theta), math.sin(theta)
    I_d, I_a = m * R * R / 4, m * R * R / 2
    J = np.array([[cf * ct, -st * sf, cf], [sf * ct, st * cf, sf], [0.0, -ct, 0.0]])
    Jdot_qd = np.array([
        (-sf * ct * phd - cf * st * thd) * phd + (-ct * sf * thd - st * cf * phd) * thd
        - sf * phd * psd,
        (cf * ct * phd - sf * st * thd) * phd + (ct * cf * thd - st * sf * phd) * thd
        + cf * phd * psd,
        st * thd * thd])
    W = np.array([[0.0, cf, st * sf], [0.0, sf, -st * cf], [1.0, 0.0, ct]])
    Wdot_qd = np.array([-sf * phd * thd + (ct * sf * thd + st * cf * phd) * psd,
                        cf * phd * thd + (st * sf * phd - ct * cf * thd) * psd,
                        -st * thd * psd])
    qd = np.array([phd, thd, psd])
    v_G = -R * (J @ qd)
    omega = W @ qd
    n = np.array([st * sf, -st * cf, ct])
    I_cm = I_d * np.eye(3) + (I_a - I_d) * np.outer(n, n)
    r = R * np.array([-sf * ct, cf * ct, st])
    S_r = np.array([[0.0, -r[2], r[1]], [r[2], 0.0, -r[0]], [-r[1], r[0], 0.0]])
    A = I_cm @ W - m * R * (S_r @ J)
    L = I_cm @ omega
    omega_x_L = np.array([omega[1] * L[2] - omega[2] * L[1], omega[2] * L[0] - omega[0] * L[2],
                          omega[0] * L[1] - omega[1] * L[0]])
    b = (-m * g * np.array([r[1], -r[0], 0.0])          # r x e3
         + m * R * (S_r @ Jdot_qd) - I_cm @ Wdot_qd - omega_x_L)
    qdd = np.linalg.solve(A, b)
    return np.array([v_G[0], v_G[1], phd, thd, psd, qdd[0], qdd[1], qdd[2]])


def coin(m, R, g, theta_min, y0, times, method, tol, jit=False):
    """theta at the output times; the run ends early (error) if the coin falls flat."""
    kernel = jitted(coin_derivatives) if jit else coin_derivatives

    def rhs(t, y):
        return kernel(y, m, R, g)

    def flat(t, y):
        return math.sin(y[3]) - math.sin(theta_min)
    flat.terminal, flat.direction = True, -1
    counted = _Counted(rhs)
    sol = solve_ivp(counted, (times[0], times[-1]), np.asarray(y0, float), method=method,
                    rtol=tol, atol=tol * 1e-2, dense_output=True, events=flat)
    if not sol.success:
        raise RuntimeError(f"solve_ivp {method}: {sol.message}")
    if sol.status == 1:
        raise RuntimeError(f"coin fell flat at t = {sol.t[-1]:.6g}")
    return sol.sol(times)[3], counted.calls, len(sol.t) - 1
