"""Independent reference for MSL's CoupledClutches, written from MSL's documented equations.

Nothing here calls the library's models. The drive train is four inertias J1..J4 joined
by three clutches; clutch k joins body k (its flange_a) and body k+1 (flange_b), with
``w_rel = w[k+1] - w[k]`` and MSL's friction torque ``tau_k`` acting +tau_k on body k and
-tau_k on body k+1 (``flange_b.tau = tau``). Per MSL's Clutch and PartialFriction:

- free (``fn = fn_max f_normalized <= 0``): tau_k = 0;
- sliding forward / backward (mode +1 / -1): tau_k = mode mu cgeo fn;
- locked (mode 0): w_rel stays 0, tau_k is what the torque balance needs, as long as
  ``|tau_k| <= peak mu cgeo fn``; beyond it the clutch slides in the direction of tau_k.

Between events the accelerations are the solution of one linear system (the torque
balances plus each clutch's law); events are located by scipy's solve_ivp on the
indicators (w_rel of a sliding clutch, the static margin of a locked one, fn of each
clutch) and at the signals' step times, where the integration restarts.
"""
from __future__ import annotations

import functools
import math
from dataclasses import dataclass, field

import numpy as np

RTOL = 1e-12  # solve_ivp's tolerances here: event times to ~1e-10 s, far inside 1e-4


@dataclass(frozen=True)  # hashable: a parameter set names its cached solution
class CoupledClutches:
    """MSL.Mechanics.Rotational.Examples.CoupledClutches (MSL 4 parameters)."""
    J: tuple = (1.0, 1.0, 1.0, 1.0)
    w0: tuple = (10.0, 0.0, 0.0, 0.0)
    fn_max: float = 20.0
    peak: float = 1.1
    mu: float = 0.5    # mu_pos = [0, 0.5]: constant
    cgeo: float = 1.0
    amplitude: float = 10.0  # sin1: driving torque on J1
    f1: float = 5.0
    f2: float = 0.2          # sin2 (phase pi/2): clutch1's f_normalized
    T2: float = 0.4          # step1: clutch2
    T3: float = 0.9          # step2: clutch3
    stop: float = 1.5

    def torque(self, t):
        return self.amplitude * math.sin(2 * math.pi * self.f1 * t)

    def fn(self, t) -> np.ndarray:
        f_norm = (math.sin(2 * math.pi * self.f2 * t + math.pi / 2),
                  1.0 if t >= self.T2 else 0.0, 1.0 if t >= self.T3 else 0.0)
        return self.fn_max * np.array(f_norm)


def _accelerations(m: CoupledClutches, t, modes, fn):
    """(a[4], tau[3]) for the modes (0 locked, +-1 sliding; a clutch with fn <= 0 free)."""
    A, b = np.zeros((7, 7)), np.zeros(7)
    for i in range(4):  # J_i a_i - tau_{i} + tau_{i-1} = T (on body 0)
        A[i, i] = m.J[i]
        if i < 3:
            A[i, 4 + i] = -1.0
        if i > 0:
            A[i, 4 + i - 1] = 1.0
    b[0] = m.torque(t)
    for k in range(3):
        row = 4 + k
        if fn[k] <= 0:
            A[row, 4 + k] = 1.0
        elif modes[k] == 0:
            A[row, k + 1], A[row, k] = 1.0, -1.0
        else:
            A[row, 4 + k], b[row] = 1.0, modes[k] * m.mu * m.cgeo * fn[k]
    sol = np.linalg.solve(A, b)
    return sol[:4], sol[4:]


@dataclass
class Solution:
    t: np.ndarray
    w: np.ndarray                       # (len(t), 4)
    events: list = field(default_factory=list)  # (time, clutch 1..3, new mode) in order


def _settle(m, t, w, modes, fn):
    """Modes consistent at (t, w): locks where w_rel is 0, breaks where the margin is
    exceeded (the largest excess first: one clutch's break changes the others' needs)."""
    modes = list(modes)
    for _ in range(20):  # 3 clutches, each changes at most a few times per instant
        _, tau = _accelerations(m, t, modes, fn)
        excess = [abs(tau[k]) - m.peak * m.mu * m.cgeo * fn[k]
                  if fn[k] > 0 and modes[k] == 0 else -1.0 for k in range(3)]
        k = int(np.argmax(excess))
        if excess[k] <= 0:
            return modes
        modes[k] = 1 if tau[k] > 0 else -1
    raise RuntimeError("CoupledClutches reference: modes did not settle")


