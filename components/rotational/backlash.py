"""Backlash in series with a spring and damper (MSL Rotational.Components.ElastoBacklash and
ElastoBacklash2).

Both are MSL's ``PartialCompliant`` pair (motion of both flanges in, torque out) with a
gap of total width ``b`` about ``phi_rel0``: no torque inside it, a spring-damper
``tau_c + tau_d`` outside it that only pushes (MSL sets it to zero where it would pull:
no sticking at the gap's edges). MSL writes the kinks with ``noEvent``; here every one
is an event indicator (contact at either edge, and each switch of the no-pull and
damper-bound rules), so the solver never steps across a kink and contact times are
located to the tolerance.

MSL's ``lossPower`` is 0 on the branch where the contact lets go while the spring is
still compressed (``tau_c + tau_d`` of the wrong sign): the spring's energy then vanishes
without being counted. Ours counts it, ``lossPower = (tau - tau_c) w_rel`` (>= 0), so
that the work done on the element is its elastic energy plus ``W_loss`` exactly.
"""
from __future__ import annotations

from ..component import Component
from ..interfaces import Parameter, State
from ..lazy import lazy
from .elements import _COMPLIANT_PORTS, _COMPLIANT_PROFILES

ca = lazy("casadi")  # loaded by the first equation written, not by an import

#: MSL's bEps: below this total backlash the element is a plain spring-damper (no gap,
#: so no events at phi_diff = 0)
B_EPS = 1e-10

_PARAMETERS = (
    Parameter("c", 1e5, "N.m/rad", "spring constant (c > 0 required)", min=0.0,
              min_strict=True),  # MSL: no default, start 1e5
    # MSL: no default, start 0; 1 as for Damper, so that a default instance dissipates
    Parameter("d", 1.0, "N.m.s/rad", "damping constant", min=0.0),
    Parameter("b", 0.0, "rad", "total backlash", min=0.0),
    Parameter("phi_rel0", 0.0, "rad", "unstretched spring angle"))
_LOSS = State("W_loss", 0.0, "J", "energy dissipated since t = 0 (damper and released "
              "spring energy)")


def _backlash(e, bounded: bool) -> None:
    """MSL's backlash law; `bounded` (ElastoBacklash) limits |tau_d| to |tau_c| in contact,
    otherwise (ElastoBacklash2) the damper acts in full until the torque would pull."""
    p, a, b = e.p, e.port("flange_a"), e.port("flange_b")
    phi_rel, w_rel = b.phi - a.phi, b.w - a.w
    phi_diff = phi_rel - p.phi_rel0
    gapless = p.b <= B_EPS
    upper, lower = phi_diff - p.b / 2, phi_diff + p.b / 2  # > 0 / < 0: contact at that edge
    tau_c = ca.if_else(gapless, p.c * phi_diff,
                       ca.if_else(upper > 0, p.c * upper, ca.if_else(lower < 0, p.c * lower, 0)))
    contact = ca.logic_and(ca.logic_not(gapless), ca.logic_or(upper > 0, lower < 0))
    tau_d = p.d * w_rel
    reach = ca.fabs(tau_c)  # the damper's bound in contact: |tau_d| <= |tau_c|
    if bounded:
        # tau_c + clip(tau_d, -|tau_c|, |tau_c|): 0 where it would pull, 2 tau_c at most
        pushing = tau_c + ca.fmin(ca.fmax(tau_d, -reach), reach)
    else:
        # tau_c + tau_d, or 0 once it has the opposite sign of tau_c (it would pull)
        pushing = ca.if_else(tau_c * (tau_c + tau_d) > 0, tau_c + tau_d, 0)
    tau = ca.if_else(gapless, tau_c + tau_d, ca.if_else(contact, pushing, 0))
    # a flow is the torque ON this component: twisted forward at b, it is turned +n there
    e.residual(b.tau - tau)
    e.residual(a.tau + tau)
    depth = tau_c / p.c  # the spring's compression beyond the gap's edge (signed)
    loss = (tau - tau_c) * w_rel
    e.residual(e.der.W_loss - loss)
    e.indicator(ca.if_else(gapless, 1, upper), "beyond the gap's upper edge while positive")
    e.indicator(ca.if_else(gapless, 1, -lower), "beyond the gap's lower edge while positive")
    # in contact: the damper's bounds (bounded) or the no-pull rule's switch (both)
    sign = ca.if_else(tau_c >= 0, 1, -1)
    e.indicator(ca.if_else(contact, sign * (tau_c + tau_d), 1),
                "in contact: spring + damper torque pushing while positive")
    if bounded:
        e.indicator(ca.if_else(contact, reach - sign * tau_d, 1),
                    "in contact: damper torque below its bound |tau_c| while positive")
    e.output("tau", tau, "N.m", "torque in the element, positive when pushing flange_b "
             "forward (phi_rel beyond the gap's upper edge)")
    e.output("phi_rel", phi_rel, "rad", "flange_b.phi - flange_a.phi")
    e.output("w_rel", w_rel, "rad/s", "flange_b.w - flange_a.w")
    e.output("contact", ca.if_else(contact, ca.if_else(tau_c > 0, 1, -1), 0), "1",
             "+1 in contact beyond the upper edge, -1 beyond the lower, 0 in the gap")
    e.output("tau_c", tau_c, "N.m", "spring torque (0 in the gap)")
    e.output("E", p.c * depth**2 / 2, "J", "elastic energy")
    e.output("lossPower", loss, "W", "power dissipated (damper, and spring energy released "
             "without work where the contact lets go)")


