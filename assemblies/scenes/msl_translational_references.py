"""Independent references for the rebuilt ``Modelica.Mechanics.Translational.Examples``.

Written from MSL's documented equations (the documentation of Mass, Spring, Damper,
ElastoGap, MassWithStopAndFriction, Brake), never from our components: closed forms where
the motion has one (the Oscillator's resonance, a brake at constant force, the ElastoGap
example's linear mass), and otherwise an event-driven integration with scipy of one
body's equation of motion, its friction mode switched by located events.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Callable

import numpy as np
from scipy.integrate import solve_ivp

#: the event-driven references integrate to this relative and absolute tolerance
REF_TOL = 1e-11


# --- closed forms ---------------------------------------------------------------------
def forced_oscillator(t, m: float, c: float, d: float, F: float, w: float, s_eq: float = 0.0):
    """(s, v) of m x'' + d x' + c x = F sin(w t) from rest at the equilibrium s_eq.

    The particular solution X sin(w t - phi) plus the homogeneous solution that cancels
    its position and speed at t = 0; d = 0 at resonance (w^2 = c/m) gives the secular
    F/(2 m w^2) (sin w t - w t cos w t) instead.
    """
    t = np.asarray(t, dtype=float)
    w0sq = c / m
    if d == 0 and w * w == w0sq:
        x = F / (2 * m * w**2) * (np.sin(w * t) - w * t * np.cos(w * t))
        xd = F / (2 * m) * t * np.sin(w * t)
        return s_eq + x, xd
    # particular: x_p = A sin + B cos
    den = (c - m * w * w)**2 + (d * w)**2
    A, B = F * (c - m * w * w) / den, -F * d * w / den
    xp0, vp0 = B, A * w
    sigma = d / (2 * m)
    wd = math.sqrt(w0sq - sigma**2)
    C1 = -xp0
    C2 = (-vp0 + sigma * C1) / wd
    e = np.exp(-sigma * t)
    xh = e * (C1 * np.cos(wd * t) + C2 * np.sin(wd * t))
    vh = e * ((-sigma * C1 + wd * C2) * np.cos(wd * t) + (-sigma * C2 - wd * C1) * np.sin(wd * t))
    x = A * np.sin(w * t) + B * np.cos(w * t) + xh
    v = A * w * np.cos(w * t) - B * w * np.sin(w * t) + vh
    return s_eq + x, v


def steady_amplitude(m: float, c: float, d: float, F: float, w: float) -> float:
    """F / sqrt((c - m w^2)^2 + (d w)^2): the amplitude forced vibration settles to."""
    return F / math.hypot(c - m * w * w, d * w)


def brake_stop(v0: float, m: float, t_on: float, force: float) -> tuple[float, float]:
    """(time, distance) at which a mass sliding at v0 > 0 stops when a constant friction
    `force` acts from t_on: v = v0 - force/m (t - t_on), stuck afterwards (the brake holds
    it: nothing else pushes)."""
    t_brake = m * v0 / force
    return t_on + t_brake, v0 * t_on + v0 * t_brake / 2


def damped_free(t, m: float, c: float, d: float, x0: float):
    """(x, v) of m x'' + d x' + c x = 0 from x0 at rest (underdamped)."""
    t = np.asarray(t, dtype=float)
    sigma = d / (2 * m)
    wd = math.sqrt(c / m - sigma**2)
    e = np.exp(-sigma * t)
    x = e * x0 * (np.cos(wd * t) + sigma / wd * np.sin(wd * t))
    v = -e * x0 * (wd + sigma**2 / wd) * np.sin(wd * t)
    return x, v


# --- one body with exact stick/slip, event-driven ------------------------------------
@dataclass
class StickSlipBody:
    """m v' = force(t, s, v) - f on a fixed surface, MSL's MassWithStopAndFriction.

    Sliding, ``f = sign(v) kinetic(|v|)``; stuck, v = 0 and f balances the force as
    long as |force| <= f0_max; stops at ``low`` and ``high`` for s set v = 0 and stick.
    """
    m: float
    force: Callable[[float, float, float], float]
    kinetic: Callable[[float], float]  # sliding friction magnitude at speed |v| >= 0
    f0_max: float
    low: float = -math.inf
    high: float = math.inf