def coupled_clutches(m: CoupledClutches | None = None, grid=None) -> Solution:
    """The reference solution: speeds on `grid` (default 1 ms) and every mode change of
    an engaged clutch (a free clutch's mode is not recorded: it carries no torque).

    On the default grid the solution is computed once per parameter set: at rtol 1e-12
    it costs more than the engine's run it judges (0.05 against 0.03 s CPU), and a
    run's figures, repeated, would time the reference instead of the run."""
    m = m or CoupledClutches()
    if grid is None:
        return _on_default_grid(m)
    return _solve(m, np.asarray(grid))


@functools.lru_cache(maxsize=8)
def _on_default_grid(m: CoupledClutches) -> Solution:
    sol = _solve(m, np.arange(0.0, m.stop + 5e-4, 1e-3))
    for a in (sol.t, sol.w):  # shared by every caller: read-only
        a.flags.writeable = False
    sol.events = tuple(sol.events)
    return sol


def _solve(m: CoupledClutches, grid: np.ndarray) -> Solution:
    from scipy.integrate import solve_ivp
    t, w = 0.0, np.array(m.w0, dtype=float)
    fn = m.fn(t)
    modes = [int(np.sign(w[k + 1] - w[k])) for k in range(3)]
    modes = _settle(m, t, w, modes, fn)
    out_t, out_w, events = [], [], []
    breaks = sorted({m.T2, m.T3, m.stop})
    while t < m.stop:
        t_end = next(b for b in breaks if b > t)

        def rhs(tt, ww, modes=tuple(modes)):
            return _accelerations(m, tt, modes, m.fn(tt))[0]

        # each indicator is positive while its mode holds and fires only on its way down,
        # so one that starts at 0 (the event just handled) does not fire again
        indicators = []
        engaged = m.fn(t + 1e-14) > 0  # a free clutch has nothing to detect until engaged
        for k in range(3):
            if not engaged[k]:
                indicators.append(lambda tt, ww: 1.0)
            elif modes[k] != 0:
                indicators.append(lambda tt, ww, k=k, q=modes[k]: q * (ww[k + 1] - ww[k]))
            else:
                def margin(tt, ww, k=k, modes=tuple(modes)):
                    f = m.fn(tt)
                    return m.peak * m.mu * m.cgeo * f[k] - abs(_accelerations(m, tt, modes, f)[1][k])
                indicators.append(margin)
        if engaged[0]:  # clutch1 disengages (sin2 < 0)
            indicators.append(lambda tt, ww: m.fn(tt)[0])
        for ev in indicators:
            ev.terminal, ev.direction = True, -1
        sol = solve_ivp(rhs, (t, t_end), w, method="DOP853", rtol=RTOL, atol=RTOL,
                        events=indicators, dense_output=True)
        t_new = float(sol.t[-1])
        if t_new <= t:
            raise RuntimeError(f"CoupledClutches reference: no progress at t = {t}")
        inside = (grid >= t) & (grid < t_new) if t_new < m.stop else (grid >= t) & (grid <= t_new)
        out_t.append(grid[inside])
        out_w.append(sol.sol(grid[inside]).T if inside.any() else np.zeros((0, 4)))
        w = sol.sol(t_new)
        t = t_new
        if t >= m.stop:
            break
        fn = m.fn(t + 1e-14)  # the signals' values after a step at t
        fired = {i for i, te in enumerate(sol.t_events) if len(te) and te[0] == t}
        _, tau = _accelerations(m, t, modes, fn)
        new = list(modes)
        for k in range(3):
            w_rel = w[k + 1] - w[k]
            if fn[k] <= 0 or not engaged[k]:  # free, or engaged just now: by its slip
                new[k] = int(np.sign(w_rel))
            elif k in fired and modes[k] != 0:  # a slide ends: locked, exactly
                w[k + 1] = w[k]
                new[k] = 0
            elif k in fired:  # the static margin reached 0: it breaks away along tau
                new[k] = 1 if tau[k] > 0 else -1
        new = _settle(m, t, w, new, fn)
        for k in range(3):
            if new[k] != modes[k] and fn[k] > 0 and engaged[k]:
                events.append((t, k + 1, new[k]))
        modes = new
    return Solution(np.concatenate(out_t), np.concatenate(out_w), events)
