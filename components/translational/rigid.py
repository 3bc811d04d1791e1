"""Massless rigid elements that pass motion one way and force the other (MSL Rod, and the
connection sets MSL forms where three flanges meet).

A connection here joins exactly two ports, and an FMU's force input takes one source, so
the point where MSL connects three flanges is a ``Junction``: one flange takes the
motion of what computes it, the other two pass it on and add the forces they take back.
Each has a profile per flange that may carry the motion in; the assembly picks it.
"""
from __future__ import annotations

from ..component import Component
from ..interfaces import FORCE_IN, MOTION_IN, TRANSLATIONAL, Parameter, Port, Profile

_ACROSS = ("s", "v", "a")


def _through(names):
    """One profile per flange taking the motion in, the others passing it on."""
    return tuple(Profile(f"motion_at_{name[-1]}", f"motion in at {name}, passed on at the "
                         "others; their forces in, summed back out at " + name,
                         {n: MOTION_IN if n == name else FORCE_IN for n in names})
                 for name in names)


class Rod(Component):
    """Rigid massless rod of length L (MSL Translational.Components.Rod).

    ``flange_b.s = flange_a.s + L``, same v and a; ``flange_a.f + flange_b.f = 0``.
    Parameter: ``L`` [m]. Connectors: ``flange_a``, ``flange_b`` — one takes the motion
    in and gives the force out, the other passes the motion on and takes the force in
    (profiles ``motion_at_a``, ``motion_at_b``; the assembly picks one).
    """

    parameters = (Parameter("L", 0.0, "m", "length of the rod"),)
    ports = (Port("flange_a", TRANSLATIONAL, "left end"),
             Port("flange_b", TRANSLATIONAL, "right end"))
    profiles = _through(("flange_a", "flange_b"))

    def equations(self, e):
        a, b = e.port("flange_a"), e.port("flange_b")
        e.residual(b.s - a.s - e.p.L)
        e.residual(b.v - a.v)
        e.residual(b.a - a.a)
        e.residual(a.f + b.f)


class Junction(Component):
    """Three flanges rigidly joined at one point (a Modelica connection set of three).

    Every flange has the same s, v, a; ``flange_a.f + flange_b.f + flange_c.f = 0``.
    Connectors: ``flange_a``, ``flange_b``, ``flange_c`` — one takes the motion in and
    gives the sum of the others' forces out, the other two pass the motion on and take
    their forces in (profiles ``motion_at_a``, ``_b``, ``_c``; the assembly picks one).
    """

    ports = tuple(Port(f"flange_{k}", TRANSLATIONAL, f"flange {k} of the joint")
                  for k in "abc")
    profiles = _through(("flange_a", "flange_b", "flange_c"))

    def equations(self, e):
        a, b, c = (e.port(f"flange_{k}") for k in "abc")
        for other in (b, c):
            for name in _ACROSS:
                e.residual(getattr(other, name) - getattr(a, name))
        e.residual(a.f + b.f + c.f)