@dataclass
class Trajectory:
    t: np.ndarray
    s: np.ndarray
    v: np.ndarray
    events: list = field(default_factory=list)  # (time, new mode, s, v)

    def at(self, time: float) -> tuple[float, float]:
        return float(np.interp(time, self.t, self.s)), float(np.interp(time, self.t, self.v))


def stick_slip(body: StickSlipBody, s0: float, v0: float, t_end: float) -> Trajectory:
    """Integrate `body` from (s0, v0) to t_end; every mode change is a located event."""
    t, s, v = 0.0, s0, v0
    mode = int(np.sign(v0)) or _breakaway(body, t, s)
    ts, ss, vs, events = [t], [s], [v], []
    for _ in range(10000):  # a mode change per event: bounded by the events of a run
        if t >= t_end:
            break
        if mode == 0:
            def rhs(tt, y):
                return [0.0, 0.0]
            margins = [lambda tt, y: body.f0_max - body.force(tt, y[0], 0.0),
                       lambda tt, y: body.f0_max + body.force(tt, y[0], 0.0)]
            # stuck, the margins change with time only: steps short enough to see them cross
            options = {"max_step": 1e-3}
        else:
            def rhs(tt, y, q=mode):
                return [y[1], (body.force(tt, y[0], y[1]) - q * body.kinetic(q * y[1])) / body.m]
            margins = [lambda tt, y, q=mode: q * y[1],
                       lambda tt, y, q=mode: body.high - y[0] if q > 0 else y[0] - body.low]
            options = {}
        for g in margins:
            g.terminal, g.direction = True, -1
        sol = solve_ivp(rhs, (t, t_end), [s, v], events=margins, rtol=REF_TOL, atol=REF_TOL,
                        **options)
        ts.extend(sol.t[1:]), ss.extend(sol.y[0, 1:]), vs.extend(sol.y[1, 1:])
        t, s, v = float(sol.t[-1]), float(sol.y[0, -1]), float(sol.y[1, -1])
        if sol.status != 1:
            break  # reached t_end
        which = next(k for k, te in enumerate(sol.t_events) if len(te))
        if mode != 0:  # at rest: the speed reached zero, or a stop stopped it there
            if which == 1:
                s = body.high if mode > 0 else body.low
            v = 0.0
            mode = _breakaway(body, t, s)
        else:  # a stuck margin crossed: break away (never into a stop)
            mode = _breakaway(body, t, s) or (1 if which == 0 else -1)
            if (mode > 0 and s >= body.high) or (mode < 0 and s <= body.low):
                mode = 0
        events.append((t, mode, s, v))
        ts.append(t), ss.append(s), vs.append(v)
    return Trajectory(np.array(ts), np.array(ss), np.array(vs), events)


def _breakaway(body: StickSlipBody, t: float, s: float) -> int:
    """The mode at rest: slide where the force exceeds f0_max (never into a stop)."""
    f = body.force(t, s, 0.0)
    if f > body.f0_max and s < body.high:
        return 1
    if f < -body.f0_max and s > body.low:
        return -1
    return 0


def stribeck(F_prop: float, F_Coulomb: float, F_Stribeck: float, fexp: float):
    """MSL's sliding friction at speed u >= 0: F_prop u + F_Coulomb + F_Stribeck e^(-fexp u)."""
    return lambda u: F_prop * u + F_Coulomb + F_Stribeck * math.exp(-fexp * u)


def first_event(traj: Trajectory, mode: int | None = None, after: float = 0.0) -> float:
    """Time of the first event after `after` that enters `mode` (any change if None)."""
    for t, q, _, _ in traj.events:
        if t > after and (mode is None or q == mode):
            return t
    return math.nan
