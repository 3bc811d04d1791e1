"""Independent reference solutions the benchmark errors are measured against.

Nothing here calls the library's models: the stick-slip solution is piecewise analytic
(derived as in tests/conftest.py), the beam's is modal from matrices integrated here by
quadrature, the pendulum's is Jacobi's elliptic sn. Scenes without a closed form use a
tight-tolerance run, chosen per scene in benchmarks.scenes.
"""
from __future__ import annotations

import math

import numpy as np
from scipy.linalg import eigh
from scipy.optimize import brentq
from scipy.special import ellipj, ellipk

from fmus.build import cache_dir


def cached(key: str, compute) -> np.ndarray:
    """A tight-tolerance reference, computed once and kept in the FMU cache's bench/ folder:
    it depends only on `key` (the scene's parameters, times and method), never on our code."""
    import hashlib
    path = cache_dir() / "bench" / f"{hashlib.sha256(key.encode()).hexdigest()[:20]}.npy"
    if path.exists():
        return np.load(path)
    values = np.asarray(compute(), dtype=float)
    path.parent.mkdir(parents=True, exist_ok=True)
    np.save(path, values)
    return values


def coulomb_drag(m, k, g, mu_k, mu_s, v, t_end):
    """Piecewise exact solution of m x'' = k (v t - x) + f under Coulomb friction (seed 9.2).

    Derived from the linear ODE of each phase, independently of the library:
    stuck phases hold x until the spring force k (v t - x) reaches mu_s m g; sliding
    phases solve m xi'' = -k xi for xi = x - v t + mu_k m g / k, until x' = 0.
    Returns (phases, x_of_t) where phases are (kind, t_start, t_end) tuples.
    """
    w, N = math.sqrt(k / m), m * g
    t, x, phases, pieces = 0.0, 0.0, [], []
    while t < t_end:
        t_slip = (mu_s * N / k + x) / v
        phases.append(("stick", t, t_slip))
        pieces.append((t, t_slip, lambda tt, x=x: np.full_like(tt, x)))
        xi0, dxi0 = x - v * t_slip + mu_k * N / k, -v

        def x_slide(tt, t0=t_slip, xi0=xi0, dxi0=dxi0):
            tau = tt - t0
            return v * tt - mu_k * N / k + xi0 * np.cos(w * tau) + dxi0 / w * np.sin(w * tau)

        def v_slide(tau, xi0=xi0, dxi0=dxi0):
            return v - xi0 * w * math.sin(w * tau) + dxi0 * math.cos(w * tau)

        # x' > 0 right after slip starts; its first zero lies within one period
        grid = np.linspace(1e-9, 2 * math.pi / w, 2001)
        vals = [v_slide(s) for s in grid]
        i = next(j for j in range(1, len(grid)) if vals[j] <= 0 < vals[j - 1])
        tau_stop = brentq(v_slide, grid[i - 1], grid[i], xtol=1e-15, rtol=1e-15)
        t_stick = t_slip + tau_stop
        phases.append(("slide", t_slip, t_stick))
        pieces.append((t_slip, t_stick, x_slide))
        t, x = t_stick, float(x_slide(np.array(t_stick)))
        assert abs(k * (v * t - x)) < mu_s * N, "the block re-sticks in this regime"

    def x_of_t(tt):
        tt = np.asarray(tt, dtype=float)
        out = np.empty_like(tt)
        for a, b, fn in pieces:
            sel = (tt >= a) & (tt <= b)
            out[sel] = fn(tt[sel])
        return out

    return phases, x_of_t


# --- the cantilever by assumed modes (seed Eq. 7.8), integrated here by quadrature ---
def beam_shapes(n_modes: int, xi: np.ndarray):
    """(phi, phi'') of the seed's basis at xi: xi^2 and xi sin(k pi xi), k = 1..N."""
    phi = [xi**2] + [xi * np.sin(k * math.pi * xi) for k in range(1, n_modes + 1)]
    dd = [np.full_like(xi, 2.0)] + [2 * k * math.pi * np.cos(k * math.pi * xi)
                                    - (k * math.pi) ** 2 * xi * np.sin(k * math.pi * xi)
                                    for k in range(1, n_modes + 1)]
    return np.array(phi), np.array(dd)


def beam_matrices(n_modes: int, EI=1.0, L=1.0, m=1.0):
    """(M, K, phi_tip): M = m ∫φφᵀ, K = EI/L³ ∫φ''φ''ᵀ by Gauss–Legendre, exact for these
    trigonometric polynomials once the rule has a few points per half wave."""
    nodes, weights = np.polynomial.legendre.leggauss(8 * (n_modes + 4))
    xi, wq = (nodes + 1) / 2, weights / 2
    phi, dd = beam_shapes(n_modes, xi)
    M = m * (phi * wq) @ phi.T
    K = EI / L**3 * (dd * wq) @ dd.T
    tip = beam_shapes(n_modes, np.array([1.0]))[0][:, 0]
    return M, K, tip


def beam_free_vibration(n_modes: int, w_tip0: float):
    """w_tip(t) after release at rest from the static shape with tip deflection w_tip0.

    Undamped, so each mode of K u = ω² M u swings as cos(ω t) with the modal coordinate
    it starts with: a(t) = U diag(cos ω t) Uᵀ M a0 (U M-orthonormal).
    """
    M, K, tip = beam_matrices(n_modes)
    shape = np.linalg.solve(K, tip)
    a0 = shape * (w_tip0 / (tip @ shape))
    lam, U = eigh(K, M)
    omega, q0 = np.sqrt(lam), U.T @ M @ a0
    tip_modal = tip @ U

    def w_tip(t):
        t = np.asarray(t, dtype=float)
        return np.cos(np.outer(t, omega)) @ (tip_modal * q0)

    return a0, w_tip


# --- the body on an inclined axle as a pendulum (seed 8.5) -------------------------
def axle_potential(m, g, r, n):
    """(rho, delta, J_n-free part): m g z_G(theta) = rho cos(theta - delta) + const.

    Rodrigues: r(θ) = cos θ r + sin θ (n × r) + (1 - cos θ)(n·r) n, so its height is
    A cos θ + B sin θ + const with A = r_z - (n·r) n_z and B = (n × r)_z.
    """
    r, n = np.asarray(r, float), np.asarray(n, float) / np.linalg.norm(n)
    A = m * g * (r[2] - (n @ r) * n[2])
    B = m * g * np.cross(n, r)[2]
    return math.hypot(A, B), math.atan2(B, A)


def axle_inertia(m, I_cm, r, n):
    """J_n = n·I_cm n + m |n × r|² about the axle."""
    n = np.asarray(n, float) / np.linalg.norm(n)
    return float(n @ np.asarray(I_cm) @ n + m * np.linalg.norm(np.cross(n, r)) ** 2)


def pendulum(omega0: float, theta_eq: float, theta0: float):
    """θ(t) of J θ'' = -ρ sin(θ - θ_eq) from rest at θ0: θ_eq + 2 asin(k sn(K - ω0 t | k²))."""
    amplitude = theta0 - theta_eq
    k = math.sin(abs(amplitude) / 2)
    K = ellipk(k**2)

    def theta(t):
        sn = ellipj(K - omega0 * np.asarray(t, dtype=float), k**2)[0]
        return theta_eq + math.copysign(1.0, amplitude) * 2 * np.arcsin(k * sn)

    return theta
