"""Rotational friction elements with exact stick/slip (MSL BearingFriction, Brake, Clutch).

MSL writes these as massless elements whose stuck torque is "whatever keeps the
relative acceleration zero", which a tool finds by solving the mixed system of the
whole drive train. Across an FMU boundary that torque is an algebraic loop through the
accelerations of the inertias it holds, which no master closes exactly. So each of our
friction elements carries the inertia ``J`` it holds (the braked shaft, the clutch's
driven side), as :class:`components.translational.elements.MassWithFriction` carries
its mass: stuck is then exactly ``a_rel = 0`` inside one FMU, with the modes of the
shared mode machine :func:`components.friction.coulomb_modes` (MSL's Forward /
Stuck / Backward; ``free`` is a zero normal force: both limits are 0).

The kinetic characteristic is MSL's table (``mu_pos`` or ``tau_pos``, rows ``[w, value]``
for w >= 0), interpolated linearly and extrapolated from the last two points
(MSL's Extrapolation.LastTwoPoints); one row is a constant. The static limit is
``peak`` times the value at w = 0.
"""
from __future__ import annotations

from ..component import Component
from ..friction import FREE, UNKNOWN, coulomb_modes
from ..interfaces import (FIXED, FORCE_IN, MOTION_IN, ROTATIONAL, SIGNAL_IN, ComponentError,
                          Constraint, Mode, Option, Parameter, Port, Profile, State, signal)
from ..lazy import lazy

ca = lazy("casadi")  # loaded by the first equation written, not by an import

MAX_ROWS = 8
_ROWS = Option("rows", 1, range(1, MAX_ROWS + 1), "rows of the friction table")
_MODE = (Mode("mode", 0, "friction mode: -1 sliding backward, 0 stuck, +1 sliding forward"),)
_PEAK = Parameter("peak", 1.0, "1", "static / kinetic friction at w = 0 (>= 1)", min=1.0)
_J = Parameter("J", 1.0, "kg.m2", "inertia held by the friction (not in MSL's element)",
               min=0.0, min_strict=True)
_CGEO = Parameter("cgeo", 1.0, "m", "geometry constant (friction torque / friction force)",
                  min=0.0)
_FN_MAX = Parameter("fn_max", 1.0, "N", "maximum normal force", min=0.0)
_LOSS = State("W_loss", 0.0, "J", "energy dissipated by friction since t = 0")


def interpolate(x, W, V):
    """Linear in the table (W increasing), extrapolated from the first/last two rows."""
    if len(W) == 1:
        return V[0]
    value = None
    for k in range(len(W) - 2, -1, -1):  # segment k holds W[k] <= x < W[k+1]
        seg = V[k] + (V[k + 1] - V[k]) / (W[k + 1] - W[k]) * (x - W[k])
        value = seg if value is None else ca.if_else(x < W[k + 1], seg, value)
    return value


class _TableFriction(Component):
    """The table options and parameters of a friction element; `table` names them."""
    table: tuple[str, str, str, float] = ("mu_pos", "1", "friction coefficient", 0.5)
    fixed_parameters: tuple[Parameter, ...] = ()

    def __init__(self, name=None, profile=None, **values):
        rows = _ROWS.parse(values.pop("rows", 1))
        if rows is None:
            raise ComponentError(f"{type(self).__name__} '{name or type(self).__name__}': option "
                                 f"rows is not allowed; rows must be {_ROWS.allowed()}")
        self.parameters = self._parameters_for(rows)
        super().__init__(name, profile, rows=rows, **values)

    def _parameters_for(self, rows: int) -> tuple[Parameter, ...]:
        label, unit, what, default = self.table
        return (*[Parameter(f"{label}[{k},{j}]", v, u, f"{d} of row {k}")
                  for k in range(1, rows + 1)
                  for j, v, u, d in ((1, k - 1.0, "rad/s", "relative speed"),
                                     (2, default, unit, what))],
                *self.fixed_parameters)

    def set(self, key: str, value) -> None:
        super().set(key, value)
        if key == "rows":  # set after construction (--param clutch.rows=2): the table grows
            self.resize_parameters(self._parameters_for(self.option("rows")))

    options = (_ROWS,)
    modes = _MODE

    @property
    def constraints(self):
        rows = self.option("rows")
        if rows == 1:
            return ()
        label = self.table[0]

        def smallest_gap(p):
            ws = [getattr(p, f"{label}[{k},1]") for k in range(1, rows + 1)]
            gaps = [b - a for a, b in zip(ws, ws[1:])]
            out = gaps[0]
            for g in gaps[1:]:
                out = ca.fmin(out, g) if not isinstance(out, float) else min(out, g)
            return out
        return (Constraint(smallest_gap, f"{label} speeds strictly increasing", strict=True),)

    def characteristic(self, e, speed):
        """The table's value at `speed` (>= 0 while sliding) and at 0."""
        label, rows = self.table[0], self.option("rows")
        W = [getattr(e.p, f"{label}[{k},1]") for k in range(1, rows + 1)]
        V = [getattr(e.p, f"{label}[{k},2]") for k in range(1, rows + 1)]
        return interpolate(speed, W, V), interpolate(0, W, V)


