"""Independent references for MSL's Rotational.Examples.Friction and .OneWayClutch,
written from MSL's documented equations; nothing here calls the library's models.

A drive train is rigid inertias ``J_i`` (states phi_i, w_i), known torques on them
(sources, springs and dampers: functions of t, phi, w) and friction contacts. Contact k
joins body ``a`` (or the housing) and body ``b``, ``w_rel = w_b - w_a``, and carries
MSL's friction torque ``tau_k`` (``flange_b.tau``): -tau_k on body b, +tau_k on body a.
Per MSL's Clutch / Brake (PartialFriction) and OneWayClutch, with ``fn(t)`` the normal
force and the constant mu of the examples (``mu_pos = [0, mu]``):

- free (``fn <= 0``): tau = 0 (a one-way clutch keeps its freewheel, see below);
- sliding forward / backward (mode +1 / -1): tau = mode mu cgeo fn;
- locked (mode 0): ``w_rel`` stays 0, tau is what the torque balance needs, while
  ``|tau| <= peak mu cgeo fn``; beyond it the contact slides in the direction of tau.
- one-way clutch: never slides backward; locked, it holds any tau <= peak mu cgeo fn
  (0 while free: a freewheel), and a forward slide that stops locks.

Between events the accelerations solve one linear system (the bodies' torque balances
and each contact's law); solve_ivp (DOP853) locates the events on the indicators (the
relative speed of a sliding contact, the static margins of a locked one) and restarts
at each time where a signal jumps.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Callable

import numpy as np

RTOL = 1e-12  # solve_ivp's tolerances: event times to ~1e-10 s, far inside the scenes'


@dataclass
class Contact:
    a: int | None            # driving body (None: the housing, a brake)
    b: int                   # driven body
    fn: Callable             # normal force at t [N]
    mu: float = 0.5
    cgeo: float = 1.0
    peak: float = 1.0
    one_way: bool = False

    def kinetic(self, t):
        return self.mu * self.cgeo * max(self.fn(t), 0.0)


@dataclass
class DriveTrain:
    J: tuple
    torques: Callable        # (t, phi, w) -> known torques on the bodies
    contacts: list
    breaks: tuple = ()       # times where a signal jumps (fn or a torque)


@dataclass
class Solution:
    t: np.ndarray
    y: np.ndarray            # (len(t), 2 n): phi then w
    events: list = field(default_factory=list)  # (time, contact index, new mode)


def _w_rel(c: Contact, w):
    return w[c.b] - (w[c.a] if c.a is not None else 0.0)


def _solve(m: DriveTrain, t, y, modes):
    """(accelerations, contact torques) for the modes."""
    n, k = len(m.J), len(m.contacts)
    phi, w = y[:n], y[n:]
    A, rhs = np.zeros((n + k, n + k)), np.zeros(n + k)
    rhs[:n] = m.torques(t, phi, w)
    for i in range(n):
        A[i, i] = m.J[i]
    for j, c in enumerate(m.contacts):
        A[c.b, n + j] += 1.0          # J_b a_b + tau_j = ...
        if c.a is not None:
            A[c.a, n + j] -= 1.0      # J_a a_a - tau_j = ...
        row = n + j
        held = modes[j] == 0 and (c.one_way or c.fn(t) > 0)
        if held:
            A[row, c.b] = 1.0
            if c.a is not None:
                A[row, c.a] = -1.0
        else:
            A[row, n + j], rhs[row] = 1.0, modes[j] * c.kinetic(t)
    sol = np.linalg.solve(A, rhs)
    return sol[:n], sol[n:]


def _static(c: Contact, t):
    return c.peak * c.kinetic(t)


def _excess(c: Contact, t, tau):
    """How far a locked contact's torque is beyond what it can hold, and which way it
    then slides (excess <= 0: it holds)."""
    limit = _static(c, t)
    if c.one_way:
        return tau - limit, 1
    return abs(tau) - limit, (1 if tau > 0 else -1)


def _settle(m, t, y, modes):
    """Modes consistent at (t, y): a free two-way contact follows its relative speed's
    sign; a locked contact beyond its limit breaks (the largest excess first: one
    contact's break changes the others' torques)."""
    modes = list(modes)
    n = len(m.J)
    for j, c in enumerate(m.contacts):
        if not c.one_way and c.fn(t) <= 0:
            modes[j] = int(np.sign(_w_rel(c, y[n:])))
    for _ in range(4 * len(modes) + 1):
        _, tau = _solve(m, t, y, modes)
        best, pick = 0.0, None
        for j, c in enumerate(m.contacts):
            if modes[j] == 0 and (c.one_way or c.fn(t) > 0):
                excess, way = _excess(c, t, tau[j])
                # at the threshold itself the contact breaks free (an event located
                # at exactly zero margin must switch, or it would stay locked)
                if excess >= 0 and (pick is None or excess > best):
                    best, pick = excess, (j, way)
        if pick is None:
            return modes
        modes[pick[0]] = pick[1]
    raise RuntimeError("drive train reference: modes did not settle")


def simulate(m: DriveTrain, y0, stop: float, grid) -> Solution:
    """The event-driven solution from y0 (phi then w) to `stop`, sampled on `grid`."""
    from scipy.integrate import solve_ivp
    n = len(m.J)
    t, y = 0.0, np.array(y0, dtype=float)
    modes = [int(np.sign(_w_rel(c, y[n:]))) for c in m.contacts]
    if any(c.one_way and q < 0 for c, q in zip(m.contacts, modes)):
        raise ValueError("one-way clutch starting with w_rel < 0 (MSL: not possible)")
    modes = _settle(m, t, y, modes)
    grid = np.asarray(grid)
    out_t, out_y, events = [], [], []
    breaks = sorted({*[b for b in m.breaks if 0 < b < stop], stop})
    while t < stop:
        t_end = next(b for b in breaks if b > t)

        def rhs(tt, yy, modes=tuple(modes)):
            return np.concatenate([yy[n:], _solve(m, tt, yy, modes)[0]])

        # each indicator is positive while its mode holds and fires on its way down
        indicators, owners = [], []
        for j, c in enumerate(m.contacts):
            engaged = c.one_way or c.fn(t + 1e-14) > 0
            if not engaged:
                continue  # free: nothing happens until a break engages it
            owners.append(j)
            if modes[j] != 0:
                indicators.append(lambda tt, yy, c=c, q=modes[j]: q * _w_rel(c, yy[n:]))
                continue

            def margin(tt, yy, j=j, c=c, modes=tuple(modes)):
                tau = _solve(m, tt, yy, modes)[1][j]
                return -_excess(c, tt, tau)[0]
            indicators.append(margin)
        for ev in indicators:
            ev.terminal, ev.direction = True, -1
        sol = solve_ivp(rhs, (t, t_end), y, method="DOP853", rtol=RTOL, atol=RTOL,
                        events=indicators or None, dense_output=True)
        t_new = float(sol.t[-1])
        if t_new <= t:
            raise RuntimeError(f"drive train reference: no progress at t = {t}")
        last = t_new >= stop
        inside = (grid >= t) & ((grid <= t_new) if last else (grid < t_new))
        out_t.append(grid[inside])
        out_y.append(sol.sol(grid[inside]).T if inside.any() else np.zeros((0, 2 * n)))
        y, t = sol.sol(t_new), t_new
        if last:
            break
        after = t + 1e-14  # the signals' values after a jump at t
        fired = {owners[i] for i, te in enumerate(sol.t_events or ()) if len(te)}
        _, tau = _solve(m, after, y, modes)
        new = list(modes)
        for j, c in enumerate(m.contacts):
            engaged = c.one_way or c.fn(after) > 0
            w_rel = _w_rel(c, y[n:])
            if not engaged:
                new[j] = int(np.sign(w_rel))
            elif j in fired and modes[j] != 0:  # a slide ends: locked, exactly
                y[n + c.b] = y[n + c.a] if c.a is not None else 0.0
                new[j] = 0
            elif j in fired:  # the static margin reached 0: it breaks away along tau
                new[j] = _excess(c, after, tau[j])[1]
            elif modes[j] != 0 and c.fn(t - 1e-14) <= 0 and not c.one_way:
                new[j] = int(np.sign(w_rel))  # engaged just now: by its slip
        new = _settle(m, after, y, new)
        for j, c in enumerate(m.contacts):
            if new[j] != modes[j] and (c.one_way or c.fn(after) > 0):
                events.append((t, j, new[j]))
        modes = new
    return Solution(np.concatenate(out_t), np.concatenate(out_y), events)


# --- MSL Rotational.Examples.Friction ---------------------------------------------

@dataclass
class Friction:
    """MSL 4 Rotational.Examples.Friction: inertia3 (J = 1, w = 100) driven by
    200 sin(100 t) until startTime, a clutch (fn_max = 160, always engaged) to inertia2
    (J = 0.05, w = 90), a spring-damper (c = 160, d = 1) to a brake (fn_max = 1600,
    engaged by a step at startTime) holding inertia1 (J = 1, w = 90); all angles 0;
    mu_pos = [0, 0.5], peak = 1, cgeo = 1 (MSL's defaults); stop time 3 s."""
    J3: float = 1.0
    J2: float = 0.05
    J1: float = 1.0
    w0: tuple = (100.0, 90.0, 90.0)   # inertia3, inertia2, inertia1
    amplitude: float = 200.0
    f: float = 50 / math.pi           # sine: 200 sin(2 pi f t) = 200 sin(100 t)
    start_time: float = 0.5
    fn_clutch: float = 160.0
    fn_brake: float = 1600.0
    c: float = 160.0
    d: float = 1.0
    stop: float = 3.0

    def motor(self, t):
        return self.amplitude * math.sin(2 * math.pi * self.f * t) if t < self.start_time else 0.0

    def drive_train(self) -> DriveTrain:
        # bodies 0: inertia3, 1: inertia2, 2: inertia1 (held by the brake)
        def torques(t, phi, w):
            tau_s = self.c * (phi[2] - phi[1]) + self.d * (w[2] - w[1])  # spring.tau
            return np.array([self.motor(t), tau_s, -tau_s])
        fn_b = self.fn_brake
        return DriveTrain(
            (self.J3, self.J2, self.J1), torques,
            [Contact(0, 1, lambda t: self.fn_clutch),                           # clutch
             Contact(None, 2, lambda t, s=self.start_time: fn_b if t >= s else 0.0)],  # brake
            breaks=(self.start_time,))

    def solve(self, grid=None) -> Solution:
        grid = np.arange(0.0, self.stop + 5e-4, 1e-3) if grid is None else grid
        return simulate(self.drive_train(), [0.0, 0.0, 0.0, *self.w0], self.stop, grid)


# --- MSL Rotational.Examples.OneWayClutch -----------------------------------------

@dataclass
class OneWayClutchExample:
    """MSL 4 Rotational.Examples.OneWayClutch: inertiaIn (J = 1, w = -0.5) driven by
    10 sin(2 pi 3 t), a one-way clutch (peak = 25, fn_max = 3, mu 0.5, cgeo 1) to
    inertiaOut (J = 1, w = 0), engaged by a pulse (amplitude 1, width 50 %, period
    1.3 s, startTime 0.3 s); stop time 2 s."""
    J_in: float = 1.0
    J_out: float = 1.0
    w0: tuple = (-0.5, 0.0)
    amplitude: float = 10.0
    f: float = 3.0
    peak: float = 25.0
    fn_max: float = 3.0
    period: float = 1.3
    width: float = 50.0   # percent of the period
    start_time: float = 0.3
    stop: float = 2.0

    def pulse_edges(self) -> list[float]:
        """Rising and falling instants of the pulse up to the stop time."""
        edges, k = [], 0
        while self.start_time + k * self.period < self.stop:
            on = self.start_time + k * self.period
            edges += [on, on + self.width / 100 * self.period]
            k += 1
        return [e for e in edges if e < self.stop]

    def engaged(self, t) -> float:
        if t < self.start_time:
            return 0.0
        return 1.0 if (t - self.start_time) % self.period < self.width / 100 * self.period \
            else 0.0

    def drive_train(self) -> DriveTrain:
        def torques(t, phi, w):
            return np.array([self.amplitude * math.sin(2 * math.pi * self.f * t), 0.0])
        return DriveTrain(
            (self.J_in, self.J_out), torques,
            [Contact(0, 1, lambda t: self.fn_max * self.engaged(t), peak=self.peak,
                     one_way=True)],
            breaks=tuple(self.pulse_edges()))

    def solve(self, grid=None) -> Solution:
        grid = np.arange(0.0, self.stop + 5e-4, 1e-3) if grid is None else grid
        return simulate(self.drive_train(), [0.0, 0.0, *self.w0], self.stop, grid)
