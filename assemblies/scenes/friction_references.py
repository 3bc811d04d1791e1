"""Independent references for seed 9.2, 9.3 and 9.5 (the scenes of friction_seed.py).

Closed forms and exact event-driven solutions of the spring-block with dry friction,
derived here from the linear ODE of each phase; nothing here calls the library's
models. Symbols as in the seed: m, k, g, mu_s, mu_k, the driven end's speed v or its
motion U sin(w t), the spring's parallel dashpot d, w0 = sqrt(k/m).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from components.translational.spring_block import SLIDING_AT

from .references import earliest_zero


# --- 9.2: steady sliding and its perturbations -----------------------------------------
def steady_sliding_lag(m: float, k: float, g: float, mu_k: float) -> float:
    """x_ss = mu_k m g / k: how far the block trails the driven end while it slides
    steadily (x = v t - x_ss; the dashpot carries nothing since x' = v)."""
    return mu_k * m * g / k


def _underdamped(m: float, k: float, d: float) -> tuple[float, float]:
    sigma = d / (2 * m)
    if sigma**2 >= k / m:
        raise ValueError(f"d = {d:g} N.s/m: the closed forms need an underdamped spring "
                         f"(d < 2 sqrt(k m) = {2 * math.sqrt(k * m):g})")
    return sigma, math.sqrt(k / m - sigma**2)


def sliding_perturbation(t, m: float, k: float, d: float, eta0: float, deta0: float = 0.0):
    """(eta, eta') of m eta'' + d eta' + k eta = 0 from (eta0, deta0) at t = 0.

    eta = x - (v t - x_ss) is the deviation from steady sliding: while the block keeps
    sliding forward the friction stays -mu_k m g, so the deviation is a free damped
    oscillation (seed 9.2: neutral when d = 0, decaying at d / 2m otherwise).
    """
    sigma, wd = _underdamped(m, k, d)
    t = np.asarray(t, dtype=float)
    c = (deta0 + sigma * eta0) / wd
    decay, cos, sin = np.exp(-sigma * t), np.cos(wd * t), np.sin(wd * t)
    return (decay * (eta0 * cos + c * sin),
            decay * (deta0 * cos - (sigma * c + wd * eta0) * sin))


def perturbation_decay_rate(m: float, d: float) -> float:
    """sigma = d / (2 m): the rate at which a disturbance of steady sliding dies out."""
    return d / (2 * m)


@dataclass(frozen=True)
class StickSlipCycle:
    """The stick-slip of seed 9.2 from rest with a dashpot d beside the spring."""
    t1: float      # first slip [s]
    t2: float      # first re-stick [s]
    x2: float      # position at the re-stick [m]
    period: float  # the cycle repeats exactly from t1 on [s]


def damped_first_slip(m, k, d, g, mu_k, mu_s, v) -> tuple[float, float, float]:
    """(t1, eta(t1), eta'(t1)) for the block of seed 9.2 pulled from rest at x = 0 with a
    dashpot d beside the spring: stuck, the pull is k v t + d v, so it slips at
    t1 = (mu_s m g - d v) / (k v); there eta = x - (v t - x_ss) starts at
    -((mu_s - mu_k) m g - d v) / k and eta' = -v."""
    N = m * g
    t1 = (mu_s * N - d * v) / (k * v)
    if t1 <= 0:
        raise ValueError("the dashpot alone overcomes static friction: the block slips at once")
    return t1, -((mu_s - mu_k) * N - d * v) / k, -v


def damped_stick_slip(m, k, d, g, mu_k, mu_s, v) -> StickSlipCycle:
    """Seed 9.2 with a dashpot d parallel to the spring (Eq. 9.1 plus d (v - x')).

    Stuck at x = 0 the spring and dashpot pull with k v t + d v, so the block slips at
    t1 = (mu_s m g - d v) / (k v). Sliding, eta = x - (v t - x_ss) obeys
    m eta'' + d eta' + k eta = 0 from eta(t1) = -((mu_s - mu_k) m g - d v) / k and
    eta'(t1) = -v; the slide ends at the first root of x' = v + eta' = 0. Stuck again,
    the pull k (v t - x2) + d v reaches mu_s m g at x2 / v + t1: each slip starts from
    the same state relative to the driven end, so the cycle repeats with period x2 / v.
    Raises ValueError where the block does not re-stick (enough damping turns the first
    slide into steady sliding: stick-slip no longer persists).
    """
    N, sigma, wd = m * g, *_underdamped(m, k, d)
    t1, eta0, deta0 = damped_first_slip(m, k, d, g, mu_k, mu_s, v)
    x_ss = steady_sliding_lag(m, k, g, mu_k)
    amplitude = math.hypot(eta0, (deta0 + sigma * eta0) / wd)

    def x_dot(tau):
        return v + float(sliding_perturbation(tau, m, k, d, eta0, deta0)[1])

    def x_ddot(tau):
        eta, deta = sliding_perturbation(tau, m, k, d, eta0, deta0)
        return float(-(k * eta + d * deta) / m)

    # x' starts at 0 and rises (x'' = (mu_s - mu_k) g > 0); |eta'''| <= (k/m)^(3/2) amplitude.
    # A slide that has not stopped within ten periods never will: x' - v decays
    horizon = 20 * math.pi / wd
    tau = earliest_zero(x_dot, x_ddot, (k / m) ** 1.5 * amplitude, 0.0, horizon, 1)
    if tau is None:
        raise ValueError(f"d = {d:g} N.s/m: the first slide never stops, stick-slip does not "
                         "persist (the block settles into steady sliding)")
    t2 = t1 + tau
    x2 = v * t2 - x_ss + float(sliding_perturbation(tau, m, k, d, eta0, deta0)[0])
    pull = k * (v * t2 - x2) + d * v
    if abs(pull) >= mu_s * N:
        raise ValueError("the block does not re-stick where its slide ends")
    # the next slip is at x2 / v + t1: in a period the block advances as far as the end
    return StickSlipCycle(t1, t2, x2, x2 / v)


# --- 9.2: the smooth law, Eq. 9.5 ------------------------------------------------------
def smooth_friction_coefficient(u, mu_k: float, mu_s: float):
    """Seed Eq. 9.5 in u = v / eps: mu_k tanh(3u) + (mu_s - mu_k) u exp(1/2 - u^2/2)."""
    u = np.asarray(u, dtype=float)
    return mu_k * np.tanh(3 * u) + (mu_s - mu_k) * u * np.exp(0.5 - u**2 / 2)


def smooth_law_peak(mu_k: float, mu_s: float) -> tuple[float, float]:
    """(u*, mu_max): where Eq. 9.5 peaks over u >= 0, and its peak value.

    The peak is "very close to" mu_s (the seed), not equal: for mu_s = 0.4, mu_k = 0.3
    it is 0.39868 at u* = 1.0364. Beyond u = 10 the law is mu_k to 1e-20, so a grid on
    [0, 10] finds the global peak, refined by a bounded scalar search.
    """
    u = np.linspace(0.0, 10.0, 100_001)
    i = int(np.argmax(smooth_friction_coefficient(u, mu_k, mu_s)))
    lo, hi = u[max(i - 1, 0)], u[min(i + 1, len(u) - 1)]
    from scipy.optimize import minimize_scalar  # here: scipy loads in 0.2-0.6 s
    best = minimize_scalar(lambda s: -float(smooth_friction_coefficient(s, mu_k, mu_s)),
                           bounds=(lo, hi), method="bounded", options={"xatol": 1e-12})
    return float(best.x), float(-best.fun)


def smooth_slip_bracket(m, k, g, mu_k, mu_s, v, eps) -> tuple[float, float]:
    """Bounds on when a block under Eq. 9.5, pulled from rest at speed v, first reaches
    the speed u* eps at which friction peaks (the onset of gross slip).

    Before then 0 <= x' < u* eps, so 0 <= x <= u* eps t. Lower: crossing upward needs
    x'' >= 0, so the pull k (v t - x) has reached mu_max m g: t >= mu_max m g / (k v).
    Upper: the pull is at least k (v - u* eps) t; once it exceeds mu_max m g by delta,
    x'' >= delta / m (friction never exceeds mu_max m g), so u* eps is reached within
    m u* eps / delta more; the best delta gives
    t <= mu_max m g / (k (v - u* eps)) + 2 sqrt(m u* eps / (k (v - u* eps))).
    """
    u_star, mu_max = smooth_law_peak(mu_k, mu_s)
    creep = u_star * eps
    if creep >= v:
        raise ValueError(f"eps = {eps:g} m/s: the bounds need u* eps < v (u* = {u_star:.4f})")
    lower = mu_max * m * g / (k * v)
    upper = mu_max * m * g / (k * (v - creep)) + 2 * math.sqrt(m * creep / (k * (v - creep)))
    return lower, upper


def law_coefficient(law: str, u, mu_k: float, mu_s: float):
    """The friction coefficient of SpringBlock's smooth laws in u = v / eps: ``smooth``
    (Eq. 9.5) or ``tanh`` (Eq. 9.7, mu_k tanh(3u), no stiction)."""
    if law == "smooth":
        return smooth_friction_coefficient(u, mu_k, mu_s)
    return mu_k * np.tanh(3 * np.asarray(u, dtype=float))


def smooth_mode_slip_bracket(law: str, m, k, g, mu_k, mu_s, v, eps,
                             level: float = SLIDING_AT) -> tuple[float, float]:
    """Bounds on when a block under a smooth law, pulled from rest at speed v, first
    reports sliding: its mode flips where x' reaches `level` eps (SpringBlock: 3 eps,
    beyond the stiction peak of Eq. 9.5).

    Before then 0 <= x' < level eps, so 0 <= x <= level eps t, and friction never exceeds
    the law's supremum mu_sup m g (Eq. 9.5's peak, mu_k for Eq. 9.7). Lower: to pass the
    peak (Eq. 9.5) the pull k (v t - x) <= k v t must reach mu_max m g (x'' >= 0 there);
    for Eq. 9.7, crossing `level` upward needs the pull to reach the friction there.
    Upper: the pull is at least k (v - level eps) t; once it exceeds mu_sup m g by delta,
    x'' >= delta / m and level eps is reached within m level eps / delta more; the best
    delta gives t <= mu_sup m g / (k (v - c)) + 2 sqrt(m c / (k (v - c))), c = level eps.
    """
    creep = level * eps
    if creep >= v:
        raise ValueError(f"eps = {eps:g} m/s: the bounds need {level:g} eps < v = {v:g} m/s")
    if law == "smooth":
        mu_sup = smooth_law_peak(mu_k, mu_s)[1]
        mu_needed = mu_sup
    else:
        mu_sup = mu_k
        mu_needed = float(law_coefficient(law, level, mu_k, mu_s))
    lower = mu_needed * m * g / (k * v)
    upper = mu_sup * m * g / (k * (v - creep)) + 2 * math.sqrt(m * creep / (k * (v - creep)))
    return lower, upper


#: beyond u = v / eps = 20 both smooth laws are mu_k to double precision (Eq. 9.7 differs by
#: 2 mu_k e^-120; Eq. 9.5's stiction term by (mu_s - mu_k) 20 e^-199.5)
LAW_BAND = 20.0


def _band_integrals(law: str, accel: float, sign: int, g, mu_k, mu_s, eps):
    """(time, distance) a smooth law takes over Coulomb's mu_k to cross |v| < LAW_BAND eps
    at the frozen spring acceleration `accel`, friction helping it (sign +1: the approach
    to rest) or opposing it (sign -1: leaving rest). inf where friction there can beat the
    spring (the block would not leave rest the way Coulomb's reverses)."""
    from scipy.integrate import quad

    u = np.linspace(0.0, LAW_BAND, 4001)
    if sign < 0 and float(np.min(accel - g * law_coefficient(law, u, mu_k, mu_s))) <= 0:
        return math.inf, math.inf

    def excess(u, power):
        smooth = accel + sign * g * float(law_coefficient(law, u, mu_k, mu_s))
        return u**power * (1.0 / smooth - 1.0 / (accel + sign * g * mu_k))

    spots = [0.5, 1.0, 2.0, 4.0]  # where the laws bend: u ~ 1
    time = quad(excess, 0.0, LAW_BAND, args=(0,), points=spots, epsabs=0, limit=200)[0]
    distance = quad(excess, 0.0, LAW_BAND, args=(1,), points=spots, epsabs=0, limit=200)[0]
    return eps * time, eps**2 * distance


def smooth_turning_allowance(law: str, m, k, g, mu_k, mu_s, eps,
                             amplitudes: list[float]) -> list[tuple[float, float]]:
    """How far a smooth law's turning points (x' = 0) may lie from exact Coulomb
    friction's in seed 9.4, where the block swings about a fixed end through turning
    points at distances `amplitudes` from it (A_0 the release from rest): [(time,
    position)] for each.

    The laws are Coulomb's kinetic mu_k outside |v| < LAW_BAND eps, so between turns the
    motion is Coulomb's half cycle exactly, only shifted in time and space by what each
    band does differently. Crossing a band (V = LAW_BAND eps) the block moves at most
    V^2 / (2 |x''|), so the spring's pull per mass stays within k V^2 / (2 m |x''|) of
    k|A|/m (under 1e-3 of it for the scene's eps = 1e-3). With the pull held fixed, the
    time and distance from the band's edge to rest (friction helping the spring back)
    and from rest to the far edge (friction against it) are quadratures of
    1 / (pull +- g mu(v/eps)) against Coulomb's with mu_k; each is taken at whichever
    end of the pull's range makes it largest. Turning point n carries those of every
    band before it plus the approach half of its own; summed in absolute value (the
    time shifts alternate in sign). An estimate, not a bound: the position shifts'
    effect on the phase (of order the distance shift over LAW_BAND eps) is left out,
    far smaller than the sum for eps << |A| sqrt(k/m); where friction in a band can
    beat the spring (the block would stay at rest, unlike Coulomb's) it is inf.
    """
    mu_sup = float(np.max(law_coefficient(law, np.linspace(0.0, LAW_BAND, 4001), mu_k, mu_s)))

    def band(accel, sign):
        # the spring moves by at most k/m times the band's length, V^2 / (2 x''): the
        # integrals, monotone in the spring's pull, are largest at one end of that range
        slowest = accel if sign > 0 else accel - g * mu_sup  # the least |x''| in the band
        if slowest <= 0:
            return math.inf, math.inf
        spread = k / m * (LAW_BAND * eps) ** 2 / (2 * slowest)
        ends = [_band_integrals(law, a, sign, g, mu_k, mu_s, eps)
                for a in (accel - spread, accel + spread)]
        return max(abs(e[0]) for e in ends), max(abs(e[1]) for e in ends)

    shifts = []
    for i, amplitude in enumerate(amplitudes):
        accel = k * abs(amplitude) / m
        approach = (0.0, 0.0) if i == 0 else band(accel, 1)
        leave = band(accel, -1) if i < len(amplitudes) - 1 else (0.0, 0.0)
        shifts.append((approach, leave))
    allowance, carried_t, carried_x = [], 0.0, 0.0
    for (approach_t, approach_x), (leave_t, leave_x) in shifts:
        allowance.append((carried_t + abs(approach_t), carried_x + abs(approach_x)))
        carried_t += abs(approach_t) + abs(leave_t)
        carried_x += abs(approach_x) + abs(leave_x)
    return allowance


def creep_speed(law: str, m, g, mu_k, mu_s, eps, spring_force: float) -> float:
    """The largest speed a block at rest under a smooth law reaches while a spring force
    of at most `spring_force` pulls it and friction opposes: the least v > 0 where the
    law's friction mu(v / eps) m g balances the force (the block accelerates from rest
    until it gets there and, the force never larger, never passes it). inf where the law
    never balances it (the block slides off)."""
    from scipy.optimize import brentq

    need = spring_force / (m * g)
    if need <= 0:
        return 0.0
    u = np.linspace(0.0, LAW_BAND, 20001)
    above = np.flatnonzero(law_coefficient(law, u, mu_k, mu_s) >= need)
    if not len(above):
        return math.inf
    j = int(above[0])
    root = brentq(lambda s: float(law_coefficient(law, s, mu_k, mu_s)) - need, u[j - 1], u[j],
                  xtol=1e-15, rtol=8.9e-16)
    return eps * root


def richardson_bound(coarse: float, fine: float, ratio: float, order: float) -> float:
    """The error at the coarse parameter from a convergence study with parameters in the
    given ratio: |coarse - fine| / (1 - ratio^-order). An upper bound when the error is a
    sum of terms of one sign whose orders are all at least `order`."""
    return abs(coarse - fine) / (1 - ratio ** -order)


# --- 9.3: the distinguished limit ------------------------------------------------------
def chain_first_slip(n: int, m: float, k: float, g: float, mu_s: float, v: float) -> float:
    """Seed 9.3: the block as n masses m/n in a row joined by springs K, pulled at its
    front through the spring k whose end moves at speed v, all at rest and unstretched
    at t = 0.

    Until something slips nothing moves but the driven end, so the springs K stay
    unstretched and carry nothing: the front mass alone holds the pull k v t, with
    static friction mu_s m g / n. It slips first, at t = mu_s m g / (n k v): n times
    earlier than the rigid block (n = 1), whatever K is.
    """
    return mu_s * m * g / (n * k * v)


def two_halves_rear_slip(m: float, k: float, g: float, mu_k: float, mu_s: float,
                         v: float) -> float:
    """Seed 9.3, n = 2: when the rear half first slips (the whole block slides), as K
    grows without bound after eps -> 0 (exact Coulomb friction).

    With N = m g / 2 and D = (mu_s - mu_k) N: the front half slips when the pull, k v t
    (the halves move by O(1/K)), exceeds the inner spring's tension F by mu_s N; it
    then slides against mu_k N in a fast oscillation on K about P - mu_k N and stops
    half a fast period later with F raised by 2 D, sticking again (P - F = mu_s N - 2 D
    is within the static limit). The tension climbs this staircase, 2 D a step, one
    step each time the pull gains 2 D, until a step would carry it past mu_s N: the
    rear half, held by static friction mu_s N, slips during step j = ceil(mu_s N / 2D),
    at the pull mu_s N + 2 (j - 1) D. For the seed's mu_s = 0.4, mu_k = 0.3: j = 2, the
    pull 0.3 m g, t = 6 s against the rigid block's 8 s. At finite K each step starts
    later by a part of the fast period ~ sqrt(m / K), so the time falls like K^-1/2.
    """
    N, D = m * g / 2, (mu_s - mu_k) * m * g / 2
    if D <= 0:
        raise ValueError("two_halves_rear_slip: needs mu_s > mu_k (the staircase steps by "
                         "2 (mu_s - mu_k) m g / 2)")
    steps = math.ceil(mu_s * N / (2 * D) - 1e-9)  # a step that reaches mu_s N exactly counts
    return (mu_s * N + 2 * (steps - 1) * D) / (k * v)


# --- 9.5: resonance --------------------------------------------------------------------
def resonance_growth_rate(m, k, g, mu, U) -> float:
    """Seed 9.5: growth of the amplitude per unit time at resonance (w = w0),
    w0 (U pi - 4 mu m g / k) / (2 pi); (pi - 2.4) / (2 pi) = 0.118 for the seed's U = 1."""
    return math.sqrt(k / m) * (U * math.pi - 4 * mu * m * g / k) / (2 * math.pi)


def resonance_threshold(m, k, g, mu) -> float:
    """U* = 4 mu m g / (pi k): the forcing amplitude above which resonance grows."""
    return 4 * mu * m * g / (math.pi * k)


def half_period_turning_points(m, k, g, mu, U, x0, t_end):
    """Turning points (t, x) of seed 9.5 at resonance from rest at x0, while every slide
    lasts exactly half a period: t_j = j pi / w0.

    The particular solution -(U w0 t / 2) cos(w0 t) moves the cos(w0 t) part by U pi / 2
    per half period, friction by 2 mu m g / k. From x0 > 0 (the seed's x(0) = 10) the
    forcing is in anti-phase: |x| falls by U pi/2 + 2 mu m g/k, and the slide from a
    turning point |x| = a lasts a half period while a >= mu m g/k + U pi/2 (its speed
    w0 sin(w0 t) (U w0 t/2 - (a - mu m g/k)) keeps one sign). From x0 < 0 it is in phase:
    |x| changes by U pi/2 - 2 mu m g/k, the seed's growth rate, while a > mu m g/k.
    """
    w0, slack = math.sqrt(k / m), mu * m * g / k
    a, sign, t, j = abs(x0), math.copysign(1.0, x0), 0.0, 0
    points = [(0.0, x0)]
    while True:
        if sign > 0 and a < slack + U * math.pi / 2 or sign < 0 and a <= slack:
            return points  # the next slide is not a half period long: the law ends here
        a += (-U * math.pi / 2 - 2 * slack) if sign > 0 else (U * math.pi / 2 - 2 * slack)
        j += 1
        t = j * math.pi / w0
        if t > t_end:
            return points
        points.append((t, (-1) ** j * sign * a))


def eq_9_10(U: float, x0: float, v0: float, t, mu: float = 0.6, scale: float = 1e-3):
    """(x, x') at the times t of seed Eq. 9.10 as printed,
    x'' = -x + U sin t - mu tanh(x' / 0.001), by scipy's Radau (exact Jacobian, rtol
    1e-12): an independent integration of the seed's equation, for the scenes that run
    it through SpringBlock's tanh law."""
    from scipy.integrate import solve_ivp

    def rhs(tt, y):
        return [y[1], -y[0] + U * math.sin(tt) - mu * math.tanh(y[1] / scale)]

    def jac(tt, y):
        # sech^2 as 1 - tanh^2: cosh overflows beyond |x'| ~ 0.7
        return [[0.0, 1.0], [-1.0, -mu / scale * (1 - math.tanh(y[1] / scale) ** 2)]]
    t = np.asarray(t, dtype=float)
    sol = solve_ivp(rhs, (0.0, float(t[-1])), [x0, v0], method="Radau", jac=jac, t_eval=t,
                    rtol=1e-12, atol=1e-14)
    return sol.y[0], sol.y[1]


def eq_9_5_gross_slip(m, k, g, mu_k, mu_s, v, eps, t_end) -> tuple[float, float]:
    """(t1, t2): where x' of the seed 9.2 block under Eq. 9.5, pulled from rest at speed
    v, first rises through the law's peak speed u* eps and then falls back through it;
    scipy's Radau (exact Jacobian, rtol 1e-12) with its own event location, written from
    the equation (m x'' = k (v t - x) - mu(x'/eps) m g), not from the library's models.
    NaN where the run to t_end has fewer crossings."""
    from scipy.integrate import solve_ivp
    u_star = smooth_law_peak(mu_k, mu_s)[0]

    def rhs(t, y):
        return [y[1], (k * (v * t - y[0])) / m
                - g * float(smooth_friction_coefficient(y[1] / eps, mu_k, mu_s))]

    def jac(t, y):
        u = y[1] / eps
        slope = (3 * mu_k * (1 - math.tanh(3 * u) ** 2)
                 + (mu_s - mu_k) * (1 - u * u) * math.exp(0.5 - u * u / 2)) / eps
        return [[0.0, 1.0], [-k / m, -g * slope]]

    def level(t, y):
        return y[1] - u_star * eps
    sol = solve_ivp(rhs, (0.0, t_end), [0.0, 0.0], method="Radau", jac=jac, events=level,
                    rtol=1e-12, atol=1e-15)
    found = list(sol.t_events[0][:2]) + [math.nan, math.nan]
    return float(found[0]), float(found[1])


@dataclass
class Phase:
    """One phase of the driven block: from time t on, in friction mode (-1 sliding
    backward, 0 stuck, +1 forward, as the components count it), from state (x, v)."""
    t: float
    x: float
    v: float
    mode: int


class DrivenCoulombBlock:
    """Seed Eqs. 9.8-9.9: m x'' = k (U sin(w t) - x) + f with exact Coulomb friction
    (mu_s >= mu_k, incipient sliding as in Eq. 9.3), solved phase by phase.

    Sliding in mode s, x = -s mu_k m g / k + A cos(w0 tau) + B sin(w0 tau) + p(t) with
    p the particular solution of the forcing (U w0^2 / (w0^2 - w^2) sin(w t), or at
    resonance -(U w0 t / 2) cos(w0 t)); a slide ends at the earliest zero of its speed,
    a stick at the earliest time the spring's pull reaches mu_s m g, both found by the
    rigorous search of :func:`.references.earliest_zero` (no short phase can be skipped).
    """

    def __init__(self, m, k, g, mu_s, mu_k, U, omega):
        if mu_k > mu_s:
            raise ValueError("DrivenCoulombBlock: needs mu_k <= mu_s")
        self.m, self.k, self.U, self.w = m, k, U, omega
        self.w0, self.N = math.sqrt(k / m), m * g
        self.mu_s, self.mu_k = mu_s, mu_k
        self.resonant = math.isclose(omega, self.w0, rel_tol=1e-12)

    # the particular solution and its derivatives
    def _p(self, n: int, t: float) -> float:
        U, w0 = self.U, self.w0
        if self.resonant:  # p = -(U w0 / 2) t cos(w0 t): d^n (t c) = t c^(n) + n c^(n-1)
            c = lambda j: w0**j * math.cos(w0 * t + j * math.pi / 2)  # noqa: E731
            return -(U * w0 / 2) * (t * c(n) + (n * c(n - 1) if n else 0.0))
        amp = U * w0**2 / (w0**2 - self.w**2)
        return amp * self.w**n * math.sin(self.w * t + n * math.pi / 2)

    def _p_bound(self, n: int, t_max: float) -> float:
        if self.resonant:
            return (self.U * self.w0 / 2) * (t_max * self.w0**n + n * self.w0 ** (n - 1))
        return abs(self.U * self.w0**2 / (self.w0**2 - self.w**2)) * self.w**n

    def _slide(self, ph: Phase):
        """(x, v, a) of t during the slide `ph`, and the amplitude of its free part."""
        c0, w0 = -ph.mode * self.mu_k * self.N / self.k, self.w0
        A = ph.x - c0 - self._p(0, ph.t)
        B = (ph.v - self._p(1, ph.t)) / w0

        def state(t):
            """x, v, a and the jerk at t."""
            tau = t - ph.t
            cos, sin = math.cos(w0 * tau), math.sin(w0 * tau)
            return (c0 + A * cos + B * sin + self._p(0, t),
                    w0 * (B * cos - A * sin) + self._p(1, t),
                    -w0**2 * (A * cos + B * sin) + self._p(2, t),
                    w0**3 * (A * sin - B * cos) + self._p(3, t))
        return state, math.hypot(A, B)

    def _quiet_start(self, ph: Phase, state, amplitude: float, t_end: float) -> float:
        """A time after ph.t before which the slide's speed provably keeps its sign.

        A slide starts from rest with s a >= 0; after a stick with mu_s = mu_k it starts
        with a = 0 exactly and only the jerk moves it, so its speed is ~ tau^2 and lost
        in rounding near the start. From s v >= a0 tau + j0 tau^2/2 - C tau^3/6 (C bounds
        the fourth derivative of x) no zero lies before half the positive root.
        """
        _, _, a, jerk = state(ph.t)
        # s a >= 0 by construction (the pull reached mu_s m g >= mu_k m g); rounding can
        # show -1e-16, which would end the slide where it starts
        a0, j0 = max(ph.mode * a, 0.0), ph.mode * jerk
        c = (self.w0**4 * amplitude + self._p_bound(4, t_end)) / 6
        if a0 == 0 and j0 <= 0:
            return ph.t  # nothing to skip: the search starts where the phase does
        root = (j0 / 2 + math.sqrt(j0**2 / 4 + 4 * c * a0)) / (2 * c)
        return min(ph.t + root / 2, t_end)

    def _pull(self, t: float, x: float) -> float:
        return self.k * (self.U * math.sin(self.w * t) - x)

    def _mode_at_rest(self, t: float, x: float) -> int:
        """The mode a block at rest takes: it breaks free where the pull reaches mu_s m g."""
        pull = self._pull(t, x)
        return 0 if abs(pull) < self.mu_s * self.N else int(math.copysign(1, pull))

    def solve(self, x0: float, v0: float, t_end: float) -> list[Phase]:
        """Every phase from t = 0 to t_end, in order."""
        mode = int(math.copysign(1, v0)) if v0 else self._mode_at_rest(0.0, x0)
        phases = [Phase(0.0, x0, v0, mode)]
        while True:
            ph = phases[-1]
            if ph.mode == 0:
                limit, U, w = self.mu_s * self.N, self.U, self.w
                ends = []
                for s in (1, -1):
                    t = earliest_zero(lambda t, s=s: limit - s * self._pull(t, ph.x),
                                       lambda t, s=s: -s * self.k * U * w * math.cos(w * t),
                                       self.k * abs(U) * w**2, ph.t, t_end, 1)
                    if t is not None:
                        ends.append((t, s))
                if not ends:
                    return phases
                t, s = min(ends)
                phases.append(Phase(t, ph.x, 0.0, s))
                continue
            state, amplitude = self._slide(ph)
            curvature = self.w0**3 * amplitude + self._p_bound(3, t_end)
            t = earliest_zero(lambda t: state(t)[1], lambda t: state(t)[2], curvature,
                               self._quiet_start(ph, state, amplitude, t_end), t_end, ph.mode)
            if t is None:
                return phases
            x = state(t)[0]
            phases.append(Phase(t, x, 0.0, self._mode_at_rest(t, x)))

    def position(self, phases: list[Phase], t) -> np.ndarray:
        """x at the times t (within the solved span)."""
        t = np.atleast_1d(np.asarray(t, dtype=float))
        out = np.empty_like(t)
        starts = np.array([ph.t for ph in phases])
        for i, ti in enumerate(t):
            ph = phases[max(int(np.searchsorted(starts, ti, side="right")) - 1, 0)]
            out[i] = ph.x if ph.mode == 0 else self._slide(ph)[0](ti)[0]
        return out


def slide_ends(phases: list[Phase]) -> list[Phase]:
    """The phases that begin where a slide ended: the turning points of the motion."""
    return [ph for prev, ph in zip(phases, phases[1:]) if prev.mode != 0]


__all__ = ["LAW_BAND", "DrivenCoulombBlock", "Phase", "StickSlipCycle", "chain_first_slip",
           "creep_speed", "damped_first_slip", "damped_stick_slip", "eq_9_10", "eq_9_5_gross_slip", "half_period_turning_points",
           "perturbation_decay_rate", "resonance_growth_rate", "resonance_threshold",
           "richardson_bound", "sliding_perturbation", "slide_ends",
           "smooth_friction_coefficient", "smooth_law_peak", "smooth_slip_bracket",
           "smooth_turning_allowance", "steady_sliding_lag", "two_halves_rear_slip"]