def _friction(e, *, speed, acceleration, applied, static, kinetic, base=0, one_way=False,
              free=None):
    """The mode machine on the speed state `speed` relative to `base`; returns the
    friction torque on the body."""
    f = e.unknown("tau_friction")
    coulomb_modes(e, speed=speed, acceleration=acceleration, friction=f, applied=applied,
                  static_limit=static, kinetic_limit=kinetic, base=base, one_way=one_way,
                  free=free)
    w = getattr(e.x, speed) - base
    e.residual(e.der.W_loss + f * w)
    e.output("tau", -f, "N.m", "friction torque, MSL's sign (positive for forward sliding)")
    e.output("lossPower", -f * w, "W", "power dissipated by friction")
    return f


_BODY_STATES = (State("phi", 0.0, "rad", "absolute angle of the held inertia"),
                State("w", 0.0, "rad/s", "absolute angular velocity of the held inertia"), _LOSS)
_BODY_PORTS = (Port("flange_a", ROTATIONAL, "left flange of the held shaft"),
               Port("flange_b", ROTATIONAL, "right flange of the held shaft"))


def _normal_force(e):
    """MSL's ``fn``: ``fn_max f_normalized``, and 0 where the element is free
    (``f_normalized <= 0``: no friction torque, neither stuck nor sliding)."""
    return ca.fmax(e.p.fn_max * e.port("f_normalized"), 0)


def _body(e, friction_of):
    """A shaft of inertia J in a fixed housing, both flanges moving with it."""
    a_, b_, a = e.port("flange_a"), e.port("flange_b"), e.der.w
    e.residual(e.der.phi - e.x.w)
    f = friction_of(applied=a_.tau + b_.tau, acceleration=a)
    e.residual(e.p.J * a - a_.tau - b_.tau - f)
    for flange in (a_, b_):
        e.residual(flange.phi - e.x.phi)
        e.residual(flange.w - e.x.w)
        e.residual(flange.a - a)
    e.output("E", e.p.J * e.x.w**2 / 2, "J", "kinetic energy of the held inertia")


class BearingFriction(_TableFriction):
    """Coulomb friction in a bearing, holding a shaft of inertia J (MSL BearingFriction).

    Sliding: ``tau = tau_pos(|w|) sign(w)`` opposing the motion; stuck (``w = 0``) while
    the torque on the shaft stays within ``peak tau_pos(0)``.
    Parameters: ``tau_pos[k,1]`` [rad/s], ``tau_pos[k,2]`` [N.m] (option ``rows``;
    MSL's default [0, 1]), ``peak`` [1], ``J`` [kg.m2]. States: ``phi``, ``w``,
    ``W_loss`` [J]. Mode: ``mode``. Connectors: ``flange_a``, ``flange_b`` — torque in,
    motion out (housing fixed: MSL's useSupport = false).
    Outputs: ``tau`` [N.m] friction torque, ``lossPower`` [W], ``E`` [J].
    """

    table = ("tau_pos", "N.m", "friction torque", 1.0)
    fixed_parameters = (_PEAK, _J)
    states = _BODY_STATES
    ports = _BODY_PORTS
    profiles = (Profile("direct", "torques in, motion out; housing fixed",
                        {"flange_a": FORCE_IN, "flange_b": FORCE_IN}),)

    def equations(self, e):
        def friction(applied, acceleration):
            kinetic, at_rest = self.characteristic(e, e.q.mode * e.x.w)
            return _friction(e, speed="w", acceleration=acceleration, applied=applied,
                             static=e.p.peak * at_rest, kinetic=kinetic)
        _body(e, friction)


