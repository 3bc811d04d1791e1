"""Exact Coulomb friction at one sliding contact, as a mode machine (seed Eq. 9.3).

Shared by every component with dry friction, so stick, slip and incipient sliding
mean the same everywhere: mode -1 slides backward, 0 sticks, +1 slides forward;
while stuck the relative acceleration is exactly zero and the friction is whatever
holds it there; events end a stick when the needed friction reaches the static limit
and end a slide when the relative velocity reaches zero.
"""
from __future__ import annotations

from .lazy import lazy

ca = lazy("casadi")  # loaded by the first equation written, not by an import


def coulomb_modes(e, *, speed: str, acceleration, friction, applied, static_limit,
                  kinetic_limit, mode: str = "mode", base=0, one_way: bool = False,
                  free=None) -> None:
    """Write the residual, indicators and jumps of exact Coulomb friction.

    `speed` names the state holding the relative velocity (it is reset to exactly 0
    when a slide ends), `acceleration` is its derivative and `friction` the friction
    force or torque (both unknowns of `e`), `applied` everything but friction in the
    contact's frame, and the limits are mu_s N and mu_k N (or torques). `base`: the
    velocity of the other side of the contact when the state is an absolute velocity
    (a clutch's driven side, its driver's speed an input): the relative velocity is
    then ``state - base`` and a slide ends by setting the state to ``base``.
    `one_way`: a freewheel in parallel (MSL's OneWayClutch): stuck, the contact holds
    against any backward push, so it never breaks free backward; a forward slide that
    stops locks. Mode -1 is then reached only from a backward relative speed at an
    event (a start value MSL rules out), which the caller must treat as an error.
    `free`: true where the contact carries no force at all (MSL's free mode, a clutch or
    brake with no normal force; both limits must then be 0): it neither sticks nor ends
    a slide (no reset of the state). On a fixed base its mode follows the relative
    speed's sign; on a moving base it is MSL's Free (:data:`FREE`), and being pressed
    again is an event that takes the direction of the relative speed then.
    """
    q, v = getattr(e.q, mode), getattr(e.x, speed) - base
    moving_base = not (isinstance(base, (int, float)) and base == 0)
    released = free is not None and moving_base  # the contact has MSL's Free mode
    # without `free`, the expressions (and the generated code) are the two-mode machine's
    held = q == 0 if free is None else ca.logic_and(q == 0, ca.logic_not(free))
    e.residual(ca.if_else(held, acceleration, friction + kinetic_limit * q))
    e.indicator(ca.if_else(q == 0, static_limit - applied,
                           ca.if_else(q == FREE, 1, q * v) if released else q * v),
                "stuck: static margin for forward slip; sliding: relative speed")
    e.indicator(1 if one_way else ca.if_else(q == 0, static_limit + applied, 1),
                "stuck: static margin for backward slip")
    if released:  # free and pressed differ in sign: each change of the two is an event
        e.indicator(ca.if_else(free, -1, 1) * ca.if_else(q == FREE, 1, -1),
                    "free: pressed again; pressed: released")
    # at the threshold itself the contact breaks free: an event located exactly at the
    # zero of the margin must switch the mode, or the contact would stay stuck
    breaks_free = ca.if_else(applied >= static_limit, 1,
                             0 if one_way else ca.if_else(applied <= -static_limit, -1, 0))
    if moving_base:
        _jumps_on_a_base(e, speed, mode, q, v, base, breaks_free, free)
        return
    stopped = ca.logic_and(q != 0, q * v <= 0)
    settles = ca.logic_or(stopped, q == 0)
    if free is not None:
        stopped = ca.logic_and(stopped, ca.logic_not(free))
        settles = ca.logic_or(settles, free)
    v_new = ca.if_else(stopped, 0, v)  # exactly zero: stuck means no relative motion
    e.jump(speed, ca.if_else(stopped, base, getattr(e.x, speed)))
    e.jump(mode, ca.if_else(settles,
                            ca.if_else(v_new == 0, breaks_free, ca.sign(v_new)), q))


