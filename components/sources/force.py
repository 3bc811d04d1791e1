"""Force sources: flanges that push on whatever they are connected to, however it moves."""
from __future__ import annotations

from ..component import Component
from ..interfaces import MOTION_IN, SIGNAL_IN, TRANSLATIONAL, Parameter, Port, Profile, signal


class ConstantForce(Component):
    """Constant force F applied to the connected flange (MSL Translational.Sources.ConstantForce).

    Parameter: ``F`` [N], positive along +s of the flange it acts on.
    Connector: ``flange`` — takes the motion (s, v, a) of what it drives as inputs and
    outputs its cut force ``flange.f = -F``: a flow is the force on the component, and
    a connection makes the flows sum to zero, so the connected component feels +F.
    """

    parameters = (Parameter("F", 1.0, "N", "force applied to the connected flange, along +s"),)
    ports = (Port("flange", TRANSLATIONAL, "flange the force acts through"),)
    profiles = (Profile("applied", "motion in, force out", {"flange": MOTION_IN}),)

    def equations(self, e):
        e.residual(e.port("flange").f + e.p.F)


class Force(Component):
    """Force given by a signal, applied to the connected flange (MSL Translational.Sources.Force).

    Input: ``f`` [N], positive along +s of the flange it acts on (e.g. a controller's
    output). Connector: ``flange`` — motion in, cut force ``flange.f = -f`` out (the
    sign convention of :class:`ConstantForce`).
    """

    ports = (Port("f", signal("N"), "force applied to the connected flange, along +s"),
             Port("flange", TRANSLATIONAL, "flange the force acts through"))
    profiles = (Profile("applied", "force signal in; motion in, force out",
                        {"f": SIGNAL_IN, "flange": MOTION_IN}),)

    def equations(self, e):
        e.residual(e.port("flange").f + e.port("f"))