class RotationalBrake(_TableFriction):
    """Brake based on Coulomb friction, holding a shaft of inertia J (MSL Rotational.Components.Brake;
    registered as RotationalBrake).

    ``fn = fn_max f_normalized``; sliding ``tau = cgeo mu(|w|) fn`` opposing w; stuck
    while the torque on the shaft stays within ``peak cgeo mu(0) fn`` (free when fn <= 0).
    Parameters: ``mu_pos[k,1]`` [rad/s], ``mu_pos[k,2]`` [1] (option ``rows``; MSL's
    default [0, 0.5]), ``peak`` [1], ``cgeo`` [m], ``fn_max`` [N], ``J`` [kg.m2].
    Input: ``f_normalized`` [1] (0..1). States: ``phi``, ``w``, ``W_loss`` [J].
    Mode: ``mode``. Connectors: ``flange_a``, ``flange_b`` — torque in, motion out.
    Outputs: ``tau`` [N.m], ``lossPower`` [W], ``fn`` [N], ``E`` [J].
    """

    fixed_parameters = (_PEAK, _CGEO, _FN_MAX, _J)
    states = _BODY_STATES
    ports = (*_BODY_PORTS, Port("f_normalized", signal("1"), "normal force / fn_max (0..1)"))
    profiles = (Profile("direct", "normal force in; torques in, motion out; housing fixed",
                        {"flange_a": FORCE_IN, "flange_b": FORCE_IN, "f_normalized": SIGNAL_IN}),)

    def equations(self, e):
        fn = _normal_force(e)
        e.output("fn", fn, "N", "normal force")

        def friction(applied, acceleration):
            mu, mu0 = self.characteristic(e, e.q.mode * e.x.w)
            pressed = e.p.cgeo * fn  # free (no friction) when fn <= 0
            return _friction(e, speed="w", acceleration=acceleration, applied=applied,
                             static=e.p.peak * mu0 * pressed, kinetic=mu * pressed,
                             free=fn <= 0)
        _body(e, friction)


