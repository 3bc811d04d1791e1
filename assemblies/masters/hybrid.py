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
- Domains are compared not only at step ends but inside every step, on its dense
  output (:func:`_scan`): an indicator that crosses zero and back inside one step (a
  slip shorter than a solver step) has the same sign at both ends, and only a look
  inside finds it. Three rules, each for a case measured to be missed without it:
  ``SCAN_POINTS`` equally spaced interior points, and at least one every output step
  (while a block sticks its relative states are constant, the error estimate is zero
  and the steps grow tenfold each, soon spanning whole periods of a driving motion);
  where a parabola through neighbouring samples dips to the wrong side of zero
  between two of them, that interval is halved until it does not (the static margin
  of tests/short_slip.py is below zero for 0.09 s, between samples 1 s apart); and
  an indicator starting at zero is probed just after the start (next bullet). No
  sampling locator can promise to see every excursion; these see every one whose
  shape the samples resolve to second order.
- An indicator exactly zero where a phase starts (a velocity reset to 0 by the jump)
  has no domain yet: it takes the side it leaves zero to, from the first scanned point
  where it is nonzero (the first is ``ZERO_PROBE`` of the step in, so a slide shorter
  than the sampling is not over before its side is known). Leaving zero is the start
  of the new phase, not an event; counting it as one (z > 0 versus z <= 0) would
  restart the solver for nothing after every friction event and record a second event
  row there.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Callable, Protocol

import numpy as np
from scipy.integrate import BDF, DOP853, LSODA, RK45, Radau

from components.errors import MechfmuError

METHODS = {"DOP853": DOP853, "RK45": RK45, "Radau": Radau, "BDF": BDF, "LSODA": LSODA}

# Interior points scanned per step. Measured (me master, the conveyor from rest over 40
# periods at tolerance 1e-8, whose 102 mode changes include 3 and 0.05 ms phases, and
# tests/short_slip.py): 0 points miss 4 of the 102 (the parabola test needs 3 samples),
# 1 to 8 find all 102 and all 8 of short_slip; indicator evaluations per rhs call are
# 0.25, 0.31, 0.37, 0.48, 0.70 for 0, 1, 2, 4, 8 points (in `me` one costs about one rhs
# call). 2: the least that finds everything, plus one for margin, for ~5 % more work.
SCAN_POINTS = 2
# how narrow (as a fraction of the step) the parabola test may split an interval
MIN_REFINED = 1e-6
# where (as a fraction of the step) an indicator starting at zero is first looked at
ZERO_PROBE = 1e-3


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
    scans: int = 0            # indicator evaluations looking for events inside steps
    event_times: list[float] = field(default_factory=list)


class IntegrationError(MechfmuError, RuntimeError):
    """The ODE solver failed or the events never settle; says where and why."""


def integrate(system: HybridSystem, y0: np.ndarray, stop_time: float, output_times: np.ndarray,
              method: str = "DOP853", rtol: float = 1e-8, atol: float = 1e-10,
              max_step: float = math.inf, max_events: int = 100_000,
              progress: Callable[[float], None] | None = None,
              scan_spacing: float | None = None):
    """Integrate from the first output time to `stop_time`; returns (rows at
    `output_times`, stats, terminated).

    The system's initial event iteration (at the first output time) must already be done. Indicators
    are scanned at least every `scan_spacing` seconds (default: the output step).
    `terminated` is ``(time, message)`` when the system ended the run, else None.
    """
    own = getattr(system, "stepper", None)  # a system may bring a method of its own (CVODES)
    if method not in METHODS and method not in getattr(system, "stepper_methods", ()):
        raise IntegrationError(f"method must be one of {', '.join(METHODS)}, not '{method}'")
    solver_class = METHODS.get(method) or own
    stats = Statistics()
    t, y = float(output_times[0]), np.asarray(y0, dtype=float)
    rows, k = [], 0
    next_time = None
    if scan_spacing is None:
        gaps = np.diff(output_times)
        scan_spacing = float(np.min(gaps[gaps > 0])) if np.any(gaps > 0) else stop_time
    spacing = scan_spacing if scan_spacing > 0 else math.inf

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
        reference = _Reference(system.indicators(t, y))
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
            bracket = _scan(system, dense, solver.t_old, solver.t, solver.y, reference,
                            spacing, stats)
            if bracket is not None:
                event_at = _locate(system, dense, *bracket, reference)
                emit_until(event_at, dense, inclusive=False)
                break
            emit_until(solver.t, dense, inclusive=True)
            if progress is not None:
                progress(solver.t)
        if event_at is None:
            t, y = solver.t, solver.y
            if t >= stop_time:
                break
            # a requested time event
            outcome = system.handle_event(t, y, np.zeros(len(reference.sign), dtype=bool))
        else:
            t = event_at
            y_at = dense(event_at)
            changed = reference.crossed(system.indicators(t, y_at))
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


