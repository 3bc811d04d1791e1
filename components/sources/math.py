"""Signal arithmetic (MSL ``Modelica.Blocks.Math``): the blocks MSL's examples put
between a source and the input it feeds.

``Product`` multiplies two signals, as MSL's Rotational.Examples.Friction gates its
driving sine with a step. Like the sources, its signals have no unit: the output's
unit is the one of the input it feeds.
"""
from __future__ import annotations

from ..component import Component
from ..interfaces import SIGNAL_IN, SIGNAL_OUT, Port, Profile, signal


class Product(Component):
    """Output the product of the two inputs, y = u1 u2 (MSL Blocks.Math.Product).

    Inputs: ``u1``, ``u2``. Output: ``y`` (direct feedthrough, no state).
    """

    ports = (Port("u1", signal(""), "first factor"), Port("u2", signal(""), "second factor"),
             Port("y", signal(""), "u1 u2"))
    profiles = (Profile("block", "two signals in, their product out",
                        {"u1": SIGNAL_IN, "u2": SIGNAL_IN, "y": SIGNAL_OUT}),)
    default_stop_time = 1.0

    def equations(self, e):
        e.residual(e.port("y") - e.port("u1") * e.port("u2"))