class ElastoBacklash(Component):
    """Backlash in series with a spring and damper, never pulling (MSL Rotational.Components.ElastoBacklash).

    ``phi_diff = phi_rel - phi_rel0``, ``phi_rel = flange_b.phi - flange_a.phi``: for
    ``|phi_diff| <= b/2`` no torque; beyond the edge ``tau_c = c (phi_diff -+ b/2)``,
    ``tau_d = d w_rel`` bounded to ``|tau_d| <= |tau_c|`` (so the torque is continuous
    at first contact), ``tau = tau_c + tau_d``, 0 where it would pull; ``b <= 1e-10``:
    a spring-damper ``c phi_diff + d w_rel``. Every kink is an event.
    Parameters: ``c`` [N.m/rad] (> 0), ``d`` [N.m.s/rad], ``b`` [rad] total backlash,
    ``phi_rel0`` [rad]. State: ``W_loss`` [J] energy dissipated.
    Connectors: ``flange_a``, ``flange_b`` — motion in, torque out.
    Outputs: ``tau``, ``tau_c`` [N.m], ``phi_rel`` [rad], ``w_rel`` [rad/s], ``contact``
    [1], ``E`` [J] elastic energy, ``lossPower`` [W].
    """

    parameters = _PARAMETERS
    states = (_LOSS,)
    ports, profiles = _COMPLIANT_PORTS, _COMPLIANT_PROFILES

    def equations(self, e):
        _backlash(e, bounded=True)


class ElastoBacklash2(Component):
    """Backlash in series with a spring and damper, the torque may jump at contact (MSL Rotational.Components.ElastoBacklash2).

    As :class:`ElastoBacklash`, but the damper is not bounded by the spring: in contact
    ``tau = tau_c + tau_d``, 0 where it would pull (so the torque jumps by ``d w_rel``
    at first contact). Parameters ``c``, ``d``, ``b``, ``phi_rel0``; state ``W_loss``;
    connectors and outputs as ElastoBacklash's.
    """

    parameters = _PARAMETERS
    states = (_LOSS,)
    ports, profiles = _COMPLIANT_PORTS, _COMPLIANT_PROFILES

    def equations(self, e):
        _backlash(e, bounded=False)
