"""Kinematic sources that are functions of time are evaluated at the step's end, not
integrated (issue 27): a model without event indicators and with no states (SineMotion,
HarmonicMotion) or with derivatives that are constants of the parameters (ConstantSpeed's
travel' = v) takes no solver step in its doStep, and its outputs are the closed form to
rounding. A source with real dynamics (Speed's filter) still takes solver steps."""
from __future__ import annotations

import math
import re

import pytest

from components import ConstantSpeed, HarmonicMotion, SineMotion, Speed
from cs_slave import initialize, open_slave

WORK = re.compile(r"(\d+) steps, (\d+) rejected, (\d+) derivative evaluations")


def _path(component, t):
    p = component.values
    if isinstance(component, ConstantSpeed):
        return p["s0"] + p["v"] * t
    if isinstance(component, SineMotion):
        return p["s0"] + p["U"] * math.sin(p["omega"] * t)
    return p["s0"] + p["U"] * sum(c * math.sin(k * p["omega"] * t)
                                  for k, c in ((1, p["c1"]), (2, p["c2"]), (3, p["c3"])))


def _steps(component, inputs=None, n=50, h=0.0123):
    """(solver work summed over n doSteps: steps, rejected, derivative evaluations;
    the flange positions after each step; the step end times)."""
    work, positions, times = [0, 0, 0], [], []

    def log(message):
        m = WORK.search(message.decode())
        if m:
            work[:] = [w + int(g) for w, g in zip(work, m.groups())]

    fmu, vr = open_slave(component, 3, log, instance_name="source")
    fmu.setDebugLogging(True, ["logSolver"])  # every doStep reports its work there
    for name, value in (inputs or {}).items():
        fmu.setFloat64([vr[name]], [value])
    initialize(fmu, 3, 1e-8)
    t = 0.0
    for _ in range(n):
        fmu.doStep(t, h)
        t += h
        times.append(t)
        positions.extend(fmu.getFloat64([vr["flange.s"]]))
    fmu.terminate()
    fmu.freeInstance()
    return work, positions, times


@pytest.mark.parametrize("component", [SineMotion(U=0.1, omega=20.0, s0=0.3),
                                       HarmonicMotion(U=0.1, omega=20.0),
                                       ConstantSpeed(v=0.7, s0=-0.2)],
                         ids=["sine", "harmonic", "constant_speed"])
def test_a_source_that_is_a_function_of_time_takes_no_solver_step(component):
    work, positions, times = _steps(component)
    assert work == [0, 0, 0], f"steps, rejected, derivative evaluations: {work}"
    worst = max(abs(s - _path(component, t)) for s, t in zip(positions, times))
    assert worst < 1e-14


def test_a_source_with_dynamics_still_integrates():
    work, positions, times = _steps(Speed(f_crit=5.0), {"v_ref": 1.0})
    assert work[0] > 0 and work[2] > 0
    # MSL's first-order filter from rest: v = 1 - exp(-w t), s = t - (1 - exp(-w t)) / w
    w = 2 * math.pi * 5.0
    exact = [t - (1 - math.exp(-w * t)) / w for t in times]
    assert max(abs(s - e) for s, e in zip(positions, exact)) < 1e-6
