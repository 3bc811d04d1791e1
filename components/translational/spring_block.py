"""The spring-block with dry friction of Chatterjee, Intermediate Dynamics, 9.2–9.6."""
from __future__ import annotations

from ..component import Component
from ..friction import coulomb_modes
from ..interfaces import (FIXED, MOTION_IN, TRANSLATIONAL, Constraint, Mode, Option, Parameter,
                         Port, Profile, State)
from ..lazy import lazy

ca = lazy("casadi")  # loaded by the first equation written, not by an import


#: a smooth law's block slides once |v| passes this many eps (stuck again below half)
SLIDING_AT = 3.0


class SpringBlock(Component):
    """Block on a (possibly moving) surface, pulled through a spring by a driven end.

    Seed Fig. 9.2, Eqs. 9.1–9.9: ``m (a_support + x'') = k (s_end - s_support - x)
    + d (v_end - v_support - x') + f`` with normal load ``m g``.

    Parameters: ``m`` [kg], ``k`` [N/m], ``d`` [N.s/m], ``g`` [m/s2], ``mu_k``,
    ``mu_s`` [1], ``eps`` [m/s] (smooth laws only).
    Options: ``friction`` — ``coulomb`` (exact: stick and slip are modes switched by
    events, incipient sliding as in Eq. 9.3; while stuck the relative velocity is
    exactly zero), ``smooth`` (Eq. 9.5) or ``tanh`` (Eq. 9.7, ``mu_k tanh(3 v/eps)``).
    States: ``x`` [m], ``v`` [m/s], position and velocity of the block relative to the
    support, as the seed defines ``x`` in 9.2 and 9.6 (absolute when it is fixed).
    Mode: ``mode`` = -1 sliding backward, 0 stuck, +1 sliding forward (for the smooth
    laws, which never stick exactly: sliding once ``|v| > 3 eps``, stuck again below
    ``1.5 eps``).
    Connectors: ``flange_a`` the spring's free end, ``support`` the surface.
    """

    options = (Option("friction", "coulomb", ("coulomb", "smooth", "tanh"),
                      "friction law: exact Coulomb with modes, seed Eq. 9.5, or seed Eq. 9.7"),)
    parameters = (
        Parameter("m", 1.0, "kg", "mass of the block", min=0.0, min_strict=True),
        Parameter("k", 1.0, "N/m", "stiffness of the spring", min=0.0),
        Parameter("d", 0.0, "N.s/m", "damping of a dashpot parallel to the spring", min=0.0),
        Parameter("g", 9.81, "m/s2", "gravity, pressing the block on the surface", min=0.0),
        Parameter("mu_k", 0.3, "1", "kinetic friction coefficient", min=0.0),
        Parameter("mu_s", 0.4, "1", "static friction coefficient", min=0.0),
        Parameter("eps", 1e-3, "m/s", "velocity scale of the smooth friction laws",
                  min=0.0, min_strict=True),
    )
    constraints = (Constraint(lambda p: p.mu_s - p.mu_k, "mu_k <= mu_s"),)
    states = (State("x", 0.0, "m", "position of the block relative to the support"),
              State("v", 0.0, "m/s", "velocity of the block relative to the support"))
    modes = (Mode("mode", 0, "friction mode: -1 sliding backward, 0 stuck, +1 sliding forward"),)
    ports = (Port("flange_a", TRANSLATIONAL, "free end of the spring"),
             Port("support", TRANSLATIONAL, "surface the block slides on"))
    profiles = (
        Profile("driven", "spring end moved by a kinematic input; fixed surface",
                {"flange_a": MOTION_IN, "support": FIXED}),
        Profile("driven_on_moving_support", "spring end and surface both moved by inputs",
                {"flange_a": MOTION_IN, "support": MOTION_IN}),
    )
    default_stop_time = 20.0

    def equations(self, e):
        p, x, v, a = e.p, e.x.x, e.x.v, e.der.v
        end, support = e.port("flange_a"), e.port("support")
        f = e.unknown("f")
        normal = p.m * p.g
        f_spring = p.k * (end.s - support.s - x) + p.d * (end.v - support.v - v)
        f_applied = f_spring - p.m * support.a  # all but friction, in the support's frame
        e.residual(e.der.x - v)
        e.residual(p.m * (support.a + a) - f_spring - f)
        e.residual(end.f - f_spring)
        e.residual(support.f - f)
        law = e.option("friction")
        if law == "coulomb":
            # stuck: the block moves with the support; sliding: kinetic friction against it
            coulomb_modes(e, speed="v", acceleration=a, friction=f, applied=f_applied,
                          static_limit=p.mu_s * normal, kinetic_limit=p.mu_k * normal)
        else:
            s = v / p.eps
            if law == "smooth":  # seed Eq. 9.5
                mu = p.mu_k * ca.tanh(3 * s) + (p.mu_s - p.mu_k) * s * ca.exp(0.5 - s**2 / 2)
            else:  # seed Eq. 9.7
                mu = p.mu_k * ca.tanh(3 * s)
            e.residual(f + mu * normal)
            # a smooth law never sticks exactly: the block counts as sliding once |v| passes
            # SLIDING_AT eps, beyond the stiction peak of Eq. 9.5 (near eps): only a block
            # that has broken away gets there, and it gets there accelerating, so the event
            # is sharply located (at eps itself the creep before the peak is so slow that
            # the solver's error in v moves the crossing by milliseconds). It counts as
            # stuck again below half that; the gap is the hysteresis that keeps an event
            # located at one level (the state a hair past it) from switching straight back.
            q, level = e.q.mode, SLIDING_AT * p.eps
            e.indicator(ca.if_else(q == 0, v - level, q * v - level / 2),
                        "stuck: relative velocity above 3 eps; sliding: |velocity| above 1.5 eps")
            e.indicator(ca.if_else(q == 0, v + level, 1),
                        "stuck: relative velocity below -3 eps (sliding backward)")
            from_rest = ca.if_else(v > level, 1, ca.if_else(v < -level, -1, 0))
            e.jump("mode", ca.if_else(q * v >= level / 2, q, from_rest))
        e.output("a", a, "m/s2", "acceleration of the block relative to the support")
        e.output("s", support.s + x, "m", "absolute position of the block")
        e.output("f_friction", f, "N", "friction force on the block")
        e.output("f_spring", f_spring, "N", "spring (and dashpot) force on the block")
