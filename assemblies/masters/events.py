"""Event synchronisation for the co-simulation master: where a step must end.

An FMU locates its own events (a friction contact sticking or slipping) and reports
each through FMI 3 intermediate update. Two kinds matter to the master:

- an event *inside* a step, at a time the FMU located from its own states: every
  FMU is rolled back and the step retaken to end just past that time, so that the
  other FMUs see the new outputs (a changed friction force) from there on, not from
  the end of a step that may be much longer;
- an event at the *start* of a step: the FMU's inputs were moved across an
  indicator's zero at the communication point (a spring force, held by another FMU,
  passed the static friction limit during the previous step). The coupled system
  crossed somewhere in that previous step; bisecting it through rollback (retake it
  shorter, then a tiny probe step, undone, asks whether the event fires) finds the
  earliest point where it does, to `EVENT_TOL`. There the FMUs' modes settle before
  the next step (:meth:`assemblies.masters.cosim._Stepper._settle`): the FMU changes
  its mode only in a doStep, after the master set inputs from the old modes' outputs.

This is the scheme of the compiled engine (``assemblies/engine/c/cosim.c``:
``earliest_event_in_step``, ``fires_at_start``, ``locate_start_event``); the time
stepping that uses it is :class:`assemblies.masters.cosim._Stepper`.
"""
from __future__ import annotations

import math
from typing import TYPE_CHECKING

if TYPE_CHECKING:  # only for the annotations: cosim imports this module
    from .cosim import _Master, _Snapshot

# width of the final bracket when an event is moved back [s]; the engine's
# assemblies.engine.cosim.EVENT_TOL (not imported: the engine imports the masters)
EVENT_TOL = 1e-10


# settle steps after an event at a communication point: a cascade needs one per FMU
# whose mode change moves another's inputs across its condition (cosim.c MAX_SETTLE_STEPS)
MAX_SETTLE_STEPS = 16


def probe_step(t: float) -> float:
    """The step a probe takes to see whether an event fires at its start: the FMU
    handles such an event before it integrates, so any length it accepts will do."""
    return 1e-8 * max(1.0, abs(t))


def earliest_event_in_step(master: _Master) -> float:
    """The earliest event any FMU located inside the last step (inf: none)."""
    return min((inst.event_in_step for inst in master.instances.values()), default=math.inf)


def events_at_start(master: _Master) -> set[str]:
    """The instances that handled an event at the start of the last step."""
    return {name for name, inst in master.instances.items() if inst.event_at_start}


def fires_at_start(master: _Master, which: set[str], t: float, h_probe: float) -> bool:
    """Would an event fire at the start of the next step from `t` (inputs consistent
    at `t`)? Each instance in `which` takes a tiny step and is put back."""
    for name, inst in master.instances.items():  # in the engine's order, first that fires
        if name not in which:
            continue
        state, n_events = inst.save(), len(inst.event_rows)
        try:
            inst.clear_event_flags()
            inst.do_step(t, h_probe)  # (a terminate request is the real step's business)
            master.do_steps += 1
            fires = inst.event_at_start
        finally:
            inst.restore(state)
            inst.discard(state)
            del inst.event_rows[n_events:]  # the probe's event is not the run's
        if fires:
            return True
    return False


def locate_start_event(master: _Master, prev: _Snapshot, h_prev: float, which: set[str],
                       event_tol: float = EVENT_TOL) -> float:
    """An event fired at the start of the step from ``prev.t + h_prev``: the inputs
    crossed an indicator's zero somewhere in the previous step. Bisect that step
    (rollback to `prev`) for the earliest point where the event fires, and leave the
    run there; returns that time. `which`: the instances whose event it was."""
    lo, hi, t0 = 0.0, h_prev, prev.t
    # no narrower than the spacing of doubles at t0 allows
    width = max(event_tol, 4e-16 * max(1.0, abs(t0)))
    probe = probe_step(t0)
    # the trial steps hold the sources' values from t0 (cosim.c locate_start_event says
    # why: an extrapolated input runs ahead by what grows with the trial's length)
    held_raw, master.hold_raw = master.hold_raw, True
    try:
        while hi - lo > width:
            m = 0.5 * (lo + hi)
            master.restore(prev)
            master.step(t0, m)
            if master.terminated is not None or which & events_at_start(master):
                hi = m  # the model ended before m, or the event fires at t0 already
            elif fires_at_start(master, which, t0 + m, probe):
                hi = m
            else:
                lo = m
        # the step to the first point known to fire, taking the inputs as any step does
        # (cosim.c locate_start_event says why): the event settles there
        master.hold_raw = held_raw
        master.restore(prev)
        master.step(t0, hi)
    finally:
        master.hold_raw = held_raw
    master.events_located += 1
    return t0 + hi


__all__ = ["EVENT_TOL", "MAX_SETTLE_STEPS", "earliest_event_in_step", "events_at_start", "fires_at_start",
           "locate_start_event", "probe_step"]
