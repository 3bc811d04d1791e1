"""Independent references for ``nutation_damper`` (seed 8.3.1's body with a viscous
spherical damper): the linearised nutation about pure spin on the major axis, and a
decay-rate measurement whose error follows from that linear solution, not from the
data's misfit.

Axes are renamed cyclically so that the major axis is z (x', y', z' = the axes after
it); I are the body's moments without the sphere, J the sphere's, u = w + sigma its
absolute rate, H = I w + J u fixed in the ground. The excess energy over the least the
momentum allows is EXACTLY a quadratic form,
  2 dT = 2 T - |H|^2 / (I_z + J)
       = sum over x, y of [I_i w_i^2 + J u_i^2 - (I_i w_i + J u_i)^2 / (I_z + J)]
         + I_z J sigma_z^2 / (I_z + J),
so it is computed from the recorded transverse rates without the cancellation of
T - H^2 / (2 (I_z + J)). Linearised about the spin W = |H| / (I_z + J), the transverse
unknowns y = (w_x, w_y, sigma_x, sigma_y) obey M y' = A y (the equations in
:func:`linear_system`; their neglected terms are cubic in y, as w_z - W and sigma_z are
second order). The slowest pair lambda = -r +- i Omega is the nutation; on it alone
  dT = e^{-2 r t} (a + b cos(2 Omega t + phi)),  b / a = rho = |v^T Q v| / (v^H Q v)
with v its eigenvector and Q the form above: rho comes from the eigenvector, not from a
run. So ln dT = const - 2 r t + ln(1 + rho cos(2 Omega t + phi)), whose periodic part
has the Fourier series ln((1 + s) / 2) + 2 sum_k (-1)^(k+1) q^k cos(k theta) / k,
s = sqrt(1 - rho^2), q = rho / (1 + s). A least-squares fit of a line plus the first K
harmonics of 2 Omega therefore leaves the tail of that series, at most
2 q^(K+1) / ((K + 1)(1 - q)) in every sample: the slope moves by at most that times the
sum of |weights| of its row of the fit's pseudo-inverse.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np


def _renamed(I, major: int) -> tuple[float, float, float]:
    return tuple(float(I[(major + k) % 3]) for k in (1, 2, 3))


def linear_system(I, J: float, c: float, H: float, major: int) -> tuple[np.ndarray, np.ndarray]:
    """(M, A) of M y' = A y, y = (w_x, w_y, sigma_x, sigma_y), axes renamed (major = z),
    spin W = H / (I_z + J) (H signed: negative when the body spins about -z):
    I_x w_x' = -W (I_z - I_y) w_y + c sigma_x,   I_y w_y' = -W (I_x - I_z) w_x + c sigma_y,
    J (w_x' + sigma_x') = J W sigma_y - c sigma_x,  J (w_y' + sigma_y') = -J W sigma_x - c sigma_y.
    """
    Ix, Iy, Iz = _renamed(I, major)
    W = H / (Iz + J)
    M = np.array([[Ix, 0, 0, 0], [0, Iy, 0, 0], [J, 0, J, 0], [0, J, 0, J]])
    A = np.array([[0, -W * (Iz - Iy), c, 0], [-W * (Ix - Iz), 0, 0, c],
                  [0, 0, -c, J * W], [0, 0, -J * W, -c]])
    return M, A


def nutation_decay_rate(I: tuple[float, float, float], J: float, c: float, H: float,
                        major: int) -> float:
    """Slowest decay rate of small nutation about pure spin on the major axis, from the
    linearised equations (:func:`linear_system`): the excess energy falls like
    exp(-2 rate t)."""
    M, A = linear_system(I, J, c, H, major)
    return float(-np.linalg.eigvals(np.linalg.solve(M, A)).real.max())


def excess_form(I, J: float, major: int) -> np.ndarray:
    """Q with dT = y^T Q y on the transverse unknowns y (the sigma_z term aside)."""
    Ix, Iy, Iz = _renamed(I, major)
    Q = np.zeros((4, 4))
    for i, Ii in ((0, Ix), (1, Iy)):  # w_i = y[i], u_i = y[i] + y[i + 2]
        # I w^2 + J (w + s)^2 - (I w + J (w + s))^2 / (Iz + J), halved
        g = np.zeros(4)
        g[i], g[i + 2] = Ii + J, J  # the momentum I w + J u in y
        Q[i, i] += Ii / 2
        uu = np.zeros(4)
        uu[i], uu[i + 2] = 1.0, 1.0
        Q += J * np.outer(uu, uu) / 2 - np.outer(g, g) / (2 * (Iz + J))
    return Q


def excess_energy(I, J: float, major: int, w: np.ndarray, h: np.ndarray) -> np.ndarray:
    """dT over time from body rates w and body momenta h (rows: samples, columns x y z)."""
    Ix, Iy, Iz = _renamed(I, major)
    order = [(major + k) % 3 for k in (1, 2, 3)]
    w, h = w[:, order], h[:, order]
    u = (h - np.array([Ix, Iy, Iz]) * w) / J  # the sphere's absolute rate
    out = Iz * J * (w[:, 2] - u[:, 2]) ** 2 / (Iz + J)
    for i, Ii in ((0, Ix), (1, Iy)):
        out = out + Ii * w[:, i] ** 2 + J * u[:, i] ** 2 - h[:, i] ** 2 / (Iz + J)
    return out / 2


@dataclass(frozen=True)
class Nutation:
    rate: float     # r [1/s]
    omega: float    # Omega [rad/s]
    rho: float      # ripple ratio b / a of dT on the nutation alone
    fast: float     # decay rate of the other pair [1/s]


def nutation(I, J: float, c: float, H: float, major: int) -> Nutation:
    M, A = linear_system(I, J, c, H, major)
    lam, vec = np.linalg.eig(np.linalg.solve(M, A))
    slow = int(np.argmax(lam.real))
    v, Q = vec[:, slow], excess_form(I, J, major)
    rho = abs(v @ Q @ v) / float((v.conj() @ Q @ v).real)
    fast = float(-np.max(lam.real[np.abs(lam.real - lam.real[slow]) > 1e-12 * abs(lam[slow])]))
    return Nutation(float(-lam.real[slow]), float(abs(lam.imag[slow])), float(rho), fast)


def ripple_tail(rho: float, harmonics: int) -> float:
    """Largest |ln(1 + rho cos theta) - its Fourier series to `harmonics` terms|."""
    q = rho / (1 + math.sqrt(max(0.0, 1 - rho * rho)))
    if q >= 1:
        return math.inf
    return 2 * q ** (harmonics + 1) / ((harmonics + 1) * (1 - q))


def harmonic_slope(t: np.ndarray, y: np.ndarray, omega: float,
                   harmonics: int) -> tuple[float, np.ndarray]:
    """(slope, weights) of the least-squares fit of y by a line plus `harmonics`
    harmonics of `omega`: the slope is weights @ y, so misfits of at most e_j in the
    samples move it by at most sum |weights_j| e_j."""
    t0 = t - t.mean()
    columns = [np.ones_like(t0), t0]
    for k in range(1, harmonics + 1):
        columns += [np.cos(k * omega * t), np.sin(k * omega * t)]
    weights = np.linalg.pinv(np.stack(columns, axis=1))[1]
    return float(weights @ y), weights


def excess_error(I, J: float, major: int, w: np.ndarray, h: np.ndarray, e: float) -> np.ndarray:
    """Largest change of :func:`excess_energy` per sample when every recorded w and h errs
    by at most e: e times the sum of |gradient| (dT/dw_i = -I_i sigma_i, dT/dh_i =
    u_i - h_i / (I_z + J) across; -I_z sigma_z and I_z sigma_z / (I_z + J) along)."""
    Ix, Iy, Iz = _renamed(I, major)
    order = [(major + k) % 3 for k in (1, 2, 3)]
    w, h = w[:, order], h[:, order]
    moments = np.array([Ix, Iy, Iz])
    u = (h - moments * w) / J
    sigma = u - w
    grad = np.abs(moments * sigma).sum(axis=1)
    grad += np.abs(u[:, :2] - h[:, :2] / (Iz + J)).sum(axis=1)
    grad += np.abs(Iz * sigma[:, 2] / (Iz + J))
    return e * grad


def transverse_state(major: int, w: np.ndarray, h: np.ndarray, I, J: float) -> np.ndarray:
    """y = (w_x, w_y, sigma_x, sigma_y) in renamed axes, one row per sample."""
    order = [(major + k) % 3 for k in (1, 2, 3)]
    moments = np.array(_renamed(I, major))
    w, h = w[:, order], h[:, order]
    sigma = (h - moments * w) / J - w
    return np.column_stack([w[:, 0], w[:, 1], sigma[:, 0], sigma[:, 1]])


def fast_log_error(I, J: float, c: float, H: float, major: int, y1: np.ndarray,
                   dt: np.ndarray) -> np.ndarray:
    """Bound on |ln dT - ln dT_nutation| at times dt after a state y1 of the linear
    system: the other pair's share. With f = y_f^T Q y_f / y_s^T Q y_s (Q >= 0: dT is
    never negative), dT / dT_s lies in [(1 - sqrt f)^2, (1 + sqrt f)^2]; each pair's
    Q-norm swings by (1 + rho) / (1 - rho) over its ripple and decays at its rate, so
    f(dt) <= f(0) (1 + rho_s)(1 + rho_f) / ((1 - rho_s)(1 - rho_f)) e^{-2 (r_f - r_s) dt}."""
    M, A = linear_system(I, J, c, H, major)
    lam, vec = np.linalg.eig(np.linalg.solve(M, A))
    Q = excess_form(I, J, major)
    coef = np.linalg.solve(vec, y1.astype(complex))
    slow = np.abs(lam.real - lam.real.max()) <= 1e-12 * np.abs(lam).max()
    parts = {key: (vec[:, pick] @ coef[pick]).real for key, pick in (("s", slow), ("f", ~slow))}
    norms = {key: float(y @ Q @ y) for key, y in parts.items()}

    def swing(pick):
        v = vec[:, np.argmax(pick)]
        rho = abs(v @ Q @ v) / float((v.conj() @ Q @ v).real)
        return (1 + rho) / (1 - rho) if rho < 1 else math.inf
    rates = -lam.real
    gap = float(rates[~slow].min() - rates[slow].min())
    f = (norms["f"] / norms["s"] * swing(slow) * swing(~slow)
         * np.exp(-2 * gap * np.asarray(dt, dtype=float)))
    root = np.sqrt(f)
    return np.where(root < 1, -2 * np.log1p(-np.minimum(root, 1 - 1e-300)), math.inf)


__all__ = ["Nutation", "excess_energy", "excess_error", "excess_form", "fast_log_error",
           "harmonic_slope", "linear_system", "nutation", "nutation_decay_rate", "ripple_tail",
           "transverse_state"]
