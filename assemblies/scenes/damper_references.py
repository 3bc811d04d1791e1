"""Independent references for ``beam_friction_damper``: the assumed-modes cantilever
whose tip drives a Jenkins element (a contact spring to a Coulomb pad), written here
from the physics and integrated by scipy. Nothing here calls the library's beam or
friction models.

The beam (seed 7.5): w(x, t) = sum a_i(t) phi_i(x/L), with the seed's shapes
(``poly2``: xi^2, xi^3; ``sine``, Eq. 7.8: xi^2 and xi sin(k pi xi), k = 1..N). Its
kinetic energy (m/L)/2 int w_t^2 dx and strain energy EI/2 int w_xx^2 dx give
M = m int phi phi^T dxi and K = EI/L^3 int phi'' phi''^T dxi, here in closed form for
poly2 and by scipy's adaptive quadrature (quad) for the sine shapes; a tip spring to
ground adds k_tip phi(1) phi(1)^T, Rayleigh damping alpha M + beta K, modal damping
2 zeta omega_j in the bare cantilever's mass-normalised modes. A tip force F enters
as phi(1) F.

The pad (seed 9.2's block, fixed surface): m_p x'' = f_s + f, the contact force
f_s = k (w_tip - x) + d (w_tip' - x') (the beam feels -f_s at its tip), the friction f:
while stuck x' = 0 and f = -f_s, which holds until |f_s| reaches mu_s N; sliding
forward (backward) f = -mu_k N (+mu_k N) until x' comes back to zero, where the pad
sticks unless |f_s| >= mu_s N, when it slides towards f_s. Each phase is integrated
by solve_ivp (DOP853) up to its event, located by the solver's root finder.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

#: the reference's own tolerance (rtol = atol): far below any run's
REFERENCE_TOL = 1e-12
MAX_PHASES = 10_000  # stick/slip phases: a run with more is not this scene's


def basis_shapes(basis: str, n_modes: int):
    """(phi, phi'') of the seed's shapes as functions of xi, and phi(1), phi'(1)."""
    if basis == "poly2":
        return (lambda xi: np.array([xi**2, xi**3]), lambda xi: np.array([2.0, 6 * xi]),
                np.array([1.0, 1.0]))
    if basis == "sine":
        k = math.pi * np.arange(1, n_modes + 1)

        def phi(xi):
            return np.concatenate([[xi**2], xi * np.sin(k * xi)])

        def phi_xx(xi):
            return np.concatenate([[2.0], 2 * k * np.cos(k * xi) - k**2 * xi * np.sin(k * xi)])
        return phi, phi_xx, np.concatenate([[1.0], np.zeros(n_modes)])
    raise ValueError(f"basis must be poly2 or sine, not {basis!r}")


def unit_matrices(basis: str, n_modes: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(int phi phi^T, int phi'' phi''^T, phi(1)) on xi in [0, 1]."""
    if basis == "poly2":  # int xi^(i+j) = 1/(i+j+1); phi'' = 2, 6 xi
        return (np.array([[1 / 5, 1 / 6], [1 / 6, 1 / 7]]), np.array([[4.0, 6.0], [6.0, 12.0]]),
                np.array([1.0, 1.0]))
    from scipy.integrate import quad
    phi, phi_xx, tip = basis_shapes(basis, n_modes)
    n = len(tip)
    mass, stiffness = np.empty((n, n)), np.empty((n, n))
    for i in range(n):
        for j in range(i, n):
            mass[i, j] = mass[j, i] = quad(lambda x: phi(x)[i] * phi(x)[j], 0.0, 1.0,
                                           epsabs=1e-14, epsrel=1e-12, limit=400)[0]
            stiffness[i, j] = stiffness[j, i] = quad(lambda x: phi_xx(x)[i] * phi_xx(x)[j],
                                                     0.0, 1.0, epsabs=1e-14, epsrel=1e-12,
                                                     limit=400)[0]
    return mass, stiffness, tip


@dataclass(frozen=True)
class Beam:
    """The discretised cantilever: M a'' + C a' + K a = phi(1) F."""
    M: np.ndarray
    C: np.ndarray
    K: np.ndarray
    tip: np.ndarray

    @classmethod
    def of(cls, basis: str, n_modes: int, EI: float, L: float, m: float, k_tip: float = 0.0,
           alpha: float = 0.0, beta: float = 0.0, zeta: float = 0.0) -> "Beam":
        from scipy.linalg import eigh
        mass, stiffness, tip = unit_matrices(basis, n_modes)
        M, K_bare = m * mass, EI / L**3 * stiffness
        K = K_bare + k_tip * np.outer(tip, tip)
        C = alpha * M + beta * K
        if zeta:
            omega2, modes = eigh(K_bare, M)  # mass-normalised: modes^T M modes = I
            Mphi = M @ modes
            C = C + Mphi @ np.diag(2 * zeta * np.sqrt(omega2)) @ Mphi.T
        return cls(M, C, K, tip)

    def frequencies(self, k_extra: float = 0.0) -> np.ndarray:
        """Undamped angular frequencies [rad/s] with a further tip spring to ground."""
        from scipy.linalg import eigh
        return np.sqrt(eigh(self.K + k_extra * np.outer(self.tip, self.tip), self.M,
                            eigvals_only=True))


