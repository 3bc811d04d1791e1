"""One error-controlled integration of a hybrid ODE with state events, for the `me` and
`monolithic` masters.

The system supplies ``rhs(t, y)``, ``indicators(t, y)``, ``handle_event(t, y, changed)``
and ``sample(t, y)``. Between events we step one of scipy's ODE solvers
(DOP853, RK45, Radau, BDF, LSODA) by hand rather than through ``solve_ivp``:

- An event is a change of an indicator's *domain* ``z > 0`` versus ``z <= 0``, the FMI
  convention. ``solve_ivp`` instead triggers on a sign change *from* zero, and after a
  friction jump the indicator (the relative velocity) restarts at exactly zero, which
  would make it find the same root again at once, forever.
- The event time is the right end of a bisection bracket on the domain predicate, so
  the state handed to the jump lies past the crossing (the side the jump must see),
  within ``time_resolution`` of it.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Callable, Protocol

import numpy as np
from scipy.integrate import BDF, DOP853, LSODA, RK45, Radau

METHODS = {"DOP853": DOP853, "RK45": RK45, "Radau": Radau, "BDF": BDF, "LSODA": LSODA}


class HybridSystem(Protocol):
    def rhs(self, t: float, y: np.ndarray) -> np.ndarray: ...

    def indicators(self, t: float, y: np.ndarray) -> np.ndarray: ...

    def handle_event(self, t: float, y: np.ndarray, changed: np.ndarray) -> "EventOutcome": ...

    def sample(self, t: float, y: np.ndarray) -> list[float]: ...


@dataclass
class EventOutcome:
    y: np.ndarray                     # continuous state after the jumps
    terminate: str | None = None      # why the run must end here, or None
    next_time: float | None = None    # a time event the system asks for


@dataclass
class Statistics:
    steps: int = 0
    events: int = 0
    rhs_calls: int = 0
    event_times: list[float] = field(default_factory=list)


class IntegrationError(RuntimeError):
    """The ODE solver failed or the events never settle; says where and why."""


def integrate(system: HybridSystem, y0: np.ndarray, stop_time: float, output_times: np.ndarray,
              method: str = "DOP853", rtol: float = 1e-8, atol: float = 1e-10,
              max_step: float = math.inf, max_events: int = 100_000,
              progress: Callable[[float], None] | None = None):
    """Integrate from t = 0 to `stop_time`; returns (rows at `output_times`, stats, terminated).

    The system's initial event iteration (at t = 0) must already be done.
    `terminated` is ``(time, message)`` when the system ended the run, else None.
    """
    own = getattr(system, "stepper", None)  # a system may bring a method of its own (CVODES)
    if method not in METHODS and method not in getattr(system, "stepper_methods", ()):
        raise IntegrationError(f"method must be one of {', '.join(METHODS)}, not '{method}'")
    solver_class = METHODS.get(method) or own
    stats = Statistics()
    t, y = 0.0, np.asarray(y0, dtype=float)
    rows, k = [], 0
    next_time = None

    def rhs(tt, yy):
        stats.rhs_calls += 1
        return system.rhs(tt, yy)

    def emit_until(limit, dense, inclusive):
        nonlocal k
        while k < len(output_times) and (output_times[k] < limit or
                                         (inclusive and output_times[k] <= limit)):
            rows.append(system.sample(output_times[k], dense(output_times[k])))
            k += 1

    while True:
        bound = stop_time if next_time is None else min(stop_time, next_time)
        domain = system.indicators(t, y) > 0
        if t >= bound:
            break
        # implicit methods get the exact Jacobian when the system has one (the CasADi model)
        extra = ({"jac": system.jacobian} if method in ("Radau", "BDF", "LSODA")
                 and hasattr(system, "jacobian") else {})
        if not len(y):
            solver = _NoStates(t, bound)
        elif method in METHODS:
            solver = solver_class(rhs, t, y, bound, rtol=rtol, atol=atol, max_step=max_step,
                                  **extra)
        else:
            solver = own(method, t, y, bound, rtol=rtol, atol=atol)
        event_at = None
        while solver.status == "running":
            message = solver.step()
            if solver.status == "failed":
                raise IntegrationError(f"{method} failed at t = {solver.t:.10g}: {message}")
            stats.steps += 1
            dense = solver.dense_output()
            new_domain = system.indicators(solver.t, solver.y) > 0
            if np.any(new_domain != domain):
                event_at = _locate(system, dense, solver.t_old, solver.t, domain)
                emit_until(event_at, dense, inclusive=False)
                break
            domain = new_domain
            emit_until(solver.t, dense, inclusive=True)
            if progress is not None:
                progress(solver.t)
        if event_at is None:
            t, y = solver.t, solver.y
            if t >= stop_time:
                break
            # a requested time event
            outcome = system.handle_event(t, y, np.zeros_like(domain))
        else:
            t = event_at
            y_at = dense(event_at)
            changed = (system.indicators(t, y_at) > 0) != domain
            outcome = system.handle_event(t, y_at, changed)
            stats.event_times.append(t)
        stats.events += 1
        if stats.events > max_events:
            raise IntegrationError(f"more than {max_events} events before t = {t:.10g}: the "
                                   "modes chatter (Zeno behaviour?)")
        y = np.asarray(outcome.y, dtype=float)
        next_time = outcome.next_time
        # output points at the event time show the state after the jumps
        emit_until(t, lambda _t: y, inclusive=True)
        if outcome.terminate is not None:
            return rows, stats, (t, outcome.terminate)
    return rows, stats, None


def _locate(system, dense, t_lo, t_hi, domain, resolution=None):
    """The earliest time in (t_lo, t_hi] where some indicator's domain differs from `domain`.

    Bisection on the predicate keeps the returned time on the far side of the crossing.
    """
    resolution = resolution or 4e-14 * max(1.0, abs(t_hi))
    lo, hi = t_lo, t_hi
    while hi - lo > resolution:
        mid = 0.5 * (lo + hi)
        if np.any((system.indicators(mid, dense(mid)) > 0) != domain):
            hi = mid
        else:
            lo = mid
    return hi


class _NoStates:
    """Stands in for an ODE solver when the system has no continuous state."""

    def __init__(self, t0, bound):
        self.t_old, self.t, self.y, self.bound = t0, t0, np.zeros(0), bound
        self.status = "running"

    def step(self):
        self.t_old, self.t = self.t, min(self.bound, self.t + max(1e-3, (self.bound - self.t) / 100))
        if self.t >= self.bound:
            self.status = "finished"
        return None

    def dense_output(self):
        return lambda tt: np.zeros(0)
