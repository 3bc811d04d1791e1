"""Signal sources (MSL ``Modelica.Blocks.Sources``): Constant, Step, Ramp, Sine.

Each is an FMU with one output ``y`` of no unit (it feeds any Float64 signal input, a
torque, a normalised normal force, a reference speed), MSL's parameter names and
defaults. Our runtime has no time events, so each instant where the signal or its
slope jumps (``startTime``, the end of a ramp) is a state event on time itself, as in
:class:`components.sources.table.TimeTable`: a mode ``passed`` counts the instants
passed, one indicator ``time - (next instant)`` is linear in time and located to
rounding, and it fires :data:`~components.sources.table.EARLY` before the instant so
that a result row at that very time reads the value after it (fmpy's rule).
"""
from __future__ import annotations

import math

from ..component import Component
from ..interfaces import SIGNAL_OUT, Mode, Parameter, Port, Profile, signal
from ..lazy import lazy
from .table import EARLY

ca = lazy("casadi")  # loaded by the first equation written, not by an import

_PORTS = (Port("y", signal(""), "the signal"),)
_PROFILES = (Profile("source", "signal out", {"y": SIGNAL_OUT}),)
_OFFSET = Parameter("offset", 0.0, "", "offset of the output signal")
_START = Parameter("startTime", 0.0, "s", "output = offset before this time")


def _passed(e, instants) -> ca.SX:
    """The mode ``passed``: how many of `instants` (non-decreasing) time has passed."""
    def early(t):
        return t - EARLY * ca.fmax(1, ca.fabs(t))
    q = e.q.passed
    e.jump("passed", sum(ca.if_else(early(t) <= e.t, 1, 0) for t in instants))
    upcoming = sum(ca.if_else(q == k, instants[k], 0) for k in range(len(instants)))
    e.indicator(ca.if_else(q < len(instants), e.t - early(upcoming), -1),
                "time past the next instant where the signal or its slope jumps")
    return q


def _passed_mode(n: int) -> tuple[Mode, ...]:
    return (Mode("passed", 0, "instants passed (startTime, end of the ramp)",
                 values=tuple(range(n + 1))),)


class Constant(Component):
    """Constant signal y = k (MSL Blocks.Sources.Constant).

    Parameter: ``k`` (no unit: the output's unit is the one of the input it feeds).
    Output: ``y``.
    """

    parameters = (Parameter("k", 1.0, "", "constant output value"),)
    ports, profiles = _PORTS, _PROFILES
    default_stop_time = 1.0

    def equations(self, e):
        e.residual(e.port("y") - e.p.k)


class Step(Component):
    """Step y = offset + (time < startTime ? 0 : height) (MSL Blocks.Sources.Step).

    Parameters: ``height``, ``offset`` (no unit), ``startTime`` [s]. Output: ``y``.
    Mode: ``passed`` 0 before startTime, 1 after (an event at startTime).
    """

    parameters = (Parameter("height", 1.0, "", "height of the step"), _OFFSET, _START)
    modes = _passed_mode(1)
    ports, profiles = _PORTS, _PROFILES
    default_stop_time = 1.0

    def equations(self, e):
        q = _passed(e, [e.p.startTime])
        e.residual(e.port("y") - (e.p.offset + ca.if_else(q >= 1, e.p.height, 0)))


class Ramp(Component):
    """Ramp from offset to offset + height over duration from startTime (MSL Blocks.Sources.Ramp).

    ``y = offset`` before startTime, rising linearly by ``height`` over ``duration``,
    then ``offset + height``. Parameters: ``height``, ``offset`` (no unit),
    ``duration`` [s] (>= 0; 0 is a step), ``startTime`` [s]. Output: ``y``.
    Mode: ``passed`` 0 before, 1 rising, 2 after (events at both corners).
    """

    parameters = (Parameter("height", 1.0, "", "height of the ramp"),
                  Parameter("duration", 2.0, "s", "duration of the ramp", min=0.0),
                  _OFFSET, _START)
    modes = _passed_mode(2)
    ports, profiles = _PORTS, _PROFILES
    default_stop_time = 3.0

    def equations(self, e):
        p = e.p
        q = _passed(e, [p.startTime, p.startTime + p.duration])
        rising = p.height * (e.t - p.startTime) / ca.if_else(p.duration > 0, p.duration, 1)
        e.residual(e.port("y") - (p.offset + ca.if_else(q >= 2, p.height,
                                                        ca.if_else(q == 1, rising, 0))))


class Sine(Component):
    """Sine y = offset + amplitude sin(2 pi f (time - startTime) + phase) after startTime
    (MSL Blocks.Sources.Sine; ``offset`` before it).

    Parameters: ``amplitude``, ``offset`` (no unit), ``f`` [Hz] frequency, ``phase``
    [rad], ``startTime`` [s]. Output: ``y``. Mode: ``passed`` 0
    before startTime, 1 after.
    """

    parameters = (Parameter("amplitude", 1.0, "", "amplitude of the sine wave"),
                  Parameter("f", 1.0, "Hz", "frequency of the sine wave"),
                  Parameter("phase", 0.0, "rad", "phase of the sine wave"),
                  _OFFSET, _START)
    modes = _passed_mode(1)
    ports, profiles = _PORTS, _PROFILES
    default_stop_time = 1.0

    def equations(self, e):
        p = e.p
        q = _passed(e, [p.startTime])
        wave = p.amplitude * ca.sin(2 * math.pi * p.f * (e.t - p.startTime) + p.phase)
        e.residual(e.port("y") - (p.offset + ca.if_else(q >= 1, wave, 0)))
