"""Kinematic sources along periodic paths: a table shaken sinusoidally (seed 9.6).

Like :class:`components.sources.translational.ConstantSpeed`, the flange's motion is prescribed
(``force`` causality: s, v, a out; the force it takes to move it in, reported only).
The velocity and acceleration are the exact derivatives of the path, so a connected
component that extrapolates its motion inputs with them sees the true path to
second order.
"""
from __future__ import annotations

from ..component import Component
from ..interfaces import FORCE_IN, TRANSLATIONAL, Parameter, Port, Profile
from ..lazy import lazy

ca = lazy("casadi")  # loaded by the first equation written, not by an import

_KINEMATIC = (Profile("kinematic", "motion out, reaction force in", {"flange": FORCE_IN}),)


class SineMotion(Component):
    """Translational flange moved along s = s0 + U sin(omega t) (seed 9.6, example 1).

    Parameters: ``U`` [m] amplitude, ``omega`` [rad/s] angular frequency, ``s0`` [m]
    mean position.
    Connector: ``flange`` — outputs s, v = U omega cos(omega t), a = -U omega² sin(omega t);
    the force needed to move it is an input.
    """

    parameters = (Parameter("U", 0.1, "m", "amplitude of the motion"),
                  Parameter("omega", 20.0, "rad/s", "angular frequency of the motion", min=0.0),
                  Parameter("s0", 0.0, "m", "mean position"))
    ports = (Port("flange", TRANSLATIONAL, "the shaken flange"),)
    profiles = _KINEMATIC

    def equations(self, e):
        flange, p, wt = e.port("flange"), e.p, e.p.omega * e.t
        e.residual(flange.s - (p.s0 + p.U * ca.sin(wt)))
        e.residual(flange.v - p.U * p.omega * ca.cos(wt))
        e.residual(flange.a + p.U * p.omega**2 * ca.sin(wt))


class HarmonicMotion(Component):
    """Translational flange moved along s = s0 + U Σ c_k sin(k omega t), k = 1..3 (seed 9.6, ex. 2).

    The seed's asymmetric conveyor table is c = (1, -0.33, 0.08).
    Parameters: ``U`` [m] amplitude scale, ``omega`` [rad/s] fundamental angular
    frequency, ``c1``, ``c2``, ``c3`` [1] harmonic coefficients, ``s0`` [m] mean position.
    Connector: ``flange`` — outputs s and its exact derivatives v, a; force in.
    """

    parameters = (Parameter("U", 0.1, "m", "amplitude scale of the motion"),
                  Parameter("omega", 20.0, "rad/s", "fundamental angular frequency", min=0.0),
                  Parameter("c1", 1.0, "1", "coefficient of sin(omega t)"),
                  Parameter("c2", -0.33, "1", "coefficient of sin(2 omega t)"),
                  Parameter("c3", 0.08, "1", "coefficient of sin(3 omega t)"),
                  Parameter("s0", 0.0, "m", "mean position"))
    ports = (Port("flange", TRANSLATIONAL, "the shaken flange"),)
    profiles = _KINEMATIC

    def equations(self, e):
        flange, p = e.port("flange"), e.p
        terms = ((1, p.c1), (2, p.c2), (3, p.c3))
        s = sum(c * ca.sin(k * p.omega * e.t) for k, c in terms)
        v = sum(c * k * p.omega * ca.cos(k * p.omega * e.t) for k, c in terms)
        a = sum(-c * (k * p.omega)**2 * ca.sin(k * p.omega * e.t) for k, c in terms)
        e.residual(flange.s - (p.s0 + p.U * s))
        e.residual(flange.v - p.U * v)
        e.residual(flange.a - p.U * a)