#: the mode's start for a contact on a moving base (MSL's Unknown): decided by the event
#: iteration at initialisation, from the relative speed, then from the forces
UNKNOWN = 3
#: a contact with no normal force on a moving base (MSL's Free): no direction is kept
#: while free; pressed again, it takes the relative speed's then. Like UNKNOWN, a
#: Mode's `also`: its equations are those of -1 (no friction while free: both limits 0),
#: and an event leaves it before any step once pressed
FREE = 2


def _jumps_on_a_base(e, speed, mode, q, v, base, breaks_free, free) -> None:
    """The jumps of a contact whose other side moves (`base`, the state absolute).

    Stuck (mode 0) the state *is* the base's speed, so at every event it is set to the
    base exactly: when the base itself jumps (the contact it is stuck to ends a slide,
    its state set to its own base), a stuck contact follows instead of reading the jump,
    a rounding-level speed, as a slide (which chattered at every lock of CoupledClutches'
    clutches in series and, under scipy, cycled without settling at t = 0.8311). Only
    the forces decide whether it leaves the stick, as in MSL (startForward reads the
    torque, not w_rel). A slide that ends is set to the base too (never as
    base + (state - base), which rounds). A mode of UNKNOWN (the start: MSL's initial())
    takes the direction of the relative speed, or at rest sticks and lets the next
    iteration weigh the forces; the state stays as the user started it. A `free`
    contact (coulomb_modes) is never set to its base and its mode is FREE: a direction
    kept while free went stale without an event (a contact free at rest took one from a
    zero push, +1, whose indicator q v then left 0 the wrong way unseen: in a
    co-simulation CoupledClutches' clutch3, free until 0.9 s, slid the wrong way once
    pressed). Pressed again (an event: coulomb_modes' third indicator), it slides the
    way the relative speed goes, or at rest sticks and lets the forces decide.
    """
    sliding = ca.logic_or(q == 1, q == -1)
    stopped = ca.logic_and(sliding, q * v <= 0)
    to_base = ca.logic_or(stopped, q == 0)
    if free is not None:
        to_base = ca.logic_and(to_base, ca.logic_not(free))
    e.jump(speed, ca.if_else(to_base, base, getattr(e.x, speed)))
    # unknown at rest: stuck first, so that the next iteration weighs the forces of the
    # stuck contact (those of whatever mode 3 selects in the equations mean nothing)
    q_new = ca.if_else(to_base, breaks_free, ca.if_else(sliding, q, ca.sign(v)))
    if free is not None:
        q_new = ca.if_else(free, FREE, q_new)
    e.jump(mode, q_new)


def hard_stops(e, *, position: str, speed: str, low, high, mode: str = "mode") -> None:
    """Add MSL's hard stops (MassWithStopAndFriction) to the jumps of `coulomb_modes`.

    Call it after `coulomb_modes` on the same `speed` and `mode`. The state `position`
    may not pass `low` or `high`: sliding into a stop is an event that puts it exactly
    on the stop at rest and stuck (MSL's ``reinit(s, ...); reinit(v, 0)``), and a
    contact stuck at a stop may break free only away from it (MSL's startForward needs
    ``s < smax - L/2``), however hard it is pushed into it: the stop's reaction is then
    part of the sticking force, as in MSL.
    """
    q, s = getattr(e.q, mode), getattr(e.x, position)
    # each indicator watches only the stop the contact slides towards: one stuck at a
    # stop would otherwise sit on an indicator of exactly zero
    e.indicator(ca.if_else(q == 1, high - s, 1), "sliding forward: distance to the upper stop")
    e.indicator(ca.if_else(q == -1, s - low, 1), "sliding backward: distance to the lower stop")
    q_new, v_new = e.jumps[mode], e.jumps[speed]
    blocked = ca.logic_or(ca.logic_and(s >= high, q_new == 1),
                          ca.logic_and(s <= low, q_new == -1))
    e.jump(position, ca.fmin(ca.fmax(s, low), high))  # an event lands a hair past the stop
    e.jump(speed, ca.if_else(blocked, 0, v_new))
    e.jump(mode, ca.if_else(blocked, 0, q_new))
