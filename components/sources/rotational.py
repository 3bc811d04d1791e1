"""Rotational sources (MSL Rotational.Sources): torques applied to a flange, and flanges
moved to follow a speed or angle signal.

A torque source takes the motion of the flange it drives in and gives the torque out
(``flange.tau = -tau``: a flow is the torque on the source, so the connected flange
feels +tau); each integrates the work it does, ``W' = tau w``, for energy balances.
``RotationalSpeed`` and ``RotationalPosition`` compute the motion (MSL's exact = false
filters, as :mod:`components.sources.translational` explains) and take the torque in.
Where MSL's name exists in Translational the class carries the prefix ``Rotational``;
MSL's own names are aliases at the bottom.
"""
from __future__ import annotations

import math

from ..component import Component
from ..interfaces import (FORCE_IN, MOTION_IN, ROTATIONAL, SIGNAL_IN, Option, Parameter, Port,
                          Profile, State, signal)
from ..lazy import lazy
from .translational import _AF, _BF, _F_CRIT

ca = lazy("casadi")  # loaded by the first equation written, not by an import

_FLANGE = Port("flange", ROTATIONAL, "flange the torque acts on")
_WORK = State("W", 0.0, "J", "work done on the flange since t = 0")


def _apply(e, tau, *, report_tau=True):
    """Drive the flange with +tau and integrate the work done."""
    flange = e.port("flange")
    e.residual(flange.tau + tau)
    e.residual(e.der.W - tau * flange.w)
    if report_tau:  # (a Torque's tau is its input already)
        e.output("tau", tau, "N.m", "torque applied to the flange")
    e.output("power", tau * flange.w, "W", "power delivered to the flange")


class Torque(Component):
    """Torque given by a signal, applied to a flange (MSL Rotational.Sources.Torque).

    Input: ``tau`` [N.m], accelerating the flange for tau > 0 (MSL's useSupport = false).
    State: ``W`` [J] work done. Connector: ``flange`` — motion in, torque out.
    Output: ``power`` [W] delivered to the flange.
    """

    states = (_WORK,)
    ports = (Port("tau", signal("N.m"), "torque driving the flange"), _FLANGE)
    profiles = (Profile("applied", "torque signal in; motion in, torque out",
                        {"tau": SIGNAL_IN, "flange": MOTION_IN}),)

    def equations(self, e):
        _apply(e, e.port("tau"), report_tau=False)


class ConstantTorque(Component):
    """Constant torque, not dependent on speed (MSL Rotational.Sources.ConstantTorque).

    Parameter: ``tau_constant`` [N.m] (positive: accelerating). State: ``W`` [J].
    Connector: ``flange`` — motion in, torque out. Outputs: ``tau``, ``power`` [W].
    """

    parameters = (Parameter("tau_constant", 1.0, "N.m", "constant torque (if negative, "
                            "braking in the direction of rotation)"),)
    states = (_WORK,)
    ports = (_FLANGE,)
    profiles = (Profile("applied", "motion in, torque out", {"flange": MOTION_IN}),)

    def equations(self, e):
        _apply(e, e.p.tau_constant)


class QuadraticSpeedDependentTorque(Component):
    """Torque quadratic in speed (MSL Rotational.Sources.QuadraticSpeedDependentTorque).

    ``tau = tau_nominal (w / w_nominal)^2`` for TorqueDirection = true, else
    ``tau_nominal (w / w_nominal)^2 sign(w)`` (opposing the motion when tau_nominal < 0,
    as a fan or a drag). Parameters: ``tau_nominal`` [N.m], ``w_nominal`` [rad/s] (> 0).
    Option: ``TorqueDirection`` true/false. State: ``W`` [J]. Connector: ``flange`` —
    motion in, torque out. Outputs: ``tau``, ``power`` [W].
    """

    parameters = (Parameter("tau_nominal", -1.0, "N.m", "nominal torque (if negative, "
                            "braking)"),
                  Parameter("w_nominal", 1.0, "rad/s", "nominal speed", min=0.0,
                            min_strict=True))
    options = (Option("TorqueDirection", "true", ("true", "false"),
                      "same direction of torque in both directions of rotation"),)
    states = (_WORK,)
    ports = (_FLANGE,)
    profiles = (Profile("applied", "motion in, torque out", {"flange": MOTION_IN}),)

    def equations(self, e):
        w, p = e.port("flange").w, e.p
        tau = p.tau_nominal * (w / p.w_nominal)**2
        _apply(e, tau if e.option("TorqueDirection") == "true" else tau * ca.sign(w))


_KINEMATIC_STATES = (State("phi", 0.0, "rad", "absolute angle of the flange"),
                     State("w", 0.0, "rad/s", "absolute angular velocity of the flange"))


def _drive(e):
    flange = e.port("flange")
    e.residual(e.der.phi - e.x.w)
    e.residual(flange.phi - e.x.phi)
    e.residual(flange.w - e.x.w)
    e.residual(flange.a - e.der.w)


class RotationalSpeed(Component):
    """Flange moved to follow a speed signal (MSL Rotational.Sources.Speed, exact = false;
    registered as RotationalSpeed).

    ``a = (w_ref - w) w_crit``, ``w_crit = 2 pi f_crit``; phi is the integral of w.
    Parameter: ``f_crit`` [Hz]. States: ``phi`` [rad], ``w`` [rad/s]. Input: ``w_ref``
    [rad/s]. Connector: ``flange`` — phi, w, a out; the torque it takes in (reported).
    """

    parameters = (_F_CRIT,)
    states = _KINEMATIC_STATES
    ports = (Port("w_ref", signal("rad/s"), "reference angular velocity"), _FLANGE)
    profiles = (Profile("kinematic", "speed signal in; motion out, reaction torque in",
                        {"w_ref": SIGNAL_IN, "flange": FORCE_IN}),)

    def equations(self, e):
        _drive(e)
        e.residual(e.der.w - (e.port("w_ref") - e.x.w) * (2 * math.pi * e.p.f_crit))


class RotationalPosition(Component):
    """Flange moved to follow an angle signal (MSL Rotational.Sources.Position, exact = false;
    registered as RotationalPosition).

    ``a = ((phi_ref - phi) w_crit - 1.3617 w) w_crit / 0.6180`` (MSL's critically damped
    filter), ``w_crit = 2 pi f_crit``. Parameter: ``f_crit`` [Hz]. States: ``phi``
    [rad], ``w`` [rad/s]. Input: ``phi_ref`` [rad]. Connector: ``flange`` — motion out,
    torque in.
    """

    parameters = (_F_CRIT,)
    states = _KINEMATIC_STATES
    ports = (Port("phi_ref", signal("rad"), "reference angle"), _FLANGE)
    profiles = (Profile("kinematic", "angle signal in; motion out, reaction torque in",
                        {"phi_ref": SIGNAL_IN, "flange": FORCE_IN}),)

    def equations(self, e):
        w = 2 * math.pi * e.p.f_crit
        _drive(e)
        e.residual(e.der.w - ((e.port("phi_ref") - e.x.phi) * w - _AF * e.x.w) * (w / _BF))


# MSL's names inside this module
Speed, Position = RotationalSpeed, RotationalPosition