@dataclass(frozen=True)
class Pad:
    m: float
    k: float
    d: float
    N: float
    mu_s: float
    mu_k: float


@dataclass(frozen=True)
class ModeChange:
    """One change of the pad's friction mode in the reference solution."""
    t: float      # [s]
    x: float      # pad position there [m]
    mode: int     # the mode after it: -1, 0, +1
    rate: float   # |d/dt| of the indicator that located it (pad acceleration [m/s2]
                  # for a stop, d f_s/dt [N/s] for a break-away), just before it
    scale: float  # |d indicator / d state|, summed over the states (1 for a stop)


def _contact_force(beam: Beam, pad: Pad, a, a_dot, x, v) -> float:
    return pad.k * (beam.tip @ a - x) + pad.d * (beam.tip @ a_dot - v)


def _breaks_free(f_s: float, pad: Pad) -> int:
    static = pad.mu_s * pad.N
    return 1 if f_s >= static else -1 if f_s <= -static else 0


def damper_solution(beam: Beam, pad: Pad, a0, a0_dot, x0: float, v0: float, mode0: int,
                    t_end: float, tol: float = REFERENCE_TOL):
    """The pad's mode changes over [0, t_end] and the final state (a, a', x, v, mode).

    `mode0` is the start value of the pad's mode; as a model's initialisation does, a
    stuck pad whose contact force is already at the static limit breaks free at t = 0
    (a mode change at t = 0 in the list).
    """
    from scipy.integrate import solve_ivp
    n = len(a0)
    Minv = np.linalg.inv(beam.M)
    a, a_dot = np.asarray(a0, dtype=float), np.asarray(a0_dot, dtype=float)
    x, v, mode, t = float(x0), float(v0), int(mode0), 0.0
    changes: list[ModeChange] = []
    if mode == 0:
        v = 0.0
        new = _breaks_free(_contact_force(beam, pad, a, a_dot, x, v), pad)
        if new:
            mode = new
            changes.append(ModeChange(0.0, x, mode, math.inf, 1.0))

    def rhs(_, y, q):
        a, a_dot, x, v = y[:n], y[n:2 * n], y[2 * n], y[2 * n + 1]
        f_s = _contact_force(beam, pad, a, a_dot, x, v)
        a_ddot = Minv @ (-beam.C @ a_dot - beam.K @ a - beam.tip * f_s)
        v_dot = 0.0 if q == 0 else (f_s - q * pad.mu_k * pad.N) / pad.m
        return np.concatenate([a_dot, a_ddot, [0.0 if q == 0 else v, v_dot]])

    for _ in range(MAX_PHASES):
        q = mode
        if q == 0:
            static = pad.mu_s * pad.N
            events = [lambda t_, y: static - _contact_force(beam, pad, y[:n], y[n:2 * n],
                                                            y[2 * n], 0.0),
                      lambda t_, y: static + _contact_force(beam, pad, y[:n], y[n:2 * n],
                                                            y[2 * n], 0.0)]
        else:
            events = [lambda t_, y: q * y[2 * n + 1]]
        for ev in events:
            ev.terminal, ev.direction = True, -1
        sol = solve_ivp(lambda t_, y: rhs(t_, y, q), (t, t_end),
                        np.concatenate([a, a_dot, [x, v]]), method="DOP853", rtol=tol, atol=tol,
                        events=events)
        hits = [(float(te[0]), ye[0]) if len(te) else (math.inf, None)
                for te, ye in zip(sol.t_events, sol.y_events)]
        if all(h[1] is None for h in hits):
            y = sol.y[:, -1]
            return changes, (y[:n], y[n:2 * n], float(y[2 * n]), float(y[2 * n + 1]), mode)
        t, y, which = min(((h[0], h[1], i) for i, h in enumerate(hits)), key=lambda h: h[0])
        a, a_dot, x, v = y[:n].copy(), y[n:2 * n].copy(), float(y[2 * n]), float(y[2 * n + 1])
        slope = rhs(t, y, q)  # the indicator's rate just before the event
        if q == 0:
            a_ddot = slope[n:2 * n]
            rate = abs(pad.k * (beam.tip @ a_dot) + pad.d * (beam.tip @ a_ddot))
            scale = (pad.k + pad.d) * (np.abs(beam.tip).sum() + 1)
            # the margin that reached zero says which way: at the threshold itself the
            # pad breaks free (the root finder may land a hair before it)
            mode = 1 if which == 0 else -1
        else:
            rate, scale = abs(slope[2 * n + 1]), 1.0
            v = 0.0  # the slide ended: exactly at rest
            mode = _breaks_free(_contact_force(beam, pad, a, a_dot, x, v), pad)
        changes.append(ModeChange(t, x, mode, rate, scale))
    raise RuntimeError(f"the damper's reference changed mode more than {MAX_PHASES} times "
                       f"before t = {t_end} s")


__all__ = ["REFERENCE_TOL", "Beam", "ModeChange", "Pad", "basis_shapes", "damper_solution",
           "unit_matrices"]