# What our FMUs report for an indicator that is exactly 0 at an event restart, on the
# side it takes (MF_INDICATOR_SHIFT, fmus/runtime/events.h): a zero here too
INDICATOR_SHIFT = 1e-100


def _side(z: np.ndarray) -> np.ndarray:
    """The side each indicator is on: +1, -1, or 0 at zero (a restart's shift included)."""
    z = np.asarray(z, dtype=float)
    return np.where(np.abs(z) == INDICATOR_SHIFT, 0.0, np.sign(z))


class _Reference:
    """The domain (z > 0 or z <= 0) each indicator had where the phase began; an
    indicator that began exactly at zero takes the side it leaves zero to. Keeps the
    indicators at the last point scanned (the start of the next step)."""

    def __init__(self, z: np.ndarray):
        self.z = np.asarray(z, dtype=float)
        self.sign = _side(self.z)

    def crossed(self, z: np.ndarray) -> np.ndarray:
        return ((self.sign > 0) & (z <= 0)) | ((self.sign < 0) & (z > 0))

    def adopt(self, z: np.ndarray) -> None:
        fresh = self.sign == 0
        self.sign[fresh] = _side(z[fresh])
        self.z = z


def _may_dip(times, values, i, sign) -> bool:
    """Whether a parabola through three neighbouring samples that include [t_i, t_i+1]
    reaches the wrong side of zero inside that interval, for some indicator."""
    t_a, t_b = times[i], times[i + 1]
    for j in (i - 1, i):
        if j < 0 or j + 2 >= len(times):
            continue
        (t0, t1, t2), (z0, z1, z2) = times[j:j + 3], values[j:j + 3]
        d01, d12 = (z1 - z0) / (t1 - t0), (z2 - z1) / (t2 - t1)
        curvature = (d12 - d01) / (t2 - t0)  # z ~ z0 + d01 (t - t0) + c (t - t0)(t - t1)
        with np.errstate(divide="ignore", invalid="ignore"):
            vertex = 0.5 * (t0 + t1) - d01 / (2 * curvature)
        inside = (curvature != 0) & (vertex > t_a) & (vertex < t_b)
        if not np.any(inside):
            continue
        tv = np.where(inside, vertex, t_a)
        at_vertex = z0 + d01 * (tv - t0) + curvature * (tv - t0) * (tv - t1)
        if np.any(inside & (sign * at_vertex <= 0) & (sign != 0)):
            return True
    return False


def _scan(system, dense, t_lo, t_hi, y_hi, reference, spacing, stats):
    """(ta, tb): the first scanned sub-interval of the step [t_lo, t_hi] at whose end some
    indicator has left its reference domain, or None. Adopts the sides of zero starts.

    Samples SCAN_POINTS interior points, and at least one every `spacing` seconds; where
    a parabola through neighbouring samples dips to the wrong side of zero between two
    samples (an excursion narrower than the sampling), halves that interval, down to
    MIN_REFINED of the step, before believing the signs.
    """
    n = max(SCAN_POINTS, math.ceil((t_hi - t_lo) / spacing) - 1)
    times = list(t_lo + (t_hi - t_lo) * np.arange(n + 2) / (n + 1))
    times[-1] = t_hi
    if np.any(reference.sign == 0):
        # an indicator starting at zero: learn its side just after the start, before a
        # phase shorter than the sampling (a 3 ms slide) is over and the wrong side adopted
        times.insert(1, t_lo + ZERO_PROBE * (t_hi - t_lo))
    values = [reference.z] + [system.indicators(tt, dense(tt)) for tt in times[1:-1]] \
        + [system.indicators(t_hi, y_hi)]
    stats.scans += len(times) - 1
    narrowest = MIN_REFINED * (t_hi - t_lo)
    i = 0
    while i + 1 < len(times):
        if np.any(reference.crossed(values[i + 1])):
            return times[i], times[i + 1]
        if times[i + 1] - times[i] > narrowest and _may_dip(times, values, i, reference.sign):
            mid = 0.5 * (times[i] + times[i + 1])
            times.insert(i + 1, mid)
            values.insert(i + 1, system.indicators(mid, dense(mid)))
            stats.scans += 1
            continue
        reference.adopt(values[i + 1])
        i += 1
    return None


def _locate(system, dense, t_lo, t_hi, reference, resolution=None):
    """The earliest time in (t_lo, t_hi] where some indicator has left its reference
    domain; none has at t_lo, one has at t_hi.

    Bisection on the predicate keeps the returned time on the far side of the crossing.
    """
    resolution = resolution or 4e-14 * max(1.0, abs(t_hi))
    lo, hi = t_lo, t_hi
    while hi - lo > resolution:
        mid = 0.5 * (lo + hi)
        if np.any(reference.crossed(system.indicators(mid, dense(mid)))):
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