class Clutch(_TableFriction):
    """Clutch based on Coulomb friction, its driven side an inertia J (MSL Rotational.Components.Clutch).

    ``w_rel = flange_b.w - flange_a.w``;
    ``fn = fn_max f_normalized``; sliding ``tau = cgeo mu(|w_rel|) fn sign(w_rel)``;
    stuck while the torque needed stays within ``peak cgeo mu(0) fn``; free (MSL's
    ``free``: fn reported 0, no torque, never stuck) while ``f_normalized <= 0``. The driven side
    (inertia ``J``, flange_b) is part of the element; flange_a takes the motion of the
    driving side in (a speed source, a spring end: something whose motion does not
    depend on this clutch's torque at the same instant).
    Parameters: ``mu_pos`` rows, ``peak``, ``cgeo`` [m], ``fn_max`` [N], ``J`` [kg.m2].
    Input: ``f_normalized`` [1]. States: ``phi``, ``w`` of the driven side (absolute:
    MSL's are relative), ``W_loss`` [J]; a lock sets w to the driver's speed exactly.
    Mode: ``mode``. Connectors: ``flange_a`` — motion in, torque out; ``flange_b`` —
    torque in, motion out. Outputs: ``tau``, ``lossPower``, ``fn``, ``phi_rel``,
    ``w_rel``, ``E`` [J].
    """

    fixed_parameters = (_PEAK, _CGEO, _FN_MAX, _J)
    one_way = False  # OneWayClutch: a freewheel in parallel
    # decided at initialisation from w_rel, then the torques (friction.UNKNOWN: a stuck
    # start would be set to the driver's speed); the equations are three, FREE (MSL's
    # free: no normal force, no friction) and UNKNOWN take those of -1
    modes = (Mode("mode", UNKNOWN, "friction mode: -1 sliding backward, 0 stuck, +1 sliding "
                                   "forward, 2 free (3 before initialisation)",
                  also=(FREE, UNKNOWN)),)
    # absolute states of the driven side: free or sliding, its motion does not depend on
    # the driver's acceleration (an input a co-simulation holds over a step)
    states = _BODY_STATES
    ports = (Port("flange_a", ROTATIONAL, "driving side"),
             Port("flange_b", ROTATIONAL, "driven side (the inertia J)"),
             Port("f_normalized", signal("1"), "normal force / fn_max (0..1)"))
    profiles = (Profile("driven", "driving motion in at flange_a; driven side computed",
                        {"flange_a": MOTION_IN, "flange_b": FORCE_IN, "f_normalized": SIGNAL_IN}),)

    def equations(self, e):
        p, a_, b_, a = e.p, e.port("flange_a"), e.port("flange_b"), e.der.w
        w_rel = e.x.w - a_.w
        fn = _normal_force(e)
        mu, mu0 = self.characteristic(e, e.q.mode * w_rel)
        pressed = p.cgeo * fn
        e.residual(e.der.phi - e.x.w)
        f = _friction(e, speed="w", base=a_.w, acceleration=a - a_.a,
                      applied=b_.tau - p.J * a_.a,  # in the driving side's frame
                      static=p.peak * mu0 * pressed, kinetic=mu * pressed,
                      # a one-way clutch's freewheel holds with no normal force too
                      one_way=self.one_way, free=None if self.one_way else fn <= 0)
        e.residual(p.J * a - b_.tau - f)
        e.residual(a_.tau - f)  # the plates: what the driven side feels, the driver feels back
        e.residual(b_.phi - e.x.phi)
        e.residual(b_.w - e.x.w)
        e.residual(b_.a - a)
        e.output("fn", fn, "N", "normal force")
        e.output("phi_rel", e.x.phi - a_.phi, "rad", "flange_b.phi - flange_a.phi")
        e.output("w_rel", w_rel, "rad/s", "flange_b.w - flange_a.w")
        e.output("E", p.J * e.x.w**2 / 2, "J", "kinetic energy of the driven side")


Brake = RotationalBrake  # MSL's name inside the rotational package


class OneWayClutch(Clutch):
    """Clutch in parallel with a freewheel, its driven side an inertia J (MSL Rotational.Components.OneWayClutch).

    ``w_rel = flange_b.w - flange_a.w`` never falls below 0: the driven side may overrun
    the driver (``w_rel > 0``), never lag it. Overrunning, the clutch slides forward with
    ``tau = cgeo mu(w_rel) fn``, or carries no torque while free (``fn = fn_max
    f_normalized <= 0``); when ``w_rel`` returns to 0 it locks, and locked it holds
    against any backward torque (the freewheel) and against forward torques up to
    ``peak cgeo mu(0) fn`` (0 while free: a pure freewheel). MSL's modes: free, stuck
    (locked or starting forward), forward sliding; exact, with events.
    MSL's free freewheel starts forward above ``1e-4 cgeo mu(0) fn_max`` (its eps0
    hysteresis); this one at any positive torque. A start (or a driver's speed jump)
    with ``w_rel < 0``, which MSL calls physically impossible, ends the run with a
    message.
    Parameters, input, states, outputs and connectors as :class:`Clutch`; mode ``mode``:
    0 stuck, +1 sliding forward (overrunning).
    """

    one_way = True

    def equations(self, e):
        super().equations(e)
        e.terminate_when(ca.if_else(e.q.mode == -1, -1, 1),
                         "one-way clutch with w_rel = flange_b.w - flange_a.w < 0 (the driven "
                         "side lags the driver: MSL's OneWayClutch needs w_rel >= 0)")
